//! Solver stage: the only FFI module of the crate — the safe wrapper over SUNDIALS IDA.
//!
//! This module (this file and its children `ida/callbacks.rs` — residual and root callbacks,
//! error handler — and `ida/linear.rs` — linear solver, Jacobian callback, matrix handle) is the
//! only part of `modia3d-core` that contains `unsafe`. It may touch the `sundials-sys`
//! bindings, the standard library and the plain-data types of the sibling modules
//! ([`super::IdaOptions`], [`super::IdaStats`], [`super::IdaError`]); nothing else in the crate
//! calls C.
//!
//! Invariants that make the safe API sound:
//! * [`Ida`] owns every SUNDIALS object (context, vectors, matrix, linear solver, IDA memory)
//!   through raw pointers that are either null or valid, and frees them exactly once
//!   (`free_ffi`, called by `Drop` and `into_system`).
//! * The system lives in a heap block (`CallbackState`) created with `Box::into_raw`, whose
//!   address is IDA's user data. Rust references into it are only created while no IDA call is
//!   running (they borrow `self`), and the callbacks create theirs only for the duration of the
//!   callback, so they never alias.
//! * Callbacks never unwind into C: each wraps the user code in `catch_unwind`, stores what
//!   happened in the `CallbackState`, and returns a SUNDIALS status code.
//! * SUNDIALS never prints: its error handlers are replaced by one that appends the message to an
//!   `ErrorSink` read after each call, and warnings go to the null device.

use std::any::Any;
use std::ffi::{c_char, c_int, c_long, c_void, CStr};
use std::panic::{catch_unwind, AssertUnwindSafe};
use std::ptr;
use std::slice;

use sundials_sys as sys;

use super::args::{bad, check_finite, check_state, validate};
use super::block_lu::BlockLu;
use super::colouring::Colouring;
use super::error::flag_hint;
use super::{
    capped_increment, dq_increment, Atol, DaeSystem, IdaError, IdaOptions, IdaStats, JacobianArgs,
    JacobianSink, ResidualError, SolveStatus,
};

mod callbacks;
mod linear;
use callbacks::*;

/// Longest SUNDIALS message text kept per call (bytes); later messages are dropped.
const MAX_SINK_LEN: usize = 4096;

