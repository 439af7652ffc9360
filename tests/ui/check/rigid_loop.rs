use modia3d::prelude::*;

model! {
    pub M {
        world = Object3D(feature = Scene()),
        body = Object3D(parent = world, translation = [0.0, 0.0, 1.0],
                        feature = Solid(shape = Sphere(diameter = 0.1), solid_material = "Steel")),
        rev = Revolute(obj1 = world, obj2 = body),
    }
}

fn main() {}
