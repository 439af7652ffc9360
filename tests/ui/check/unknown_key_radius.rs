use modia3d::prelude::*;

model! {
    pub M {
        world = Object3D(feature = Scene()),
        body = Object3D(feature = Solid(shape = Sphere(radius = 0.05), solid_material = "Steel")),
    }
}

fn main() {}
