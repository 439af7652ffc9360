use modia3d::prelude::*;

model! {
    pub Inner {
        world = Object3D(feature = Scene()),
    }
}

model! {
    pub Outer {
        world = Object3D(feature = Scene()),
        inner = Inner(parent = world),
    }
}

fn main() {}
