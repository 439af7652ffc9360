//! The volume law of pairs without a sphere (docs/contact-model.md §3.2) at the default scene
//! options, against rigid-body references (the scenes and references of docs/peer-comparison.md):
//! a table per rtol with wall time (median of `runs`, model built once, the run with its
//! output grid of 0.01 s; the pivot goes step by step and stops at its crossing, as the
//! peers' runners do),
//! IDA steps, steps per simulated second, residual and Jacobian evaluations, events and the
//! relative error against the rigid answer. The scenes are those of `tests/contact_volume.rs`,
//! plus a wooden ball rolling down the same incline (the step count a round body needs) and
//! `demo::FallingBoxes` at `k_red = 1` beside the paper's law at `k_red = 1e-3`. Release
//! build:
//!
//!     cargo run --release --example volume_contacts [-- runs [scene-filter [rtol]]]
//!
//! A filter (a substring of the scene's name) and an rtol run only those rows, e.g. to profile
//! one scene: `-- 200 cylinder 1e-2`. For diagnosis, `VC_DQ=1` forms every Jacobian column by
//! the solver's difference quotients (`SimOptions::analytic_jacobian(false)`) and
//! `VC_NOREUSE=1` forms every iteration matrix anew (`SimOptions::jacobian_reuse(false)`).

use modia3d::demo::{
    self, box_stack, cube_on_edge, housner_fall_back_time, on_incline, with_profile, FallingBoxes,
};
use modia3d::prelude::*;
use std::time::Instant;

const G: f64 = 9.81;
const WOOD: ContactPairMaterial = ContactPairMaterial::new(0.6, 0.3, 0.001);

fn cube(a: f64) -> Shape {
    Shape::Box {
        lengths: Vector3::new(a, a, a),
    }
}

fn downhill_speed(res: &SimulationResult, alpha: f64, t: f64) -> f64 {
    demo::downhill_speed(res, alpha, t).unwrap_or(f64::NAN)
}

/// How a run's error against the rigid answer is read.
enum Error {
    /// From the result of a run to the stop time.
    Of(Box<dyn Fn(&SimulationResult) -> f64>),
    /// The relative error of a crossing time \[s\]: the run goes step by step
    /// (`Simulation::step`) and stops at the first step whose end has the tilt of the pivot's
    /// cube at or below 0, as the peers' runners stop at the crossing
    /// (docs/peer-comparison.md); the crossing is located within that step on IDA's
    /// interpolant (`SimOptions::dense_output`).
    Crossing(f64),
}

/// A scene, its stop time, its output interval and its error against the rigid answer.
struct Case {
    name: &'static str,
    scene: SceneDesc,
    stop: f64,
    /// Output interval \[s\]: the times the error reads are output points.
    interval: f64,
    error: Error,
    /// Whether the error reads per-pair contact signals (`<pair>.f_n`): only then does the
    /// run record them (`SimOptions::contact_results`), at the output points only
    /// (`contact_phases(false)`: the error reads no contact phase).
    contact_signals: bool,
}

