//! Newton's cradle: five steel balls on pendulums (Revolute joints with `can_collide = true`),
//! 1 mm apart, cor = 1. The first ball swings in at 0.5 m/s; the motion is handed on ball by
//! ball and the last one swings out. Prints the impacts and the final speeds, and writes a 2 s
//! animation to `out/newtons_cradle.{json,gltf,html}`.

use modia3d::demo;
use modia3d::prelude::*;

fn main() -> Result<(), Box<dyn std::error::Error>> {
    // The scene is the `model!` type `demo::NewtonsCradle`.
    let model = demo::NewtonsCradle {
        diameter: 0.05,
        gap: 1e-3,
        v0: 0.5,
        pair: ContactPairMaterial::new(1.0, 0.0, 0.0),
    }
    .build()?;
    let res = model.simulate(&SimOptions::new(0.012).tolerance(1e-8).interval(1e-4))?;
    for e in &res.events {
        println!("t = {:.6} s: {}", e.t, e.description);
    }
    for b in 0..5 {
        let v = res
            .signal(&format!("ball{b}.v_abs[0]"))?
            .last()
            .ok_or("no output point")?[0];
        println!("ball{b}: v_x = {v:+.5} m/s");
    }
    // Two seconds of swinging for the animation (three.js JSON, glTF, HTML player).
    // Contact results give the player its contact points and force arrows.
    let anim = model.simulate(
        &SimOptions::new(2.0)
            .tolerance(1e-8)
            .interval(0.01)
            .contact_results(true),
    )?;
    std::fs::create_dir_all("out")?;
    anim.write_threejs_json("out/newtons_cradle.json")?;
    anim.write_gltf("out/newtons_cradle.gltf")?;
    anim.write_html("out/newtons_cradle.html")?;
    println!(
        "wrote out/newtons_cradle.{{json,gltf,html}} ({} events in 2 s)",
        anim.events.len()
    );
    Ok(())
}
