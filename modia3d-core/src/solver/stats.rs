//! Solver stage: integrator statistics (plain data, no FFI).
//!
//! May touch only the standard library; [`super::ida`] fills these from the IDA counters and
//! accumulates them across re-initialisations.

use std::ops::{Add, AddAssign};

/// Counters of an IDA integration, accumulated over the whole run (IDA itself resets its
/// counters at every re-initialisation; these do not): `SimStats::solver` of a result.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct IdaStats {
    /// Internal steps taken.
    pub steps: u64,
    /// Residual evaluations, not counting those for difference-quotient Jacobians.
    pub residual_evals: u64,
    /// Jacobian evaluations (matrix set-ups).
    pub jacobian_evals: u64,
    /// Of `jacobian_evals`, those formed from the last difference-quotient Jacobian's parts
    /// `∂F/∂y` and `∂F/∂y'` for a new `c_j` (no residual evaluations: the system's
    /// `yp_jacobian`).
    pub jacobian_reuses: u64,
    /// Residual evaluations spent on difference-quotient Jacobians.
    pub residual_evals_for_jacobian: u64,
    /// Local error test failures.
    pub error_test_failures: u64,
    /// Nonlinear (Newton) iterations.
    pub nonlinear_iterations: u64,
    /// Nonlinear convergence failures.
    pub nonlinear_convergence_failures: u64,
    /// Root function evaluations.
    pub root_evals: u64,
    /// Size of the last internal step taken \[s\] (0 before the first step).
    pub last_step: f64,
    /// Order of the last internal step taken (0 before the first step).
    pub last_order: i32,
}

impl Add for IdaStats {
    type Output = IdaStats;

    /// Adds the counters; `last_step` and `last_order` are those of `rhs` (the later segment of a
    /// run) unless `rhs` has taken no step yet, in which case those of `self` are kept.
    fn add(self, rhs: IdaStats) -> IdaStats {
        let (last_step, last_order) = if rhs.steps > 0 {
            (rhs.last_step, rhs.last_order)
        } else {
            (self.last_step, self.last_order)
        };
        IdaStats {
            steps: self.steps + rhs.steps,
            residual_evals: self.residual_evals + rhs.residual_evals,
            jacobian_evals: self.jacobian_evals + rhs.jacobian_evals,
            jacobian_reuses: self.jacobian_reuses + rhs.jacobian_reuses,
            residual_evals_for_jacobian: self.residual_evals_for_jacobian
                + rhs.residual_evals_for_jacobian,
            error_test_failures: self.error_test_failures + rhs.error_test_failures,
            nonlinear_iterations: self.nonlinear_iterations + rhs.nonlinear_iterations,
            nonlinear_convergence_failures: self.nonlinear_convergence_failures
                + rhs.nonlinear_convergence_failures,
            root_evals: self.root_evals + rhs.root_evals,
            last_step,
            last_order,
        }
    }
}

impl AddAssign for IdaStats {
    fn add_assign(&mut self, rhs: IdaStats) {
        *self = *self + rhs;
    }
}
