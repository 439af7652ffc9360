//! The coloured Jacobian and block-diagonal LU (one block per joint tree, coupled by the
//! contacts in the set) against IDA's dense difference quotients and dense LU: the same scene
//! run both ways reaches a tight-tolerance reference equally well, at a fraction of the
//! residual evaluations per Jacobian.

use modia3d::demo;
use modia3d::prelude::*;

/// Final positions \[m\] and velocities [m/s] of `bodies`.
fn final_state(res: &SimulationResult, bodies: &[&str]) -> Vec<f64> {
    let mut out = vec![];
    for b in bodies {
        for s in ["r_abs", "v_abs"] {
            out.extend_from_slice(res.signal(&format!("{b}.{s}")).unwrap().last().unwrap());
        }
    }
    out
}

fn max_diff(a: &[f64], b: &[f64]) -> f64 {
    a.iter()
        .zip(b)
        .map(|(x, y)| (x - y).abs())
        .fold(0.0, f64::max)
}

/// Runs `scene` to `stop` at `rtol` with the structured and the dense Jacobian and at
/// `ref_rtol` (structured; the reference only has to be much more accurate than either run).
/// Asserts that the structured run's error is no worse than the dense run's (within a factor
/// 2, plus a floor of 10·rtol times the state scale for runs whose errors are both at
/// round-off-like levels), and returns the two runs' statistics. The structured run forms
/// every matrix by its quotients (`jacobian_reuse(false)`), so that the two differ only by
/// their quotients; a third run with the default reuse of the matrix's parts for new `c_j`
/// must be as accurate too (Newton's convergence depends on the matrix, not the accuracy).
fn compare(
    scene: SceneDesc,
    stop: f64,
    rtol: f64,
    ref_rtol: f64,
    bodies: &[&str],
) -> (SimStats, SimStats) {
    let model = scene.build().unwrap();
    let run = |rtol: f64, structured: bool, reuse: bool| {
        model
            .simulate(
                &SimOptions::new(stop)
                    .tolerance(rtol)
                    .interval(stop / 50.0)
                    .structured_jacobian(structured)
                    .jacobian_reuse(reuse),
            )
            .unwrap()
    };
    let reference = final_state(&run(ref_rtol, true, false), bodies);
    let (s, d) = (run(rtol, true, false), run(rtol, false, false));
    let r = run(rtol, true, true);
    let scale = reference.iter().fold(0.0f64, |m, x| m.max(x.abs()));
    let (err_s, err_d) = (
        max_diff(&final_state(&s, bodies), &reference),
        max_diff(&final_state(&d, bodies), &reference),
    );
    println!(
        "rtol {rtol:e}: error structured {err_s:.2e}, dense {err_d:.2e} (scale {scale:.2e})\n  structured {:?}\n  dense      {:?}",
        s.stats.solver, d.stats.solver
    );
    assert!(
        err_s <= 2.0 * err_d + 10.0 * rtol * scale,
        "structured error {err_s:e} vs dense {err_d:e}"
    );
    assert_eq!(s.stats.events, d.stats.events, "same contact events");
    let err_r = max_diff(&final_state(&r, bodies), &reference);
    println!("  with reuse: error {err_r:.2e}, {:?}", r.stats.solver);
    assert!(
        err_r <= 2.0 * err_d + 10.0 * rtol * scale,
        "structured error with reuse {err_r:e} vs dense {err_d:e}"
    );
    assert!(r.stats.solver.jacobian_reuses > 0, "the reuse is at work");
    // A missing coupling would leave the structured Jacobian wrong where contacts couple
    // trees: Newton would need more iterations per step and fail to converge more often (the
    // solver unit tests, modia3d-core/src/solver/tests/). The two Jacobians differ only by
    // their difference-quotient increments, so the iterations per step agree to a few per
    // cent; the step counts may differ more (up to 7 % seen, with the contact tightening of
    // the error test, docs/contact-model.md §5: the error estimates of the Newton iterates
    // differ), and are bounded at 15 %.
    let (ss, ds) = (s.stats.solver, d.stats.solver);
    let it_ratio = (ss.nonlinear_iterations as f64 / ss.steps as f64)
        / (ds.nonlinear_iterations as f64 / ds.steps as f64);
    assert!(
        (it_ratio - 1.0).abs() < 0.05,
        "Newton iterations per step structured/dense = {it_ratio}"
    );
    assert!(
        ss.nonlinear_convergence_failures <= ds.nonlinear_convergence_failures + ds.steps / 100,
        "convergence failures structured {} vs dense {}",
        ss.nonlinear_convergence_failures,
        ds.nonlinear_convergence_failures
    );
    let ratio = ss.steps as f64 / ds.steps as f64;
    assert!(
        (ratio - 1.0).abs() < 0.15,
        "steps structured/dense = {ratio}"
    );
    (s.stats, d.stats)
}

/// Per-Jacobian residual evaluations.
fn per_jacobian(s: &SimStats) -> f64 {
    s.solver.residual_evals_for_jacobian as f64 / s.solver.jacobian_evals as f64
}

#[test]
fn touching_cradle_chain_couples_all_five_trees() {
    // No gaps: the impact runs through a chain of simultaneous contacts, so the five revolute
    // trees (2 unknowns each) are coupled in a path: distance-2 colouring needs 3 colours,
    // i.e. 6 residuals per Jacobian while the chain is closed, 10 for the dense quotients.
    let scene = demo::newtons_cradle(0.05, 0.0, 0.5, ContactPairMaterial::new(1.0, 0.0, 0.0));
    let balls = ["ball0", "ball1", "ball2", "ball3", "ball4"];
    let (s, d) = compare(scene, 0.005, 1e-7, 1e-11, &balls);
    assert_eq!(per_jacobian(&d), 10.0);
    assert!(per_jacobian(&s) < 10.0, "{}", per_jacobian(&s));
}

#[test]
fn falling_boxes_cost_one_tree_per_jacobian() {
    // Four free bodies (13 unknowns each) landing on a fixed table: the table is no tree, so
    // the bodies are coupled only if they touch each other; the dense quotients cost 52.
    let scene = demo::falling_boxes(1e-3);
    let bodies = ["box1", "box2", "cyl1", "cyl2"];
    let (s, d) = compare(scene, 0.4, 1e-6, 1e-10, &bodies);
    assert_eq!(per_jacobian(&d), 52.0);
    assert!(per_jacobian(&s) <= 26.0, "{}", per_jacobian(&s));
}

#[test]
fn billiards_break_is_as_accurate_and_cheaper() {
    // 16 free balls (208 unknowns); the break couples a few at a time.
    let scene = demo::billiards16([3.0, 0.1, 0.0], 1.0);
    let mut balls: Vec<String> = (1..=15).map(|k| format!("ball{k}")).collect();
    balls.push("cue".into());
    let names: Vec<&str> = balls.iter().map(|s| s.as_str()).collect();
    let (s, d) = compare(scene, 0.5, 1e-6, 1e-9, &names);
    assert_eq!(per_jacobian(&d), 208.0);
    assert!(per_jacobian(&s) < 52.0, "{}", per_jacobian(&s));
}
