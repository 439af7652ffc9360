//! Random sequences of calls on the builder and the step-wise API, each under `catch_unwind`:
//! wrong input names and lengths, NaN/inf/huge/tiny values everywhere, `advance_to` backwards
//! and past the stop time, `reset` at any point (also right after an event), signals by random
//! names and random accessor indices, `build()` twice. Asserts that no panic escapes the
//! library and that every failure is a typed error with a message.
//!
//! Seeded with a small SplitMix64 (no dependency); each sequence's seed is printed when it
//! fails. `API_FUZZ_SEQUENCES` and `API_FUZZ_SEED` override the count and the first seed.

use modia3d::prelude::*;
use std::panic::{catch_unwind, AssertUnwindSafe};
use std::sync::Arc;

/// SplitMix64 (Steele, Lea, Flood 2014): a full-period 64-bit generator, plenty for choosing
/// calls and values.
struct Rng(u64);

impl Rng {
    fn next(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^ (z >> 31)
    }
    /// Uniform in `0..n` (n > 0).
    fn below(&mut self, n: usize) -> usize {
        (self.next() % n as u64) as usize
    }
    fn chance(&mut self, p: f64) -> bool {
        self.unit() < p
    }
    /// Uniform in [0, 1).
    fn unit(&mut self) -> f64 {
        (self.next() >> 11) as f64 / (1u64 << 53) as f64
    }
    fn pick<'a, T>(&mut self, xs: &'a [T]) -> &'a T {
        &xs[self.below(xs.len())]
    }
    /// A number: mostly sensible in `[lo, hi]`, sometimes hostile.
    fn value(&mut self, lo: f64, hi: f64) -> f64 {
        const HOSTILE: [f64; 10] = [
            f64::NAN,
            f64::INFINITY,
            f64::NEG_INFINITY,
            0.0,
            -1.0,
            1e-300,
            1e300,
            -0.0,
            f64::MIN_POSITIVE,
            f64::EPSILON,
        ];
        if self.chance(0.04) {
            *self.pick(&HOSTILE)
        } else {
            lo + (hi - lo) * self.unit()
        }
    }
}

const OBJECTS: [&str; 5] = ["world", "ball", "box", "arm", "tip"];
const JOINTS: [&str; 3] = ["free", "rev", "slide"];
/// Names the calls use: the real ones, near misses, clashes and junk.
const NAMES: [&str; 14] = [
    "ball",
    "box",
    "arm",
    "rev",
    "free",
    "slide",
    "tau",
    "push",
    "bal",
    "",
    "ball.r_abs",
    "a|b",
    "world",
    "rev.phi",
];
const QUANTITIES: [&str; 12] = [
    "r_abs",
    "v_abs",
    "w_abs",
    "R_abs",
    "phi",
    "w",
    "s",
    "q",
    "r_abs[2]",
    "r_abs[9]",
    "f_n",
    "penetration",
];

