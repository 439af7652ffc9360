//! Contact phases (`SimulationResult::contacts`): a steel ball dropped on a steel table, its
//! 0.07 ms impact sampled by a 10 ms output grid that never sees it. The phase's impulse is
//! checked against the momentum balance of the simulated motion, its peak force against the
//! Hertz closed form, and the whole phase against a run with a 1 ms grid.

use modia3d::demo::{self, sphere_mass};
use modia3d::prelude::*;

const D: f64 = 0.02;
const GAP: f64 = 0.05;
const G: f64 = 9.81;

fn steel() -> SolidMaterial {
    modia3d::core::scene::builtin_solid_material("Steel").unwrap()
}

/// Ball Ø 20 mm dropped from rest 50 mm above the table; cor = 1 (d = 0, the Hertz law).
fn drop_model() -> Model {
    let options = SceneOptions {
        gravity: Vector3::new(0.0, 0.0, -G),
        k_red: 1.0,
        ..Default::default()
    };
    let pair = ContactPairMaterial::new(1.0, 0.0, 0.0);
    demo::sphere_on_plane(D, steel(), 0.0, GAP, pair, options)
        .build()
        .unwrap()
}

fn run(interval: f64) -> SimulationResult {
    drop_model()
        .simulate(
            &SimOptions::new(0.15)
                .tolerance(1e-10)
                .interval(interval)
                .contact_results(true),
        )
        .unwrap()
}

/// `ball.v_abs[2]` [m/s] at the event at `t` (the point recorded at the event).
fn vz_at_event(res: &SimulationResult, t: f64) -> f64 {
    let k = res.time().iter().rposition(|&x| x == t).unwrap();
    res.signal("ball.v_abs[2]").unwrap().at(k).unwrap()[0]
}

/// A run with contact results recorded at every solver step (and a 10 ms grid).
fn run_with_steps() -> SimulationResult {
    drop_model()
        .simulate(
            &SimOptions::new(0.12)
                .tolerance(1e-8)
                .interval(0.01)
                .contact_results(true)
                .output_steps(true),
        )
        .unwrap()
}

/// Largest penetration δ_m of the Hertz contact of a mass `m` hitting a fixed half-space at
/// `v` under gravity `g` (normal against gravity): the energy balance
/// `½ m v² + m g δ_m = (2/5) K δ_m^{5/2}`, solved by Newton from the gravity-free value.
fn hertz_delta_max(m: f64, v: f64, k: f64, g: f64) -> f64 {
    let mut d = (5.0 * m * v * v / (4.0 * k)).powf(0.4);
    for _ in 0..50 {
        let f = 0.4 * k * d.powf(2.5) - m * g * d - 0.5 * m * v * v;
        let df = k * d.powf(1.5) - m * g;
        d -= f / df;
    }
    d
}

