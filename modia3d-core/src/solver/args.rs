//! Argument checks of the IDA wrapper (`ida.rs`), done in safe code before any C call, so a
//! bad argument is an [`IdaError::BadArgument`] naming the argument and the allowed range.

use std::ffi::{c_int, c_long};

use super::{Atol, IdaError, IdaOptions};

/// A [`IdaError::BadArgument`] with this message.
pub(super) fn bad(msg: impl Into<String>) -> IdaError {
    IdaError::BadArgument(msg.into())
}

pub(super) fn check_finite(what: &str, v: f64) -> Result<(), IdaError> {
    if v.is_finite() {
        Ok(())
    } else {
        Err(bad(format!(
            "{what} = {v} is not finite; pass a finite number"
        )))
    }
}

pub(super) fn check_state(what: &str, v: &[f64], n: usize) -> Result<(), IdaError> {
    if v.len() != n {
        return Err(bad(format!(
            "{what} has length {} but the system has n = {n} unknowns; pass a slice of length {n}",
            v.len()
        )));
    }
    if let Some(i) = v.iter().position(|x| !x.is_finite()) {
        return Err(bad(format!(
            "{what}[{i}] = {} is not finite; pass finite initial values",
            v[i]
        )));
    }
    Ok(())
}

/// Checks the arguments of `Ida::new` before any C call: sizes, finiteness, option ranges.
pub(super) fn validate(
    n: usize,
    n_roots: usize,
    t0: f64,
    y0: &[f64],
    yp0: &[f64],
    opts: &IdaOptions,
) -> Result<(), IdaError> {
    if n == 0 {
        return Err(bad(
            "the system has no unknowns (len() == 0); IDA needs n >= 1",
        ));
    }
    if i64::try_from(n).is_err() || c_int::try_from(n_roots).is_err() {
        return Err(bad(format!(
            "system too large: n = {n}, num_roots = {n_roots}"
        )));
    }
    check_finite("t0", t0)?;
    check_state("y0", y0, n)?;
    check_state("yp0", yp0, n)?;
    if !(opts.rtol.is_finite() && opts.rtol > 0.0) {
        return Err(bad(format!(
            "rtol = {} must be finite and > 0 (typical: 1e-4 .. 1e-10)",
            opts.rtol
        )));
    }
    match &opts.atol {
        Atol::Scalar(a) => {
            if !(a.is_finite() && *a > 0.0) {
                return Err(bad(format!("atol = {a} must be finite and > 0")));
            }
        }
        Atol::Vector(v) => {
            if v.len() != n {
                return Err(bad(format!(
                    "atol vector has length {} but the system has n = {n} unknowns",
                    v.len()
                )));
            }
            if let Some(i) = v.iter().position(|a| !(a.is_finite() && *a > 0.0)) {
                return Err(bad(format!("atol[{i}] = {} must be finite and > 0", v[i])));
            }
        }
    }
    if let Some(h) = opts.max_step {
        if !(h.is_finite() && h > 0.0) {
            return Err(bad(format!(
                "max_step = {h} s must be finite and > 0 (or None)"
            )));
        }
    }
    if opts.max_num_steps == 0 || c_long::try_from(opts.max_num_steps).is_err() {
        return Err(bad(format!(
            "max_num_steps = {} must be >= 1 and fit a C long",
            opts.max_num_steps
        )));
    }
    if let Some(d) = &opts.differential {
        if d.len() != n {
            return Err(bad(format!(
                "differential has length {} but the system has n = {n} unknowns",
                d.len()
            )));
        }
    }
    if let Some(dirs) = &opts.root_directions {
        if dirs.len() != n_roots {
            return Err(bad(format!(
                "root_directions has length {} but the system has {n_roots} root functions",
                dirs.len()
            )));
        }
        if let Some(i) = dirs.iter().position(|d| !(-1..=1).contains(d)) {
            return Err(bad(format!(
                "root_directions[{i}] = {} must be -1, 0 or +1",
                dirs[i]
            )));
        }
    }
    if let Some(h) = opts.init_step {
        if !(h.is_finite() && h != 0.0) {
            return Err(bad(format!(
                "init_step = {h} s must be finite and non-zero (or None)"
            )));
        }
    }
    Ok(())
}
