//! Solver stage, FFI: the linear algebra attached to IDA — SUNDIALS' dense matrix and LU, or,
//! for systems with a block structure, the coloured difference-quotient Jacobian callback, a
//! storage-less custom `SUNMatrix` handle and a custom `SUNLinearSolver` over the safe
//! block-diagonal LU (`block_lu.rs`). Part of the `ida` FFI module (`unsafe` allowed here, see
//! `ida.rs` for the invariants).

use super::*;

/// IDA Jacobian callback for systems with a [`super::BlockStructure`]: the iteration matrix
/// `∂F/∂y + c_j ∂F/∂y'` by difference quotients, perturbing the unknowns of all blocks of one
/// colour together, written into the zeroed diagonal blocks of the `BlockLu` (the SUNMatrix IDA passes is a handle without
/// storage, see `attach_linear_solver`). Entries outside the structure stay zero. Returns 0, 1 for a
/// recoverable residual failure (or a non-finite quotient), -1 for a fatal one, an invalid
/// structure or a caught panic.
///
/// Increments: `max(√ε · max(|h·y'_j|, atol_j/rtol), 1e3·ε·|y_j|)`: `√ε` of the step's
/// change of the unknown, or of `atol_j/rtol`, the size below which the tolerances count it
/// as zero — not of its value, and never below a thousand roundings of it. IDA's own dense
/// quotients use `max(√ε·max(|y_j|, |h·y'_j|), 1/w_j)` with the error weight
/// `1/w_j = rtol·|y_j| + atol_j`: a position's increment grows with its distance from the
/// origin (√ε·0.25 m = 4e-9 m for the top cube of a stack of three) and with rtol (1e-4 m at
/// rtol 1e-3), while contact forces change on the scale of the penetration (7e-10 m for a
/// steel cube on steel): the perturbed state lost the contact, the Jacobian held a secant
/// instead of the contact stiffness, and Newton failed on every other step. Measured
/// (`cargo run --release --example resting_stack`, BENCHMARKS.md): ten steel cubes stacked at
/// the default `k_red = 1`, 1 s at rtol 1e-6, 1,189 steps with 2 convergence failures, where
/// IDA's increments did not finish 1 s in 200 s; billiards16 at rtol 1e-3 0.47 s instead of 1.97 s.
#[allow(clippy::too_many_arguments)] // the C signature
pub(super) unsafe extern "C" fn jacobian_callback<S: DaeSystem>(
    t: f64,
    c_j: f64,
    yy: sys::N_Vector,
    yp: sys::N_Vector,
    rr: sys::N_Vector,
    _jac: sys::SUNMatrix,
    user_data: *mut c_void,
    tmp1: sys::N_Vector,
    _tmp2: sys::N_Vector,
    _tmp3: sys::N_Vector,
) -> c_int {
    let state = user_data.cast::<CallbackState<S>>();
    let outcome = catch_unwind(AssertUnwindSafe(|| {
        // SAFETY: as in residual_callback. yy and yp are IDA's current iterate, which IDA's own
        // difference quotients also perturb in place and restore; rr and tmp1 are distinct
        // vectors of length n; jac is the n × n dense matrix attached in attach_linear_solver
        // (column-major, leading dimension n); mem is the running IDA memory.
        let st = unsafe { &mut *state };
        let n = st.n;
        let mut hh = 0.0;
        let (y, ypv, r, rp) = unsafe {
            sys::IDAGetCurrentStep(st.mem, &mut hh);
            (
                slice::from_raw_parts_mut(sys::N_VGetArrayPointer(yy), n),
                slice::from_raw_parts_mut(sys::N_VGetArrayPointer(yp), n),
                slice::from_raw_parts(sys::N_VGetArrayPointer(rr), n),
                slice::from_raw_parts_mut(sys::N_VGetArrayPointer(tmp1), n),
            )
        };
        let Some(col) = st.colouring.as_mut() else {
            return -1;
        };
        if !st.system.jacobian_structure(&mut col.next) {
            // The structure is gone for now: one block, i.e. plain dense difference quotients.
            col.next.block_of.clear();
            col.next.block_of.resize(n, 0);
            col.next.n_blocks = 1;
            col.next.couplings.clear();
            col.next.analytic.clear();
        }
        // The colouring is rebuilt only when the structure changed (at events).
        let rebuilt = match col.refresh(n) {
            Ok(rebuilt) => rebuilt,
            Err(msg) => {
                st.fatal.get_or_insert((msg, t));
                return -1;
            }
        };
        if rebuilt {
            st.jac_parts.valid = false;
        }
        let mut conv_fails: c_long = 0;
        // SAFETY: mem is the running IDA memory.
        unsafe { sys::IDAGetNumNonlinSolvConvFails(st.mem, &mut conv_fails) };
        let jp = &mut st.jac_parts;
        // A matrix from the parts that Newton failed with (a convergence failure since the
        // last request) makes the next `penalty` matrices new ones, the penalty doubling
        // while that repeats and dropping back once such a matrix serves: on a scene whose
        // ∂F/∂y changes within a step (a light body carrying others) the parts would
        // otherwise cost a failed Newton iteration and a step cut by 4 per reuse.
        let failed = conv_fails != jp.conv_seen;
        jp.conv_seen = conv_fails;
        if jp.last_reused {
            if failed {
                jp.penalty = (jp.penalty * 2).clamp(MIN_PENALTY, MAX_PENALTY);
                jp.skip = jp.penalty;
            } else {
                jp.penalty = 0;
            }
        }
        jp.last_reused = false;
        if jp.enabled
            && jp.valid
            && jp.skip == 0
            && jp.conv_fails == conv_fails
            && st.block_lu.set_entries(&jp.dy, &jp.dyp, c_j)
        {
            // IDA asks again because c_j moved (a new step size, a failed error test): the
            // same ∂F/∂y with the new c_j ∂F/∂y', written over every entry of the unchanged
            // layout. IDA's modified Newton iteration uses an iteration matrix from an
            // earlier point anyway; after a convergence failure the next matrix is new.
            jp.reuses += 1;
            jp.last_reused = true;
            return 0;
        }
        jp.skip = jp.skip.saturating_sub(1);
        st.block_lu.layout(col, n, rebuilt);
        if col.any_analytic() {
            // The system's own columns first (the quotients below set other columns only).
            let args = JacobianArgs {
                t,
                c_j,
                h: hh,
                y,
                yp: ypv,
                zero_size: &st.zero_size,
            };
            let mut sink = LuSink {
                lu: &mut st.block_lu,
                bad: None,
            };
            let outcome = st.system.jacobian(&args, &mut sink);
            if let Some((i, d)) = sink.bad {
                record_non_finite(&mut st.non_finite, i, t, d);
                return 1;
            }
            if let Err(flag) = callback_flag(&mut st.fatal, t, outcome) {
                return flag;
            }
        }
        // The system's bounds on the increments (allocation only at the first Jacobian).
        let caps = &mut st.jac_caps;
        caps.clear();
        caps.resize(n, f64::INFINITY);
        let any_cap = st.system.increment_caps(
            &JacobianArgs {
                t,
                c_j,
                h: hh,
                y,
                yp: ypv,
                zero_size: &st.zero_size,
            },
            caps,
        );
        let saved = &mut st.jac_saved;
        saved.resize(n, (0.0, 0.0, 0.0));
        if col.n_colours() > 0 {
            match callback_flag(&mut st.fatal, t, st.system.begin_quotients(t, y, ypv)) {
                Ok(evaluated) => st.jac_residuals += u64::from(evaluated),
                Err(flag) => return flag,
            }
        }
        let changed = &mut st.jac_changed;
        changed.reserve(n.saturating_sub(changed.len()));
        for c in 0..col.n_colours() {
            for k in 0..col.width(c) {
                changed.clear();
                for &b in col.blocks_of_colour(c) {
                    if let Some(&j) = col.members(b).get(k) {
                        let (yj, ypj) = (y[j], ypv[j]);
                        let mut inc = dq_increment(yj, ypj, hh, st.zero_size[j]);
                        if any_cap {
                            inc = capped_increment(inc, st.jac_caps[j], yj);
                        }
                        saved[j] = (yj, ypj, inc);
                        y[j] += inc;
                        ypv[j] += c_j * inc;
                        changed.push(j);
                    }
                }
                st.jac_residuals += 1;
                let outcome = st.system.quotient_residual(t, y, ypv, rp, changed);
                for &b in col.blocks_of_colour(c) {
                    if let Some(&j) = col.members(b).get(k) {
                        (y[j], ypv[j], _) = saved[j];
                    }
                }
                if let Err(flag) = callback_flag(&mut st.fatal, t, outcome) {
                    return flag;
                }
                for &b in col.blocks_of_colour(c) {
                    let Some(&j) = col.members(b).get(k) else {
                        continue;
                    };
                    let inv = 1.0 / saved[j].2;
                    for blk in std::iter::once(b).chain(col.neighbours(b).iter().copied()) {
                        for &i in col.members(blk) {
                            let d = (rp[i] - r[i]) * inv;
                            if !d.is_finite() {
                                record_non_finite(&mut st.non_finite, i, t, d);
                                return 1;
                            }
                            st.block_lu.set(i, j, d);
                        }
                    }
                }
            }
        }
        let args = JacobianArgs {
            t,
            c_j,
            h: hh,
            y,
            yp: ypv,
            zero_size: &st.zero_size,
        };
        let parts = (&mut st.block_lu, &mut st.jac_parts);
        keep_parts(&mut st.system, parts, col, n, &args, conv_fails);
        0
    }));
    // SAFETY: the closure's borrow of the state has ended.
    unsafe { settle(state, t, outcome, "in the Jacobian: ") }
}

