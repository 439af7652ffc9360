//! Two boxes and two cylinders (dry wood) dropped onto a wooden table land, bounce, tip over
//! and come to rest under the default volume law (docs/contact-model.md §3.2): the force of
//! each box–table and cylinder–table pair follows the overlap of the sharp shapes and acts at
//! its centroid, so a box lying on its face is carried by its whole face, and slow contacts
//! are critically damped, so the bodies settle without hopping and without events once they
//! rest (BENCHMARKS.md, "Face contacts: the volume law").
//!
//! `k_red = 1` (default) is the wood's own stiffness: a static depth of a few nanometres.
//! `paper` as a second argument runs the paper's single-point linear law instead
//! (`ContactProfile::Paper2019`), which needs `k_red = 1e-3` to run in reasonable time.
//!
//!     cargo run --release --example falling_boxes [-- k_red [paper]]

use modia3d::demo;
use modia3d::prelude::*;

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let k_red = std::env::args()
        .nth(1)
        .and_then(|a| a.parse().ok())
        .unwrap_or(1.0);
    let profile = if std::env::args().nth(2).as_deref() == Some("paper") {
        ContactProfile::Paper2019
    } else {
        ContactProfile::Volume
    };
    // The scene is the `model!` type `demo::FallingBoxes`.
    let model = demo::with_profile(demo::FallingBoxes { k_red }.scene(), profile).build()?;
    let (res, failure) = match model.simulate(&SimOptions::new(3.0).tolerance(1e-5).interval(0.01))
    {
        Ok(r) => (r, None),
        Err(e) => (*e.partial, Some(e.kind)),
    };
    let st = res.stats;
    println!(
        "k_red = {k_red}: reached t = {:.4} s; {} events, {} steps, {} narrow-phase calls, wall {:.2} s",
        res.time().last().copied().unwrap_or(0.0),
        st.events,
        st.solver.steps,
        st.narrow_phase_calls,
        st.wall_time
    );
    for ev in res.events.iter().rev().take(4).rev() {
        println!("  t = {:.6} s: {}", ev.t, ev.description);
    }
    for n in ["box1", "box2", "cyl1", "cyl2"] {
        let z = res
            .signal(&format!("{n}.r_abs[2]"))?
            .last()
            .ok_or("no output point")?[0];
        let v = res.signal(&format!("{n}.v_abs"))?;
        let v = v.last().ok_or("no output point")?;
        println!(
            "{n}: height {z:.4} m, speed {:.2e} m/s",
            (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt()
        );
    }
    if let Some(kind) = failure {
        println!("stopped early: {kind}");
    }
    Ok(())
}
