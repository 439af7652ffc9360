//! Run options: [`SimOptions`] with its setters and the range check done before every run
//! (docs/options.md), and the budget constants of the driver.
#![deny(clippy::indexing_slicing)]

/// Default [`SimOptions::max_steps`]: IDA steps per run, all restarts included.
pub const DEFAULT_MAX_STEPS: u64 = 1_000_000;
/// Largest number of output-grid points of a run (`(stop − start)/interval`).
pub const MAX_OUTPUT_POINTS: f64 = 1e7;
/// Chattering guard: this many consecutive events within
/// [`CHATTER_SPAN`]` · (stop − start)` end the run with [`SimErrorKind::Chattering`](crate::SimErrorKind::Chattering).
pub const CHATTER_EVENTS: usize = 100;
/// Chattering guard: relative time span (see [`CHATTER_EVENTS`]).
pub const CHATTER_SPAN: f64 = 1e-6;

/// Options of a simulation run. Build with [`SimOptions::new`] and the setters.
#[derive(Clone, Debug, PartialEq)]
pub struct SimOptions {
    /// Start time \[s\] (default 0).
    pub start_time: f64,
    /// Stop time \[s\].
    pub stop_time: f64,
    /// Output interval \[s\]; default: 500 intervals over the run.
    pub interval: Option<f64>,
    /// Relative tolerance (default 1e-6).
    pub rtol: f64,
    /// Absolute tolerance; default `0.01 · rtol` (the states are in m, rad, m/s, rad/s), or
    /// `0.1 · rtol` with Modia3D conventions ([`SimOptions::effective_atol`]).
    pub atol: Option<f64>,
    /// Largest step \[s\]; default unlimited.
    pub max_step: Option<f64>,
    /// Show a progress bar for [`Model::simulate`](crate::Model::simulate) when standard error is a terminal (default
    /// true; never shown when it is not a terminal, e.g. in tests and CI).
    pub progress: bool,
    /// Record per-pair contact signals (penetration, forces, torque, point, normal) at every
    /// output point (default false: a run pays only for what it asks for).
    pub contact_results: bool,
    /// With [`SimOptions::contact_results`]: also measure every contact phase on the solver's
    /// steps (default true): its impulses, maxima and restitution, read by
    /// [`SimulationResult::contacts`](crate::SimulationResult::contacts) and
    /// [`SimulationResult::contact_phases`](crate::SimulationResult::contact_phases).
    /// The measurement evaluates the contacts three times per step (the quadrature of
    /// `simulation/contact_phases.rs`); false records only the per-pair signals at the output
    /// points. Measured on a stack of three wooden cubes at rest (0.5 s, rtol 1e-2, 56 steps,
    /// 50 output points): 1.5 ms with the phases, 0.8 ms without (BENCHMARKS.md, "Face
    /// contacts").
    pub contact_phases: bool,
    /// Also record an output point after every solver step (default false), so that contacts
    /// shorter than the output interval show in the signals and plots; events are always
    /// recorded.
    pub output_steps: bool,
    /// Keep IDA's interpolating polynomial of every step (default false), so that
    /// [`SimulationResult::signal_at`](crate::SimulationResult::signal_at) evaluates joint and
    /// object signals at any time with the solver's own interpolant (its order, its accuracy)
    /// instead of a cubic through the output points. Costs `(q + 1)·n` values per step (q ≤ 5,
    /// n the number of unknowns).
    pub dense_output: bool,
    /// Form IDA's Jacobian by difference quotients coloured by the scene's independent joint
    /// trees and their current contacts (default true): a scene of many free bodies then costs
    /// a few residual evaluations per Jacobian instead of one per state. False = IDA's dense
    /// difference quotients (for comparison; the results agree to the tolerance).
    pub structured_jacobian: bool,
    /// With the coloured Jacobian: a new iteration matrix for a new `c_j = α/h` (IDA asks for
    /// one whenever `c_j` moves by more than 25 %, after every failed error test) is formed
    /// from the last one's parts `∂F/∂y` and `∂F/∂y'`, with no residual evaluations, until
    /// Newton's method fails to converge (default true). Newton's convergence, not the
    /// accuracy, depends on it; false = new difference quotients every time (for comparison).
    pub jacobian_reuse: bool,
    /// With the coloured Jacobian: the DAE computes the columns of the joint trees it can
    /// differentiate itself — a free body with its contacts, a tree of hinges — and the solver
    /// forms only the rest by coloured difference quotients (default true). False = every
    /// block by the coloured quotients, as before those columns existed (for comparison:
    /// `tests/jacobian_analytic.rs`, `examples/drag_billiards.rs`, `examples/hinge_chain.rs`);
    /// Newton's convergence, not the accuracy, depends on it.
    pub analytic_jacobian: bool,
    /// With the coloured Jacobian: factor every component of the iteration matrix densely
    /// (true) instead of choosing dense or block-sparse per component by its estimated cost
    /// (false, the default; for comparison: `examples/ball_pit.rs`). The results agree to
    /// rounding; only the time differs.
    pub dense_lu: bool,
    /// Start the components in steady state (default false: their states start at their
    /// given values): the components' states and the coordinates their flanges drive are
    /// solved for `ẋ = 0` and `q̈ = 0` with `q̇ = 0` (Newton's method on the consistent
    /// derivatives), so a servo starts holding its load against gravity (docs/drive-trains.md).
    pub steady_state: bool,
    /// Start bodies placed resting on one another pressed in by their load (default true):
    /// the pairs of the initial contact set under the volume law whose bodies are at rest
    /// along the normal start at the depth where the normal component of their relative
    /// acceleration is zero, the force a rigid contact would carry there, by moving the
    /// translations of the bodies' free joints (by the static depth, ~1e-8 m for a wooden
    /// cube on a table). At zero depth the compliant contact first rings about that depth
    /// for ~1 ms, which the error test resolves: a stack of three wooden cubes resting for
    /// 0.5 s took 56 IDA steps at rtol 1e-2 from zero depth and 11 preloaded (BENCHMARKS.md,
    /// "Face contacts"). Pairs with a sphere (the paper's law) start as given; so does
    /// everything when the preload finds no solution near the given positions
    /// (`simulation/preload.rs`). False = the given positions exactly.
    pub preload_contacts: bool,
    /// Work budget: IDA steps over the whole run, every restart included (default
    /// [`DEFAULT_MAX_STEPS`]; `None` = unlimited). Reaching it ends the run with
    /// [`SimErrorKind::WorkBudget`](crate::SimErrorKind::WorkBudget), whose diagnosis names the limiting cause.
    pub max_steps: Option<u64>,
    /// Work budget: wall time \[s\] of the run (default `None` = unlimited); checked every
    /// few thousand steps and at every output point and event.
    pub max_wall_time: Option<f64>,
    /// How many times tighter than `rtol`/`atol` the error test is, at rtol 1e-6, for the
    /// unknowns of the joint trees of bodies in contact (pairs in the contact set), for as long
    /// as the contact lasts (default [`DEFAULT_CONTACT_TIGHTENING`] = 100; 1 = IDA's own
    /// weights throughout). The factor used is `contact_tightening·(1e-6/rtol)^(1/6)`, at
    /// least `rtol/`[`LOOSEST_CONTACT_RTOL`] (so loose tolerances still resolve contacts) and
    /// capped so that `rtol/factor ≥ 1e-13`. Why: IDA bounds the error of each step, and an impact
    /// takes 30–300 steps (more at tighter rtol, as `rtol^(−1/6)`), so a rebound speed carried
    /// the error of all of them (contact times of a steel ball off by 6–276 × rtol over rtol
    /// 1e-4…1e-10; now within 1.2·rtol); and a resting or rolling contact's force depends on a
    /// penetration of ~1e-6 m that IDA's position tolerance `rtol·|r|` did not resolve at loose
    /// rtol (balls hopped on the table at 1e-3). See docs/contact-model.md §5 and
    /// `tests/contact_times.rs`. When IDA's error test then fails repeatedly (`IDA_ERR_FAIL`),
    /// the run goes on from IDA's last step with the factor divided by 10 (down to 1) and the
    /// warning `SimWarning::ContactTighteningRelaxed`. Range `[1, 1e6]`.
    pub contact_tightening: f64,
    /// Keep the run's warnings ([`SimulationResult::warnings`](crate::SimulationResult::warnings))
    /// off standard error (default false). By default a run prints the warnings it finds to
    /// standard error once (each warning once, when [`Simulation::advance_to`](crate::Simulation::advance_to)
    /// returns) when no `tracing` subscriber is installed; with a subscriber they reach it
    /// through `tracing::warn!` instead and are not printed. Runs of a
    /// [`Sweep`](crate::Sweep) are always quiet. The warnings stay in `result.warnings`.
    /// A quiet run also leaves out the notice of an unoptimised build
    /// ([`build_profile`](crate::build_profile)), which the first run of a process that is not
    /// quiet gives once.
    pub quiet: bool,
}