/// What the callbacks share with the wrapper: the system and what went wrong inside it.
struct CallbackState<S> {
    system: S,
    n: usize,
    n_roots: usize,
    /// Panic message and time of the first panic in the current call.
    panic: Option<(String, f64)>,
    /// Message and time of the first fatal residual error in the current call.
    fatal: Option<(String, f64)>,
    /// Earliest (component, time, value text) at which the residual was non-finite in the
    /// current call.
    non_finite: Option<(usize, f64, &'static str)>,
    /// IDA memory (for the error weights and step size in the Jacobian callback).
    mem: *mut c_void,
    /// Coloured difference-quotient Jacobian, when the system reports a block structure.
    colouring: Option<Colouring>,
    /// Residual evaluations spent on coloured Jacobians in the current segment.
    jac_residuals: u64,
    /// Saved `(y_j, y'_j, increment)` of the perturbed unknowns (len n once used).
    jac_saved: Vec<(f64, f64, f64)>,
    /// Bounds on the quotients' increments from `DaeSystem::increment_caps` (len n).
    jac_caps: Vec<f64>,
    /// The unknowns perturbed by the current difference quotient (capacity n after the
    /// first Jacobian: no allocation afterwards).
    jac_changed: Vec<usize>,
    /// `atol_j / rtol` [unit of y_j] per unknown: the size below which it counts as zero,
    /// which sets the difference-quotient increments (`ida/linear.rs`).
    zero_size: Vec<f64>,
    /// Relative tolerance (for the error weights of [`DaeSystem::error_weight_factors`]).
    rtol: f64,
    /// Scratch for the factors of the error weights (len n once used).
    ewt_factor: Vec<f64>,
    /// Factors of the block-diagonal iteration matrix (with a colouring only).
    block_lu: BlockLu,
    /// The parts `∂F/∂y` and `∂F/∂y'` of the last iteration matrix formed by difference
    /// quotients, in the block LU's entry order, for matrices at a new `c_j` (`ida/linear.rs`).
    jac_parts: JacobianParts,
}

/// See [`CallbackState::jac_parts`].
#[derive(Default)]
struct JacobianParts {
    dy: Vec<f64>,
    dyp: Vec<f64>,
    /// The parts belong to the current structure and segment.
    valid: bool,
    /// IDA's count of nonlinear convergence failures when they were formed.
    conv_fails: c_long,
    /// Matrices formed from the parts in the current segment.
    reuses: u64,
    /// Reuse is on (`IdaOptions::jacobian_reuse`).
    enabled: bool,
    /// IDA's count of convergence failures at the last request, whether the last matrix came
    /// from the parts, the matrices still to form anew and the next such penalty.
    conv_seen: c_long,
    last_reused: bool,
    skip: u32,
    penalty: u32,
}

impl<S> CallbackState<S> {
    fn clear(&mut self) {
        self.panic = None;
        self.fatal = None;
        self.non_finite = None;
    }
}

/// Collects the messages SUNDIALS passes to the error handler during one call.
#[derive(Default)]
struct ErrorSink {
    text: String,
}

/// The IDA integrator for a [`DaeSystem`].
///
/// Owns the SUNDIALS context, the solution vectors, the dense matrix and linear solver, and the
/// IDA memory; dropping it frees all of them. Statistics accumulate over [`Ida::reinit`].
pub(crate) struct Ida<S: DaeSystem> {
    ctx: sys::SUNContext,
    mem: *mut c_void,
    /// Current solution y (also the output vector of IDASolve).
    y: sys::N_Vector,
    /// Current derivative y'.
    yp: sys::N_Vector,
    /// Differential (1) / algebraic (0) flags for IDASetId.
    id: sys::N_Vector,
    /// Scratch output of `IDAGetDky` ([`Ida::interpolate`]).
    dky: sys::N_Vector,
    /// Vector absolute tolerance, or null for a scalar one.
    atol: sys::N_Vector,
    mat: sys::SUNMatrix,
    ls: sys::SUNLinearSolver,
    state: *mut CallbackState<S>,
    sink: *mut ErrorSink,
    n: usize,
    t: f64,
    root_info: Vec<i32>,
    /// Statistics of the segments before the last re-initialisation.
    base_stats: IdaStats,
}

// SAFETY: all SUNDIALS objects are owned exclusively by this value and reached only through it;
// serial SUNDIALS keeps no thread-local or global state tied to them, so moving the whole solver
// to another thread is sound when the system itself may move.
unsafe impl<S: DaeSystem + Send> Send for Ida<S> {}

impl<S: DaeSystem> Ida<S> {
    /// Creates the integrator for `system` starting at time `t0` \[s\] with y(t0) = `y0` and
    /// y'(t0) = `yp0` (both of length `system.len()`).
    ///
    /// The initial values need not be consistent if [`Ida::calc_ic_ya_ydp`] or
    /// [`Ida::calc_ic_y`] is called before the first [`Ida::solve`]. Invalid arguments return
    /// [`IdaError::BadArgument`] (the system is dropped).
    pub(crate) fn new(
        system: S,
        t0: f64,
        y0: &[f64],
        yp0: &[f64],
        opts: &IdaOptions,
    ) -> Result<Self, IdaError> {
        let n = system.len();
        let n_roots = system.num_roots();
        validate(n, n_roots, t0, y0, yp0, opts)?;
        let state = Box::into_raw(Box::new(CallbackState {
            system,
            n,
            n_roots,
            panic: None,
            fatal: None,
            non_finite: None,
            mem: ptr::null_mut(),
            colouring: None,
            jac_residuals: 0,
            jac_saved: Vec::new(),
            jac_caps: Vec::new(),
            jac_changed: Vec::new(),
            zero_size: Vec::new(),
            rtol: 0.0,
            ewt_factor: Vec::new(),
            block_lu: BlockLu::new(opts.dense_lu),
            jac_parts: JacobianParts::default(),
        }));
        let sink = Box::into_raw(Box::<ErrorSink>::default());
        let mut ida = Ida {
            ctx: ptr::null_mut(),
            mem: ptr::null_mut(),
            y: ptr::null_mut(),
            yp: ptr::null_mut(),
            id: ptr::null_mut(),
            dky: ptr::null_mut(),
            atol: ptr::null_mut(),
            mat: ptr::null_mut(),
            ls: ptr::null_mut(),
            state,
            sink,
            n,
            t: t0,
            root_info: vec![0; n_roots],
            base_stats: IdaStats::default(),
        };
        // On error `ida` is dropped here, which frees whatever was created so far.
        ida.setup(t0, y0, yp0, opts)?;
        Ok(ida)
    }

