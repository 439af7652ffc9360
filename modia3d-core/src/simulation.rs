//! Simulation driver: [`Simulation`] runs the DAE of a model with IDA from the start to the
//! stop time, records output points, handles events, and returns results — or, on failure, an
//! error that carries the results up to the failure. [`SimOptions`] and [`SimError`] live here;
//! [`Model::simulate`](crate::Model::simulate) is `Simulation::new` + `advance_to(stop_time)`.

use crate::contact::ContactError;
use crate::dae::MultibodyDae;
use crate::model::Model;
use crate::results::Event;
use crate::results::{SimStats, SimulationResult};
use crate::solver::{Atol, Ida, IdaError, IdaOptions, SolveStatus};
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
    /// Show a progress bar for [`Model::simulate`] when standard error is a terminal (default
    /// true; never shown when it is not a terminal, e.g. in tests and CI).
    pub progress: bool,
    /// Record per-pair contact signals (penetration, forces, torque, point, normal) at every
    /// output point (default false: a run pays only for what it asks for).
    pub contact_results: bool,
    /// Form IDA's Jacobian by difference quotients coloured by the scene's independent joint
    /// trees and their current contacts (default true): a scene of many free bodies then costs
    /// a few residual evaluations per Jacobian instead of one per state. False = IDA's dense
    /// difference quotients (for comparison; the results agree to the tolerance).
    pub structured_jacobian: bool,
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
            progress: true,
            structured_jacobian: true,
        }
    }
    /// Uses (true, the default) or not the coloured Jacobian (see
    /// [`SimOptions::structured_jacobian`]).
    pub fn structured_jacobian(mut self, on: bool) -> Self {
        self.structured_jacobian = on;
        self
    }
    /// Records per-pair contact signals (`"<a>|<b>.f_n"`, … see
    /// [`SimulationResult::signal`]).
    pub fn contact_results(mut self, on: bool) -> Self {
        self.contact_results = on;
        self
    }
    /// Shows (true, the default on a terminal) or hides the progress bar of `simulate`.
    pub fn progress(mut self, on: bool) -> Self {
        self.progress = on;
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

/// `model.simulate(opts)`: a [`Simulation`] advanced to the stop time, with a progress bar on
/// a terminal.
pub(crate) fn run(model: &Model, opts: &SimOptions) -> Result<SimulationResult, SimError> {
    let mut sim = Simulation::new(model, opts)?;
    use std::io::IsTerminal;
    if opts.progress && std::io::stderr().is_terminal() {
        let bar = indicatif::ProgressBar::new(1000);
        bar.set_style(
            indicatif::ProgressStyle::with_template("{bar:40} {percent:>3}% {msg}")
                .unwrap_or_else(|_| indicatif::ProgressStyle::default_bar()),
        );
        sim.progress = Some(bar);
    }
    tracing::info!(
        stop_time = opts.stop_time,
        rtol = opts.rtol,
        states = model.plan.nq + model.plan.nv,
        "simulation started"
    );
    let outcome = sim.advance_to(opts.stop_time);
    if let Some(bar) = sim.progress.take() {
        bar.finish_and_clear();
    }
    outcome?;
    let s = &sim.result.stats;
    tracing::info!(
        steps = s.solver.steps,
        events = s.events,
        wall_time = s.wall_time,
        "simulation finished"
    );
    Ok(sim.into_result())
}

/// A wrong use of inputs.
#[derive(thiserror::Error, Debug, Clone, PartialEq)]
pub enum InputError {
    /// No input of that name.
    #[error("unknown input `{name}`{}", match .hint { Some(h) => format!(" (hint: did you mean `{h}`?)"), None => " (declare it with SceneDesc::add_input)".into() })]
    Unknown {
        /// The name given.
        name: String,
        /// A close existing name.
        hint: Option<String>,
    },
    /// Wrong number of values.
    #[error("input `{name}` takes {expected} value(s), got {got}")]
    Length {
        /// The input.
        name: String,
        /// Its number of values.
        expected: usize,
        /// The number given.
        got: usize,
    },
    /// A NaN or infinite value.
    #[error("input `{name}` got a non-finite value {value}: inputs must be finite")]
    NotFinite {
        /// The input.
        name: String,
        /// The value.
        value: f64,
    },
}

/// A simulation advanced step by step from Rust: error-controlled integration (events
/// handled) up to each requested time, inputs set between steps, outputs read by name.
/// [`Model::simulate`] is `Simulation::new` + `advance_to(stop_time)`.
///
/// Output points are recorded at every multiple of the output interval, at every event and at
/// every time passed to [`Simulation::advance_to`].
pub struct Simulation {
    model: Model,
    opts: SimOptions,
    ida: Ida<MultibodyDae>,
    result: SimulationResult,
    /// Index of the next output-grid point.
    k_grid: u64,
    /// Inputs changed since the last restart: the next step restarts IDA.
    inputs_changed: bool,
    stalled: u32,
    last_event_t: f64,
    wall: f64,
    /// Progress bar of a one-shot run on a terminal.
    progress: Option<indicatif::ProgressBar>,
}

impl std::fmt::Debug for Simulation {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Simulation")
            .field("t", &self.time())
            .field("stop_time", &self.opts.stop_time)
            .finish_non_exhaustive()
    }
}

