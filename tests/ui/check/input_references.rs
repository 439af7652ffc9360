use modia3d::prelude::*;

model! {
    pub M {
        world    = Object3D(feature = Scene()),
        arm      = Object3D(feature = Solid(shape = Sphere(diameter = 0.1), solid_material = "Steel")),
        ball     = Object3D(feature = Solid(shape = Sphere(diameter = 0.1), solid_material = "Steel")),
        shoulder = Revolute(obj1 = world, obj2 = arm, axis = 1),
        free     = FreeMotion(obj1 = world, obj2 = ball),
        tau1     = JointForce(joint = sholder),
        tau2     = JointForce(joint = arm),
        push     = ObjectWrench(object = balll),
        wrong    = ObjectWrench(object = shoulder),
        drive    = JointAcceleration(joint = free),
        acc1     = JointAcceleration(joint = shoulder),
        acc2     = JointAcceleration(joint = shoulder),
        nothing  = JointForce(),
    }
}

fn main() {}
