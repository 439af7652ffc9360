//! Tests of the safe SUNDIALS IDA wrapper `modia3d::core::solver` against analytic or published
//! reference solutions, plus its failure paths (panics, NaN, bad arguments) and memory hygiene.

use modia3d::core::solver::*;

/// y' = -k y written as the implicit residual F = y' + k y.
struct Decay {
    k: f64,
}

impl DaeSystem for Decay {
    fn len(&self) -> usize {
        1
    }
    fn residual(
        &mut self,
        _t: f64,
        y: &[f64],
        yp: &[f64],
        res: &mut [f64],
    ) -> Result<(), ResidualError> {
        res[0] = yp[0] + self.k * y[0];
        Ok(())
    }
}

fn decay_solver(k: f64, opts: &IdaOptions) -> Ida<Decay> {
    Ida::new(Decay { k }, 0.0, &[1.0], &[-k], opts).expect("valid decay problem")
}

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

/// Point mass falling onto the ground h = 0: h' = v, v' = -g, root h with direction -1.
struct Ball {
    g: f64,
}

impl DaeSystem for Ball {
    fn len(&self) -> usize {
        2
    }
    fn residual(
        &mut self,
        _t: f64,
        y: &[f64],
        yp: &[f64],
        res: &mut [f64],
    ) -> Result<(), ResidualError> {
        res[0] = yp[0] - y[1];
        res[1] = yp[1] + self.g;
        Ok(())
    }
    fn num_roots(&self) -> usize {
        1
    }
    fn roots(&mut self, _t: f64, y: &[f64], _yp: &[f64], g: &mut [f64]) {
        g[0] = y[0];
    }
}

/// Simulates `bounces` impacts with restitution `e`; returns the impact times and the
/// statistics after every impact (taken right before and right after the re-initialisation).
fn bouncing_ball(bounces: usize, e: f64) -> (Vec<f64>, Vec<(IdaStats, IdaStats)>) {
    let g = 9.81;
    let opts = IdaOptions::default()
        .rtol(1e-10)
        .atol(1e-12)
        .root_directions(vec![-1]);
    let mut ida = Ida::new(Ball { g }, 0.0, &[1.0, 0.0], &[0.0, -g], &opts).unwrap();
    let mut times = Vec::new();
    let mut stats = Vec::new();
    while times.len() < bounces {
        match ida.solve(10.0, false).unwrap() {
            SolveStatus::Root { t } => {
                assert_eq!(ida.root_info(), &[-1]);
                times.push(t);
                let (h, v) = (ida.y()[0], ida.y()[1]);
                assert!(h.abs() < 1e-9, "height at impact {h}");
                let before = ida.stats();
                ida.reinit(t, &[h, -e * v], &[-e * v, -g]).unwrap();
                assert_eq!(ida.root_info(), &[0]);
                stats.push((before, ida.stats()));
            }
            other => panic!("expected an impact before t = 10 s, got {other:?}"),
        }
    }
    (times, stats)
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

/// Decay whose residual misbehaves once t passes `t_bad`.
struct Faulty {
    t_bad: f64,
    mode: Fault,
}

#[derive(Clone, Copy)]
enum Fault {
    Panic,
    Nan,
    Fatal,
}

impl DaeSystem for Faulty {
    fn len(&self) -> usize {
        1
    }
    fn residual(
        &mut self,
        t: f64,
        y: &[f64],
        yp: &[f64],
        res: &mut [f64],
    ) -> Result<(), ResidualError> {
        res[0] = yp[0] + y[0];
        if t > self.t_bad {
            match self.mode {
                Fault::Panic => panic!("boom: residual refused t = {t}"),
                Fault::Nan => res[0] = f64::NAN,
                Fault::Fatal => return Err(ResidualError::Fatal("state left the table".into())),
            }
        }
        Ok(())
    }
}

fn faulty(t_bad: f64, mode: Fault) -> Ida<Faulty> {
    Ida::new(
        Faulty { t_bad, mode },
        0.0,
        &[1.0],
        &[-1.0],
        &IdaOptions::default(),
    )
    .unwrap()
}

#[test]
fn panic_in_residual_becomes_an_error() {
    let mut ida = faulty(0.5, Fault::Panic);
    let err = ida.solve(1.0, false).unwrap_err();
    match &err {
        IdaError::Panic { message, t } => {
            assert!(message.contains("boom"), "payload lost: {message}");
            // The first residual call past 0.5 happens within one step (h < 0.2 at rtol 1e-6
            // for this decay) of the last accepted time.
            assert!(*t > 0.5 && *t < 0.7, "panic time {t}");
        }
        other => panic!("expected IdaError::Panic, got {other:?}"),
    }
    let text = err.to_string();
    assert!(text.contains("panicked") && text.contains("boom"), "{text}");
    // The solver stopped at the last accepted time and is still usable before 0.5.
    assert!(ida.t() <= 0.5 + 1e-12, "t = {}", ida.t());
    drop(ida);
}

/// Ball whose root function panics after the first evaluations past t = 0.2.
struct PanickingRoots(Ball);

impl DaeSystem for PanickingRoots {
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
        self.0.residual(t, y, yp, res)
    }
    fn num_roots(&self) -> usize {
        1
    }
    fn roots(&mut self, t: f64, y: &[f64], _yp: &[f64], g: &mut [f64]) {
        g[0] = y[0];
        if t > 0.2 {
            panic!("root function gave up at t = {t}");
        }
    }
}

