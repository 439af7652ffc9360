// Every joint kind beyond Revolute/Prismatic/FreeMotion in `model!`, with initial values,
// spring-dampers and inputs on named coordinates; built and run for a few steps.
use modia3d::prelude::*;

model! {
    pub Mechanisms {
        world = Object3D(feature = Scene(gravity = [0.0, 0.0, -9.81])),
        bob = Object3D(feature = Solid(shape = Sphere(diameter = 0.1), solid_material = "Steel")),
        ball = Spherical(obj1 = world, obj2 = bob, rot = Var(init = [0.3, 0.0, 0.0]), w = Var(init = [0.0, 0.0, 1.0])),
        shaft = Object3D(feature = Solid(shape = Box(lengths = [0.1, 0.2, 0.3]), solid_material = "Steel")),
        uj = Universal(obj1 = world, obj2 = shaft, axis1 = 3, axis2 = [1.0, 0.0, 0.0], phi1 = Var(init = 0.1), w2 = Var(init = 2.0)),
        spring = JointSpringDamper(joint = uj, coordinate = "phi2", stiffness = 10.0, damping = 0.1),
        rod = Object3D(feature = Solid(shape = Cylinder(axis = 3, diameter = 0.05, length = 0.5), solid_material = "Steel")),
        cyl = Cylindrical(obj1 = world, obj2 = rod, axis = 3, s = Var(init = 0.2), w = Var(init = 1.0)),
        push = JointForce(joint = cyl, coordinate = "s"),
        puck = Object3D(feature = Solid(shape = Cylinder(axis = 3, diameter = 0.2, length = 0.05), solid_material = "Steel")),
        pl = Planar(obj1 = world, obj2 = puck, normal = 3, x = Var(init = 1.0), vy = Var(init = 0.5), can_collide = true),
        drive = JointAcceleration(joint = pl, coordinate = "phi"),
    }
}

fn main() {
    let model = Mechanisms::default().build().unwrap();
    let res = model
        .simulate(&SimOptions::new(0.01).progress(false))
        .unwrap();
    for s in ["ball.q", "ball.w", "uj.phi1", "uj.w2", "cyl.s", "cyl.w", "pl.x", "pl.vy", "pl.phi"] {
        res.signal(s).unwrap();
    }
}
