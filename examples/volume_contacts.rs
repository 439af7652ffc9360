//! The volume law of pairs without a sphere (docs/contact-model.md §3.2) at the default scene
//! options, against rigid-body references (the scenes and references of docs/peer-comparison.md):
//! a table per rtol with wall time (median of `runs`, model built once, the run with its
//! output grid of 0.01 s, 1e-4 s for the pivot whose crossing it interpolates),
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

/// A scene, its stop time, its output interval and its error against the rigid answer.
struct Case {
    name: &'static str,
    scene: SceneDesc,
    stop: f64,
    /// Output interval \[s\]: the times the error reads are output points (the pivot's
    /// crossing is interpolated between them).
    interval: f64,
    error: Box<dyn Fn(&SimulationResult) -> f64>,
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
            error: Box::new(move |res| {
                let a =
                    (downhill_speed(res, incline, 0.5) - downhill_speed(res, incline, 0.1)) / 0.4;
                let rigid = G * (incline.sin() - 0.3 * incline.cos());
                ((a - rigid) / rigid).abs()
            }),
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
            error: Box::new(|res| {
                let d = res.signal("body.r_abs").unwrap().last().unwrap()[0] + 1.0;
                let rigid = 1.0 / (2.0 * 0.3 * G);
                ((d - rigid) / rigid).abs()
            }),
        },
        Case {
            name: "stack of three cubes (interface forces)",
            scene: box_stack([0.1; 3], 3, 0.0, SceneOptions::default()),
            stop: 0.5,
            interval: 0.01,
            contact_signals: true,
            error: Box::new(|res| {
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
            }),
        },
        Case {
            name: "cube pivoting on an edge (Housner, fall-back time)",
            scene: pivot,
            stop: 1.1 * t_housner,
            interval: 1e-4,
            contact_signals: false,
            error: Box::new(move |res| {
                let tilt = res.signal("body.R_abs").unwrap().component(6);
                let time = res.time();
                let k = tilt
                    .iter()
                    .position(|&s| -s <= 0.0)
                    .unwrap_or(time.len() - 1);
                let (s0, s1) = (-tilt[k - 1], -tilt[k]);
                let t = time[k - 1] + (time[k] - time[k - 1]) * s0 / (s0 - s1);
                ((t - t_housner) / t_housner).abs()
            }),
        },
        Case {
            name: "cylinder rolling down a 20° incline (acceleration)",
            scene: cyl_scene,
            stop: 0.5,
            interval: 0.01,
            contact_signals: false,
            error: cyl_error,
        },
        Case {
            name: "ball rolling down a 20° incline (acceleration; Hertz)",
            scene: ball_scene,
            stop: 0.5,
            interval: 0.01,
            contact_signals: false,
            error: ball_error,
        },
    ]
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
            let mut walls = vec![];
            let mut last = None;
            for _ in 0..runs {
                let t0 = Instant::now();
                let res = model.simulate(&opts)?;
                walls.push(t0.elapsed().as_secs_f64());
                last = Some(res);
            }
            walls.sort_by(f64::total_cmp);
            let res = last.ok_or("no run")?;
            let st = &res.stats;
            println!(
                "| {} | {rtol:.0e} | {:.4} | {} | {:.0} | {} | {} | {} / {} | {} | {:.1e} |",
                case.name,
                walls[runs / 2],
                st.solver.steps,
                st.solver.steps as f64 / case.stop,
                st.solver.residual_evals,
                st.solver.jacobian_evals,
                st.solver.error_test_failures,
                st.solver.nonlinear_convergence_failures,
                st.events,
                (case.error)(&res)
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
