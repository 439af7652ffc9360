//! Joint limits (issue 43, point 1; docs/joint-limits.md): stops on scalar joint coordinates
//! as compliant impacts located by the contact events. Each test names its independent
//! reference (closed forms of a pendulum and a slider, the restitution relation of the linear
//! law solved here by its own bisection, statics) and argues its tolerance.

use modia3d::prelude::*;

fn point_mass(mass: f64, inertia: f64) -> Solid {
    Solid {
        mass_properties: MassSpec::Explicit {
            mass,
            com: Vector3::zeros(),
            inertia: Matrix3::from_diagonal(&Vector3::new(inertia, inertia, inertia)),
        },
        ..Default::default()
    }
}

/// A pendulum: a point-like bob (mass `m`, own inertia `i`) at `bob` [m] from the revolute
/// `hinge` (axis y), with `limit` on its angle, starting at `phi0` at rest.
fn pendulum(bob: [f64; 3], phi0: f64, limit: JointLimit, options: SceneOptions) -> SceneDesc {
    let (m, i) = (1.0, 1e-4);
    let mut s = SceneDesc::new();
    s.add(Object3D::new("world").scene(options))
        .add(Object3D::new("arm"))
        .add(Object3D::new("bob").parent("arm").translation(bob))
        .add(Object3D::new("mass").parent("bob").solid(point_mass(m, i)))
        .add_joint(
            Joint::new("hinge", "world", "arm", JointKind::revolute(2))
                .init_position(phi0)
                .limit(limit),
        );
    s
}

fn options(exact: bool) -> SceneOptions {
    SceneOptions {
        exact_restitution: exact,
        ..Default::default()
    }
}

/// The rebound ratio `e` of the linear law `δ'' = −δ·(1 + χ δ')` (the contact law in joint
/// space, no other force), from its closed form `−χe − ln(1 − χe) = χ − ln(1 + χ)`
/// (docs/contact-model.md §3), solved by bisection here (independently of
/// `contact/restitution.rs`, which solves the inverse problem).
fn rebound_of_chi(chi: f64) -> f64 {
    let rhs = chi - chi.ln_1p();
    let (mut lo, mut hi) = (0.0f64, (1.0 / chi).min(1.0));
    for _ in 0..200 {
        let e = 0.5 * (lo + hi);
        let u = chi * e;
        if -u - (-u).ln_1p() < rhs {
            lo = e;
        } else {
            hi = e;
        }
    }
    0.5 * (lo + hi)
}

/// The first finished phase of stop `name`: (impact speed, exit speed).
fn first_rebound(res: &SimulationResult, name: &str) -> (f64, f64) {
    let ph = res.contact_phases(name).unwrap();
    let p = ph.first().expect("a stop phase");
    (p.impact_speed, p.exit_speed.expect("the phase ended"))
}

/// A pendulum (l = 1 m) released at 1 rad swings down into a stop at the bottom (φ = 0, where
/// gravity has no moment: the impact sees the stop alone, up to gravity's stiffness
/// `m·g·l` = 1e-7 of the default stop's `J·ω_s²`). With exact restitution the rebound ratio
/// is the asked cor to 1e-6 (the relation is exact for the linear law; the rest is gravity's
/// 1e-7, the soft clamp's band, ~1e-9, and the run's rtol 1e-9 on the exit speed). With the
/// paper's damping `d = 8(1 − cor)/(5·cor·δ̇⁻)` the ratio is the relation's `e(χ)` at
/// `χ = 8(1 − cor)/(5·cor)` (cor 0.5: 0.4705…, the "cor 0.5 gives 0.470" of the docs), to the
/// same 1e-6.
#[test]
fn pendulum_rebounds_from_its_stop_with_the_asked_restitution() {
    for (cor, exact) in [(0.5, true), (0.8, true), (0.5, false), (0.8, false)] {
        let s = pendulum(
            [0.0, 0.0, -1.0],
            1.0,
            JointLimit::lower(0.0).cor(cor),
            options(exact),
        );
        let res = s
            .build()
            .unwrap()
            .simulate(
                &SimOptions::new(0.8)
                    .tolerance(1e-9)
                    .contact_results(true)
                    .progress(false),
            )
            .unwrap();
        let (impact, exit) = first_rebound(&res, "hinge.phi.lower");
        let want = if exact {
            cor
        } else {
            rebound_of_chi(8.0 * (1.0 - cor) / (5.0 * cor))
        };
        let got = exit / impact;
        println!(
            "cor {cor}, exact {exact}: rebound {got:.9} (want {want:.9}), impact {impact} rad/s"
        );
        assert!(
            (got - want).abs() < 1e-6,
            "cor {cor}, exact {exact}: rebound ratio {got}, want {want}"
        );
        assert_eq!(res.events[0].started, vec!["hinge.phi.lower".to_string()]);
    }
}

