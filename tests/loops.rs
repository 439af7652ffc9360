//! Closed kinematic loops against independent references: Freudenstein's equation of the
//! four-bar, energy conservation, constraint residuals. Every tolerance is argued where it is
//! asserted.

use modia3d::prelude::*;

mod energy;
use energy::{energy, Part};

#[allow(dead_code)] // the model type and the closed form are used, not the example's main
#[path = "../examples/four_bar.rs"]
mod four_bar;
use four_bar::{freudenstein, FourBar};

/// The crank driven at 2π rad/s for one revolution: the rocker angle equals Freudenstein's
/// closed form at the simulated crank angle. The crank coordinate is prescribed, so it is the
/// independent coordinate; the rocker angle is then fixed by the constraints alone, which the
/// stabilised formulation holds to the Newton tolerance of each step (~rtol · atol-scale ≈
/// 1e-12 rad here) plus the interpolation error of output points inside a step (the local
/// error, ≤ ~1e-10 at rtol 1e-10); 1e-9 rad leaves a factor ten.
#[test]
fn driven_four_bar_follows_freudenstein() {
    let fb = FourBar::default();
    let model = fb.build().unwrap();
    let loops = model.loops();
    assert_eq!(loops.len(), 1, "{loops:?}");
    assert_eq!(loops[0].cut, "loop_joint");
    // A planar loop of spatial revolutes: 5 rows of rank 2 (x, y kept; z, two tilts dropped).
    assert_eq!(loops[0].rows, 2, "{loops:?}");
    assert_eq!(loops[0].dropped.len(), 3, "{loops:?}");
    assert_eq!(model.independent_coordinates(), vec!["crank_joint.phi"]);
    let res = model
        .simulate(&SimOptions::new(1.0).tolerance(1e-10).interval(0.005))
        .unwrap();
    let theta2 = res.signal("crank_joint.phi").unwrap().values();
    let theta4 = res.signal("rocker_joint.phi").unwrap().values();
    assert!(
        theta2.last().unwrap() - theta2[0] > 2.0 * std::f64::consts::PI - 1e-9,
        "a full revolution"
    );
    let worst = theta2
        .iter()
        .zip(&theta4)
        .map(|(t2, t4)| (freudenstein(fb.a, fb.b, fb.c, fb.d, *t2) - t4).abs())
        .fold(0.0, f64::max);
    eprintln!("worst {worst:e} steps {}", res.stats.solver.steps);
    assert!(worst <= 1e-9, "max |θ4 − θ4_Freudenstein| = {worst:e} rad");
}

#[allow(dead_code)]
#[path = "../examples/slider_crank.rs"]
mod slider_crank;

/// The slider-crank of SUNDIALS' `idaSlCrank_dns` (Haug's example 6.1.8) at t = 1 s against an
/// independent formulation: the minimal-coordinate ODE in the crank angle alone, integrated by
/// scipy's DOP853 at rtol 1e-12, atol 1e-14. The numbers below are the output of
/// `python3 scripts/slider_crank_reference.py` (scipy 1.17.1). The ODE's own error is ~1e-12;
/// ours at rtol 1e-10 (atol 1e-12) over one second of a smooth, non-stiff motion is a few
/// 1e-10 (global error ≈ 10–100 × the local tolerance), so 1e-7 is met with a wide margin and
/// would still catch any wrong force, inertia or constraint term (they change the state at
/// t = 1 s by far more than 1e-3).
#[test]
fn slider_crank_matches_the_minimal_coordinate_ode() {
    let model = slider_crank::SliderCrank::default().build().unwrap();
    assert_eq!(model.independent_coordinates(), vec!["crank_joint.phi"]);
    let res = model
        .simulate(&SimOptions::new(1.0).tolerance(1e-10))
        .unwrap();
    let reference = [
        ("crank_joint.phi", 1.315420570881723e+00),
        ("slide.s", 1.001491807230787e+00),
        ("rod_joint.phi", -5.04973470642005e-1),
        ("crank_joint.w", -5.087929769098432e-01),
        ("slide.v", 2.816690946869714e-01),
        ("rod_joint.w", 7.342752901417478e-02),
    ];
    for (name, expected) in reference {
        let got = res.signal(name).unwrap().last().unwrap()[0];
        eprintln!(
            "{name}: {got:.15e} vs {expected:.15e}: {:e}",
            (got - expected).abs()
        );
        assert!(
            (got - expected).abs() <= 1e-7,
            "{name} at 1 s: {got:.15e}, reference {expected:.15e}"
        );
    }
}

