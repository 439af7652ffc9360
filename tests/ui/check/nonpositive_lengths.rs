use modia3d::prelude::*;

model! {
    pub M {
        world = Object3D(feature = Scene()),
        body = Object3D(feature = Solid(shape = Sphere(diameter = -0.1), solid_material = "Steel")),
        block = Object3D(parent = body, feature = Solid(shape = Box(lengths = [1.0, 0.0, 1.0]), solid_material = "Steel", smoothing_radius = -0.001)),
    }
}

fn main() {}