#[test]
fn panic_in_roots_becomes_an_error() {
    let g = 9.81;
    let mut ida = Ida::new(
        PanickingRoots(Ball { g }),
        0.0,
        &[1.0, 0.0],
        &[0.0, -g],
        &IdaOptions::default(),
    )
    .unwrap();
    match ida.solve(1.0, false).unwrap_err() {
        IdaError::Panic { message, t } => {
            assert!(message.contains("in roots()") && message.contains("gave up"));
            assert!(t > 0.2 && t < 0.5, "t = {t}");
        }
        other => panic!("expected IdaError::Panic, got {other:?}"),
    }
}

#[test]
fn nan_residual_ends_with_an_error_naming_the_time() {
    let mut ida = faulty(0.3, Fault::Nan);
    let err = ida.solve(1.0, false).unwrap_err();
    match &err {
        IdaError::NonFiniteResidual {
            index, t, value, ..
        } => {
            assert_eq!(*index, 0);
            assert_eq!(value, "NaN");
            // IDA shrinks the step by 4x per retry, so the earliest NaN time ends up just past
            // 0.3; it can never be before 0.3, and never beyond one normal step.
            assert!(*t > 0.3 && *t < 0.3 + 0.05, "NaN time {t}");
        }
        other => panic!("expected NonFiniteResidual, got {other:?}"),
    }
    let text = err.to_string();
    assert!(
        text.contains("t = 0.3"),
        "message must name the time: {text}"
    );
    assert!(ida.t() <= 0.3 + 1e-12);
}

#[test]
fn fatal_residual_error_is_reported() {
    let mut ida = faulty(0.2, Fault::Fatal);
    match ida.solve(1.0, false).unwrap_err() {
        IdaError::ResidualFatal { message, t } => {
            assert_eq!(message, "state left the table");
            assert!(t > 0.2 && t < 0.4, "t = {t}");
        }
        other => panic!("expected ResidualFatal, got {other:?}"),
    }
}

#[test]
fn ida_failure_flag_carries_name_time_and_sundials_message() {
    let opts = IdaOptions::default().max_num_steps(5);
    let mut ida = decay_solver(1.0, &opts);
    match ida.solve(100.0, false).unwrap_err() {
        IdaError::Flag {
            flag,
            name,
            t,
            hint,
            message,
        } => {
            assert_eq!(flag, -1);
            assert_eq!(name, "IDA_TOO_MUCH_WORK");
            assert!(t > 0.0 && t < 100.0);
            assert!(hint.contains("max_num_steps"));
            // Captured by the wrapper's error handler instead of being printed.
            assert!(message.contains("mxstep"), "SUNDIALS message: {message}");
        }
        other => panic!("expected Flag, got {other:?}"),
    }
    // The solver stays usable: one more internal step continues from where it stopped.
    let t_fail = ida.t();
    let status = ida.solve(100.0, true).unwrap();
    assert!(status.t() > t_fail);
}

