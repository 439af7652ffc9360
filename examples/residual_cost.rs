//! Cost of one DAE residual evaluation per body (issue 16: ≤ 200 ns per body per residual on
//! billiards16), timed directly instead of estimated from a profile's share: each scene is
//! simulated to a state of interest, then the residual (what IDA calls per Newton iteration:
//! kinematics, contact stage, forces, Newton–Euler, residual rows) and the root functions are
//! timed at that state in short chunks (default 50 evaluations) repeated many times (default
//! 2001), interleaved, and the medians printed (chunks in which the process was descheduled
//! are outliers the median ignores). Release build:
//!
//!     cargo run --release --example residual_cost \[evaluations repeats\]

use modia3d::core::bench::{busiest_output, chunk_args, residual_cost};
use modia3d::demo;
use modia3d::prelude::*;

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let (evaluations, repeats) = chunk_args(50, 2001);
    println!("| scene | state | bodies | pairs in contact | residual [ns] | per body [ns] | roots [ns] |");
    println!("|---|---|---:|---:|---:|---:|---:|");
    let row = |scene: &str, state: &str, model: &Model, t: f64, y: &[f64]| match residual_cost(
        model,
        t,
        y,
        evaluations,
        repeats,
    ) {
        Ok(Some(c)) => println!(
            "| {scene} | {state} | {} | {} | {:.0} | {:.0} | {:.0} |",
            c.bodies,
            c.active_pairs,
            c.residual_ns,
            c.per_body_ns(),
            c.roots_ns
        ),
        Ok(None) => println!("| {scene} | {state} | no consistent state | | | | |"),
        Err(e) => println!("| {scene} | {state} | error: {e} | | | | |"),
    };
    // billiards16 (cue (3, 0.1, 0) m/s, k_red 1, rtol 1e-5): the state with the most pairs in
    // the contact set (inside the break), and t = 4 s (balls rolling on the cloth).
    let model = demo::billiards16([3.0, 0.1, 0.0], 1.0).build()?;
    let res = model.simulate(&SimOptions::new(4.0).tolerance(1e-5).interval(0.001))?;
    let (k, last) = (busiest_output(&model, &res)?, res.time().len() - 1);
    row(
        "billiards16",
        &format!("break, t = {:.3} s", res.time()[k]),
        &model,
        res.time()[k],
        res.state(k).ok_or("no state")?,
    );
    row(
        "billiards16",
        &format!("rolling, t = {:.1} s", res.time()[last]),
        &model,
        res.time()[last],
        res.state(last).ok_or("no state")?,
    );
    // The scaling scene (N steel balls bouncing and rolling on a table, BENCHMARKS.md
    // "Scaling"): the state of the first 0.3 s (output every 10 ms) with the most pairs in
    // the contact set.
    for n in [64, 256, 1024] {
        let model = demo::balls_on_table(n).build()?;
        let res = model.simulate(&SimOptions::new(0.3).tolerance(1e-6).interval(0.01))?;
        let k = busiest_output(&model, &res)?;
        row(
            &format!("{n} balls"),
            &format!("t = {:.2} s", res.time()[k]),
            &model,
            res.time()[k],
            res.state(k).ok_or("no state")?,
        );
    }
    Ok(())
}