/// Matrices formed anew after the first failure of Newton's method with a matrix from the
/// parts, and the most after repeated ones (see `jacobian_callback`).
const MIN_PENALTY: u32 = 4;
const MAX_PENALTY: u32 = 1024;

/// After a Jacobian by difference quotients (in the block LU, not yet factored): keeps its
/// parts `∂F/∂y = J − c_j ∂F/∂y'` and `∂F/∂y'` (from [`DaeSystem::yp_jacobian`]) for the
/// matrices at the next values of `c_j`, and leaves the block LU holding `J` as it was.
fn keep_parts<S: DaeSystem>(
    system: &mut S,
    (lu, jp): (&mut BlockLu, &mut JacobianParts),
    col: &Colouring,
    n: usize,
    args: &JacobianArgs<'_>,
    conv_fails: c_long,
) {
    jp.valid = false;
    if !jp.enabled {
        return;
    }
    lu.entries(&mut jp.dy);
    lu.layout(col, n, false);
    let mut sink = LuSink { lu, bad: None };
    let available = matches!(system.yp_jacobian(args, &mut sink), Ok(true)) && sink.bad.is_none();
    lu.entries(&mut jp.dyp);
    // J back as it was (`dyp` is finite: the sink writes no run with a non-finite value).
    lu.set_entries(&jp.dy, &jp.dyp, 0.0);
    if !available {
        return;
    }
    for (a, d) in jp.dy.iter_mut().zip(&jp.dyp) {
        *a -= args.c_j * d;
    }
    jp.valid = true;
    jp.conv_fails = conv_fails;
}

