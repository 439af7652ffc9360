//! A rolling billiard cue ball (2 m/s) hits a resting ball head-on: the cue ball stops sliding
//! (cor = 1, equal masses), then its remaining spin drives it forward again, while the struck
//! ball slides and turns into rolling at 5/7 of 2 m/s. Writes `out/two_balls.csv`.

use modia3d::demo;
use modia3d::prelude::*;

fn main() -> Result<(), Box<dyn std::error::Error>> {
    // The scene is the `model!` type `demo::TwoBalls`.
    let model = demo::TwoBalls { v: 2.0 }.build()?;
    let res = model.simulate(&SimOptions::new(1.0).tolerance(1e-6).interval(1e-3))?;
    for e in &res.events {
        println!("t = {:.6} s: {}", e.t, e.description);
    }
    let cue = res
        .signal("cue.v_abs[0]")?
        .last()
        .ok_or("no output point")?[0];
    let ball = res
        .signal("ball.v_abs[0]")?
        .last()
        .ok_or("no output point")?[0];
    println!(
        "at 1 s: cue ball {cue:.4} m/s (ideal 2/7·2 = {:.4}, minus rolling resistance 5/7·μ_r·g·0.75 s = {:.4}), struck ball {ball:.4} m/s (ideal 5/7·2 = {:.4}, minus {:.4}); wall {:.3} s",
        2.0 * 2.0 / 7.0,
        5.0 / 7.0 * 0.01 * 9.81 * 0.75,
        5.0 * 2.0 / 7.0,
        5.0 / 7.0 * 0.01 * 9.81 * 0.75,
        res.stats.wall_time
    );
    std::fs::create_dir_all("out")?;
    res.write_csv("out/two_balls.csv")?;
    println!("wrote out/two_balls.csv");
    Ok(())
}
