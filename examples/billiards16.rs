//! Modia3D's 16-ball billiards (docs/reference/materials.md): the cue ball breaks the rack. Runs 5 s
//! at rtol 1e-5, prints the wall time, statistics and where the balls end, and writes the
//! trajectories to `out/billiards16.csv` and the animation to `out/billiards16.{json,gltf,html}`.
//! The third argument is rtol (default 1e-5).
//!
//!     cargo run --release --example billiards16 [-- k_red vy rtol]

use modia3d::demo;
use modia3d::prelude::*;

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let args: Vec<f64> = std::env::args()
        .skip(1)
        .filter_map(|a| a.parse().ok())
        .collect();
    let k_red = args.first().copied().unwrap_or(1.0);
    let vy = args.get(1).copied().unwrap_or(0.1);
    let rtol = args.get(2).copied().unwrap_or(1e-5);
    // The scene is the `model!` type `demo::Billiards16`.
    let model = demo::Billiards16 {
        cue_v: [3.0, vy, 0.0],
        k_red,
    }
    .build()?;
    let res = model.simulate(&SimOptions::new(5.0).tolerance(rtol).interval(0.01))?;
    let st = &res.stats;
    println!(
        "billiards16, cue (3, {vy}, 0) m/s, k_red = {k_red}, rtol {rtol:e}: 5 s in {:.3} s wall; {} steps, {} residuals (+{} for Jacobians), {} Jacobians, {} events, {} root functions, {} narrow-phase calls",
        st.wall_time,
        st.solver.steps,
        st.solver.residual_evals,
        st.solver.residual_evals_for_jacobian,
        st.solver.jacobian_evals,
        st.events,
        st.root_functions,
        st.narrow_phase_calls
    );
    let mut names: Vec<String> = (1..=15).map(|k| format!("ball{k}")).collect();
    names.push("cue".into());
    for n in &names {
        let r = res.signal(&format!("{n}.r_abs"))?;
        let p = r.last().ok_or("no output point")?;
        println!(
            "{n:>6}: x = {:+.4} m, y = {:+.4} m, z = {:.6} m",
            p[0], p[1], p[2]
        );
    }
    std::fs::create_dir_all("out")?;
    res.write_csv("out/billiards16.csv")?;
    res.write_threejs_json("out/billiards16.json")?;
    res.write_gltf("out/billiards16.gltf")?;
    res.write_html("out/billiards16.html")?;
    println!("wrote out/billiards16.{{csv,json,gltf,html}} (open the .html in a browser)");
    Ok(())
}