#[test]
fn stop_time_and_one_step_mode() {
    let mut ida = decay_solver(1.0, &IdaOptions::default());
    ida.set_stop_time(0.25).unwrap();
    assert_eq!(
        ida.solve(1.0, false).unwrap(),
        SolveStatus::StopTime { t: 0.25 }
    );
    assert!((ida.y()[0] - (-0.25_f64).exp()).abs() < 1e-6);
    let status = ida.solve(1.0, true).unwrap();
    assert!(matches!(status, SolveStatus::Reached { t } if t > 0.25 && t < 1.0));
    ida.set_max_step(Some(1e-3)).unwrap();
    // IDA applies the limit when it picks the next step size, so the step already chosen may
    // still be longer; every step after it must respect the limit.
    ida.solve(1.0, true).unwrap();
    for _ in 0..3 {
        let t0 = ida.t();
        ida.solve(1.0, true).unwrap();
        assert!(
            ida.t() - t0 <= 1e-3 * (1.0 + 1e-12),
            "step {}",
            ida.t() - t0
        );
    }
    ida.set_max_step(None).unwrap();
    ida.clear_stop_time().unwrap();
    ida.solve(2.0, false).unwrap();
    let sys = ida.into_system();
    assert_eq!(sys.k, 1.0);
}

#[test]
fn bad_arguments_are_errors_not_panics() {
    let ok = IdaOptions::default();
    let is_bad = |r: Result<Ida<Decay>, IdaError>| matches!(r, Err(IdaError::BadArgument(_)));
    let d = || Decay { k: 1.0 };
    assert!(is_bad(Ida::new(d(), 0.0, &[1.0, 2.0], &[0.0], &ok)));
    assert!(is_bad(Ida::new(d(), 0.0, &[1.0], &[], &ok)));
    assert!(is_bad(Ida::new(d(), 0.0, &[f64::NAN], &[0.0], &ok)));
    assert!(is_bad(Ida::new(d(), f64::INFINITY, &[1.0], &[0.0], &ok)));
    for rtol in [0.0, -1e-6, f64::NAN] {
        assert!(is_bad(Ida::new(
            d(),
            0.0,
            &[1.0],
            &[0.0],
            &ok.clone().rtol(rtol)
        )));
    }
    assert!(is_bad(Ida::new(
        d(),
        0.0,
        &[1.0],
        &[0.0],
        &ok.clone().atol(0.0)
    )));
    let v = ok.clone().atol_vector(vec![1e-8, 1e-8]);
    assert!(is_bad(Ida::new(d(), 0.0, &[1.0], &[0.0], &v)));
    let diff = ok.clone().differential(vec![true, false]);
    assert!(is_bad(Ida::new(d(), 0.0, &[1.0], &[0.0], &diff)));
    let dirs = ok.clone().root_directions(vec![-1]); // Decay has no roots
    assert!(is_bad(Ida::new(d(), 0.0, &[1.0], &[0.0], &dirs)));
    assert!(is_bad(Ida::new(
        d(),
        0.0,
        &[1.0],
        &[0.0],
        &ok.clone().max_num_steps(0)
    )));
    assert!(is_bad(Ida::new(
        d(),
        0.0,
        &[1.0],
        &[0.0],
        &ok.clone().max_step(Some(0.0))
    )));
    assert!(is_bad(Ida::new(
        d(),
        0.0,
        &[1.0],
        &[0.0],
        &ok.clone().init_step(Some(f64::NAN))
    )));

    let mut ida = decay_solver(1.0, &ok);
    let err = ida.reinit(0.0, &[1.0, 1.0], &[0.0]).unwrap_err();
    assert!(err.to_string().contains("length 2"), "{err}");
    assert!(matches!(
        ida.solve(f64::NAN, false),
        Err(IdaError::BadArgument(_))
    ));
    assert!(matches!(
        ida.set_max_step(Some(-1.0)),
        Err(IdaError::BadArgument(_))
    ));
    assert!(matches!(
        ida.set_stop_time(f64::NAN),
        Err(IdaError::BadArgument(_))
    ));
    assert!(matches!(ida.calc_ic_y(0.0), Err(IdaError::BadArgument(_))));
    // Still fully usable after rejected calls.
    ida.solve(1.0, false).unwrap();
    assert!((ida.y()[0] - (-1.0_f64).exp()).abs() < 1e-5);

    // A request IDA itself rejects (output time behind the current time in the same
    // direction it is already integrating) is an IDA_ILL_INPUT error with its message.
    match ida.solve(0.5, false) {
        Err(IdaError::Flag { name, message, .. }) => {
            assert_eq!(name, "IDA_ILL_INPUT");
            assert!(!message.is_empty());
        }
        other => panic!("expected IDA_ILL_INPUT, got {other:?}"),
    }
}

