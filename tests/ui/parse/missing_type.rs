use modia3d::prelude::*;

model! {
    pub M(length = 1.0) {
        world = Object3D(feature = Scene()),
    }
}

fn main() {}
