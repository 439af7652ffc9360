//! The wrapper against analytic or published reference solutions.

use super::*;

#[test]
fn exponential_decay_matches_exp() {
    let k = 2.0;
    let opts = IdaOptions::default().rtol(1e-10).atol(1e-12);
    let mut ida = decay_solver(k, &opts);
    let status = ida.solve(1.0, false).unwrap();
    assert_eq!(status, SolveStatus::Reached { t: 1.0 });
    let exact = (-k).exp();
    let rel = (ida.y()[0] - exact).abs() / exact;
    // IDA controls the local error per step at rtol = 1e-10; the global error of a BDF method
    // over ~100 steps on a stable decay stays within about 100 * rtol, hence 1e-8 relative.
    assert!(
        rel < 1e-8,
        "y(1) = {}, exp(-2) = {exact}, rel err {rel:e}",
        ida.y()[0]
    );
    // y' must be consistent with the ODE at the output time as well.
    assert!((ida.yp()[0] + k * ida.y()[0]).abs() < 1e-8);
    assert_eq!(ida.t(), 1.0);
}

/// Index-1 DAE: y1' = y2, 0 = y2 - cos t; with y1(0) = 0 the solution is y1 = sin t, y2 = cos t.
struct CosDae;

impl DaeSystem for CosDae {
    fn len(&self) -> usize {
        2
    }
    fn residual(
        &mut self,
        t: f64,
        y: &[f64],
        yp: &[f64],
        res: &mut [f64],
    ) -> Result<(), ResidualError> {
        res[0] = yp[0] - y[1];
        res[1] = y[1] - t.cos();
        Ok(())
    }
}

#[test]
fn index1_dae_with_consistent_initialisation() {
    let opts = IdaOptions::default()
        .rtol(1e-9)
        .atol(1e-11)
        .differential(vec![true, false]);
    // Inconsistent start: the algebraic y2 and both derivatives are wrong.
    let mut ida = Ida::new(CosDae, 0.0, &[0.0, 5.0], &[3.0, -7.0], &opts).unwrap();
    ida.calc_ic_ya_ydp(0.1).unwrap();
    // calc_ic must keep the differential y1 and solve for y2 = cos 0 = 1 and y1' = y2 = 1; the
    // IC Newton iteration stops at a small fraction of the error weights (rtol 1e-9), so 1e-8.
    assert_eq!(ida.y()[0], 0.0);
    assert!((ida.y()[1] - 1.0).abs() < 1e-8, "y2(0) = {}", ida.y()[1]);
    assert!((ida.yp()[0] - 1.0).abs() < 1e-8, "y1'(0) = {}", ida.yp()[0]);
    assert_eq!(ida.t(), 0.0);

    for &t in &[0.5, 1.0, 2.0, 3.0] {
        ida.solve(t, false).unwrap();
        let (y1, y2) = (ida.y()[0], ida.y()[1]);
        // Global error ~ 100 * rtol * |y| plus atol; 1e-6 leaves margin over ~1e-7.
        assert!(
            (y1 - t.sin()).abs() < 1e-6,
            "y1({t}) = {y1} vs sin = {}",
            t.sin()
        );
        assert!(
            (y2 - t.cos()).abs() < 1e-6,
            "y2({t}) = {y2} vs cos = {}",
            t.cos()
        );
    }
}

/// Robertson's stiff chemical kinetics with the conservation law as algebraic equation, the
/// standard IDA example (idaRoberts_dns).
struct Robertson;

impl DaeSystem for Robertson {
    fn len(&self) -> usize {
        3
    }
    fn residual(
        &mut self,
        _t: f64,
        y: &[f64],
        yp: &[f64],
        res: &mut [f64],
    ) -> Result<(), ResidualError> {
        let r1 = -0.04 * y[0] + 1.0e4 * y[1] * y[2];
        res[0] = r1 - yp[0];
        res[1] = -r1 - 3.0e7 * y[1] * y[1] - yp[1];
        res[2] = y[0] + y[1] + y[2] - 1.0;
        Ok(())
    }
}

