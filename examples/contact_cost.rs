//! Cost per active contact of the contact stage beyond the narrow phase (issue 16): billiards16
//! (cue (3, 0.1, 0) m/s, k_red 1) is run at rtol 1e-5 for 0.5 s with output every ms; at the
//! output point whose state has the most pairs in the contact set (inside the rack break), one
//! continuous-mode contact evaluation (what the residual does per evaluation: poses, narrow
//! phase, contact point, relative velocity, force law, friction, wrenches on both bodies) is
//! timed against the narrow-phase distance calls alone for the same pairs and poses. Prints
//! both medians and `(stage − narrow) / pairs`. The timer runs over short chunks (default 50
//! evaluations, ~0.1 ms) repeated many times (default 4001, the two kinds interleaved), so on a
//! shared machine the chunks in which the process was descheduled are outliers the median
//! ignores (chunks of 0.1 s measured twice the time under load). Release build:
//!
//!     cargo run --release --example contact_cost \[evaluations repeats\]

use modia3d::core::bench::{busiest_output, chunk_args, contact_stage_cost};
use modia3d::demo;
use modia3d::prelude::*;

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let (evaluations, repeats) = chunk_args(50, 4001);
    let model = demo::billiards16([3.0, 0.1, 0.0], 1.0).build()?;
    let res = model.simulate(&SimOptions::new(0.5).tolerance(1e-5).interval(0.001))?;
    let k = busiest_output(&model, &res)?;
    let t = res.time()[k];
    let y = res.state(k).ok_or("no state")?;
    let c = contact_stage_cost(&model, t, y, evaluations, repeats)?.ok_or("no contacts")?;
    println!(
        "billiards16 at t = {t:.3} s: {} pairs in the contact set ({} ball-ball, {} ball-table/cushion)",
        c.active_pairs,
        c.moving_pairs,
        c.active_pairs - c.moving_pairs
    );
    println!(
        "medians of {repeats} x {evaluations} evaluations: contact stage {:.1} ns, narrow phase alone {:.1} ns per evaluation",
        c.stage_ns, c.narrow_ns
    );
    println!(
        "per active contact: stage {:.1} ns, narrow phase {:.1} ns, beyond the narrow phase {:.1} ns",
        c.stage_ns / c.active_pairs as f64,
        c.narrow_ns / c.active_pairs as f64,
        c.per_pair_beyond_narrow_ns()
    );
    Ok(())
}
