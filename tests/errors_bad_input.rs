//! Regression tests of issue 15's probes of single faults and bad values ("no panic anywhere on
//! user input"): each probe ends in the exact typed error (or builds and simulates correctly),
//! and each message names the culprit (object, joint, element, option, time).

use modia3d::core::scene::MaterialFileError;
use modia3d::prelude::*;
use nalgebra::Quaternion;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::Arc;

const G: f64 = 9.81;

/// A world with gravity −9.81 m/s² along z and a free steel ball `ball` (Ø 0.1 m) at z = 1 m.
fn free_ball() -> SceneDesc {
    let mut s = SceneDesc::new();
    s.add(Object3D::new("world").scene(SceneOptions::default()))
        .add(
            Object3D::new("ball")
                .solid(Solid::new(Shape::Sphere { diameter: 0.1 }).material("Steel")),
        )
        .add_joint(Joint::new(
            "free",
            "world",
            "ball",
            JointKind::FreeMotion {
                r: Vector3::new(0.0, 0.0, 1.0),
                rot: FreeRotation::Cardan([0.0; 3]),
                v: Vector3::zeros(),
                w: Vector3::zeros(),
            },
        ));
    s
}

fn with_law(
    mut s: SceneDesc,
    law: impl Fn(f64, &ObjectMotion) -> Wrench + Send + Sync + 'static,
) -> SceneDesc {
    s.add_force(ForceElement::ObjectForce {
        object: "ball".into(),
        law: ForceFn::new(law),
    });
    s
}

fn opts(stop: f64) -> SimOptions {
    SimOptions::new(stop).progress(false)
}

/// The message of `e` contains every needle.
fn assert_words(msg: &str, needles: &[&str]) {
    for n in needles {
        assert!(msg.contains(n), "`{n}` missing in: {msg}");
    }
}

fn scene_errors(s: &SceneDesc) -> Vec<SceneError> {
    match s.build() {
        Ok(_) => panic!("the scene should be rejected"),
        Err(e) => e.0,
    }
}

// ---- 1. Signal accessors never panic -------------------------------------------------------

/// A run that fails at its first evaluation (the force law panics at t = 0) returns an empty
/// partial result; `last()` / `at(0)` of its signals are `None` instead of an index panic.
#[test]
fn last_of_an_empty_partial_result_is_none() {
    let s = with_law(free_ball(), |_, _| panic!("law broken"));
    let model = s.build().unwrap();
    let err = model.simulate(&opts(0.1)).unwrap_err();
    assert!(err.partial.time().is_empty());
    let r = err.partial.signal("ball.r_abs").unwrap();
    assert!(r.is_empty());
    assert_eq!(r.len(), 0);
    assert_eq!(r.last(), None);
    assert_eq!(r.first(), None);
    assert_eq!(r.at(0), None);
    assert_eq!(err.partial.final_state(), None);
    assert_eq!(err.partial.state(0), None);
    // An index beyond the end of a full result is `None` as well.
    let res = free_ball().build().unwrap().simulate(&opts(0.1)).unwrap();
    let z = res.signal("ball.r_abs[2]").unwrap();
    assert_eq!(z.at(z.len()), None);
    assert_eq!(z.at(usize::MAX), None);
    assert!(z.last().is_some());
    assert_eq!(res.state(res.time().len()), None);
    assert_eq!(res.state(0).map(<[f64]>::len), Some(res.state_len()));
}

// ---- 2. User closures are caught at every call site ----------------------------------------

/// A panic in the consistent initial derivatives (`Simulation::new`).
#[test]
fn force_law_panic_at_start_is_a_typed_error() {
    let s = with_law(free_ball(), |_, _| panic!("law broken at start"));
    let model = s.build().unwrap();
    let err = model.simulation(&opts(0.1)).unwrap_err();
    match &err.kind {
        SimErrorKind::UserPanic {
            element,
            t,
            message,
        } => {
            assert_eq!(element, "ObjectForce on `ball` (force element 0)");
            assert_eq!(*t, 0.0);
            assert_eq!(message, "law broken at start");
        }
        k => panic!("expected UserPanic, got {k:?}"),
    }
    assert_words(
        &err.to_string(),
        &["ObjectForce on `ball`", "panicked at t = 0 s", "law broken"],
    );
}

