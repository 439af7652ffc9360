//! Simulation driver: [`Simulation`] runs the DAE of a model with IDA from the start to the
//! stop time, records output points, handles events, and returns results — or, on failure, an
//! error that carries the results up to the failure. [`SimOptions`] and [`SimError`] live here;
//! [`Model::simulate`](crate::Model::simulate) is `Simulation::new` + `advance_to(stop_time)`.
// No panic on user input: indexing goes through `get` and iterators (issue 15's audit).
#![deny(clippy::indexing_slicing)]

use crate::contact::ContactError;
use crate::dae::{DerivativeError, MultibodyDae};
use crate::dynamics::forces::{FaultKind, UserFault};
use crate::model::Model;
use crate::results::Event;
use crate::results::{SimStats, SimulationResult};
use crate::solver::{Atol, Ida, IdaError, IdaOptions, SolveStatus};
use std::time::Instant;

mod contact_phases;
mod diagnosis;
mod options;
mod preload;
mod segments;
mod steady_state;
mod warnings;
pub use diagnosis::{Budget, SlowCause, WorkDiagnosis};
pub use options::{
    SimOptions, CHATTER_EVENTS, CHATTER_SPAN, DEFAULT_CONTACT_TIGHTENING, DEFAULT_MAX_STEPS,
    LOOSEST_CONTACT_RTOL, MAX_OUTPUT_POINTS,
};
pub use segments::ActionError;

/// Collapsed accepted steps in a row with a contact past the depth limit after which a run
/// ends with [`SimErrorKind::TooDeep`] (see `Simulation::check_depth`): at 1e-10 s a step, 200
/// of them advance 2e-8 s, so the run would not have finished within any budget.
pub const TOO_DEEP_STEPS: u32 = 200;

/// A step shorter than this fraction of the run's duration counts as collapsed for
/// [`TOO_DEEP_STEPS`] \[-\]: 1e-8 s in a 1 s run, two orders below the steps through a hard
/// steel impact at rtol 1e-10 (BENCHMARKS.md, "Error in contact phases").
pub const TOO_DEEP_STEP: f64 = 1e-8;