/// The Jacobian callback's return flag for an `Err` of the system: 1 (recoverable: IDA
/// retries with a smaller step) or −1 with the message kept as the run's fatal error.
fn callback_flag<T>(
    fatal: &mut Option<(String, f64)>,
    t: f64,
    outcome: Result<T, ResidualError>,
) -> Result<T, c_int> {
    match outcome {
        Ok(x) => Ok(x),
        Err(ResidualError::Recoverable) => Err(1),
        Err(ResidualError::Fatal(msg)) => {
            fatal.get_or_insert((msg, t));
            Err(-1)
        }
    }
}

/// Writes the system's own Jacobian columns into the diagonal blocks, remembering the first
/// non-finite value instead.
struct LuSink<'a> {
    lu: &'a mut BlockLu,
    bad: Option<(usize, f64)>,
}

impl JacobianSink for LuSink<'_> {
    fn add(&mut self, i0: usize, j: usize, values: &[f64]) {
        if let Some(t) = values.iter().position(|v| !v.is_finite()) {
            self.bad.get_or_insert((i0 + t, values[t]));
        } else {
            self.lu.add_run(i0, j, values);
        }
    }
}

/// Matrix id of the storage-less handle: a custom one.
pub(super) unsafe extern "C" fn block_mat_id(_a: sys::SUNMatrix) -> sys::SUNMatrix_ID {
    sys::SUNMatrix_ID_SUNMATRIX_CUSTOM
}