/// A panic at the restart after `set_input` (consistent derivatives again, outside IDA).
#[test]
fn force_law_panic_at_restart_after_set_input_is_a_typed_error() {
    let broken = Arc::new(AtomicBool::new(false));
    let flag = broken.clone();
    let mut s = with_law(free_ball(), move |_, _| {
        if flag.load(Ordering::Relaxed) {
            panic!("law broken after the input changed");
        }
        Wrench::default()
    });
    s.add_input(Input::object_wrench("push", "ball"));
    let model = s.build().unwrap();
    let mut sim = model.simulation(&opts(1.0)).unwrap();
    sim.advance_to(0.25).unwrap();
    broken.store(true, Ordering::Relaxed);
    sim.set_input("push", &[1.0, 0.0, 0.0, 0.0, 0.0, 0.0])
        .unwrap();
    let err = sim.advance_to(0.5).unwrap_err();
    match &err.kind {
        SimErrorKind::UserPanic { element, t, .. } => {
            assert!(element.contains("`ball`"));
            // The restart happens at the current time, before any step.
            assert!((t - 0.25).abs() < 1e-12, "t = {t}");
        }
        k => panic!("expected UserPanic, got {k:?}"),
    }
    // The results up to the failure: the points up to 0.25 s.
    let last = *err.partial.time().last().unwrap();
    assert!((last - 0.25).abs() < 1e-12);
}

/// A panic inside the integration (the residual) from t = 0.3 s on: the results up to there.
#[test]
fn force_law_panic_during_the_run_keeps_the_results_up_to_it() {
    let s = with_law(free_ball(), |t, _| {
        if t > 0.3 {
            panic!("law broken after 0.3 s");
        }
        Wrench::default()
    });
    let err = s.build().unwrap().simulate(&opts(1.0)).unwrap_err();
    match &err.kind {
        SimErrorKind::UserPanic {
            element,
            t,
            message,
        } => {
            assert!(element.contains("`ball`"));
            // The first call after 0.3 s: IDA's trial step of this free fall (a quadratic,
            // so its steps grow long) may end anywhere before the stop time.
            assert!(*t > 0.3 && *t <= 1.0, "t = {t}");
            assert_eq!(message, "law broken after 0.3 s");
        }
        k => panic!("expected UserPanic, got {k:?}"),
    }
    // Every step that succeeded called the law at t ≤ 0.3 s only.
    let time = err.partial.time();
    let last = *time.last().unwrap();
    assert!(last <= 0.3 + 1e-12 && time.len() > 1, "last output {last}");
    // The partial result is the free fall up to there (rtol 1e-6: 1e-6 m is ample).
    let z = err.partial.signal("ball.r_abs[2]").unwrap();
    let z_last = z.last().unwrap()[0];
    assert!((z_last - (1.0 - 0.5 * G * last * last)).abs() < 1e-6);
}

/// A NaN force from t = 0 names the element and the time.
#[test]
fn nan_force_law_from_the_start_names_the_element() {
    let s = with_law(free_ball(), |_, _| Wrench {
        force: Vector3::new(f64::NAN, 0.0, 0.0),
        torque: Vector3::zeros(),
    });
    let err = s.build().unwrap().simulate(&opts(0.1)).unwrap_err();
    match &err.kind {
        SimErrorKind::NonFiniteForce {
            element,
            t,
            force,
            torque,
        } => {
            assert_eq!(element, "ObjectForce on `ball` (force element 0)");
            assert_eq!(*t, 0.0);
            assert!(force[0].is_nan() && force[1] == 0.0);
            assert_eq!(*torque, [0.0; 3]);
        }
        k => panic!("expected NonFiniteForce, got {k:?}"),
    }
    assert_words(
        &err.to_string(),
        &["ObjectForce on `ball`", "non-finite wrench at t = 0 s"],
    );
}

/// An infinite torque during the run (inside IDA) is the same typed error, at its time.
#[test]
fn infinite_torque_during_the_run_names_the_element_and_time() {
    let mut s = free_ball();
    s.add(Object3D::new("marker").parent("ball"));
    s.add_force(ForceElement::ObjectForce {
        object: "marker".into(),
        law: ForceFn::new(|t, _| Wrench {
            force: Vector3::zeros(),
            torque: Vector3::new(0.0, if t > 0.5 { f64::INFINITY } else { 0.0 }, 0.0),
        }),
    });
    let err = s.build().unwrap().simulate(&opts(1.0)).unwrap_err();
    match &err.kind {
        SimErrorKind::NonFiniteForce {
            element, t, torque, ..
        } => {
            assert_eq!(element, "ObjectForce on `marker` (force element 0)");
            assert!(*t > 0.5 && *t <= 1.0, "t = {t}");
            assert_eq!(torque[1], f64::INFINITY);
        }
        k => panic!("expected NonFiniteForce, got {k:?}"),
    }
    assert!(*err.partial.time().last().unwrap() <= 0.5 + 1e-12);
}

