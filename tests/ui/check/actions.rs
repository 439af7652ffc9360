use modia3d::prelude::*;

model! {
    pub M {
        world   = Object3D(feature = Scene()),
        gripper = Object3D(feature = Solid(shape = Sphere(diameter = 0.1), solid_material = "Steel")),
        ball    = Object3D(feature = Solid(shape = Sphere(diameter = 0.1), solid_material = "Steel")),
        hold    = Revolute(obj1 = world, obj2 = gripper, axis = 1),
        free    = FreeMotion(obj1 = world, obj2 = ball),
        pick    = ActionAttach(object = balll, to = gripper, at = 1.0, gap = 0.01),
        grab    = ActionAttach(object = ball, to = hold, at = 1.0, gap = 0.01),
        self_   = ActionAttach(object = ball, to = ball, at = 1, gap = 0.01),
        early   = ActionRelease(object = ball, at = -1.0),
        wide    = ActionAttach(object = ball, to = gripper, at = 2.0, gap = -0.5),
        later   = ActionDelete(object = ball, time = 3.0),
    }
}

fn main() {}
