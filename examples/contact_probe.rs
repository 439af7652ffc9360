//! A short contact run for profiling the collision stage (instruction counts under
//! `valgrind --tool=callgrind`, peak memory under `/usr/bin/time -v`): billiards16 (cue
//! (3, 0.1, 0) m/s, k_red 1, rtol 1e-5) or the scaling scene with `n` balls
//! (`demo::balls_on_table`, rtol 1e-6), `stop` seconds, output every 0.01 s. Prints the
//! statistics the benchmark tables use.
//!
//!     cargo run --example contact_probe -- billiards 0.5
//!     cargo run --example contact_probe -- balls 256 0.05

use modia3d::demo;
use modia3d::prelude::*;

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let num = |k: usize, default: f64| -> f64 {
        args.get(k).and_then(|a| a.parse().ok()).unwrap_or(default)
    };
    let (model, opts) = match args.first().map(String::as_str) {
        Some("balls") => (
            demo::balls_on_table(num(1, 256.0) as usize).build()?,
            SimOptions::new(num(2, 0.05)).tolerance(1e-6),
        ),
        _ => (
            demo::billiards16([3.0, 0.1, 0.0], 1.0).build()?,
            SimOptions::new(num(1, 0.5)).tolerance(1e-5),
        ),
    };
    let res = model.simulate(&opts.interval(0.01))?;
    let st = &res.stats;
    println!(
        "wall {:.3} s; {} steps, {} residuals (+{} for Jacobians), {} Jacobians, {} events, {} root functions, {} narrow-phase calls",
        st.wall_time,
        st.solver.steps,
        st.solver.residual_evals,
        st.solver.residual_evals_for_jacobian,
        st.solver.jacobian_evals,
        st.events,
        st.root_functions,
        st.narrow_phase_calls
    );
    if let Some(y) = res.state(res.time().len() - 1) {
        println!(
            "final state checksum {:.12e}",
            y.iter().map(|x| x.abs()).sum::<f64>()
        );
        // FNV-1a over the bits: equal iff the final states are equal bit for bit (up to a
        // hash collision).
        let hash = y.iter().fold(0xcbf2_9ce4_8422_2325_u64, |h, x| {
            (h ^ x.to_bits()).wrapping_mul(0x0000_0100_0000_01b3)
        });
        println!("final state FNV-1a {hash:016x}");
    }
    Ok(())
}
