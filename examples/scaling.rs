//! How run time grows with the number of bodies: N steel balls (N = 16, 64, 256) on a square
//! grid, dropped from a few centimetres onto a steel table with small sideways speeds, 0.5 s
//! at rtol 1e-6 (k_red = 1e-3). Prints a table: wall time, steps, residuals, Jacobians
//! (+residuals for them), events, and wall time per step; N ≤ 64 also with IDA's dense
//! Jacobian in the same run. Release build:
//!
//!     cargo run --release --example scaling [N]

use modia3d::demo;
use modia3d::prelude::*;

fn main() -> Result<(), Box<dyn std::error::Error>> {
    println!("| balls | Jacobian | wall [s] | steps | residuals | Jacobians (+residuals for them) | events | wall per step [ms] |");
    println!("|---:|---|---:|---:|---:|---:|---:|---:|");
    for n in std::env::args()
        .nth(1)
        .map_or(vec![16, 64, 256], |a| vec![a.parse().unwrap()])
    {
        let model = demo::balls_on_table(n).build()?;
        for structured in [true, false] {
            if !structured && n > 64 {
                continue; // 3328 unknowns: a dense LU per Jacobian would take minutes
            }
            let res = model.simulate(
                &SimOptions::new(0.5)
                    .tolerance(1e-6)
                    .interval(0.05)
                    .structured_jacobian(structured),
            )?;
            let s = res.stats.solver;
            println!(
                "| {n} | {} | {:.2} | {} | {} | {} (+{}) | {} | {:.3} |",
                if structured { "structured" } else { "dense" },
                res.stats.wall_time,
                s.steps,
                s.residual_evals,
                s.jacobian_evals,
                s.residual_evals_for_jacobian,
                res.stats.events,
                1e3 * res.stats.wall_time / s.steps as f64
            );
        }
    }
    Ok(())
}