#[test]
fn solver_is_send() {
    fn assert_send<T: Send>() {}
    assert_send::<Ida<Decay>>();
}

/// Run under valgrind by hand to check for leaks on every path:
/// `valgrind --leak-check=full target/debug/deps/ida_wrapper-* create_solve_drop_10000_solvers`.
#[test]
fn create_solve_drop_10000_solvers() {
    let opts = IdaOptions::default().rtol(1e-4).atol(1e-6);
    let mut checksum = 0.0;
    for i in 0..10_000 {
        match i % 100 {
            // Error paths must free everything too.
            0 => {
                let mut ida = faulty(0.01, Fault::Nan);
                assert!(ida.solve(0.1, false).is_err());
            }
            1 => {
                assert!(Ida::new(
                    Decay { k: 1.0 },
                    0.0,
                    &[1.0],
                    &[0.0],
                    &opts.clone().rtol(-1.0)
                )
                .is_err());
            }
            2 => {
                let mut ida = decay_solver(1.0, &opts);
                ida.solve(0.1, false).unwrap();
                checksum += ida.into_system().k;
            }
            3 => {
                let (t, _) = bouncing_ball(1, 0.5);
                checksum += t[0];
            }
            _ => {
                let mut ida = decay_solver(1.0, &opts);
                ida.solve(0.1, false).unwrap();
                checksum += ida.y()[0];
            }
        }
    }
    assert!(checksum.is_finite() && checksum > 0.0);
}

/// Ten unit masses, each on a spring to ground (k = 1000 N/m) with light damping; masses 0–5
/// are also chained by springs (k_c = 2000 N/m), masses 6–9 are independent. Unknowns
/// `[x_i, v_i]` per mass, so the block of mass i is {2i, 2i + 1}.
struct SpringChain {
    /// Block structure to report: `None` = none (dense), `Some(true)` = the right one,
    /// `Some(false)` = a wrong one that omits the chain couplings.
    structure: Option<bool>,
}

impl SpringChain {
    const N: usize = 10;
    const CHAIN: usize = 6;
}

impl DaeSystem for SpringChain {
    fn len(&self) -> usize {
        2 * Self::N
    }
    fn residual(
        &mut self,
        _t: f64,
        y: &[f64],
        yp: &[f64],
        r: &mut [f64],
    ) -> Result<(), ResidualError> {
        let (k, kc, c) = (1000.0, 2000.0, 0.5);
        for i in 0..Self::N {
            let (x, v) = (y[2 * i], y[2 * i + 1]);
            let mut f = -k * x - c * v;
            if i < Self::CHAIN {
                if i > 0 {
                    f -= kc * (x - y[2 * (i - 1)]);
                }
                if i + 1 < Self::CHAIN {
                    f -= kc * (x - y[2 * (i + 1)]);
                }
            }
            r[2 * i] = yp[2 * i] - v;
            r[2 * i + 1] = yp[2 * i + 1] - f;
        }
        Ok(())
    }
    fn jacobian_structure(&mut self, s: &mut BlockStructure) -> bool {
        let Some(right) = self.structure else {
            return false;
        };
        s.block_of = (0..2 * Self::N).map(|i| i / 2).collect();
        s.n_blocks = Self::N;
        s.couplings = if right {
            (1..Self::CHAIN).map(|i| (i - 1, i)).collect()
        } else {
            vec![]
        };
        true
    }
}

fn run_chain(structure: Option<bool>) -> (Vec<f64>, IdaStats) {
    let n = 2 * SpringChain::N;
    let y0: Vec<f64> = (0..n)
        .map(|i| {
            if i % 2 == 0 {
                0.01 * (i / 2 + 1) as f64
            } else {
                0.0
            }
        })
        .collect();
    let mut sys = SpringChain { structure };
    let mut r = vec![0.0; n];
    let zeros = vec![0.0; n];
    // Consistent y'(0): the residual at y' = 0 is −(v, f), so y' = −r.
    sys.residual(0.0, &y0, &zeros, &mut r).unwrap();
    let yp0: Vec<f64> = r.iter().map(|x| -x).collect();
    let opts = IdaOptions::default().rtol(1e-9).atol(1e-12);
    let mut ida = Ida::new(sys, 0.0, &y0, &yp0, &opts).unwrap();
    ida.solve(2.0, false).unwrap();
    (ida.y().to_vec(), ida.stats())
}

