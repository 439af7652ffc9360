//! Solver stage: the safe interface to the SUNDIALS IDA DAE integrator.
//!
//! This module may touch only the standard library, `thiserror` and (in the FFI module `ida` —
//! `ida.rs`, `ida/callbacks.rs`, `ida/linear.rs`, the only files of the crate that contain
//! `unsafe`) the `sundials-sys` FFI bindings. It knows nothing about
//! scenes, bodies or contacts: the multibody stages describe their equations through the
//! [`DaeSystem`] trait and drive the integration with [`Ida`].
//!
//! A DAE is written in fully implicit form `F(t, y, y') = 0` with `n` unknowns `y`, plus optional
//! root (zero-crossing) functions `g(t, y, y')` whose sign changes IDA locates precisely, which is
//! how events such as impacts are detected.
//!
//! The module is internal to the crate, so this sketch is not run as a doctest; the unit tests
//! in `solver/tests/` run the same kind of system against analytic solutions.
//!
//! ```ignore
//! use crate::solver::{DaeSystem, Ida, IdaOptions, ResidualError, SolveStatus};
//!
//! /// y' = -y as the implicit residual F = y' + y.
//! struct Decay;
//! impl DaeSystem for Decay {
//!     fn len(&self) -> usize { 1 }
//!     fn residual(&mut self, _t: f64, y: &[f64], yp: &[f64], res: &mut [f64])
//!         -> Result<(), ResidualError> {
//!         res[0] = yp[0] + y[0];
//!         Ok(())
//!     }
//! }
//!
//! let opts = IdaOptions::default().rtol(1e-8).atol(1e-10);
//! let mut ida = Ida::new(Decay, 0.0, &[1.0], &[-1.0], &opts)?;
//! assert_eq!(ida.solve(1.0, false)?, SolveStatus::Reached { t: 1.0 });
//! assert!((ida.y()[0] - (-1.0f64).exp()).abs() < 1e-6);
//! ```

mod args;
mod block_lu;
mod colouring;
mod error;
#[allow(unsafe_code)]
// the one FFI module of the crate (with its children ida/callbacks.rs, ida/linear.rs)
mod ida;
mod options;
mod stats;
#[cfg(test)]
mod tests;

pub use error::IdaError;
pub(crate) use ida::Ida;
pub(crate) use options::{Atol, IdaOptions};
pub use stats::IdaStats;

/// A DAE `F(t, y, y') = 0` with optional root (zero-crossing) functions.
///
/// Units of `t`, `y` and `y'` are the system's own; in modia3d `t` is always in seconds \[s\].
pub(crate) trait DaeSystem {
    /// Number of unknowns n.
    fn len(&self) -> usize;

    /// Fills `res` (len n) with F(t, y, y'). `Err(Recoverable)` asks IDA to retry with a smaller
    /// step; `Err(Fatal(msg))` stops the integration with that message.
    ///
    /// Every component of `res` must be finite after an `Ok` return; a NaN or infinity is
    /// treated as a recoverable error, and if IDA cannot step around it the integration ends
    /// with [`IdaError::NonFiniteResidual`].
    fn residual(
        &mut self,
        t: f64,
        y: &[f64],
        yp: &[f64],
        res: &mut [f64],
    ) -> Result<(), ResidualError>;

    /// Number of root functions (fixed for the lifetime of the solver). Default 0.
    fn num_roots(&self) -> usize {
        0
    }

    /// Fills `g` (len num_roots) with the root functions at (t, y, y'). Default: nothing.
    fn roots(&mut self, _t: f64, _y: &[f64], _yp: &[f64], _g: &mut [f64]) {}

    /// The block structure of the iteration matrix `∂F/∂y + c_j ∂F/∂y'` at the current point,
    /// for a coloured difference-quotient Jacobian (see [`BlockStructure`]). Called once when
    /// the solver is created (to decide whether to use it) and before every Jacobian
    /// evaluation (the couplings may change at events). Return `false` — the default — to
    /// let IDA form the dense Jacobian with one residual evaluation per unknown.
    fn jacobian_structure(&mut self, _s: &mut BlockStructure) -> bool {
        false
    }

    /// Whether the system tightens its error weights with [`DaeSystem::error_weight_factors`]
    /// (asked once when the solver is created). Default `false`: IDA's own weights
    /// `1/(rtol·|y_i| + atol_i)`.
    fn has_error_weight_factors(&self) -> bool {
        false
    }

    /// Factors `f_i ≥ 1` by which the error weights `1/(rtol·|y_i| + atol_i)` are multiplied
    /// at the current point (called by IDA once per step, before the step, with `y` the
    /// accepted solution); returns `false` (and may leave `f` as it is) when every factor is 1.
    /// Must not allocate.
    fn error_weight_factors(&mut self, _y: &[f64], _f: &mut [f64]) -> bool {
        false
    }

