use modia3d::prelude::*;

model! {
    pub M {
        world = Object3D(feature = Scene()),
        a = Object3D(parent = c),
        b = Object3D(parent = a),
        c = Object3D(parent = b),
    }
}

fn main() {}
