use modia3d::prelude::*;

model! {
    pub M(length: f64) {
        world = Object3D(feature = Scene()),
    }
}

fn main() {}
