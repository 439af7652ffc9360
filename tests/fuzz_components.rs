//! Random drive trains nobody tuned: a link or a two-link arm under gravity driven by random
//! servos (rigid, elastic or DC-motor drives; PI, PID, LimPID or sampled controllers; step,
//! ramp, sine, table or path references; parameters log-uniform over six decades; random
//! tolerances and steady-state starts). Every run must end, within its work budget, with
//! results or a typed error (`SceneErrors` or `SimError`): never a panic, never non-finite
//! results. A bounded batch runs in CI; `MODIA3D_FUZZ_COMPONENTS=<n>` runs more.

use modia3d::core::blocks::{
    Drive, Feedback, Gain, LimPID, PtpPath, Ramp, Sampled, Sine, Step, Table, PI, PID,
};
use modia3d::prelude::*;

/// xorshift64: a reproducible stream per seed.
struct Rng(u64);

impl Rng {
    fn next(&mut self) -> u64 {
        self.0 ^= self.0 << 13;
        self.0 ^= self.0 >> 7;
        self.0 ^= self.0 << 17;
        self.0
    }
    fn unit(&mut self) -> f64 {
        (self.next() >> 11) as f64 / (1u64 << 53) as f64
    }
    /// Log-uniform in `[lo, hi]`.
    fn log(&mut self, lo: f64, hi: f64) -> f64 {
        (lo.ln() + self.unit() * (hi.ln() - lo.ln())).exp()
    }
    fn pick(&mut self, n: usize) -> usize {
        (self.next() % n as u64) as usize
    }
}

/// A random scene and options for `seed`.
fn scene(seed: u64) -> (SceneDesc, SimOptions) {
    let mut r = Rng(seed | 1);
    let mut s = SceneDesc::new();
    s.add(Object3D::new("world").scene(SceneOptions::default()));
    let links = 1 + r.pick(2);
    let mut parent = "world".to_string();
    for i in 0..links {
        let (name, pivot) = (format!("link{i}"), format!("pivot{i}"));
        let len = r.log(0.05, 1.0);
        s.add(
            Object3D::new(&name).solid(
                Solid::new(Shape::Box {
                    lengths: Vector3::new(len, 0.05, 0.05),
                })
                .given_mass(r.log(0.01, 10.0)),
            ),
        )
        .add(
            Object3D::new(&pivot)
                .parent(&name)
                .translation([-len / 2.0, 0.0, 0.0]),
        );
        let attach = if i == 0 {
            "world".to_string()
        } else {
            let tip = format!("tip{i}");
            s.add(
                Object3D::new(&tip)
                    .parent(&parent)
                    .translation([0.5 * len, 0.0, 0.0]),
            );
            tip
        };
        let kind = if r.pick(4) == 0 {
            JointKind::prismatic(1)
        } else {
            JointKind::revolute(2)
        };
        s.add_joint(
            Joint::new(&format!("j{i}"), &attach, &pivot, kind).init_position(r.unit() - 0.5),
        );
        parent = name;
    }
    let t_end = r.log(0.1, 2.0);
    for i in 0..links {
        if r.pick(4) == 0 {
            continue; // an undriven joint
        }
        let p = |n: &str| format!("s{i}.{n}");
        let reference = match r.pick(5) {
            0 => ComponentDecl::new(
                &p("ref"),
                Step {
                    height: r.unit() - 0.5,
                    startTime: r.unit() * t_end,
                    ..Default::default()
                },
            ),
            1 => ComponentDecl::new(
                &p("ref"),
                Ramp {
                    height: 2.0 * r.unit() - 1.0,
                    duration: r.log(1e-3, 1.0),
                    ..Default::default()
                },
            ),
            2 => ComponentDecl::new(
                &p("ref"),
                Sine {
                    amplitude: r.unit(),
                    f: r.log(0.1, 100.0),
                    ..Default::default()
                },
            ),
            3 => ComponentDecl::new(
                &p("ref"),
                Table {
                    table: vec![(0.0, 0.0), (r.unit() * t_end, r.unit()), (t_end, 0.0)],
                },
            ),
            _ => ComponentDecl::new(
                &p("ref"),
                PtpPath {
                    positions: vec![vec![0.0], vec![r.unit() - 0.5], vec![0.0]],
                    v_max: vec![r.log(0.1, 10.0)],
                    a_max: vec![r.log(0.1, 100.0)],
                    startTime: 0.0,
                },
            ),
        };
        let out = if reference.component.kind() == "PtpPath" {
            "ref.q"
        } else {
            "ref.y"
        };
        let ratio = r.log(1.0, 300.0);
        let mut drive = Drive::rigid(&format!("j{i}"), ratio, r.log(1e-7, 1e-3));
        if r.pick(3) == 0 {
            drive = drive.elastic(r.log(10.0, 1e6), r.log(1e-3, 10.0));
        }
        let dc = r.pick(4) == 0;
        if dc {
            drive = drive.dc_motor(r.log(0.01, 10.0), r.log(1e-5, 1e-2), r.log(0.01, 1.0));
        }
        let (k, ti) = (r.log(1e-3, 1e2), r.log(1e-3, 1.0));
        let ctrl = match r.pick(4) {
            0 => ComponentDecl::new(&p("ctrl"), PI::new(k, ti)),
            1 => ComponentDecl::new(
                &p("ctrl"),
                PID {
                    k,
                    Ti: ti,
                    Td: r.log(1e-4, 0.1),
                    ..Default::default()
                },
            ),
            2 => ComponentDecl::new(&p("ctrl"), Sampled::new(r.log(1e-4, 1e-2), PI::new(k, ti))),
            _ => {
                let y_max = r.log(1e-2, 1e2);
                ComponentDecl::new(
                    &p("ctrl"),
                    LimPID {
                        k,
                        Ti: ti,
                        Td: r.log(1e-4, 0.1),
                        yMax: y_max,
                        yMin: -y_max,
                        ..Default::default()
                    },
                )
            }
        };
        let ctrl = if ctrl.component.kind() == "LimPID" {
            ctrl.input("u_s", p("err.y").as_str())
                .input("u_m", p("drive.motor_w").as_str())
        } else {
            ctrl.input("u", p("err.y").as_str())
        };
        s.add_component(reference)
            .add_component(
                ComponentDecl::new(
                    &p("gain"),
                    Gain {
                        k: ratio * r.log(0.1, 100.0),
                    },
                )
                .input("u", p(out).as_str()),
            )
            .add_component(
                ComponentDecl::new(&p("err"), Feedback)
                    .input("u1", p("gain.y").as_str())
                    .input("u2", p("drive.motor_phi").as_str()),
            )
            .add_component(ctrl)
            .add_component(
                ComponentDecl::new(&p("drive"), drive)
                    .input(if dc { "v" } else { "tau" }, p("ctrl.y").as_str()),
            );
    }
    let opts = SimOptions::new(t_end)
        .tolerance(r.log(1e-9, 1e-4))
        .steady_state(r.pick(4) == 0)
        .max_steps(Some(20_000))
        .quiet(true);
    (s, opts)
}