/// The four-bar without its drive (the input removed), swinging under gravity (−y) from the
/// example's initial state. Bars are steel boxes `l × w × w` (8000 kg/m³) whose centres are the
/// `*_bar` objects.
fn free_four_bar() -> (Model, Vec<Part<'static>>) {
    let fb = FourBar::default();
    let mut scene = fb.scene();
    scene.inputs.clear();
    let bar = |name, l: f64| {
        let m = 8000.0 * l * fb.w * fb.w;
        let (side, end) = (m * (fb.w * fb.w + l * l) / 12.0, m * fb.w * fb.w / 6.0);
        (
            name,
            m,
            Matrix3::from_diagonal(&Vector3::new(end, side, side)),
        )
    };
    let parts = vec![
        bar("crank_bar", fb.a),
        bar("coupler_bar", fb.b),
        bar("rocker_bar", fb.c),
    ];
    (scene.build().unwrap(), parts)
}

/// Free under gravity, the linkage conserves its energy: the constraint forces do no work
/// (they act at coincident points with equal and opposite velocities), so any change is
/// integration error. Scale: the largest energy of the run (0.64 J). BDF dissipates slowly and
/// steadily: at rtol 1e-10 the drift grows about linearly, measured 2.5e-9 J after 1 s,
/// 2.6e-9 J after 2 s (the crank's first two turns), 7e-9 J after 5 s; over 2 s 1e-8 of the
/// scale (6.4e-9 J) leaves a factor two, while a wrong constraint force (power λ·G v ≠ 0) or a
/// wrong inertia term changes it by orders of magnitude more.
#[test]
fn free_four_bar_conserves_energy() {
    let (model, parts) = free_four_bar();
    let res = model
        .simulate(&SimOptions::new(2.0).tolerance(1e-10).interval(0.01))
        .unwrap();
    let e = energy(&res, &parts, Vector3::new(0.0, -9.81, 0.0));
    let scale = e.iter().fold(0.0f64, |m, x| m.max(x.abs()));
    let drift = e.iter().map(|x| (x - e[0]).abs()).fold(0.0, f64::max);
    eprintln!(
        "energy scale {scale:e} J, drift {drift:e} J, steps {}",
        res.stats.solver.steps
    );
    assert!(
        drift <= 1e-8 * scale,
        "energy drift {drift:e} J of {scale:e} J"
    );
}

/// A planar four-bar of spatial revolutes is over-constrained: the cut revolute's five rows
/// (three translations, two axis alignments) have rank 2 on planar motions. The build drops
/// the three redundant rows by name and the run (above) has a regular iteration matrix.
#[test]
fn redundant_rows_of_a_planar_loop_are_dropped_by_name() {
    let loops = FourBar::default().build().unwrap().loops();
    assert_eq!(
        loops[0].dropped,
        ["loop_joint.z", "loop_joint.align3", "loop_joint.align4"]
    );
}