    /// The columns of the iteration matrix `∂F/∂y + c_j ∂F/∂y'` that belong to the blocks
    /// marked in [`BlockStructure::analytic`], computed by the system itself: every non-zero
    /// entry `(i, j)` of those columns (rows of the block and of the blocks coupled with it) is
    /// passed to `out` (entries may be passed in parts; they are summed). Called before the
    /// difference quotients of the other blocks, at the point of `args`. The default adds
    /// nothing. `Err` as for [`DaeSystem::residual`].
    fn jacobian(
        &mut self,
        _args: &JacobianArgs<'_>,
        _out: &mut dyn JacobianSink,
    ) -> Result<(), ResidualError> {
        Ok(())
    }

    /// `∂F/∂y'` at `args.y` (`args.c_j` unused), written into `out` as [`DaeSystem::jacobian`]
    /// writes its columns, every nonzero entry inside the block structure; returns whether it
    /// did. With it, the solver forms the iteration matrix `∂F/∂y + c_j ∂F/∂y'` for a new
    /// `c_j` from the last one's parts instead of new difference quotients (IDA asks for a new
    /// matrix whenever `c_j = α/h` moves by more than 25 %, as after every failed error test).
    /// Default: not available (`Ok(false)`), and every matrix is formed anew.
    fn yp_jacobian(
        &mut self,
        _args: &JacobianArgs<'_>,
        _out: &mut dyn JacobianSink,
    ) -> Result<bool, ResidualError> {
        Ok(false)
    }

    /// Upper bounds on the sizes of the difference-quotient increments of the solver's
    /// coloured Jacobian, per unknown, at the point of `args` (called once per Jacobian, after
    /// [`DaeSystem::jacobian`]): `caps` (len n) arrives filled with `+∞` (no bound); the
    /// system lowers the entries it must and returns whether it lowered any. The solver then
    /// uses [`capped_increment`] of its rule's increment. For unknowns the residual depends on
    /// through a feature much finer than the unknown's own scale (a contact's centre of
    /// pressure under a tilt, see `dae/increment_caps.rs`). Default: no bound. Must not
    /// allocate.
    fn increment_caps(&mut self, _args: &JacobianArgs<'_>, _caps: &mut [f64]) -> bool {
        false
    }

    /// Called once per Jacobian before the difference quotients of the coloured blocks, at
    /// the point `(t, y, y')` of the Jacobian (after [`DaeSystem::increment_caps`]), so that
    /// [`DaeSystem::quotient_residual`] can keep what the perturbed unknowns do not change.
    /// Returns whether it evaluated the residual (counted in the solver's statistics as a
    /// residual for the Jacobian). Default: nothing (`Ok(false)`). `Err` as for
    /// [`DaeSystem::residual`]. Must not allocate.
    fn begin_quotients(&mut self, _t: f64, _y: &[f64], _yp: &[f64]) -> Result<bool, ResidualError> {
        Ok(false)
    }

    /// The residual at a point that differs from the one of the last
    /// [`DaeSystem::begin_quotients`] only in the unknowns `changed` (in `y` and `y'`): one
    /// difference quotient of the coloured Jacobian. It must give the same values, to the
    /// last bit, as [`DaeSystem::residual`] at that point; a system may skip the work the
    /// changed unknowns cannot affect. Default: [`DaeSystem::residual`].
    fn quotient_residual(
        &mut self,
        t: f64,
        y: &[f64],
        yp: &[f64],
        res: &mut [f64],
        _changed: &[usize],
    ) -> Result<(), ResidualError> {
        self.residual(t, y, yp, res)
    }
}

/// Receives the columns of [`DaeSystem::jacobian`] in runs of consecutive rows.
pub(crate) trait JacobianSink {
    /// Adds `values[k]` to entry (`i0 + k`, `j`) of the iteration matrix; the rows
    /// `i0..i0 + values.len()` must be unknowns of one block (a block's unknowns need not be
    /// consecutive, but each run must be).
    fn add(&mut self, i0: usize, j: usize, values: &[f64]);
}

/// Any `FnMut(i, j, value)` receives the entries one by one.
impl<F: FnMut(usize, usize, f64)> JacobianSink for F {
    fn add(&mut self, i0: usize, j: usize, values: &[f64]) {
        for (k, &v) in values.iter().enumerate() {
            self(i0 + k, j, v);
        }
    }
}

/// The point at which [`DaeSystem::jacobian`] is asked for its columns.
#[derive(Clone, Copy, Debug)]
pub(crate) struct JacobianArgs<'a> {
    /// Time \[s\].
    pub t: f64,
    /// IDA's coefficient `c_j` \[1/s\] of `∂F/∂y'` in the iteration matrix.
    pub c_j: f64,
    /// Current step size `h` \[s\].
    pub h: f64,
    /// The current iterate `y` (len n).
    pub y: &'a [f64],
    /// Its derivative `y'` (len n).
    pub yp: &'a [f64],
    /// `atol_j / rtol` per unknown (len n): the size below which an unknown counts as zero.
    pub zero_size: &'a [f64],
}

