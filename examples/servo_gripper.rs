//! Drive trains with contacts and structure changes: the two-link arm of `gripper.rs` picks
//! the wooden box off the table, carries it and drops it — moved not by prescribed
//! accelerations but by two servo drives in the DAE: a motor (rotor 2e-5 kg·m²) behind an
//! elastic gear (100:1, 1e5 N·m/rad, 30 N·m·s/rad) per joint, a P–PI cascade on the motor
//! angle and speed, and a point-to-point path through the gripper's waypoints as reference.
//! The grip and the release are the scene's actions at the times the path reaches the box and
//! the drop point; the controllers' and gears' states carry across both structure changes.
//! The same run with the speed controllers sampled at 1 kHz (`Sampled`, zero-order hold)
//! beside the continuous one.
//!
//!     cargo run --release --example servo_gripper

#[path = "gripper.rs"]
#[allow(dead_code)] // its `run` and `main` are its own
mod gripper;

use gripper::{ik, Gripper, WAYPOINTS};
use modia3d::core::blocks::{Drive, Feedback, Gain, PtpPath, Sampled, PI};
use modia3d::prelude::*;

/// Gear ratio, rotor inertia [kg·m²], gear stiffness [N·m/rad] and damping [N·m·s/rad].
const RATIO: f64 = 100.0;
const J_MOTOR: f64 = 2e-5;
const C_GEAR: f64 = 1e5;
const D_GEAR: f64 = 30.0;
/// Position gain [1/s] (motor angle error → motor speed) and the speed PI's gain [N·m·s/rad]
/// and time constant [s].
const KP: f64 = 30.0;
const KV: f64 = 0.015;
const TV: f64 = 0.05;

/// The reference: the gripper's waypoints (holds dropped: a point-to-point path stops at each
/// row anyway) in joint space, at most 2 rad/s and 4 rad/s².
fn path() -> PtpPath {
    let rows = [0, 1, 3, 4, 6];
    PtpPath {
        positions: rows
            .iter()
            .map(|&k| ik(WAYPOINTS[k].1[0], WAYPOINTS[k].1[1]).to_vec())
            .collect(),
        v_max: vec![2.0, 2.0],
        a_max: vec![4.0, 4.0],
        startTime: 0.2,
    }
}

/// The servo of joint `joint` under `name.`: P on the motor angle against the path's
/// position `q_ref`, the path's speed `qd_ref` fed forward, a PI on the motor speed.
fn servo(scene: &mut SceneDesc, name: &str, joint: &str, axis: usize, sampled: bool) {
    let p = |s: &str| format!("{name}.{s}");
    let pi = PI::new(KV, TV);
    let speed_ctrl = if sampled {
        ComponentDecl::new(&p("pi"), Sampled::new(1e-3, pi))
    } else {
        ComponentDecl::new(&p("pi"), pi)
    };
    let (q_ref, qd_ref) = (format!("path.q{axis}"), format!("path.qd{axis}"));
    let (kp_y, motor_w) = (p("kp.y"), p("drive.motor_w"));
    scene
        .add_component(ComponentDecl::new(&p("ref"), Gain { k: RATIO }).input("u", q_ref.as_str()))
        .add_component(
            ComponentDecl::new(&p("angle"), Feedback)
                .input("u1", p("ref.y").as_str())
                .input("u2", p("drive.motor_phi").as_str()),
        )
        .add_component(
            ComponentDecl::new(&p("kp"), Gain { k: KP }).input("u", p("angle.y").as_str()),
        )
        // The speed error with the path's speed fed forward: kp·(N·q_ref − φ_m) + N·q̇_ref − ω_m.
        .add_component(speed_ctrl.input(
            "u",
            Src::expr(&[&kp_y, &qd_ref, &motor_w], |_, v| {
                v[0] + RATIO * v[1] - v[2]
            }),
        ))
        .add_component(
            ComponentDecl::new(
                &p("drive"),
                Drive::rigid(joint, RATIO, J_MOTOR).elastic(C_GEAR, D_GEAR),
            )
            .input("tau", p("pi.y").as_str()),
        );
}

/// The scene: the gripper's arm and box with the servos, and the times of the grip and the
/// release.
pub fn scene(sampled: bool) -> Result<(SceneDesc, f64, f64), Box<dyn std::error::Error>> {
    let path = path();
    let arrive = path.arrival_times();
    let (t_pick, t_drop) = (arrive[1], arrive[3]);
    let q0 = &path.positions[0];
    let mut scene = Gripper {
        phi1: q0[0],
        phi2: q0[1],
        t_pick,
        t_drop,
    }
    .scene();
    // The gripper's own arm is moved by prescribed accelerations; here the drives move it.
    scene.inputs.clear();
    scene.add_component(ComponentDecl::new("path", path));
    servo(&mut scene, "shoulder_servo", "shoulder", 1, sampled);
    servo(&mut scene, "elbow_servo", "elbow", 2, sampled);
    Ok((scene, t_pick, t_drop))
}

/// The largest |joint angle − path| over the run and over its first 0.2 s (before the path
/// starts: the sag under gravity).
pub fn tracking(r: &SimulationResult) -> Result<(f64, f64), Box<dyn std::error::Error>> {
    let (mut all, mut start) = (0.0f64, 0.0f64);
    let t = r.time();
    for (q, reference) in [("shoulder.phi", "path.q1"), ("elbow.phi", "path.q2")] {
        let (a, b) = (r.signal(q)?.values(), r.signal(reference)?.values());
        for (k, (x, y)) in a.iter().zip(&b).enumerate() {
            all = all.max((x - y).abs());
            if t[k] < 0.2 {
                start = start.max((x - y).abs());
            }
        }
    }
    Ok((all, start))
}

#[allow(dead_code)] // tests/drive_trains.rs includes this file for `scene`
fn main() -> Result<(), Box<dyn std::error::Error>> {
    for (sampled, steady) in [(false, false), (false, true), (true, false)] {
        let (scene, t_pick, t_drop) = scene(sampled)?;
        let t_end = t_drop + 1.0;
        let model = scene.build()?;
        let opts = SimOptions::new(t_end)
            .tolerance(1e-6)
            .interval(0.005)
            .steady_state(steady)
            .quiet(true);
        let r = model.simulate(&opts)?;
        let (err, sag) = tracking(&r)?;
        let carried = r.signal_at("cube.r_abs", 0.5 * (t_pick + t_drop))?;
        let end = r.signal_at("cube.r_abs", t_end)?;
        println!(
            "{}, {}: {} IDA steps, {} events, wall {:.2} s",
            if sampled {
                "speed PIs sampled at 1 kHz"
            } else {
                "continuous controllers"
            },
            if steady {
                "started in steady state"
            } else {
                "started from given values"
            },
            r.stats.solver.steps,
            r.stats.events,
            r.stats.wall_time,
        );
        println!(
            "  largest tracking error {err:.2e} rad (before the path starts: {sag:.2e} rad); grip at \
             {t_pick:.3} s, release at {t_drop:.3} s; box carried at z = {:.3} m, at rest at \
             x = {:+.3} m, z = {:.4} m",
            carried[2], end[0], end[2]
        );
    }
    // A sampled controller's held output is no state the steady state can solve for.
    let (scene, ..) = scene(true)?;
    let e = scene
        .build()?
        .simulate(&SimOptions::new(1.0).steady_state(true).quiet(true))
        .err();
    println!(
        "sampled, steady state asked: {}",
        e.map_or("found one".into(), |e| e.kind.to_string())
    );
    Ok(())
}