    /// Creates all SUNDIALS objects and applies `opts` (already validated).
    fn setup(
        &mut self,
        t0: f64,
        y0: &[f64],
        yp0: &[f64],
        opts: &IdaOptions,
    ) -> Result<(), IdaError> {
        // SAFETY: every pointer passed below was just created and checked for null; slices have
        // length n (validated).
        unsafe {
            let mut ctx: sys::SUNContext = ptr::null_mut();
            let rc = sys::SUNContext_Create(sys::SUN_COMM_NULL, &mut ctx);
            if rc != 0 || ctx.is_null() {
                return Err(self.creation_error("SUNContext_Create", rc));
            }
            self.ctx = ctx;
            sys::SUNContext_ClearErrHandlers(ctx);
            sys::SUNContext_PushErrHandler(ctx, Some(error_handler), self.sink.cast());
            self.silence_warnings();

            self.y = self.new_vector(y0)?;
            self.yp = self.new_vector(yp0)?;
            let id: Vec<f64> = match &opts.differential {
                Some(d) => d.iter().map(|&b| if b { 1.0 } else { 0.0 }).collect(),
                None => vec![1.0; self.n],
            };
            self.id = self.new_vector(&id)?;
            self.dky = self.new_vector(y0)?;

            self.mem = sys::IDACreate(ctx);
            if self.mem.is_null() {
                return Err(self.creation_error("IDACreate", 0));
            }
            let mem = self.mem;
            self.check(
                sys::IDAInit(mem, Some(residual_callback::<S>), t0, self.y, self.yp),
                "IDAInit",
            )?;
            (*self.state).zero_size = match &opts.atol {
                Atol::Scalar(a) => vec![a / opts.rtol; self.n],
                Atol::Vector(v) => v.iter().map(|a| a / opts.rtol).collect(),
            };
            match &opts.atol {
                Atol::Scalar(a) => {
                    self.check(sys::IDASStolerances(mem, opts.rtol, *a), "IDASStolerances")?
                }
                Atol::Vector(v) => {
                    self.atol = self.new_vector(v)?;
                    self.check(
                        sys::IDASVtolerances(mem, opts.rtol, self.atol),
                        "IDASVtolerances",
                    )?;
                }
            }
            self.check(
                sys::IDASetUserData(mem, self.state.cast()),
                "IDASetUserData",
            )?;
            (*self.state).rtol = opts.rtol;
            if (*self.state).system.has_error_weight_factors() {
                (*self.state).ewt_factor = vec![1.0; self.n];
                self.check(
                    sys::IDAWFtolerances(mem, Some(ewt_callback::<S>)),
                    "IDAWFtolerances",
                )?;
            }
            self.check(sys::IDASetId(mem, self.id), "IDASetId")?;
            if opts.suppress_algebraic_error {
                self.check(sys::IDASetSuppressAlg(mem, 1), "IDASetSuppressAlg")?;
            }
            self.check(
                sys::IDASetMaxNumSteps(mem, opts.max_num_steps as c_long),
                "IDASetMaxNumSteps",
            )?;
            if let Some(h) = opts.max_step {
                self.check(sys::IDASetMaxStep(mem, h), "IDASetMaxStep")?;
            }
            if let Some(h) = opts.init_step {
                self.check(sys::IDASetInitStep(mem, h), "IDASetInitStep")?;
            }
            if let Some(c) = opts.nonlinear_convergence_coefficient {
                self.check(sys::IDASetNonlinConvCoef(mem, c), "IDASetNonlinConvCoef")?;
            }
            if let Some(k) = opts.max_order {
                self.check(sys::IDASetMaxOrd(mem, k as c_int), "IDASetMaxOrd")?;
            }
            (*self.state).jac_parts.enabled = opts.jacobian_reuse;
            if opts.structured_jacobian {
                let st = &mut *self.state;
                let mut colouring = Colouring::default();
                if st.system.jacobian_structure(&mut colouring.structure) {
                    colouring.update(self.n).map_err(bad)?;
                    st.colouring = Some(colouring);
                }
            }
            (*self.state).mem = mem;
            self.attach_linear_solver()?;
            let n_roots = self.root_info.len();
            if n_roots > 0 {
                self.check(
                    sys::IDARootInit(mem, n_roots as c_int, Some(root_callback::<S>)),
                    "IDARootInit",
                )?;
                if let Some(dirs) = &opts.root_directions {
                    let mut dirs: Vec<c_int> = dirs.iter().map(|&d| d as c_int).collect();
                    // IDA copies the directions into its own array.
                    self.check(
                        sys::IDASetRootDirection(mem, dirs.as_mut_ptr()),
                        "IDASetRootDirection",
                    )?;
                }
                // A root function that is exactly zero at the start (e.g. right after an impact)
                // is normal for event handling; do not warn about it.
                self.check(
                    sys::IDASetNoInactiveRootWarn(mem),
                    "IDASetNoInactiveRootWarn",
                )?;
            }
        }
        Ok(())
    }

