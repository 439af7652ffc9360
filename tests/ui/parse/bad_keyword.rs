use modia3d::prelude::*;

model! {
    pub modle M {
        world = Object3D(feature = Scene()),
    }
}

fn main() {}
