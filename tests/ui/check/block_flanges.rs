use modia3d::prelude::*;

model! {
    pub M {
        world = Object3D(feature = Scene()),
        a     = Object3D(feature = Solid(shape = Sphere(diameter = 0.1), solid_material = "Steel")),
        b     = Object3D(feature = Solid(shape = Sphere(diameter = 0.1), solid_material = "Steel")),
        c     = Object3D(feature = Solid(shape = Sphere(diameter = 0.1), solid_material = "Steel")),
        d     = Object3D(feature = Solid(shape = Sphere(diameter = 0.1), solid_material = "Steel")),
        ball  = Spherical(obj1 = world, obj2 = a),
        rev   = Revolute(obj1 = world, obj2 = b),
        cyl   = Cylindrical(obj1 = world, obj2 = c),
        free  = FreeMotion(obj1 = world, obj2 = d),
        d1    = Drive(joint = ball, ratio = 100.0, J_motor = 1e-5, tau = 0.0),
        d2    = Drive(joint = rev, coordinate = "s", ratio = 100.0, J_motor = 1e-5, tau = 0.0),
        d3    = Drive(joint = cyl, ratio = 100.0, J_motor = 1e-5, tau = 0.0),
        d4    = Drive(joint = cyl, coordinate = "phii", ratio = 100.0, J_motor = 1e-5, tau = 0.0),
        d5    = Drive(joint = free, ratio = 100.0, J_motor = 1e-5, tau = 0.0),
        d6    = Drive(joint = a, ratio = 100.0, J_motor = 1e-5, tau = 0.0),
        d7    = Drive(joint = rev, ratio = 100.0, J_motor = 1e-5, motor = Motor::Dc { R: 1.0, L: 1e-3, k: 0.1 }, v = 0.0),
        d8    = Drive(joint = rev, ratio = 100.0, J_motor = 1e-5, motor = Dc(R = 1.0, L = 1e-3), tau = 0.0),
        d9    = Drive(joint = rev, ratio = 100.0, J_motor = 1e-5, gear = Elastik(c = 1.0, d = 0.0), tau = 0.0),
    }
}

fn main() {}