/// A coupler too short to reach the rocker (crank tip to rocker pivot ≥ 0.2 m, coupler + rocker
/// = 0.3 m, but the coupler alone is 0.05 m and the rocker 0.1 m): no configuration closes the
/// loop, and the build says so by name instead of failing in Newton's method.
#[test]
fn a_loop_that_cannot_close_is_a_typed_error_naming_it() {
    let fb = FourBar {
        b: 0.05,
        c: 0.1,
        ..FourBar::default()
    };
    let errors = fb.build().unwrap_err();
    let [SceneError::ImpossibleLoop {
        cut,
        joints,
        residual,
        reach,
    }] = &errors.0[..]
    else {
        panic!("expected one ImpossibleLoop, got {errors:?}");
    };
    assert_eq!(cut, "loop_joint");
    assert_eq!(joints.len(), 4, "{joints:?}");
    // The closest approach leaves a gap of at least 0.2 − 0.15 = 0.05 m.
    assert!(*residual > 0.01, "residual {residual}");
    let text = errors.to_string();
    println!("{text}");
    assert!(
        text.contains("loop_joint") && text.contains("cannot close"),
        "{text}"
    );
    // And why (issue 44, point 8): the ground, 0.3 m from the crank's pivot to the rocker's,
    // is longer than crank, coupler and rocker together (0.1 + 0.05 + 0.1 = 0.25 m) — the
    // polygon of the four pivots cannot close, whatever the angles. The lengths are the
    // scene's own numbers, so they agree to rounding.
    let reach = reach
        .as_ref()
        .expect("the link lengths show the loop cannot close");
    let mut ends = [reach.from.as_str(), reach.to.as_str()];
    ends.sort_unstable();
    assert_eq!(ends, ["ground_b", "world"]);
    assert!((reach.length - 0.3).abs() < 1e-12, "{reach:?}");
    assert!((reach.others - 0.25).abs() < 1e-12, "{reach:?}");
    assert!(
        text.contains("too short to reach")
            && text.contains("3.0000e-1 m")
            && text.contains("2.5000e-1 m"),
        "{text}"
    );
}

/// A four-bar whose links reach but whose start is far off still assembles: the reach test
/// claims nothing about it (the default four-bar, and one with the ground exactly as long as
/// the others together, a flat limit that closes stretched out).
#[test]
fn a_loop_that_can_close_has_no_reach_complaint() {
    FourBar::default().build().unwrap();
    let flat = FourBar {
        a: 0.1,
        b: 0.1,
        c: 0.1,
        d: 0.3,
        theta2: 0.0,
        phi3: 0.0,
        phi4: 0.0,
        ..FourBar::default()
    };
    // Stretched flat the loop closes (or fails for the singular position, but never for
    // its lengths).
    if let Err(errors) = flat.build() {
        for e in &errors.0 {
            assert!(
                !matches!(e, SceneError::ImpossibleLoop { reach: Some(_), .. }),
                "{e}"
            );
        }
    }
}

/// Constraint drift of the driven four-bar over 100 s (100 crank turns) at rtol = atol = 1e-8
/// (the states are O(1) m, rad, m/s): at step points (the step-wise API stops exactly at each
/// 0.5 s) the gap between the coupler's and the rocker's tips and their relative velocity stay
/// within 10·atol, and show no growth: the mean of the last 25 s is within 3× the mean of the
/// first 25 s (the stabilised formulation solves g = 0 and G v = 0 at every step, so the gaps
/// are Newton-tolerance noise that does not accumulate; a drifting index-1 formulation would
/// grow roughly linearly, 4× from the first to the last quarter).
#[test]
fn four_bar_constraints_do_not_drift_over_100_s() {
    let model = FourBar::default().build().unwrap();
    let (rtol, atol) = (1e-8, 1e-8);
    let mut sim = model
        .simulation(
            &SimOptions::new(100.0)
                .tolerance(rtol)
                .atol(atol)
                .interval(1.0),
        )
        .unwrap();
    let mut gaps = vec![];
    for k in 1..=200 {
        sim.advance_to(0.5 * k as f64).unwrap();
        let diff = |s: &str, sim: &mut Simulation| {
            let a = sim.output(&format!("coupler_tip.{s}")).unwrap();
            let b = sim.output(&format!("rocker_tip.{s}")).unwrap();
            (0..3).map(|i| (a[i] - b[i]).abs()).fold(0.0, f64::max)
        };
        gaps.push((diff("r_abs", &mut sim), diff("v_abs", &mut sim)));
    }
    let stats = |w: &[(f64, f64)]| {
        let n = w.len() as f64;
        let max = w
            .iter()
            .fold((0.0f64, 0.0f64), |m, x| (m.0.max(x.0), m.1.max(x.1)));
        let mean = w
            .iter()
            .fold((0.0, 0.0), |m, x| (m.0 + x.0 / n, m.1 + x.1 / n));
        (max, mean)
    };
    let ((max, _), (_, first), (_, last)) = (stats(&gaps), stats(&gaps[..50]), stats(&gaps[150..]));
    eprintln!(
        "max gaps {max:?} (m, m/s); means first 25 s {first:?}, last 25 s {last:?}; steps {}",
        sim.result().stats.solver.steps
    );
    assert!(max.0 <= 10.0 * atol, "position gap {:e} m", max.0);
    assert!(max.1 <= 10.0 * atol, "velocity gap {:e} m/s", max.1);
    assert!(
        last.0 <= 3.0 * first.0 + 1e-15 && last.1 <= 3.0 * first.1 + 1e-15,
        "growth: first 25 s {first:?}, last 25 s {last:?}"
    );
}

