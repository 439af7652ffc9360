use modia3d::prelude::*;

model! {
    pub M {
        world = Object3D(feature = Scene()),
        a = Object3D(feature = Solid(shape = Beam(length = 0.3, width = 0.1), solid_material = "Steel")),
        b = Object3D(feature = Solid(shape = Beam(length = 0.3, diameter = 0.1, thickness = 0.02), solid_material = "Steel")),
        c = Object3D(feature = Solid(shape = Beam(axis = 4, length = 0.3, width = 0.1, thickness = 0.02), solid_material = "Steel")),
        d = Object3D(feature = Solid(shape = Beam(length = 0.3, width = -0.1, thickness = 0.02), solid_material = "Steel")),
        e = Object3D(feature = Solid(shape = FileMesh(scale = [1.0, 1.0, 1.0]), solid_material = "Steel")),
        f = Object3D(feature = Visual(shape = FileMesh(path = "part.stl", scaling = [1.0, 1.0, 1.0]))),
    }
}

fn main() {}