/// Why a simulation failed.
#[derive(thiserror::Error, Debug, Clone, PartialEq)]
pub enum SimErrorKind {
    /// The options are inconsistent.
    #[error("invalid simulation options: {0}")]
    InvalidOptions(String),
    /// At a restart (an event, an input change) the state or its derivative is not finite.
    #[error("the solution diverged by t = {t} s: {what} or its rate is not finite at a restart; an input or a force grew without bound (a controller closed from host code at too long a period is unstable: put it in the model as components, or shorten the period)")]
    Diverged {
        /// Time \[s\].
        t: f64,
        /// Which value, by name.
        what: String,
    },
    /// Components' forces depend on the accelerations they read (`der(…)` signals, their
    /// flanges' accelerations) too strongly for consistent accelerations to be found.
    #[error("no consistent accelerations at t = {t} s: components' forces depend on the accelerations they read as strongly as the inertias they act on (the fixed point on them does not converge); state an inertia rigidly geared to a flange as `FlangeSpec::inertia`, or filter the acceleration (a FirstOrder block)")]
    AccelerationLoop {
        /// Time \[s\].
        t: f64,
    },
    /// `SimOptions::steady_state` found no steady state.
    #[error("no steady state at t = {t} s: Newton's method left the largest rate at {residual:.3e} (of {worst}) after {iterations} iterations; start from given values (`steady_state(false)`) or give initial values nearer one (a servo's reference at its joint's initial position)")]
    SteadyState {
        /// Time \[s\].
        t: f64,
        /// The largest remaining rate (an acceleration [rad/s² or m/s²] or a state's rate).
        residual: f64,
        /// The unknown whose equation it is.
        worst: String,
        /// Newton iterations taken.
        iterations: usize,
    },
    /// No consistent initial accelerations (singular mass matrix).
    #[error("no consistent accelerations at t = {t} s: the mass matrix is singular; check the masses and inertias of moving bodies")]
    Inconsistent {
        /// Time \[s\].
        t: f64,
    },
    /// A user closure (an `ObjectForce` law, or a law of a `Bushing`, `SpringDamperPtP`,
    /// `WorldForce` or `WorldTorque`) panicked; the panic was caught at the call.
    #[error("{element} panicked at t = {t} s: {message}; the run was stopped: a force law must return a finite wrench for every state the integrator tries")]
    UserPanic {
        /// The element whose closure panicked, e.g. ``ObjectForce on `ball` (force element 0)``.
        element: String,
        /// Time \[s\] passed to the closure.
        t: f64,
        /// The panic payload as text.
        message: String,
    },
    /// A user force law returned a NaN or infinite force or torque.
    #[error("{element} returned a non-finite wrench at t = {t} s (force {force:?} N, torque {torque:?} N·m); the run was stopped: check the force law for divisions by zero or unbounded growth")]
    NonFiniteForce {
        /// The element, e.g. ``ObjectForce on `ball` (force element 0)``.
        element: String,
        /// Time \[s\] passed to the law.
        t: f64,
        /// The force returned \[N\], resolved in world.
        force: [f64; 3],
        /// The torque returned [N·m], resolved in world.
        torque: [f64; 3],
    },
    /// A force element is undefined in the state reached, or one of its scalar laws returned a
    /// non-finite value: a bushing's Cardan angles at gimbal lock, a body at the centre of point
    /// gravity, a spring law returning NaN.
    #[error("{element} failed at t = {t} s: {reason}; the run was stopped")]
    ForceElement {
        /// The element, e.g. ``bushing `mount` (force element 0)``.
        element: String,
        /// Time \[s\].
        t: f64,
        /// What happened and what to do.
        reason: String,
    },
    /// A kinematic loop could not be closed again at a restart (an event or an input change).
    #[error("kinematic loop closed by joint `{cut}` (through {joints:?}) does not close at t = {t} s: constraint residual {residual:.3e} after projection; the mechanism reached a position its links cannot take (a singular or locked position), check the drive and its inputs")]
    LoopClosure {
        /// The cut joint.
        cut: String,
        /// The joints of its loop.
        joints: Vec<String>,
        /// Largest remaining residual (\[m\] or \[1\]).
        residual: f64,
        /// Time \[s\].
        t: f64,
    },
    /// A scheduled action (attach, release, delete) could not be carried out.
    #[error("at t = {t} s: {error}")]
    Action {
        /// Time \[s\].
        t: f64,
        /// Why.
        error: Box<ActionError>,
    },
    /// The integrator failed.
    #[error(transparent)]
    Solver(#[from] IdaError),
    /// IDA gave up at a step it could not take (`IDA_ERR_FAIL`, `IDA_CONV_FAIL`,
    /// `IDA_TOO_MUCH_ACC`, a failed linear-solver setup or solve, repeated recoverable
    /// residual failures), with the diagnosis a run at its work budget gets: what made the
    /// steps collapse, measured on the run (a deep or stiff contact, an ill-conditioned mass
    /// matrix, a fast body, …).
    #[error("{error}; diagnosis: {cause}{}", limiting_suffix(.limiting_state))]
    SolverStalled {
        /// The integrator's error (flag, time, hint).
        error: Box<IdaError>,
        /// What limited the steps.
        cause: Box<SlowCause>,
        /// The state with the largest weighted local error at the last step (see
        /// [`WorkDiagnosis::limiting_state`]).
        limiting_state: Option<String>,
    },
    /// The collision stage failed.
    #[error(transparent)]
    Contact(#[from] ContactError),
    /// The run reached its work budget; the diagnosis names what limited the steps.
    #[error("{0}")]
    WorkBudget(Box<WorkDiagnosis>),
    /// Many contact events within a tiny time span (the chattering guard: [`CHATTER_EVENTS`]
    /// events within [`CHATTER_SPAN`] of the run's duration).
    #[error("contact `{pair}` chatters: {events} events within {span:.3e} s up to t = {t} s; check the pair's initial overlap and materials, or lower k_red")]
    Chattering {
        /// The pair `"a|b"` with the most of those events.
        pair: String,
        /// Number of events in the span.
        events: usize,
        /// Their time span \[s\].
        span: f64,
        /// Time \[s\].
        t: f64,
    },
    /// A contact is deeper than the whole extent of its thinner shape, or deeper than half of
    /// it (the limit an initial overlap has at build time, `SceneError::InitialPenetration`)
    /// while IDA's steps have collapsed ([`TOO_DEEP_STEPS`] steps in a row shorter than
    /// [`TOO_DEEP_STEP`] of the run): one solid has passed into the other, the signed
    /// distance's normal jumps, and the compliant law no longer describes the two solids.
    #[error("contact `{pair}` is {depth:.3e} m deep at t = {t} s, past the depth limit of its thinner shape (extent {extent:.3e} m: half of it with the steps collapsed there, or all of it): one solid has passed into the other, where the compliant contact law no longer holds (the limit an initial overlap has too); what drives them together is more than the contact can carry — check masses, applied forces and initial speeds, or stiffen the contact (k_red, the materials' E, a solid's layer depth)")]
    TooDeep {
        /// The pair `"a|b"`.
        pair: String,
        /// Penetration depth `−z_AB` at the accepted step \[m\].
        depth: f64,
        /// The thinner shape's extent (smallest edge of its own bounding box) \[m\].
        extent: f64,
        /// Time of the accepted step \[s\].
        t: f64,
    },
    /// Events follow each other without progress in time (a chattering contact).
    #[error("{count} events at t = {t} s without the contact set changing or time advancing: a contact chatters; raise the hysteresis or loosen the tolerance")]
    EventLoop {
        /// Time \[s\].
        t: f64,
        /// Events without progress.
        count: u32,
    },
}

/// `"; the step is limited by …"` for a named limiting state, else nothing.
fn limiting_suffix(state: &Option<String>) -> String {
    state
        .as_ref()
        .map(|s| format!("; the step is limited by {s}"))
        .unwrap_or_default()
}

impl From<UserFault> for SimErrorKind {
    fn from(f: UserFault) -> Self {
        let element = f.element_name();
        match f.kind {
            FaultKind::Panic(message) => SimErrorKind::UserPanic {
                element,
                t: f.t,
                message,
            },
            FaultKind::NonFinite { force, torque } => SimErrorKind::NonFiniteForce {
                element,
                t: f.t,
                force,
                torque,
            },
            FaultKind::Undefined(reason) => SimErrorKind::ForceElement {
                element,
                t: f.t,
                reason,
            },
        }
    }
}

/// Absolute tolerances of the `n` unknowns: `atol` for every state; with closed loops, the
/// multipliers `λ`, `μ` (algebraic, left out of the error test) get `LOOP_MULTIPLIER_ATOL`
/// in IDA's Newton convergence test (see `dynamics/loops.rs`).
/// The components' states (after them) get `atol` times their nominal size.
fn loop_atol(plan: &crate::dynamics::Plan, n: usize, atol: f64) -> Atol {
    let cp = &plan.components;
    if plan.loops.m() == 0 && cp.nx == 0 {
        return Atol::Scalar(atol);
    }
    let states = plan.nq + plan.nv;
    let xo = plan.x_offset();
    Atol::Vector(
        (0..n)
            .map(|i| {
                if i < states {
                    atol
                } else if i < xo {
                    LOOP_MULTIPLIER_ATOL
                } else {
                    atol * cp.x_nominal.get(i - xo).copied().unwrap_or(1.0)
                }
            })
            .collect(),
    )
}

/// IDA's options for a run (or a segment) of `plan` with `n` unknowns and root functions of
/// `root_directions` (`MultibodyDae::root_directions`).
fn ida_options(
    plan: &crate::dynamics::Plan,
    opts: &SimOptions,
    n: usize,
    dae: &MultibodyDae,
) -> IdaOptions {
    let volume_law = dae.contact_plan().is_some_and(|cp| cp.has_volume_law());
    let root_directions = dae.root_directions();
    IdaOptions {
        rtol: opts.rtol,
        atol: loop_atol(plan, n, opts.effective_atol(&plan.scene.options)),
        max_step: opts.max_step,
        // z_1 matters when it rises (a contact ends), z_2 when it falls (one starts), the
        // components' smallest crossing when it falls.
        root_directions,
        structured_jacobian: opts.structured_jacobian,
        jacobian_reuse: opts.jacobian_reuse,
        dense_lu: opts.dense_lu,
        // Closed loops: λ and μ are algebraic and left out of the error test
        // (dynamics/loops.rs).
        differential: (plan.loops.m() > 0).then(|| {
            (0..n)
                .map(|i| i < plan.nq + plan.nv || i >= plan.x_offset())
                .collect()
        }),
        suppress_algebraic_error: plan.loops.m() > 0,
        // A stricter Newton test for the index-2 multipliers: on the free four-bar at rtol
        // 1e-10 it takes 11,400 steps over 5 s instead of 16,300 (fewer error-test failures
        // from inexact λ) and drifts less in energy.
        // With both, the stricter of the two.
        nonlinear_convergence_coefficient: [
            (plan.loops.m() > 0).then_some(LOOP_NEWTON_COEFFICIENT),
            volume_law.then(|| {
                (VOLUME_NEWTON_PRODUCT / opts.rtol).clamp(VOLUME_NEWTON_COEFFICIENT, 0.33)
            }),
        ]
        .into_iter()
        .flatten()
        .reduce(f64::min),
        // IDA's own first step comes from ‖y'‖ and, with velocities starting at zero and
        // large accelerations, can be 1e-17 s, where the index-2 iteration matrix (condition
        // ∝ 1/h²) defeats Newton's method (Andrews' squeezer fails at t = 0 so); a first
        // step of 1e-6 of the run is cut by the error test if too large.
        // Components: their states start at rest while a source acts through the controller
        // at once (a PI's ẍ(0) = 19500/s² in Modia3D's servo), and IDA's first step of 1e-3 of
        // the span, cut by at most 4⁻⁹ by its ten error-test failures, stayed too large below
        // rtol 3e-9 (`tests/drive_trains.rs`); the loops' first step fixes it.
        init_step: (plan.loops.m() > 0 || plan.components.nx > 0)
            .then_some(LOOP_FIRST_STEP * (opts.stop_time - opts.start_time)),
        ..IdaOptions::default()
    }
}

/// IDA's Newton convergence coefficient in a scene with pairs under the volume law
/// (`IDASetNonlinConvCoef`; IDA's own is 0.33, closed loops alone take 0.05). IDA accepts a
/// corrector whose error is this fraction of the error test's tolerance, in the weighted norm
/// of the states; but a volume-law force is `κ·V`, with a static depth of ~1e-8 m for wooden
/// bodies, far below the positions' tolerance (`rtol·|r|`), so what IDA's 0.33 admits in a
/// position is a force error the error test never sees. A wooden cylinder rolling down an
/// incline fed on it: its tilt rate grew 5–10× per 19 ms step from 1e-10 rad/s until the
/// steps collapsed (96 IDA steps at rtol 1e-2; 80 with 0.05, 76 with 0.02, 63 with 0.01). With
/// 0.01 a cube sliding down an incline is 2e-11 off the rigid acceleration at rtol 1e-2
/// (2.1e-3 with 0.33), the pivot and the rolling cylinder take 34–42 % fewer steps at rtol
/// 1e-6 (379 and 250 instead of 575 and 432), and `falling_boxes` at rtol 1e-5 13,957
/// instead of 15,133 (BENCHMARKS.md, "Face contacts"). Scenes without such pairs keep IDA's
/// coefficient, bit for bit. At tight tolerances the depth is resolved and the corrector's
/// error meets the rounding of the forces instead (the same cube sliding to rest at rtol
/// 1e-10 with 0.01: 499,771 Newton failures by t = 0.04 s), so the coefficient is
/// `1e-8/rtol` within `[0.01, 0.33]` ([`VOLUME_NEWTON_PRODUCT`]): 0.01 from rtol 1e-6 up,
/// IDA's 0.33 from 3e-8 down. A scene with closed loops too takes the smaller of this and
/// [`LOOP_NEWTON_COEFFICIENT`].
const VOLUME_NEWTON_COEFFICIENT: f64 = 0.01;

/// IDA's Newton convergence coefficient with closed loops: a stricter test for the index-2
/// multipliers (see `ida_options`).
const LOOP_NEWTON_COEFFICIENT: f64 = 0.05;

/// See [`VOLUME_NEWTON_COEFFICIENT`]: the product of Newton's coefficient and rtol below which
/// the coefficient is not taken.
const VOLUME_NEWTON_PRODUCT: f64 = 1e-8;

/// First step of a run with closed loops, as a fraction of its span (see `Simulation::new`).
const LOOP_FIRST_STEP: f64 = 1e-6;

/// Absolute tolerance of the loop multipliers in IDA's Newton test [N, N·m for λ; m/s, rad/s
/// for μ]. They are out of the error test, so this only sets how exactly each corrector solve
/// must fix them: with the states' atol (1e-12 at rtol 1e-10) the index-2 multipliers, whose
/// round-off grows like the iteration matrix's condition (∝ 1/h²), never pass it and the first
/// step fails at h ≈ 1e-17 (measured on the four-bar; 1e-6 fails, 1e-3 and 1 pass, 1e-3
/// conserves the free four-bar's energy better).
const LOOP_MULTIPLIER_ATOL: f64 = 1e-3;

/// The error of [`MultibodyDae::consistent_derivative`] at time `t` \[s\].
fn derivative_error(e: DerivativeError, t: f64) -> SimErrorKind {
    match e {
        DerivativeError::Singular => SimErrorKind::Inconsistent { t },
        DerivativeError::Contact(c) => c.into(),
        DerivativeError::User(f) => f.into(),
        DerivativeError::Loop(f) => SimErrorKind::LoopClosure {
            cut: f.cut,
            joints: f.joints,
            residual: f.residual,
            t,
        },
        DerivativeError::AccelerationLoop => SimErrorKind::AccelerationLoop { t },
    }
}

/// A failed simulation: what went wrong, and the results computed up to the failure.
///
/// `Debug` (what `unwrap()` and `fn main() -> Result<(), Box<dyn Error>>` print) is the
/// message, the kind's variant and a one-line summary of the partial results, e.g.
/// `partial: output points: 437, t = 0 … 0.4374 s, events: 12, warnings: 0 (in e.partial)`;
/// the results themselves stay in [`SimError::partial`].
#[derive(thiserror::Error, Clone)]
#[error("simulation failed: {kind}")]
pub struct SimError {
    /// What went wrong.
    pub kind: SimErrorKind,
    /// Results up to the failure.
    pub partial: Box<SimulationResult>,
}

impl std::fmt::Debug for SimError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(
            f,
            "{self}\n  kind: SimErrorKind::{}\n  partial: {}, warnings: {} (in e.partial)",
            self.kind.variant(),
            self.partial.span_line(),
            self.partial.warnings.len()
        )
    }
}

