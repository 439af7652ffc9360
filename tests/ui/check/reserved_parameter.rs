use modia3d::prelude::*;

model! {
    pub M(parent: f64 = 1.0) {
        world = Object3D(feature = Scene()),
    }
}

fn main() {}