impl Simulation {
    /// Prepares a run of `model` with `opts`: validates the options, computes consistent
    /// initial values (initial contact set included) and records the start point.
    pub fn new(model: &Model, opts: &SimOptions) -> Result<Self, SimError> {
        let started = Instant::now();
        let plan = model.plan.clone();
        let mut result = SimulationResult::new(model.clone());
        let fail = |kind: SimErrorKind, partial: SimulationResult| SimError {
            kind,
            partial: Box::new(partial),
        };
        if let Err(msg) = opts.check() {
            return Err(fail(SimErrorKind::InvalidOptions(msg), result));
        }
        if opts.contact_results {
            result.enable_contact_record();
        }
        let t0 = opts.start_time;
        let mut dae = MultibodyDae::new(plan.clone(), model.contact.clone());
        let y0 = plan.y0();
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
            structured_jacobian: opts.structured_jacobian,
            ..IdaOptions::default()
        };
        record(&mut dae, &mut result, t0, &y0, opts.contact_results);
        let ida = match Ida::new(dae, t0, &y0, &yp0, &ida_opts) {
            Ok(ida) => ida,
            Err(e) => return Err(fail(e.into(), result)),
        };
        result.stats.root_functions = root_functions;
        let mut sim = Simulation {
            model: model.clone(),
            opts: opts.clone(),
            ida,
            result,
            k_grid: 1,
            inputs_changed: false,
            stalled: 0,
            last_event_t: f64::NEG_INFINITY,
            wall: 0.0,
            progress: None,
        };
        sim.wall = started.elapsed().as_secs_f64();
        sim.update_stats();
        Ok(sim)
    }

    /// Current time [s].
    pub fn time(&self) -> f64 {
        self.ida.t()
    }

    /// Current state `y = [q; v]`.
    pub fn state(&self) -> &[f64] {
        self.ida.y()
    }

    /// The results recorded so far.
    pub fn result(&self) -> &SimulationResult {
        &self.result
    }

    /// The results recorded so far, ending the simulation.
    pub fn into_result(self) -> SimulationResult {
        self.result
    }

    /// Integrates with error control to `t` [s] (at most the stop time), handling events and
    /// recording output points. On failure the error carries the results up to the failure; the
    /// simulation can then only be [`reset`](Self::reset).
    pub fn advance_to(&mut self, t: f64) -> Result<(), SimError> {
        let started = Instant::now();
        let outcome = self.advance(t);
        self.wall += started.elapsed().as_secs_f64();
        self.update_stats();
        outcome.map_err(|kind| SimError {
            kind,
            partial: Box::new(self.result.clone()),
        })
    }

    fn update_stats(&mut self) {
        let (narrow, aabb) = self
            .ida
            .system()
            .contact()
            .map(|c| (c.narrow_calls, c.aabb_tests))
            .unwrap_or((0, 0));
        self.result.stats = SimStats {
            solver: self.ida.stats(),
            events: self.result.events.len() as u64,
            root_functions: self.result.stats.root_functions,
            narrow_phase_calls: narrow,
            aabb_tests: aabb,
            wall_time: self.wall,
        };
    }

    fn advance(&mut self, target: f64) -> Result<(), SimErrorKind> {
        let (t0, t1) = (self.opts.start_time, self.opts.stop_time);
        let now = self.time();
        let eps = 1e-12 * t1.abs().max(1.0);
        if !(target.is_finite() && target >= now - eps && target <= t1 + eps) {
            return Err(SimErrorKind::InvalidOptions(format!(
                "advance_to({target} s): the target must lie between the current time {now} s and the stop time {t1} s"
            )));
        }
        let target = target.min(t1);
        if target <= now {
            return Ok(());
        }
        let contacts = self.opts.contact_results;
        if self.inputs_changed {
            // Inputs are piecewise constant: restart with derivatives consistent with them.
            self.restart(now)?;
            self.inputs_changed = false;
        }
        let dt = self.opts.interval.unwrap_or((t1 - t0) / 500.0);
        self.ida.set_stop_time(target)?;
        loop {
            let grid = t0 + self.k_grid as f64 * dt;
            let on_grid = grid < target - eps;
            let t_out = if on_grid { grid } else { target };
            let status = self.ida.solve(t_out, false)?;
            if let Some(e) = self.ida.system_mut().take_root_error() {
                return Err(e.into());
            }
            match status {
                SolveStatus::Reached { t } | SolveStatus::StopTime { t } => {
                    let y = self.ida.y().to_vec();
                    record(self.ida.system_mut(), &mut self.result, t, &y, contacts);
                    if let Some(bar) = &self.progress {
                        bar.set_position((1000.0 * (t - t0) / (t1 - t0)) as u64);
                        bar.set_message(format!("t = {t:.4} s"));
                    }
                    if (grid - t).abs() <= eps {
                        self.k_grid += 1;
                    }
                    if !on_grid {
                        return Ok(());
                    }
                }
                SolveStatus::Root { t } => self.event(t)?,
            }
        }
    }

    /// Event at `t`: rebuild the contact set, log it, restart with consistent derivatives.
    fn event(&mut self, t: f64) -> Result<(), SimErrorKind> {
        let y = self.ida.y().to_vec();
        let dae = self.ida.system_mut();
        let changed = dae.handle_event(t, &y)?;
        let (started, ended) = dae.event_pairs();
        if !changed && t <= self.last_event_t {
            self.stalled += 1;
            if self.stalled > 20 {
                return Err(SimErrorKind::EventLoop {
                    t,
                    count: self.stalled,
                });
            }
        } else {
            self.stalled = 0;
        }
        self.last_event_t = t;
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
        let description = words.join("; ");
        tracing::debug!(t, %description, "event");
        self.result.events.push(Event {
            t,
            description,
            started,
            ended,
        });
        let contacts = self.opts.contact_results;
        record(self.ida.system_mut(), &mut self.result, t, &y, contacts);
        self.restart(t)
    }

    /// Re-initialises IDA at `t` with the current `y` and a consistent `y'`.
    fn restart(&mut self, t: f64) -> Result<(), SimErrorKind> {
        let y = self.ida.y().to_vec();
        let Some(yp) = self.ida.system_mut().consistent_derivative(t, &y) else {
            return Err(SimErrorKind::Inconsistent { t });
        };
        self.ida.reinit(t, &y, &yp)?;
        Ok(())
    }

    /// Names of the declared inputs.
    pub fn input_names(&self) -> Vec<&str> {
        self.model
            .plan
            .inputs
            .iter()
            .map(|i| i.name.as_str())
            .collect()
    }

    /// Sets input `name` to `values` (1 value for joint inputs, 6 for an object wrench: force
    /// [N] then torque [N·m], resolved in world). Takes effect from the current time on.
    pub fn set_input(&mut self, name: &str, values: &[f64]) -> Result<(), InputError> {
        let Some(inp) = self.model.plan.inputs.iter().find(|i| i.name == name) else {
            return Err(InputError::Unknown {
                name: name.into(),
                hint: crate::scene::did_you_mean(
                    name,
                    self.model.plan.inputs.iter().map(|i| i.name.as_str()),
                ),
            });
        };
        if values.len() != inp.len {
            return Err(InputError::Length {
                name: name.into(),
                expected: inp.len,
                got: values.len(),
            });
        }
        if let Some(&value) = values.iter().find(|v| !v.is_finite()) {
            return Err(InputError::NotFinite {
                name: name.into(),
                value,
            });
        }
        let (off, len) = (inp.offset, inp.len);
        let slot = &mut self.ida.system_mut().inputs_mut()[off..off + len];
        if slot != values {
            slot.copy_from_slice(values);
            self.inputs_changed = true;
        }
        Ok(())
    }

    /// The current value of a signal (same names as [`SimulationResult::signal`]; contact
    /// signals need [`SimOptions::contact_results`]).
    pub fn output(&mut self, name: &str) -> Result<Vec<f64>, crate::results::ResultError> {
        let t = self.time();
        let y = self.ida.y().to_vec();
        let mut now = SimulationResult::new(self.model.clone());
        if self.opts.contact_results {
            now.enable_contact_record();
        }
        record(
            self.ida.system_mut(),
            &mut now,
            t,
            &y,
            self.opts.contact_results,
        );
        Ok(now.signal(name)?.last().to_vec())
    }

    /// Back to the initial state and zero inputs, with the recorded results cleared; the plan
    /// is reused (no recompilation).
    pub fn reset(&mut self) -> Result<(), SimError> {
        let model = self.model.clone();
        *self = Simulation::new(&model, &self.opts)?;
        Ok(())
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
