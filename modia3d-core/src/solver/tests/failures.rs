//! Failure paths (panics, NaN, bad arguments), memory hygiene and the coloured Jacobian.

use super::*;

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
    /// `Err(Recoverable)` for the first `n` residual calls past `t_bad`.
    Recoverable(u32),
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
                Fault::Recoverable(0) => {}
                Fault::Recoverable(n) => {
                    self.mode = Fault::Recoverable(n - 1);
                    return Err(ResidualError::Recoverable);
                }
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

/// A recoverable residual failure makes IDA retry with a smaller step instead of stopping: three
/// refusals past t = 0.5 s, and the run still reaches t = 1 s with y = e^-t to the tolerance
/// (rtol 1e-6, atol 1e-8 default: 1e-5 leaves room for the global error of a few hundred steps).
#[test]
fn recoverable_residual_error_retries_with_a_smaller_step() {
    let mut ida = faulty(0.5, Fault::Recoverable(3));
    let status = ida.solve(1.0, false).unwrap();
    assert!(
        matches!(status, SolveStatus::Reached { t } if t == 1.0),
        "{status:?}"
    );
    let err = (ida.y()[0] - (-1.0f64).exp()).abs();
    assert!(err < 1e-5, "|y(1) - e^-1| = {err:e}");
    assert!(
        matches!(ida.system().mode, Fault::Recoverable(0)),
        "all three refusals were seen"
    );
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
/// `valgrind --leak-check=full target/debug/deps/modia3d_core-* create_solve_drop_10000_solvers`.
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
    let mut sys = SpringChain { structure };
    let (y0, yp0) = chain_start(&mut sys);
    let opts = IdaOptions::default().rtol(1e-9).atol(1e-12);
    let mut ida = Ida::new(sys, 0.0, &y0, &yp0, &opts).unwrap();
    ida.solve(2.0, false).unwrap();
    (ida.y().to_vec(), ida.stats())
}

/// The spring chain's initial state (masses displaced by 0.01·(i + 1) m, at rest) and its
/// consistent `y'(0)`: the residual at `y' = 0` is `−(v, f)`, so `y' = −r`.
fn chain_start(sys: &mut SpringChain) -> (Vec<f64>, Vec<f64>) {
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
    let mut r = vec![0.0; n];
    let zeros = vec![0.0; n];
    sys.residual(0.0, &y0, &zeros, &mut r).unwrap();
    (y0, r.iter().map(|x| -x).collect())
}

/// The chain's exact state at `t`: the system is linear, `y' = A y` with `A`'s column `j`
/// the residual's response to `e_j` (`y' = −r(y = e_j, y' = 0)`), so `y(t) = exp(A t) y(0)`
/// (nalgebra's Padé matrix exponential, ~1e-12 relative here: ‖A t‖ ≈ 1e4).
fn chain_exact(t: f64) -> Vec<f64> {
    let mut sys = SpringChain { structure: None };
    let n = 2 * SpringChain::N;
    let (y0, _) = chain_start(&mut sys);
    let mut a = nalgebra::DMatrix::<f64>::zeros(n, n);
    let (mut e, zeros, mut r) = (vec![0.0; n], vec![0.0; n], vec![0.0; n]);
    for j in 0..n {
        e.fill(0.0);
        e[j] = 1.0;
        sys.residual(0.0, &e, &zeros, &mut r).unwrap();
        for i in 0..n {
            a[(i, j)] = -r[i];
        }
    }
    let y = (a * t).exp() * nalgebra::DVector::from_vec(y0);
    y.iter().copied().collect()
}

#[test]
fn coloured_jacobian_matches_dense_and_costs_less() {
    let (y_dense, s_dense) = run_chain(None);
    let (y_col, s_col) = run_chain(Some(true));
    let (_, s_wrong) = run_chain(Some(false));
    println!("dense {s_dense:?}\ncoloured {s_col:?}\nwrong structure {s_wrong:?}");
    // Both are the same BDF method; the Jacobians agree to difference-quotient error (the
    // problem is linear, but the coloured path's increments are √ε·atol/rtol where IDA's are
    // 1/w_j, so the round-off differs, and with it IDA's choices of step and order). So each
    // run is checked against the exact solution, not against the other's bits. IDA bounds the
    // local error (rtol 1e-9 of the 0.06 m amplitude, 6e-11 per step); over ~4,400 steps and
    // ten periods the phase error accumulates coherently to ~2.6e-7. Bound 5e-7, twice that;
    // measured 2.77e-7 (dense), 1.86e-7 (coloured; 2.75e-7 with a division per pivot in the
    // block LU's back substitution), and an rtol 1e-12 run within 9e-10 of
    // the exact solution (so the reference is not what limits). The two runs agree far
    // better than either with the exact solution (3.5e-9) because they share the phase error,
    // which is why their difference is no measure of either's accuracy.
    let exact = chain_exact(2.0);
    let err = |y: &[f64]| {
        y.iter()
            .zip(&exact)
            .map(|(a, b)| (a - b).abs())
            .fold(0.0, f64::max)
    };
    let (e_dense, e_col) = (err(&y_dense), err(&y_col));
    println!("error against exp(A t) y0: dense {e_dense:e}, coloured {e_col:e}");
    assert!(e_dense < 5e-7, "dense: max |Δy| = {e_dense:e}");
    assert!(e_col < 5e-7, "coloured: max |Δy| = {e_col:e}");
    // The same method, so about the same work; not the same steps to the last one: the
    // rounding of the linear solve moves IDA's step and order choices (measured 4,426 against
    // 4,409 with a division per pivot in the back substitution, 4,607 since it multiplies by
    // reciprocals). 10 %: a Jacobian wrong enough to matter costs more than that.
    let close = |a: u64, b: u64| (a as f64 - b as f64).abs() <= 0.1 * b as f64;
    assert!(
        close(s_col.steps, s_dense.steps)
            && close(s_col.nonlinear_iterations, s_dense.nonlinear_iterations),
        "coloured {s_col:?} vs dense {s_dense:?}"
    );
    // Cost: the chain of six blocks needs three colours (distance-2 colouring of a path), the
    // four free blocks join them: 3 colours × 2 unknowns = 6 residuals per Jacobian, not 20.
    assert_eq!(
        s_dense.residual_evals_for_jacobian,
        20 * s_dense.jacobian_evals
    );
    assert_eq!(s_col.residual_evals_for_jacobian, 6 * s_col.jacobian_evals);
    // The colouring follows the reported structure: without the chain couplings all ten blocks
    // share one colour (2 residuals per Jacobian), and the Jacobian lacks those entries. (Newton
    // still converges here: measured 5,085 iterations against 5,094 with the right structure;
    // before the increments followed atol/rtol it needed 10 % more.)
    assert_eq!(
        s_wrong.residual_evals_for_jacobian,
        2 * s_wrong.jacobian_evals
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
