use modia3d::prelude::*;

model! {
    pub M {
        world = Object3D(feature = Scene()),
        part = Object3D(parent = world, feature = Visual(shape = FileMesh(path = "part.obj", convex_decomposition = 1.0))),
        other = Object3D(parent = world, feature = Visual(shape = FileMesh(path = 3))),
    }
}

fn main() {}
