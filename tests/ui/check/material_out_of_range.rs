use modia3d::prelude::*;

model! {
    pub M {
        world = Object3D(feature = Scene()),
        rubber = SolidMaterial(density = 1100.0, young_modulus = 0.0, poisson_ratio = 1.5),
    }
}

fn main() {}
