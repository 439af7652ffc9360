//! A two-link arm whose joint torques come from a PD controller written in plain Rust, updated
//! every 1 ms, tracking a sinusoidal trajectory. The arm is a `model!`; the controller closes
//! the loop through the step-wise `Simulation` API (inputs set between steps, outputs read by
//! name). Prints the tracking error.

use modia3d::prelude::*;

model! {
    /// Two aluminium capsules (0.5 m and 0.4 m) on revolute joints about x, hanging down.
    pub Arm(l1: f64 = 0.5, l2: f64 = 0.4) {
        world    = Object3D(feature = Scene(gravity = [0.0, 0.0, -9.81])),
        link1    = Object3D(feature = Solid(shape = Capsule(axis = 3, diameter = 0.05, length = l1),
                                            solid_material = "Aluminium")),
        base1    = Object3D(parent = link1, translation = [0.0, 0.0, l1 / 2.0]),
        tip1     = Object3D(parent = link1, translation = [0.0, 0.0, -l1 / 2.0]),
        link2    = Object3D(feature = Solid(shape = Capsule(axis = 3, diameter = 0.04, length = l2),
                                            solid_material = "Aluminium")),
        base2    = Object3D(parent = link2, translation = [0.0, 0.0, l2 / 2.0]),
        shoulder = Revolute(obj1 = world, obj2 = base1, axis = 1),
        elbow    = Revolute(obj1 = tip1, obj2 = base2, axis = 1),
        // Inputs set by the controller between steps [N·m].
        tau1     = JointForce(joint = shoulder),
        tau2     = JointForce(joint = elbow),
    }
}

/// The desired joint angles \[rad\] and rates [rad/s] at time `t` \[s\].
fn desired(t: f64) -> ([f64; 2], [f64; 2]) {
    (
        [0.6 * (1.5 * t).sin(), 0.4 * (3.0 * t).sin()],
        [0.9 * (1.5 * t).cos(), 1.2 * (3.0 * t).cos()],
    )
}

/// Tracking error of a PD-controlled run.
pub struct Tracking {
    /// Largest joint-angle error after the first second \[rad\].
    pub max: f64,
    /// Root-mean-square joint-angle error after the first second \[rad\].
    pub rms: f64,
    /// Controller updates.
    pub updates: usize,
    /// The simulation's counters.
    pub stats: SimStats,
}

/// Runs the arm for `t_end` \[s\] with the PD controller updated every 1 ms.
pub fn run_controller(t_end: f64) -> Result<Tracking, Box<dyn std::error::Error>> {
    let model = Arm::default().build()?;
    let (kp, kd) = ([300.0, 100.0], [20.0, 6.0]); // [N·m/rad], [N·m·s/rad]
    let dt = 1e-3;
    let mut sim = model.simulation(&SimOptions::new(t_end).tolerance(1e-6).interval(0.01))?;
    let (mut max_err, mut sum_sq, mut n) = (0.0f64, 0.0, 0);
    let joints = ["shoulder", "elbow"];
    let mut k = 0;
    while sim.time() < t_end - 1e-12 {
        let t = sim.time();
        let (q_d, w_d) = desired(t);
        for (i, j) in joints.iter().enumerate() {
            let q = sim.output(&format!("{j}.phi"))?[0];
            let w = sim.output(&format!("{j}.w"))?[0];
            let err = q_d[i] - q;
            if t >= 1.0 {
                // Tracking error after the first second (the start-up transient excluded).
                max_err = max_err.max(err.abs());
                sum_sq += err * err;
                n += 1;
            }
            sim.set_input(
                &format!("tau{}", i + 1),
                &[kp[i] * err + kd[i] * (w_d[i] - w)],
            )?;
        }
        k += 1;
        sim.advance_to((k as f64 * dt).min(t_end))?;
    }
    Ok(Tracking {
        max: max_err,
        rms: (sum_sq / n.max(1) as f64).sqrt(),
        updates: k,
        stats: sim.result().stats,
    })
}

#[allow(dead_code)] // the test includes this file for `run_controller`
fn main() -> Result<(), Box<dyn std::error::Error>> {
    let t_end = 4.0;
    let r = run_controller(t_end)?;
    println!(
        "PD control at 1 kHz over {t_end} s: tracking error after 1 s: max {:.4} rad, rms {:.4} rad",
        r.max, r.rms
    );
    println!(
        "{} controller updates, {} IDA steps, {} residual evaluations, wall time {:.3} s",
        r.updates, r.stats.solver.steps, r.stats.solver.residual_evals, r.stats.wall_time
    );
    Ok(())
}