/// A 2 kg slider on a prismatic joint (axis x, gravity along −z: none along the slide) between
/// stops at ±0.1 m, started at 1 m/s: each impact leaves `e²` of the kinetic energy, here read
/// from the velocity signal between impacts (independent of the phase measurement): the ratio
/// of successive plateaus of `v²` is cor² to 1e-6 (exact restitution; the stops are the only
/// force, so the relation is exact up to the run's rtol 1e-9 and the clamp's ~1e-9).
#[test]
fn slider_between_stops_loses_energy_as_e_squared_says() {
    let cor: f64 = 0.8;
    let mut s = SceneDesc::new();
    s.add(Object3D::new("world").scene(options(true)))
        .add(Object3D::new("slider").solid(point_mass(2.0, 1e-3)))
        .add_joint(
            Joint::new("slide", "world", "slider", JointKind::prismatic(1))
                .init_velocity(1.0)
                .limit(JointLimit::range(-0.1, 0.1).cor(cor)),
        );
    let res = s
        .build()
        .unwrap()
        .simulate(
            &SimOptions::new(2.5)
                .tolerance(1e-9)
                .interval(1e-3)
                .contact_results(true)
                .progress(false),
        )
        .unwrap();
    // Without phases (`contact_phases(false)`) a scene whose only stops are joint limits
    // says which option it needs: the contact results were asked for.
    let lean = s
        .build()
        .unwrap()
        .simulate(
            &SimOptions::new(0.2)
                .contact_results(true)
                .contact_phases(false)
                .progress(false),
        )
        .unwrap();
    let err = lean.contacts().unwrap_err();
    assert!(
        matches!(err, ResultError::ContactPhasesOff { .. }),
        "{err:?}"
    );
    // The speed at the middle of each flight (half-way between the end of one phase and the
    // start of the next).
    let phases = res.contacts().unwrap();
    assert!(phases.len() >= 5, "{} impacts", phases.len());
    let mut speeds = vec![1.0];
    for w in phases.windows(2) {
        let mid = 0.5 * (w[0].end.unwrap() + w[1].start);
        speeds.push(res.signal_at("slide.v", mid).unwrap()[0].abs());
    }
    for (k, p) in speeds.windows(2).enumerate() {
        let ratio = (p[1] / p[0]).powi(2);
        println!("impact {k}: energy ratio {ratio:.9} (e² = {})", cor * cor);
        assert!(
            (ratio - cor * cor).abs() < 1e-6,
            "impact {k}: energy ratio {ratio}, want {}",
            cor * cor
        );
    }
    // One event pair per impact (the last may still be open), two root functions for two
    // stops. The first hit is at gap/v = 0.1 s exactly (free motion: IDA's polynomial is
    // exact, the root is located to its time tolerance, ~1e-14 s).
    let finished = phases.iter().filter(|p| p.end.is_some()).count();
    assert_eq!(res.events.len(), 2 * finished + (phases.len() - finished));
    assert_eq!(res.stats.root_functions, 2);
    println!("first hit at {:.15} s", phases[0].start);
    assert!((phases[0].start - 0.1).abs() < 1e-12, "{}", phases[0].start);
}