/// `SUNMatZero` on the handle: nothing to do (the Jacobian callback lays out zeroed blocks).
pub(super) unsafe extern "C" fn block_mat_zero(_a: sys::SUNMatrix) -> sys::SUNErrCode {
    0
}

/// Frees the handle; it owns no storage.
pub(super) unsafe extern "C" fn block_mat_destroy(a: sys::SUNMatrix) {
    if !a.is_null() {
        // SAFETY: a was created by SUNMatNewEmpty with a null content.
        unsafe {
            (*a).content = ptr::null_mut();
            sys::SUNMatFreeEmpty(a);
        }
    }
}

/// Linear solver type: direct (matrix-based), like SUNDIALS' dense solver.
pub(super) unsafe extern "C" fn block_ls_type(
    _ls: sys::SUNLinearSolver,
) -> sys::SUNLinearSolver_Type {
    sys::SUNLinearSolver_Type_SUNLINEARSOLVER_DIRECT
}

/// Linear solver id: a custom one.
pub(super) unsafe extern "C" fn block_ls_id(_ls: sys::SUNLinearSolver) -> sys::SUNLinearSolver_ID {
    sys::SUNLinearSolver_ID_SUNLINEARSOLVER_CUSTOM
}

/// Factors the diagonal blocks (connected components of the last Jacobian's structure) that
/// the Jacobian callback filled. Returns 0, `SUNLS_LUFACT_FAIL` (recoverable: IDA retries with a
/// smaller step) for a singular block, -1 after a caught panic.
pub(super) unsafe extern "C" fn block_ls_setup<S: DaeSystem>(
    ls: sys::SUNLinearSolver,
    _a: sys::SUNMatrix,
) -> c_int {
    // SAFETY: the content of this solver is the CallbackState of the Ida that created it
    // (set in attach_linear_solver); IDA calls setup only from inside an IDA call, while no
    // Rust reference to the state is live, and never concurrently with another callback.
    let state = unsafe { (*ls).content.cast::<CallbackState<S>>() };
    let outcome = catch_unwind(AssertUnwindSafe(|| {
        // SAFETY: see above.
        let st = unsafe { &mut *state };
        match st.block_lu.factor() {
            Ok(()) => 0,
            Err(_) => sys::SUNLS_LUFACT_FAIL as c_int,
        }
    }));
    outcome.unwrap_or(-1)
}

/// Solves with the factors of `block_ls_setup`: `x = A⁻¹ b`.
pub(super) unsafe extern "C" fn block_ls_solve<S: DaeSystem>(
    ls: sys::SUNLinearSolver,
    _a: sys::SUNMatrix,
    x: sys::N_Vector,
    b: sys::N_Vector,
    _tol: f64,
) -> c_int {
    // SAFETY: as in block_ls_setup; x and b are serial vectors of length n (possibly the same).
    let state = unsafe { (*ls).content.cast::<CallbackState<S>>() };
    let outcome = catch_unwind(AssertUnwindSafe(|| {
        let st = unsafe { &mut *state };
        let n = st.n;
        let (xp, bp) = unsafe { (sys::N_VGetArrayPointer(x), sys::N_VGetArrayPointer(b)) };
        if xp != bp {
            // SAFETY: distinct serial arrays of length n.
            unsafe { ptr::copy_nonoverlapping(bp, xp, n) };
        }
        let xs = unsafe { slice::from_raw_parts_mut(xp, n) };
        st.block_lu.solve(xs);
        0
    }));
    outcome.unwrap_or(-1)
}

