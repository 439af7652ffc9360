use modia3d::prelude::*;

model! {
    pub M {
        world = Object3D(feature = Scene()),
        body = Object3D(feature = Solid(shape = Sphere(diameter = 0.1), mass_properties = MassProperties(mass = 1.0), collision = true)),
    }
}

fn main() {}