/// Default of [`SimOptions::contact_tightening`]: an impact of ~100 steps then ends with the
/// error of about one step at `rtol`.
pub const DEFAULT_CONTACT_TIGHTENING: f64 = 100.0;

/// The loosest relative tolerance of the unknowns of bodies in contact while the contact
/// tightening is on: at rtol 1e-2 the scaled factor (22×) left 4.6e-4, and a steel ball
/// rolling on a table hopped (18 contact events in 0.7 s; billiards16 96 events instead of
/// 62); at 1.5e-4 (rtol 1e-2, 65×) it no longer hopped and at 4.6e-5 neither did billiards16
/// (`examples/contact_tolerance.rs` measured it; `tests/contact_times.rs`). A resting
/// contact's force depends on a penetration of micrometres, which a position tolerance of
/// `5e-5·|r|` still resolves for bodies within metres of the origin.
pub const LOOSEST_CONTACT_RTOL: f64 = 5e-5;

impl SimOptions {
    /// Options for a run from 0 to `stop_time` \[s\] with defaults otherwise.
    pub fn new(stop_time: f64) -> Self {
        SimOptions {
            start_time: 0.0,
            stop_time,
            interval: None,
            rtol: 1e-6,
            atol: None,
            max_step: None,
            contact_results: false,
            contact_phases: true,
            output_steps: false,
            dense_output: false,
            progress: true,
            structured_jacobian: true,
            jacobian_reuse: true,
            analytic_jacobian: true,
            dense_lu: false,
            steady_state: false,
            preload_contacts: true,
            max_steps: Some(DEFAULT_MAX_STEPS),
            max_wall_time: None,
            contact_tightening: DEFAULT_CONTACT_TIGHTENING,
            quiet: false,
        }
    }
    /// Keeps the run's warnings off standard error (true) or prints them there when no
    /// `tracing` subscriber is installed (false, the default); see [`SimOptions::quiet`].
    pub fn quiet(mut self, on: bool) -> Self {
        self.quiet = on;
        self
    }
    /// Sets the step budget of the run (`None` = unlimited; see [`SimOptions::max_steps`]).
    pub fn max_steps(mut self, n: Option<u64>) -> Self {
        self.max_steps = n;
        self
    }
    /// Sets the wall-time budget \[s\] of the run (see [`SimOptions::max_wall_time`]).
    pub fn max_wall_time(mut self, seconds: f64) -> Self {
        self.max_wall_time = Some(seconds);
        self
    }
    /// Sets the tightening of the error test of bodies in contact (see
    /// [`SimOptions::contact_tightening`]; 1 turns it off).
    pub fn contact_tightening(mut self, factor: f64) -> Self {
        self.contact_tightening = factor;
        self
    }
    /// The tightening factor a run uses: [`SimOptions::contact_tightening`] scaled with rtol,
    /// at least `rtol / LOOSEST_CONTACT_RTOL` (a contact is never resolved more loosely than
    /// that), capped so that `rtol / factor ≥ 1e-13`: billiards16 at rtol 1e-11 with 1.5e-14 in
    /// contact failed its error test repeatedly at t = 0.52 s (steps of 1e-9 s), rounding
    /// errors of a few ulp.
    pub(crate) fn effective_contact_tightening(&self) -> f64 {
        if self.contact_tightening <= 1.0 {
            return 1.0;
        }
        let scaled = self.contact_tightening * (1e-6 / self.rtol).powf(1.0 / 6.0);
        scaled
            .max(self.rtol / LOOSEST_CONTACT_RTOL)
            .min(self.rtol / 1e-13)
            .max(1.0)
    }
    /// Uses (true, the default) or not the coloured Jacobian (see
    /// [`SimOptions::structured_jacobian`]).
    pub fn structured_jacobian(mut self, on: bool) -> Self {
        self.structured_jacobian = on;
        self
    }
    /// Forms the iteration matrix for a new `c_j` from the last one's parts (true, the
    /// default) or anew (see [`SimOptions::jacobian_reuse`]).
    pub fn jacobian_reuse(mut self, on: bool) -> Self {
        self.jacobian_reuse = on;
        self
    }
    /// Lets the DAE compute the Jacobian columns of free bodies and hinge trees (true, the
    /// default) or leaves every block to coloured difference quotients (see
    /// [`SimOptions::analytic_jacobian`]).
    pub fn analytic_jacobian(mut self, on: bool) -> Self {
        self.analytic_jacobian = on;
        self
    }
    /// Factors every component of the iteration matrix densely (true) or as its cost chooses
    /// (false, the default; see [`SimOptions::dense_lu`]).
    pub fn dense_lu(mut self, on: bool) -> Self {
        self.dense_lu = on;
        self
    }
    /// Starts resting contacts preloaded or at the given positions (see
    /// [`SimOptions::preload_contacts`]).
    pub fn preload_contacts(mut self, on: bool) -> Self {
        self.preload_contacts = on;
        self
    }
    /// Starts the components in steady state (see [`SimOptions::steady_state`]).
    pub fn steady_state(mut self, on: bool) -> Self {
        self.steady_state = on;
        self
    }
    /// Records per-pair contact signals (`"<a>|<b>.f_n"`, … see
    /// [`SimulationResult::signal`](crate::SimulationResult::signal)).
    pub fn contact_results(mut self, on: bool) -> Self {
        self.contact_results = on;
        self
    }
    /// With `contact_results`, measures the contact phases too (true, the default) or records
    /// only the per-pair signals at the output points (see [`SimOptions::contact_phases`]).
    pub fn contact_phases(mut self, on: bool) -> Self {
        self.contact_phases = on;
        self
    }
    /// Records an output point after every solver step as well (see
    /// [`SimOptions::output_steps`]).
    pub fn output_steps(mut self, on: bool) -> Self {
        self.output_steps = on;
        self
    }
    /// Keeps IDA's interpolating polynomial of every step for `signal_at` (see
    /// [`SimOptions::dense_output`]).
    pub fn dense_output(mut self, on: bool) -> Self {
        self.dense_output = on;
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
    /// The absolute tolerance a run of a scene with these options uses: [`SimOptions::atol`]
    /// if set, else `0.01·rtol`, or Modia's `0.1·rtol` with
    /// [`SceneOptions::modia3d_conventions`](crate::SceneOptions::modia3d_conventions).
    pub fn effective_atol(&self, scene: &crate::SceneOptions) -> f64 {
        let per_rtol = if scene.modia3d_conventions { 0.1 } else { 0.01 };
        self.atol.unwrap_or(per_rtol * self.rtol)
    }
    /// Sets the output interval \[s\].
    pub fn interval(mut self, dt: f64) -> Self {
        self.interval = Some(dt);
        self
    }
    /// Sets the largest step \[s\] (at least `(stop − start)/max_steps`, so that the run fits
    /// its step budget).
    pub fn max_step(mut self, h: f64) -> Self {
        self.max_step = Some(h);
        self
    }
    /// Sets the start time \[s\].
    pub fn start_time(mut self, t0: f64) -> Self {
        self.start_time = t0;
        self
    }

    /// Checks every option against its documented range (see `docs/options.md`):
    /// - start and stop time finite, `stop − start ≥ 1e-12 s` and `≥ 1e-10·max(|start|, |stop|)`
    ///   (IDA must be able to tell the two apart by more than its rounding of `t`);
    /// - `rtol ∈ [1e-14, 1)` (below, the error test asks for less than double rounding);
    /// - `atol ∈ [1e-16, 1e6]`, finite;
    /// - output interval > 0 and at most [`MAX_OUTPUT_POINTS`] grid points;
    /// - `max_steps ≥ 1`; `max_step > 0` and, with a step budget, `≥ (stop − start)/max_steps`
    ///   (else the run could not end within it);
    /// - `max_wall_time > 0`, finite;
    /// - `contact_tightening ∈ [1, 1e6]`.
    pub(crate) fn check(&self) -> Result<(), String> {
        let finite = |x: f64| x.is_finite();
        let (t0, t1) = (self.start_time, self.stop_time);
        if !finite(t0) || !finite(t1) || t1 <= t0 {
            return Err(format!(
                "stop time {t1} s must be finite and after the start time {t0} s"
            ));
        }
        let span = t1 - t0;
        let min_span = 1e-12f64.max(1e-10 * t0.abs().max(t1.abs()));
        if span < min_span {
            return Err(format!(
                "the run from {t0:?} s to {t1:?} s is shorter than {min_span:e} s: the stop time must be at least 1e-12 s (and 1e-10 of the time values) after the start time"
            ));
        }
        if !(self.rtol >= 1e-14 && self.rtol < 1.0) {
            return Err(format!(
                "tolerance {:?} must be in [1e-14, 1): below 1e-14 the error test asks for less than the rounding of f64",
                self.rtol
            ));
        }
        if let Some(a) = self.atol {
            if !(1e-16..=1e6).contains(&a) {
                return Err(format!(
                    "absolute tolerance {a:?} must be in [1e-16, 1e6] (units of the states: m, rad, m/s, rad/s)"
                ));
            }
        }
        if let Some(dt) = self.interval {
            if !(dt > 0.0 && finite(dt)) {
                return Err(format!("output interval {dt} s must be finite and > 0"));
            }
            let points = span / dt;
            if points > MAX_OUTPUT_POINTS {
                return Err(format!(
                    "output interval {dt:?} s gives {points:.3e} output points over {span:?} s, more than the limit of {MAX_OUTPUT_POINTS:e}: choose an interval of at least {:e} s",
                    span / MAX_OUTPUT_POINTS
                ));
            }
        }
        if self.max_steps == Some(0) {
            return Err("max_steps must be >= 1 (or None for no step budget)".into());
        }
        if let Some(h) = self.max_step {
            if h.is_nan() || h <= 0.0 {
                return Err(format!("max step {h} s must be > 0"));
            }
            if let Some(n) = self.max_steps {
                let h_min = span / n as f64;
                if h < h_min {
                    return Err(format!(
                        "max step {h:?} s needs more than max_steps = {n} steps for the run of {span:?} s: use a max step of at least {h_min:e} s or raise max_steps"
                    ));
                }
            }
        }
        if let Some(w) = self.max_wall_time {
            if !(w > 0.0 && finite(w)) {
                return Err(format!("max wall time {w} s must be finite and > 0"));
            }
        }
        if !(1.0..=1e6).contains(&self.contact_tightening) {
            return Err(format!(
                "contact_tightening {:?} must be in [1, 1e6] (1 = no tightening of the error test of bodies in contact)",
                self.contact_tightening
            ));
        }
        Ok(())
    }
}
