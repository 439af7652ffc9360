//! Random scenes nobody tuned (issue 15, point 1): a bounded batch of generated scenes
//! (`tests/fuzz/`) must end, each fast or with a typed error. The batch FAILS on any panic,
//! any process abort or hang, any non-finite value in a result signal, and any run that ends
//! without a typed error later than twice its wall budget (`SimOptions::max_wall_time`).
//! Typed build errors (a missing contact pair, a deep initial penetration, …) and typed
//! simulation errors (the work budget, chattering, …) are fair outcomes: counted and printed.
//!
//! Seeds: the base seed comes from the git HEAD commit (new scenes for every commit), or from
//! `MODIA3D_FUZZ_SEED` (decimal or 0x-hex) to replay a batch; `MODIA3D_FUZZ_SCENE=<scene seed>`
//! runs and prints one scene (`replay_one_scene`). Every failure prints its scene seed and the
//! scene as JSON (a reproducer for `tests/regressions/`).
//!
//! Each scene runs in a worker process (this test binary, re-invoked for `fuzz_worker`) with
//! `catch_unwind` around it: a panic is an outcome, an abort kills only the worker (the driver
//! records it and starts a new worker behind that scene).
//!
//! `cargo test --release --test fuzz_scenes -- --ignored` runs 10,000 scenes (20 s wall budget
//! each, the yardstick; `MODIA3D_FUZZ_WALL` sets another) and prints the
//! class table with the median and 99th-percentile wall time per run.

mod fuzz;

use fuzz::run::{is_failure, minimise, run_scene, Outcome};
use fuzz::{generate, scene_seed};
use std::collections::BTreeMap;
use std::io::{BufRead, BufReader, Read, Write};
use std::process::{Command, Stdio};
use std::sync::mpsc;
use std::time::{Duration, Instant};

/// Scenes of the CI batch: 300 took 83 s with 2 workers on a 2-core machine shared with two
/// other builds (debug profile at opt-level 2; BENCHMARKS.md, "Random scenes"), within the
/// ~3 min CI allows.
const CI_SCENES: u64 = 300;
/// Scenes of the ignored long batch.
const LONG_SCENES: u64 = 10_000;
/// Wall budget per scene of the long batch \[s\] (issue 15's yardstick).
const LONG_WALL: f64 = 20.0;

fn parse_seed(s: &str) -> Option<u64> {
    let s = s.trim();
    match s.strip_prefix("0x") {
        Some(h) => u64::from_str_radix(h, 16).ok(),
        None => s.parse().ok(),
    }
}

/// The commit id of the git HEAD of this checkout (a worktree's `.git` file followed), if
/// readable.
fn git_head() -> Option<String> {
    let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR"));
    let dot = root.join(".git");
    let gitdir = if dot.is_file() {
        let s = std::fs::read_to_string(&dot).ok()?;
        std::path::PathBuf::from(s.trim().strip_prefix("gitdir:")?.trim())
    } else {
        dot
    };
    let head = std::fs::read_to_string(gitdir.join("HEAD")).ok()?;
    let Some(r) = head.trim().strip_prefix("ref:") else {
        return Some(head.trim().to_string());
    };
    let r = r.trim();
    let common = std::fs::read_to_string(gitdir.join("commondir"))
        .map(|c| gitdir.join(c.trim()))
        .unwrap_or_else(|_| gitdir.clone());
    for dir in [&gitdir, &common] {
        if let Ok(id) = std::fs::read_to_string(dir.join(r)) {
            return Some(id.trim().to_string());
        }
        if let Ok(packed) = std::fs::read_to_string(dir.join("packed-refs")) {
            if let Some(line) = packed.lines().find(|l| l.ends_with(&format!(" {r}"))) {
                return line.split(' ').next().map(str::to_string);
            }
        }
    }
    None
}

