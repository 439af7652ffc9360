//! A stack of `n` steel cubes (0.1 m) standing on a steel table, each touching the one below,
//! simulated for `t_end` s at rtol 1e-6: prints events, IDA steps, CPU time and the bottom
//! support force against the weight. The bench row "resting stack" in BENCHMARKS.md. With
//! `shape` = `cylinder` (Ø 0.1 m × 0.2 m on its side) or `ellipsoid` (0.1 × 0.06 × 0.04 m
//! lying flat) the stack is of those instead.
//!
//!     cargo run --release --example resting_stack [-- n t_end k_red shape]

use modia3d::demo;
use modia3d::prelude::*;

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let arg = |i: usize, d: f64| {
        std::env::args()
            .nth(i)
            .and_then(|a| a.parse().ok())
            .unwrap_or(d)
    };
    let (n, t_end, k_red) = (arg(1, 10.0) as usize, arg(2, 10.0), arg(3, 1e-3));
    let which = std::env::args().nth(4).unwrap_or_else(|| "cube".into());
    let (_, shape, h, volume) = demo::lying_shapes()
        .into_iter()
        .find(|c| c.0 == which)
        .ok_or("shape: cube, cylinder or ellipsoid")?;
    let s = demo::stack(shape, h, [0.0; 3], n, k_red);
    let model = s.build()?;
    let opts = SimOptions::new(t_end).contact_results(true);
    let (res, failure) = match model.simulate(&opts) {
        Ok(r) => (r, None),
        Err(e) => (*e.partial, Some(e.kind)),
    };
    let st = res.stats;
    let f = res
        .signal("table|b0.f_n")?
        .last()
        .ok_or("no output point")?[0];
    let weight = n as f64 * 8000.0 * volume * 9.81;
    println!(
        "n = {n}, k_red = {k_red}: reached t = {:.4} s; {} events, {} steps, wall {:.2} s; \
         bottom support force {f:.3} N (weight {weight:.3} N)",
        res.time().last().copied().unwrap_or(0.0),
        st.events,
        st.solver.steps,
        st.wall_time
    );
    if let Some(e) = failure {
        println!("stopped: {e}");
    }
    Ok(())
}