    /// Sends SUNDIALS warnings (which would go to stdout) to the null device.
    fn silence_warnings(&mut self) {
        #[cfg(unix)]
        // SAFETY: ctx is valid; the logger belongs to it and copies the file name.
        unsafe {
            let mut logger: sys::SUNLogger = ptr::null_mut();
            if sys::SUNContext_GetLogger(self.ctx, &mut logger) == 0 && !logger.is_null() {
                sys::SUNLogger_SetWarningFilename(logger, c"/dev/null".as_ptr());
            }
        }
    }

    /// A new serial vector holding `values` (length n).
    fn new_vector(&mut self, values: &[f64]) -> Result<sys::N_Vector, IdaError> {
        debug_assert_eq!(values.len(), self.n);
        // SAFETY: ctx is valid; the new vector has n entries.
        unsafe {
            let v = sys::N_VNew_Serial(self.n as sys::sunindextype, self.ctx);
            if v.is_null() {
                return Err(self.creation_error("N_VNew_Serial", 0));
            }
            slice::from_raw_parts_mut(sys::N_VGetArrayPointer(v), self.n).copy_from_slice(values);
            Ok(v)
        }
    }

    fn creation_error(&mut self, what: &str, rc: c_int) -> IdaError {
        let message = self.take_sink();
        IdaError::Flag {
            flag: if rc != 0 { rc } else { sys::IDA_MEM_FAIL },
            name: format!("{what} failed"),
            t: self.t,
            hint: format!(
                "SUNDIALS could not create an object ({what}); the system may be out of memory"
            ),
            message,
        }
    }

    fn take_sink(&mut self) -> String {
        // SAFETY: sink is valid for the lifetime of self and not borrowed elsewhere.
        unsafe { std::mem::take(&mut (*self.sink).text) }
    }

    fn state_mut(&mut self) -> &mut CallbackState<S> {
        // SAFETY: state is valid until Drop/into_system, and borrowing self mutably ensures no
        // IDA call (hence no callback) is running.
        unsafe { &mut *self.state }
    }

    fn state_ref(&self) -> &CallbackState<S> {
        // SAFETY: as for state_mut.
        unsafe { &*self.state }
    }

    /// Clears what the callbacks and the error handler recorded before a new IDA call.
    fn begin_call(&mut self) {
        self.state_mut().clear();
        self.take_sink();
    }

    /// Maps a non-success return code of the IDA call `what` to an error.
    fn check(&mut self, rc: c_int, what: &str) -> Result<(), IdaError> {
        if rc >= 0 {
            return Ok(());
        }
        let mut err = self.failure(rc);
        if let IdaError::Flag { hint, .. } = &mut err {
            *hint = format!("{what} failed: {hint}");
        }
        Err(err)
    }

    /// The error for failure flag `rc`: a caught panic or fatal residual error wins over a
    /// non-finite residual, which wins over the plain IDA flag.
    fn failure(&mut self, rc: c_int) -> IdaError {
        let message = self.take_sink();
        let t = self.t;
        let st = self.state_mut();
        if let Some((message, t)) = st.panic.take() {
            return IdaError::Panic { message, t };
        }
        if let Some((message, t)) = st.fatal.take() {
            return IdaError::ResidualFatal { message, t };
        }
        if let Some((index, t, value)) = st.non_finite.take() {
            return IdaError::NonFiniteResidual {
                index,
                t,
                value: value.to_string(),
                flag_name: flag_name(rc),
            };
        }
        IdaError::Flag {
            flag: rc,
            name: flag_name(rc),
            t,
            hint: flag_hint(rc).to_string(),
            message,
        }
    }

