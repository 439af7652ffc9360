//! A beam (box with half-cylinder ends) dropped tilted and an L-shaped block read from an STL
//! file (non-convex: it collides as the convex parts of a V-HACD decomposition, each a
//! collision shape of the same body) dropped flat onto a wooden table; both come to rest and
//! the contact forces carry their weights.
//!
//! The mesh file ships with the crate: its path is built from `CARGO_MANIFEST_DIR` at compile
//! time, so the example runs from any directory (a plain relative path would be relative to the
//! current directory).
//!
//!     cargo run --release --example beam_and_mesh

use modia3d::prelude::*;

model! {
    /// A table, a free beam and a free L-block.
    BeamAndMesh(tilt: f64 = 0.3) {
        world = Object3D(feature = Scene(k_red = 1e-3)),
        table = Object3D(parent = world, translation = [0.0, 0.0, -0.05],
                         feature = Solid(shape = Box(lengths = [2.0, 2.0, 0.1]), solid_material = "DryWood",
                                         collision = true)),
        beam  = Object3D(feature = Solid(shape = Beam(axis = 1, length = 0.3, width = 0.1, thickness = 0.04),
                                         solid_material = "DryWood", collision = true)),
        fall  = FreeMotion(obj1 = world, obj2 = beam, r = Var(init = [-0.4, 0.0, 0.1]),
                           rot = Var(init = [tilt, 0.2, 0.0])),
        block = Object3D(feature = Solid(shape = FileMesh(path = concat!(env!("CARGO_MANIFEST_DIR"), "/tests/data/l_block.stl"),
                                                          convex_decomposition = true),
                                         solid_material = "DryWood", collision = true)),
        drop  = FreeMotion(obj1 = world, obj2 = block, r = Var(init = [0.2, 0.0, 0.02])),
    }
}

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let model = BeamAndMesh::default().build()?;
    let weight: std::collections::HashMap<String, f64> = model
        .bodies()
        .iter()
        .map(|b| (b.objects[0].clone(), b.mass * 9.81))
        .collect();
    let opts = SimOptions::new(2.0)
        .tolerance(1e-6)
        .interval(0.01)
        .contact_results(true);
    let res = model.simulate(&opts)?;
    println!(
        "{} events, {} steps, wall {:.2} s",
        res.stats.events, res.stats.solver.steps, res.stats.wall_time
    );
    for body in ["beam", "block"] {
        // Vertical contact force on the body at the end, summed over its parts.
        let mut force = 0.0;
        for pair in res.contact_pairs() {
            let Some(part) = pair.strip_prefix("table|") else {
                continue;
            };
            if part == body || part.starts_with(&format!("{body}#")) {
                let f_n = res.signal(&format!("{pair}.f_n"))?;
                let n = res.signal(&format!("{pair}.normal"))?;
                let (f_n, n) = (f_n.last().ok_or("no output")?, n.last().ok_or("no output")?);
                println!("  {pair}: f_n = {:.4} N", f_n[0]);
                force += f_n[0] * n[2];
            }
        }
        // The beam's frame is at its centre, the block's at its bottom corner (the file's).
        let z = res.signal(&format!("{body}.r_abs[2]"))?;
        println!(
            "{body}: frame height {:.3e} m, weight {:.4} N, contact force {:.4} N",
            z.last().ok_or("no output")?[0],
            weight[body],
            force
        );
    }
    Ok(())
}
