//! modia3d against Rapier (`rapier3d-f64`) at equal error, in one run (issue 16, point 7).
//!
//! For each scene of docs/rapier-comparison.md both sides run a ladder of accuracy settings
//! (modia3d: rtol 1e-2 … 1e-9; Rapier: time step × solver iterations); each setting's wall
//! time is the median of `RUNS` runs and its error is measured against the scene's reference
//! (analytic, or a converged run of the same law). Per scene the program prints a table and
//! the wall ratio modia3d / Rapier at errors 1e-2, 1e-3 and 1e-4, interpolated on each side's
//! error–wall front (see [`wall_at`]). Release build, from this directory:
//!
//!     cargo run --release [scene-name-filter]

mod rapier_side;
mod scenes;

use rapier_side::Setting;

/// Runs per setting; the wall time is their median.
pub const RUNS: usize = 5;

/// One setting's result on one side.
pub struct Point {
    /// "rtol 1e-6" or "dt 1/960, it 4".
    pub setting: String,
    /// Median wall time \[s\].
    pub wall: f64,
    /// Error against the scene's reference (the scene defines it; `INFINITY` when the run
    /// failed or missed an event the error needs).
    pub error: f64,
    /// Scene-specific detail (work counters, mirror error, ...).
    pub note: String,
}

/// Median of `runs` calls of `f`, which returns (wall \[s\], error, note); error and note of
/// the last run (every run is the same computation).
pub fn median_of(setting: String, runs: usize, mut f: impl FnMut() -> (f64, f64, String)) -> Point {
    let mut walls = Vec::with_capacity(runs);
    let mut last = (f64::INFINITY, String::new());
    for _ in 0..runs {
        let (w, e, n) = f();
        walls.push(w);
        last = (e, n);
    }
    walls.sort_by(f64::total_cmp);
    Point {
        setting,
        wall: walls[walls.len() / 2],
        error: last.0,
        note: last.1,
    }
}

/// The modia3d ladder: rtol 1e-2 … 1e-9.
pub fn rtols() -> Vec<f64> {
    (2..=9).map(|k| 10f64.powi(-k)).collect()
}

/// The Rapier ladder: dt = 1/60 … 1/15360 s (factors of 4), with Rapier's default 4 solver
/// iterations and with 16.
pub fn rapier_settings() -> Vec<Setting> {
    let mut v = vec![];
    for iterations in [4, 16] {
        for k in 0..5 {
            v.push(Setting {
                dt: 1.0 / (60.0 * 4f64.powi(k)),
                iterations,
            });
        }
    }
    v
}

/// Wall time \[s\] at which a side reaches error `target`, from its points: the front of
/// settings that no other setting beats in both error and wall, sorted by error; `target` is
/// interpolated log-log between the two front points around it. Above every error it is the
/// cheapest point's wall; below every error `None` (not reached). Points whose setting says
/// "not ranked" (references, the paper's law) are left out.
pub fn wall_at(points: &[Point], target: f64) -> Option<f64> {
    let ranked = |p: &&Point| p.error.is_finite() && !p.setting.contains("not ranked");
    let mut front: Vec<(f64, f64)> = points
        .iter()
        .filter(ranked)
        .filter(|p| {
            !points.iter().filter(ranked).any(|q| {
                q.error.is_finite()
                    && q.error <= p.error
                    && q.wall <= p.wall
                    && (q.error < p.error || q.wall < p.wall)
            })
        })
        .map(|p| (p.error.max(1e-300), p.wall))
        .collect();
    front.sort_by(|a, b| b.0.total_cmp(&a.0)); // error descending, wall ascending
    front.dedup();
    let first = *front.first()?;
    if target >= first.0 {
        return Some(first.1);
    }
    for w in front.windows(2) {
        let ((e0, t0), (e1, t1)) = (w[0], w[1]);
        if target <= e0 && target >= e1 {
            let s = (target.ln() - e0.ln()) / (e1.ln() - e0.ln());
            return Some((t0.ln() + s * (t1.ln() - t0.ln())).exp());
        }
    }
    None
}

fn print_side(side: &str, points: &[Point]) {
    for p in points {
        println!(
            "| {side} | {} | {:.5} | {:.2e} | {} |",
            p.setting, p.wall, p.error, p.note
        );
    }
}

fn print_ratios(name: &str, m: &[Point], r: &[Point], targets: &[f64]) {
    println!();
    println!("{name}: wall at equal error (log-log on each side's front)");
    println!();
    println!("| error | modia3d [s] | Rapier [s] | modia3d / Rapier |");
    println!("|---:|---:|---:|---:|");
    for &e in targets {
        let (a, b) = (wall_at(m, e), wall_at(r, e));
        let f = |x: Option<f64>| x.map_or("not reached".to_string(), |x| format!("{x:.5}"));
        let ratio = match (a, b) {
            (Some(a), Some(b)) => format!("{:.3}", a / b),
            _ => "—".into(),
        };
        println!("| {e:.0e} | {} | {} | {ratio} |", f(a), f(b));
    }
}

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let only = std::env::args().nth(1).unwrap_or_default();
    for scene in scenes::all() {
        if !scene.name.contains(&only) {
            continue;
        }
        println!();
        println!("### {}", scene.name);
        println!();
        println!("{}", scene.about);
        println!();
        let m = (scene.modia)()?;
        let r = (scene.rapier)()?;
        println!("| side | setting | wall [s] (median of {RUNS}) | error | notes |");
        println!("|---|---|---:|---:|---|");
        print_side("modia3d", &m);
        print_side("Rapier", &r);
        print_ratios(scene.name, &m, &r, &[1e-2, 1e-3, 1e-4]);
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    fn pt(error: f64, wall: f64) -> Point {
        Point {
            setting: String::new(),
            wall,
            error,
            note: String::new(),
        }
    }

    /// The interpolation on the front: exact at the points, log-linear between them, the
    /// dominated point ignored, `None` below the smallest error.
    #[test]
    fn wall_at_interpolates_the_front() {
        let p = [pt(1e-2, 1.0), pt(1e-4, 100.0), pt(1e-3, 1000.0)];
        assert_eq!(wall_at(&p, 1e-2), Some(1.0));
        assert_eq!(wall_at(&p, 1e-1), Some(1.0));
        assert!((wall_at(&p, 1e-3).unwrap() - 10.0).abs() < 1e-9);
        assert_eq!(wall_at(&p, 1e-5), None);
    }
}
