//! Monte Carlo over Modia3D's 16-ball break (`demo::Billiards16`): the cue speed and direction
//! are uncertain — speed normal with mean 3 m/s and standard deviation 0.1 m/s, direction
//! normal about atan(0.1/3) ≈ 0.0333 rad (the `billiards16` example's shot) with standard
//! deviation 0.01 rad — sampled by a seeded Latin hypercube (the same points on every run and
//! thread count). Each run keeps where the cue ball and the rack's apex ball (`ball1`) stopped
//! after 3 s; the example prints their spread and a histogram of the cue ball's x, writes the
//! table to `out/monte_carlo_billiards.csv` and a scatter plot of the cue ball's resting
//! places, coloured by the cue speed, to `out/monte_carlo_billiards.{svg,png}`.
//!
//!     cargo run --release --example monte_carlo_billiards [-- samples [seed]]

use modia3d::demo;
use modia3d::prelude::*;
use std::time::Instant;

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let args: Vec<u64> = std::env::args()
        .skip(1)
        .filter_map(|a| a.parse().ok())
        .collect();
    let samples = args.first().copied().unwrap_or(32) as usize;
    let seed = args.get(1).copied().unwrap_or(2024);
    let points = ParamPoints::latin_hypercube(
        &[
            (
                "speed",
                "m/s",
                Distribution::Normal {
                    mean: 3.0,
                    std_dev: 0.1,
                },
            ),
            (
                "angle",
                "rad",
                Distribution::Normal {
                    mean: (0.1f64 / 3.0).atan(),
                    std_dev: 0.01,
                },
            ),
        ],
        samples,
        seed,
    )?;
    let sweep = Sweep::new(|p| {
        let (v, a) = (p.get("speed")?, p.get("angle")?);
        Ok(demo::Billiards16 {
            cue_v: [v * a.cos(), v * a.sin(), 0.0],
            k_red: 1.0,
        }
        .build()?)
    })
    .points(points)
    .options(SimOptions::new(3.0).tolerance(1e-5).interval(0.05))
    .final_value("cue.r_abs[0]")
    .final_value("cue.r_abs[1]")
    .final_value("ball1.r_abs[0]")
    .final_value("ball1.r_abs[1]");
    let start = Instant::now();
    let table = sweep.run()?;
    println!(
        "{} runs in {:.1} s ({} failed)",
        table.rows.len(),
        start.elapsed().as_secs_f64(),
        table.failures().count()
    );
    for r in table.failures() {
        let msg = r.error.as_ref().map(|e| e.to_string()).unwrap_or_default();
        println!("  row {} failed: {msg}", r.index);
    }
    println!("resting place after 3 s   mean [m]   std dev [m]   min [m]   max [m]");
    for name in [
        "cue.r_abs[0]",
        "cue.r_abs[1]",
        "ball1.r_abs[0]",
        "ball1.r_abs[1]",
    ] {
        let v: Vec<f64> = table
            .column(name)
            .ok_or("no column")?
            .into_iter()
            .filter(|x| x.is_finite())
            .collect();
        let n = v.len().max(1) as f64;
        let mean = v.iter().sum::<f64>() / n;
        let sd = (v.iter().map(|x| (x - mean).powi(2)).sum::<f64>() / (n - 1.0).max(1.0)).sqrt();
        let (lo, hi) = v
            .iter()
            .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), &x| {
                (a.min(x), b.max(x))
            });
        println!("{name:<22} {mean:>10.4} {sd:>13.4} {lo:>9.4} {hi:>9.4}");
    }
    // Histogram of the cue ball's x over the table's length (−1.12 … 1.12 m), 14 bins.
    let x = table.column("cue.r_abs[0]").ok_or("no column")?;
    let mut bins = [0usize; 14];
    for v in x.iter().filter(|v| v.is_finite()) {
        let k = ((v + 1.12) / 2.24 * 14.0).floor().clamp(0.0, 13.0) as usize;
        bins[k] += 1;
    }
    println!("cue ball x after 3 s:");
    for (k, n) in bins.iter().enumerate() {
        let lo = (16 * k as i32 - 112) as f64 / 100.0;
        let hi = (16 * k as i32 - 96) as f64 / 100.0;
        println!("  [{lo:+.2}, {hi:+.2}) m {}", "#".repeat(*n));
    }
    std::fs::create_dir_all("out")?;
    table.write_csv("out/monte_carlo_billiards.csv")?;
    for ext in ["svg", "png"] {
        table.plot_scatter(
            "cue.r_abs[0]",
            "cue.r_abs[1]",
            Some("speed"),
            format!("out/monte_carlo_billiards.{ext}"),
            Some("Cue ball after 3 s (colour: cue speed)"),
        )?;
    }
    println!("wrote out/monte_carlo_billiards.{{csv,svg,png}}");
    Ok(())
}
