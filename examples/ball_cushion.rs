//! A rolling billiard ball (1 m/s) hits the east cushion, whose contact is at 7/5·r above the
//! table (the centre of percussion): it rebounds rolling. The cushion normal is tilted (it
//! points from the cushion's axis to the ball centre), so it presses the ball onto the table
//! during the impact and table friction takes some speed: the rebound is below cor · v.
//! Writes `out/ball_cushion.csv`.

use modia3d::demo;
use modia3d::prelude::*;

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let v = 1.0;
    // The scene is the `model!` type `demo::BallCushion`.
    let model = demo::BallCushion { v }.build()?;
    let res = model.simulate(
        &SimOptions::new(1.0)
            .tolerance(1e-6)
            .interval(1e-3)
            .contact_results(true),
    )?;
    for e in &res.events {
        println!("t = {:.6} s: {}", e.t, e.description);
    }
    let t_end = res.events.last().map_or(0.0, |e| e.t);
    let k = res.time().iter().position(|&t| t >= t_end).unwrap_or(0);
    let vx = res.signal("ball.v_abs[0]")?.values()[k];
    let wy = res.signal("ball.w_abs[1]")?.values()[k];
    let zc = res
        .signal("ball|table.cushion_e.point[2]")?
        .values()
        .into_iter()
        .fold(0.0, f64::max);
    println!(
        "when the contact ends: v = {vx:.4} m/s (−cor·v = {:.4}), ω·r = {:.4} m/s (rolling when equal to v); contact point height {zc:.4} m (7/5·r = {:.4} m)",
        -0.98 * v,
        wy * 0.03,
        1.4 * 0.03
    );
    std::fs::create_dir_all("out")?;
    res.write_csv("out/ball_cushion.csv")?;
    println!("wrote out/ball_cushion.csv");
    Ok(())
}
