//! Parameter sweeps (issue 14): a sweep's rows equal single `simulate` calls bit for bit, in
//! point order, whatever the thread count or shard split; failing runs are rows with their
//! typed error and the sweep finishes; Latin-hypercube points are stratified; the shard binary
//! (`examples/sweep_shard.rs`) and its merge give the in-process table, locally and on a
//! HyperQueue cluster (`scripts/hq_sweep.py`; run under `CI=true` or `MODIA3D_HQ_TEST=1`).
use modia3d::core::BoxError;
use modia3d::demo;
use modia3d::prelude::*;
use std::path::{Path, PathBuf};
use std::process::Command;

const G: f64 = 9.81;

fn quiet(stop: f64) -> SimOptions {
    SimOptions::new(stop)
        .tolerance(1e-6)
        .interval(0.01)
        .progress(false)
}

/// A bouncing-sphere sweep over drop height and restitution: each row's final height and
/// event count equal those of a single `simulate` of the same model, bit for bit, in the
/// grid's nested-loop order; 1 thread, 2 threads and 3 merged shards give the same table.
#[test]
fn sweep_rows_equal_single_runs_bit_for_bit() {
    let heights = [0.2, 0.35, 0.5];
    let cors = [0.6, 0.9];
    let sweep = demo::bouncing_sphere_sweep()
        .points(
            ParamPoints::grid(&[("h0", "m", heights.to_vec()), ("cor", "1", cors.to_vec())])
                .unwrap(),
        )
        .options(quiet(0.4))
        .final_value("ball.r_abs[2]")
        .progress(false);
    let one = sweep.clone().threads(1).run().unwrap();
    let two = sweep.clone().threads(2).run().unwrap();
    assert_eq!(one, two);
    let parts = (0..3).map(|i| sweep.run_shard(i, 3).unwrap()).collect();
    assert_eq!(SweepTable::merge(parts, Some(6)).unwrap(), one);

    let names: Vec<&str> = one.outputs.iter().map(|c| c.name.as_str()).collect();
    assert_eq!(names, ["ball.r_abs[2]", "events", "t_end"]);
    assert_eq!(one.outputs[0].unit, "m");
    assert_eq!(one.params[0].unit, "m");
    let mut i = 0;
    for &h0 in &heights {
        for &cor in &cors {
            let row = &one.rows[i];
            assert_eq!((row.index, row.params.as_slice()), (i, &[h0, cor][..]));
            assert!(row.error.is_none(), "{:?}", row.error);
            let pair = ContactPairMaterial::new(cor, 0.5, 0.001);
            let model = demo::BouncingSphere {
                h0,
                pair,
                ..Default::default()
            }
            .build()
            .unwrap();
            let res = model.simulate(&quiet(0.4)).unwrap();
            let z = res.signal("ball.r_abs[2]").unwrap().last().unwrap()[0];
            assert_eq!(row.outputs[0].to_bits(), z.to_bits(), "row {i}");
            assert_eq!(row.outputs[1], res.events.len() as f64);
            assert_eq!(row.outputs[2], 0.4);
            i += 1;
        }
    }
    // The runs differ: a higher drop bounces later (the sweep did not run one point six times).
    let z = one.column("ball.r_abs[2]").unwrap();
    assert!(z.windows(2).any(|w| w[0] != w[1]));
}

/// A free ball falling under gravity with a user force that turns non-finite after `t_fail`.
fn falling_ball(p: &Params) -> Result<Model, BoxError> {
    if p.get("mode")? == 1.0 {
        panic!("constructor broken for row {}", p.index());
    }
    let t_fail = p.get("t_fail")?;
    let mut s = SceneDesc::new();
    s.add(demo::world(SceneOptions::default()));
    let (r, zero) = ([0.0, 0.0, 1.0], [0.0; 3]);
    demo::add_free_sphere(&mut s, "ball", p.get("d")?, "Steel", None, r, zero, zero);
    s.add_force(ForceElement::ObjectForce {
        object: "ball".into(),
        law: ForceFn::new(move |t, _| Wrench {
            force: Vector3::new(0.0, 0.0, if t > t_fail { f64::NAN } else { 0.0 }),
            torque: Vector3::zeros(),
        }),
    });
    Ok(s.build()?)
}

