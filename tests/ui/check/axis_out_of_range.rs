use modia3d::prelude::*;

model! {
    pub M {
        world = Object3D(feature = Scene()),
        body = Object3D(feature = Solid(shape = Cylinder(axis = 0, diameter = 0.1, length = 1.0), solid_material = "Steel")),
        rev = Revolute(obj1 = world, obj2 = body, axis = -4),
    }
}

fn main() {}