    fn calc_ic(&mut self, icopt: c_int, t_out1: f64) -> Result<(), IdaError> {
        check_finite("t_out1", t_out1)?;
        if t_out1 == self.t {
            return Err(bad(format!(
                "t_out1 = {t_out1} s equals the current time; pass the first output time, which \
                 only sets the direction and scale of the initial-condition search"
            )));
        }
        self.begin_call();
        // SAFETY: mem, y, yp are valid; callbacks get the state through user data.
        let rc = unsafe { sys::IDACalcIC(self.mem, icopt, t_out1) };
        if rc < 0 {
            return Err(self.failure(rc));
        }
        // SAFETY: y and yp are valid vectors of length n.
        let rc = unsafe { sys::IDAGetConsistentIC(self.mem, self.y, self.yp) };
        self.check(rc, "IDAGetConsistentIC")
    }

    /// `IDACalcIC(IDA_YA_YDP_INIT)`: given the differential components of y (see
    /// [`IdaOptions::differential`]; `None` means all differential), computes the algebraic
    /// components of y and all of y' so that F = 0 at the current time. `t_out1` \[s\] is the
    /// first output time (it sets the direction and scale of the search). Afterwards
    /// [`Ida::y`]/[`Ida::yp`] hold the consistent values.
    pub(crate) fn calc_ic_ya_ydp(&mut self, t_out1: f64) -> Result<(), IdaError> {
        self.calc_ic(sys::IDA_YA_YDP_INIT, t_out1)
    }

    /// `IDACalcIC(IDA_Y_INIT)`: computes all of y given y' at the current time; `t_out1` \[s\] as
    /// for [`Ida::calc_ic_ya_ydp`].
    pub(crate) fn calc_ic_y(&mut self, t_out1: f64) -> Result<(), IdaError> {
        self.calc_ic(sys::IDA_Y_INIT, t_out1)
    }

    /// Sets a time \[s\] past which IDA must not step (`IDASetStopTime`); `solve` then returns
    /// [`SolveStatus::StopTime`] there. The stop time is cleared once it is reached.
    pub(crate) fn set_stop_time(&mut self, t_stop: f64) -> Result<(), IdaError> {
        check_finite("t_stop", t_stop)?;
        self.begin_call();
        // SAFETY: mem is valid.
        let rc = unsafe { sys::IDASetStopTime(self.mem, t_stop) };
        self.check(rc, "IDASetStopTime")
    }

    /// Sets the first step of the next integration start \[s\] (`IDASetInitStep`; 0: IDA
    /// estimates it from `y'`). It holds for every later `reinit` until set again.
    pub(crate) fn set_init_step(&mut self, h: f64) -> Result<(), IdaError> {
        check_finite("init_step", h)?;
        self.begin_call();
        // SAFETY: mem is valid.
        let rc = unsafe { sys::IDASetInitStep(self.mem, h) };
        self.check(rc, "IDASetInitStep")
    }

    /// Removes the stop time (`IDAClearStopTime`).
    pub(crate) fn clear_stop_time(&mut self) -> Result<(), IdaError> {
        self.begin_call();
        // SAFETY: mem is valid.
        let rc = unsafe { sys::IDAClearStopTime(self.mem) };
        self.check(rc, "IDAClearStopTime")
    }

    /// Sets the largest step size \[s\] (`None` = unlimited).
    pub(crate) fn set_max_step(&mut self, h: Option<f64>) -> Result<(), IdaError> {
        let h = match h {
            Some(h) if h.is_finite() && h > 0.0 => h,
            Some(h) => {
                return Err(bad(format!(
                    "max_step = {h} s must be finite and > 0 (or None)"
                )))
            }
            None => 0.0, // IDA's code for "no limit"
        };
        self.begin_call();
        // SAFETY: mem is valid.
        let rc = unsafe { sys::IDASetMaxStep(self.mem, h) };
        self.check(rc, "IDASetMaxStep")
    }

