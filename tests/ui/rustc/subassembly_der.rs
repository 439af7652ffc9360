use modia3d::prelude::*;

model! {
    pub assembly Axis {
        base = Object3D(),
        load = Object3D(feature = Solid(shape = Sphere(diameter = 0.1), solid_material = "Steel")),
        rev  = Revolute(obj1 = base, obj2 = load),
        pi   = PI(T = 1.0, u = -rev.w),
        drive = Drive(joint = rev, ratio = 100.0, J_motor = 1e-5, tau = pi.y),
    }
}

model! {
    pub Cell {
        world = Object3D(feature = Scene()),
        axis = Axis(parent = world),
        ok = Gain(k = 1.0, u = der(axis.rev.w)),
        g1 = Gain(k = 1.0, u = der(axis.rev.phi)),
        g2 = Gain(k = 1.0, u = der(axis.pi.y) + der(axis.drive.motor_w)),
        g3 = Gain(k = 1.0, u = der(axis.rev.ww)),
    }
}

fn main() {}
