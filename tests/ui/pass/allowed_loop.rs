//! A closed chain of moving joints is accepted: `slide` closes the loop world → body → frame →
//! world and becomes a cut joint (enforced by constraints when the model is built).
use modia3d::prelude::*;

model! {
    pub M {
        world = Object3D(feature = Scene()),
        body = Object3D(feature = Solid(shape = Sphere(diameter = 0.1), solid_material = "Steel")),
        frame = Object3D(parent = body, translation = [0.0, 0.0, 1.0]),
        rev = Revolute(obj1 = world, obj2 = body),
        slide = Prismatic(obj1 = frame, obj2 = world),
    }
}

fn main() {}
