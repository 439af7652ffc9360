//! Gripping (Modia3D's segmented simulation, as in its YouBot example): a two-link arm over a
//! table picks a wooden box off the table, carries it and drops it. The grip and the release
//! are actions declared in the `model!` (`ActionAttach` with a gap, `ActionRelease`); each
//! changes the structure — the box's FreeMotion joint disappears while it is held and comes
//! back at the release — and the run goes on in one result. The arm's joints follow a
//! minimum-jerk trajectory through joint-space waypoints by prescribed accelerations set from
//! Rust every 2 ms (a kinematic PD correction on top of the planned acceleration).
//!
//!     cargo run --release --example gripper

use modia3d::prelude::*;

model! {
    /// A two-link arm (shoulder 0.6 m above the table, links 0.4 m and 0.35 m, both turning
    /// about y) with a small sphere as gripper, and a 5 cm wooden box on a wooden table.
    /// `k_red = 1e-3` (as the falling-boxes demo) softens the wood contact: at the default 1
    /// the box resting on the table and rattling after the drop, with IDA restarted at every
    /// 2 ms input change, takes 16 times the steps (measured: 374,600 vs 23,800).
    pub Gripper(phi1: f64 = 0.0, phi2: f64 = 0.0, t_pick: f64 = 1.0, t_drop: f64 = 2.2) {
        world    = Object3D(feature = Scene(k_red = 1e-3)),
        table    = Object3D(parent = world, translation = [0.0, 0.0, -0.05],
                            feature = Solid(shape = Box(lengths = [1.4, 0.6, 0.1]),
                                            solid_material = "DryWood", collision = true)),
        mount    = Object3D(parent = world, translation = [0.0, 0.0, 0.6]),
        link1    = Object3D(feature = Solid(shape = Capsule(axis = 3, diameter = 0.04, length = 0.4),
                                            solid_material = "Aluminium")),
        l1_root  = Object3D(parent = link1, translation = [0.0, 0.0, 0.2]),
        l1_tip   = Object3D(parent = link1, translation = [0.0, 0.0, -0.2]),
        link2    = Object3D(feature = Solid(shape = Capsule(axis = 3, diameter = 0.03, length = 0.35),
                                            solid_material = "Aluminium")),
        l2_root  = Object3D(parent = link2, translation = [0.0, 0.0, 0.175]),
        gripper  = Object3D(parent = link2, translation = [0.0, 0.0, -0.175],
                            feature = Solid(shape = Sphere(diameter = 0.02), solid_material = "Aluminium")),
        shoulder = Revolute(obj1 = mount, obj2 = l1_root, axis = 2, phi = Var(init = phi1)),
        elbow    = Revolute(obj1 = l1_tip, obj2 = l2_root, axis = 2, phi = Var(init = phi2)),
        acc1     = JointAcceleration(joint = shoulder),
        acc2     = JointAcceleration(joint = elbow),
        cube     = Object3D(feature = Solid(shape = Box(lengths = [0.05, 0.05, 0.05]),
                                            solid_material = "DryWood", collision = true)),
        cube_free = FreeMotion(obj1 = world, obj2 = cube, r = Var(init = [-0.4, 0.0, 0.025])),
        // Grip when the gripper sphere is within 1 cm of the box; release over the table.
        pick     = ActionAttach(object = cube, to = gripper, at = t_pick, gap = 0.01),
        drop     = ActionRelease(object = cube, at = t_drop),
    }
}

/// Shoulder height \[m\] and link lengths \[m\] of [`Gripper`].
pub const SHOULDER: f64 = 0.6;
const L1: f64 = 0.4;
const L2: f64 = 0.35;

/// Joint angles \[rad\] that put the gripper's centre at `(x, z)` \[m\] (elbow bent one way).
/// With both links hanging down at zero angles, the tip is at
/// `x = −l1 sin φ1 − l2 sin(φ1 + φ2)`, `z = h − l1 cos φ1 − l2 cos(φ1 + φ2)`.
pub fn ik(x: f64, z: f64) -> [f64; 2] {
    let (a, b) = (-x, SHOULDER - z);
    let c = ((a * a + b * b - L1 * L1 - L2 * L2) / (2.0 * L1 * L2)).clamp(-1.0, 1.0);
    let phi2 = c.acos();
    let phi1 = a.atan2(b) - (L2 * phi2.sin()).atan2(L1 + L2 * phi2.cos());
    [phi1, phi2]
}

