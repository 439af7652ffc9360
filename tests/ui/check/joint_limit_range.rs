// A literal limit whose lower bound is not below its upper one, and limit keys that are not
// `[lower, upper]` or lack their `<coordinate>_limits`.
use modia3d::prelude::*;

model! {
    pub M {
        world = Object3D(feature = Scene()),
        arm = Object3D(feature = Solid(shape = Sphere(diameter = 0.1), solid_material = "Steel")),
        slide = Object3D(feature = Solid(shape = Sphere(diameter = 0.1), solid_material = "Steel")),
        hinge = Revolute(obj1 = world, obj2 = arm, axis = 2, phi_limits = [1.2, -1.2]),
        rail = Prismatic(obj1 = world, obj2 = slide, axis = 1, s_limits = [0.0, 0.1, 0.2], s_limit_cor = 0.5),
    }
}

fn main() {}
