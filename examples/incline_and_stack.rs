//! A wooden block sliding down a 30° wooden incline and a stack of three wooden cubes on a
//! table, at the default scene options (the volume law of docs/contact-model.md §3.2), with
//! their contact forces: the normal force, where it acts and along which normal, against the
//! rigid answers `m g cos α` and the weight above each interface (the block's speed leads the
//! rigid `a·t` by 1.5 mm/s: the regularised friction is weaker than Coulomb's below `v_min`
//! during the first milliseconds; its acceleration after that is the rigid one). Writes
//! `out/incline_f_n.svg` and `out/stack_f_n.svg`.
//!
//!     cargo run --release --example incline_and_stack

use modia3d::demo::{box_stack, on_incline};
use modia3d::prelude::*;

fn main() -> Result<(), Box<dyn std::error::Error>> {
    std::fs::create_dir_all("out")?;
    let g = 9.81;
    let alpha = 30f64.to_radians();
    let cube = Shape::Box {
        lengths: Vector3::repeat(0.1),
    };
    let incline = on_incline(
        cube,
        0.05,
        alpha,
        -1.0,
        0.0,
        [0.0; 3],
        "DryWood",
        ContactPairMaterial::new(0.6, 0.3, 0.001),
        SceneOptions::default(),
    )
    .build()?;
    let opts = SimOptions::new(0.5).interval(1e-3).contact_results(true);
    let res = incline.simulate(&opts)?;
    let m = incline.bodies()[0].mass;
    println!(
        "block on a 30° incline (μ 0.3): {} steps",
        res.stats.solver.steps
    );
    for t in [0.1, 0.3, 0.5] {
        let f_n = res.signal_at("plank|body.f_n", t)?[0];
        let p = res.signal_at("plank|body.point", t)?;
        let n = res.signal_at("plank|body.normal", t)?;
        let v = res.signal_at("body.v_abs", t)?;
        println!(
            "  t = {t:.1} s: speed {:.5} m/s (rigid {:.5}), f_n {f_n:.6} N (m g cos α = {:.6}), \
             at [{:.4}, {:.4}, {:.4}] m, normal [{:.4}, {:.4}, {:.4}]",
            (v[0] * v[0] + v[2] * v[2]).sqrt(),
            g * (alpha.sin() - 0.3 * alpha.cos()) * t,
            m * g * alpha.cos(),
            p[0],
            p[1],
            p[2],
            n[0],
            n[1],
            n[2]
        );
    }
    res.plot(&["plank|body.f_n"], "out/incline_f_n.svg")?;

    let stack = box_stack([0.1; 3], 3, 0.0, SceneOptions::default()).build()?;
    let res = stack.simulate(&opts)?;
    println!(
        "stack of three cubes: {} steps, {} events",
        res.stats.solver.steps, res.stats.events
    );
    let w = stack.bodies()[0].mass * g;
    for (k, pair) in ["table|b0", "b0|b1", "b1|b2"].iter().enumerate() {
        let f = res.signal_at(&format!("{pair}.f_n"), 0.5)?[0];
        println!(
            "  {pair}: f_n {f:.6} N (weight above {:.6} N)",
            (3 - k) as f64 * w
        );
    }
    res.plot(
        &["table|b0.f_n", "b0|b1.f_n", "b1|b2.f_n"],
        "out/stack_f_n.svg",
    )?;
    Ok(())
}
