//! Work-precision table of the closed-loop examples against their independent references:
//! the driven four-bar (max |θ4 − Freudenstein| over 1 s on a 0.01 s grid [rad]), the
//! slider-crank of idaSlCrank_dns (max state error at 1 s against
//! `scripts/slider_crank_reference.py`), Andrews' squeezer (max relative angle error at 0.03 s
//! against the Bari test set). For each rtol (atol = 0.01·rtol, the default) the median wall
//! time of three runs. Numbers in BENCHMARKS.md.

#![allow(dead_code)]

use modia3d::prelude::*;

#[path = "andrews_squeezer.rs"]
mod andrews;
#[path = "four_bar.rs"]
mod four_bar;
#[path = "slider_crank.rs"]
mod slider_crank;

/// `python3 scripts/slider_crank_reference.py`: q, x, p and their rates at 1 s.
const SLIDER_CRANK_1S: [(&str, f64); 6] = [
    ("crank_joint.phi", 1.315420570881723),
    ("slide.s", 1.001491807230787),
    ("rod_joint.phi", -0.504973470642005),
    ("crank_joint.w", -0.5087929769098432),
    ("slide.v", 0.2816690946869714),
    ("rod_joint.w", 0.07342752901417478),
];

type ErrorOf = Box<dyn Fn(&SimulationResult) -> Result<f64, Box<dyn std::error::Error>>>;

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let fb = four_bar::FourBar::default();
    let cases: Vec<(&str, Model, f64, f64, ErrorOf)> = vec![
        (
            "four_bar (driven)",
            fb.build()?,
            1.0,
            0.01,
            Box::new(move |res| {
                let t2 = res.signal("crank_joint.phi")?.values();
                let t4 = res.signal("rocker_joint.phi")?.values();
                Ok(t2
                    .iter()
                    .zip(&t4)
                    .map(|(a, b)| (four_bar::freudenstein(fb.a, fb.b, fb.c, fb.d, *a) - b).abs())
                    .fold(0.0, f64::max))
            }),
        ),
        (
            "slider_crank",
            slider_crank::SliderCrank::default().build()?,
            1.0,
            0.1,
            Box::new(|res| {
                let mut e = 0.0f64;
                for (name, r) in SLIDER_CRANK_1S {
                    let got = res.signal(name)?.last().map_or(f64::NAN, |v| v[0]);
                    e = e.max((got - r).abs());
                }
                Ok(e)
            }),
        ),
        (
            "andrews_squeezer",
            andrews::AndrewsSqueezer::default().build()?,
            0.03,
            0.001,
            Box::new(|res| {
                let mut e = 0.0f64;
                for (j, r) in andrews::JOINTS.iter().zip(andrews::REFERENCE_003) {
                    let got = res
                        .signal(&format!("{j}.phi"))?
                        .last()
                        .map_or(f64::NAN, |v| v[0]);
                    e = e.max(((got - r) / r).abs());
                }
                Ok(e)
            }),
        ),
    ];
    println!("| example | rtol | wall [s] (median of 3) | steps | residuals | error |");
    println!("|---|---:|---:|---:|---:|---:|");
    for (name, model, stop, interval, error) in &cases {
        for rtol in [1e-4, 1e-6, 1e-8, 1e-10] {
            let opts = SimOptions::new(*stop).tolerance(rtol).interval(*interval);
            let mut walls = vec![];
            let mut last = None;
            for _ in 0..3 {
                let res = model.simulate(&opts)?;
                walls.push(res.stats.wall_time);
                last = Some(res);
            }
            walls.sort_by(f64::total_cmp);
            let res = last.ok_or("no run")?;
            let s = &res.stats.solver;
            println!(
                "| {name} | {rtol:.0e} | {:.4} | {} | {} | {:.2e} |",
                walls[1],
                s.steps,
                s.residual_evals + s.residual_evals_for_jacobian,
                error(&res)?
            );
        }
    }
    Ok(())
}
