use modia3d::prelude::*;

model! {
    pub M {
        body = Object3D(parent = bdy, feature = Solid(shape = Sphere(radius = 0.1))),
        body = Object3D(),
        rev = Revolute(obj1 = body, obj2 = body, axis = 7),
    }
}

fn main() {}