/// Runs that fail — a negative diameter (scene error), a force turning NaN mid-run, a
/// constructor that panics — are rows with their typed error; the other rows are right (free
/// fall: z = 1 − g t²/2) and the sweep ends.
#[test]
fn failing_runs_are_rows_and_the_sweep_finishes() {
    let rows = vec![
        vec![0.1, 1e9, 0.0],
        vec![-0.1, 1e9, 0.0],
        vec![0.1, 0.05, 0.0],
        vec![0.1, 1e9, 1.0],
        vec![0.1, 1e9, 0.0],
    ];
    let points = ParamPoints::list(&[("d", "m"), ("t_fail", "s"), ("mode", "")], rows).unwrap();
    let table = Sweep::new(falling_ball)
        .points(points)
        .options(SimOptions::new(0.2).tolerance(1e-8))
        .final_value("ball.r_abs[2]")
        .progress(false)
        .threads(2)
        .run()
        .unwrap();
    assert_eq!(table.rows.len(), 5);
    let status: Vec<&str> = table.rows.iter().map(SweepRow::status).collect();
    assert_eq!(status, ["ok", "build", "simulation", "panic", "ok"]);
    let msg = |i: usize| table.rows[i].error.as_ref().unwrap().to_string();
    assert!(msg(1).contains("ball"), "{}", msg(1));
    assert!(msg(2).contains("non-finite"), "{}", msg(2));
    assert!(
        msg(3).contains("constructor broken for row 3"),
        "{}",
        msg(3)
    );
    // How far the failed run got [s]: past t_fail, before the stop time.
    let t_end = table.column("t_end").unwrap();
    assert!(t_end[2] >= 0.0 && t_end[2] < 0.2, "{}", t_end[2]);
    assert!(t_end[1].is_nan());
    let z = table.column("ball.r_abs[2]").unwrap();
    for i in [0, 4] {
        assert!((z[i] - (1.0 - 0.5 * G * 0.04)).abs() < 1e-6, "{}", z[i]);
    }
    assert!(z[1].is_nan() && z[2].is_nan() && z[3].is_nan());
}

/// A final value of a vector signal, or metric closures that panic or return an error, mark
/// their row (`output`, `panic`: the first error) and keep the other outputs; an unknown
/// parameter name is a typed error with a did-you-mean.
#[test]
fn metric_failures_and_unknown_parameters_are_rows() {
    let points = ParamPoints::list(&[("h0", "m")], vec![vec![0.2], vec![0.3], vec![0.4]]).unwrap();
    let table = demo::bouncing_sphere_sweep()
        .points(points)
        .options(quiet(0.05))
        .metric("vx", "m/s", |res| {
            Ok(res
                .signal("ball.v_abs[0]")?
                .last()
                .ok_or("no output point")?[0])
        })
        .final_value("ball.r_abs")
        .progress(false)
        .run()
        .unwrap();
    for r in &table.rows {
        let e = r.error.as_ref().unwrap();
        assert_eq!(e.status(), "output");
        assert!(e.to_string().contains("`ball.r_abs[0]`"), "{e}");
        // The metric still ran.
        assert_eq!(r.outputs[2], 0.0);
    }
    let s = demo::bouncing_sphere_sweep()
        .points(ParamPoints::list(&[("h0", "m")], vec![vec![0.3]]).unwrap())
        .options(quiet(0.05))
        .metric("bad", "", |_| panic!("metric broken"))
        .metric("err", "", |_| Err("not computable".into()))
        .progress(false)
        .run()
        .unwrap();
    let e = s.rows[0].error.as_ref().unwrap();
    assert_eq!(e.status(), "panic");
    assert!(
        e.to_string()
            .contains("metric `bad` panicked: metric broken"),
        "{e}"
    );
    assert!(s.rows[0].outputs[0] >= 0.0); // `events` computed
    assert!(s.rows[0].outputs[1].is_nan() && s.rows[0].outputs[2].is_nan());
    let p = Sweep::new(|p| {
        p.get("h00")?;
        unreachable!()
    })
    .points(ParamPoints::list(&[("h0", "m")], vec![vec![0.3]]).unwrap())
    .progress(false)
    .run()
    .unwrap();
    let e = p.rows[0].error.as_ref().unwrap().to_string();
    assert!(
        e.contains("no parameter `h00`") && e.contains("did you mean `h0`"),
        "{e}"
    );
    assert_eq!(p.rows[0].error.as_ref().unwrap().status(), "build");
}