impl SimErrorKind {
    /// The variant's name, for `SimError`'s `Debug`.
    fn variant(&self) -> &'static str {
        match self {
            SimErrorKind::InvalidOptions(_) => "InvalidOptions",
            SimErrorKind::Inconsistent { .. } => "Inconsistent",
            SimErrorKind::UserPanic { .. } => "UserPanic",
            SimErrorKind::NonFiniteForce { .. } => "NonFiniteForce",
            SimErrorKind::ForceElement { .. } => "ForceElement",
            SimErrorKind::LoopClosure { .. } => "LoopClosure",
            SimErrorKind::Action { .. } => "Action",
            SimErrorKind::Solver(_) => "Solver",
            SimErrorKind::SolverStalled { .. } => "SolverStalled",
            SimErrorKind::Contact(_) => "Contact",
            SimErrorKind::WorkBudget(_) => "WorkBudget",
            SimErrorKind::Chattering { .. } => "Chattering",
            SimErrorKind::EventLoop { .. } => "EventLoop",
            SimErrorKind::TooDeep { .. } => "TooDeep",
            SimErrorKind::SteadyState { .. } => "SteadyState",
            SimErrorKind::Diverged { .. } => "Diverged",
            SimErrorKind::AccelerationLoop { .. } => "AccelerationLoop",
        }
    }
}

// The runners of a model live with the driver they run (issue 41, "runners up"): `model.rs`
// holds the compiled plans and knows nothing of runs.
impl Model {
    /// Runs the model with error control from `opts.start_time` to `opts.stop_time`.
    pub fn simulate(&self, opts: &SimOptions) -> Result<SimulationResult, SimError> {
        run(self, opts)
    }