/// Acceptance of issue 12: impulse within 1e-6 of the momentum change, peak force within 1e-3
/// of Hertz, the same phase from a 1 ms grid within 1e-9.
#[test]
fn impact_phase_from_a_coarse_grid() {
    let res = run(0.01);
    let phases = res.contacts().unwrap();
    assert_eq!(phases.len(), 1, "{phases:#?}");
    let ph = &phases[0];
    assert_eq!(ph.pair, "ball|plane");
    let (t0, t1) = (ph.start, ph.end.expect("the ball leaves the table"));
    // No grid point inside the contact: the grid alone would have missed it.
    assert!(res.time().iter().all(|&t| t <= t0 || t >= t1 || t == t0));
    let m = sphere_mass(D, steel().density);

    // Impulse: m (v_out − v_in) = J_n − m g (t1 − t0) for the vertical motion (the normal is
    // vertical, no friction). v_in, v_out: the simulated velocities at the two events.
    // Tolerance 1e-6: the solver's relative tolerance is 1e-10 and the phase takes ~40 steps;
    // the quadrature error is far below (module header of simulation/contact_phases.rs).
    let (v_in, v_out) = (vz_at_event(&res, t0), vz_at_event(&res, t1));
    let j_ref = m * (v_out - v_in) + m * G * (t1 - t0);
    let rel = (ph.normal_impulse - j_ref).abs() / j_ref;
    println!(
        "J_n = {:.12e} N·s, momentum balance {j_ref:.12e} N·s, rel {rel:.1e}; t_c = {:.4e} s",
        ph.normal_impulse,
        t1 - t0
    );
    assert!(rel < 1e-6, "impulse off by {rel:e}");
    // Impulse on the plane (b) points down, along the normal from ball to plane.
    assert!((ph.impulse.z + ph.normal_impulse).abs() < 1e-12 * ph.normal_impulse);
    assert!(ph.tangential_impulse.norm() == 0.0);

    // Impact speed from free fall, exit speed and restitution (cor = 1: elastic; the exit is at
    // a separation of 2ε = 2e-8 m, so gravity takes 2ε·g/v² ≈ 2e-7 of the speed's square).
    let v0 = (2.0 * G * GAP).sqrt();
    assert!(
        (ph.impact_speed - v0).abs() < 1e-6 * v0,
        "{}",
        ph.impact_speed
    );
    assert!((ph.impact_speed + v_in).abs() < 1e-9 * v0);
    let exit = ph.exit_speed.unwrap();
    assert!((exit - v_out).abs() < 1e-9 * v0);
    let e = ph.restitution().unwrap();
    assert!((e - 1.0).abs() < 1e-5, "restitution {e}");

    // Peak force against Hertz with gravity: F_max = K δ_m^{3/2}, K = 4/3 E* √R.
    let k = 4.0 / 3.0 * demo::c_res(&steel(), &steel()) * (D / 2.0).sqrt();
    let dm = hertz_delta_max(m, v0, k, G);
    let f_ref = k * dm.powf(1.5);
    let rel_f = (ph.max_normal_force - f_ref).abs() / f_ref;
    let rel_d = (ph.max_penetration - dm).abs() / dm;
    println!(
        "F_max = {:.8e} N (Hertz {f_ref:.8e}, rel {rel_f:.1e}), δ_max = {:.8e} m (Hertz {dm:.8e}, rel {rel_d:.1e})",
        ph.max_normal_force, ph.max_penetration
    );
    assert!(rel_f < 1e-3 && rel_d < 1e-3);
    assert!(ph.t_max_normal_force > t0 && ph.t_max_normal_force < t1);

    // The same phase from a 1 ms grid: the grid does not steer the steps.
    let fine = run(0.001);
    let f = &fine.contacts().unwrap()[0];
    let close = |a: f64, b: f64| (a - b).abs() <= 1e-9 * a.abs().max(b.abs());
    assert!(close(f.start, ph.start) && close(f.end.unwrap(), t1));
    assert!(
        close(f.normal_impulse, ph.normal_impulse),
        "{f:?} vs {ph:?}"
    );
    assert!(close(f.max_normal_force, ph.max_normal_force));
    assert!(close(f.max_penetration, ph.max_penetration));
    assert!(close(f.impact_speed, ph.impact_speed) && close(f.exit_speed.unwrap(), exit));
}

/// Pair names work in both orders; reversed, the vectors are those on the first-named object.
#[test]
fn pair_lookup_in_both_orders() {
    let res = run_with_steps();
    let ab = res.signal("ball|plane.f_n").unwrap();
    let ba = res.signal("plane|ball.f_n").unwrap();
    assert_eq!(ab.data, ba.data);
    // With output_steps the contact shows in the signal itself.
    assert!(ab.values().iter().any(|&f| f > 100.0));
    let n_ab = res.signal("ball|plane.normal").unwrap();
    let n_ba = res.signal("plane|ball.normal").unwrap();
    assert!(n_ab.data.iter().zip(&n_ba.data).all(|(a, b)| *a == -*b));
    let p_ab = &res.contact_phases("ball|plane").unwrap()[0];
    let p_ba = &res.contact_phases("plane|ball").unwrap()[0];
    assert_eq!(p_ba.pair, "plane|ball");
    assert_eq!(p_ab.impulse, -p_ba.impulse);
    assert_eq!(p_ab.normal_impulse, p_ba.normal_impulse);
    let err = res.contact_phases("ball|table").unwrap_err().to_string();
    assert!(err.contains("ball|plane"), "{err}");
}

/// Asking for contact results of a run without them names the option.
#[test]
fn missing_contact_results_is_named() {
    let res = drop_model()
        .simulate(&SimOptions::new(0.01).interval(0.005))
        .unwrap();
    for name in ["ball|plane.f_n", "plane|ball.penetration"] {
        let err = res.signal(name).unwrap_err().to_string();
        assert!(err.contains("contact_results(true)"), "{err}");
    }
    let err = res.contacts().unwrap_err().to_string();
    assert!(err.contains("contact_results(true)"), "{err}");
}

/// `contact_phases(false)` records the same contact signals without measuring phases: the
/// measurement reads the solver and never steers it, so the run and its signals are the same
/// bit for bit (an independent check: a run that measures them), and asking for the phases
/// names the option.
#[test]
fn signals_without_phases_are_the_same_run() {
    let opts = SimOptions::new(0.12)
        .tolerance(1e-8)
        .interval(0.01)
        .contact_results(true)
        .output_steps(true);
    let full = drop_model().simulate(&opts).unwrap();
    let lean = drop_model()
        .simulate(&opts.clone().contact_phases(false))
        .unwrap();
    assert_eq!(full.stats.solver, lean.stats.solver);
    assert_eq!(full.time(), lean.time());
    for name in ["ball|plane.f_n", "ball|plane.penetration", "ball.r_abs"] {
        assert_eq!(
            full.signal(name).unwrap().data,
            lean.signal(name).unwrap().data,
            "{name}"
        );
    }
    assert!(lean
        .signal("ball|plane.f_n")
        .unwrap()
        .values()
        .iter()
        .any(|&f| f > 100.0));
    assert!(!full.contacts().unwrap().is_empty());
    let err = lean.contacts().unwrap_err();
    assert!(
        matches!(err, ResultError::ContactPhasesOff { .. }),
        "{err:?}"
    );
    assert!(err.to_string().contains("contact_phases(true)"), "{err}");
}

