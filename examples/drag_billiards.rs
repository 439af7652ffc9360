//! billiards16 with air drag on every ball: an `ObjectForce` closure `F = −c |v| v` with
//! `c = ½ ρ C_d A` (air 1.2 kg/m³, `C_d` 0.47, a 57.2 mm ball: 7.3e-4 kg/m) and a torque
//! `−c_w ω` (`c_w` 1e-7 N·m·s). Each ball is a free body whose own force element acts on it
//! alone, so its block of the iteration matrix stays analytic and only the element is
//! differentiated by quotients (`dae/jacobian.rs`, `own_force_columns`); with
//! `SimOptions::analytic_jacobian(false)` every block takes the solver's coloured quotients of the whole
//! residual, as all of these balls did before. The two run interleaved, 5 runs each; prints a
//! table (median wall, steps, residuals, residuals for Jacobians, Jacobians, events) and the
//! largest difference of the cue ball's final position between the two (both follow rtol).
//! Release build:
//!
//!     cargo run --release --example drag_billiards [-- rtol]      # default 1e-5

use modia3d::demo;
use modia3d::prelude::*;

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let rtol: f64 = match std::env::args().nth(1) {
        Some(a) => a.parse()?,
        None => 1e-5,
    };
    let mut desc = demo::billiards16([3.0, 0.02, 0.0], 1.0);
    let c = 0.5 * 1.2 * 0.47 * std::f64::consts::PI * 0.25 * 0.0572f64.powi(2);
    let names: Vec<String> = std::iter::once("cue".to_string())
        .chain((1..16).map(|i| format!("ball{i}")))
        .collect();
    for name in &names {
        desc.add_force(ForceElement::ObjectForce {
            object: name.clone(),
            law: ForceFn::new(move |_, m| Wrench {
                force: -c * m.v_abs.norm() * m.v_abs,
                torque: -1e-7 * m.w_abs,
            }),
        });
    }
    let model = desc.build()?;
    let opts = SimOptions::new(5.0).tolerance(rtol).progress(false);
    println!("billiards16 with air drag on every ball, 5 s, rtol {rtol:e}");
    println!("| Jacobian of the balls | wall [s] (median of 5) | steps | residuals | residuals for Jacobians | Jacobians | events |");
    println!("|---|---:|---:|---:|---:|---:|---:|");
    let dq_opts = opts.clone().analytic_jacobian(false);
    let modia3d::core::bench::Alternated {
        mut walls,
        last: [own, dq],
    } = modia3d::core::bench::alternate(&model, [&opts, &dq_opts], 5)?;
    for (k, (label, res)) in [
        ("analytic, own elements by quotients", &own),
        ("coloured quotients (analytic_jacobian(false))", &dq),
    ]
    .into_iter()
    .enumerate()
    {
        walls[k].sort_by(f64::total_cmp);
        let s = res.stats.solver;
        println!(
            "| {label} | {:.3} | {} | {} | {} | {} | {} |",
            walls[k][2],
            s.steps,
            s.residual_evals,
            s.residual_evals_for_jacobian,
            s.jacobian_evals,
            res.stats.events
        );
    }
    let end = |r: &SimulationResult| -> Result<Vec<f64>, Box<dyn std::error::Error>> {
        Ok(r.signal("cue.r_abs")?.last().ok_or("no output")?.to_vec())
    };
    let (a, b) = (end(&own)?, end(&dq)?);
    let diff = a
        .iter()
        .zip(&b)
        .map(|(x, y)| (x - y).abs())
        .fold(0.0, f64::max);
    println!(
        "ratio of medians {:.2}; cue ball's final positions differ by {diff:.1e} m",
        walls[1][2] / walls[0][2]
    );
    Ok(())
}
