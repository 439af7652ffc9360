//! A robot cell: two identical two-link arms, built from the same `Arm` assembly (itself built
//! from two `Link` assemblies) with different parameters, hanging from a gantry above a table. Simulates a few
//! seconds and prints joint angles and a tip position; shows paths into nested assemblies
//! (`arm2.link2.tip`) and a force law written as a closure.

use modia3d::prelude::*;

model! {
    /// A capsule-shaped link along z: `base` at its upper end, `tip` at its lower end.
    pub assembly Link(length: f64 = 0.5, diameter: f64 = 0.05) {
        body = Object3D(feature = Solid(shape = Capsule(axis = 3, diameter = diameter, length = length),
                                        solid_material = "Aluminium")),
        base = Object3D(parent = body, translation = [0.0, 0.0, length / 2.0]),
        tip  = Object3D(parent = body, translation = [0.0, 0.0, -length / 2.0]),
    }
}

model! {
    /// A two-link arm: shoulder and elbow about x, a damper in the elbow.
    pub assembly Arm(l1: f64 = 0.5, l2: f64 = 0.4, q1: f64 = 0.0, q2: f64 = 0.0, damping: f64 = 0.2) {
        mount    = Object3D(),
        link1    = Link(length = l1),
        link2    = Link(length = l2, diameter = 0.04),
        shoulder = Revolute(obj1 = mount, obj2 = link1.base, axis = 1, phi = Var(init = q1)),
        elbow    = Revolute(obj1 = link1.tip, obj2 = link2.base, axis = 1, phi = Var(init = q2)),
        friction = JointSpringDamper(joint = elbow, stiffness = 0.0, damping = damping),
    }
}

model! {
    /// The cell: a floor and a gantry with two hanging arms `spacing` apart; a wind pushes the
    /// second arm's tip.
    pub RobotCell(spacing: f64 = 1.0, wind: f64 = 0.5) {
        world = Object3D(feature = Scene(gravity = [0.0, 0.0, -9.81])),
        table = Object3D(parent = world, translation = [0.0, 0.0, -0.05],
                         feature = Solid(shape = Box(lengths = [2.0, 1.0, 0.1]),
                                         solid_material = "DryWood")),
        left  = Object3D(parent = world, translation = [-spacing / 2.0, 0.0, 1.5]),
        right = Object3D(parent = world, translation = [spacing / 2.0, 0.0, 1.5]),
        arm1  = Arm(parent = left, q1 = 0.3),
        arm2  = Arm(parent = right, l1 = 0.6, q1 = -0.5, q2 = 0.4, damping = 0.5),
        gust  = ObjectForce(object = arm2.link2.tip, law = move |_t: f64, _m: &ObjectMotion| Wrench {
            force: Vector3::new(0.0, wind, 0.0),
            torque: Vector3::zeros(),
        }),
    }
}

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let cell = RobotCell::default();
    let model = cell.build()?;
    let result = model.simulate(&SimOptions::new(3.0).tolerance(1e-6))?;
    let t = result.time();
    for name in [
        "arm1.shoulder.phi",
        "arm1.elbow.phi",
        "arm2.shoulder.phi",
        "arm2.elbow.phi",
    ] {
        let s = result.signal(name)?;
        println!(
            "{name:>18}: {:+.4} rad at t = 0, {:+.4} rad at t = {:.1} s",
            s.first().ok_or("no output point")?[0],
            s.last().ok_or("no output point")?[0],
            t[t.len() - 1]
        );
    }
    let tip = result.signal("arm2.link2.tip.r_abs")?;
    println!("arm2.link2.tip.r_abs at the end: {:?}", tip.last());
    println!("{:?}", result.stats);
    Ok(())
}