    /// Integrates towards `t_out` \[s\] (`IDASolve`): in `IDA_NORMAL` mode it returns the
    /// interpolated solution at `t_out`, unless a root or the stop time comes first; with
    /// `one_step` it returns after one internal step (`IDA_ONE_STEP`). The solution is then in
    /// [`Ida::y`]/[`Ida::yp`] at [`Ida::t`].
    pub(crate) fn solve(&mut self, t_out: f64, one_step: bool) -> Result<SolveStatus, IdaError> {
        check_finite("t_out", t_out)?;
        self.begin_call();
        let itask = if one_step {
            sys::IDA_ONE_STEP
        } else {
            sys::IDA_NORMAL
        };
        let mut tret = self.t;
        // SAFETY: mem, y, yp are valid; y/yp are only written by IDA as outputs.
        let rc = unsafe { sys::IDASolve(self.mem, t_out, &mut tret, self.y, self.yp, itask) };
        if tret.is_finite() {
            self.t = tret;
        }
        match rc {
            sys::IDA_ROOT_RETURN => {
                // SAFETY: root_info has num_roots entries, as IDA expects.
                let rc2 = unsafe { sys::IDAGetRootInfo(self.mem, self.root_info.as_mut_ptr()) };
                self.check(rc2, "IDAGetRootInfo")?;
                Ok(SolveStatus::Root { t: self.t })
            }
            sys::IDA_TSTOP_RETURN => Ok(SolveStatus::StopTime { t: self.t }),
            rc if rc >= 0 => Ok(SolveStatus::Reached { t: self.t }),
            rc => Err(self.failure(rc)),
        }
    }

    /// IDA's interpolating polynomial of the last step as Taylor coefficients about the
    /// internal time `t_n` \[s\]: appends `y⁽ᵏ⁾(t_n)/k!` for `k = 0..=q` (each of length n) to
    /// `out` and returns `(t_n, q)`, `q` the order used. The polynomial has degree `q`, so these
    /// `q + 1` terms reproduce it exactly on `[t_n − h_u, t_n]` (dense output at the solver's
    /// order).
    pub(crate) fn taylor(&mut self, out: &mut Vec<f64>) -> Result<(f64, usize), IdaError> {
        self.begin_call();
        let (mut tn, mut q): (f64, c_int) = (0.0, 0);
        // SAFETY: mem is valid; the out-pointers are valid locals.
        let rc = unsafe { sys::IDAGetCurrentTime(self.mem, &mut tn) };
        self.check(rc, "IDAGetCurrentTime")?;
        // SAFETY: as above.
        let rc = unsafe { sys::IDAGetLastOrder(self.mem, &mut q) };
        self.check(rc, "IDAGetLastOrder")?;
        let q = q.max(0) as usize;
        let mut factorial = 1.0;
        for k in 0..=q {
            if k > 0 {
                factorial *= k as f64;
            }
            // SAFETY: mem and dky are valid; dky has length n; k ≤ the order used.
            let rc = unsafe { sys::IDAGetDky(self.mem, tn, k as c_int, self.dky) };
            self.check(rc, "IDAGetDky")?;
            // SAFETY: dky is a valid serial vector of length n.
            let d = unsafe { slice::from_raw_parts(sys::N_VGetArrayPointer(self.dky), self.n) };
            out.extend(d.iter().map(|x| x / factorial));
        }
        Ok((tn, q))
    }

    /// The solution at `t` \[s\] by IDA's own interpolating polynomial (`IDAGetDky` with
    /// k = 0), written into `out` (length n): as accurate as the steps, and free of any effect on
    /// them. `t` must lie within the last step, `[t_n − h_u, t_n]` (IDA checks: otherwise
    /// `IDA_BAD_T` as an error naming the interval).
    pub(crate) fn interpolate(&mut self, t: f64, out: &mut [f64]) -> Result<(), IdaError> {
        check_finite("t", t)?;
        if out.len() != self.n {
            return Err(bad(format!(
                "interpolate: out has length {} but the system has n = {} unknowns",
                out.len(),
                self.n
            )));
        }
        self.begin_call();
        // SAFETY: mem and dky are valid; dky has length n.
        let rc = unsafe { sys::IDAGetDky(self.mem, t, 0, self.dky) };
        self.check(rc, "IDAGetDky")?;
        // SAFETY: dky is a valid serial vector of length n.
        out.copy_from_slice(unsafe {
            slice::from_raw_parts(sys::N_VGetArrayPointer(self.dky), self.n)
        });
        Ok(())
    }

