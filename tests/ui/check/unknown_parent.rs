use modia3d::prelude::*;

model! {
    pub M {
        world = Object3D(feature = Scene()),
        body = Object3D(feature = Solid(shape = Sphere(diameter = 0.1), solid_material = "Steel")),
        arm = Object3D(parent = body),
        tip = Object3D(parent = arm1),
    }
}

fn main() {}
