use modia3d::prelude::*;

model! {
    pub M {
        world = Object3D(feature = Scene()),
        body = Object3D(feature = Solid(shape = Sphere(diameter = 0.1), solid_material = "Steel")),
        world2 = Object3D(feature = Scene(gravity = [0.0, 0.0, -1.0])),
    }
}

fn main() {}
