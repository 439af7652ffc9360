// Limit keys of a coordinate the joint does not have.
use modia3d::prelude::*;

model! {
    pub M {
        world = Object3D(feature = Scene()),
        arm = Object3D(feature = Solid(shape = Sphere(diameter = 0.1), solid_material = "Steel")),
        ball = Object3D(feature = Solid(shape = Sphere(diameter = 0.1), solid_material = "Steel")),
        hinge = Revolute(obj1 = world, obj2 = arm, axis = 2, s_limits = [-0.1, 0.1]),
        socket = Spherical(obj1 = world, obj2 = ball, phi_limit_cor = 0.5),
    }
}

fn main() {}