/// Latin hypercube: for every parameter each of the n strata of probability holds exactly one
/// point (uniform: equal value intervals; log-uniform: equal intervals of ln x; normal with
/// n = 4: the quartiles ±0.674489750196082, 0); the same seed gives the same points, another
/// seed others; random points lie inside their bounds.
#[test]
fn latin_hypercube_is_stratified_and_seeded() {
    let n = 37;
    let dims = [
        (
            "a",
            "m",
            Distribution::Uniform {
                low: -2.0,
                high: 3.0,
            },
        ),
        (
            "b",
            "N",
            Distribution::LogUniform {
                low: 1e-3,
                high: 10.0,
            },
        ),
    ];
    let p = ParamPoints::latin_hypercube(&dims, n, 42).unwrap();
    assert_eq!(p.len(), n);
    let strata = |f: &dyn Fn(f64) -> f64, k: usize| {
        let mut s: Vec<usize> = (0..n)
            .map(|i| (f(p.row(i).unwrap()[k]) * n as f64).floor() as usize)
            .collect();
        s.sort_unstable();
        s
    };
    let all: Vec<usize> = (0..n).collect();
    assert_eq!(strata(&|x| (x + 2.0) / 5.0, 0), all);
    assert_eq!(strata(&|x| (x / 1e-3).ln() / (1e4f64).ln(), 1), all);
    assert_eq!(p, ParamPoints::latin_hypercube(&dims, n, 42).unwrap());
    assert_ne!(p, ParamPoints::latin_hypercube(&dims, n, 43).unwrap());

    let q = 0.674489750196082;
    let normal = [(
        "x",
        "",
        Distribution::Normal {
            mean: 1.0,
            std_dev: 2.0,
        },
    )];
    for seed in 0..20 {
        let p = ParamPoints::latin_hypercube(&normal, 4, seed).unwrap();
        let mut z: Vec<f64> = (0..4).map(|i| (p.row(i).unwrap()[0] - 1.0) / 2.0).collect();
        z.sort_by(f64::total_cmp);
        assert!(z[0] < -q && -q < z[1] && z[1] < 0.0 && 0.0 < z[2] && z[2] < q && q < z[3]);
    }
    let r = ParamPoints::random(&dims, 1000, 7).unwrap();
    assert_eq!(r, ParamPoints::random(&dims, 1000, 7).unwrap());
    for i in 0..1000 {
        let row = r.row(i).unwrap();
        assert!((-2.0..3.0).contains(&row[0]) && (1e-3..10.0).contains(&row[1]));
    }
}

// ---- the shard binary, locally and on HyperQueue ----------------------------------------

const SWEEP_FILE: &str = concat!(env!("CARGO_MANIFEST_DIR"), "/examples/bouncing_sweep.json");

/// `target/<profile>/examples/sweep_shard`, which `cargo test` builds with the examples
/// (`cargo test --test sweep` alone does not: `cargo build --example sweep_shard` first, or the
/// binary may be stale).
fn shard_binary() -> PathBuf {
    let exe = std::env::current_exe().unwrap();
    let profile_dir = exe.parent().and_then(Path::parent).unwrap();
    let bin = profile_dir
        .join("examples")
        .join(format!("sweep_shard{}", std::env::consts::EXE_SUFFIX));
    assert!(
        bin.is_file(),
        "{} is missing: `cargo test` builds it with the examples (or `cargo build --example sweep_shard`)",
        bin.display()
    );
    bin
}

fn scratch(name: &str) -> PathBuf {
    let d = Path::new(env!("CARGO_TARGET_TMPDIR")).join(format!("sweep-{name}"));
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).unwrap();
    d
}

/// The whole sweep of the file in this process (the reference for the shards' merge).
fn in_process() -> SweepTable {
    SweepSpec::read(SWEEP_FILE)
        .unwrap()
        .sweep(&demo::sweep_registry())
        .unwrap()
        .progress(false)
        .run()
        .unwrap()
}

fn run_ok(cmd: &mut Command) -> String {
    let out = cmd.output().unwrap();
    assert!(
        out.status.success(),
        "{cmd:?} failed:\n{}\n{}",
        String::from_utf8_lossy(&out.stdout),
        String::from_utf8_lossy(&out.stderr)
    );
    String::from_utf8_lossy(&out.stdout).into_owned()
}

/// Three shards of the example sweep file run by the binary (one with its index from the job
/// array's environment) and merged by it equal the in-process sweep row for row; a merge with
/// a part missing fails naming the row.
#[test]
fn shard_binary_parts_merge_to_the_in_process_table() {
    let bin = shard_binary();
    let dir = scratch("cli");
    // The parts' directory does not exist yet: the binary makes it.
    let part = |i: usize| dir.join(format!("parts/part-{i}.csv"));
    for i in 0..3 {
        let mut cmd = Command::new(&bin);
        cmd.args(["run", SWEEP_FILE, "--of", "3", "--out"])
            .arg(dir.join("parts/part-{shard}.csv"))
            .env_remove("HQ_TASK_ID")
            .env_remove("SLURM_ARRAY_TASK_COUNT");
        if i == 1 {
            cmd.env("SLURM_ARRAY_TASK_ID", "1");
        } else {
            cmd.args(["--shard", &i.to_string()]);
        }
        let msg = run_ok(&mut cmd);
        assert!(
            msg.contains(&format!("shard {i} of 3: 8 runs (4 ok, 4 failed)")),
            "{msg}"
        );
    }
    let merged = dir.join("merged.csv");
    let msg = run_ok(
        Command::new(&bin)
            .args(["merge", SWEEP_FILE, "--out"])
            .arg(&merged)
            .args((0..3).map(part)),
    );
    assert!(msg.contains("24 rows (12 failed)"), "{msg}");
    let table = SweepTable::read_csv(&merged).unwrap();
    assert_eq!(table, in_process());
    // Half the grid has a negative diameter: build errors naming the sphere.
    for r in &table.rows {
        assert_eq!(r.error.is_some(), r.params[2] < 0.0);
    }
    let out = Command::new(&bin)
        .args(["merge", SWEEP_FILE, "--out"])
        .arg(dir.join("bad.csv"))
        .args([part(0), part(2)])
        .output()
        .unwrap();
    assert!(!out.status.success());
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(err.contains("row 1 is missing"), "{err}");
}

