//! Reading results as people do: `signal_at`, `SimStats`'s `Display`, `signal_names` without
//! the constant signals of fixed objects.

use modia3d::demo;
use modia3d::prelude::*;

fn pendulum() -> Model {
    let mut s = SceneDesc::new();
    s.add(demo::world(SceneOptions::default()))
        .add(
            Object3D::new("base")
                .parent("world")
                .translation([0.0, 0.0, 1.0]),
        )
        .add(Object3D::new("link"))
        .add(
            Object3D::new("bob")
                .parent("link")
                .translation([0.0, 0.0, -1.0])
                .solid(Solid::new(Shape::Sphere { diameter: 0.05 }).material("Steel")),
        )
        .add_joint(Joint::new(
            "rev",
            "base",
            "link",
            JointKind::Revolute {
                axis: Vector3::y(),
                phi: 1.0,
                w: 0.0,
            },
        ));
    s.build().unwrap()
}

/// Between output points: against a run whose 1 ms grid holds the time asked for (the grid
/// never steers the steps, so both runs take the same steps and the fine grid's value is the
/// solver's own interpolant there). A 1 m pendulum from 1 rad (period ≈ 2.1 s). With
/// `output_steps` the nodes are the solver's steps: the cubic's error is then of the order of
/// the solver's local error (rtol 1e-9) for steps up to a few ms, and 1e-6 rad leaves room;
/// on a coarse 0.1 s grid alone the cubic is worse but within 1e-3 rad (error ~ (ωh)⁴/4!·φ
/// with ωh = 0.3: 3e-4 rad).
#[test]
fn signal_at_between_output_points() {
    let model = pendulum();
    let opts = SimOptions::new(1.0).tolerance(1e-9).progress(false);
    let fine = model.simulate(&opts.clone().interval(0.001)).unwrap();
    let steps = model
        .simulate(&opts.clone().interval(0.1).output_steps(true))
        .unwrap();
    let coarse = model.simulate(&opts.clone().interval(0.1)).unwrap();
    for t in [0.123, 0.555, 0.987] {
        let k = fine
            .time()
            .iter()
            .position(|&x| (x - t).abs() < 1e-12)
            .unwrap();
        let reference = fine.signal("rev.phi").unwrap().at(k).unwrap()[0];
        let a = steps.signal_at("rev.phi", t).unwrap()[0];
        let b = coarse.signal_at("rev.phi", t).unwrap()[0];
        println!(
            "t = {t}: steps {:.1e}, coarse {:.1e}",
            a - reference,
            b - reference
        );
        assert!((a - reference).abs() < 1e-6, "{a} vs {reference}");
        assert!((b - reference).abs() < 1e-3, "{b} vs {reference}");
        // A vector signal interpolates per component (R_abs: 9 values).
        assert_eq!(steps.signal_at("bob.R_abs", t).unwrap().len(), 9);
    }
    // Exact at output points; outside the run an error.
    let k = 5;
    let t = coarse.time()[k];
    assert_eq!(
        coarse.signal_at("rev.phi", t).unwrap()[0],
        coarse.signal("rev.phi").unwrap().at(k).unwrap()[0]
    );
    assert!(coarse.signal_at("rev.phi", 1.5).is_err());
}

/// With `dense_output`, `signal_at` evaluates IDA's own interpolating polynomial of the step
/// that holds `t`: on a coarse 0.1 s grid it equals the 1 ms grid's value, which is read off the
/// same polynomial by `IDAGetDky` (the grid never steers the steps, so both runs take the same
/// steps), up to rounding: the Taylor form about the step's end and IDA's own evaluation differ
/// by a few ulps of the terms, hence 1e-12 (rad, m). The cubic through the coarse grid is off by
/// ~1e-4 rad there (previous test), so the bound tells the two apart by eight orders.
#[test]
fn dense_output_is_the_solvers_interpolant() {
    let model = pendulum();
    let opts = SimOptions::new(1.0).tolerance(1e-9).progress(false);
    let fine = model.simulate(&opts.clone().interval(0.001)).unwrap();
    let dense = model
        .simulate(&opts.clone().interval(0.1).dense_output(true))
        .unwrap();
    assert_eq!(fine.stats.solver.steps, dense.stats.solver.steps);
    for t in [0.031, 0.123, 0.555, 0.987] {
        let k = fine
            .time()
            .iter()
            .position(|&x| (x - t).abs() < 1e-12)
            .unwrap();
        let t = fine.time()[k];
        for name in ["rev.phi", "rev.w", "bob.r_abs[2]", "bob.v_abs[0]"] {
            let reference = fine.signal(name).unwrap().at(k).unwrap()[0];
            let v = dense.signal_at(name, t).unwrap()[0];
            println!("t = {t}: {name} {:.1e}", v - reference);
            assert!(
                (v - reference).abs() < 1e-12,
                "{name} at {t}: {v} vs {reference}"
            );
        }
        assert_eq!(dense.signal_at("bob.R_abs", t).unwrap().len(), 9);
    }
}

/// At an event time `signal_at` returns the value recorded at the event, exactly.
#[test]
fn signal_at_is_exact_at_events() {
    let pair = ContactPairMaterial::new(0.9, 0.0, 0.0);
    let steel = modia3d::core::scene::builtin_solid_material("Steel").unwrap();
    let model = demo::sphere_on_plane(0.02, steel, 0.0, 0.05, pair, SceneOptions::default())
        .build()
        .unwrap();
    let res = model
        .simulate(&SimOptions::new(0.15).interval(0.01).progress(false))
        .unwrap();
    let ev = &res.events[0];
    let k = res.time().iter().rposition(|&x| x == ev.t).unwrap();
    let v = res.signal("ball.v_abs").unwrap();
    assert_eq!(res.signal_at("ball.v_abs", ev.t).unwrap(), v.at(k).unwrap());
    // Just before the impact the cubic uses only the free-flight stretch: the speed there is
    // that of free fall, v = −g t, to the solver's accuracy (not smeared by the rebound).
    let t = ev.t - 1e-4;
    let vz = res.signal_at("ball.v_abs[2]", t).unwrap()[0];
    assert!((vz + 9.81 * t).abs() < 1e-4, "{vz} vs {}", -9.81 * t);
}

/// `signal_names` lists what moves; fixed objects' signals stay readable by name.
#[test]
fn signal_names_skip_fixed_objects() {
    let res = pendulum()
        .simulate(&SimOptions::new(0.1).progress(false))
        .unwrap();
    let names = res.signal_names();
    assert!(names.contains(&"bob.r_abs".to_string()));
    assert!(!names
        .iter()
        .any(|n| n.starts_with("base.") || n.starts_with("world.")));
    let base = res.signal("base.r_abs").unwrap();
    assert_eq!(base.first().unwrap(), &[0.0, 0.0, 1.0]);
    // Every listed name is readable.
    for n in &names {
        res.signal(n).unwrap();
    }
}

/// `SimStats` prints as readable lines with the counters.
#[test]
fn stats_display() {
    let res = pendulum()
        .simulate(&SimOptions::new(0.5).progress(false))
        .unwrap();
    let text = res.stats.to_string();
    println!("{text}");
    assert!(text.contains(&format!("steps: {} ", res.stats.solver.steps)));
    assert!(text.contains("events: 0") && text.contains("wall time:"));
    assert_eq!(text.lines().count(), 5);
}