    /// Re-initialises after an event (`IDAReInit`) at time `t` \[s\] with new y and y' (length n).
    /// Keeps the options, root functions and linear solver; statistics keep accumulating.
    pub(crate) fn reinit(&mut self, t: f64, y: &[f64], yp: &[f64]) -> Result<(), IdaError> {
        check_finite("t", t)?;
        check_state("y", y, self.n)?;
        check_state("yp", yp, self.n)?;
        self.base_stats += self.segment_stats();
        self.state_mut().jac_residuals = 0;
        self.state_mut().jac_parts.reuses = 0;
        self.state_mut().jac_parts.valid = false;
        // SAFETY: y and yp are valid vectors of length n (validated lengths).
        unsafe {
            slice::from_raw_parts_mut(sys::N_VGetArrayPointer(self.y), self.n).copy_from_slice(y);
            slice::from_raw_parts_mut(sys::N_VGetArrayPointer(self.yp), self.n).copy_from_slice(yp);
        }
        self.t = t;
        self.root_info.iter_mut().for_each(|r| *r = 0);
        self.begin_call();
        // SAFETY: mem, y, yp are valid; IDA copies y and yp.
        let rc = unsafe { sys::IDAReInit(self.mem, t, self.y, self.yp) };
        self.check(rc, "IDAReInit")?;
        // IDAReInit resets the integrator counters but the linear solver's only at the next
        // solve; re-attaching resets them now, so stats() never counts a segment twice.
        self.attach_linear_solver()
    }

    /// The component of y whose estimated local error, weighted as in IDA's error test
    /// (`IDAGetEstLocalErrors` × `IDAGetErrWeights`), was largest at the last step, with that
    /// weighted error (≈ 1 at the limit of the error test); `None` before the first step.
    /// Allocates (two vectors): for diagnoses, not for the hot path.
    pub(crate) fn limiting_component(&mut self) -> Option<(usize, f64)> {
        if self.mem.is_null() || self.n == 0 {
            return None;
        }
        self.begin_call();
        // SAFETY: y is a valid serial vector of this context; clones are freed below.
        let (ele, ewt) = unsafe { (sys::N_VClone(self.y), sys::N_VClone(self.y)) };
        let mut best = None;
        if !ele.is_null() && !ewt.is_null() {
            // SAFETY: mem is valid; ele/ewt are vectors of length n owned here.
            let ok = unsafe {
                sys::IDAGetEstLocalErrors(self.mem, ele) >= 0
                    && sys::IDAGetErrWeights(self.mem, ewt) >= 0
            };
            if ok {
                // SAFETY: both are serial vectors of length n.
                let (e, w) = unsafe {
                    (
                        slice::from_raw_parts(sys::N_VGetArrayPointer(ele), self.n),
                        slice::from_raw_parts(sys::N_VGetArrayPointer(ewt), self.n),
                    )
                };
                for (i, (a, b)) in e.iter().zip(w).enumerate() {
                    let x = (a * b).abs();
                    if x.is_finite() && best.is_none_or(|(_, y)| x > y) {
                        best = Some((i, x));
                    }
                }
            }
        }
        // SAFETY: each is null or a vector created above, destroyed once.
        unsafe {
            if !ele.is_null() {
                sys::N_VDestroy(ele);
            }
            if !ewt.is_null() {
                sys::N_VDestroy(ewt);
            }
        }
        best
    }

    /// Time \[s\] of the current [`Ida::y`] and [`Ida::yp`].
    pub(crate) fn t(&self) -> f64 {
        self.t
    }

    /// Current solution y (length n): the initial values, or the result of the last
    /// `solve`/`calc_ic_*`/`reinit`.
    pub(crate) fn y(&self) -> &[f64] {
        // SAFETY: y is a valid serial vector of length n, written only by IDA calls that need
        // `&mut self`.
        unsafe { slice::from_raw_parts(sys::N_VGetArrayPointer(self.y), self.n) }
    }

    /// Current derivative y' (length n), as for [`Ida::y`].
    pub(crate) fn yp(&self) -> &[f64] {
        // SAFETY: as for y().
        unsafe { slice::from_raw_parts(sys::N_VGetArrayPointer(self.yp), self.n) }
    }

    /// After [`SolveStatus::Root`]: for each root function, +1 if it crossed zero upwards, -1
    /// downwards, 0 if it did not cross (`IDAGetRootInfo`). All 0 otherwise.
    pub(crate) fn root_info(&self) -> &[i32] {
        &self.root_info
    }

