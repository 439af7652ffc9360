//! Simulation driver: `Model::simulate` runs the DAE of a plan with IDA from the start to the
//! stop time, records output points, handles events, and returns results — or, on failure, an
//! error that carries the results up to the failure.

use crate::contact::ContactError;
use crate::dae::MultibodyDae;
use crate::dynamics::Plan;
use crate::results::Event;
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
    /// Record per-pair contact signals (penetration, forces, torque, point, normal) at every
    /// output point (default false: a run pays only for what it asks for).
    pub contact_results: bool,
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
            contact_results: false,
        }
    }
    /// Records per-pair contact signals (`"<a>|<b>.f_n"`, … see
    /// [`SimulationResult::signal`]).
    pub fn contact_results(mut self, on: bool) -> Self {
        self.contact_results = on;
        self
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
    /// The collision stage failed.
    #[error(transparent)]
    Contact(#[from] ContactError),
    /// Events follow each other without progress in time (a chattering contact).
    #[error("{count} events at t = {t} s without the contact set changing or time advancing: a contact chatters; raise the hysteresis or loosen the tolerance")]
    EventLoop {
        /// Time [s].
        t: f64,
        /// Events without progress.
        count: u32,
    },
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
        // The initial contact set (event mode), then consistent derivatives including contacts.
        if let Err(e) = dae.handle_event(t0, &y0) {
            return Err(fail(e.into(), result));
        }
        let Some(yp0) = dae.consistent_derivative(t0, &y0) else {
            return Err(fail(SimErrorKind::Inconsistent { t: t0 }, result));
        };
        let root_functions = dae.num_roots_public();
        let ida_opts = IdaOptions {
            rtol: opts.rtol,
            atol: Atol::Scalar(opts.atol.unwrap_or(0.01 * opts.rtol)),
            max_step: opts.max_step,
            // z_1 matters when it rises (a contact ends), z_2 when it falls (one starts).
            root_directions: (root_functions == 2).then(|| vec![1, -1]),
            ..IdaOptions::default()
        };
        if opts.contact_results {
            result.enable_contact_record();
        }
        record(&mut dae, &mut result, t0, &y0, opts.contact_results);
        let mut ida = match Ida::new(dae, t0, &y0, &yp0, &ida_opts) {
            Ok(ida) => ida,
            Err(e) => return Err(fail(e.into(), result)),
        };
        let outcome = run(&mut ida, &mut result, t0, t1, dt, opts.contact_results);
        let (narrow, aabb) = ida
            .system()
            .contact()
            .map(|c| (c.narrow_calls, c.aabb_tests))
            .unwrap_or((0, 0));
        result.stats = SimStats {
            solver: ida.stats(),
            events: result.events.len() as u64,
            root_functions,
            narrow_phase_calls: narrow,
            aabb_tests: aabb,
            wall_time: started.elapsed().as_secs_f64(),
        };
        match outcome {
            Ok(()) => Ok(result),
            Err(kind) => Err(fail(kind, result)),
        }
    }
}

/// Stores an output point (and, if asked for, the contact signals at it).
fn record(
    dae: &mut MultibodyDae,
    result: &mut SimulationResult,
    t: f64,
    y: &[f64],
    contacts: bool,
) {
    result.push(t, y);
    if contacts {
        // Output values only: a failure here shows up in the next residual anyway.
        let _ = dae.update_contacts(t, y);
        if let Some(cs) = dae.contact() {
            result.push_contacts(cs);
        }
    }
}

fn run(
    ida: &mut Ida<MultibodyDae>,
    result: &mut SimulationResult,
    t0: f64,
    t1: f64,
    dt: f64,
    contacts: bool,
) -> Result<(), SimErrorKind> {
    ida.set_stop_time(t1)?;
    let mut k = 1u64;
    let mut stalled = 0u32;
    let mut last_event_t = f64::NEG_INFINITY;
    loop {
        let t_out = (t0 + k as f64 * dt).min(t1);
        let status = ida.solve(t_out, false)?;
        if let Some(e) = ida.system_mut().take_root_error() {
            return Err(e.into());
        }
        match status {
            SolveStatus::Reached { t } | SolveStatus::StopTime { t } => {
                let y = ida.y().to_vec();
                record(ida.system_mut(), result, t, &y, contacts);
                if t >= t1 - 1e-12 * t1.abs().max(1.0) {
                    return Ok(());
                }
                k += 1;
            }
            SolveStatus::Root { t } => {
                // Event: rebuild the contact set, restart with consistent derivatives.
                let y = ida.y().to_vec();
                let dae = ida.system_mut();
                let changed = dae.handle_event(t, &y)?;
                let (started, ended) = dae.event_pairs();
                let Some(yp) = dae.consistent_derivative(t, &y) else {
                    return Err(SimErrorKind::Inconsistent { t });
                };
                if !changed && t <= last_event_t {
                    stalled += 1;
                    if stalled > 20 {
                        return Err(SimErrorKind::EventLoop { t, count: stalled });
                    }
                } else {
                    stalled = 0;
                }
                last_event_t = t;
                let mut words = vec![];
                if !started.is_empty() {
                    words.push(format!("contact started: {}", started.join(", ")));
                }
                if !ended.is_empty() {
                    words.push(format!("contact ended: {}", ended.join(", ")));
                }
                if words.is_empty() {
                    words.push("root without a change of the contact set".into());
                }
                result.events.push(Event {
                    t,
                    description: words.join("; "),
                    started,
                    ended,
                });
                record(ida.system_mut(), result, t, &y, contacts);
                ida.reinit(t, &y, &yp)?;
            }
        }
    }
}