/// Frees the solver object; its content (the CallbackState) belongs to the Ida.
pub(super) unsafe extern "C" fn block_ls_free(ls: sys::SUNLinearSolver) -> sys::SUNErrCode {
    if !ls.is_null() {
        // SAFETY: ls was created by SUNLinSolNewEmpty; clearing the content keeps
        // SUNLinSolFreeEmpty from freeing memory it does not own.
        unsafe {
            (*ls).content = ptr::null_mut();
            sys::SUNLinSolFreeEmpty(ls);
        }
    }
    0
}

impl<S: DaeSystem> Ida<S> {
    /// Creates (once) the dense matrix and dense direct linear solver and attaches them to IDA.
    ///
    /// This is the single place to change for another linear solver (banded, sparse KLU,
    /// iterative) or to add a user Jacobian (`IDASetJacFn` must follow `IDASetLinearSolver`).
    /// It is called again after `IDAReInit`, which gives fresh linear-solver counters.
    pub(super) fn attach_linear_solver(&mut self) -> Result<(), IdaError> {
        let n = self.n as sys::sunindextype;
        // SAFETY: ctx, y and mem are valid (created in setup); mat/ls are null or valid.
        unsafe {
            let structured = (*self.state).colouring.is_some();
            if self.mat.is_null() && structured {
                // A handle without storage: the Jacobian goes straight into the diagonal
                // blocks of the BlockLu, so no n × n matrix is allocated or zeroed.
                let a = sys::SUNMatNewEmpty(self.ctx);
                if a.is_null() {
                    return Err(self.creation_error("SUNMatNewEmpty", 0));
                }
                let ops = &mut *(*a).ops;
                ops.getid = Some(block_mat_id);
                ops.zero = Some(block_mat_zero);
                ops.destroy = Some(block_mat_destroy);
                self.mat = a;
            }
            if self.mat.is_null() {
                self.mat = sys::SUNDenseMatrix(n, n, self.ctx);
                if self.mat.is_null() {
                    return Err(self.creation_error("SUNDenseMatrix", 0));
                }
            }
            if self.ls.is_null() && structured {
                // Block-diagonal LU over the connected components of the Jacobian structure.
                let ls = sys::SUNLinSolNewEmpty(self.ctx);
                if ls.is_null() {
                    return Err(self.creation_error("SUNLinSolNewEmpty", 0));
                }
                (*ls).content = self.state.cast();
                let ops = &mut *(*ls).ops;
                ops.gettype = Some(block_ls_type);
                ops.getid = Some(block_ls_id);
                ops.setup = Some(block_ls_setup::<S>);
                ops.solve = Some(block_ls_solve::<S>);
                ops.free = Some(block_ls_free);
                self.ls = ls;
            }
            if self.ls.is_null() {
                self.ls = sys::SUNLinSol_Dense(self.y, self.mat, self.ctx);
                if self.ls.is_null() {
                    return Err(self.creation_error("SUNLinSol_Dense", 0));
                }
            }
            let rc = sys::IDASetLinearSolver(self.mem, self.ls, self.mat);
            if rc != 0 {
                let message = self.take_sink();
                return Err(IdaError::Flag {
                    flag: rc,
                    name: lin_flag_name(rc),
                    t: self.t,
                    hint: "attaching the dense linear solver failed; this is a bug in the \
                           wrapper, please report it"
                        .to_string(),
                    message,
                });
            }
            if (*self.state).colouring.is_some() {
                self.check(
                    sys::IDASetJacFn(self.mem, Some(jacobian_callback::<S>)),
                    "IDASetJacFn",
                )?;
            }
        }
        Ok(())
    }
}
