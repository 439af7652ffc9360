use modia3d::prelude::*;

model! {
    pub M {
        world = Object3D(feature = Scene()),
        body Object3D(),
    }
}

fn main() {}