    /// A step-wise simulation of this model (see [`Simulation`]); the plans are shared, not
    /// recompiled.
    pub fn simulation(&self, opts: &SimOptions) -> Result<Simulation, SimError> {
        Simulation::new(self, opts)
    }
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
/// every time passed to [`Simulation::advance_to`]. Actions (the scene's scheduled ones, run by
/// `advance_to` at their times, or [`Simulation::attach`], [`release`](Simulation::release),
/// [`delete`](Simulation::delete) between steps) change the structure and start a new
/// segment; the action's time then has two output points, before and after (see
/// `docs/segments.md`).
pub struct Simulation {
    model: Model,
    opts: SimOptions,
    ida: Ida<MultibodyDae>,
    result: SimulationResult,
    /// Index of the next output-grid point.
    k_grid: u64,
    /// Scratch for interpolated output points (length n once used).
    y_out: Vec<f64>,
    /// The step limit IDA has now \[s\] (`None`: unlimited).
    h_max: Option<f64>,
    /// Inputs changed since the last restart: the next step restarts IDA.
    inputs_changed: bool,
    /// `advance` returns after the first step it takes ([`Simulation::step`]).
    one_step: bool,
    stalled: u32,
    last_event_t: f64,
    wall: f64,
    /// When the current `advance_to` call started (for the wall-time budget).
    call_started: Instant,
    /// Progress bar of a one-shot run on a terminal.
    progress: Option<indicatif::ProgressBar>,
    /// Warnings found at the start of the run (`warnings::start_warnings`) and the relaxations
    /// of the contact tightening (`relax_contact_tightening`).
    start_warnings: Vec<crate::results::SimWarning>,
    /// Scratch of `measure_step`, with the end samples of the last measured step.
    phase_scratch: contact_phases::PhaseScratch,
    /// The step guard must be evaluated before the next step (at the start and after a
    /// restart; otherwise it follows each step, see `advance_to`).
    guard_due: bool,
    /// Accepted steps in a row that were collapsed with a pair of the contact set past the
    /// depth limit (`check_depth`).
    deep_steps: u32,
    /// Structure changes (`segments.rs`): the model the run started with, IDA's counters of
    /// the finished segments, the scheduled actions and what they did.
    segments: segments::SegmentState,
    /// The warnings already printed to standard error (`report_warnings`).
    reported: Vec<crate::results::SimWarning>,
}

impl std::fmt::Debug for Simulation {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Simulation")
            .field("t", &self.time())
            .field("stop_time", &self.opts.stop_time)
            .finish_non_exhaustive()
    }
}