/// A horizontal arm (bob 1 m out along x) laid on a stop at φ = 0 rests without any event;
/// dropped from 0.1 rad above onto the same stop (its
/// upper bound: gravity turns it to positive φ) and settles: after it does, no events, and the
/// stop holds the weight's moment, `limit_f = −m·g·l·cos δ` with `δ` ~1e-7 rad, i.e. `m·g·l` to
/// 1e-14: statics, to 1e-6 relative (the run's rtol 1e-8 on a state at rest, where IDA's
/// error is the residual's); so does the hinge's load signal, which includes the stop.
#[test]
fn arm_resting_on_its_stop_carries_its_weight() {
    let (m, l, g) = (1.0, 1.0, 9.81);
    // The arm from `phi0` onto the stop at φ = 0, 3 s at rtol 1e-8.
    let run = |phi0: f64| {
        pendulum(
            [l, 0.0, 0.0],
            phi0,
            JointLimit::upper(0.0).cor(0.5),
            options(false),
        )
        .build()
        .unwrap()
        .simulate(
            &SimOptions::new(3.0)
                .tolerance(1e-8)
                .interval(1e-2)
                .progress(false),
        )
        .unwrap()
    };
    let res = run(-0.1);
    let last = res.events.last().unwrap().t;
    println!(
        "{} events, the last at {last} s; {} steps",
        res.events.len(),
        res.stats.solver.steps
    );
    assert!(last < 1.5, "events until {last} s");
    let f = res.signal("hinge.limit_f").unwrap();
    let f_end = *f.values().last().unwrap();
    println!("stop torque {f_end} N·m (m g l = {})", m * g * l);
    assert!(
        (f_end + m * g * l).abs() < 1e-6 * m * g * l,
        "stop torque {f_end}"
    );
    assert_eq!(f.unit, "N·m");
    // Laid on its stop at rest (φ = 0, the bound) instead of dropped: in the stop's contact
    // from the start, it sinks ~1e-7 rad into the compliant stop and stays: no event at all.
    let laid = run(0.0);
    println!(
        "laid on the stop: {} events, {} steps",
        laid.events.len(),
        laid.stats.solver.steps
    );
    assert!(laid.events.is_empty(), "{:?}", laid.events);
    let f_laid = *laid
        .signal("hinge.limit_f")
        .unwrap()
        .values()
        .last()
        .unwrap();
    assert!((f_laid + m * g * l).abs() < 1e-6 * m * g * l, "{f_laid}");
    // The hinge's load on the arm includes the stop's torque: it holds the arm's weight, force
    // `m·g` up and torque `−m·g·l` about y (about the arm's origin, on the axis), by statics.
    let t = res.signal("hinge.t").unwrap();
    let f = res.signal("hinge.f").unwrap();
    let (t, f) = (t.last().unwrap(), f.last().unwrap());
    println!("hinge load at rest: f = {f:?} N, t = {t:?} N·m");
    let want = [(f, [0.0, 0.0, m * g]), (t, [0.0, -m * g * l, 0.0])];
    for (got, want) in want {
        for (a, b) in got.iter().zip(want) {
            assert!((a - b).abs() < 1e-6 * m * g * l, "{got:?} vs {want:?}");
        }
    }
}

/// Joints with several coordinates: a Planar puck (normal z, gravity along −x) and a
/// Cylindrical slider (axis z, gravity along −z) fall onto stops on one coordinate each (`x`,
/// `s`) and rest there; each stop holds `m·g` (statics, 1e-6 relative as for the arm), read
/// from the per-coordinate signals `limit_f_x`, `limit_f_s`, while the other coordinates'
/// limits stay unreached (zero force). The planar joint's tree is no hinge tree: its stop's
/// row entries come from the difference quotients.
#[test]
fn multi_coordinate_joints_rest_on_their_stops() {
    let (m, g) = (2.0, 9.81);
    for (kind, gravity, coords) in [
        (JointKind::planar(3), [-g, 0.0, 0.0], ["x", "y"]),
        (JointKind::cylindrical(3), [0.0, 0.0, -g], ["s", "phi"]),
    ] {
        let options = SceneOptions {
            gravity: Vector3::from(gravity),
            ..Default::default()
        };
        let mut s = SceneDesc::new();
        s.add(Object3D::new("world").scene(options))
            .add(Object3D::new("body").solid(point_mass(m, 1e-2)))
            .add_joint(
                Joint::new("j", "world", "body", kind)
                    .limit(JointLimit::lower(-0.05).on(coords[0]))
                    .limit(JointLimit::range(-1.0, 1.0).on(coords[1])),
            );
        let res = s
            .build()
            .unwrap()
            .simulate(&SimOptions::new(2.0).tolerance(1e-8).progress(false))
            .unwrap();
        let held = res.signal(&format!("j.limit_f_{}", coords[0])).unwrap();
        let free = res.signal(&format!("j.limit_f_{}", coords[1])).unwrap();
        let (held, free) = (
            *held.values().last().unwrap(),
            free.values().last().copied(),
        );
        println!(
            "stop on {} holds {held} N ({} events, the last at {} s)",
            coords[0],
            res.events.len(),
            res.events.last().map_or(0.0, |e| e.t)
        );
        assert!((held - m * g).abs() < 1e-6 * m * g, "{held}");
        assert_eq!(free, Some(0.0));
        assert!(res.events.last().unwrap().t < 1.0);
    }
}