/// A base scene (floor, free ball, a pendulum arm, a slider box, inputs), then random edits
/// of the kind a user makes: renames, broken references, hostile values, extra elements.
fn random_scene(rng: &mut Rng) -> SceneDesc {
    let mut s = SceneDesc::new();
    let mut opts = SceneOptions::default();
    if rng.chance(0.2) {
        opts.k_red = rng.value(1e-6, 1.0);
    }
    if rng.chance(0.1) {
        opts.hysteresis = rng.value(1e-9, 1e-5);
    }
    if rng.chance(0.1) {
        opts.gravity = Vector3::new(0.0, 0.0, rng.value(-20.0, 0.0));
    }
    s.add(Object3D::new("world").scene(opts))
        .add(
            Object3D::new("floor").parent("world").solid(
                Solid::new(Shape::Box {
                    lengths: Vector3::new(2.0, 2.0, 0.1),
                })
                .material("Steel"),
            ),
        )
        .add(
            Object3D::new("ball").solid(
                Solid::new(Shape::Sphere {
                    diameter: rng.value(0.01, 0.2),
                })
                .material("Steel"),
            ),
        )
        .add(
            Object3D::new("arm").solid(
                Solid::new(Shape::Box {
                    lengths: Vector3::new(0.05, 0.05, rng.value(0.1, 0.5)),
                })
                .mass(rng.value(0.1, 2.0))
                .collision(false),
            ),
        )
        .add(
            Object3D::new("tip")
                .parent("arm")
                .translation([0.0, 0.0, -0.2]),
        )
        .add(
            Object3D::new("box").solid(
                Solid::new(Shape::Box {
                    lengths: Vector3::new(0.1, 0.1, 0.1),
                })
                .mass(1.0)
                .collision(false),
            ),
        )
        .add_joint(Joint::new(
            "free",
            "world",
            "ball",
            JointKind::FreeMotion {
                r: Vector3::new(0.5, 0.0, rng.value(0.06, 0.3)),
                rot: FreeRotation::Cardan([0.0, rng.value(-1.0, 1.0), 0.0]),
                v: Vector3::new(rng.value(-2.0, 2.0), 0.0, rng.value(-2.0, 2.0)),
                w: Vector3::zeros(),
            },
        ))
        .add_joint(
            Joint::new("rev", "world", "arm", JointKind::revolute(1))
                .init_position(rng.value(-1.0, 1.0)),
        )
        .add_joint(
            Joint::new("slide", "world", "box", JointKind::prismatic(1))
                .init_velocity(rng.value(-1.0, 1.0)),
        )
        .add_input(Input::joint_force("tau", "rev"))
        .add_input(Input::object_wrench("push", "ball"));
    for _ in 0..rng.below(3) {
        edit(rng, &mut s);
    }
    s
}

/// One random edit of the scene description.
fn edit(rng: &mut Rng, s: &mut SceneDesc) {
    match rng.below(12) {
        0 => {
            let i = rng.below(s.objects.len());
            s.objects[i].name = rng.pick(&NAMES).to_string();
        }
        1 => {
            let i = rng.below(s.joints.len());
            s.joints[i].name = rng.pick(&NAMES).to_string();
        }
        2 => {
            let i = rng.below(s.joints.len());
            s.joints[i].obj1 = rng.pick(&OBJECTS).to_string();
        }
        3 => {
            let i = rng.below(s.objects.len());
            s.objects[i].translation =
                Vector3::new(rng.value(-1.0, 1.0), 0.0, rng.value(-1.0, 1.0));
        }
        4 => {
            let i = rng.below(s.objects.len());
            s.objects[i].rotation =
                Rotation::Cardan([rng.value(-3.0, 3.0), 0.0, rng.value(-3.0, 3.0)]);
        }
        5 => {
            let law_seed = rng.next();
            let object = rng.pick(&OBJECTS).to_string();
            s.add_force(ForceElement::ObjectForce {
                object,
                law: ForceFn::new(move |t, m| {
                    // Hostile user code: panics or returns NaN for some times and states.
                    let k = ((t * 1e4) as u64 ^ law_seed) % 50;
                    if k == 0 && law_seed % 3 == 0 {
                        panic!("fuzz law: deliberate panic at t = {t}");
                    }
                    let f = if k == 1 && law_seed % 3 == 1 {
                        f64::NAN
                    } else {
                        -m.v_abs.x
                    };
                    Wrench {
                        force: Vector3::new(f, 0.0, 0.0),
                        torque: Vector3::zeros(),
                    }
                }),
            });
        }
        6 => {
            s.add_force(ForceElement::SpringDamper {
                name: rng.pick(&NAMES).to_string(),
                obj1: rng.pick(&OBJECTS).to_string(),
                obj2: rng.pick(&OBJECTS).to_string(),
                stiffness: rng.value(0.0, 100.0),
                damping: rng.value(0.0, 1.0),
                length0: rng.value(0.0, 1.0),
            });
        }
        7 => {
            s.add_force(ForceElement::JointSpringDamper {
                joint: rng.pick(&JOINTS).to_string(),
                coordinate: None,
                stiffness: rng.value(0.0, 100.0),
                damping: rng.value(0.0, 1.0),
                offset: rng.value(-1.0, 1.0),
            });
        }
        8 => {
            let name = rng.pick(&NAMES).to_string();
            let joint = rng.pick(&JOINTS).to_string();
            s.add_input(match rng.below(3) {
                0 => Input::joint_force(&name, &joint),
                1 => Input::joint_acceleration(&name, &joint),
                _ => Input::object_wrench(&name, OBJECTS[rng.below(OBJECTS.len())]),
            });
        }
        9 => {
            if let Feature::Solid(solid) = &mut s.objects[2].feature {
                solid.mass_properties = match rng.below(3) {
                    0 => MassSpec::FromShapeAndMass(rng.value(1e-3, 10.0)),
                    1 => MassSpec::Explicit {
                        mass: rng.value(1e-3, 10.0),
                        com: Vector3::zeros(),
                        inertia: Matrix3::identity() * rng.value(-1e-3, 1e-3),
                    },
                    _ => MassSpec::FromShapeAndDensity,
                };
                if rng.chance(0.3) {
                    solid.material = Some(MaterialRef::Name(rng.pick(&NAMES).to_string()));
                }
            }
        }
        10 => {
            let q = nalgebra::Quaternion::new(rng.value(-1.0, 1.0), 0.0, rng.value(-1.0, 1.0), 0.0);
            s.joints[0].kind = JointKind::FreeMotion {
                r: Vector3::new(0.5, 0.0, 0.3),
                rot: FreeRotation::Quaternion(UnitQuaternion::new_unchecked(q)),
                v: Vector3::zeros(),
                w: Vector3::zeros(),
            };
        }
        _ => {
            s.add_contact_pair(
                ["Steel", "DryWood", "Rubber"][rng.below(3)],
                "Steel",
                ContactPairMaterial::new(
                    rng.value(0.0, 1.0),
                    rng.value(0.0, 1.0),
                    rng.value(0.0, 0.1),
                ),
            );
        }
    }
}