/// The batch's base seed: `MODIA3D_FUZZ_SEED`, else from the HEAD commit, else fixed.
fn base_seed() -> u64 {
    if let Some(s) = std::env::var("MODIA3D_FUZZ_SEED")
        .ok()
        .and_then(|s| parse_seed(&s))
    {
        return s;
    }
    match git_head() {
        // FNV-1a of the commit id.
        Some(id) => id.bytes().fold(0xcbf2_9ce4_8422_2325u64, |h, b| {
            (h ^ b as u64).wrapping_mul(0x100_0000_01b3)
        }),
        None => 0x5eed_1515,
    }
}

/// Worker side: runs the scenes named in `MODIA3D_FUZZ_WORKER` (`base:first:step:count`) and
/// prints one line per scene; a no-op without that variable.
#[test]
fn fuzz_worker() {
    let Ok(spec) = std::env::var("MODIA3D_FUZZ_WORKER") else {
        return;
    };
    let v: Vec<u64> = spec.split(':').filter_map(parse_seed).collect();
    let [base, first, step, count] = v[..] else {
        panic!("MODIA3D_FUZZ_WORKER = {spec}: expected base:first:step:count");
    };
    std::panic::set_hook(Box::new(|_| {})); // panics are outcomes, reported below
    let wall = wall_budget();
    let mut out = std::io::stdout();
    for k in 0..count {
        let i = first + k * step;
        let _ = writeln!(out, "FUZZ|start|{i}");
        let _ = out.flush();
        let mut s = generate(scene_seed(base, i));
        if let Some(w) = wall {
            s.run.max_wall_time = w;
        }
        let o = run_scene(&s);
        let detail = o.detail.replace(['\n', '|'], " ");
        let _ = writeln!(out, "FUZZ|done|{i}|{}|{}|{detail}", o.class, o.wall);
        let _ = out.flush();
    }
}

/// `MODIA3D_FUZZ_WALL=<s>`: every scene's wall budget (`SimOptions::max_wall_time`) in place
/// of the generator's 2 s; the driver passes it on to its workers.
fn wall_budget() -> Option<f64> {
    std::env::var("MODIA3D_FUZZ_WALL")
        .ok()
        .and_then(|w| w.parse::<f64>().ok())
        .filter(|w| w.is_finite() && *w > 0.0)
}

/// Results of a batch: the outcome of every scene index.
struct Batch {
    base: u64,
    outcomes: BTreeMap<u64, Outcome>,
}