/// Whether a `tracing` subscriber is installed (for this thread or globally): it then gets the
/// warnings through `tracing::warn!`, and they are not printed to standard error.
pub(crate) fn subscriber_installed() -> bool {
    tracing::dispatcher::get_default(|d| !d.is::<tracing::subscriber::NoSubscriber>())
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
        if !opts.quiet {
            // An unoptimised build says so once per process, naming the Cargo.toml fix.
            crate::build_profile::notice_once(subscriber_installed());
        }
        if opts.contact_results {
            result.enable_contact_record(opts.contact_phases);
        }
        let t0 = opts.start_time;
        let new_dae = || {
            let mut dae = MultibodyDae::new(plan.clone(), model.contact.clone());
            dae.set_analytic_jacobian(opts.analytic_jacobian);
            dae.set_contact_tightening(opts.effective_contact_tightening());
            dae.set_tolerance(opts.rtol);
            dae
        };
        // The start at `y0`: the components' discrete states (limiters' modes, samplers' first
        // tick), then the initial contact set (event mode); consistent derivatives including
        // contacts follow.
        let begin = |dae: &mut MultibodyDae, y0: &[f64]| -> Result<(), SimErrorKind> {
            dae.component_event(t0, y0)?;
            dae.handle_event(t0, y0)?;
            Ok(())
        };
        let mut dae = new_dae();
        let mut y0 = plan.y0();
        // A scene without unknowns integrates one dummy state (see `MultibodyDae::len`).
        y0.resize(crate::solver::DaeSystem::len(&dae), 0.0);
        let xo = plan.x_offset();
        for (slot, &x) in y0.iter_mut().skip(xo).zip(&plan.components.x0) {
            *slot = x;
        }
        if let Err(e) = begin(&mut dae, &y0) {
            return Err(fail(e, result));
        }
        if opts.steady_state {
            if let Err(e) = steady_state::solve(&mut dae, t0, &mut y0) {
                return Err(fail(e, result));
            }
        }
        if opts.preload_contacts && preload::solve(&mut dae, t0, &mut y0) {
            // The preloaded start as a first event: a fresh contact set, so every pair in it
            // starts here (its phase, its `δ̇⁻`) as from the given positions.
            dae = new_dae();
            if let Err(e) = begin(&mut dae, &y0) {
                return Err(fail(e, result));
            }
        }
        let yp0 = match dae.consistent_derivative(t0, &mut y0) {
            Ok(yp0) => yp0,
            Err(e) => return Err(fail(derivative_error(e, t0), result)),
        };
        let root_functions = dae.num_roots_public();
        let ida_opts = ida_options(&plan, opts, y0.len(), &dae);
        if let Some((lp, _)) = dae.limits() {
            result.enable_limits(lp, opts.contact_results && opts.contact_phases);
        }
        result.phase_event(&dae, t0);
        let start_warnings = warnings::start_warnings(model, dae.contact());
        for w in &start_warnings {
            tracing::warn!(t = t0, "{w}");
        }
        result.warnings.clone_from(&start_warnings);
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
            y_out: Vec::new(),
            h_max: opts.max_step,
            inputs_changed: false,
            stalled: 0,
            last_event_t: f64::NEG_INFINITY,
            wall: 0.0,
            call_started: started,
            one_step: false,
            progress: None,
            phase_scratch: Default::default(),
            guard_due: true,
            deep_steps: 0,
            start_warnings,
            segments: segments::SegmentState::new(model),
            reported: Vec::new(),
        };
        sim.wall = started.elapsed().as_secs_f64();
        sim.update_stats();
        Ok(sim)
    }

    /// Current time \[s\].
    pub fn time(&self) -> f64 {
        self.ida.t()
    }

    /// Current state `y = [q; v]` (empty for a scene without unknowns).
    pub fn state(&self) -> &[f64] {
        let y = self.ida.y();
        // IDA's vector holds nq + nv values, or one dummy value for a scene without unknowns.
        y.get(..self.model.plan.nq + self.model.plan.nv)
            .unwrap_or(&[])
    }

    /// The results recorded so far.
    pub fn result(&self) -> &SimulationResult {
        &self.result
    }

    /// The results recorded so far, ending the simulation.
    pub fn into_result(self) -> SimulationResult {
        self.result
    }

    /// Integrates with error control to `t` \[s\] (at most the stop time), handling events,
    /// carrying out the scene's actions scheduled up to `t` and recording output points. On failure the error carries the results up to the failure; the
    /// simulation can then only be [`reset`](Self::reset).
    pub fn advance_to(&mut self, t: f64) -> Result<(), SimError> {
        self.call(|sim| sim.advance_with_actions(t))
    }

    /// One public advancing call: `run` timed against the wall budget and added to the wall
    /// time, then the statistics and warnings brought up to date; a failure carries the
    /// results up to it.
    fn call(
        &mut self,
        run: impl FnOnce(&mut Self) -> Result<(), SimErrorKind>,
    ) -> Result<(), SimError> {
        let started = Instant::now();
        self.call_started = started;
        let outcome = run(self);
        self.wall += started.elapsed().as_secs_f64();
        self.update_stats();
        self.update_warnings();
        self.report_warnings();
        outcome.map_err(|kind| SimError {
            kind,
            partial: Box::new(self.result.clone()),
        })
    }

    /// Takes one step of the solver, of the size its error control chooses (at most to the
    /// next scheduled action or the stop time), handling an event or a time event at its end
    /// and recording the output points it passes (and its end with
    /// [`SimOptions::output_steps`]); returns the time reached \[s\]. At the stop time it
    /// does nothing. For a host program that watches the motion step by step and stops where
    /// it wants (a monitor, an optimisation that cuts a run short), as `mj_step` serves
    /// MuJoCo users: [`Simulation::state`] and [`Simulation::output`] read the state there,
    /// and the dense output ([`SimOptions::dense_output`]) interpolates within the step. On
    /// failure as [`Simulation::advance_to`].
    pub fn step(&mut self) -> Result<f64, SimError> {
        self.call(Self::one_step_with_actions)?;
        Ok(self.time())
    }

    /// [`Simulation::step`]: the actions due now first, then one step towards the next one.
    fn one_step_with_actions(&mut self) -> Result<(), SimErrorKind> {
        let now = self.time();
        self.advance_with_actions(now)?;
        let target = self
            .next_action_time()
            .map_or(self.opts.stop_time, |a| a.min(self.opts.stop_time));
        self.one_step = true;
        let outcome = self.advance(target);
        self.one_step = false;
        outcome
    }

    /// The start warnings and those of the run so far; new ones are traced.
    fn update_warnings(&mut self) {
        let (t0, t1) = (self.opts.start_time, self.opts.stop_time);
        let interval = self.opts.interval.unwrap_or((t1 - t0) / 500.0);
        let run = warnings::run_warnings(&self.result, t1 - t0, interval, self.opts.output_steps);
        let mut all = self.start_warnings.clone();
        for w in run {
            if !self.result.warnings.contains(&w) {
                tracing::warn!(t = self.time(), "{w}");
            }
            all.push(w);
        }
        self.result.warnings = all;
    }

    /// Prints the warnings not printed before to standard error, in one block, unless the
    /// run is [`quiet`](SimOptions::quiet) or a `tracing` subscriber is installed (it got
    /// them from `tracing::warn!`): a new user sees them without printing `result.warnings`.
    fn report_warnings(&mut self) {
        let new: Vec<_> = self
            .result
            .warnings
            .iter()
            .filter(|w| !self.reported.contains(w))
            .cloned()
            .collect();
        if new.is_empty() {
            return;
        }
        self.reported.extend(new.iter().cloned());
        if self.opts.quiet || subscriber_installed() {
            return;
        }
        let text = warnings::report(&new);
        match &self.progress {
            Some(bar) => bar.suspend(|| eprint!("{text}")),
            None => eprint!("{text}"),
        }
    }

    fn update_stats(&mut self) {
        let (narrow, aabb, limits) = self
            .ida
            .system()
            .contact()
            .map(|c| (c.narrow_calls, c.aabb_tests, c.narrow_limits))
            .unwrap_or((0, 0, 0));
        self.result.stats = SimStats {
            solver: self.segments.solver_base + self.ida.stats(),
            events: self.result.events.len() as u64,
            root_functions: self.result.stats.root_functions,
            narrow_phase_calls: narrow,
            aabb_tests: aabb,
            narrow_phase_limits: limits,
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
        // The components' time events (a source's kink, a sampler's tick) stop the
        // integration there: the event, then a restart.
        let mut t_event = self.ida.system().next_time_event(now);
        let stop = |e: Option<f64>| e.map_or(target, |e| e.min(target));
        self.ida.set_stop_time(stop(t_event))?;
        // One internal step per `solve`: the output grid never steers the steps (IDA's first
        // step after a restart would otherwise be 0.001 × the distance to the next output
        // point, and every output point inside a step would cost a root evaluation); output
        // points inside a step are read off IDA's interpolating polynomial instead.
        loop {
            self.check_budget()?;
            if self.guard_due {
                self.guard_step()?;
            }
            let t_prev = self.time();
            let solved = self.ida.solve(target, true);
            // The guard reads the body motion in the workspace; here it is what IDA's own
            // evaluations left (a step's root functions), before the measurement and the
            // outputs below evaluate anything: neither the output grid nor contact results
            // may steer the steps. IDA keeps the step limit until the next guard.
            self.guard_due = false;
            if solved.is_ok() {
                self.guard_step()?;
                self.check_depth()?;
            }
            if let Some(f) = self.ida.system_mut().take_user_fault() {
                return Err(f.into());
            }
            if let Some(e) = self.ida.system_mut().take_root_error() {
                return Err(e.into());
            }
            let status = match solved {
                Err(IdaError::Flag { ref name, .. })
                    if name == "IDA_ERR_FAIL" && self.relax_contact_tightening() =>
                {
                    // Go on from the last step IDA reached, with the looser error test.
                    self.restart(self.time())?;
                    continue;
                }
                Err(e) => return Err(self.stalled(e)),
                Ok(status) => status,
            };
            let (SolveStatus::Reached { t }
            | SolveStatus::StopTime { t }
            | SolveStatus::Root { t }) = status;
            self.measure_step(t_prev, t)?;
            if self.opts.dense_output && t > t_prev {
                self.result.push_dense(&mut self.ida, t_prev, t)?;
            }
            self.record_grid(t0, dt, t.min(target - eps))?;
            let at_event = t_event.is_some_and(|e| t >= e - 1e-14 * e.abs().max(1.0));
            if at_event && !matches!(status, SolveStatus::Root { .. }) {
                self.time_event(t)?;
                t_event = self.ida.system().next_time_event(t);
                if t < target - eps {
                    self.restart(t)?;
                    self.ida.set_stop_time(stop(t_event))?;
                    if self.one_step {
                        return Ok(());
                    }
                    continue;
                }
                // At the target: the next call restarts from here.
                self.inputs_changed = true;
            }
            match status {
                SolveStatus::Root { t } => {
                    self.event(t)?;
                    if t_event.is_some_and(|e| e <= t) {
                        t_event = self.ida.system().next_time_event(t);
                        self.ida.set_stop_time(stop(t_event))?;
                    }
                }
                SolveStatus::Reached { t } if self.opts.output_steps && t < target - eps => {
                    let y = self.ida.y().to_vec();
                    record(self.ida.system_mut(), &mut self.result, t, &y, contacts);
                }
                _ if t >= target - eps => {
                    let y = self.ida.y().to_vec();
                    record(self.ida.system_mut(), &mut self.result, t, &y, contacts);
                    self.show_progress(t);
                    // The target was a grid point too.
                    if (t0 + self.k_grid as f64 * dt - t).abs() <= eps {
                        self.k_grid += 1;
                    }
                    return Ok(());
                }
                _ => {}
            }
            if self.one_step {
                return Ok(());
            }
        }
    }

    /// After IDA's error test failed repeatedly (`IDA_ERR_FAIL`) with the error test of the
    /// bodies in contact tightened (`SimOptions::contact_tightening`): divides the factor by 10
    /// (to 1 = off at most) for the rest of the run (segment), records a
    /// [`SimWarning::ContactTighteningRelaxed`](crate::results::SimWarning::ContactTighteningRelaxed)
    /// and returns true (the caller restarts IDA from its last step); false when nothing is
    /// tightened (the failure is the run's error). Why: random scenes at rtol ≈ 1.4e-9 asked
    /// ~5e-12 in contact and failed at 2e-14 s steps (fuzz scene 0x51c3833739c3634e, BENCHMARKS.md
    /// "Random scenes"), while the same runs end at 1/2 of that factor; a fixed floor under the
    /// tightened tolerance would loosen the contact times of `tests/contact_times.rs` at rtol
    /// 1e-9 and 1e-10, which never fail.
    fn relax_contact_tightening(&mut self) -> bool {
        let t = self.time();
        let dae = self.ida.system_mut();
        let from = dae.contact_tightening();
        if from <= 1.0 {
            return false;
        }
        let to = if from > 10.0 { from / 10.0 } else { 1.0 };
        dae.set_contact_tightening(to);
        let w = crate::results::SimWarning::ContactTighteningRelaxed { t, from, to };
        tracing::warn!(t, "{w}");
        self.start_warnings.push(w);
        true
    }

    /// Limits the next step to the tunnelling guard's (`MultibodyDae::max_safe_step`) and the
    /// user's `max_step`; IDA is told only when the limit changed by more than 10 %.
    fn guard_step(&mut self) -> Result<(), SimErrorKind> {
        let Some(guard) = self.ida.system().max_safe_step() else {
            if self.h_max != self.opts.max_step {
                self.ida.set_max_step(self.opts.max_step)?;
                self.h_max = self.opts.max_step;
            }
            return Ok(());
        };
        let h = self.opts.max_step.map_or(guard, |m| m.min(guard));
        let stale = self.h_max.is_none_or(|old| (h - old).abs() > 0.1 * old);
        if stale {
            self.ida.set_max_step(Some(h))?;
            self.h_max = Some(h);
        }
        Ok(())
    }

    /// Ends the run with [`SimErrorKind::TooDeep`] when a pair of the contact set is, at the
    /// end of an accepted step (IDA's root functions, evaluated there, left `z_AB` in the set;
    /// MPR's centre-ray depth corrected by sampled support directions as the build check does):
    ///
    /// - deeper than the whole extent of its thinner shape (a ball sunk below its top, a plate
    ///   passed through), or
    /// - deeper than half of it (`contact::initial::MAX_INITIAL_DEPTH_RATIO`, the limit a scene
    ///   may not start with) for [`TOO_DEEP_STEPS`] accepted steps in a row, each shorter than
    ///   [`TOO_DEEP_STEP`] of the run.
    ///
    /// Why. Past half the extent the centre of a ball or the mid-plane of a plate lies inside the
    /// other solid; where the shortest way out then turns (a thin plate, a box edge) the normal
    /// jumps and IDA's steps collapse to 1e-10 s and below until a work budget ends the run:
    /// the largest group of random scenes that did not finish (BENCHMARKS.md "Random scenes").
    /// Half the extent alone is not enough: in the 10,000-scene batch 447 runs that finished
    /// passed it (to 0.50–0.60 of the extent) and came back at steps of the impact's scale,
    /// while the runs that ground to their budget sat there with steps of 1e-12 to 1e-8 s. A
    /// whole extent deep is no contact at all, whatever the steps. One comparison per pair of
    /// the set; the sampled depth (800 support points) only past a limit.
    fn check_depth(&mut self) -> Result<(), SimErrorKind> {
        use crate::contact::initial::{extent, sampled_depth, MAX_INITIAL_DEPTH_RATIO};
        let span = self.opts.stop_time - self.opts.start_time;
        let collapsed = self.ida.stats().last_step < TOO_DEEP_STEP * span;
        let t = self.time();
        let dae = self.ida.system();
        let (Some(cp), Some(cs)) = (dae.contact_plan(), dae.contact()) else {
            return Ok(());
        };
        let too_deep = |depth, extent, pp| SimErrorKind::TooDeep {
            pair: cp.pair_name(&self.model.plan.scene, pp),
            depth,
            extent,
            t,
        };
        let mut deep_and_collapsed = None;
        for (_, pp, ps) in cs.active_pairs() {
            let (Some(a), Some(b)) = (cp.shapes.get(pp.a), cp.shapes.get(pp.b)) else {
                continue;
            };
            let (a, b) = (&a.shape, &b.shape);
            let thinner = extent(a).min(extent(b));
            let half = MAX_INITIAL_DEPTH_RATIO * thinner;
            if -ps.z <= half || !(collapsed || -ps.z > thinner) {
                continue;
            }
            let depth = (-ps.z).min(sampled_depth(a, cs.pose(pp.a), b, cs.pose(pp.b)));
            if depth > thinner {
                return Err(too_deep(depth, thinner, pp));
            }
            if collapsed && depth > half && deep_and_collapsed.is_none() {
                deep_and_collapsed = Some(too_deep(depth, thinner, pp));
            }
        }
        let Some(error) = deep_and_collapsed else {
            self.deep_steps = 0;
            return Ok(());
        };
        self.deep_steps += 1;
        if self.deep_steps < TOO_DEEP_STEPS {
            return Ok(());
        }
        Err(error)
    }

    /// Records the output-grid points up to `t_end` \[s\] (within the last step) from IDA's
    /// interpolating polynomial.
    fn record_grid(&mut self, t0: f64, dt: f64, t_end: f64) -> Result<(), SimErrorKind> {
        let contacts = self.opts.contact_results;
        let mut recorded = false;
        loop {
            let grid = t0 + self.k_grid as f64 * dt;
            if grid > t_end {
                break;
            }
            let mut y = std::mem::take(&mut self.y_out);
            y.resize(self.ida.y().len(), 0.0);
            self.ida.interpolate(grid, &mut y)?;
            record(self.ida.system_mut(), &mut self.result, grid, &y, contacts);
            self.y_out = y;
            self.k_grid += 1;
            recorded = true;
        }
        if recorded {
            self.show_progress(t_end);
        }
        Ok(())
    }

    /// Moves the progress bar (a one-shot run on a terminal) to `t` \[s\].
    fn show_progress(&self, t: f64) {
        if let Some(bar) = &self.progress {
            let (t0, t1) = (self.opts.start_time, self.opts.stop_time);
            bar.set_position((1000.0 * (t - t0) / (t1 - t0)) as u64);
            bar.set_message(format!("t = {t:.4} s"));
        }
    }

    /// IDA steps of the run so far, over all restarts and segments.
    fn run_steps(&self) -> u64 {
        self.segments.solver_base.steps + self.ida.stats().steps
    }

    /// Ends the run if a budget is reached (checked before every internal step).
    fn check_budget(&mut self) -> Result<(), SimErrorKind> {
        let steps = self.run_steps();
        let wall = self.wall + self.call_started.elapsed().as_secs_f64();
        let reached = match (self.opts.max_steps, self.opts.max_wall_time) {
            (Some(n), _) if steps >= n => Some(Budget::Steps(n)),
            (_, Some(w)) if wall >= w => Some(Budget::WallTime(w)),
            _ => None,
        };
        if let Some(budget) = reached {
            return Err(self.diagnose(budget, steps));
        }
        Ok(())
    }

    /// The diagnosis of a run that reached `budget` after `steps` steps (see
    /// [`WorkDiagnosis`]): a chattering pair if one had an event at least every 10 mean
    /// steps among the last 200 events, else a contact deeper than half its thinner shape,
    /// else an ill-conditioned mass matrix when Newton failed
    /// more often than the error test, else a fast body that the tunnelling guard follows,
    /// else the stiffest element if it explains the steps, else a fast-spinning body that
    /// does; and the limiting state.
    fn diagnose(&mut self, budget: Budget, steps: u64) -> SimErrorKind {
        let t = self.time();
        let cause = self.slow_cause(steps, self.ida.stats().last_step);
        let run = self.segments.solver_base + self.ida.stats();
        let limiting_state = self.limiting_state();
        SimErrorKind::WorkBudget(Box::new(WorkDiagnosis {
            budget,
            t,
            steps,
            events: self.result.events.len(),
            last_step: self.ida.stats().last_step,
            error_test_failures: run.error_test_failures,
            newton_failures: run.nonlinear_convergence_failures,
            cause,
            limiting_state,
        }))
    }

    /// The state with the largest weighted local error at IDA's last step, by name.
    fn limiting_state(&mut self) -> Option<String> {
        self.ida
            .limiting_component()
            .and_then(|(i, _)| diagnosis::state_name(&self.model.plan, i))
    }

    /// `error` with the diagnosis of [`Simulation::diagnose`] when IDA gave up at a step it
    /// could not take (its error test or Newton's method failed repeatedly, the accuracy
    /// cannot be reached, or the iteration matrix is singular): the same measurements name
    /// what made the steps collapse ([`SimErrorKind::SolverStalled`]). Other solver errors
    /// (bad arguments, caught panics, fatal residuals) are returned as they are.
    fn stalled(&mut self, error: IdaError) -> SimErrorKind {
        if !error.is_stall() {
            return SimErrorKind::Solver(error);
        }
        // The step IDA gave up at, not the last one it took: that one can be orders of
        // magnitude longer (a run that stepped at the tunnelling guard's 3e-5 s and then failed
        // to converge at 2e-10 s is not limited by the guard).
        let last = self.ida.stats().last_step;
        let h = self.ida.current_step().map_or(last, |h| h.min(last));
        let cause = self.slow_cause(self.run_steps(), h);
        let limiting_state = self.limiting_state();
        SimErrorKind::SolverStalled {
            error: Box::new(error),
            cause: Box::new(cause),
            limiting_state,
        }
    }

    /// What limited the steps of the run so far, after `steps` steps, the last of size
    /// `h_last` \[s\] (see [`Simulation::diagnose`]).
    fn slow_cause(&mut self, steps: u64, h_last: f64) -> SlowCause {
        let (t0, t1) = (self.opts.start_time, self.opts.stop_time);
        let t = self.time();
        let h_budget = (t1 - t0) / self.opts.max_steps.unwrap_or(DEFAULT_MAX_STEPS) as f64;
        let mean_step = (t - t0) / steps.max(1) as f64;
        let events = &self.result.events;
        match diagnosis::busiest_pair(events, 200) {
            Some((pair, n, span)) if n >= 20 && span <= 10.0 * mean_step * n as f64 => {
                SlowCause::Chattering {
                    pair,
                    events: n,
                    span,
                }
            }
            _ => {
                let dae = self.ida.system();
                let stiffest = diagnosis::stiffest(
                    &self.model.plan,
                    dae.contact_plan(),
                    dae.contact(),
                    h_budget,
                );
                let cause = diagnosis::limiting(stiffest, h_last, h_budget);
                let speeds: Vec<(f64, f64)> = dae.body_speeds().collect();
                let guard = dae.guard_limit();
                let run = self.segments.solver_base + self.ida.stats();
                let plan = &self.model.plan;
                let ill = (run.nonlinear_convergence_failures > run.error_test_failures)
                    .then(|| self.ida.y().get(..plan.nq))
                    .flatten()
                    .and_then(|q| diagnosis::worst_conditioned(plan, q))
                    .filter(|&(_, ratio)| ratio >= diagnosis::ILL_CONDITIONED)
                    .map(|(i, ratio)| SlowCause::IllConditioned {
                        coordinate: diagnosis::state_name(plan, plan.nq + i)
                            .unwrap_or_else(|| format!("velocity {i}")),
                        ratio,
                    });
                let cause = diagnosis::deep_contact(plan, dae.contact_plan(), dae.contact())
                    .unwrap_or_else(|| {
                        diagnosis::with_fast_body(cause, plan, &speeds, guard, ill, h_last)
                    });
                match cause {
                    SlowCause::StepCollapse { .. } | SlowCause::Unknown => {
                        diagnosis::damping_limited(plan, dae.contact_plan(), dae.contact())
                            .or_else(|| {
                                diagnosis::rough_contact(
                                    plan,
                                    dae.contact_plan(),
                                    dae.contact(),
                                    dae.workspace(),
                                )
                            })
                            .or_else(|| {
                                diagnosis::stiff_friction(
                                    plan,
                                    dae.contact_plan(),
                                    dae.contact(),
                                    h_last,
                                )
                            })
                            .or_else(|| {
                                diagnosis::linear_law_at_touch(
                                    plan,
                                    dae.contact_plan(),
                                    dae.contact(),
                                    h_last,
                                )
                            })
                            .unwrap_or(cause)
                    }
                    cause => cause,
                }
            }
        }
    }

    /// Chattering guard: [`CHATTER_EVENTS`] events within [`CHATTER_SPAN`] of the run's
    /// duration end the run, naming the pair with the most of them.
    fn check_chattering(&self, t: f64) -> Result<(), SimErrorKind> {
        let events = &self.result.events;
        let Some(oldest) = events
            .len()
            .checked_sub(CHATTER_EVENTS)
            .and_then(|k| events.get(k))
        else {
            return Ok(());
        };
        let span = t - oldest.t;
        if span > CHATTER_SPAN * (self.opts.stop_time - self.opts.start_time) {
            return Ok(());
        }
        let pair = diagnosis::busiest_pair(events, CHATTER_EVENTS)
            .map(|p| p.0)
            .unwrap_or_default();
        Err(SimErrorKind::Chattering {
            pair,
            events: CHATTER_EVENTS,
            span,
            t,
        })
    }

    /// Event at `t`: rebuild the contact set, log it, restart with consistent derivatives.
    fn event(&mut self, t: f64) -> Result<(), SimErrorKind> {
        let y = self.ida.y().to_vec();
        let dae = self.ida.system_mut();
        let switched = dae.component_event(t, &y)?;
        let changed = dae.handle_event(t, &y)? || switched;
        let (started, ended) = dae.event_pairs();
        self.result.phase_event(self.ida.system(), t);
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
        if switched {
            words.push("a component switched".into());
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
        self.check_chattering(t)?;
        self.restart(t)
    }

    /// A time event of the components at `t` \[s\]: their discrete states are set anew (the
    /// caller restarts IDA).
    /// The event is logged and has an output point, as a contact's (a source's kink or a
    /// sampler's jump bounds the interpolation of `signal_at`).
    fn time_event(&mut self, t: f64) -> Result<(), SimErrorKind> {
        let y = self.ida.y().to_vec();
        let switched = self.ida.system_mut().component_event(t, &y)?;
        let description = if switched {
            "time event; a component switched"
        } else {
            "time event"
        };
        tracing::debug!(t, description, "event");
        self.result.events.push(Event {
            t,
            description: description.into(),
            started: vec![],
            ended: vec![],
        });
        let contacts = self.opts.contact_results;
        record(self.ida.system_mut(), &mut self.result, t, &y, contacts);
        Ok(())
    }

    /// Re-initialises IDA at `t` with the current `y` and a consistent `y'`.
    fn restart(&mut self, t: f64) -> Result<(), SimErrorKind> {
        self.phase_scratch.forget();
        // The guard after a restart: from the consistent derivative's evaluation (the last).
        self.guard_due = true;
        let mut y = self.ida.y().to_vec();
        let yp = self
            .ida
            .system_mut()
            .consistent_derivative(t, &mut y)
            .map_err(|e| derivative_error(e, t))?;
        if let Some(k) = (0..y.len()).find(|&k| {
            !(y.get(k).is_some_and(|v| v.is_finite()) && yp.get(k).is_some_and(|v| v.is_finite()))
        }) {
            return Err(SimErrorKind::Diverged {
                t,
                what: unknown_name(&self.model.plan, k),
            });
        }
        let plan = &self.model.plan;
        if plan.components.nx > 0 && plan.loops.m() == 0 {
            // The components' first step is for the start only (see `ida_options`): after a
            // time event IDA's own estimate is better (a servo after a path's smooth
            // segment switch, restarted at 1e-6 of the span, stayed at 6e-5 s steps with an
            // error-test failure at each for 0.45 s: 3,890 steps instead of 476).
            self.ida.set_init_step(0.0)?;
        }
        self.ida.reinit(t, &y, &yp)?;
        Ok(())
    }

    /// Names of the declared inputs, then of the `Input` components.
    pub fn input_names(&self) -> Vec<&str> {
        let plan = &self.model.plan;
        plan.inputs
            .iter()
            .map(|i| i.name.as_str())
            .chain(input_components(plan).map(|(c, _)| c.name.as_str()))
            .collect()
    }

    /// Sets input `name` to `values` (1 value for joint inputs, 6 for an object wrench: force
    /// \[N\] then torque [N·m], resolved in world). Takes effect from the current time on.
    pub fn set_input(&mut self, name: &str, values: &[f64]) -> Result<(), InputError> {
        let plan = self.model.plan.clone();
        if let Some((_, at)) = input_components(&plan).find(|(c, _)| c.name == name) {
            return self.set_input_component(name, at, values);
        }
        let Some(inp) = self.model.plan.inputs.iter().find(|i| i.name == name) else {
            return Err(InputError::Unknown {
                name: name.into(),
                hint: crate::scene::did_you_mean(name, self.input_names().into_iter()),
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
        // The plan lays out `len` values at `off` for every input: the slot always exists.
        if let Some(slot) = self.ida.system_mut().inputs_mut().get_mut(off..off + len) {
            if slot != values {
                slot.copy_from_slice(values);
                self.inputs_changed = true;
            }
        }
        Ok(())
    }

    /// Sets the `Input` component whose value is discrete state `at` to `values` (one value).
    fn set_input_component(
        &mut self,
        name: &str,
        at: usize,
        values: &[f64],
    ) -> Result<(), InputError> {
        let &[value] = values else {
            return Err(InputError::Length {
                name: name.into(),
                expected: 1,
                got: values.len(),
            });
        };
        if !value.is_finite() {
            return Err(InputError::NotFinite {
                name: name.into(),
                value,
            });
        }
        let dae = self.ida.system_mut();
        if let Some(slot) = dae.component_discrete_mut().and_then(|d| d.get_mut(at)) {
            if *slot != value {
                *slot = value;
                self.inputs_changed = true;
            }
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
            now.enable_contact_record(false);
        }
        if let Some((lp, _)) = self.ida.system().limits() {
            now.enable_limits(lp, false);
        }
        record(
            self.ida.system_mut(),
            &mut now,
            t,
            &y,
            self.opts.contact_results,
        );
        Ok(now.signal(name)?.last().unwrap_or(&[]).to_vec())
    }

    /// Back to the initial state and zero inputs, with the recorded results cleared; the plan
    /// is reused (no recompilation; after structure changes, the model the run started with).
    pub fn reset(&mut self) -> Result<(), SimError> {
        let model = self.segments.initial.clone();
        *self = Simulation::new(&model, &self.opts)?;
        Ok(())
    }
}

/// The name of unknown `k` of `y` of `plan` (a joint coordinate, its velocity, a loop
/// multiplier, a component's state), for messages.
fn unknown_name(plan: &crate::dynamics::Plan, k: usize) -> String {
    for j in &plan.joints {
        for c in j.coord.coordinates() {
            if j.q_offset + c.q == k {
                return format!("`{}.{}`", j.name, c.name);
            }
            if plan.nq + j.v_offset + c.v == k {
                return format!("the velocity of `{}.{}`", j.name, c.name);
            }
        }
    }
    if let Some(i) = k.checked_sub(plan.x_offset()) {
        if let Some(n) = plan.components.state_names().nth(i) {
            return format!("`{n}`");
        }
    }
    format!("unknown {k} of the state vector")
}

/// The `Input` components of `plan` with the index of their value among the discrete states.
fn input_components(
    plan: &crate::dynamics::Plan,
) -> impl Iterator<Item = (&crate::dynamics::components::CompPlan, usize)> + '_ {
    plan.components
        .comps
        .iter()
        .filter(|c| c.component.kind() == "Input" && c.d.len() == 1)
        .map(|c| (c, c.d.start))
}

/// Stores an output point (and, if asked for, the contact signals at it).
fn record(
    dae: &mut MultibodyDae,
    result: &mut SimulationResult,
    t: f64,
    y: &[f64],
    contacts: bool,
) {
    // A scene without unknowns integrates one dummy state (see `MultibodyDae::len`).
    let n = dae.plan().nq + dae.plan().nv;
    result.push(t, y.get(..n).unwrap_or(y));
    // Constraint multipliers of closed loops (their forces are signals).
    let m = dae.plan().loops.m();
    result.push_multipliers(y.get(n..n + m).unwrap_or(&[]));
    if let Some(f) = dae.limit_forces(y) {
        result.push_limit_forces(f);
    }
    if !dae.plan().components.comps.is_empty() {
        let (mut values, mut flanges) = (Vec::new(), Vec::new());
        dae.component_record(t, y, &mut values, &mut flanges);
        result.push_components(&values);
        result.push_flange_forces(&flanges);
    }
    if contacts {
        // Output values only: a failure here shows up in the next residual anyway.
        let _ = dae.update_contacts(t, y);
        if let Some(cs) = dae.contact() {
            result.push_contacts(cs);
        }
    }
}
