//! Exact Jacobian columns of hinge trees (`modia3d-core/src/dae/hinge_jacobian.rs`) against
//! the difference quotients they replace, on an N-link chain of revolute joints (a
//! single-tree robot without contact): each link a 0.3 m box of 1 kg, the axes alternating
//! between x and y, every joint damped (0.5 N·m·s/rad, so that the chain is not chaotic and
//! the error of its final angles follows rtol), released from angles 0.3 + 0.1·i rad, 1 s.
//! Per N and rtol the two Jacobians run alternately in this process
//! (`SimOptions::analytic_jacobian(false)` selects the quotients; the mass matrix `∂F/∂y'` that both keep
//! for new `c_j` comes from the hinge trees' own pass either way), 5 times each; the table
//! has the median wall times, the work of one run of each, and the largest error of the
//! final joint angles against the same scene at rtol 1e-10. Release build:
//!
//!     cargo run --release --example hinge_chain [runs]
//!
//! With `limits` (`cargo run --release --example hinge_chain limits [runs]`), the joint limits'
//! table (BENCHMARKS.md "Joint limits"): the 2- and 7-link chains without limits, with limits
//! they never reach (±10 rad: two root functions, no event) and with limits they hit (each
//! joint's range [0.1 + 0.1·i, 0.35 + 0.1·i] rad around its start angle 0.3 + 0.1·i, default stiffness,
//! cor 0.5), with the events and stop contacts per run.

use modia3d::prelude::*;
use std::time::Instant;

/// The chain of `n` links.
fn chain(n: usize) -> SceneDesc {
    let rod = || {
        Solid::new(Shape::Box {
            lengths: Vector3::new(0.05, 0.05, 0.3),
        })
        .mass(1.0)
    };
    let mut s = SceneDesc::new();
    s.add(Object3D::new("world").scene(SceneOptions::default()));
    for i in 0..n {
        let top = format!("top{i}");
        s.add(Object3D::new(&top))
            .add(
                Object3D::new(&format!("rod{i}"))
                    .parent(&top)
                    .translation([0.0, 0.0, -0.15])
                    .solid(rod()),
            )
            .add(
                Object3D::new(&format!("bottom{i}"))
                    .parent(&format!("rod{i}"))
                    .translation([0.0, 0.0, -0.15]),
            );
        let parent = if i == 0 {
            "world".to_string()
        } else {
            format!("bottom{}", i - 1)
        };
        let joint = format!("j{i}");
        s.add_joint(
            Joint::new(
                &joint,
                &parent,
                &top,
                JointKind::revolute(1 + (i % 2) as i64),
            )
            .init_position(0.3 + 0.1 * i as f64),
        )
        .add_force(ForceElement::JointSpringDamper {
            joint: joint.clone(),
            coordinate: None,
            stiffness: 0.0,
            damping: 0.5,
            offset: 0.0,
        });
    }
    s
}

/// One run: wall time [s], the solver's statistics, the final joint angles [rad].
fn run(
    model: &Model,
    n: usize,
    rtol: f64,
    quotients: bool,
) -> (f64, modia3d::core::SimStats, Vec<f64>) {
    let t0 = Instant::now();
    let res = model
        .simulate(
            &SimOptions::new(1.0)
                .tolerance(rtol)
                .interval(0.01)
                .analytic_jacobian(!quotients),
        )
        .expect("the chain simulates");
    let wall = t0.elapsed().as_secs_f64();
    let phi = (0..n)
        .map(|i| {
            res.signal(&format!("j{i}.phi"))
                .ok()
                .and_then(|s| s.data.last().copied())
                .unwrap_or(f64::NAN)
        })
        .collect();
    (wall, res.stats, phi)
}

fn median(mut x: Vec<f64>) -> f64 {
    x.sort_by(f64::total_cmp);
    x[x.len() / 2]
}