fn cases() -> Vec<Case> {
    let incline = 30f64.to_radians();
    let roll = 20f64.to_radians();
    let (b, theta0) = (0.05, 0.3);
    let t_housner = housner_fall_back_time(b, theta0);
    let pivot = cube_on_edge(b, theta0, ContactPairMaterial::new(0.6, 0.8, 0.0));
    let rolling = |shape: Shape, factor: f64| {
        (
            on_incline(
                shape,
                0.05,
                roll,
                -1.0,
                0.0,
                [0.0; 3],
                "DryWood",
                ContactPairMaterial::new(0.6, 0.6, 0.0),
                SceneOptions::default(),
            ),
            Box::new(move |res: &SimulationResult| {
                let a = (downhill_speed(res, roll, 0.5) - downhill_speed(res, roll, 0.1)) / 0.4;
                let rigid = factor * G * roll.sin();
                ((a - rigid) / rigid).abs()
            }) as Box<dyn Fn(&SimulationResult) -> f64>,
        )
    };
    let (cyl_scene, cyl_error) = rolling(
        Shape::Cylinder {
            axis: Axis::Y,
            diameter: 0.1,
            length: 0.2,
        },
        2.0 / 3.0,
    );
    let (ball_scene, ball_error) = rolling(Shape::Sphere { diameter: 0.1 }, 5.0 / 7.0);
    vec![
        Case {
            name: "block sliding down a 30° incline (acceleration)",
            scene: on_incline(
                cube(0.1),
                0.05,
                incline,
                -1.0,
                0.0,
                [0.0; 3],
                "DryWood",
                WOOD,
                SceneOptions::default(),
            ),
            stop: 0.5,
            interval: 0.01,
            contact_signals: false,
            error: Error::Of(Box::new(move |res| {
                let a =
                    (downhill_speed(res, incline, 0.5) - downhill_speed(res, incline, 0.1)) / 0.4;
                let rigid = G * (incline.sin() - 0.3 * incline.cos());
                ((a - rigid) / rigid).abs()
            })),
        },
        Case {
            name: "block sliding to rest from 1 m/s (distance)",
            scene: on_incline(
                cube(0.1),
                0.05,
                0.0,
                -1.0,
                1.0,
                [0.0; 3],
                "DryWood",
                WOOD,
                SceneOptions::default(),
            ),
            stop: 0.6,
            interval: 0.01,
            contact_signals: false,
            error: Error::Of(Box::new(|res| {
                let d = res.signal("body.r_abs").unwrap().last().unwrap()[0] + 1.0;
                let rigid = 1.0 / (2.0 * 0.3 * G);
                ((d - rigid) / rigid).abs()
            })),
        },
        Case {
            name: "stack of three cubes (interface forces)",
            scene: box_stack([0.1; 3], 3, 0.0, SceneOptions::default()),
            stop: 0.5,
            interval: 0.01,
            contact_signals: true,
            error: Error::Of(Box::new(|res| {
                let w = 0.7 * G;
                ["table|b0", "b0|b1", "b1|b2"]
                    .iter()
                    .enumerate()
                    .map(|(k, p)| {
                        let f = res.signal(&format!("{p}.f_n")).unwrap().last().unwrap()[0];
                        let e = (3 - k) as f64 * w;
                        ((f - e) / e).abs()
                    })
                    .fold(0.0, f64::max)
            })),
        },
        Case {
            name: "cube pivoting on an edge (Housner, fall-back time)",
            scene: pivot,
            stop: 1.1 * t_housner,
            interval: 0.01,
            contact_signals: false,
            error: Error::Crossing(t_housner),
        },
        Case {
            name: "cylinder rolling down a 20° incline (acceleration)",
            scene: cyl_scene,
            stop: 0.5,
            interval: 0.01,
            contact_signals: false,
            error: Error::Of(cyl_error),
        },
        Case {
            name: "ball rolling down a 20° incline (acceleration; Hertz)",
            scene: ball_scene,
            stop: 0.5,
            interval: 0.01,
            contact_signals: false,
            error: Error::Of(ball_error),
        },
    ]
}

/// Tilt \[rad\] of the pivot's cube about y from its free joint's quaternion `(w, x, y, z)`.
fn tilt(q: &[f64]) -> f64 {
    2.0 * q[2].atan2(q[0])
}

