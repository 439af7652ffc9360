//! A parameter sweep: the steel sphere of `bouncing_sphere` dropped from 8 heights onto the
//! steel box with 8 coefficients of restitution (64 runs on all cores). Each run keeps the
//! effective restitution of its first impact (exit over impact speed of the contact phase, as
//! the force law delivers it against the material's `cor`), the number of impacts and the
//! final height; the table goes to `out/sweep_restitution.csv` and a heat map of the effective
//! restitution to `out/sweep_restitution.{svg,png}`.
//!
//!     cargo run --release --example sweep_restitution
//!     cargo run --release --example sweep_restitution -- --bench [repeats]
//!
//! `--bench` runs the 64-run sweep (with 3 s runs at rtol 1e-9) on 1 and on 2 threads,
//! alternately `repeats` times (default 5), checks that every table is the same bit for bit,
//! and prints the wall times and the throughput ratio (BENCHMARKS.md, "Parameter sweeps").

use modia3d::demo;
use modia3d::prelude::*;
use std::time::Instant;

fn sweep() -> Result<Sweep, SweepError> {
    let points = ParamPoints::grid(&[
        ("h0", "m", linspace(0.15, 1.0, 8)),
        ("cor", "1", linspace(0.3, 0.95, 8)),
    ])?;
    Ok(Sweep::new(|p| {
        let pair = ContactPairMaterial::new(p.get("cor")?, 0.5, 0.001);
        Ok(demo::BouncingSphere {
            h0: p.get("h0")?,
            pair,
            ..Default::default()
        }
        .build()?)
    })
    .points(points)
    .options(
        SimOptions::new(1.5)
            .tolerance(1e-6)
            .interval(0.01)
            .contact_results(true),
    )
    .final_value("ball.r_abs[2]")
    .metric("e_eff", "1", |res| {
        let first = res.contact_phases("ball|table")?.into_iter().next();
        Ok(first
            .and_then(|ph| ph.restitution())
            .ok_or("no complete first impact")?)
    })
    .metric("impacts", "", |res| {
        Ok(res.contact_phases("ball|table")?.len() as f64)
    }))
}

fn median(mut v: Vec<f64>) -> f64 {
    v.sort_by(f64::total_cmp);
    let n = v.len();
    if n % 2 == 1 {
        v[n / 2]
    } else {
        0.5 * (v[n / 2 - 1] + v[n / 2])
    }
}

/// CPU time of this process so far \[s\] (user + system, from `/proc/self/stat`; Linux
/// only, NaN elsewhere), in clock ticks of 10 ms.
fn cpu_seconds() -> f64 {
    let stat = std::fs::read_to_string("/proc/self/stat").unwrap_or_default();
    // Fields after the command name (which may hold spaces) in parentheses: utime is the
    // 12th, stime the 13th.
    let rest = stat.rsplit_once(')').map_or("", |(_, r)| r);
    let f: Vec<f64> = rest
        .split_whitespace()
        .skip(11)
        .take(2)
        .filter_map(|v| v.parse().ok())
        .collect();
    if f.len() == 2 {
        (f[0] + f[1]) / 100.0
    } else {
        f64::NAN
    }
}

fn bench(repeats: usize) -> Result<(), Box<dyn std::error::Error>> {
    // Longer and tighter runs than the study's (3 s at rtol 1e-9, every bounce until rest), so
    // that a sweep takes seconds and thread start-up is not what is measured.
    let sweep = sweep()?
        .options(
            SimOptions::new(3.0)
                .tolerance(1e-9)
                .interval(0.01)
                .contact_results(true),
        )
        .progress(false);
    let load = std::fs::read_to_string("/proc/loadavg").unwrap_or_default();
    let reference = sweep.clone().threads(1).run()?;
    let mut times = [vec![], vec![]];
    let mut cpu = [0.0, 0.0];
    for _ in 0..repeats {
        for (k, threads) in [1, 2].into_iter().enumerate() {
            let s = sweep.clone().threads(threads);
            let (t, c) = (Instant::now(), cpu_seconds());
            let table = s.run()?;
            times[k].push(t.elapsed().as_secs_f64());
            cpu[k] += cpu_seconds() - c;
            if table != reference {
                return Err(
                    format!("the {threads}-thread table differs from the 1-thread one").into(),
                );
            }
        }
    }
    let runs = reference.rows.len() as f64;
    println!(
        "{} runs, {} repeats, {} cores; /proc/loadavg at the start: {}",
        reference.rows.len(),
        repeats,
        std::thread::available_parallelism().map_or(0, |n| n.get()),
        load.trim()
    );
    println!("| threads | wall per sweep, median [s] | min [s] | max [s] | runs/s | speed-up | CPU per sweep, mean [s] |");
    println!("|---|---|---|---|---|---|---|");
    let base = median(times[0].clone());
    for (k, threads) in [1, 2].into_iter().enumerate() {
        let t = &times[k];
        let med = median(t.clone());
        println!(
            "| {threads} | {med:.3} | {:.3} | {:.3} | {:.1} | {:.2} | {:.3} |",
            t.iter().copied().fold(f64::INFINITY, f64::min),
            t.iter().copied().fold(0.0, f64::max),
            runs / med,
            base / med,
            cpu[k] / repeats as f64
        );
    }
    let ratios: Vec<f64> = times[0].iter().zip(&times[1]).map(|(a, b)| a / b).collect();
    println!(
        "per-repeat ratios (1 thread / 2 threads): {}; median {:.2}; tables equal bit for bit: yes",
        ratios
            .iter()
            .map(|r| format!("{r:.2}"))
            .collect::<Vec<_>>()
            .join(", "),
        median(ratios.clone())
    );
    Ok(())
}

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    if args.first().map(String::as_str) == Some("--bench") {
        let repeats = args.get(1).and_then(|s| s.parse().ok()).unwrap_or(5);
        return bench(repeats);
    }
    let start = Instant::now();
    let table = sweep()?.run()?;
    println!(
        "{} runs in {:.2} s ({} failed)",
        table.rows.len(),
        start.elapsed().as_secs_f64(),
        table.failures().count()
    );
    let (h0, cor, e) = (
        table.column("h0").ok_or("h0")?,
        table.column("cor").ok_or("cor")?,
        table.column("e_eff").ok_or("e_eff")?,
    );
    println!("effective restitution of the first impact (rows: h0 [m], columns: cor):");
    let cors = linspace(0.3, 0.95, 8);
    print!("{:>8}", "h0 \\ cor");
    for c in &cors {
        print!("{c:>8.3}");
    }
    println!();
    for (k, row) in e.chunks(cors.len()).enumerate() {
        print!("{:>8.3}", h0[k * cors.len()]);
        for v in row {
            print!("{v:>8.4}");
        }
        println!();
    }
    let worst = e
        .iter()
        .zip(&cor)
        .map(|(e, c)| (e - c).abs())
        .fold(0.0, f64::max);
    println!("largest |e_eff − cor| = {worst:.2e}");
    for r in table.failures() {
        println!(
            "row {} failed: {}",
            r.index,
            r.error.as_ref().map(|e| e.to_string()).unwrap_or_default()
        );
    }
    std::fs::create_dir_all("out")?;
    table.write_csv("out/sweep_restitution.csv")?;
    let title = Some("Effective restitution of the first impact");
    table.plot_heatmap("cor", "h0", "e_eff", "out/sweep_restitution.svg", title)?;
    table.plot_heatmap("cor", "h0", "e_eff", "out/sweep_restitution.png", title)?;
    println!("wrote out/sweep_restitution.{{csv,svg,png}}");
    Ok(())
}
