use modia3d::prelude::*;

model! {
    pub M {
        world = Object3D(feature = Scene(gravity = 9.81)),
        body = Object3D(feature = Solid(shape = Box(lengths = [1.0, 2.0]), solid_material = "Steel")),
    }
}

fn main() {}