/// A Python with the `hyperqueue` package: a venv under `~/.cache/modia3d-hq` (made and filled
/// by pip on first use), or, where `venv` is missing (Debian without python3-venv), a
/// `pip install --target` directory on `PYTHONPATH`.
fn hq_python() -> Result<Command, String> {
    let cache = std::env::var_os("XDG_CACHE_HOME")
        .map(PathBuf::from)
        .or_else(|| std::env::var_os("HOME").map(|h| Path::new(&h).join(".cache")))
        .ok_or("neither XDG_CACHE_HOME nor HOME is set")?
        .join("modia3d-hq");
    let has_hq = |cmd: &mut Command| {
        cmd.args(["-c", "import hyperqueue"])
            .output()
            .is_ok_and(|o| o.status.success())
    };
    let venv_python = cache.join("venv/bin/python");
    let target = cache.join("site");
    let with_target = || {
        let mut c = Command::new("python3");
        c.env("PYTHONPATH", &target);
        c
    };
    if venv_python.is_file() && has_hq(&mut Command::new(&venv_python)) {
        return Ok(Command::new(&venv_python));
    }
    if target.is_dir() && has_hq(&mut with_target()) {
        return Ok(with_target());
    }
    let pip = "hyperqueue==0.27.0";
    let venv_ok = Command::new("python3")
        .args(["-m", "venv"])
        .arg(cache.join("venv"))
        .status()
        .is_ok_and(|s| s.success());
    if venv_ok {
        let ok = Command::new(&venv_python)
            .args(["-m", "pip", "install", "-q", pip])
            .status()
            .is_ok_and(|s| s.success());
        if ok && has_hq(&mut Command::new(&venv_python)) {
            return Ok(Command::new(&venv_python));
        }
    }
    for extra in [&[][..], &["--break-system-packages"][..]] {
        let ok = Command::new("python3")
            .args(["-m", "pip", "install", "-q", "--target"])
            .arg(&target)
            .args(extra)
            .arg(pip)
            .status()
            .is_ok_and(|s| s.success());
        if ok && has_hq(&mut with_target()) {
            return Ok(with_target());
        }
    }
    Err(format!(
        "could not install {pip} with pip (python3 -m venv / pip install --target {})",
        target.display()
    ))
}

/// The example sweep file in 8 shards on a local HyperQueue cluster of two workers
/// (`scripts/hq_sweep.py --local-workers 2`): the merged table equals the in-process sweep
/// row for row. Runs under `CI=true` (where a missing HyperQueue or pip is a failure) or with
/// `MODIA3D_HQ_TEST=1`; skipped otherwise.
#[test]
fn hyperqueue_shards_merge_to_the_in_process_table() {
    let ci = std::env::var("CI").is_ok_and(|v| v == "true");
    if !ci && std::env::var("MODIA3D_HQ_TEST").is_err() {
        eprintln!(
            "skipped: the HyperQueue test runs under CI=true or with MODIA3D_HQ_TEST=1 (it installs the `hyperqueue` Python package with pip into ~/.cache/modia3d-hq)"
        );
        return;
    }
    let bin = shard_binary();
    let mut python = hq_python().unwrap_or_else(|e| panic!("HyperQueue is needed: {e}"));
    let dir = scratch("hq");
    let merged = dir.join("merged.csv");
    let script = concat!(env!("CARGO_MANIFEST_DIR"), "/scripts/hq_sweep.py");
    let msg = run_ok(
        python
            .arg(script)
            .arg(SWEEP_FILE)
            .arg("--binary")
            .arg(&bin)
            .args(["--shards", "8", "--local-workers", "2", "--out"])
            .arg(&merged)
            .current_dir(&dir),
    );
    assert!(msg.contains("merged 8 parts: 24 rows (12 failed)"), "{msg}");
    let table = SweepTable::read_csv(&merged).unwrap();
    assert_eq!(table, in_process());
}
