//! Solver stage, FFI: IDA's residual and root callbacks, the SUNDIALS error handler and the
//! helpers every callback shares (panics caught and recorded, never unwinding into C;
//! non-finite residuals recorded). Part of the `ida` FFI module (`unsafe` allowed here, see
//! `ida.rs` for the invariants).

use super::*;

/// Keeps in `slot` the earliest (component, time, value text) of a non-finite residual.
pub(super) fn record_non_finite(
    slot: &mut Option<(usize, f64, &'static str)>,
    index: usize,
    t: f64,
    value: f64,
) {
    if slot.is_none_or(|(_, t_prev, _)| t < t_prev) {
        let text = if value.is_nan() {
            "NaN"
        } else if value > 0.0 {
            "inf"
        } else {
            "-inf"
        };
        *slot = Some((index, t, text));
    }
}

pub(super) fn panic_message(payload: &(dyn Any + Send)) -> String {
    if let Some(s) = payload.downcast_ref::<&str>() {
        (*s).to_string()
    } else if let Some(s) = payload.downcast_ref::<String>() {
        s.clone()
    } else {
        "panic with a non-string payload".to_string()
    }
}

/// Reads a C string returned by an `IDAGet*ReturnFlagName` function and frees it.
///
/// # Safety
/// `p` must be null or a NUL-terminated string allocated with C `malloc`.
pub(super) unsafe fn take_c_string(p: *mut c_char, flag: c_int) -> String {
    if p.is_null() {
        return format!("IDA flag {flag}");
    }
    // SAFETY: per the contract, p is a valid NUL-terminated malloc'ed string that we own.
    let s = unsafe { CStr::from_ptr(p) }.to_string_lossy().into_owned();
    // SAFETY: allocated by SUNDIALS with malloc, freed once here.
    unsafe { sys::free(p.cast()) };
    s
}

pub(super) fn flag_name(flag: c_int) -> String {
    // SAFETY: IDAGetReturnFlagName accepts any flag and returns a fresh malloc'ed string.
    unsafe { take_c_string(sys::IDAGetReturnFlagName(flag as c_long), flag) }
}

pub(super) fn lin_flag_name(flag: c_int) -> String {
    // SAFETY: as for IDAGetReturnFlagName.
    unsafe { take_c_string(sys::IDAGetLinReturnFlagName(flag as c_long), flag) }
}

/// SUNDIALS error handler: appends the message to the `ErrorSink` passed as user data.
pub(super) unsafe extern "C" fn error_handler(
    _line: c_int,
    func: *const c_char,
    _file: *const c_char,
    msg: *const c_char,
    err_code: sys::SUNErrCode,
    err_user_data: *mut c_void,
    _sunctx: sys::SUNContext,
) {
    let _ = catch_unwind(AssertUnwindSafe(|| {
        if err_user_data.is_null() {
            return;
        }
        // SAFETY: err_user_data is the ErrorSink pushed with this handler; it outlives the
        // context and no Rust reference to it is live while SUNDIALS runs.
        let sink = unsafe { &mut *err_user_data.cast::<ErrorSink>() };
        if sink.text.len() >= MAX_SINK_LEN {
            return;
        }
        let text = |p: *const c_char| {
            if p.is_null() {
                None
            } else {
                // SAFETY: SUNDIALS passes NUL-terminated strings or null.
                Some(
                    unsafe { CStr::from_ptr(p) }
                        .to_string_lossy()
                        .trim()
                        .to_string(),
                )
            }
        };
        let msg = text(msg).unwrap_or_else(|| format!("error code {err_code}"));
        if !sink.text.is_empty() {
            sink.text.push_str("; ");
        }
        match text(func) {
            Some(f) => sink.text.push_str(&format!("{f}: {msg}")),
            None => sink.text.push_str(&msg),
        }
    }));
}

/// The status code of a callback whose body ran under `catch_unwind`: the body's own code, or
/// -1 after recording the first panic (its message prefixed by `context`) in the state.
///
/// # Safety
/// `state` must be the valid CallbackState of the running Ida, with no live reference to it.
pub(super) unsafe fn settle<S>(
    state: *mut CallbackState<S>,
    t: f64,
    outcome: std::thread::Result<c_int>,
    context: &str,
) -> c_int {
    match outcome {
        Ok(code) => code,
        Err(payload) => {
            let message = panic_message(payload.as_ref());
            // SAFETY: per the contract.
            let st = unsafe { &mut *state };
            st.panic
                .get_or_insert_with(|| (format!("{context}{message}"), t));
            -1
        }
    }
}

/// IDA residual callback: F(t, y, y') into `rr`. Returns 0 on success, 1 for a recoverable
/// failure (including a non-finite residual), -1 for a fatal one or a caught panic.
pub(super) unsafe extern "C" fn residual_callback<S: DaeSystem>(
    t: f64,
    yy: sys::N_Vector,
    yp: sys::N_Vector,
    rr: sys::N_Vector,
    user_data: *mut c_void,
) -> c_int {
    let state = user_data.cast::<CallbackState<S>>();
    let outcome = catch_unwind(AssertUnwindSafe(|| {
        // SAFETY: user_data is the CallbackState of the Ida that is running this call; no other
        // reference to it is live (see the module invariants). yy, yp, rr are distinct serial
        // vectors of length n owned by IDA for the duration of the call.
        let st = unsafe { &mut *state };
        let n = st.n;
        let (y, ypv, res) = unsafe {
            (
                slice::from_raw_parts(sys::N_VGetArrayPointer(yy), n),
                slice::from_raw_parts(sys::N_VGetArrayPointer(yp), n),
                slice::from_raw_parts_mut(sys::N_VGetArrayPointer(rr), n),
            )
        };
        match st.system.residual(t, y, ypv, res) {
            Ok(()) => match res.iter().position(|v| !v.is_finite()) {
                None => 0,
                Some(i) => {
                    record_non_finite(&mut st.non_finite, i, t, res[i]);
                    1
                }
            },
            Err(ResidualError::Recoverable) => 1,
            Err(ResidualError::Fatal(msg)) => {
                if st.fatal.is_none() {
                    st.fatal = Some((msg, t));
                }
                -1
            }
        }
    }));
    // SAFETY: the closure's borrow of the state has ended.
    unsafe { settle(state, t, outcome, "") }
}

/// IDA root callback: g(t, y, y') into `gout` (length num_roots). Returns 0, or -1 after a
/// caught panic.
pub(super) unsafe extern "C" fn root_callback<S: DaeSystem>(
    t: f64,
    yy: sys::N_Vector,
    yp: sys::N_Vector,
    gout: *mut f64,
    user_data: *mut c_void,
) -> c_int {
    let state = user_data.cast::<CallbackState<S>>();
    let outcome = catch_unwind(AssertUnwindSafe(|| {
        // SAFETY: as in residual_callback; gout has num_roots entries (IDARootInit was called
        // with that number).
        let st = unsafe { &mut *state };
        let (n, m) = (st.n, st.n_roots);
        let (y, ypv, g) = unsafe {
            (
                slice::from_raw_parts(sys::N_VGetArrayPointer(yy), n),
                slice::from_raw_parts(sys::N_VGetArrayPointer(yp), n),
                slice::from_raw_parts_mut(gout, m),
            )
        };
        st.system.roots(t, y, ypv, g);
    }));
    // SAFETY: the closure's borrow of the state has ended.
    unsafe { settle(state, t, outcome.map(|()| 0), "in roots(): ") }
}

/// IDA error-weight callback (`IDAWFtolerances`), installed when the system has
/// [`DaeSystem::error_weight_factors`]: IDA's own weights `1/(rtol·|y_i| + atol_i)` times the
/// system's factors. Returns 0, or -1 for a non-positive or non-finite weight or a caught panic
/// (IDA then stops with IDA_ILL_INPUT, or shrinks the step if this happens after a step).
pub(super) unsafe extern "C" fn ewt_callback<S: DaeSystem>(
    yy: sys::N_Vector,
    ewt: sys::N_Vector,
    user_data: *mut c_void,
) -> c_int {
    let state = user_data.cast::<CallbackState<S>>();
    let outcome = catch_unwind(AssertUnwindSafe(|| {
        // SAFETY: user_data is the CallbackState set with IDASetUserData; yy and ewt are
        // distinct IDA vectors of length n; no other Rust reference to the state is live while
        // IDA runs its own code.
        let st = unsafe { &mut *state };
        let n = st.n;
        let (y, w) = unsafe {
            (
                slice::from_raw_parts(sys::N_VGetArrayPointer(yy), n),
                slice::from_raw_parts_mut(sys::N_VGetArrayPointer(ewt), n),
            )
        };
        let rtol = st.rtol;
        let tighten = st.system.error_weight_factors(y, &mut st.ewt_factor);
        // Zipped slices (no bounds check per entry) and one test of the whole vector at the
        // end: IDA calls this once per step, over every unknown.
        let (z, f) = (&st.zero_size[..n], &st.ewt_factor);
        let weight = |yi: f64, zi: f64| 1.0 / (rtol * yi.abs() + rtol * zi);
        // Each weight tested as it is formed (no second pass), without branching.
        let valid = |wi: f64| wi.is_finite() & (wi > 0.0);
        let mut ok = true;
        if tighten {
            for (((wi, &yi), &zi), &fi) in w.iter_mut().zip(y).zip(z).zip(&f[..n]) {
                *wi = weight(yi, zi) * fi;
                ok &= valid(*wi);
            }
        } else {
            for ((wi, &yi), &zi) in w.iter_mut().zip(y).zip(z) {
                *wi = weight(yi, zi);
                ok &= valid(*wi);
            }
        }
        if ok {
            0
        } else {
            -1
        }
    }));
    // SAFETY: the closure's borrow of the state has ended.
    unsafe { settle(state, f64::NAN, outcome, "in the error weights: ") }
}
