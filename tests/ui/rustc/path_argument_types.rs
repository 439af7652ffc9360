use modia3d::prelude::*;

model! {
    pub assembly Servo(joint: JointRef = JointRef::default(), gain: f64 = 1.0) {
        pi    = PI(T = 1.0, u = gain * time),
        drive = Drive(joint = joint, ratio = 100.0, J_motor = 1e-5, tau = pi.y),
    }
}

model! {
    pub M {
        world = Object3D(feature = Scene()),
        load  = Object3D(feature = Solid(shape = Sphere(diameter = 0.1), solid_material = "Steel")),
        rev   = Revolute(obj1 = world, obj2 = load),
        ramp  = Ramp(height = 1.0, duration = 1.0),
        s1    = Servo(joint = rev, gain = ramp.y),
    }
}

fn main() {}
