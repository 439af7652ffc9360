use modia3d::prelude::*;

model! {
    pub M {
        world = Object3D(feature = Scene()),
        body = Object3D(feature = Solidd(shape = Sphere(diameter = 0.1))),
        ball = Object3D(feature = Solid(shape = Spere(diameter = 0.1), solid_material = "Steel")),
    }
}

fn main() {}
