//! Work-precision table of the contact scenes: for each rtol, the median wall time of several
//! runs, steps, residual and Jacobian evaluations, events, and the error of the final
//! positions (max over moving bodies of |r − r_ref| \[m\]) against the same scene at a much
//! tighter tolerance (reference rtol given per scene). Each rtol is also run with IDA's dense
//! Jacobian (`structured_jacobian(false)`, median of 3 runs), interleaved with the default
//! runs, for a before/after wall-time ratio measured under the same machine load. Release
//! build:
//!
//!     cargo run --release --example work_precision [scene-name-filter]

use modia3d::demo;
use modia3d::prelude::*;

/// Runs of the dense-Jacobian comparison (billiards16 at rtol 1e-3 takes ~40 s each that way).
const DENSE_RUNS: usize = 3;

struct Case {
    name: &'static str,
    scene: SceneDesc,
    stop: f64,
    bodies: Vec<String>,
    rtols: Vec<f64>,
    reference_rtol: f64,
    runs: usize,
}

fn final_positions(res: &SimulationResult, bodies: &[String]) -> Vec<f64> {
    bodies
        .iter()
        .flat_map(|b| {
            res.signal(&format!("{b}.r_abs"))
                .unwrap()
                .last()
                .map(<[f64]>::to_vec)
                .unwrap_or_default()
        })
        .collect()
}

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let small: Vec<f64> = (3..=9).map(|k| 10f64.powi(-k)).collect();
    let mut balls: Vec<String> = (1..=15).map(|k| format!("ball{k}")).collect();
    balls.push("cue".into());
    let cases = vec![
        Case {
            name: "sliding_rolling_ball",
            scene: demo::sliding_ball(0.1, 4.0, 0.0, ContactPairMaterial::new(0.7, 0.5, 0.0)),
            stop: 0.7,
            bodies: vec!["ball".into()],
            rtols: small.clone(),
            reference_rtol: 1e-11,
            runs: 5,
        },
        Case {
            name: "bouncing_sphere",
            scene: demo::bouncing_sphere(0.1, 0.5, ContactPairMaterial::new(0.7, 0.0, 0.0)),
            stop: 1.5,
            bodies: vec!["ball".into()],
            rtols: small.clone(),
            reference_rtol: 1e-11,
            runs: 5,
        },
        Case {
            name: "two_balls",
            scene: demo::two_balls(2.0),
            stop: 1.0,
            bodies: vec!["cue".into(), "ball".into()],
            rtols: small.clone(),
            reference_rtol: 1e-11,
            runs: 5,
        },
        Case {
            name: "billiards16",
            scene: demo::billiards16([3.0, 0.1, 0.0], 1.0),
            stop: 5.0,
            bodies: balls,
            rtols: small.clone(),
            reference_rtol: 1e-11,
            runs: 5,
        },
        Case {
            name: "ball_pile",
            scene: demo::ball_pile(
                SceneOptions {
                    k_red: 1e-3,
                    ..Default::default()
                },
                demo::STEEL_STEEL,
            ),
            stop: 2.0,
            bodies: (0..demo::PILE_BALLS).map(|k| format!("b{k}")).collect(),
            rtols: (3..=8).map(|k| 10f64.powi(-k)).collect(),
            reference_rtol: 1e-10,
            runs: 3,
        },
    ];
    // Optional filter: run only the scenes whose name contains the first argument.
    let only = std::env::args().nth(1).unwrap_or_default();
    let cases: Vec<Case> = cases
        .into_iter()
        .filter(|c| c.name.contains(&only))
        .collect();
    println!("| scene | rtol | wall [s] (median) | dense Jacobian: wall [s] | steps | residuals | Jacobians (+residuals for them) | events | error [m] |");
    println!("|---|---:|---:|---:|---:|---:|---:|---:|---:|");
    for c in &cases {
        let model = c.scene.build()?;
        let opts = |rtol: f64| {
            SimOptions::new(c.stop)
                .tolerance(rtol)
                .interval(c.stop / 100.0)
        };
        // Before/after in one run: IDA's dense difference quotients and dense LU.
        let dense = |rtol: f64| opts(rtol).structured_jacobian(false);
        let reference = model.simulate(&opts(c.reference_rtol))?;
        let r_ref = final_positions(&reference, &c.bodies);
        for &rtol in &c.rtols {
            let (mut walls, mut walls_dense) = (vec![], vec![]);
            let mut last = None;
            for _ in 0..c.runs {
                let res = model.simulate(&opts(rtol))?;
                walls.push(res.stats.wall_time);
                last = Some(res);
                if walls_dense.len() < DENSE_RUNS {
                    walls_dense.push(model.simulate(&dense(rtol))?.stats.wall_time);
                }
            }
            walls.sort_by(f64::total_cmp);
            walls_dense.sort_by(f64::total_cmp);
            let res = last.expect("runs > 0");
            let r = final_positions(&res, &c.bodies);
            let err = r
                .chunks(3)
                .zip(r_ref.chunks(3))
                .map(|(a, b)| {
                    ((a[0] - b[0]).powi(2) + (a[1] - b[1]).powi(2) + (a[2] - b[2]).powi(2)).sqrt()
                })
                .fold(0.0, f64::max);
            let s = res.stats.solver;
            println!(
                "| {} | {rtol:.0e} | {:.4} | {:.4} | {} | {} | {} (+{}) | {} | {err:.2e} |",
                c.name,
                walls[walls.len() / 2],
                walls_dense[walls_dense.len() / 2],
                s.steps,
                s.residual_evals,
                s.jacobian_evals,
                s.residual_evals_for_jacobian,
                res.stats.events
            );
        }
        println!(
            "| {} (reference) | {:.0e} | {:.4} | | {} | | | {} | |",
            c.name,
            c.reference_rtol,
            reference.stats.wall_time,
            reference.stats.solver.steps,
            reference.stats.events
        );
    }
    Ok(())
}
