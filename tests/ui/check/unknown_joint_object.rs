use modia3d::prelude::*;

model! {
    pub M {
        world = Object3D(feature = Scene()),
        body = Object3D(feature = Solid(shape = Sphere(diameter = 0.1), solid_material = "Steel")),
        frame = Object3D(parent = body),
        rev = Revolute(obj1 = world, obj2 = fram),
    }
}

fn main() {}
