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

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let runs: usize = std::env::args()
        .nth(1)
        .and_then(|a| a.parse().ok())
        .unwrap_or(5);
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