/// Runs scenes `first, first + step, …` (`count` of them) in worker processes, restarting a
/// worker after an abort or a hang (no line for `hang_after`).
fn run_worker_share(
    base: u64,
    first: u64,
    step: u64,
    count: u64,
    hang_after: Duration,
    wall: Option<f64>,
) -> Vec<(u64, Outcome)> {
    let mut done = vec![];
    let mut next = 0; // index into the share
    while next < count {
        let mut cmd = Command::new(std::env::current_exe().expect("test binary"));
        cmd.args(["fuzz_worker", "--exact", "--nocapture", "--test-threads=1"])
            .env(
                "MODIA3D_FUZZ_WORKER",
                format!("{base}:{}:{step}:{}", first + next * step, count - next),
            );
        if let Some(w) = wall {
            cmd.env("MODIA3D_FUZZ_WALL", w.to_string());
        }
        let mut child = cmd
            .stdout(Stdio::piped())
            .stderr(Stdio::piped())
            .spawn()
            .expect("spawn a fuzz worker");
        let stdout = child.stdout.take().expect("piped");
        let mut stderr = child.stderr.take().expect("piped");
        let err_tail = std::thread::spawn(move || {
            let mut s = String::new();
            let _ = stderr.read_to_string(&mut s);
            s.chars()
                .rev()
                .take(600)
                .collect::<Vec<_>>()
                .into_iter()
                .rev()
                .collect::<String>()
        });
        let (tx, rx) = mpsc::channel();
        std::thread::spawn(move || {
            for line in BufReader::new(stdout).lines().map_while(Result::ok) {
                if tx.send(line).is_err() {
                    break;
                }
            }
        });
        let mut current = None;
        let mut started = Instant::now();
        let lost = loop {
            match rx.recv_timeout(hang_after) {
                Ok(line) => {
                    let f: Vec<&str> = line.splitn(6, '|').collect();
                    match f[..] {
                        ["FUZZ", "start", i] => {
                            current = parse_seed(i);
                            started = Instant::now();
                        }
                        ["FUZZ", "done", i, class, wall, detail] => {
                            let i = parse_seed(i).expect("index");
                            let o = Outcome {
                                class: class.into(),
                                detail: detail.into(),
                                wall: wall.parse().unwrap_or(f64::NAN),
                            };
                            done.push((i, o));
                            current = None;
                            next += 1;
                        }
                        _ => {}
                    }
                }
                Err(mpsc::RecvTimeoutError::Timeout) => {
                    let _ = child.kill();
                    break current.map(|i| (i, "hang", format!("no answer for {hang_after:?}")));
                }
                Err(mpsc::RecvTimeoutError::Disconnected) => {
                    let status = child.wait().ok();
                    break current.map(|i| (i, "abort", format!("worker exited: {status:?}")));
                }
            }
        };
        let _ = child.wait();
        let tail = err_tail.join().unwrap_or_default();
        match lost {
            Some((i, class, why)) => {
                done.push((
                    i,
                    Outcome {
                        class: class.into(),
                        detail: format!("{why}; stderr: {tail}"),
                        wall: started.elapsed().as_secs_f64(),
                    },
                ));
                next += 1;
            }
            None if next < count => panic!("fuzz worker stopped before its first scene: {tail}"),
            None => {}
        }
    }
    done
}

/// Runs `count` scenes of base seed `base` on `jobs` worker processes.
fn run_batch(base: u64, count: u64, jobs: u64, wall: Option<f64>) -> Batch {
    // A worker silent for three wall budgets (at least a minute) is hung.
    let hang_after = Duration::from_secs_f64(wall.map_or(60.0, |w| (3.0 * w).max(60.0)));
    let handles: Vec<_> = (0..jobs.min(count))
        .map(|w| {
            let share = (count - w).div_ceil(jobs);
            std::thread::spawn(move || run_worker_share(base, w, jobs, share, hang_after, wall))
        })
        .collect();
    let mut outcomes = BTreeMap::new();
    for h in handles {
        outcomes.extend(h.join().expect("worker thread"));
    }
    Batch { base, outcomes }
}

fn jobs() -> u64 {
    std::env::var("MODIA3D_FUZZ_JOBS")
        .ok()
        .and_then(|s| s.parse().ok())
        .unwrap_or_else(|| {
            std::thread::available_parallelism()
                .map(|n| n.get() as u64)
                .unwrap_or(1)
                .min(2)
        })
}

fn quantile(sorted: &[f64], q: f64) -> f64 {
    if sorted.is_empty() {
        return f64::NAN;
    }
    sorted[((sorted.len() - 1) as f64 * q).round() as usize]
}

