//! A steel sphere (Ø 0.1 m) dropped from 0.5 m onto a fixed steel box (Steel–Steel: cor 0.7).
//! Prints the events (contact start/end) and the apex heights, which fall by about cor² per
//! bounce, and that the sphere comes to rest after finitely many events.

use modia3d::demo;
use modia3d::prelude::*;

fn main() -> Result<(), Box<dyn std::error::Error>> {
    // The scene is the `model!` type `demo::BouncingSphere` (Steel–Steel as built in).
    let model = demo::BouncingSphere::default().build()?;
    let res = model.simulate(&SimOptions::new(3.0).tolerance(1e-6).interval(1e-3))?;
    for e in res.events.iter().take(8) {
        println!("t = {:.6} s: {}", e.t, e.description);
    }
    let z = res.signal("ball.r_abs[2]")?;
    println!(
        "{} events; final height {:.7} m (radius 0.05 m); stats: {} steps, {} root functions, {} narrow-phase calls, wall {:.3} s",
        res.events.len(),
        z.last().ok_or("no output point")?[0],
        res.stats.solver.steps,
        res.stats.root_functions,
        res.stats.narrow_phase_calls,
        res.stats.wall_time
    );
    Ok(())
}