fn random_options(rng: &mut Rng) -> SimOptions {
    let mut o = SimOptions::new(rng.value(0.005, 0.05))
        .progress(false)
        .max_wall_time(0.5)
        .max_steps(Some(20_000));
    match rng.below(8) {
        0 => o = o.tolerance(rng.value(1e-9, 1e-3)),
        1 => o = o.interval(rng.value(1e-4, 1e-2)),
        2 => o = o.start_time(rng.value(-0.01, 0.01)),
        3 => o = o.max_step(rng.value(1e-5, 1e-2)),
        4 => o = o.atol(rng.value(1e-10, 1e-4)),
        5 => o = o.contact_results(true),
        6 => o = o.max_steps(Some(rng.below(50) as u64)),
        _ => {}
    }
    o
}

/// A random signal name: owner (object, joint, pair, junk) and quantity.
fn signal_name(rng: &mut Rng) -> String {
    let owner = match rng.below(3) {
        0 => rng.pick(&OBJECTS).to_string(),
        1 => rng.pick(&NAMES).to_string(),
        _ => "floor|ball".to_string(),
    };
    if rng.chance(0.05) {
        return owner; // no quantity at all
    }
    format!("{owner}.{}", rng.pick(&QUANTITIES))
}

/// Reads a signal of `res` by a random name and pokes its accessors with random indices.
fn poke_result(rng: &mut Rng, res: &SimulationResult) {
    let _ = res.signal_names();
    let _ = res.final_state();
    if let Ok(sig) = res.signal(&signal_name(rng)) {
        assert_eq!(sig.data.len(), sig.dim * sig.len());
        let _ = sig.last();
        let _ = sig.first();
        let k = match rng.below(3) {
            0 => rng.below(sig.len() + 2),
            1 => usize::MAX,
            _ => sig.len(),
        };
        assert_eq!(sig.at(k).is_some(), k < sig.len());
        let _ = sig.component(rng.below(12));
    }
}