// ---- 3. Zero quaternion ---------------------------------------------------------------------

#[test]
fn zero_quaternion_is_a_build_error_naming_the_joint() {
    for q in [
        Quaternion::new(0.0, 0.0, 0.0, 0.0),
        Quaternion::new(2.0, 0.0, 0.0, 0.0),
    ] {
        let mut s = free_ball();
        s.joints[0].kind = JointKind::FreeMotion {
            r: Vector3::new(0.0, 0.0, 1.0),
            rot: FreeRotation::Quaternion(UnitQuaternion::new_unchecked(q)),
            v: Vector3::zeros(),
            w: Vector3::zeros(),
        };
        let errs = scene_errors(&s);
        assert_eq!(errs.len(), 1, "{errs:?}");
        match &errs[0] {
            SceneError::InvalidValue { what, value, .. } => {
                assert_eq!(what, "joint `free`: norm of the initial quaternion");
                assert_eq!(*value, q.norm());
            }
            e => panic!("expected InvalidValue, got {e:?}"),
        }
        assert_words(&errs[0].to_string(), &["joint `free`", "unit quaternion"]);
    }
    // A NaN quaternion is named as well (the finite check).
    let mut s = free_ball();
    s.joints[0].kind = JointKind::FreeMotion {
        r: Vector3::zeros(),
        rot: FreeRotation::Quaternion(UnitQuaternion::new_unchecked(Quaternion::new(
            f64::NAN,
            0.0,
            0.0,
            0.0,
        ))),
        v: Vector3::zeros(),
        w: Vector3::zeros(),
    };
    assert_words(
        &scene_errors(&s)[0].to_string(),
        &["joint `free`: initial quaternion", "NaN"],
    );
    // A slightly rounded unit quaternion (1e-9 off) is accepted and normalised.
    let mut s = free_ball();
    s.joints[0].kind = JointKind::FreeMotion {
        r: Vector3::new(0.0, 0.0, 1.0),
        rot: FreeRotation::Quaternion(UnitQuaternion::new_unchecked(Quaternion::new(
            1.0 + 1e-9,
            0.0,
            0.0,
            0.0,
        ))),
        v: Vector3::zeros(),
        w: Vector3::zeros(),
    };
    let res = s.build().unwrap().simulate(&opts(0.1)).unwrap();
    let q = res.signal("free.q").unwrap();
    let q0 = q.first().unwrap();
    assert!((q0.iter().map(|x| x * x).sum::<f64>().sqrt() - 1.0).abs() < 1e-15);
}

// ---- 4. One namespace for objects, joints and named force elements -------------------------

#[test]
fn object_and_joint_of_the_same_name_are_rejected() {
    let mut s = free_ball();
    s.joints[0].name = "ball".into();
    let errs = scene_errors(&s);
    assert_eq!(
        errs,
        vec![SceneError::NameClash {
            name: "ball".into(),
            first: "object",
            second: "joint",
        }]
    );
    assert_words(
        &errs[0].to_string(),
        &["object `ball` and joint `ball`", "rename one"],
    );
    // A spring-damper named like a joint.
    let mut s = free_ball();
    s.add_force(ForceElement::SpringDamper {
        name: "free".into(),
        obj1: "world".into(),
        obj2: "ball".into(),
        stiffness: 1.0,
        damping: 0.0,
        length0: 1.0,
    });
    assert_eq!(
        scene_errors(&s),
        vec![SceneError::NameClash {
            name: "free".into(),
            first: "joint",
            second: "force element",
        }]
    );
    // Two spring-dampers of one name: their signals would be ambiguous as well.
    let mut s = free_ball();
    for _ in 0..2 {
        s.add_force(ForceElement::SpringDamper {
            name: "spring".into(),
            obj1: "world".into(),
            obj2: "ball".into(),
            stiffness: 1.0,
            damping: 0.0,
            length0: 1.0,
        });
    }
    assert_eq!(
        scene_errors(&s),
        vec![SceneError::DuplicateName {
            kind: "force element",
            name: "spring".into(),
        }]
    );
}