/// The joint limits' table (see the header).
fn limits_table(runs: usize) -> Result<(), Box<dyn std::error::Error>> {
    println!("| links | limits | Jacobian | wall [s] (median of {runs}) | steps | residuals (+ for Jacobians) | Jacobians | root functions | events | stop contacts | events per contact |");
    println!("|---:|---|---|---:|---:|---:|---:|---:|---:|---:|---:|");
    for n in [2, 7] {
        for (label, range) in [
            ("none", None),
            ("±10 rad, never reached", Some((-10.0, 10.0, 0.0))),
            ("hit", Some((0.1, 0.35, 0.1))),
        ] {
            let mut scene = chain(n);
            if let Some((lo, hi, step)) = range {
                for (i, j) in scene.joints.iter_mut().enumerate() {
                    let shift = step * i as f64;
                    *j = j.clone().limits(lo + shift, hi + shift);
                }
            }
            let model = scene.build()?;
            for (jac, quotients) in [("exact", false), ("quotients", true)] {
                if range.is_none() && quotients {
                    continue;
                }
                std::env::set_var("MODIA3D_DQ_JACOBIAN", if quotients { "1" } else { "0" });
                let mut walls = vec![];
                let mut last = None;
                for _ in 0..runs {
                    let t0 = Instant::now();
                    let res = model.simulate(
                        &SimOptions::new(1.0)
                            .tolerance(1e-6)
                            .interval(0.01)
                            .contact_results(true)
                            .progress(false),
                    )?;
                    walls.push(t0.elapsed().as_secs_f64());
                    last = Some(res);
                }
                let res = last.expect("runs ≥ 1");
                let (st, contacts) = (&res.stats, res.contacts()?.len());
                let per = if contacts > 0 {
                    format!("{:.2}", st.events as f64 / contacts as f64)
                } else {
                    "—".into()
                };
                println!(
                    "| {n} | {label} | {jac} | {:.4} | {} | {} (+{}) | {} | {} | {} | {contacts} | {per} |",
                    median(walls),
                    st.solver.steps,
                    st.solver.residual_evals,
                    st.solver.residual_evals_for_jacobian,
                    st.solver.jacobian_evals,
                    st.root_functions,
                    st.events,
                );
            }
        }
    }
    Ok(())
}

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let mut args: Vec<String> = std::env::args().skip(1).collect();
    let limits = args.first().is_some_and(|a| a == "limits");
    if limits {
        args.remove(0);
    }
    let runs: usize = args.first().and_then(|a| a.parse().ok()).unwrap_or(5);
    if limits {
        return limits_table(runs);
    }
    println!("| links | rtol | Jacobian | wall [s] (median of {runs}) | steps | residuals (+ for Jacobians) | Jacobians | error [rad] |");
    println!("|---:|---:|---|---:|---:|---:|---:|---:|");
    for n in [2, 7, 20, 50] {
        let model = chain(n).build()?;
        let (_, _, reference) = run(&model, n, 1e-10, false);
        for rtol in [1e-4, 1e-6, 1e-8] {
            let mut walls = [vec![], vec![]];
            let mut last = [None, None];
            for _ in 0..runs {
                for (k, quotients) in [false, true].into_iter().enumerate() {
                    let (wall, stats, phi) = run(&model, n, rtol, quotients);
                    walls[k].push(wall);
                    let err = phi
                        .iter()
                        .zip(&reference)
                        .map(|(a, b)| (a - b).abs())
                        .fold(0.0, f64::max);
                    last[k] = Some((stats, err));
                }
            }
            for (k, label) in ["exact (hinge tree)", "difference quotients"]
                .iter()
                .enumerate()
            {
                let (st, err) = last[k].expect("runs ≥ 1");
                println!(
                    "| {n} | {rtol:.0e} | {label} | {:.4} | {} | {} (+{}) | {} | {err:.2e} |",
                    median(walls[k].clone()),
                    st.solver.steps,
                    st.solver.residual_evals,
                    st.solver.residual_evals_for_jacobian,
                    st.solver.jacobian_evals
                );
            }
        }
    }
    Ok(())
}