/// What one sequence met: counts of successful calls and of typed errors.
#[derive(Default)]
struct Tally {
    built: usize,
    scene_errors: usize,
    sim_errors: usize,
    ok_calls: usize,
    /// Simulation errors by kind (the variant's name).
    kinds: std::collections::BTreeMap<String, usize>,
}

impl Tally {
    fn sim_error(&mut self, e: &SimError) {
        check_sim_error(e);
        self.sim_errors += 1;
        let kind = format!("{:?}", e.kind);
        let name = kind.split(['(', ' ', '{']).next().unwrap_or("").to_string();
        *self.kinds.entry(name).or_default() += 1;
    }
}

/// A failure is "typed" if it is one of the library's error enums with a non-empty message;
/// an `IdaError::Panic` would be a panic of the library itself, caught only at the FFI.
fn check_sim_error(e: &SimError) {
    assert!(!e.to_string().is_empty());
    let msg = e.kind.to_string();
    assert!(
        !msg.contains("a DaeSystem callback panicked"),
        "a library panic reached the FFI boundary: {msg}"
    );
}

/// One random sequence of calls.
fn sequence(seed: u64, tally: &mut Tally) {
    let mut rng = Rng(seed);
    let scene = random_scene(&mut rng);
    let first = scene.build();
    // build() twice gives the same verdict and the same errors.
    let second = scene.build();
    assert_eq!(first.is_ok(), second.is_ok());
    let model = match (first, second) {
        (Ok(m), Ok(_)) => m,
        (Err(a), Err(b)) => {
            // By text: the errors carry the offending values, and NaN != NaN.
            assert_eq!(a.to_string(), b.to_string());
            assert!(a.0.iter().all(|e| !e.to_string().is_empty()));
            tally.scene_errors += 1;
            return;
        }
        _ => unreachable!(),
    };
    tally.built += 1;
    let _ = model.signal_names();
    let _ = model.bodies();
    let opts = random_options(&mut rng);
    let mut sim = match model.simulation(&opts) {
        Ok(sim) => sim,
        Err(e) => {
            if std::env::var("API_FUZZ_VERBOSE").is_ok() {
                println!("seed {seed}: {e}");
            }
            tally.sim_error(&e);
            poke_result(&mut rng, &e.partial);
            return;
        }
    };
    let span = opts.stop_time - opts.start_time;
    for _ in 0..rng.below(12) + 1 {
        match rng.below(9) {
            0 | 1 => {
                let t = match rng.below(10) {
                    0 => sim.time() - span * rng.unit(), // backwards
                    1 => *rng.pick(&[f64::NAN, f64::INFINITY, f64::NEG_INFINITY]),
                    2 => opts.stop_time + span * rng.unit(), // past the stop time
                    3 => sim.time() + 1e-15,                 // a tiny step
                    4 => f64::NAN,                           // single solver steps instead
                    _ => sim.time() + 0.3 * span * rng.unit(),
                };
                let outcome = if t.is_nan() && rng.below(2) == 0 {
                    // A few single steps: each ends later, never past the stop time.
                    let mut r = Ok(());
                    for _ in 0..rng.below(20) + 1 {
                        let before = sim.time();
                        match sim.step() {
                            Ok(t) => {
                                assert!(t >= before && t <= opts.stop_time, "{before} → {t}")
                            }
                            Err(e) => {
                                r = Err(e);
                                break;
                            }
                        }
                    }
                    r
                } else {
                    sim.advance_to(t)
                };
                match outcome {
                    Ok(()) => tally.ok_calls += 1,
                    Err(e) => {
                        tally.sim_error(&e);
                        poke_result(&mut rng, &e.partial);
                        // After a failure only `reset` is promised to work; try it.
                        if let Err(e) = sim.reset() {
                            check_sim_error(&e);
                            return;
                        }
                    }
                }
            }
            2 => {
                let name = rng.pick(&NAMES);
                let n = *rng.pick(&[0usize, 1, 5, 6, 7]);
                let values: Vec<f64> = (0..n).map(|_| rng.value(-10.0, 10.0)).collect();
                match sim.set_input(name, &values) {
                    Ok(()) => tally.ok_calls += 1,
                    Err(e) => assert!(!e.to_string().is_empty()),
                }
            }
            3 => {
                // Reset at any point: right after an event if the last advance ended at one.
                match sim.reset() {
                    Ok(()) => tally.ok_calls += 1,
                    Err(e) => {
                        check_sim_error(&e);
                        return;
                    }
                }
            }
            4 => match sim.output(&signal_name(&mut rng)) {
                Ok(v) => assert!(!v.is_empty()),
                Err(e) => assert!(!e.to_string().is_empty()),
            },
            5 => poke_result(&mut rng, sim.result()),
            6 => {
                let _ = (sim.time(), sim.state().len(), sim.input_names());
            }
            7 => {
                // Structure changes with any names and gaps (also NaN, negative, huge): a typed
                // error or a new segment, never a panic.
                let (a, b) = (*rng.pick(&OBJECTS), *rng.pick(&OBJECTS));
                let gap = *rng.pick(&[f64::NAN, -1.0, 0.0, 1e-3, 10.0, f64::INFINITY]);
                let r = match rng.below(3) {
                    0 => sim.attach(a, b, gap),
                    1 => sim.release(a),
                    _ => sim.delete(a),
                };
                match r {
                    Ok(()) => tally.ok_calls += 1,
                    Err(e) => assert!(!e.to_string().is_empty()),
                }
            }
            _ => {
                // A second simulation of the same model runs independently.
                if let Ok(mut other) = model.simulation(&opts) {
                    let _ = other.advance_to(opts.start_time + 0.1 * span);
                }
            }
        }
    }
    poke_result(&mut rng, &sim.into_result());
}

