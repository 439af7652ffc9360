use modia3d::prelude::*;

model! {
    pub M {
        body = Object3D(feature = Solid(shape = Sphere(diameter = 0.1), solid_material = "Steel")),
        world = Object3D(parent = body, feature = Scene()),
    }
}

fn main() {}