#[allow(dead_code)]
#[path = "../examples/andrews_squeezer.rs"]
mod andrews;

/// Andrews' squeezing mechanism at t = 0.03 s against the reference solution of the Bari test
/// set for IVP solvers (F. Mazzia, C. Magherini et al., "Test Set for IVP Solvers",
/// problem `andrews`, reference solution at t = 0.03 computed with RADAU5 at tight tolerances;
/// the same numbers as Hairer & Wanner, *Solving ODEs II*, §VII.7), copied into
/// `examples/andrews_squeezer.rs` as `REFERENCE_003`. Our coordinates are the test set's (the
/// example's joints), so each angle compares directly. At rtol 1e-10 (atol 1e-12) the measured
/// relative errors are 2e-12 … 1.3e-9 (γ, the smallest angle, largest); 1e-7, the issue's
/// bound, leaves a factor 70, and any wrong mass, lever arm or force in the seven-body model
/// changes the angles at 0.03 s by far more (β turns 2.5 times in that time). (Also measured
/// while building it: the consistent initial accelerations equal the test set's `w0`,
/// β̈ = 14222.44 and Θ̈ = −10666.83 rad/s², to 13 digits.)
#[test]
fn andrews_squeezer_matches_the_test_set_reference() {
    let model = andrews::AndrewsSqueezer::default().build().unwrap();
    assert_eq!(model.loops().len(), 3);
    let res = model
        .simulate(&SimOptions::new(0.03).tolerance(1e-10).interval(0.001))
        .unwrap();
    for (j, reference) in andrews::JOINTS.iter().zip(andrews::REFERENCE_003) {
        let got = res.signal(&format!("{j}.phi")).unwrap().last().unwrap()[0];
        let rel = ((got - reference) / reference).abs();
        assert!(
            rel <= 1e-7,
            "{j} at 0.03 s: {got:.15e}, reference {reference:.15e}, relative error {rel:e}"
        );
    }
}

/// The constraint force signal against statics: a 1 m beam of 2 kg (centre of mass in the
/// middle) pinned to the world at one end and, by the cut revolute `support`, at the other.
/// Only the support's vertical row is independent (the beam cannot move at all); the support
/// then carries half the weight, `support.f = (0, 0, m g / 2)` on the beam, resolved in the
/// anchor's (world-aligned) frame, and no torque. Statics is exact, so only round-off of the
/// Newton solves remains: 1e-9 of m g.
#[test]
fn cut_joint_force_of_a_beam_on_two_supports_is_half_its_weight() {
    let (m, g) = (2.0, 9.81);
    let mut s = SceneDesc::new();
    s.add(Object3D::new("world").scene(SceneOptions::default()))
        .add(
            Object3D::new("anchor")
                .parent("world")
                .translation([1.0, 0.0, 0.0]),
        )
        .add(Object3D::new("beam").solid(Solid {
            mass_properties: MassSpec::Explicit {
                mass: m,
                com: Vector3::new(0.5, 0.0, 0.0),
                inertia: Matrix3::from_diagonal(&Vector3::new(0.01, m / 12.0, m / 12.0)),
            },
            ..Default::default()
        }))
        .add(
            Object3D::new("beam_end")
                .parent("beam")
                .translation([1.0, 0.0, 0.0]),
        )
        .add_joint(Joint::new("pin", "world", "beam", JointKind::revolute(2)))
        .add_joint(Joint::new("support", "anchor", "beam_end", JointKind::revolute(2)).cut(true));
    let model = s.build().unwrap();
    assert_eq!(model.loops()[0].rows, 1, "{:?}", model.loops());
    let res = model
        .simulate(&SimOptions::new(0.1).tolerance(1e-8))
        .unwrap();
    let (f, t) = (
        res.signal("support.f").unwrap(),
        res.signal("support.t").unwrap(),
    );
    assert_eq!((f.unit, t.unit), ("N", "N·m"));
    for k in 0..f.len() {
        let (fk, tk) = (f.at(k).unwrap(), t.at(k).unwrap());
        let expected = [0.0, 0.0, m * g / 2.0];
        for i in 0..3 {
            assert!((fk[i] - expected[i]).abs() <= 1e-9 * m * g, "f = {fk:?}");
            assert!(tk[i].abs() <= 1e-9 * m * g, "t = {tk:?}");
        }
    }
}

