//! Benchmark: a servo drive (Modia3D's P–PI cascade, motor inertia through a 156:1 gear) on a
//! link swinging under gravity, with its controller and drive in the DAE (one error control
//! over the mechanism's and the controller's states) against the same drive closed from
//! host code at 1 kHz (the controller's state by forward Euler between `advance_to` calls,
//! the motor torque set through an `Input` component). Error: the largest |φ − φ_ref| over
//! 0…4 s against the in-DAE run at rtol 1e-11. Prints one table (medians of 5 runs).
//!
//!     cargo run --release --example servo_bench

use modia3d::core::blocks::{Drive, Feedback, Gain, Input, PtpPath, Ramp, PI};
use modia3d::prelude::*;
use std::time::Instant;

/// Motor inertia [kg·m²] and gear ratio of Modia3D's servo tests.
const J_MOTOR: f64 = 0.0000135 + 0.000000409;
const RATIO: f64 = 156.0;

/// A 1.4 kg aluminium-like box link 0.3 m long hinged at one end about z, gravity along −y.
fn link() -> SceneDesc {
    let mut scene = SceneDesc::new();
    scene
        .add(Object3D::new("world").scene(SceneOptions {
            gravity: Vector3::new(0.0, -9.81, 0.0),
            ..Default::default()
        }))
        .add(
            Object3D::new("link").solid(
                Solid::new(Shape::Box {
                    lengths: Vector3::new(0.3, 0.05, 0.05),
                })
                .given_mass(1.4),
            ),
        )
        .add(
            Object3D::new("hinge")
                .parent("link")
                .translation([-0.15, 0.0, 0.0]),
        )
        .add_joint(Joint::new("rev", "world", "hinge", JointKind::revolute(3)));
    scene
}

/// The reference of a case: Modia3D's ramp (2.95 rad in 1.18 s) or its point-to-point path.
fn reference(scene: &mut SceneDesc, path: bool) {
    if path {
        scene.add_component(ComponentDecl::new(
            "ref",
            PtpPath {
                positions: vec![vec![0.0], vec![0.3], vec![0.0]],
                v_max: vec![2.68512],
                a_max: vec![1.5],
                startTime: 0.0,
            },
        ));
    } else {
        scene.add_component(ComponentDecl::new(
            "ref",
            Ramp {
                height: 2.95,
                duration: 1.18,
                ..Default::default()
            },
        ));
    }
}

fn signal_of(path: bool) -> &'static str {
    if path {
        "ref.q"
    } else {
        "ref.y"
    }
}

/// The servo in the DAE.
fn in_dae(path: bool) -> Result<Model, Box<dyn std::error::Error>> {
    let mut scene = link();
    reference(&mut scene, path);
    scene
        .add_component(ComponentDecl::new("outer", Gain { k: RATIO }).input("u", signal_of(path)))
        .add_component(
            ComponentDecl::new("angle", Feedback)
                .input("u1", "outer.y")
                .input("u2", "drive.motor_phi"),
        )
        .add_component(ComponentDecl::new("inner", Gain { k: 50.0 }).input("u", "angle.y"))
        .add_component(
            ComponentDecl::new("speed", Feedback)
                .input("u1", "inner.y")
                .input("u2", "drive.motor_w"),
        )
        .add_component(ComponentDecl::new("pi", PI::new(0.1, 1.0)).input("u", "speed.y"))
        .add_component(
            ComponentDecl::new("drive", Drive::rigid("rev", RATIO, J_MOTOR)).input("tau", "pi.y"),
        );
    Ok(scene.build()?)
}

/// The same drive with its torque from the host.
fn host_model(path: bool) -> Result<Model, Box<dyn std::error::Error>> {
    let mut scene = link();
    reference(&mut scene, path);
    scene
        .add_component(ComponentDecl::new("torque", Input { start: 0.0 }))
        .add_component(
            ComponentDecl::new("drive", Drive::rigid("rev", RATIO, J_MOTOR))
                .input("tau", "torque.y"),
        );
    Ok(scene.build()?)
}

/// The reference signal at `t` (the host reads it as the in-DAE controller does).
fn reference_at(path: bool, t: f64) -> f64 {
    if path {
        let ta = (0.3f64 / 1.5).sqrt();
        let s = |t: f64| -> f64 {
            if t <= 0.0 {
                0.0
            } else if t < ta {
                0.5 * 5.0 * t * t
            } else if t < 2.0 * ta {
                1.0 - 0.5 * 5.0 * (2.0 * ta - t).powi(2)
            } else {
                1.0
            }
        };
        if t < 2.0 * ta {
            0.3 * s(t)
        } else {
            0.3 - 0.3 * s(t - 2.0 * ta)
        }
    } else {
        2.95 * (t / 1.18).clamp(0.0, 1.0)
    }
}

struct Run {
    wall: f64,
    stats: SimStats,
    result: SimulationResult,
}

