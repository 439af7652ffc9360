//! A steel ball (Ø 0.1 m) launched sliding at 4 m/s without spin on a steel table (μ_k = 0.5):
//! friction slows it and spins it up until it rolls at 5/7 of the launch speed after
//! t* = 2 v0/(7 μ g). Prints the measured and closed-form values.

use modia3d::demo;
use modia3d::prelude::*;

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let (d, v0, mu) = (0.1, 4.0, 0.5);
    // The scene is the `model!` type `demo::SlidingBall`.
    let model = demo::SlidingBall {
        diameter: d,
        v0,
        spin: 0.0,
        pair: ContactPairMaterial::new(0.7, mu, 0.0),
    }
    .build()?;
    let t_star = 2.0 * v0 / (7.0 * mu * 9.81);
    let res = model.simulate(&SimOptions::new(0.7).tolerance(1e-7).interval(1e-4))?;
    let vx = res.signal("ball.v_abs[0]")?.values();
    let wy = res.signal("ball.w_abs[1]")?.values();
    let k = (0..vx.len())
        .find(|&k| vx[k] - wy[k] * d / 2.0 < 0.01)
        .unwrap_or(vx.len() - 1);
    println!(
        "slip below v_min at t = {:.5} s (t* = {t_star:.5} s); final speed {:.6} m/s (5/7 v0 = {:.6} m/s); {} steps, {} events",
        res.time()[k],
        vx.last().unwrap(),
        5.0 / 7.0 * v0,
        res.stats.solver.steps,
        res.stats.events
    );
    Ok(())
}
