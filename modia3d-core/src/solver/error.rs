//! Solver stage: errors of the IDA wrapper (plain data, no FFI).
//!
//! May touch only the standard library, `thiserror` and the integer return-flag constants of
//! `sundials-sys` (no calls into C happen here).

use sundials_sys as sys;

/// Everything that can go wrong in the IDA integrator (the crate's internal wrapper). Every
/// message says what went wrong, at which time `t` \[s\], and what to try.
#[derive(thiserror::Error, Debug, Clone, PartialEq)]
pub enum IdaError {
    /// IDA returned a failure flag.
    #[error("{name} (flag {flag}) at t = {t} s: {hint}{}", sundials_suffix(.message))]
    Flag {
        /// The IDA return flag (negative).
        flag: i32,
        /// Its name as given by `IDAGetReturnFlagName`, e.g. `IDA_CONV_FAIL`.
        name: String,
        /// Time \[s\] reached when the failure happened (last successful time).
        t: f64,
        /// What to try, written for this flag.
        hint: String,
        /// The message SUNDIALS reported through the context's error handler (may be empty).
        message: String,
    },
    /// A callback of the DAE system (the residual, root or Jacobian-structure function) panicked; the panic was caught at the FFI boundary.
    #[error(
        "a DaeSystem callback panicked at t = {t} s: {message}; the integration was stopped \
         (the system may be in an inconsistent state: re-initialise or rebuild it)"
    )]
    Panic {
        /// The panic payload as text.
        message: String,
        /// Time \[s\] passed to the callback that panicked.
        t: f64,
    },
    /// The DAE residual returned a fatal error.
    #[error(
        "the residual reported a fatal error at t = {t} s: {message}; the integration was stopped"
    )]
    ResidualFatal {
        /// The message given by the residual.
        message: String,
        /// Time \[s\] passed to the residual.
        t: f64,
    },
    /// The residual produced a NaN or infinite value that IDA could not step around.
    #[error(
        "the residual component {index} was {value} at t = {t} s and IDA could not step around it \
         ({flag_name}); check the model for divisions by zero, square roots of negatives or \
         unbounded growth near this time"
    )]
    NonFiniteResidual {
        /// Index of the (first) non-finite residual component.
        index: usize,
        /// Earliest time \[s\] at which the residual was non-finite during the failed call.
        t: f64,
        /// `"NaN"`, `"inf"` or `"-inf"`.
        value: String,
        /// Name of the IDA flag the failure ended with.
        flag_name: String,
    },
    /// An argument was invalid (length mismatch, non-positive tolerance, non-finite number, ...).
    #[error("invalid argument: {0}")]
    BadArgument(String),
}

impl IdaError {
    /// IDA reached its step limit of one call (`IDA_TOO_MUCH_WORK`); the integration can
    /// continue from the last step with another call.
    pub fn is_too_much_work(&self) -> bool {
        matches!(self, IdaError::Flag { flag, .. } if *flag == sys::IDA_TOO_MUCH_WORK)
    }

    /// IDA gave up at a step it could not take: its error test or Newton's method failed
    /// repeatedly (`IDA_ERR_FAIL`, `IDA_CONV_FAIL`), the accuracy cannot be reached
    /// (`IDA_TOO_MUCH_ACC`), the linear solver's setup or solve failed, or the residual kept
    /// failing recoverably (`IDA_REP_RES_ERR`): failures whose cause lies in the system's
    /// dynamics (bad arguments, caught panics and fatal residuals are not).
    pub fn is_stall(&self) -> bool {
        matches!(self, IdaError::Flag { flag, .. } if [
            sys::IDA_ERR_FAIL,
            sys::IDA_CONV_FAIL,
            sys::IDA_TOO_MUCH_ACC,
            sys::IDA_LSETUP_FAIL,
            sys::IDA_LSOLVE_FAIL,
            sys::IDA_REP_RES_ERR,
        ]
        .contains(flag))
    }
}

fn sundials_suffix(message: &str) -> String {
    if message.is_empty() {
        String::new()
    } else {
        format!(" (SUNDIALS: {message})")
    }
}

/// What to try when IDA returns `flag`.
pub(crate) fn flag_hint(flag: i32) -> &'static str {
    match flag {
        sys::IDA_TOO_MUCH_WORK => {
            "IDA took the maximum number of steps before reaching the output time; raise \
             IdaOptions::max_num_steps, request output times closer together, or check whether \
             the model is very stiff or chattering"
        }
        sys::IDA_TOO_MUCH_ACC => {
            "IDA could not satisfy the requested accuracy; loosen rtol/atol (rtol near machine \
             precision cannot be met)"
        }
        sys::IDA_ERR_FAIL => {
            "the local error test failed repeatedly (or the step became too small); check the \
             residual for discontinuities or events that should be root functions, or loosen \
             tolerances"
        }
        sys::IDA_CONV_FAIL => {
            "the corrector did not converge; tighten tolerances or check the residual for \
             discontinuities"
        }
        sys::IDA_LINIT_FAIL | sys::IDA_LSETUP_FAIL | sys::IDA_LSOLVE_FAIL => {
            "the linear solver failed; the iteration matrix dF/dy + c dF/dy' is probably singular \
             (a higher-index DAE, a wrong differential/algebraic split, or a redundant equation)"
        }
        sys::IDA_RES_FAIL => "the residual failed unrecoverably; see the residual's own error",
        sys::IDA_REP_RES_ERR => {
            "the residual kept reporting recoverable errors; the solution leaves the domain where \
             the residual can be evaluated"
        }
        sys::IDA_RTFUNC_FAIL => "the root function failed unrecoverably",
        sys::IDA_CONSTR_FAIL => "the inequality constraints could not be met",
        sys::IDA_FIRST_RES_FAIL => {
            "the first residual evaluation of the initial-condition calculation failed \
             recoverably; check y0 and y'0"
        }
        sys::IDA_LINESEARCH_FAIL => {
            "the line search of the initial-condition calculation failed; give a better guess of \
             y0/y'0, or check the differential/algebraic split"
        }
        sys::IDA_NO_RECOVERY => {
            "the residual or linear solver failed recoverably but the initial-condition \
             calculation could not recover; give a better guess of y0/y'0"
        }
        sys::IDA_NLS_INIT_FAIL | sys::IDA_NLS_SETUP_FAIL | sys::IDA_NLS_FAIL => {
            "the nonlinear solver failed; check the residual and the differential/algebraic split"
        }
        sys::IDA_MEM_FAIL => "SUNDIALS could not allocate memory; reduce the problem size",
        sys::IDA_ILL_INPUT => {
            "IDA rejected an input; check the output time direction and magnitude, the stop \
             time, and the options"
        }
        sys::IDA_BAD_EWT => {
            "an error weight became non-positive; use strictly positive absolute tolerances"
        }
        sys::IDA_BAD_T => "the requested time is outside the last step's interval",
        _ => "unexpected IDA failure; please report it with the model that triggers it",
    }
}