#[test]
fn coloured_jacobian_matches_dense_and_costs_less() {
    let (y_dense, s_dense) = run_chain(None);
    let (y_col, s_col) = run_chain(Some(true));
    let (_, s_wrong) = run_chain(Some(false));
    println!("dense {s_dense:?}\ncoloured {s_col:?}\nwrong structure {s_wrong:?}");
    // Both are the same BDF method with Jacobians that agree to difference-quotient round-off
    // (the problem is linear): the step sequences match and the solutions agree far below the
    // global error of rtol 1e-9 (≈ 1e-8 of the 0.06 m amplitude).
    let diff = y_dense
        .iter()
        .zip(&y_col)
        .map(|(a, b)| (a - b).abs())
        .fold(0.0, f64::max);
    assert!(diff < 1e-10, "coloured vs dense: max |Δy| = {diff:e}");
    // Cost: the chain of six blocks needs three colours (distance-2 colouring of a path), the
    // four free blocks join them: 3 colours × 2 unknowns = 6 residuals per Jacobian, not 20.
    assert_eq!(
        s_dense.residual_evals_for_jacobian,
        20 * s_dense.jacobian_evals
    );
    assert_eq!(s_col.residual_evals_for_jacobian, 6 * s_col.jacobian_evals);
    // On this linear problem the coloured columns are bitwise those of the dense quotients
    // (each row sees one perturbed unknown), so IDA takes the very same steps.
    assert_eq!(
        (
            s_col.steps,
            s_col.nonlinear_iterations,
            s_col.error_test_failures
        ),
        (
            s_dense.steps,
            s_dense.nonlinear_iterations,
            s_dense.error_test_failures
        )
    );
    // The check can fail: a structure that omits the chain couplings leaves those Jacobian
    // entries zero; the modified Newton iteration then converges more slowly (measured: 10 %
    // more iterations and steps), so the run differs.
    assert!(
        s_wrong.nonlinear_iterations > s_dense.nonlinear_iterations + s_dense.steps / 20,
        "a wrong structure should cost Newton iterations: {} vs {}",
        s_wrong.nonlinear_iterations,
        s_dense.nonlinear_iterations
    );
}

/// The spring chain whose `jacobian_structure` misbehaves after the set-up call: it panics, or
/// it reports an unknown in a block that does not exist.
struct BadStructure {
    calls: usize,
    panic: bool,
}

impl DaeSystem for BadStructure {
    fn len(&self) -> usize {
        SpringChain { structure: None }.len()
    }
    fn residual(
        &mut self,
        t: f64,
        y: &[f64],
        yp: &[f64],
        r: &mut [f64],
    ) -> Result<(), ResidualError> {
        SpringChain { structure: None }.residual(t, y, yp, r)
    }
    fn jacobian_structure(&mut self, s: &mut BlockStructure) -> bool {
        self.calls += 1;
        let ok = SpringChain {
            structure: Some(true),
        }
        .jacobian_structure(s);
        if self.calls > 1 {
            if self.panic {
                panic!("structure gave up");
            }
            s.block_of[3] = 99;
        }
        ok
    }
}

#[test]
fn misbehaving_jacobian_structure_is_an_error_not_a_crash() {
    let n = 2 * SpringChain::N;
    let y0: Vec<f64> = (0..n).map(|i| if i == 0 { 0.01 } else { 0.0 }).collect();
    let mut yp0 = vec![0.0; n];
    yp0[1] = -10.0; // −k x of the first mass; the rest starts at rest
    for panic in [true, false] {
        let sys = BadStructure { calls: 0, panic };
        let mut ida = Ida::new(sys, 0.0, &y0, &yp0, &IdaOptions::default()).unwrap();
        let err = ida.solve(1.0, false).unwrap_err();
        let text = err.to_string();
        match (panic, &err) {
            (true, IdaError::Panic { message, .. }) => {
                assert!(
                    message.contains("in the Jacobian") && message.contains("gave up"),
                    "{text}"
                );
            }
            (false, IdaError::ResidualFatal { .. }) => {
                assert!(text.contains("unknown 3 is in block 99"), "{text}");
            }
            _ => panic!("unexpected error for panic = {panic}: {err:?}"),
        }
    }
}
