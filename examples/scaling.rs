//! How run time grows with the number of bodies: N steel balls (N = 16, 64, 256) on a square
//! grid, dropped from a few centimetres onto a steel table with small sideways speeds, 0.5 s
//! at rtol 1e-6 (k_red = 1e-3). Prints a table: wall time, steps, residuals, Jacobians
//! (+residuals for them), events, and wall time per step; N ≤ 64 also with IDA's dense
//! Jacobian in the same run. After the table, one line per run with the number of output
//! points and a checksum of the final state's bits (to compare versions bit for bit).
//! Release build:
//!
//!     cargo run --release --example scaling \[N \[contact_tightening\]\]
//!
//! (`contact_tightening` 1 turns the tightening of the error test in contact off, the error
//! test the library had before it; default `SimOptions`' 100.)

use modia3d::demo;
use modia3d::prelude::*;

fn main() -> Result<(), Box<dyn std::error::Error>> {
    println!("| balls | Jacobian | wall [s] | steps | residuals | Jacobians (+residuals for them) | events | wall per step [ms] |");
    println!("|---:|---|---:|---:|---:|---:|---:|---:|");
    let mut finals = Vec::new();
    for n in std::env::args()
        .nth(1)
        .map_or(vec![16, 64, 256], |a| vec![a.parse().unwrap()])
    {
        let tightening: f64 = std::env::args()
            .nth(2)
            .and_then(|a| a.parse().ok())
            .unwrap_or(modia3d::core::DEFAULT_CONTACT_TIGHTENING);
        let model = demo::balls_on_table(n).build()?;
        for structured in [true, false] {
            if !structured && n > 64 {
                continue; // 3328 unknowns: a dense LU per Jacobian would take minutes
            }
            let res = model.simulate(
                &SimOptions::new(0.5)
                    .tolerance(1e-6)
                    .interval(0.05)
                    .structured_jacobian(structured)
                    .contact_tightening(tightening),
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
            // FNV-1a over the bits of the final state: equal iff every bit is equal (up to
            // hash collisions, which a changed result is not tuned to hit).
            let y = res.final_state().unwrap_or(&[]);
            let hash = y.iter().fold(0xcbf2_9ce4_8422_2325_u64, |h, x| {
                (h ^ x.to_bits()).wrapping_mul(0x0000_0100_0000_01b3)
            });
            // Reading every ball's position signal, as an export of the result does: the
            // cost of the results side (each signal places only its body's chain).
            let t0 = std::time::Instant::now();
            let mut z_sum = 0.0;
            for name in res.signal_names().iter().filter(|s| s.ends_with(".r_abs")) {
                let r = res.signal(name)?;
                z_sum += r.at(res.time().len() - 1).map_or(f64::NAN, |v| v[2]);
            }
            let read = t0.elapsed().as_secs_f64();
            finals.push(format!(
                "{n} balls, {}: {} output points, final state {} values, FNV-1a {hash:016x}, y[0] = {:e}; every r_abs signal read in {read:.3} s (final z summed {z_sum:e} m)",
                if structured { "structured" } else { "dense" },
                res.time().len(),
                y.len(),
                y.first().copied().unwrap_or(f64::NAN),
            ));
        }
    }
    for line in finals {
        println!("{line}");
    }
    Ok(())
}
