use modia3d::prelude::*;

model! {
    pub assembly Arm(length: f64 = 0.5) {
        link = Object3D(feature = Solid(shape = Sphere(diameter = 0.1), solid_material = "Steel")),
        tip = Object3D(parent = link, translation = [0.0, 0.0, length]),
        mount = Object3D(),
        rev = Revolute(obj1 = mount, obj2 = link),
    }
}

model! {
    pub Cell {
        world = Object3D(feature = Scene()),
        arm1 = Arm(parent = world),
        tau = JointForce(joint = arm1.revv),
        push = ObjectWrench(object = arm1.rev),
        drive = JointAcceleration(joint = arm1.tip),
    }
}

fn main() {}
