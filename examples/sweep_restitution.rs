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
//! and prints the wall times, the throughput ratio and, per repeat, how many cores other
//! processes kept busy meanwhile (from `/proc/stat`), so that a ratio measured on a loaded
//! machine is seen as such (BENCHMARKS.md, "Parameter sweeps").

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

/// Busy CPU time \[s\] of this process and of the whole machine so far (user + system
/// from `/proc/self/stat`; everything but idle and iowait from `/proc/stat`), in clock ticks
/// of 10 ms; NaN where `/proc` is missing (not Linux).
fn cpu_seconds() -> (f64, f64) {
    let read = |path: &str| std::fs::read_to_string(path).unwrap_or_default();
    let numbers = |s: &str| -> Vec<f64> {
        s.split_whitespace()
            .filter_map(|v| v.parse().ok())
            .collect()
    };
    // Fields after the command name (which may hold spaces): utime is the 12th, stime 13th.
    let stat = read("/proc/self/stat");
    let own: Vec<&str> = stat
        .rsplit_once(')')
        .map_or("", |(_, r)| r)
        .split_whitespace()
        .collect();
    let own = match (own.get(11), own.get(12)) {
        (Some(u), Some(s)) => {
            (u.parse::<f64>().unwrap_or(f64::NAN) + s.parse::<f64>().unwrap_or(f64::NAN)) / 100.0
        }
        _ => f64::NAN,
    };
    // `cpu  user nice system idle iowait irq softirq steal …`
    let all = numbers(read("/proc/stat").lines().next().unwrap_or_default());
    let machine = if all.len() >= 8 {
        (all.iter().take(8).sum::<f64>() - all[3] - all[4]) / 100.0
    } else {
        f64::NAN
    };
    (own, machine)
}

/// One timed sweep: wall time \[s\], this process's CPU time \[s\], and the cores other
/// processes kept busy meanwhile (machine busy time minus ours, over the wall time).
struct Timing {
    wall: f64,
    cpu: f64,
    foreign: f64,
}

fn timed(sweep: &Sweep, reference: &SweepTable) -> Result<Timing, Box<dyn std::error::Error>> {
    let ((own0, all0), t) = (cpu_seconds(), Instant::now());
    let table = sweep.run()?;
    let wall = t.elapsed().as_secs_f64();
    let (own1, all1) = cpu_seconds();
    if table != *reference {
        return Err("a table differs from the 1-thread reference".into());
    }
    let cpu = own1 - own0;
    Ok(Timing {
        wall,
        cpu,
        foreign: ((all1 - all0 - cpu) / wall).max(0.0),
    })
}

fn bench(repeats: usize) -> Result<(), Box<dyn std::error::Error>> {
    // Longer and tighter runs than the study's (3 s at rtol 1e-9, every bounce until rest), so
    // that a sweep takes about a second and thread start-up is not what is measured.
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
    // The runs' own wall times (one thread): two threads cannot finish before the longest
    // run nor before half the sum, whatever the scheduling.
    let walls = sweep
        .clone()
        .threads(1)
        .metric("wall", "s", |res| Ok(res.stats.wall_time))
        .run()?
        .column("wall")
        .unwrap_or_default();
    let (sum, longest) = (
        walls.iter().sum::<f64>(),
        walls.iter().copied().fold(0.0, f64::max),
    );
    let (one, two) = (sweep.clone().threads(1), sweep.threads(2));
    let mut pairs = vec![];
    for _ in 0..repeats {
        pairs.push((timed(&one, &reference)?, timed(&two, &reference)?));
    }
    println!(
        "{} runs per sweep, {repeats} repeats of (1 thread, 2 threads), {} cores; /proc/loadavg at the start: {}; every table equal to the first bit for bit",
        reference.rows.len(),
        std::thread::available_parallelism().map_or(0, |n| n.get()),
        load.trim()
    );
    println!(
        "runs' integration wall times: sum {sum:.3} s, longest {longest:.4} s, median {:.4} s: bound on the 2-thread ratio by the longest run {:.2}",
        median(walls.clone()),
        sum / (0.5 * sum).max(longest)
    );
    // The scheduling alone, whatever the load: the same run times slept (no CPU) by a
    // sweep's constructor on 2 threads.
    let slept = walls.clone();
    let replay = Sweep::new(move |p| {
        let t = slept.get(p.index()).copied().unwrap_or(0.0);
        std::thread::sleep(std::time::Duration::from_secs_f64(t));
        Err("replay only".into())
    })
    .points(one.param_points().ok_or("no points")?.clone())
    .threads(2)
    .progress(false);
    let t = Instant::now();
    replay.run()?;
    let makespan = t.elapsed().as_secs_f64();
    println!(
        "the same run times slept on 2 threads (scheduling only, no CPU): {makespan:.3} s, ratio {:.2}",
        sum / makespan
    );
    println!("| repeat | 1 thread [s] | 2 threads [s] | ratio | other processes' load during 1 / 2 [cores] | CPU 1 / 2 [s] |");
    println!("|---|---|---|---|---|---|");
    for (i, (a, b)) in pairs.iter().enumerate() {
        println!(
            "| {i} | {:.3} | {:.3} | {:.2} | {:.2} / {:.2} | {:.3} / {:.3} |",
            a.wall,
            b.wall,
            a.wall / b.wall,
            a.foreign,
            b.foreign,
            a.cpu,
            b.cpu
        );
    }
    let runs = reference.rows.len() as f64;
    let summary = |what: &str, sel: Vec<&(Timing, Timing)>| {
        if sel.is_empty() {
            println!("{what}: none");
            return;
        }
        let t1 = median(sel.iter().map(|p| p.0.wall).collect());
        let t2 = median(sel.iter().map(|p| p.1.wall).collect());
        let r = median(sel.iter().map(|p| p.0.wall / p.1.wall).collect());
        println!(
            "{what} ({} repeats): median 1 thread {t1:.3} s ({:.1} runs/s), 2 threads {t2:.3} s ({:.1} runs/s); median per-repeat ratio {r:.2}",
            sel.len(),
            runs / t1,
            runs / t2
        );
    };
    summary("all", pairs.iter().collect());
    summary(
        "quiet (other processes < 0.1 cores during both)",
        pairs
            .iter()
            .filter(|(a, b)| a.foreign < 0.1 && b.foreign < 0.1)
            .collect(),
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