/// Prints the class table and wall-time quantiles; returns the failures.
fn report(b: &Batch, wall: f64) -> Vec<(u64, &Outcome)> {
    let mut classes: BTreeMap<&str, usize> = BTreeMap::new();
    for o in b.outcomes.values() {
        *classes.entry(o.class.as_str()).or_default() += 1;
    }
    let mut walls: Vec<f64> = b.outcomes.values().map(|o| o.wall).collect();
    walls.sort_by(f64::total_cmp);
    println!(
        "fuzz batch: base seed {:#x}, {} scenes in {wall:.1} s; wall per run: median {:.3} s, p99 {:.3} s, max {:.3} s",
        b.base,
        b.outcomes.len(),
        quantile(&walls, 0.5),
        quantile(&walls, 0.99),
        walls.last().copied().unwrap_or(f64::NAN)
    );
    for (c, n) in &classes {
        println!("  {n:>6}  {c}");
    }
    // Issue 15's acceptance counts as finished a run that reached its stop time and a scene
    // refused at build time with a typed error (an invalid scene is answered, not simulated).
    // A run stopped by `TooDeep` is the same answer given during the run: the depth limit is
    // the one a build refuses an initial overlap by (docs/contact-model.md §4, "The depth
    // limit"), reached when what drives two solids together is more than the contact law can
    // carry (a 600 kg body of 1 cm on a 3 mm plate). It is counted beside the others, not in
    // them, so either reading of "finished" can be taken from the line.
    let n = b.outcomes.len().max(1) as f64;
    let count = |p: &dyn Fn(&str) -> bool| b.outcomes.values().filter(|o| p(&o.class)).count();
    let ok = count(&|c| c == "ok");
    let built = count(&|c| c.starts_with("build:"));
    let too_deep = count(&|c| c == "sim:TooDeep");
    let slow_ok = b
        .outcomes
        .values()
        .filter(|o| o.class == "ok" && o.wall > 2.0)
        .count();
    println!(
        "  finished: {:.2} % (ran to the end {:.2} %, typed build error {:.2} %, depth limit during the run {:.2} %); without the depth limit {:.2} %; {slow_ok} runs to the end took over 2 s",
        100.0 * (ok + built + too_deep) as f64 / n,
        100.0 * ok as f64 / n,
        100.0 * built as f64 / n,
        100.0 * too_deep as f64 / n,
        100.0 * (ok + built) as f64 / n,
    );
    if std::env::var_os("MODIA3D_FUZZ_VERBOSE").is_some() {
        for (i, o) in &b.outcomes {
            let seed = scene_seed(b.base, *i);
            println!(
                "scene {i} {seed:#x} (rtol {:.1e}): {} {:.3} s: {}",
                generate(seed).run.rtol,
                o.class,
                o.wall,
                o.detail
            );
        }
    }
    let failures: Vec<_> = b
        .outcomes
        .iter()
        .filter(|(_, o)| is_failure(&o.class))
        .map(|(&i, o)| (i, o))
        .collect();
    for (i, o) in &failures {
        let seed = scene_seed(b.base, *i);
        println!(
            "FAILED scene {i} (scene seed {seed:#x}; replay: MODIA3D_FUZZ_SCENE={seed:#x} cargo test --test fuzz_scenes replay_one_scene -- --nocapture): {} after {:.2} s: {}\n  scene: {}",
            o.class,
            o.wall,
            o.detail,
            generate(seed).to_json()
        );
    }
    failures
}

/// Runs `count` scenes, each with the wall budget `MODIA3D_FUZZ_WALL` or else `wall` (`None`:
/// the generator's 2 s), and fails on any failure class.
fn batch_test(count: u64, wall: Option<f64>) {
    let base = base_seed();
    let started = Instant::now();
    let b = run_batch(base, count, jobs(), wall_budget().or(wall));
    let failures = report(&b, started.elapsed().as_secs_f64());
    assert_eq!(b.outcomes.len() as u64, count, "every scene has an outcome");
    assert!(
        failures.is_empty(),
        "{} of {count} scenes failed (base seed {base:#x}, replay the batch with MODIA3D_FUZZ_SEED={base:#x}); see above",
        failures.len()
    );
}

/// The CI batch: `CI_SCENES` scenes (override with `MODIA3D_FUZZ_COUNT`).
#[test]
fn random_scenes_end_fast_or_with_a_typed_error() {
    let count = std::env::var("MODIA3D_FUZZ_COUNT")
        .ok()
        .and_then(|s| s.parse().ok())
        .unwrap_or(CI_SCENES);
    batch_test(count, None);
}

