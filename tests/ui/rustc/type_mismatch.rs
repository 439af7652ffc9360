use modia3d::prelude::*;

model! {
    pub M(length: f64 = 1.0, on: bool = true) {
        world = Object3D(feature = Scene()),
        body = Object3D(feature = Solid(shape = Sphere(diameter = "big"), mass_properties = MassProperties(mass = on))),
        frame = Object3D(parent = body, translation = [0.0, 0.0, length], rotation = 0.5),
    }
}

fn main() {}