#[test]
fn robertson_matches_published_values() {
    let opts = IdaOptions::default()
        .rtol(1e-6)
        .atol_vector(vec![1e-8, 1e-12, 1e-6])
        .differential(vec![true, true, false]);
    // Wrong y3 and y' on purpose: calc_ic must fix them.
    let mut ida = Ida::new(Robertson, 0.0, &[1.0, 0.0, 0.5], &[0.0, 0.0, 0.0], &opts).unwrap();
    ida.calc_ic_ya_ydp(0.4).unwrap();
    // The IC Newton iteration stops once the update is below ~0.0033 of the error weight; for
    // y3 that is ~0.0033 * atol3 (1e-6), so 1e-8 is a safe bound.
    assert!(ida.y()[2].abs() < 1e-8, "y3(0) = {}", ida.y()[2]);
    assert!(
        (ida.yp()[0] + 0.04).abs() < 1e-8,
        "y1'(0) = {}",
        ida.yp()[0]
    );
    // Reference values printed by SUNDIALS' idaRoberts_dns example (5 significant digits, at
    // tighter tolerances than ours); 1e-3 relative covers the print rounding (5e-5) and our
    // rtol-driven global error.
    let refs = [
        (0.4, [9.8517e-01, 3.3864e-05, 1.4794e-02]),
        (4.0e1, [7.1583e-01, 9.1855e-06, 2.8416e-01]),
        (4.0e3, [1.8320e-01, 8.9423e-07, 8.1680e-01]),
    ];
    for (t, r) in refs {
        ida.solve(t, false).unwrap();
        for (i, (&yi, &ri)) in ida.y().iter().zip(&r).enumerate() {
            let rel = (yi - ri).abs() / ri;
            assert!(rel < 1e-3, "t = {t}: y{} = {yi} vs {ri}", i + 1);
        }
        let sum: f64 = ida.y().iter().sum();
        assert!((sum - 1.0).abs() < 1e-10, "conservation violated: {sum}");
    }
}

#[test]
fn bouncing_ball_impact_times_match_analytic() {
    let (g, h0, e) = (9.81_f64, 1.0_f64, 0.8_f64);
    let (times, _) = bouncing_ball(5, e);
    let v1 = (2.0 * g * h0).sqrt();
    let mut exact = vec![(2.0 * h0 / g).sqrt()];
    for k in 1..5 {
        let prev = exact[k - 1];
        exact.push(prev + 2.0 * e.powi(k as i32) * v1 / g);
    }
    let max_err = times
        .iter()
        .zip(&exact)
        .map(|(a, b)| (a - b).abs())
        .fold(0.0, f64::max);
    println!("impact times {times:?}\nexact        {exact:?}\nmax error {max_err:e} s");
    // The motion is a polynomial of degree 2, which BDF integrates almost exactly; the root is
    // located to ~100 * eps * t and rtol 1e-10 bounds the state error carried from bounce to
    // bounce, so 1e-8 s absolute is a safe bound.
    assert!(max_err < 1e-8, "max impact time error {max_err:e} s");
}

#[test]
fn statistics_are_monotone_over_reinit() {
    let (_, stats) = bouncing_ball(4, 0.8);
    let mut prev = IdaStats::default();
    for (i, (before, after)) in stats.iter().enumerate() {
        assert!(before.steps > 0 && before.residual_evals > 0 && before.root_evals > 0);
        assert!(before.jacobian_evals > 0 && before.nonlinear_iterations > 0);
        // Re-initialisation must neither lose nor double-count anything.
        assert_eq!(before.steps, after.steps, "bounce {i}");
        assert_eq!(before.residual_evals, after.residual_evals, "bounce {i}");
        assert_eq!(before.jacobian_evals, after.jacobian_evals, "bounce {i}");
        assert_eq!(
            before.residual_evals_for_jacobian,
            after.residual_evals_for_jacobian
        );
        assert_eq!(before.root_evals, after.root_evals, "bounce {i}");
        assert_eq!(before.last_step, after.last_step);
        assert_eq!(before.last_order, after.last_order);
        // And each segment adds work.
        if i > 0 {
            assert!(before.steps > prev.steps, "bounce {i}: steps did not grow");
            assert!(before.residual_evals > prev.residual_evals);
            assert!(before.root_evals > prev.root_evals);
        }
        prev = *after;
    }
    // A system without roots evaluates none.
    let mut ida = decay_solver(1.0, &IdaOptions::default());
    ida.solve(1.0, false).unwrap();
    let s = ida.stats();
    assert!(s.steps > 0 && s.residual_evals > 0 && s.last_step > 0.0 && s.last_order > 0);
    assert_eq!(s.root_evals, 0);
}

#[test]
fn stats_add_keeps_latest_step() {
    let a = IdaStats {
        steps: 3,
        residual_evals: 10,
        last_step: 0.1,
        last_order: 2,
        ..Default::default()
    };
    let b = IdaStats {
        steps: 2,
        residual_evals: 5,
        last_step: 0.01,
        last_order: 1,
        ..Default::default()
    };
    let c = a + b;
    assert_eq!(
        (c.steps, c.residual_evals, c.last_step, c.last_order),
        (5, 15, 0.01, 1)
    );
    let mut d = a;
    d += IdaStats::default();
    assert_eq!(d, a);
}