/// Without phases, a run in segments (a structure change: here a second, shapeless ball
/// deleted at 0.05 s) keeps recording the contact signals in the new segment: the impact at
/// ~0.1 s shows in `ball|plane.f_n` as in a run that measures the phases (the same signals
/// bit for bit, see above).
#[test]
fn signals_without_phases_go_on_across_segments() {
    let options = SceneOptions {
        gravity: Vector3::new(0.0, 0.0, -G),
        k_red: 1.0,
        ..Default::default()
    };
    let pair = ContactPairMaterial::new(1.0, 0.0, 0.0);
    let mut scene = demo::sphere_on_plane(D, steel(), 0.0, GAP, pair, options);
    scene
        .add(Object3D::new("spare").solid(Solid {
            mass_properties: MassSpec::Explicit {
                mass: 1.0,
                com: Vector3::zeros(),
                inertia: Matrix3::identity() * 1e-3,
            },
            ..Default::default()
        }))
        .add_joint(Joint::new(
            "spare_free",
            "world",
            "spare",
            JointKind::FreeMotion {
                r: Vector3::new(1.0, 0.0, 1.0),
                rot: FreeRotation::Cardan([0.0; 3]),
                v: Vector3::zeros(),
                w: Vector3::zeros(),
            },
        ));
    let model = scene.build().unwrap();
    let run = |phases: bool| {
        let opts = SimOptions::new(0.12)
            .tolerance(1e-8)
            .interval(0.01)
            .contact_results(true)
            .contact_phases(phases)
            .output_steps(true);
        let mut sim = model.simulation(&opts).unwrap();
        sim.advance_to(0.05).unwrap();
        sim.delete("spare").unwrap();
        sim.advance_to(0.12).unwrap();
        sim.into_result()
    };
    let (full, lean) = (run(true), run(false));
    assert_eq!(lean.segment_count(), 2);
    let f = lean.signal("ball|plane.f_n").unwrap();
    assert!(f.values().iter().any(|&f| f > 100.0), "no impact recorded");
    assert_eq!(full.signal("ball|plane.f_n").unwrap().data, f.data);
    assert!(matches!(
        lean.contacts(),
        Err(ResultError::ContactPhasesOff { .. })
    ));
}

/// `write_csv_signals` of chosen signals, contact signals (in either pair order) and
/// components included, reads back equal to the signals (17 significant digits round-trip an
/// f64 exactly); the default `write_csv` includes the contact signals of the run.
#[test]
fn csv_of_chosen_signals_reads_back_equal() {
    let res = run_with_steps();
    let names = ["plane|ball.f_n", "ball.r_abs[2]", "ball|plane.normal"];
    let path = std::env::temp_dir().join(format!("modia3d-phases-{}.csv", std::process::id()));
    res.write_csv_signals(&path, &names).unwrap();
    let text = std::fs::read_to_string(&path).unwrap();
    let lines: Vec<&str> = text.lines().collect();
    let header: Vec<&str> = lines[0].split(',').collect();
    assert_eq!(
        header,
        [
            "time [s]",
            "plane|ball.f_n [N]",
            "ball.r_abs[2] [m]",
            "ball|plane.normal[0] [1]",
            "ball|plane.normal[1] [1]",
            "ball|plane.normal[2] [1]"
        ]
    );
    assert_eq!(lines.len(), 1 + res.time().len());
    let rows: Vec<Vec<f64>> = lines[1..]
        .iter()
        .map(|l| l.split(',').map(|x| x.parse().unwrap()).collect())
        .collect();
    let column = |i: usize| rows.iter().map(|r| r[i]).collect::<Vec<f64>>();
    assert_eq!(column(0), res.time());
    assert_eq!(column(1), res.signal("plane|ball.f_n").unwrap().values());
    assert_eq!(column(2), res.signal("ball.r_abs[2]").unwrap().values());
    let n = res.signal("ball|plane.normal").unwrap();
    for k in 0..3 {
        assert_eq!(column(3 + k), n.component(k));
    }
    // An unknown name fails before anything is written.
    assert!(res.write_csv_signals(&path, &["ball.nope"]).is_err());
    res.write_csv(&path).unwrap();
    let text = std::fs::read_to_string(&path).unwrap();
    std::fs::remove_file(&path).ok();
    assert!(text.lines().next().unwrap().contains("ball|plane.f_n [N]"));
}