/// The servo in the DAE; `exact` the components' Jacobian columns from the blocks' partial
/// derivatives (the default), else difference quotients (`SimOptions::analytic_jacobian`).
fn run_in_dae(model: &Model, rtol: f64, exact: bool) -> Result<Run, Box<dyn std::error::Error>> {
    let t = Instant::now();
    let result = model.simulate(
        &SimOptions::new(4.0)
            .tolerance(rtol)
            .interval(0.01)
            .analytic_jacobian(exact)
            .quiet(true),
    )?;
    Ok(Run {
        wall: t.elapsed().as_secs_f64(),
        stats: result.stats,
        result,
    })
}

/// The controller in host code at `rate` [Hz]: P on the motor angle, P–I on the motor speed,
/// the PI's state by forward Euler over each period.
fn run_host(
    model: &Model,
    rtol: f64,
    path: bool,
    rate: f64,
) -> Result<Run, Box<dyn std::error::Error>> {
    let t0 = Instant::now();
    let mut sim = model.simulation(
        &SimOptions::new(4.0)
            .tolerance(rtol)
            .interval(0.01)
            .quiet(true),
    )?;
    let dt = 1.0 / rate;
    let mut x = 0.0;
    let n = (4.0 * rate).round() as usize;
    for k in 0..n {
        let t = k as f64 * dt;
        let y = sim.state();
        let (phi, w) = (y[0], y[1]);
        let u = 50.0 * (RATIO * reference_at(path, t) - RATIO * phi) - RATIO * w;
        let tau = 0.1 * (x + u);
        x += dt * u / 1.0;
        sim.set_input("torque", &[tau])?;
        sim.advance_to(((k + 1) as f64 * dt).min(4.0))?;
    }
    let result = sim.into_result();
    Ok(Run {
        wall: t0.elapsed().as_secs_f64(),
        stats: result.stats,
        result,
    })
}

fn error(
    run: &SimulationResult,
    reference: &SimulationResult,
) -> Result<f64, Box<dyn std::error::Error>> {
    let mut e: f64 = 0.0;
    for k in 0..=400 {
        let t = 0.01 * k as f64;
        let a = run.signal_at("rev.phi", t)?[0];
        let b = reference.signal_at("rev.phi", t)?[0];
        e = e.max((a - b).abs());
    }
    Ok(e)
}

/// Who closes the loop: the DAE (with the components' exact Jacobian columns or quotients),
/// or host code at a rate \[Hz\].
#[derive(Clone, Copy)]
enum By {
    Dae(bool),
    Host(f64),
}

fn median(mut v: Vec<f64>) -> f64 {
    v.sort_by(f64::total_cmp);
    v[v.len() / 2]
}

fn main() -> Result<(), Box<dyn std::error::Error>> {
    println!("| scene | closed by | rtol | wall [ms] | steps | residuals | Jacobians | events | max |φ − φ_ref| [rad] |");
    println!("|---|---|---|---:|---:|---:|---:|---:|---:|");
    for path in [false, true] {
        let name = if path { "servo, path" } else { "servo, ramp" };
        let dae = in_dae(path)?;
        let host = host_model(path)?;
        let reference = run_in_dae(&dae, 1e-11, true)?.result;
        for rtol in [1e-6, 1e-8] {
            for closed in [By::Dae(true), By::Dae(false), By::Host(1e3), By::Host(2e4)] {
                let mut walls = vec![];
                let mut last = None;
                for _ in 0..5 {
                    let r = match closed {
                        By::Dae(exact) => run_in_dae(&dae, rtol, exact),
                        By::Host(rate) => run_host(&host, rtol, path, rate),
                    };
                    match r {
                        Ok(r) => {
                            walls.push(r.wall);
                            last = Some(Ok(r));
                        }
                        Err(e) => {
                            last = Some(Err(e));
                            break;
                        }
                    }
                }
                let by = match closed {
                    By::Dae(true) => "the DAE".to_string(),
                    By::Dae(false) => "the DAE, quotient Jacobian".to_string(),
                    By::Host(rate) => format!("host, {} kHz", rate / 1e3),
                };
                match last.ok_or("no run")? {
                    Ok(r) => {
                        let s = &r.stats.solver;
                        println!(
                            "| {name} | {by} | {rtol:.0e} | {:.1} | {} | {} | {} | {} | {:.2e} |",
                            1e3 * median(walls),
                            s.steps,
                            s.residual_evals + s.residual_evals_for_jacobian,
                            s.jacobian_evals,
                            r.stats.events,
                            error(&r.result, &reference)?
                        );
                    }
                    Err(e) => {
                        let msg = e.to_string();
                        let first = msg.lines().next().unwrap_or("");
                        println!(
                            "| {name} | {by} | {rtol:.0e} | – | – | – | – | – | fails: {first} |"
                        );
                    }
                }
            }
        }
    }
    Ok(())
}