#[allow(dead_code)]
#[path = "../examples/rssr_obstacle.rs"]
mod rssr_obstacle;

/// A spatial loop (RSSR: revolute, spherical, spherical cut, revolute) whose rocker's ball
/// strikes a wall again and again: contacts on a loop body work with the constraints. Every
/// impact is an event and a restart (the loop re-projected, consistent accelerations and
/// multipliers from the KKT system); the run must get through them (≥ 10 impacts in 2 s), and
/// at the stop time (a step point) the spherical cut's gap between the coupler's and the
/// rocker's tips stays within 10·atol (atol 1e-8 m): the restarts do not break the loop.
#[test]
fn spatial_loop_hitting_a_wall_keeps_its_constraints_through_events() {
    let model = rssr_obstacle::Rssr::default().build().unwrap();
    assert_eq!(model.loops()[0].rows, 3, "a spherical cut: three rows");
    let (rtol, atol) = (1e-6, 1e-8);
    let mut sim = model
        .simulation(
            &SimOptions::new(2.0)
                .tolerance(rtol)
                .atol(atol)
                .interval(0.01),
        )
        .unwrap();
    sim.advance_to(2.0).unwrap();
    let a = sim.output("coupler_tip.r_abs").unwrap();
    let b = sim.output("rocker_tip.r_abs").unwrap();
    let gap = (0..3).map(|i| (a[i] - b[i]).abs()).fold(0.0, f64::max);
    let events = sim.result().events.len();
    assert!(
        events >= 20,
        "{events} events (10 impacts: start and end each)"
    );
    assert!(gap <= 10.0 * atol, "gap {gap:e} m after {events} events");
}

/// Inputs and the coloured Jacobian with a loop. The crank's prescribed acceleration is set to
/// 2 rad/s² at t = 0.5 s through the step-wise API (a restart: the loop is re-projected and the
/// multipliers recomputed): the crank speed at 1 s is then 2π + 2·0.5 rad/s exactly (BDF
/// integrates a constant acceleration exactly, so 1e-9 covers round-off), and the rocker still
/// obeys Freudenstein's equation (1e-8 rad at rtol 1e-10, as in the driven test). The same run
/// with IDA's dense Jacobian (`structured_jacobian(false)`; the four-bar is two joint trees
/// coupled only by the loop) ends in the same state to 1e-8 (both are converged to ~1e-10).
#[test]
fn input_change_restarts_a_loop_and_both_jacobians_agree() {
    let fb = FourBar::default();
    let model = fb.build().unwrap();
    let run = |structured: bool| {
        let opts = SimOptions::new(1.0)
            .tolerance(1e-10)
            .interval(0.1)
            .structured_jacobian(structured);
        let mut sim = model.simulation(&opts).unwrap();
        sim.advance_to(0.5).unwrap();
        sim.set_input("drive", &[2.0]).unwrap();
        sim.advance_to(1.0).unwrap();
        sim.state().to_vec()
    };
    let (coloured, dense) = (run(true), run(false));
    // State y = [q; v]: crank, rocker, coupler (tree order).
    let (theta2, theta4, w2) = (coloured[0], coloured[1], coloured[3]);
    assert!(
        (w2 - (std::f64::consts::TAU + 1.0)).abs() <= 1e-9,
        "crank speed {w2}"
    );
    let freud = freudenstein(fb.a, fb.b, fb.c, fb.d, theta2);
    assert!((theta4 - freud).abs() <= 1e-8, "rocker {theta4} vs {freud}");
    let diff = coloured
        .iter()
        .zip(&dense)
        .map(|(a, b)| (a - b).abs())
        .fold(0.0, f64::max);
    assert!(diff <= 1e-8, "coloured vs dense Jacobian: {diff:e}");
}