impl JacobianArgs<'_> {
    /// The difference-quotient increment of unknown `j` (the rule of the solver's own
    /// quotients, see [`dq_increment`]).
    #[inline]
    pub(crate) fn increment(&self, j: usize) -> f64 {
        dq_increment(self.y[j], self.yp[j], self.h, self.zero_size[j])
    }
}

/// The difference-quotient increment of an unknown `y_j` with derivative `y'_j` at step `h`
/// \[s\] whose tolerances count values below `zero_size` (`atol_j / rtol`) as zero:
/// `max(√ε · max(|h·y'_j|, zero_size), 1e3·ε·|y_j|)` with the sign of `h·y'_j`, rounded so that
/// `y_j + inc` is exact. Why this rule and not IDA's: `solver/ida/linear.rs`
/// (`jacobian_callback`).
#[inline]
pub(crate) fn dq_increment(yj: f64, ypj: f64, h: f64, zero_size: f64) -> f64 {
    let srur = f64::EPSILON.sqrt();
    let mut inc = (srur * (h * ypj).abs().max(zero_size)).max(DQ_FLOOR * yj.abs());
    if h * ypj < 0.0 {
        inc = -inc;
    }
    (yj + inc) - yj
}

/// The difference-quotient increment `inc` of an unknown `y_j` limited to `cap` in size (sign
/// kept), never below the rounding floor of [`dq_increment`] (`1e3·ε·|y_j|`), and rounded so
/// that `y_j + inc` is exact.
#[inline]
pub(crate) fn capped_increment(inc: f64, cap: f64, yj: f64) -> f64 {
    let size = inc.abs().min(cap).max(DQ_FLOOR * yj.abs());
    (yj + size.copysign(inc)) - yj
}

/// The smallest difference-quotient increment relative to the unknown's size: a thousand
/// roundings (see [`dq_increment`]).
const DQ_FLOOR: f64 = 1e3 * f64::EPSILON;

/// The sparsity of a DAE's iteration matrix as blocks of unknowns: the residual rows of a block
/// depend only on the unknowns of that block and of the blocks it is coupled with. Rows and
/// columns share the block numbering (row `i` belongs to the block of unknown `i`).
///
/// The solver colours the blocks so that no two blocks of one colour are within two couplings
/// of each other; the unknowns of all blocks of one colour are then perturbed together, so a
/// Jacobian costs (sum over colours of the largest block) residual evaluations instead of `n`
/// (Curtis, Powell & Reid 1974). In a multibody DAE the blocks are the independent joint trees
/// and the couplings are the contacts and force elements between them.
#[derive(Clone, Debug, Default, PartialEq)]
pub(crate) struct BlockStructure {
    /// Block of each unknown, length n; blocks are numbered `0..n_blocks`.
    pub block_of: Vec<usize>,
    /// Number of blocks.
    pub n_blocks: usize,
    /// Coupled block pairs `(a, b)`, `a != b`, each listed at least once in either order;
    /// duplicates are allowed.
    pub couplings: Vec<(usize, usize)>,
    /// Blocks whose columns the system computes itself ([`DaeSystem::jacobian`]), by block
    /// (len `n_blocks`, or empty: none). They are not perturbed, but still count as
    /// neighbours in the colouring (two perturbed blocks that share one are coloured apart).
    pub analytic: Vec<bool>,
}

/// How a [`DaeSystem::residual`] evaluation failed.
#[derive(thiserror::Error, Debug, Clone, PartialEq)]
pub(crate) enum ResidualError {
    /// The residual cannot be evaluated at this point (e.g. outside a model's domain); IDA
    /// retries the step with a smaller step size.
    #[error("recoverable residual error: IDA should retry with a smaller step")]
    Recoverable,
    /// The residual cannot be evaluated at all; the integration stops with this message.
    #[error("fatal residual error: {0}")]
    Fatal(String),
}

/// What [`Ida::solve`] reached.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) enum SolveStatus {
    /// The requested output time (or, in one-step mode, the end of one internal step) was
    /// reached; `t` \[s\] is the time of [`Ida::y`] (IDA_SUCCESS).
    Reached {
        /// Time of the returned solution \[s\].
        t: f64,
    },
    /// The stop time set with [`Ida::set_stop_time`] was reached (IDA_TSTOP_RETURN).
    StopTime {
        /// Time of the returned solution, equal to the stop time \[s\].
        t: f64,
    },
    /// A root function changed sign; see [`Ida::root_info`] for which (IDA_ROOT_RETURN).
    Root {
        /// Time of the located root \[s\].
        t: f64,
    },
}

impl SolveStatus {
    /// Time of the returned solution \[s\], whatever the status.
    pub(crate) fn t(&self) -> f64 {
        match *self {
            SolveStatus::Reached { t } | SolveStatus::StopTime { t } | SolveStatus::Root { t } => t,
        }
    }
}