/// One run: `Ok(true)` if it finished, `Ok(false)` for a typed error, `Err` for what must
/// never happen (a panic, non-finite results).
fn run(seed: u64) -> Result<bool, String> {
    let outcome = std::panic::catch_unwind(|| {
        let (s, opts) = scene(seed);
        let model = match s.build() {
            Ok(m) => m,
            Err(e) => {
                if std::env::var("MODIA3D_FUZZ_VERBOSE").is_ok() {
                    println!(
                        "seed {seed:#x}: build: {}",
                        e.to_string().chars().take(160).collect::<String>()
                    );
                }
                return Ok::<bool, String>(false);
            }
        };
        match model.simulate(&opts) {
            Ok(r) => {
                let last = r.final_state().ok_or("no output point")?;
                if last.iter().any(|v| !v.is_finite()) {
                    return Err(format!("non-finite final state {last:?}"));
                }
                Ok(true)
            }
            Err(e) => {
                // A typed error with a message and its partial results.
                if e.to_string().is_empty() {
                    return Err("an error without a message".into());
                }
                if std::env::var("MODIA3D_FUZZ_VERBOSE").is_ok() {
                    let d = format!("{e:?}");
                    let kind = d
                        .lines()
                        .find(|l| l.contains("kind:"))
                        .unwrap_or("")
                        .trim()
                        .to_string();
                    println!(
                        "seed {seed:#x}: {kind}: {}",
                        e.to_string().chars().take(160).collect::<String>()
                    );
                }
                Ok(false)
            }
        }
    });
    match outcome {
        Ok(r) => r,
        Err(p) => Err(format!(
            "panicked: {}",
            p.downcast_ref::<String>()
                .cloned()
                .or_else(|| p.downcast_ref::<&str>().map(|s| s.to_string()))
                .unwrap_or_default()
        )),
    }
}

#[test]
fn random_drive_trains_end_or_fail_typed() {
    let n: u64 = std::env::var("MODIA3D_FUZZ_COMPONENTS")
        .ok()
        .and_then(|v| v.parse().ok())
        .unwrap_or(150);
    let (mut finished, mut typed) = (0, 0);
    let mut bad = vec![];
    for i in 0..n {
        let seed = 0x9e37_79b9_7f4a_7c15u64.wrapping_mul(i + 1);
        match run(seed) {
            Ok(true) => finished += 1,
            Ok(false) => typed += 1,
            Err(e) => bad.push(format!("seed {seed:#x}: {e}")),
        }
    }
    println!("{n} random drive trains: {finished} finished, {typed} typed errors");
    assert!(bad.is_empty(), "{}", bad.join("\n"));
    // Most random servos are runnable: a batch of only errors would test nothing.
    assert!(finished > n / 4, "only {finished} of {n} finished");
}
