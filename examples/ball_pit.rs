//! The linear algebra of large contact components: `demo::ball_pit(N)` (N steel balls dropped
//! into a box one layer wide, so that they settle into one component in which each ball touches
//! a handful of others), 0.5 s at rtol 1e-5, each component of the iteration matrix factored
//! as the library chooses (dense or block-sparse) and — `SimOptions::dense_lu(true)` — always densely,
//! the two run interleaved. Prints a table: median wall time of 3 runs each, steps, residuals,
//! Jacobians, events, and the largest difference of the final states between the two.
//! Release build:
//!
//!     cargo run --release --example ball_pit [N ...]      # default 8 27 64

use modia3d::demo;
use modia3d::prelude::*;

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let sizes: Vec<usize> = {
        let a: Vec<usize> = std::env::args()
            .skip(1)
            .map(|a| a.parse())
            .collect::<Result<_, _>>()?;
        if a.is_empty() {
            vec![8, 27, 64]
        } else {
            a
        }
    };
    println!("| balls | unknowns | LU | wall [s] (median of 3) | steps | residuals | Jacobians | events | final states: max difference |");
    println!("|---:|---:|---|---:|---:|---:|---:|---:|---:|");
    for n in sizes {
        let model = demo::ball_pit(n).build()?;
        let opts = SimOptions::new(0.5).tolerance(1e-5).interval(0.05);
        let dense_opts = opts.clone().dense_lu(true);
        let modia3d::core::bench::Alternated {
            mut walls,
            last: [chosen, dense],
        } = modia3d::core::bench::alternate(&model, [&opts, &dense_opts], 3)?;
        // The whole state: positions [m], quaternions, angular and linear velocities.
        let diff = match (chosen.final_state(), dense.final_state()) {
            (Some(a), Some(d)) => a
                .iter()
                .zip(d)
                .map(|(x, y)| (x - y).abs())
                .fold(0.0, f64::max),
            _ => f64::NAN,
        };
        for (k, (label, res)) in [("chosen", &chosen), ("dense", &dense)]
            .into_iter()
            .enumerate()
        {
            walls[k].sort_by(f64::total_cmp);
            let s = res.stats.solver;
            println!(
                "| {n} | {} | {label} | {:.3} | {} | {} | {} | {} | {} |",
                13 * n,
                walls[k][1],
                s.steps,
                s.residual_evals,
                s.jacobian_evals,
                res.stats.events,
                if k == 0 {
                    format!("{diff:.1e}")
                } else {
                    String::new()
                }
            );
        }
    }
    Ok(())
}