/// Waypoints: time \[s\] and gripper centre `(x, z)` \[m\]: above the box, down to 5 mm above
/// its top (the sphere's radius is 1 cm), hold while gripping, up, over to x = −0.1 m where
/// the second link has its gripping orientation again (so the box is level), hold while the
/// box is dropped 5.5 cm, back up.
pub const WAYPOINTS: [(f64, [f64; 2]); 7] = [
    (0.2, [-0.4, 0.165]),
    (0.9, [-0.4, 0.065]),
    (1.1, [-0.4, 0.065]),
    (1.6, [-0.3, 0.3]),
    (2.1, [-0.18, 0.08]),
    (2.3, [-0.18, 0.08]),
    (2.7, [-0.18, 0.3]),
];

/// Desired joint angles \[rad\], rates [rad/s] and accelerations [rad/s²] at `t` \[s\]:
/// minimum-jerk segments between the waypoints' joint angles.
fn desired(t: f64) -> [[f64; 2]; 3] {
    let q: Vec<[f64; 2]> = WAYPOINTS.iter().map(|(_, p)| ik(p[0], p[1])).collect();
    let mut out = [q[0], [0.0; 2], [0.0; 2]];
    for (k, w) in WAYPOINTS.windows(2).enumerate() {
        let (t0, t1) = (w[0].0, w[1].0);
        if t < t0 {
            break;
        }
        let s = ((t - t0) / (t1 - t0)).min(1.0);
        let (f, df, ddf) = (
            s * s * s * (10.0 - 15.0 * s + 6.0 * s * s),
            30.0 * s * s * (1.0 - s) * (1.0 - s) / (t1 - t0),
            60.0 * s * (1.0 - s) * (1.0 - 2.0 * s) / ((t1 - t0) * (t1 - t0)),
        );
        for i in 0..2 {
            let dq = q[k + 1][i] - q[k][i];
            out[0][i] = q[k][i] + dq * f;
            out[1][i] = if s < 1.0 { dq * df } else { 0.0 };
            out[2][i] = if s < 1.0 { dq * ddf } else { 0.0 };
        }
    }
    out
}

/// Runs the scene for `t_end` \[s\] with the arm's accelerations set every 2 ms (and the
/// contact signals recorded if `contacts`).
pub fn run(t_end: f64, contacts: bool) -> Result<SimulationResult, Box<dyn std::error::Error>> {
    let q0 = desired(0.0)[0];
    let model = Gripper {
        phi1: q0[0],
        phi2: q0[1],
        ..Default::default()
    }
    .build()?;
    let opts = SimOptions::new(t_end)
        .tolerance(1e-6)
        .interval(0.005)
        .contact_results(contacts);
    let mut sim = model.simulation(&opts)?;
    let (kp, kd) = (400.0, 40.0); // [1/s²], [1/s]
    let dt = 2e-3;
    let mut k = 0;
    while sim.time() < t_end - 1e-12 {
        let [q_d, w_d, a_d] = desired(sim.time());
        for (i, j) in ["shoulder", "elbow"].iter().enumerate() {
            let q = sim.output(&format!("{j}.phi"))?[0];
            let w = sim.output(&format!("{j}.w"))?[0];
            let a = a_d[i] + kp * (q_d[i] - q) + kd * (w_d[i] - w);
            sim.set_input(&format!("acc{}", i + 1), &[a])?;
        }
        k += 1;
        // The actions `pick` and `drop` run at their times inside `advance_to`.
        sim.advance_to((k as f64 * dt).min(t_end))?;
    }
    Ok(sim.into_result())
}

#[allow(dead_code)] // the test includes this file for `run`
fn main() -> Result<(), Box<dyn std::error::Error>> {
    let res = run(3.0, false)?;
    println!(
        "{} segments, {} output points, {} IDA steps, wall time {:.2} s",
        res.segment_count(),
        res.time().len(),
        res.stats.solver.steps,
        res.stats.wall_time
    );
    // The actions, and the contact events of the box on the table around them.
    let contacts = res
        .events
        .iter()
        .filter(|e| !e.description.starts_with("action"));
    println!("{} contact events of `table|cube`", contacts.count());
    for e in res
        .events
        .iter()
        .filter(|e| e.description.starts_with("action"))
    {
        println!("  t = {:.4} s: {}", e.t, e.description);
    }
    for t in [0.5, 1.5, 2.2, 2.6, 3.0] {
        let r = res.signal_at("cube.r_abs", t)?;
        println!("box at t = {t:.1} s: x = {:+.3} m, z = {:.3} m", r[0], r[2]);
    }
    Ok(())
}