/// Runs the pivot step by step to the first step whose end has the tilt at or below 0 (or
/// the stop time) and returns the result and the crossing time \[s\], located within that
/// step by bisection on IDA's interpolant (the dense output). The tilt is read from the
/// state, positions first: the free joint's `r` (3) and then its quaternion (4).
fn until_level_ground(
    model: &Model,
    opts: &SimOptions,
) -> Result<(SimulationResult, f64), Box<dyn std::error::Error>> {
    let mut sim = model.simulation(opts)?;
    let (mut a, mut b) = (sim.time(), sim.time());
    while sim.time() < opts.stop_time {
        a = sim.time();
        b = sim.step()?;
        if tilt(&sim.state()[3..7]) <= 0.0 {
            break;
        }
    }
    let res = sim.into_result();
    for _ in 0..50 {
        let m = 0.5 * (a + b);
        if tilt(&res.signal_at("body.free.q", m)?) > 0.0 {
            a = m;
        } else {
            b = m;
        }
    }
    Ok((res, 0.5 * (a + b)))
}

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let runs: usize = std::env::args()
        .nth(1)
        .and_then(|a| a.parse().ok())
        .unwrap_or(3);
    let filter = std::env::args().nth(2);
    let only_rtol: Option<f64> = std::env::args().nth(3).and_then(|a| a.parse().ok());
    println!("| scene | rtol | wall [s] (median of {runs}) | steps | steps per s | residuals | Jacobians | error-test / Newton failures | events | error |");
    println!("|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|");
    for case in cases() {
        if filter
            .as_ref()
            .is_some_and(|f| !case.name.contains(f.as_str()))
        {
            continue;
        }
        let model = case.scene.build()?;
        for rtol in [1e-2, 1e-3, 1e-4, 1e-6, 1e-8] {
            if only_rtol.is_some_and(|r| r != rtol) {
                continue;
            }
            let opts = SimOptions::new(case.stop)
                .tolerance(rtol)
                .interval(case.interval)
                .contact_results(case.contact_signals)
                .contact_phases(false)
                .analytic_jacobian(std::env::var("VC_DQ").is_err())
                .jacobian_reuse(std::env::var("VC_NOREUSE").is_err())
                .progress(false);
            let opts = opts.dense_output(matches!(case.error, Error::Crossing(_)));
            let mut walls = vec![];
            let mut last = None;
            for _ in 0..runs {
                let t0 = Instant::now();
                // (result, error, simulated span [s])
                let (res, error, span) = match &case.error {
                    Error::Of(error) => {
                        let res = model.simulate(&opts)?;
                        let e = error(&res);
                        (res, e, case.stop)
                    }
                    &Error::Crossing(t_ref) => {
                        let (res, t_hit) = until_level_ground(&model, &opts)?;
                        (res, ((t_hit - t_ref) / t_ref).abs(), t_hit)
                    }
                };
                walls.push(t0.elapsed().as_secs_f64());
                last = Some((res, error, span));
            }
            walls.sort_by(f64::total_cmp);
            let (res, error, span) = last.ok_or("no run")?;
            let st = &res.stats;
            println!(
                "| {} | {rtol:.0e} | {:.4} | {} | {:.0} | {} | {} | {} / {} | {} | {:.1e} |",
                case.name,
                walls[runs / 2],
                st.solver.steps,
                st.solver.steps as f64 / span,
                st.solver.residual_evals,
                st.solver.jacobian_evals,
                st.solver.error_test_failures,
                st.solver.nonlinear_convergence_failures,
                st.events,
                error
            );
        }
    }
    // The falling boxes: the volume law at full stiffness beside the paper's law at k_red 1e-3.
    if filter.is_some() {
        return Ok(());
    }
    println!();
    println!("| falling_boxes, 3 s, rtol 1e-5 | wall [s] | steps | events | last event [s] | max speed at 3 s [m/s] |");
    println!("|---|---:|---:|---:|---:|---:|");
    for (label, k_red, profile) in [
        ("volume law, k_red = 1", 1.0, ContactProfile::Volume),
        ("paper's law, k_red = 1e-3", 1e-3, ContactProfile::Paper2019),
    ] {
        let scene = with_profile(FallingBoxes { k_red }.scene(), profile);
        let t0 = Instant::now();
        let res = scene.build()?.simulate(
            &SimOptions::new(3.0)
                .tolerance(1e-5)
                .interval(0.01)
                .progress(false),
        )?;
        let wall = t0.elapsed().as_secs_f64();
        let speed = ["box1", "box2", "cyl1", "cyl2"]
            .iter()
            .map(|n| {
                let v = res.signal(&format!("{n}.v_abs")).unwrap();
                let v = v.last().unwrap();
                (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt()
            })
            .fold(0.0, f64::max);
        println!(
            "| {label} | {wall:.3} | {} | {} | {:.4} | {speed:.1e} |",
            res.stats.solver.steps,
            res.stats.events,
            res.events.last().map_or(0.0, |e| e.t)
        );
    }
    Ok(())
}
