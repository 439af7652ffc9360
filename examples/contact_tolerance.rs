//! What loose tolerances do to resting and rolling contacts: a steel ball (Ø 0.1 m) launched
//! sliding at 4 m/s on a steel table (`demo::sliding_ball`, μ 0.5, 0.7 s: it slides, then rolls
//! at 5/7 of its speed without ever leaving the table) and billiards16 (5 s), over rtol, with
//! the default contact tightening (`SimOptions::contact_tightening`, never looser than
//! `LOOSEST_CONTACT_RTOL` in contact) and without it (`contact_tightening(1.0)`). Every
//! contact event of the rolling ball is a hop; billiards16 has 62 events when resolved.
//! Release build:
//!
//!     cargo run --release --example contact_tolerance

use modia3d::core::DEFAULT_CONTACT_TIGHTENING;
use modia3d::demo;
use modia3d::prelude::*;

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let v0 = 4.0;
    let ball = demo::sliding_ball(0.1, v0, 0.0, ContactPairMaterial::new(0.7, 0.5, 0.0)).build()?;
    let billiards = demo::Billiards16 {
        cue_v: [3.0, 0.1, 0.0],
        k_red: 1.0,
    }
    .build()?;
    println!(
        "| scene | rtol | tightening | events | steps | wall [s] | rolling speed: relative error |"
    );
    println!("|---|---:|---|---:|---:|---:|---:|");
    for rtol in [1e-1, 3e-2, 1e-2, 1e-3, 1e-4] {
        for (label, c) in [("default", DEFAULT_CONTACT_TIGHTENING), ("off", 1.0)] {
            let opts = SimOptions::new(0.7)
                .tolerance(rtol)
                .interval(0.07)
                .contact_tightening(c);
            let res = ball.simulate(&opts)?;
            let vx = res.signal("ball.v_abs")?.last().map_or(f64::NAN, |v| v[0]);
            println!(
                "| rolling ball | {rtol:e} | {label} | {} | {} | {:.4} | {:.1e} |",
                res.events.len(),
                res.stats.solver.steps,
                res.stats.wall_time,
                (vx - 5.0 / 7.0 * v0).abs() / (5.0 / 7.0 * v0)
            );
        }
    }
    for rtol in [1e-2, 1e-3, 1e-4] {
        for (label, c) in [("default", DEFAULT_CONTACT_TIGHTENING), ("off", 1.0)] {
            let opts = SimOptions::new(5.0)
                .tolerance(rtol)
                .interval(0.01)
                .contact_tightening(c);
            let res = billiards.simulate(&opts)?;
            println!(
                "| billiards16 | {rtol:e} | {label} | {} | {} | {:.3} | |",
                res.events.len(),
                res.stats.solver.steps,
                res.stats.wall_time
            );
        }
    }
    Ok(())
}
