//! The model of docs/tutorial.md, verbatim (`tests/tutorial.rs` checks that the page's code
//! blocks are this file and runs it): a wooden block and a steel ball released on a wooden
//! incline, their contact forces, plots and the viewer page. Writes `out/incline_f_n.png`,
//! `out/incline_speed.svg` and `out/incline.html`.
//!
//!     cargo run --release --example tutorial

use modia3d::prelude::*;
use std::path::Path;

/// The point `s` [m] down the slope, `y` [m] across it and `h` [m] above the top face of a
/// plank tilted by `alpha` [rad] about the world y axis, its top face through the origin.
fn on_slope(alpha: f64, s: f64, y: f64, h: f64) -> [f64; 3] {
    [
        s * alpha.cos() + h * alpha.sin(),
        y,
        h * alpha.cos() - s * alpha.sin(),
    ]
}

model! {
    /// A wooden block (0.1 m cube) and a steel ball (Ø 0.05 m) released side by side on a
    /// wooden plank tilted by `alpha` [rad].
    pub Incline(alpha: f64 = 30f64.to_radians()) {
        world = Object3D(feature = Scene(gravity = [0.0, 0.0, -9.81])),
        plank = Object3D(parent = world, translation = on_slope(alpha, 0.0, 0.0, -0.05),
                         rotation = [0.0, alpha, 0.0],
                         feature = Solid(shape = Box(lengths = [2.0, 0.8, 0.1]),
                                         solid_material = "DryWood", collision = true)),
        block = Object3D(feature = Solid(shape = Box(lengths = [0.1, 0.1, 0.1]),
                                         solid_material = "DryWood", collision = true)),
        ball  = Object3D(feature = Solid(shape = Sphere(diameter = 0.05),
                                         solid_material = "Steel", collision = true)),
        slide = FreeMotion(obj1 = world, obj2 = block,
                           r = Var(init = on_slope(alpha, -0.5, -0.2, 0.05)),
                           rot = Var(init = [0.0, alpha, 0.0])),
        roll  = FreeMotion(obj1 = world, obj2 = ball,
                           r = Var(init = on_slope(alpha, -0.5, 0.2, 0.025))),
    }
}

/// Simulates 0.5 s of [`Incline`], prints what it found, writes the plots and the viewer page
/// into `out`, and returns the results.
pub fn run(out: &Path) -> Result<SimulationResult, Box<dyn std::error::Error>> {
    let incline = Incline::default();
    let model = incline.build()?;
    let opts = SimOptions::new(0.5).interval(1e-3).contact_results(true);
    let result = model.simulate(&opts)?;
    println!("{}", result.summary());

    // The block slides: its normal force is its weight's component across the plank.
    let alpha = incline.alpha;
    let m = model
        .bodies()
        .iter()
        .find(|b| b.joint == "slide")
        .ok_or("no block")?
        .mass;
    let f_n = result.signal_at("plank|block.f_n", 0.4)?[0];
    println!(
        "block: f_n = {f_n:.4} N (m g cos α = {:.4} N)",
        m * 9.81 * alpha.cos()
    );
    // The ball rolls: it speeds up at 5/7 g sin α.
    let v = Vector3::from_column_slice(&result.signal_at("ball.v_abs", 0.4)?).norm();
    println!(
        "ball: {v:.3} m/s at 0.4 s (rolling without slip: {:.3} m/s)",
        5.0 / 7.0 * 9.81 * alpha.sin() * 0.4
    );

    result.plot(
        &["plank|block.f_n", "plank|ball.f_n"],
        out.join("incline_f_n.png"),
    )?;
    result.plot(
        &["block.v_abs", "ball.v_abs"],
        out.join("incline_speed.svg"),
    )?;
    result.write_html(out.join("incline.html"))?;
    Ok(result)
}

fn main() -> Result<(), Box<dyn std::error::Error>> {
    std::fs::create_dir_all("out")?;
    run(Path::new("out"))?;
    println!("open out/incline.html in a browser to watch it");
    Ok(())
}