/// Complete elliptic integral of the first kind `K(k)` by the arithmetic-geometric mean.
fn elliptic_k(k: f64) -> f64 {
    let (mut a, mut b) = (1.0f64, (1.0 - k * k).sqrt());
    for _ in 0..40 {
        (a, b) = (0.5 * (a + b), (a * b).sqrt());
    }
    std::f64::consts::PI / (2.0 * a)
}

/// The first hit of the stop at the bottom is the free pendulum's quarter period
/// `K(sin(φ0/2))·√(J/(m g l))` (the stop does nothing before it): the located hit time follows
/// rtol as contact times do (tests/contact_times.rs's standard, 3·rtol·t), over rtol
/// 1e-4 … 1e-9; and a slider's first hit is `gap/v` exactly.
#[test]
fn limit_hit_times_follow_the_tolerance() {
    let (m, i, l, g, phi0): (f64, f64, f64, f64, f64) = (1.0, 1e-4, 1.0, 9.81, 1.0);
    let quarter = elliptic_k((phi0 / 2.0).sin()) * ((m * l * l + i) / (m * g * l)).sqrt();
    for k in 4..=9 {
        let rtol = 10f64.powi(-k);
        let s = pendulum([0.0, 0.0, -l], phi0, JointLimit::lower(0.0), options(false));
        let res = s
            .build()
            .unwrap()
            .simulate(&SimOptions::new(0.6).tolerance(rtol).progress(false))
            .unwrap();
        let hit = res.events[0].t;
        let err = (hit - quarter).abs() / (rtol * quarter);
        println!(
            "rtol {rtol:.0e}: pendulum hit at {hit:.12} s, error {err:.3}·rtol·t, {} steps",
            res.stats.solver.steps
        );
        assert!(err <= 3.0, "rtol {rtol:e}: hit time off by {err}·rtol·t");
    }
}

/// Bad limits are typed scene errors that name the joint and the coordinate.
#[test]
fn bad_limits_are_typed_errors_naming_the_joint() {
    let build = |limit: JointLimit, phi0: f64| {
        pendulum([0.0, 0.0, -1.0], phi0, limit, options(false))
            .build()
            .unwrap_err()
            .0
    };
    let e = build(JointLimit::range(1.0, -1.0), 0.0);
    assert!(
        matches!(&e[..], [SceneError::LimitRange { joint, coordinate: "phi", .. }] if joint == "hinge"),
        "{e:?}"
    );
    println!("{}", e[0]);
    let e = build(JointLimit::range(-1.0, 1.0), 1.5);
    assert!(
        matches!(&e[..], [SceneError::LimitOutside { joint, coordinate: "phi", value, .. }] if joint == "hinge" && *value == 1.5),
        "{e:?}"
    );
    println!("{}", e[0]);
    let e = build(JointLimit::range(-1.0, 1.0).on("s"), 0.0);
    assert!(
        matches!(&e[..], [SceneError::Unknown { name, .. }] if name == "s"),
        "{e:?}"
    );
    let e = build(JointLimit::range(-1.0, 1.0).cor(1.5), 0.0);
    assert!(
        matches!(&e[..], [SceneError::InvalidValue { what, .. }] if what.contains("hinge")),
        "{e:?}"
    );
    // A beam pinned at both ends: one of its two hinges closes the loop (a cut joint, whose
    // coordinate is no state), so limits there are refused; marking the other one `cut`
    // keeps the limited hinge in the tree.
    let beam = |limited_is_cut: bool| {
        let mut s = SceneDesc::new();
        s.add(Object3D::new("world").scene(SceneOptions::default()))
            .add(
                Object3D::new("anchor")
                    .parent("world")
                    .translation([1.0, 0.0, 0.0]),
            )
            .add(Object3D::new("beam").solid(point_mass(1.0, 0.1)))
            .add(
                Object3D::new("beam_end")
                    .parent("beam")
                    .translation([1.0, 0.0, 0.0]),
            )
            .add_joint(Joint::new("pin", "world", "beam", JointKind::revolute(2)))
            .add_joint(
                Joint::new("support", "anchor", "beam_end", JointKind::revolute(2))
                    .limits(-0.5, 0.5)
                    .cut(limited_is_cut),
            );
        if !limited_is_cut {
            // The first-declared `pin` stays in the tree unless marked; mark it.
            s.joints.iter_mut().for_each(|j| j.cut = j.name == "pin");
        }
        s.build()
    };
    let e = beam(true).unwrap_err().0;
    assert!(
        matches!(&e[..], [SceneError::LimitOnCutJoint { joint }] if joint == "support"),
        "{e:?}"
    );
    println!("{}", e[0]);
    assert!(beam(false).is_ok());
}