    /// Counters of the current segment (since the last IDAInit/IDAReInit).
    fn segment_stats(&self) -> IdaStats {
        let mem = self.mem;
        let get = |f: unsafe extern "C" fn(*mut c_void, *mut c_long) -> c_int| -> u64 {
            let mut v: c_long = 0;
            // SAFETY: mem is valid; f is one of IDA's counter getters.
            unsafe { f(mem, &mut v) };
            v.max(0) as u64
        };
        let mut last_step = 0.0;
        let mut last_order: c_int = 0;
        // SAFETY: mem is valid.
        unsafe {
            sys::IDAGetLastStep(mem, &mut last_step);
            sys::IDAGetLastOrder(mem, &mut last_order);
        }
        IdaStats {
            steps: get(sys::IDAGetNumSteps),
            residual_evals: get(sys::IDAGetNumResEvals),
            jacobian_evals: get(sys::IDAGetNumJacEvals),
            jacobian_reuses: self.state_ref().jac_parts.reuses,
            residual_evals_for_jacobian: get(sys::IDAGetNumLinResEvals)
                + self.state_ref().jac_residuals,
            error_test_failures: get(sys::IDAGetNumErrTestFails),
            nonlinear_iterations: get(sys::IDAGetNumNonlinSolvIters),
            nonlinear_convergence_failures: get(sys::IDAGetNumNonlinSolvConvFails),
            root_evals: get(sys::IDAGetNumGEvals),
            last_step,
            last_order,
        }
    }

    /// The step size \[s\] IDA will attempt next (`IDAGetCurrentStep`): after a failed step,
    /// the reduced size it failed at or will retry with (the `h` of its error message), where
    /// [`IdaStats::last_step`] is still the last step it took. `None` before IDA is set up.
    pub(crate) fn current_step(&self) -> Option<f64> {
        if self.mem.is_null() {
            return None;
        }
        let mut h = 0.0;
        // SAFETY: mem is valid.
        let flag = unsafe { sys::IDAGetCurrentStep(self.mem, &mut h) };
        (flag == 0 && h.is_finite() && h > 0.0).then_some(h)
    }

    /// Statistics of the whole run, accumulated across [`Ida::reinit`].
    pub(crate) fn stats(&self) -> IdaStats {
        self.base_stats + self.segment_stats()
    }

    /// The system.
    pub(crate) fn system(&self) -> &S {
        &self.state_ref().system
    }

    /// The system, mutably (e.g. to change a parameter before [`Ida::reinit`]).
    pub(crate) fn system_mut(&mut self) -> &mut S {
        &mut self.state_mut().system
    }

    /// Frees the SUNDIALS objects and returns the system.
    pub(crate) fn into_system(mut self) -> S {
        self.free_ffi();
        let state = std::mem::replace(&mut self.state, ptr::null_mut());
        // SAFETY: state came from Box::into_raw and is taken exactly once (nulled above, so Drop
        // skips it); IDA no longer references it.
        let state = unsafe { Box::from_raw(state) };
        state.system
    }

    /// Frees every SUNDIALS object (in dependency order) and the error sink; idempotent.
    fn free_ffi(&mut self) {
        // SAFETY: each pointer is null or owned by self and freed exactly once, then nulled.
        unsafe {
            if !self.mem.is_null() {
                sys::IDAFree(&mut self.mem);
                self.mem = ptr::null_mut();
            }
            if !self.ls.is_null() {
                sys::SUNLinSolFree(self.ls);
                self.ls = ptr::null_mut();
            }
            if !self.mat.is_null() {
                sys::SUNMatDestroy(self.mat);
                self.mat = ptr::null_mut();
            }
            for v in [
                &mut self.y,
                &mut self.yp,
                &mut self.id,
                &mut self.dky,
                &mut self.atol,
            ] {
                if !v.is_null() {
                    sys::N_VDestroy(*v);
                    *v = ptr::null_mut();
                }
            }
            if !self.ctx.is_null() {
                sys::SUNContext_Free(&mut self.ctx);
                self.ctx = ptr::null_mut();
            }
            // The sink must outlive the context (its error handler points at it).
            if !self.sink.is_null() {
                drop(Box::from_raw(self.sink));
                self.sink = ptr::null_mut();
            }
        }
    }
}

impl<S: DaeSystem> Drop for Ida<S> {
    fn drop(&mut self) {
        self.free_ffi();
        if !self.state.is_null() {
            // SAFETY: state came from Box::into_raw and was not yet taken.
            drop(unsafe { Box::from_raw(self.state) });
            self.state = ptr::null_mut();
        }
    }
}

impl<S: DaeSystem + std::fmt::Debug> std::fmt::Debug for Ida<S> {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Ida")
            .field("system", self.system())
            .field("n", &self.n)
            .field("t", &self.t)
            .field("y", &self.y())
            .field("yp", &self.yp())
            .finish()
    }
}