#[test]
fn random_call_sequences_never_panic() {
    let count: u64 = std::env::var("API_FUZZ_SEQUENCES")
        .ok()
        .and_then(|s| s.parse().ok())
        .unwrap_or(500);
    let first: u64 = std::env::var("API_FUZZ_SEED")
        .ok()
        .and_then(|s| s.parse().ok())
        .unwrap_or(0x15_0006);
    // The deliberate panics of the fuzz force laws are expected (and caught by the library):
    // keep them off the test output; anything else goes to the default hook.
    let default_hook = Arc::new(std::panic::take_hook());
    let hook = default_hook.clone();
    std::panic::set_hook(Box::new(move |info| {
        let text = info
            .payload()
            .downcast_ref::<String>()
            .map(String::as_str)
            .or_else(|| info.payload().downcast_ref::<&str>().copied())
            .unwrap_or("");
        if !text.starts_with("fuzz law:") {
            hook(info);
        }
    }));
    let started = std::time::Instant::now();
    let mut tally = Tally::default();
    let mut escaped = vec![];
    for seed in first..first + count {
        let outcome = catch_unwind(AssertUnwindSafe(|| sequence(seed, &mut tally)));
        if outcome.is_err() {
            escaped.push(seed);
        }
    }
    let _ = std::panic::take_hook();
    println!(
        "{count} sequences (seeds {first}..{}) in {:.1} s: {} built, {} scene errors, {} simulation errors {:?}, {} successful calls",
        first + count,
        started.elapsed().as_secs_f64(),
        tally.built,
        tally.scene_errors,
        tally.sim_errors,
        tally.kinds,
        tally.ok_calls
    );
    assert!(
        escaped.is_empty(),
        "a panic escaped (or an assertion failed) in the sequences of seeds {escaped:?}; rerun one with API_FUZZ_SEED=<seed> API_FUZZ_SEQUENCES=1"
    );
    // The batch must exercise both sides: scenes that build and run, and rejected ones.
    assert!(tally.built > count as usize / 4 && tally.scene_errors > 0);
    assert!(tally.ok_calls > 0 && tally.sim_errors > 0);
}