// ---- 5. JSON palettes -----------------------------------------------------------------------

fn palette_error(json: &str) -> String {
    match MaterialPalette::from_json_str(json, "probe.json") {
        Ok(p) => panic!("should be rejected: {p:?}"),
        Err(e @ MaterialFileError::Parse { .. }) => e.to_string(),
        Err(e) => panic!("expected a parse error, got {e:?}"),
    }
}

#[test]
fn palette_rejects_unknown_fields_in_every_struct() {
    let msg = palette_error(
        r#"{ "solid": { "Rubber": { "density": 1100, "young_modulus": 5e7, "poisson_ration": 0.45 } } }"#,
    );
    assert_words(
        &msg,
        &[
            "probe.json",
            "solid material `Rubber`",
            "unknown field `poisson_ration`",
        ],
    );
    // serde_json's position is given once, in the prefix, not repeated in the message.
    assert_eq!(msg.matches("line").count(), 1, "{msg}");
    let msg = palette_error(
        r#"{ "contact_pairs": [ { "materials": ["A", "B"], "cor": 0.5, "mu_k": 0.1, "mu_r": 0.0, "v_mni": 0.01 } ] }"#,
    );
    assert_words(&msg, &["probe.json", "v_mni"]);
    let msg = palette_error(r#"{ "solids": {} }"#);
    assert_words(&msg, &["probe.json", "unknown field `solids`"]);
}

#[test]
fn palette_rejects_duplicate_keys() {
    let rubber = r#"{ "density": 1100, "young_modulus": 5e7, "poisson_ratio": 0.45 }"#;
    let msg = palette_error(&format!(
        r#"{{ "solid": {{ "Rubber": {rubber}, "Rubber": {rubber} }} }}"#
    ));
    assert_words(
        &msg,
        &["probe.json", "solid material `Rubber` is defined twice"],
    );
    let msg = palette_error(
        r#"{ "solid": { "Rubber": { "density": 1100, "density": 900, "young_modulus": 5e7, "poisson_ratio": 0.45 } } }"#,
    );
    assert_words(
        &msg,
        &["solid material `Rubber`", "duplicate field `density`"],
    );
    let msg = palette_error(
        r#"{ "contact_pairs": [ { "materials": ["A", "B"], "cor": 0.5, "cor": 0.9, "mu_k": 0.1, "mu_r": 0.0 } ] }"#,
    );
    assert_words(&msg, &["probe.json", "duplicate field `cor`"]);
    let msg = palette_error(r#"{ "solid": {}, "solid": {} }"#);
    assert_words(&msg, &["duplicate field `solid`"]);
    // A correct palette still loads.
    let p = MaterialPalette::from_json_str(
        &format!(r#"{{ "solid": {{ "Rubber": {rubber} }} }}"#),
        "ok",
    )
    .unwrap();
    assert_eq!(p.solid["Rubber"].density, 1100.0);
}

// ---- 6. Singular-mass test relative to each body's own scale -------------------------------

/// A 2 mm steel ball on a 5 cm massless rod, hinged to a free 0.2 m steel block: its joint's
/// inertia is ~1e-12 of the block's mass entries, yet it is no singular mass. In free fall
/// (uniform gravity) the hinge angle stays at its initial value and everything falls with g.
#[test]
fn small_ball_hinged_to_a_big_free_block_builds_and_falls() {
    let mut s = SceneDesc::new();
    s.add(Object3D::new("world").scene(SceneOptions::default()))
        .add(
            Object3D::new("block").solid(
                Solid::new(Shape::Box {
                    lengths: Vector3::new(0.2, 0.2, 0.2),
                })
                .material("Steel")
                .collision(false),
            ),
        )
        .add(
            Object3D::new("pivot")
                .parent("block")
                .translation([0.0, 0.0, 0.1]),
        )
        .add(
            Object3D::new("bead")
                .solid(
                    Solid::new(Shape::Sphere { diameter: 0.002 })
                        .material("Steel")
                        .collision(false),
                )
                .parent("arm")
                .translation([0.0, 0.0, -0.05]),
        )
        .add(Object3D::new("arm"))
        .add_joint(Joint::new(
            "fly",
            "world",
            "block",
            JointKind::FreeMotion {
                r: Vector3::new(0.0, 0.0, 1.0),
                rot: FreeRotation::Cardan([0.0; 3]),
                v: Vector3::zeros(),
                w: Vector3::zeros(),
            },
        ))
        .add_joint(Joint::new("hinge", "pivot", "arm", JointKind::revolute(1)).init_position(0.4));
    let model = s.build().expect("a small body on a big one builds");
    let masses: Vec<f64> = model.bodies().iter().map(|b| b.mass).collect();
    // 8000 kg/m³: block 64 kg, bead 8000·π/6·(2e-3)³ = 3.35e-5 kg.
    assert!((masses[0] - 64.0).abs() < 1e-9 && (masses[1] - 3.351e-5).abs() < 1e-8);
    let res = model.simulate(&opts(0.5).tolerance(1e-9)).unwrap();
    let t = *res.time().last().unwrap();
    let z = res.signal("block.r_abs[2]").unwrap().last().unwrap()[0];
    let zb = res.signal("bead.r_abs[2]").unwrap();
    let phi = res.signal("hinge.phi").unwrap().last().unwrap()[0];
    // Free fall: z = z0 − g t²/2 exactly for the block; the hinge does not move (no relative
    // force in uniform gravity). Tolerances: a few hundred rtol·(state scale 1 m).
    assert!((z - (1.0 - 0.5 * G * t * t)).abs() < 1e-7, "block z {z}");
    assert!((phi - 0.4).abs() < 1e-7, "hinge phi {phi}");
    let zb0 = zb.first().unwrap()[0];
    let zb1 = zb.last().unwrap()[0];
    assert!((zb1 - (zb0 - 0.5 * G * t * t)).abs() < 1e-7, "bead z {zb1}");
}

/// The same bead on a fixed pivot is a pendulum: its small-amplitude period is 2π·sqrt(l/g)
/// for a point mass; the bead's own inertia (2/5 m r² at l = 5 cm) adds a factor
/// sqrt(1 + 2r²/(5l²)) = 1 + 8e-5.
#[test]
fn small_ball_pendulum_period_matches_the_analytic_value() {
    let (l, r) = (0.05, 0.001);
    let mut s = SceneDesc::new();
    s.add(Object3D::new("world").scene(SceneOptions::default()))
        .add(
            Object3D::new("bead")
                .solid(Solid::new(Shape::Sphere { diameter: 2.0 * r }).material("Steel"))
                .parent("arm")
                .translation([0.0, 0.0, -l]),
        )
        .add(Object3D::new("arm"))
        .add_joint(Joint::new("hinge", "world", "arm", JointKind::revolute(1)).init_position(0.01));
    let model = s.build().unwrap();
    let period = 2.0 * std::f64::consts::PI * (l / G).sqrt() * (1.0 + 0.4 * r * r / (l * l)).sqrt();
    let res = model
        .simulate(
            &opts(2.0 * period)
                .tolerance(1e-10)
                .interval(period / 2000.0),
        )
        .unwrap();
    let phi = res.signal("hinge.phi").unwrap().values();
    let t = res.time();
    // Upward zero crossings of phi − (its mean, 0), linearly interpolated.
    let crossings: Vec<f64> = (1..phi.len())
        .filter(|&k| phi[k - 1] < 0.0 && phi[k] >= 0.0)
        .map(|k| t[k - 1] + (t[k] - t[k - 1]) * (-phi[k - 1]) / (phi[k] - phi[k - 1]))
        .collect();
    assert!(!crossings.is_empty(), "{crossings:?}");
    // First upward crossing at 3/4 of a period (released at +amplitude, at rest). Amplitude
    // 0.01 rad lengthens the period by θ²/16 = 6e-6; interpolation error ~(period/2000)²: the
    // tolerance 1e-4 of the period.
    let measured = crossings[0] / 0.75;
    assert!(
        (measured / period - 1.0).abs() < 1e-4,
        "period {measured} vs {period}"
    );
}

/// A free 3 µm steel sphere (mass 1.1e-13 kg, inertia 1e-25 kg·m²) builds and falls with g.
#[test]
fn free_micrometre_sphere_builds_and_falls() {
    let mut s = SceneDesc::new();
    s.add(Object3D::new("world").scene(SceneOptions::default()))
        .add(
            Object3D::new("dust")
                .solid(Solid::new(Shape::Sphere { diameter: 3e-6 }).material("Steel")),
        )
        .add_joint(Joint::new(
            "free",
            "world",
            "dust",
            JointKind::FreeMotion {
                r: Vector3::new(0.0, 0.0, 1.0),
                rot: FreeRotation::Cardan([0.0; 3]),
                v: Vector3::new(0.1, 0.0, 0.0),
                w: Vector3::new(0.0, 0.0, 2.0),
            },
        ));
    let model = s.build().expect("a free 3 µm sphere builds");
    let res = model.simulate(&opts(0.3).tolerance(1e-9)).unwrap();
    let t = *res.time().last().unwrap();
    let r = res.signal("dust.r_abs").unwrap();
    let r = r.last().unwrap();
    let w = res.signal("dust.w_abs").unwrap();
    let w = w.last().unwrap();
    // The velocity-product torque leaves out `v × (m v)` exactly (modia3d-core/src/spatial.rs
    // `bias_force`): its rounding swamped the 1e-25 kg·m² inertia and IDA took 650,000 steps
    // (70 now, as for a 1 cm sphere).
    assert!(res.stats.solver.steps < 1_000, "{:?}", res.stats.solver);
    // Ballistic flight and a constant spin (sphere: no gyroscopic torque); tolerance 1e-7 m
    // (rtol 1e-9 over 0.3 s), 1e-9 rad/s.
    assert!((r[0] - 0.1 * t).abs() < 1e-7 && r[1].abs() < 1e-7);
    assert!((r[2] - (1.0 - 0.5 * G * t * t)).abs() < 1e-7, "z {}", r[2]);
    assert!((w[2] - 2.0).abs() < 1e-9 && w[0].abs() < 1e-9);
}

/// A massless moving body is still a singular mass (the relative test keeps true zeros).
#[test]
fn massless_free_body_is_still_singular() {
    let mut s = SceneDesc::new();
    s.add(Object3D::new("world").scene(SceneOptions::default()))
        .add(Object3D::new("ghost"))
        .add_joint(Joint::new("free", "world", "ghost", JointKind::free()));
    let errs = scene_errors(&s);
    assert!(
        matches!(&errs[..], [SceneError::SingularMass { joint, .. }] if joint == "free"),
        "{errs:?}"
    );
}

// ---- 7. Options that used to pass the checks and end as IDA_ILL_INPUT ----------------------

fn invalid_options(model: &Model, o: &SimOptions) -> String {
    match model.simulate(o) {
        Err(SimError {
            kind: SimErrorKind::InvalidOptions(m),
            partial,
        }) => {
            assert!(partial.time().is_empty());
            m
        }
        other => panic!("expected InvalidOptions, got {:?}", other.map(|r| r.stats)),
    }
}

#[test]
fn tiny_tolerance_and_stop_time_are_option_errors_with_the_range() {
    let model = free_ball().build().unwrap();
    let m = invalid_options(&model, &opts(0.1).tolerance(1e-300));
    assert_words(&m, &["tolerance 1e-300", "[1e-14, 1)"]);
    let m = invalid_options(&model, &opts(1e-300));
    assert_words(&m, &["1e-300", "at least 1e-12 s"]);
    let m = invalid_options(&model, &opts(0.1).atol(1e-300));
    assert_words(&m, &["absolute tolerance 1e-300", "[1e-16, 1e6]"]);
    let m = invalid_options(&model, &opts(0.1).max_step(1e-300));
    assert_words(&m, &["max step 1e-300 s", "max_steps"]);
    let m = invalid_options(&model, &opts(0.1).start_time(f64::NAN));
    assert_words(&m, &["finite"]);
}

#[test]
fn tiny_mass_is_a_build_error_with_the_range() {
    let mut s = free_ball();
    if let Feature::Solid(solid) = &mut s.objects[1].feature {
        solid.mass_properties = MassSpec::FromShapeAndMass(1e-300);
    }
    let errs = scene_errors(&s);
    match &errs[..] {
        [SceneError::InvalidValue {
            what,
            value,
            expected,
        }] => {
            assert_eq!(what, "solid `ball`: mass [kg]");
            assert_eq!(*value, 1e-300);
            assert!(expected.contains("1e-20"), "{expected}");
        }
        e => panic!("expected one InvalidValue, got {e:?}"),
    }
    // The same for a density that gives no mass worth the name.
    let mut s = free_ball();
    if let Feature::Solid(solid) = &mut s.objects[1].feature {
        solid.material = Some(MaterialRef::Value(SolidMaterial {
            density: 1e-300,
            young_modulus: 2e11,
            poisson_ratio: 0.3,
        }));
    }
    assert_words(
        &scene_errors(&s)[0].to_string(),
        &["solid `ball`", "density", "1e-300"],
    );
}