/// The long batch (issue 15 acceptance): 10,000 scenes with a 20 s wall budget each, the
/// yardstick of the issue ("0 runs over 20 s wall without a typed error"); the CI batch keeps
/// the generator's 2 s to stay within CI's time. `MODIA3D_FUZZ_WALL=2` reproduces the 2 s table.
#[test]
#[ignore = "long: 10,000 scenes; cargo test --release --test fuzz_scenes -- --ignored"]
fn ten_thousand_random_scenes() {
    batch_test(LONG_SCENES, Some(LONG_WALL));
}

/// Replays one scene (`MODIA3D_FUZZ_SCENE=<scene seed>`, optionally `MODIA3D_FUZZ_WALL=<s>` for
/// its wall budget): prints the scene, its outcome and a minimised scene with the same outcome
/// class (a reproducer for `tests/regressions/`; work-budget outcomes only with
/// `MODIA3D_FUZZ_MINIMISE=1`; `MODIA3D_FUZZ_MINIMISE_CONTAINS=<phrase>` keeps only candidates
/// whose message still contains the phrase).
#[test]
fn replay_one_scene() {
    let Some(seed) = std::env::var("MODIA3D_FUZZ_SCENE")
        .ok()
        .and_then(|s| parse_seed(&s))
    else {
        return;
    };
    let mut s = generate(seed);
    // A smaller wall budget for the reproducer (minimising runs the scene many times).
    if let Some(w) = wall_budget() {
        s.run.max_wall_time = w;
    }
    println!("scene {seed:#x}: {}", s.to_json());
    let o = run_scene(&s);
    println!("outcome: {} after {:.3} s: {}", o.class, o.wall, o.detail);
    let class = o.class.clone();
    // A wall-time outcome depends on the machine's load: minimising on it keeps candidates
    // that were merely slow at that moment, so such scenes are kept whole unless
    // `MODIA3D_FUZZ_MINIMISE` is set (with a small `MODIA3D_FUZZ_WALL`, to take them apart).
    let m = if class == "sim:WorkBudget" && std::env::var_os("MODIA3D_FUZZ_MINIMISE").is_none() {
        s.clone()
    } else {
        // `MODIA3D_FUZZ_MINIMISE_CONTAINS=<phrase>`: a candidate must also keep the phrase in
        // its message (e.g. `at t = 0.0000` for a collapse at the start, or a cause).
        let phrase = std::env::var("MODIA3D_FUZZ_MINIMISE_CONTAINS").ok();
        minimise(&s, &|c| {
            let o = run_scene(c);
            o.class == class && phrase.as_deref().is_none_or(|p| o.detail.contains(p))
        })
    };
    println!(
        "minimised ({} bodies): {}",
        m.bodies.len(),
        serde_json::json!({ "seed": seed, "expected": class, "scene": m })
    );
}

/// Reruns a list of scenes as they are, without minimising (`MODIA3D_FUZZ_SCENES=<seed>,<seed>,…`,
/// optionally `MODIA3D_FUZZ_WALL=<s>` for every scene's wall budget): one line per scene with
/// its outcome class, wall time and message. For the question whether work-budget runs would
/// finish with more time (BENCHMARKS.md, "Random scenes"); a no-op without the variable.
#[test]
fn replay_scenes() {
    let Ok(list) = std::env::var("MODIA3D_FUZZ_SCENES") else {
        return;
    };
    let wall = wall_budget();
    for seed in list.split([',', ' ', '\n']).filter_map(parse_seed) {
        let mut s = generate(seed);
        if let Some(w) = wall {
            s.run.max_wall_time = w;
        }
        let o = run_scene(&s);
        println!(
            "replay {seed:#x}: {} {:.3} s (budget {} s, stop {} s, rtol {:.1e}): {}",
            o.class, o.wall, s.run.max_wall_time, s.run.stop_time, s.run.rtol, o.detail
        );
    }
}
