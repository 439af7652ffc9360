//! Simulation driver: `Model::simulate` runs the DAE of a plan with IDA from the start to the
//! stop time, records output points, handles events, and returns results — or, on failure, an
//! error that carries the results up to the failure.

use crate::dae::MultibodyDae;
use crate::dynamics::Plan;
use crate::results::{SimStats, SimulationResult};
use crate::scene::{SceneDesc, SceneErrors};
use crate::solver::{Atol, Ida, IdaError, IdaOptions, SolveStatus};
use std::sync::Arc;
use std::time::Instant;

/// Options of a simulation run. Build with [`SimOptions::new`] and the setters.
#[derive(Clone, Debug, PartialEq)]
pub struct SimOptions {
    /// Start time [s] (default 0).
    pub start_time: f64,
    /// Stop time [s].
    pub stop_time: f64,
    /// Output interval [s]; default: 500 intervals over the run.
    pub interval: Option<f64>,
    /// Relative tolerance (default 1e-6).
    pub rtol: f64,
    /// Absolute tolerance; default `0.01 · rtol` (the states are in m, rad, m/s, rad/s).
    pub atol: Option<f64>,
    /// Largest step [s]; default unlimited.
    pub max_step: Option<f64>,
}

impl SimOptions {
    /// Options for a run from 0 to `stop_time` [s] with defaults otherwise.
    pub fn new(stop_time: f64) -> Self {
        SimOptions {
            start_time: 0.0,
            stop_time,
            interval: None,
            rtol: 1e-6,
            atol: None,
            max_step: None,
        }
    }
    /// Sets the relative tolerance.
    pub fn tolerance(mut self, rtol: f64) -> Self {
        self.rtol = rtol;
        self
    }
    /// Sets the absolute tolerance.
    pub fn atol(mut self, atol: f64) -> Self {
        self.atol = Some(atol);
        self
    }
    /// Sets the output interval [s].
    pub fn interval(mut self, dt: f64) -> Self {
        self.interval = Some(dt);
        self
    }
    /// Sets the largest step [s].
    pub fn max_step(mut self, h: f64) -> Self {
        self.max_step = Some(h);
        self
    }
    /// Sets the start time [s].
    pub fn start_time(mut self, t0: f64) -> Self {
        self.start_time = t0;
        self
    }

    fn check(&self) -> Result<(), String> {
        let finite = |x: f64| x.is_finite();
        if !finite(self.start_time) || !finite(self.stop_time) || self.stop_time <= self.start_time
        {
            return Err(format!(
                "stop time {} s must be finite and after the start time {} s",
                self.stop_time, self.start_time
            ));
        }
        if !(self.rtol > 0.0 && self.rtol < 1.0) {
            return Err(format!("tolerance {} must be in (0, 1)", self.rtol));
        }
        if let Some(a) = self.atol {
            if !(a > 0.0 && finite(a)) {
                return Err(format!("absolute tolerance {a} must be finite and > 0"));
            }
        }
        if let Some(dt) = self.interval {
            if !(dt > 0.0 && finite(dt)) {
                return Err(format!("output interval {dt} s must be finite and > 0"));
            }
        }
        if let Some(h) = self.max_step {
            if h.is_nan() || h <= 0.0 {
                return Err(format!("max step {h} s must be > 0"));
            }
        }
        Ok(())
    }
}

/// Why a simulation failed.
#[derive(thiserror::Error, Debug, Clone, PartialEq)]
pub enum SimErrorKind {
    /// The options are inconsistent.
    #[error("invalid simulation options: {0}")]
    InvalidOptions(String),
    /// No consistent initial accelerations (singular mass matrix).
    #[error("no consistent accelerations at t = {t} s: the mass matrix is singular; check the masses and inertias of moving bodies")]
    Inconsistent {
        /// Time [s].
        t: f64,
    },
    /// The integrator failed.
    #[error(transparent)]
    Solver(#[from] IdaError),
}

/// A failed simulation: what went wrong, and the results computed up to the failure.
#[derive(thiserror::Error, Debug, Clone)]
#[error("simulation failed: {kind}")]
pub struct SimError {
    /// What went wrong.
    pub kind: SimErrorKind,
    /// Results up to the failure.
    pub partial: Box<SimulationResult>,
}

/// A compiled, runnable model. Cheap to clone; runs share the immutable plan.
#[derive(Clone, Debug)]
pub struct Model {
    plan: Arc<Plan>,
}

impl SceneDesc {
    /// Validates and compiles the scene into a runnable model.
    pub fn build(&self) -> Result<Model, SceneErrors> {
        let valid = self.validate()?;
        Ok(Model {
            plan: Arc::new(Plan::compile(valid)?),
        })
    }
}

impl Model {
    /// The compiled plan.
    pub fn plan(&self) -> &Plan {
        &self.plan
    }

    /// Runs the model with error control from `opts.start_time` to `opts.stop_time`.
    pub fn simulate(&self, opts: &SimOptions) -> Result<SimulationResult, SimError> {
        let mut result = SimulationResult::new(self.plan.clone());
        let fail = |kind: SimErrorKind, partial: SimulationResult| SimError {
            kind,
            partial: Box::new(partial),
        };
        if let Err(msg) = opts.check() {
            return Err(fail(SimErrorKind::InvalidOptions(msg), result));
        }
        let started = Instant::now();
        let (t0, t1) = (opts.start_time, opts.stop_time);
        let dt = opts.interval.unwrap_or((t1 - t0) / 500.0);
        let mut dae = MultibodyDae::new(self.plan.clone());
        let y0 = self.plan.y0();
        let Some(yp0) = dae.consistent_derivative(t0, &y0) else {
            return Err(fail(SimErrorKind::Inconsistent { t: t0 }, result));
        };
        let ida_opts = IdaOptions {
            rtol: opts.rtol,
            atol: Atol::Scalar(opts.atol.unwrap_or(0.01 * opts.rtol)),
            max_step: opts.max_step,
            ..IdaOptions::default()
        };
        result.push(t0, &y0);
        let mut ida = match Ida::new(dae, t0, &y0, &yp0, &ida_opts) {
            Ok(ida) => ida,
            Err(e) => return Err(fail(e.into(), result)),
        };
        let outcome = run(&mut ida, &mut result, t0, t1, dt);
        result.stats = SimStats {
            solver: ida.stats(),
            events: result.events.len() as u64,
            root_functions: 0,
            wall_time: started.elapsed().as_secs_f64(),
        };
        match outcome {
            Ok(()) => Ok(result),
            Err(kind) => Err(fail(kind, result)),
        }
    }
}

fn run(
    ida: &mut Ida<MultibodyDae>,
    result: &mut SimulationResult,
    t0: f64,
    t1: f64,
    dt: f64,
) -> Result<(), SimErrorKind> {
    ida.set_stop_time(t1)?;
    let mut k = 1u64;
    loop {
        let t_out = (t0 + k as f64 * dt).min(t1);
        match ida.solve(t_out, false)? {
            SolveStatus::Reached { t } | SolveStatus::StopTime { t } => {
                result.push(t, ida.y());
                if t >= t1 - 1e-12 * t1.abs().max(1.0) {
                    return Ok(());
                }
                k += 1;
            }
            SolveStatus::Root { t } => {
                // No root functions yet (contacts add them); record and go on.
                result.push(t, ida.y());
            }
        }
    }
}
