//! Results stage: time points and states of a run, signals by name computed on demand from the
//! stored states (so a run pays only for the signals asked for), statistics, events, CSV export.
// No panic on user input: indexing goes through `get` and iterators (issue 15's audit).
#![deny(clippy::indexing_slicing)]

mod animation;
#[cfg(feature = "arrow")]
pub(crate) mod arrow;
mod contacts;
mod force_signals;
mod gltf;
mod html;
mod loads;
pub(crate) mod plot;
pub(crate) mod plot_axis;
mod plot_legend;
mod plot_text;
mod segments;
mod threejs;
mod warnings;

pub use plot::{PlotFormat, PlotOptions, EVENT_MARKER_COLOR};

use crate::dynamics::{kinematics, Plan, Workspace};
use crate::joints::Source;
use crate::model::Model;
use crate::solver::IdaStats;
pub(crate) use contacts::parabola_max;
pub use contacts::ContactPhase;
use contacts::PhaseBook;
pub use loads::JointLoadPeak;
use std::io::Write;
pub use warnings::SimWarning;

/// Counters of a run.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct SimStats {
    /// IDA's counters, accumulated over restarts.
    pub solver: IdaStats,
    /// Number of events (IDA restarts at a located root).
    pub events: u64,
    /// Number of root functions given to IDA (0 for a scene without collision pairs).
    pub root_functions: usize,
    /// Narrow-phase (signed distance) calls of the collision stage.
    pub narrow_phase_calls: u64,
    /// Broad-phase AABB distance tests of the collision stage.
    pub aabb_tests: u64,
    /// Narrow-phase calls that stopped at the MPR/GJK iteration limit
    /// (`SceneOptions::mpr_max_iterations`) and used their best iterate; each such pair is
    /// also warned about once (`tracing::warn!`).
    pub narrow_phase_limits: u64,
    /// Wall-clock time of the integration \[s\].
    pub wall_time: f64,
}

impl std::fmt::Display for SimStats {
    /// A few readable lines: steps and their last size and order, the work per kind, events
    /// and the collision stage's counters, the wall time.
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let s = &self.solver;
        writeln!(
            f,
            "steps: {} (last step {:.3e} s, order {}), error-test failures: {}",
            s.steps, s.last_step, s.last_order, s.error_test_failures
        )?;
        writeln!(
            f,
            "residuals: {} (+ {} for Jacobians), Jacobians: {}, Newton iterations: {} ({} convergence failures)",
            s.residual_evals,
            s.residual_evals_for_jacobian,
            s.jacobian_evals,
            s.nonlinear_iterations,
            s.nonlinear_convergence_failures
        )?;
        writeln!(
            f,
            "events: {}, root functions: {} ({} evaluations)",
            self.events, self.root_functions, s.root_evals
        )?;
        writeln!(
            f,
            "collision: {} narrow-phase calls ({} at the iteration limit), {} AABB tests",
            self.narrow_phase_calls, self.narrow_phase_limits, self.aabb_tests
        )?;
        write!(f, "wall time: {:.3} s", self.wall_time)
    }
}

/// An event: a located root at which the integration restarted.
#[derive(Clone, Debug, PartialEq)]
pub struct Event {
    /// Time \[s\].
    pub t: f64,
    /// What happened, in words.
    pub description: String,
    /// Pairs (`"a|b"`) that entered the contact set.
    pub started: Vec<String>,
    /// Pairs (`"a|b"`) that left the contact set.
    pub ended: Vec<String>,
}

/// Values recorded per pair and output point: in_contact, penetration, f_n, friction (3),
/// rolling torque (3), point (3), normal (3).
const PAIR_VALUES: usize = 15;

/// The contact signal fields of a pair, in the order of [`PAIR_VALUES`].
const CONTACT_FIELDS: [&str; 7] = [
    "in_contact",
    "penetration",
    "f_n",
    "friction_force",
    "rolling_torque",
    "point",
    "normal",
];

/// One column of an export: a time or signal component with its unit.
struct Column {
    name: String,
    unit: &'static str,
    values: Vec<f64>,
}

/// Per-pair contact signals at the output points (only when asked for).
#[derive(Clone, Debug, Default)]
struct ContactRecord {
    /// `PAIR_VALUES` per pair per time point.
    data: Vec<f64>,
}

/// A signal: `dim` values per time point, row-major (`data[k * dim + i]`).
#[derive(Clone, Debug, PartialEq)]
pub struct Signal {
    /// Its name, e.g. `"ball.r_abs"`.
    pub name: String,
    /// Unit, e.g. `"m"`.
    pub unit: &'static str,
    /// Values per time point.
    pub dim: usize,
    /// Row-major values.
    pub data: Vec<f64>,
}

impl Signal {
    /// Component `i` at every time point.
    pub fn component(&self, i: usize) -> Vec<f64> {
        self.data
            .iter()
            .skip(i)
            .step_by(self.dim)
            .copied()
            .collect()
    }
    /// Number of time points.
    pub fn len(&self) -> usize {
        self.data.len().checked_div(self.dim).unwrap_or(0)
    }
    /// True if the signal has no time point (e.g. of a run that failed before its first
    /// output point).
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }
    /// The `dim` values at time point `k`; `None` if `k` is not a recorded time point
    /// (`k >= len()`). Never panics.
    pub fn at(&self, k: usize) -> Option<&[f64]> {
        if k >= self.len() {
            return None;
        }
        // k < len() = data.len() / dim, so neither product overflows.
        self.data.get(k * self.dim..(k + 1) * self.dim)
    }
    /// The values of a scalar signal (component 0).
    pub fn values(&self) -> Vec<f64> {
        self.component(0)
    }
    /// The values at the first time point; `None` for an empty signal.
    pub fn first(&self) -> Option<&[f64]> {
        self.at(0)
    }
    /// The values at the last time point; `None` for an empty signal (e.g. the partial result
    /// of a run that failed before recording a point). Never panics.
    pub fn last(&self) -> Option<&[f64]> {
        self.len().checked_sub(1).and_then(|k| self.at(k))
    }
}

/// Errors of signal look-up and export.
#[derive(thiserror::Error, Debug)]
pub enum ResultError {
    /// No such signal.
    #[error("unknown signal `{name}`: {reason}")]
    UnknownSignal {
        /// The name asked for.
        name: String,
        /// Why, with a hint.
        reason: String,
    },
    /// A contact signal or the contact phases were asked for, but the run did not record them.
    #[error("{what} needs the contact results of the run: simulate with `SimOptions::contact_results(true)` (`SimOptions::new(stop).contact_results(true)`)")]
    ContactResultsOff {
        /// What was asked for, e.g. ``signal `ball|table.f_n` ``.
        what: String,
    },
    /// The contact phases were asked for, but the run recorded only the contact signals
    /// (`SimOptions::contact_phases(false)`).
    #[error("{what} needs the contact phases, which this run did not measure: simulate with `SimOptions::contact_phases(true)` (the default with `contact_results(true)`)")]
    ContactPhasesOff {
        /// What was asked for, e.g. `contacts()`.
        what: String,
    },
    /// No collision pair of that name (in either order).
    #[error("no collision pair `{pair}` (in either order){}; the pairs are: {known}", match .hint { Some(h) => format!(" (hint: did you mean `{h}`?)"), None => String::new() })]
    UnknownPair {
        /// The name asked for.
        pair: String,
        /// A close existing pair name.
        hint: Option<String>,
        /// The first few pair names (see `contact_pairs()`).
        known: String,
    },
    /// A time outside the recorded output points.
    #[error("signal `{name}` at t = {t} s: outside the recorded time [{start}, {end}] s")]
    OutOfRange {
        /// The signal.
        name: String,
        /// The time asked for \[s\].
        t: f64,
        /// First recorded time \[s\].
        start: f64,
        /// Last recorded time \[s\].
        end: f64,
    },
    /// Writing a file failed.
    #[error("cannot write `{path}`: {source}")]
    Io {
        /// The path.
        path: String,
        /// The cause.
        source: std::io::Error,
    },
    /// A joint load signal (`<joint>.f`, `<object>.f_parent`, …) cannot be computed for this
    /// result.
    #[error("signal `{signal}` is not available: {reason}")]
    LoadsUnavailable {
        /// The signal asked for.
        signal: String,
        /// Why, and what to do.
        reason: String,
    },
    /// An export (plot, animation) could not be made from this result.
    #[error("cannot export `{path}`: {reason}")]
    Export {
        /// The path.
        path: String,
        /// Why.
        reason: String,
    },
}

/// Size \[B\] of one chunk of a result's stored states (at least one time point).
const STATE_CHUNK_BYTES: usize = 1 << 20;

/// Time points per chunk of stored states for `n` unknowns per point (at least 1).
fn points_per_chunk(n: usize) -> usize {
    (STATE_CHUNK_BYTES / (8 * n.max(1))).max(1)
}

/// The outcome of a simulation: output time points, states `y = [q; v]` at each, statistics
/// and events. Signals are derived on demand.
///
/// `Debug` prints a summary (points, time span, statistics, counts), not the states: a failed
/// run's `SimError` is often printed whole by `unwrap()` or `main`'s `Result`, and the full
/// record (plan and every state) ran to megabytes.
#[derive(Clone)]
pub struct SimulationResult {
    model: Model,
    time: Vec<f64>,
    /// The states `[q; v]` of the time points, [`STATE_CHUNK_BYTES`] at a time: chunk `c` holds
    /// points `c·p … c·p + p − 1` (`p = points_per_chunk(n)`) back to back, allocated with
    /// exactly that capacity. A single vector grown by doubling reserved up to twice what the
    /// run recorded (1024 balls: 27.3 MB for 15.9 MB of states) and copied it at every growth.
    states: Vec<Vec<f64>>,
    /// Counters of the run.
    pub stats: SimStats,
    /// Events in time order.
    pub events: Vec<Event>,
    /// What the run found suspicious without failing (initial penetrations, unit slips,
    /// solids that can never meet, chattering contacts, contacts the output grid missed);
    /// each is also traced with `tracing::warn!`.
    pub warnings: Vec<SimWarning>,
    contacts: Option<ContactRecord>,
    /// Contact phases (with `contact_results`).
    phases: Option<PhaseBook>,
    /// The run recorded contact results without phases (`SimOptions::contact_phases(false)`).
    phases_off: bool,
    /// Constraint multipliers `λ` of closed loops (`Plan::loops.m()` per time point).
    multipliers: Vec<f64>,
    /// The joint limits' force signals (name, unit), one per limited coordinate
    /// (`contact/limits.rs`); empty without limits.
    limit_signals: Vec<(String, &'static str)>,
    /// Their values, `limit_signals.len()` per time point.
    limit_forces: Vec<f64>,
    /// The components' signals per time point: their continuous states, outputs and discrete
    /// states (`dynamics/components.rs`); empty without components.
    component_values: Vec<f64>,
    /// The components' flange forces per time point, on the coordinates of
    /// `ComponentPlan::flange_v` (for the joint loads).
    flange_forces: Vec<f64>,
    /// The names of the joint limits' stops (`"<joint>.<coordinate>.lower"`, `".upper"`).
    limit_stops: Vec<String>,
    /// The velocity index of each limited coordinate (the row its force enters; for loads).
    limit_v: Vec<usize>,
    /// With `SimOptions::dense_output`: IDA's interpolating polynomial of every step.
    dense: DenseOutput,
    /// The finished segments of a run with structure changes (`None` without; `segments.rs`).
    segments: Option<Box<segments::Segments>>,
    /// Every tree joint's load at every output point, computed when a load signal is first read
    /// (`loads.rs`) and dropped when a point is recorded.
    tree_loads: std::sync::OnceLock<loads::TreeLoads>,
}

/// IDA's interpolating polynomial of each step of a run (`SimOptions::dense_output`), as
/// Taylor coefficients about the step's internal time: evaluates the states anywhere in the run
/// at the solver's order.
#[derive(Clone, Debug, Default)]
struct DenseOutput {
    /// One entry per returned step, in time order.
    steps: Vec<DenseStep>,
    /// Coefficients `y⁽ᵏ⁾(tn)/k!`, k = 0..=q, each of length `n`, step after step.
    coeffs: Vec<f64>,
    /// Length of one coefficient vector (IDA's unknowns).
    n: usize,
}

/// A step of [`DenseOutput`].
#[derive(Clone, Copy, Debug)]
struct DenseStep {
    /// The interval `[t0, t1]` \[s\] the step covers.
    t0: f64,
    /// See `t0`.
    t1: f64,
    /// Expansion point of the coefficients: IDA's internal time at the step \[s\].
    tn: f64,
    /// Order used.
    q: usize,
    /// Offset of its `(q + 1)·n` coefficients in `DenseOutput::coeffs`.
    offset: usize,
}

impl DenseOutput {
    /// The first `len` unknowns at `t` \[s\] by the polynomial of the last step whose interval
    /// contains `t`; `None` outside the recorded steps.
    fn state_at(&self, t: f64, len: usize) -> Option<Vec<f64>> {
        // Steps are in time order: the last one starting at or before t that reaches t.
        let i = self.steps.partition_point(|s| s.t0 <= t);
        let step = self.steps.get(..i)?.iter().rev().find(|s| t <= s.t1)?;
        let (n, q, off) = (self.n, step.q, step.offset);
        let dt = t - step.tn;
        let mut y = vec![0.0; len.min(n)];
        // Horner in dt over the coefficient vectors.
        for k in (0..=q).rev() {
            let c = self.coeffs.get(off + k * n..off + k * n + y.len())?;
            for (yi, ci) in y.iter_mut().zip(c) {
                *yi = *yi * dt + ci;
            }
        }
        Some(y)
    }
}

impl std::fmt::Debug for SimulationResult {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("SimulationResult")
            .field("model", &self.model)
            .field("points", &self.time().len())
            .field("t_first", &self.time().first())
            .field("t_last", &self.time().last())
            .field("events", &self.events.len())
            .field("warnings", &self.warnings)
            .field("stats", &self.stats)
            .finish_non_exhaustive()
    }
}

/// Warnings listed by [`SimulationResult::summary`]; the rest are counted.
const SUMMARY_WARNINGS: usize = 3;

impl Model {
    /// Names of the signals a result of this model has (joint coordinates and object motions;
    /// see [`SimulationResult::signal_names`]). Contact signals (`"<a>|<b>.f_n"`, …) exist in
    /// addition for each of [`Model::contact_pairs`] when the run records them
    /// ([`SimOptions::contact_results`](crate::SimOptions::contact_results)).
    pub fn signal_names(&self) -> Vec<String> {
        SimulationResult::new(self.clone()).signal_names()
    }
}

impl SimulationResult {
    /// One line about what the run recorded: output points, time span \[s\], events, e.g.
    /// `output points: 437, t = 0 … 0.4374 s, events: 12` (how far a failed run got, in
    /// `SimError`'s `Debug`).
    pub(crate) fn span_line(&self) -> String {
        let span = match (self.time.first(), self.time.last()) {
            (Some(a), Some(b)) => format!(", t = {a} … {b} s"),
            _ => String::new(),
        };
        format!(
            "output points: {}{span}, events: {}",
            self.time.len(),
            self.events.len()
        )
    }

    /// A short report of the run, a few lines: the output points, time span \[s\] and events,
    /// the statistics (as `println!("{}", result.stats)`), and the number of
    /// [`warnings`](Self::warnings) with the first three as one-line
    /// [`headline`](SimWarning::headline)s (`result.warnings` has them in full).
    pub fn summary(&self) -> String {
        let mut text = format!("{}\n{}\n", self.span_line(), self.stats);
        let n = self.warnings.len();
        text.push_str(&match n {
            0 => "warnings: none".to_string(),
            _ => format!("warnings: {n} (in `result.warnings`)"),
        });
        for w in self.warnings.iter().take(SUMMARY_WARNINGS) {
            text.push_str(&format!("\n  - {}", w.headline()));
        }
        if n > SUMMARY_WARNINGS {
            text.push_str(&format!("\n  … and {} more", n - SUMMARY_WARNINGS));
        }
        text
    }
}

#[derive(Clone, Copy)]
enum Quantity {
    Pos,
    Vel,
    Rot,
    AngVel,
}

impl SimulationResult {
    pub(crate) fn new(model: Model) -> Self {
        SimulationResult {
            model,
            time: vec![],
            states: vec![],
            stats: SimStats::default(),
            events: vec![],
            warnings: vec![],
            contacts: None,
            phases: None,
            phases_off: false,
            multipliers: vec![],
            limit_signals: vec![],
            limit_forces: vec![],
            component_values: vec![],
            flange_forces: vec![],
            limit_stops: vec![],
            limit_v: vec![],
            dense: DenseOutput::default(),
            segments: None,
            tree_loads: std::sync::OnceLock::new(),
        }
    }

    /// Records IDA's interpolating polynomial of the step just returned, covering `[t0, t1]`
    /// \[s\] (`SimOptions::dense_output`).
    pub(crate) fn push_dense<S: crate::solver::DaeSystem>(
        &mut self,
        ida: &mut crate::solver::Ida<S>,
        t0: f64,
        t1: f64,
    ) -> Result<(), crate::solver::IdaError> {
        let off = self.dense.coeffs.len();
        let (tn, q) = ida.taylor(&mut self.dense.coeffs)?;
        self.dense.n = ida.y().len();
        self.dense.steps.push(DenseStep {
            t0,
            t1,
            tn,
            q,
            offset: off,
        });
        Ok(())
    }

    pub(crate) fn push_multipliers(&mut self, lambda: &[f64]) {
        self.multipliers.extend_from_slice(lambda);
    }

    /// `<cut>.f` (force on obj2 \[N\]) and `<cut>.t` (torque on obj2 [N·m]) of cut joint `owner`,
    /// both resolved in obj1's frame; the force acts at obj2's origin, obj1 feels the opposite.
    /// `<cut>.f_abs`, `<cut>.t_abs`: the same resolved in world.
    fn loop_signal(&self, owner: &str, field: &str) -> Option<Signal> {
        let plan = &*self.model.plan;
        let c = plan.loops.cuts.iter().position(|c| c.name == owner)?;
        let unit = match field {
            "f" | "f_abs" => "N",
            "t" | "t_abs" => "N·m",
            _ => return None,
        };
        let (nq, m) = (plan.nq, plan.loops.m());
        let mut ws = Workspace::new(plan);
        let mut data = Vec::with_capacity(3 * self.time.len());
        for (k, y) in self.states_iter().enumerate() {
            let (q, v) = y.split_at(nq);
            kinematics::position_velocity(plan, &mut ws, q, v);
            let lambda = self.multipliers.get(k * m..(k + 1) * m)?;
            let value = match field {
                "f" | "t" => {
                    let (f, t) = crate::dynamics::loops::cut_wrench(plan, &ws, c, lambda);
                    if field == "f" {
                        f
                    } else {
                        t
                    }
                }
                _ => {
                    let (f, t, _, _) =
                        crate::dynamics::loops::cut_wrench_world(plan, &ws, c, lambda);
                    if field == "f_abs" {
                        f
                    } else {
                        t
                    }
                }
            };
            data.extend_from_slice(value.as_slice());
        }
        Some(Signal {
            name: format!("{owner}.{field}"),
            unit,
            dim: 3,
            data,
        })
    }

    /// Records the per-pair contact signals and, with `phases`, the contact phases.
    pub(crate) fn enable_contact_record(&mut self, phases: bool) {
        self.phases_off = !phases;
        if let Some(cp) = &self.model.contact {
            self.contacts = Some(ContactRecord::default());
            if phases {
                self.phases = Some(PhaseBook::new(cp.n_pairs));
            }
        }
    }

    /// Records the force signals of the joint limits `lp` and, with `phases`, their stops'
    /// contact phases (ids after the collision pairs').
    pub(crate) fn enable_limits(&mut self, lp: &crate::contact::LimitPlan, phases: bool) {
        self.limit_signals = lp.limits.iter().map(|l| (l.name.clone(), l.unit)).collect();
        self.limit_stops = lp.stops.iter().map(|s| s.name.clone()).collect();
        self.limit_v = lp.limits.iter().map(|l| l.v).collect();
        if phases {
            let pairs = self.model.contact.as_ref().map_or(0, |cp| cp.n_pairs);
            self.phases
                .get_or_insert_with(|| PhaseBook::new(pairs))
                .grow(pairs + lp.stops.len());
        }
    }

    /// Appends the joint limits' forces of one time point (nothing without limits).
    pub(crate) fn push_limit_forces(&mut self, f: &[f64]) {
        if !self.limit_signals.is_empty() {
            self.limit_forces.extend_from_slice(f);
        }
    }

    /// Appends the components' flange forces of one time point.
    pub(crate) fn push_flange_forces(&mut self, values: &[f64]) {
        self.flange_forces.extend_from_slice(values);
    }

    /// Appends the components' signals of one time point.
    pub(crate) fn push_components(&mut self, values: &[f64]) {
        self.component_values.extend_from_slice(values);
    }

    /// The components' signals by name (`<component>.<state, output or discrete state>`),
    /// with their index in a time point's values and unit.
    fn component_signal_list(&self) -> Vec<(String, usize, &'static str)> {
        let cp = &self.model.plan.components;
        let mut v: Vec<(String, usize, &'static str)> = vec![];
        let mut seen = std::collections::HashSet::new();
        let mut push = |name: String, k: usize, unit: &'static str| {
            if seen.insert(name.clone()) {
                v.push((name, k, unit));
            }
        };
        for c in &cp.comps {
            for (k, o) in c.outputs.iter().enumerate() {
                push(
                    format!("{}.{}", c.name, o.name),
                    cp.nx + c.y.start + k,
                    o.unit,
                );
            }
            for (k, x) in c.states.iter().enumerate() {
                push(format!("{}.{}", c.name, x.name), c.x.start + k, x.unit);
            }
            for (k, d) in c.discrete.iter().enumerate() {
                push(
                    format!("{}.{}", c.name, d.name),
                    cp.nx + cp.ny + c.d.start + k,
                    d.unit,
                );
            }
        }
        v
    }

    /// A component's signal (`servo.pi.x`, `drive.motor_w`).
    fn component_signal(&self, owner: &str, field: &str) -> Option<Signal> {
        let cp = &self.model.plan.components;
        if cp.comps.is_empty() {
            return None;
        }
        let full = format!("{owner}.{field}");
        let (name, k, unit) = self
            .component_signal_list()
            .into_iter()
            .find(|(n, _, _)| *n == full)?;
        let n = cp.nx + cp.ny + cp.nd;
        Some(Signal {
            name,
            unit,
            dim: 1,
            data: self
                .component_values
                .iter()
                .skip(k)
                .step_by(n.max(1))
                .copied()
                .collect(),
        })
    }

    /// `<joint>.limit_f` (or `.limit_f_<coordinate>`): a joint limit's generalised force.
    fn limit_signal(&self, owner: &str, field: &str) -> Option<Signal> {
        let n = self.limit_signals.len();
        let (k, unit) = self
            .limit_signals
            .iter()
            .enumerate()
            .find(|(_, (name, _))| name.rsplit_once('.') == Some((owner, field)))
            .map(|(k, (_, unit))| (k, *unit))?;
        Some(Signal {
            name: format!("{owner}.{field}"),
            unit,
            dim: 1,
            data: self
                .limit_forces
                .iter()
                .skip(k)
                .step_by(n)
                .copied()
                .collect(),
        })
    }
    pub(crate) fn phases(&self) -> Option<&PhaseBook> {
        self.phases.as_ref()
    }

    pub(crate) fn phases_mut(&mut self) -> Option<&mut PhaseBook> {
        self.phases.as_mut()
    }

    /// Opens and closes contact phases after an event at `t` \[s\] (or the initial contact set).
    pub(crate) fn phase_event(&mut self, dae: &crate::dae::MultibodyDae, t: f64) {
        if let (Some(book), Some((lp, ls))) = (self.phases.as_mut(), dae.limits()) {
            let base = self.model.contact.as_ref().map_or(0, |cp| cp.n_pairs);
            let (started, ended) = (
                (&ls.started[..], &ls.started_speed[..]),
                (&ls.ended[..], &ls.ended_speed[..]),
            );
            book.event(t, started, ended, base, |id| {
                let stop = id.checked_sub(base).and_then(|s| lp.stops.get(s));
                stop.map(|s| s.name.clone()).unwrap_or_default()
            });
        }
        let (Some(book), Some(cs), Some(cp)) =
            (self.phases.as_mut(), dae.contact(), dae.contact_plan())
        else {
            return;
        };
        let scene = &self.model.plan.scene;
        book.event(
            t,
            (&cs.started, &cs.started_speed),
            (&cs.ended, &cs.ended_speed),
            0,
            |id| {
                cp.pair_by_id(id)
                    .map(|pp| cp.pair_name(scene, &pp))
                    .unwrap_or_default()
            },
        );
    }

    /// Every contact phase of the run in the order the phases started: per pair and stretch
    /// of contact its start and end time, impact and exit speed, effective restitution,
    /// maximum penetration and normal force, and its normal and tangential impulse, measured
    /// on the solver's steps (not the output grid; see [`ContactPhase`] for the sign
    /// convention). Needs [`SimOptions::contact_results`](crate::SimOptions::contact_results);
    /// without it an error names the option. A scene without collision pairs has none.
    /// The stops of joint limits have phases too, named `"<joint>.<coordinate>.lower"` or
    /// `".upper"`: speeds in the coordinate's unit per second, forces and impulses
    /// generalised (\[N·m\], \[N·m·s\] for an angle), penetration in its unit, vector impulses zero.
    pub fn contacts(&self) -> Result<&[ContactPhase], ResultError> {
        match (&self.phases, &self.model.contact) {
            (Some(book), _) => Ok(&book.phases),
            (None, None) if self.limit_stops.is_empty() => Ok(&[]),
            (None, _) if self.phases_off => Err(ResultError::ContactPhasesOff {
                what: "contacts()".into(),
            }),
            (None, _) => Err(ResultError::ContactResultsOff {
                what: "contacts()".into(),
            }),
        }
    }

    /// The contact phases of one pair, named in either order (`"a|b"` or `"b|a"`); in the
    /// reversed order the vector impulses are those on the first-named object (see
    /// [`ContactPhase`]).
    pub fn contact_phases(&self, pair: &str) -> Result<Vec<ContactPhase>, ResultError> {
        if self.limit_stops.iter().any(|s| s == pair) {
            let phases = self.contacts()?.iter().filter(|ph| ph.pair == pair);
            return Ok(phases.cloned().collect());
        }
        let (stored, reversed) = self.resolve_pair(pair).ok_or_else(|| {
            let names = self.contact_pairs();
            let mut known = names.iter().take(8).cloned().collect::<Vec<_>>().join(", ");
            if names.len() > 8 {
                known.push_str(", …");
            }
            ResultError::UnknownPair {
                pair: pair.to_string(),
                hint: crate::scene::did_you_mean(pair, names.iter().map(|s| s.as_str())),
                known,
            }
        })?;
        Ok(self
            .contacts()?
            .iter()
            .filter(|ph| ph.pair == stored)
            .map(|ph| {
                if reversed {
                    ph.reversed(pair)
                } else {
                    ph.clone()
                }
            })
            .collect())
    }

    /// The stored name of a pair given in either order, and whether it was reversed.
    fn resolve_pair(&self, pair: &str) -> Option<(String, bool)> {
        let names = self.contact_pairs();
        if names.iter().any(|n| n == pair) {
            return Some((pair.to_string(), false));
        }
        let (a, b) = pair.split_once('|')?;
        let swapped = format!("{b}|{a}");
        names.contains(&swapped).then_some((swapped, true))
    }

    /// A lookup from a pair name as [`Self::contact_pairs`] spells it to the pair's shape
    /// indices `(lo, hi)`, `lo < hi` (`contact_pairs()` is in that order: by `lo`, then `hi`;
    /// the name itself may put either shape first, as `ContactPlan::pair` orders them);
    /// `None` for a name that is not a candidate pair of this result's model or not spelled
    /// as that list spells it. Builds a map of the shape names once (O(shapes)) for callers
    /// that would otherwise make all N²/2 pair names (524,800 strings for 1024 balls).
    pub(crate) fn pair_lookup(&self) -> impl Fn(&str) -> Option<(usize, usize)> + '_ {
        let scene = &self.model.plan.scene;
        let cp = self.model.contact.as_deref();
        let shapes: std::collections::HashMap<String, usize> = cp
            .map(|cp| {
                (0..cp.shapes.len())
                    .map(|s| (cp.shape_name(scene, s), s))
                    .collect()
            })
            .unwrap_or_default();
        move |pair| {
            let cp = cp?;
            // An object name may hold '|' itself: try every split.
            pair.match_indices('|').find_map(|(i, _)| {
                let a = *shapes.get(pair.get(..i)?)?;
                let b = *shapes.get(pair.get(i + 1..)?)?;
                let (lo, hi) = (a.min(b), a.max(b));
                let pp = cp.pair(lo, hi)?;
                (a != b && (pp.a, pp.b) == (a, b)).then_some((lo, hi))
            })
        }
    }

    pub(crate) fn push_contacts(&mut self, cs: &crate::contact::ContactState) {
        let Some(rec) = self.contacts.as_mut() else {
            return;
        };
        let Some(cp) = self.model.contact.as_deref() else {
            return;
        };
        // Pairs without a state are apart (the contact set only holds near pairs).
        let apart = crate::contact::PairState::APART;
        for pp in cp.candidate_pairs() {
            let ps = cs.state_of(pp.a, pp.b).unwrap_or(&apart);
            let r = &ps.response;
            let on = ps.in_contact;
            rec.data.push(if on { 1.0 } else { 0.0 });
            rec.data.push(if on { r.penetration } else { 0.0 });
            rec.data.push(if on { r.f_n } else { 0.0 });
            for v in [r.friction_force, r.rolling_torque, r.point, r.normal] {
                rec.data.extend(v.iter().map(|&x| if on { x } else { 0.0 }));
            }
        }
    }

    /// Names `"<a>|<b>"` of the candidate collision pairs (owners of the contact signals); a
    /// part of a mesh collided as a convex decomposition is `<object>#<k>` (`k` from 0).
    pub fn contact_pairs(&self) -> Vec<String> {
        match &self.model.contact {
            Some(cp) => cp
                .candidate_pairs()
                .map(|pp| cp.pair_name(&self.model.plan.scene, &pp))
                .collect(),
            None => vec![],
        }
    }

    fn contact_signal(&self, owner: &str, field: &str) -> Option<Signal> {
        let rec = self.contacts.as_ref()?;
        let (stored, reversed) = self.resolve_pair(owner)?;
        let p = self.contact_pairs().iter().position(|n| *n == stored)?;
        // Named `b|a`: normal and forces as seen from the other side (normal from b to a,
        // forces and torque on a), i.e. the vectors change sign.
        let flip = reversed && matches!(field, "friction_force" | "rolling_torque" | "normal");
        let (off, dim, unit) = match field {
            "in_contact" => (0, 1, "1"),
            "penetration" => (1, 1, "m"),
            "f_n" => (2, 1, "N"),
            "friction_force" => (3, 3, "N"),
            "rolling_torque" => (6, 3, "N·m"),
            "point" => (9, 3, "m"),
            "normal" => (12, 3, "1"),
            _ => return None,
        };
        let np = self.model.contact.as_ref()?.n_pairs;
        let stride = np * PAIR_VALUES;
        let base = p * PAIR_VALUES + off;
        let mut data = Vec::with_capacity(dim * self.time.len());
        for k in 0..self.time.len() {
            let at = k * stride + base;
            let values = rec.data.get(at..at + dim)?;
            if flip {
                data.extend(values.iter().map(|x| -x));
            } else {
                data.extend_from_slice(values);
            }
        }
        Some(Signal {
            name: format!("{owner}.{field}"),
            unit,
            dim,
            data,
        })
    }

    pub(crate) fn push(&mut self, t: f64, y: &[f64]) {
        // A load read between steps (the step-wise API) covered the points before this one.
        if self.tree_loads.get().is_some() {
            self.tree_loads = std::sync::OnceLock::new();
        }
        if let Some(s) = self.segments.as_mut() {
            s.time.push(t);
        }
        self.time.push(t);
        let per_chunk = points_per_chunk(y.len());
        match self.states.last_mut() {
            Some(c) if c.len() + y.len() <= per_chunk * y.len() => c.extend_from_slice(y),
            _ => {
                let mut c = Vec::with_capacity(per_chunk * y.len());
                c.extend_from_slice(y);
                self.states.push(c);
            }
        }
    }

    /// Output time points \[s\] (of every segment of a run with structure changes).
    pub fn time(&self) -> &[f64] {
        self.segments.as_ref().map_or(&self.time, |s| &s.time)
    }

    /// Number of unknowns per time point (`nq + nv`; of the last segment's model in a run with
    /// structure changes, see [`Self::state`]).
    pub fn state_len(&self) -> usize {
        self.model.plan.nq + self.model.plan.nv
    }

    /// State `y = [q; v]` at time point `k` (in a run with structure changes, in the layout of
    /// the model of the segment holding `k`); `None` if `k` is not a recorded time point
    /// (`k >= time().len()`). Never panics.
    pub fn state(&self, k: usize) -> Option<&[f64]> {
        if self.segments.is_some() {
            // The segment's own layout (its model's `[q; v]`).
            return self.segment_of(k).and_then(|(seg, i)| seg.state_here(i));
        }
        self.state_here(k)
    }

    /// [`Self::state`] within this segment.
    fn state_here(&self, k: usize) -> Option<&[f64]> {
        if k >= self.time.len() {
            return None;
        }
        let n = self.state_len();
        let per_chunk = points_per_chunk(n);
        // k < time().len(), and the chunks hold n values per time point: no overflow.
        let at = (k % per_chunk) * n;
        self.states.get(k / per_chunk)?.get(at..at + n)
    }

    /// The states at every time point, in order.
    fn states_iter(&self) -> impl Iterator<Item = &[f64]> + '_ {
        (0..self.time.len()).filter_map(|k| self.state_here(k))
    }

    /// The final state, if any time point was recorded.
    pub fn final_state(&self) -> Option<&[f64]> {
        self.time().len().checked_sub(1).and_then(|k| self.state(k))
    }

    /// The plan the run was made with.
    pub(crate) fn plan(&self) -> &Plan {
        &self.model.plan
    }

    /// `joint.quantity` names of every tree joint's signals (its kind's, in state order).
    fn joint_signal_names(&self) -> impl Iterator<Item = String> + '_ {
        self.model.plan.joints.iter().flat_map(|j| {
            j.coord
                .signals()
                .iter()
                .map(move |s| format!("{}.{}", j.name, s.name))
        })
    }

    /// Names of the signals that can change: joint coordinates (`rev.phi`, `rev.w`;
    /// `slide.s`, `slide.v`; `free.r`, `free.q`, `free.w`, `free.v`), motions of the objects
    /// that move (`obj.r_abs`, `obj.v_abs`, `obj.w_abs`, `obj.R_abs`) and, when recorded, the
    /// contact signals. The constant motions of fixed objects (the world and everything rigidly
    /// attached to it) are left out of the list but stay readable by name
    /// (`signal("table.r_abs")`).
    pub fn signal_names(&self) -> Vec<String> {
        if self.segments.is_some() {
            return self.segmented_signal_names();
        }
        self.signal_names_one()
    }

    /// [`Self::signal_names`] of this segment's model.
    fn signal_names_one(&self) -> Vec<String> {
        let mut names = vec![];
        names.extend(self.joint_signal_names());
        for o in self.model.plan.objects.iter().filter(|o| o.body.is_some()) {
            for s in ["r_abs", "v_abs", "w_abs", "R_abs"] {
                names.push(format!("{}.{s}", o.name));
            }
        }
        names.extend(self.force_signal_names());
        for c in &self.model.plan.loops.cuts {
            for f in ["f", "t", "f_abs", "t_abs"] {
                names.push(format!("{}.{f}", c.name));
            }
        }
        names.extend(self.load_signal_names());
        names.extend(self.limit_signals.iter().map(|(n, _)| n.clone()));
        names.extend(self.component_signal_list().into_iter().map(|(n, _, _)| n));
        if self.contacts.is_some() {
            for p in self.contact_pairs() {
                names.extend(CONTACT_FIELDS.iter().map(|f| format!("{p}.{f}")));
            }
        }
        names
    }

    /// A signal by name, optionally with a component index: `"rev.phi"`, `"ball.r_abs"`,
    /// `"ball.r_abs[2]"`. Object signals are resolved in world: `r_abs` \[m\], `v_abs` [m/s],
    /// `w_abs` [rad/s], `R_abs` (rotation matrix, row-major, columns = object axes).
    /// With [`crate::SimOptions::contact_results`], per collision pair `"<a>|<b>"` (see
    /// [`Self::contact_pairs`]; normal from `a` to `b`, forces and torque on `b`, all in world):
    /// `in_contact` (1/0), `penetration` \[m\], `f_n` \[N\], `friction_force` \[N\],
    /// `rolling_torque` [N·m], `point` \[m\], `normal` \[1\]; zero while not in contact. A pair
    /// may be named in either order: as `"<b>|<a>"` the normal points from `b` to `a` and the
    /// friction force and rolling torque are those on `a` (the vectors change sign). A contact
    /// signal of a run without `contact_results` is [`ResultError::ContactResultsOff`].
    /// Per cut joint of a closed loop (see `Model::loops`): `<joint>.f`, the constraint force
    /// \[N\] on obj2 at obj2's origin, and `<joint>.t`, the constraint torque [N·m] on obj2, both
    /// resolved in obj1's frame (obj1 feels the opposite); `<joint>.f_abs`, `<joint>.t_abs` the
    /// same resolved in world.
    /// Joint loads, the same wrench through every other joint: per tree joint (every kind) and
    /// `Fix` joint `<joint>.f` \[N\] and `<joint>.t` [N·m], the force obj1 exerts on obj2 and
    /// its torque about obj2's origin, resolved in obj1's frame, `<joint>.f_abs`,
    /// `<joint>.t_abs` resolved in world and `<joint>.f_obj2`, `<joint>.t_obj2` resolved in
    /// obj2's frame; per object with a parent, its parent link's `<object>.f_parent`,
    /// `<object>.t_parent` (on the object's side of the link, about the object's origin,
    /// resolved in the parent's frame), `<object>.f_parent_abs`, `<object>.t_parent_abs`
    /// (world) and `<object>.f_parent_own`, `<object>.t_parent_own` (the object's frame). They include the joint's springs and drives along its
    /// free directions; computed on demand from the stored states by a Newton–Euler pass with
    /// the model's accelerations at each state (`dynamics/loads.rs`); a scene with collision
    /// pairs needs `contact_results` ([`ResultError::ContactResultsOff`] otherwise), a scene
    /// with inputs has none ([`ResultError::LoadsUnavailable`]). Listed by `signal_names` where
    /// obj2 moves; [`Self::signal_at`] takes them, as joint signals, at the state of IDA's
    /// polynomial with [`crate::SimOptions::dense_output`] (scenes without collision pairs,
    /// whose contact forces exist at output points only), else by the cubic of the output
    /// points.
    /// Per named point-to-point spring-damper: `<name>.length` \[m\], `<name>.length_rate` [m/s], `<name>.tension` \[N\]
    /// (positive pulls the ends together); per bushing (all resolved in obj1): `<name>.r` \[m\]
    /// and `<name>.v` [m/s] (obj2's origin relative to obj1's and its rate), `<name>.angles`
    /// \[rad\], `<name>.rates` [rad/s], `<name>.force` \[N\] and `<name>.torque` [N·m] on obj2.
    /// In a run with structure changes (actions) the signal spans every segment, NaN where its
    /// owner does not exist (see `results/segments.rs`).
    pub fn signal(&self, name: &str) -> Result<Signal, ResultError> {
        if self.segments.is_some() {
            return self.segmented_signal(name);
        }
        self.signal_one(name)
    }

    /// [`Self::signal`] within this segment.
    fn signal_one(&self, name: &str) -> Result<Signal, ResultError> {
        let unknown = |reason: String| ResultError::UnknownSignal {
            name: name.to_string(),
            reason,
        };
        let (base, owner, field, index) = split_signal_name(name).map_err(unknown)?;
        let full = self.full_signal(owner, field);
        if full.is_none() && self.contacts.is_none() && self.resolve_pair(owner).is_some() {
            return Err(ResultError::ContactResultsOff {
                what: format!("signal `{name}`"),
            });
        }
        let full = match full
            .or_else(|| self.contact_signal(owner, field))
            .or_else(|| self.loop_signal(owner, field))
            .or_else(|| self.limit_signal(owner, field))
            .or_else(|| self.component_signal(owner, field))
        {
            Some(s) => Some(s),
            None => self.load_signal(owner, field).transpose()?,
        };
        let full = full
            .or_else(|| self.force_signal(owner, field))
            .ok_or_else(|| {
                let names = self.signal_names();
                let hint = crate::scene::did_you_mean(base, names.iter().map(|s| s.as_str()));
                unknown(match hint {
                    Some(h) => {
                        format!(
                            "no joint or object quantity of that name (hint: did you mean `{h}`?)"
                        )
                    }
                    None => "no joint or object quantity of that name; see `signal_names()`".into(),
                })
            })?;
        match index {
            None => Ok(full),
            Some(i) if i < full.dim => Ok(Signal {
                name: name.to_string(),
                unit: full.unit,
                dim: 1,
                data: full.component(i),
            }),
            Some(i) => Err(unknown(format!(
                "index {i} out of range: `{base}` has {} components",
                full.dim
            ))),
        }
    }

    /// The value of signal `name` (any name [`Self::signal`] accepts) at time `t` \[s\], between
    /// the output points by a cubic through the four nearest output points of the same
    /// event-free stretch (never across an event, where derivatives jump): exact at output
    /// points and events, and with [`SimOptions::output_steps`](crate::SimOptions::output_steps)
    /// the output points are the solver's steps, so the interpolation error is below the
    /// solver's for orders up to 3. With [`SimOptions::dense_output`](crate::SimOptions::dense_output)
    /// joint and object signals are evaluated at the state that IDA's own interpolating
    /// polynomial of the step containing `t` gives (the solver's order and accuracy, exact at
    /// steps and events), up to the end of the last solver step, which may lie past the last
    /// output point of a run advanced by [`Simulation::step`](crate::Simulation::step).
    /// `t` outside the recorded time is an error.
    /// In a run with structure changes the segment holding `t` answers (the later one at an
    /// action's time).
    pub fn signal_at(&self, name: &str, t: f64) -> Result<Vec<f64>, ResultError> {
        if self.segments.is_some() {
            return self.segmented_signal_at(name, t);
        }
        self.signal_at_one(name, t)
    }

    /// [`Self::signal_at`] within this segment.
    fn signal_at_one(&self, name: &str, t: f64) -> Result<Vec<f64>, ResultError> {
        let s = self.signal_one(name)?;
        let time = &self.time;
        let (Some(&first), Some(&last)) = (time.first(), time.last()) else {
            return Err(ResultError::OutOfRange {
                name: name.into(),
                t,
                start: f64::NAN,
                end: f64::NAN,
            });
        };
        // The dense output reaches past the last output point to the end of the last solver
        // step (a run advanced with `Simulation::step` stops between output points).
        let end = self.dense.steps.last().map_or(last, |st| st.t1.max(last));
        let out_of_range = || ResultError::OutOfRange {
            name: name.into(),
            t,
            start: first,
            end: last,
        };
        if !(t >= first && t <= end) {
            return Err(out_of_range());
        }
        if t > last {
            if let Some(v) = self.dense_signal_at(name, t) {
                return Ok(v);
            }
            return match self.dense_load_at(name, t) {
                Some(v) => v,
                None => Err(out_of_range()),
            };
        }
        // Exact at a recorded point (the last one recorded at that time: after an event).
        if let Some(k) = time.iter().rposition(|&x| x == t) {
            return Ok(s.at(k).unwrap_or(&[]).to_vec());
        }
        // With dense output: the state at t by the solver's own polynomial, and the joint or
        // object signal of that state (contact and loop-force signals have no state formula:
        // they take the cubic below).
        if let Some(v) = self.dense_signal_at(name, t) {
            return Ok(v);
        }
        if let Some(v) = self.dense_load_at(name, t) {
            return v;
        }
        // The event-free stretch around t: from the last event before t to the first after.
        let lo = self
            .events
            .iter()
            .map(|e| e.t)
            .filter(|&e| e < t)
            .fold(first, f64::max);
        let hi = self
            .events
            .iter()
            .map(|e| e.t)
            .filter(|&e| e > t)
            .fold(last, f64::min);
        // Nodes: distinct times in [lo, hi], the four nearest to t.
        let mut nodes: Vec<usize> = vec![];
        for (k, &x) in time.iter().enumerate() {
            if x < lo || x > hi {
                continue;
            }
            match nodes.last() {
                Some(&j) if time.get(j) == Some(&x) => {
                    if let Some(l) = nodes.last_mut() {
                        *l = k;
                    }
                }
                _ => nodes.push(k),
            }
        }
        let at = nodes.partition_point(|&k| time.get(k).is_some_and(|&x| x < t));
        let from = at.saturating_sub(2).min(nodes.len().saturating_sub(4));
        let chosen = nodes.get(from..(from + 4).min(nodes.len())).unwrap_or(&[]);
        let mut out = vec![0.0; s.dim];
        for &i in chosen {
            let ti = time.get(i).copied().unwrap_or(t);
            let w: f64 = chosen
                .iter()
                .filter(|&&j| j != i)
                .map(|&j| {
                    let tj = time.get(j).copied().unwrap_or(t);
                    (t - tj) / (ti - tj)
                })
                .product();
            for (o, v) in out.iter_mut().zip(s.at(i).unwrap_or(&[])) {
                *o += w * v;
            }
        }
        Ok(out)
    }

    /// The joint or object signal `name` (optionally `[i]`) at `t` \[s\] from the dense output
    /// (`SimOptions::dense_output`); `None` without dense output, outside it, or for other
    /// signals.
    fn dense_signal_at(&self, name: &str, t: f64) -> Option<Vec<f64>> {
        let plan = &*self.model.plan;
        let y = self.dense.state_at(t, plan.nq + plan.nv)?;
        let (_, owner, field, index) = split_signal_name(name).ok()?;
        let full = self.full_signal_over(owner, field, std::iter::once(y.as_slice()), 1)?;
        match index {
            None => Some(full.data),
            Some(i) => full.data.get(i).map(|&x| vec![x]),
        }
    }

    fn full_signal(&self, owner: &str, field: &str) -> Option<Signal> {
        self.full_signal_over(owner, field, self.states_iter(), self.time.len())
    }

    /// [`Self::full_signal`] over the states `states` (`nt` of them, `[q; v]` each).
    fn full_signal_over<'s>(
        &self,
        owner: &str,
        field: &str,
        states: impl Iterator<Item = &'s [f64]>,
        nt: usize,
    ) -> Option<Signal> {
        let plan = &*self.model.plan;
        let nq = plan.nq;
        let make = |unit, dim, data| Signal {
            name: format!("{owner}.{field}"),
            unit,
            dim,
            data,
        };
        if let Some(j) = plan.joint_index(owner).and_then(|ji| plan.joints.get(ji)) {
            let spec = j.coord.signals().iter().find(|s| s.name == field)?;
            let (q_range, v_range) = (
                j.q_offset..j.q_offset + j.coord.nq(),
                nq + j.v_offset..nq + j.v_offset + j.coord.nv(),
            );
            let mut data = Vec::with_capacity(spec.dim * nt);
            for y in states {
                let off = match spec.source {
                    Source::Q(k) => j.q_offset + k,
                    Source::V(k) => nq + j.v_offset + k,
                    Source::Derived => {
                        let (qj, vj) = (y.get(q_range.clone())?, y.get(v_range.clone())?);
                        j.coord.derived_signal(field, qj, vj, &mut data)?;
                        continue;
                    }
                };
                data.extend_from_slice(y.get(off..off + spec.dim)?);
            }
            return Some(make(spec.unit, spec.dim, data));
        }
        let o = plan.object_index(owner)?;
        let body = plan.objects.get(o)?.body;
        let (quantity, dim, unit) = match field {
            "r_abs" => (Quantity::Pos, 3, "m"),
            "v_abs" => (Quantity::Vel, 3, "m/s"),
            "w_abs" => (Quantity::AngVel, 3, "rad/s"),
            "R_abs" => (Quantity::Rot, 9, "1"),
            _ => return None,
        };
        let mut ws = Workspace::new(plan);
        let mut data = Vec::with_capacity(dim * nt);
        // Only the object's body and its ancestors: an export of every object of N free bodies
        // cost N² body placements per output point when each signal placed the whole scene.
        let chain = kinematics::ancestor_chain(plan, body);
        for y in states {
            let (q, v) = y.split_at(nq);
            kinematics::chain_position_velocity(plan, &mut ws, &chain, q, v);
            let x = kinematics::object_in_world(plan, &ws, o);
            match quantity {
                Quantity::Pos => data.extend_from_slice(x.pos.as_slice()),
                Quantity::Rot => data.extend(x.rot.transpose().iter().copied()),
                Quantity::Vel | Quantity::AngVel => {
                    let (vel, w) = kinematics::point_velocity(&ws, body, &x.pos);
                    let val = if matches!(quantity, Quantity::Vel) {
                        vel
                    } else {
                        w
                    };
                    data.extend_from_slice(val.as_slice());
                }
            }
        }
        Some(make(unit, dim, data))
    }

    /// The signals [`Self::write_csv`] writes by default: every joint coordinate, the
    /// positions `r_abs` of moving objects, the components' states, outputs and discrete
    /// states and, when recorded, every contact signal.
    pub fn default_export_signals(&self) -> Vec<String> {
        let mut names: Vec<String> = self.joint_signal_names().collect();
        for o in &self.model.plan.objects {
            if o.body.is_some() {
                names.push(format!("{}.r_abs", o.name));
            }
        }
        // The components' states and outputs (drive-trains.md: signals like the others).
        names.extend(self.component_signal_list().into_iter().map(|(n, _, _)| n));
        if self.contacts.is_some() {
            for p in self.contact_pairs() {
                names.extend(CONTACT_FIELDS.iter().map(|f| format!("{p}.{f}")));
            }
        }
        names
    }

    /// The columns of an export of `names`: time first, then one per signal component
    /// (`name` for a scalar, `name[i]` otherwise), each with its unit and values.
    fn columns<S: AsRef<str>>(&self, names: &[S]) -> Result<Vec<Column>, ResultError> {
        let mut cols = vec![Column {
            name: "time".into(),
            unit: "s",
            values: self.time().to_vec(),
        }];
        for n in names {
            let s = self.signal(n.as_ref())?;
            for i in 0..s.dim {
                cols.push(Column {
                    name: if s.dim == 1 {
                        s.name.clone()
                    } else {
                        format!("{}[{i}]", s.name)
                    },
                    unit: s.unit,
                    values: s.component(i),
                });
            }
        }
        Ok(cols)
    }

    /// Writes time and every joint coordinate, moving object position (`r_abs`) and, with
    /// `contact_results`, contact signal as CSV (see [`Self::default_export_signals`] and
    /// [`Self::write_csv_signals`]).
    pub fn write_csv(&self, path: impl AsRef<std::path::Path>) -> Result<(), ResultError> {
        self.write_csv_signals(path, &self.default_export_signals())
    }

    /// Writes time and the signals `names` (any name [`Self::signal`] accepts, contact signals
    /// and components like `"ball.r_abs[2]"` included) as CSV: a header `name [unit]` per
    /// column (`name[i] [unit]` per component of a vector), then one row per output point,
    /// values with 17 significant digits (they read back exactly). An unknown name is an
    /// error before the file is created.
    pub fn write_csv_signals<S: AsRef<str>>(
        &self,
        path: impl AsRef<std::path::Path>,
        names: &[S],
    ) -> Result<(), ResultError> {
        let path = path.as_ref();
        let io = |source| ResultError::Io {
            path: path.display().to_string(),
            source,
        };
        let cols = self.columns(names)?;
        let mut out = std::io::BufWriter::new(std::fs::File::create(path).map_err(io)?);
        let header: Vec<String> = cols
            .iter()
            .map(|c| format!("{} [{}]", c.name, c.unit))
            .collect();
        writeln!(out, "{}", header.join(",")).map_err(io)?;
        for k in 0..self.time().len() {
            let row: Vec<String> = cols
                .iter()
                .map(|c| format!("{:.17e}", c.values.get(k).copied().unwrap_or(f64::NAN)))
                .collect();
            writeln!(out, "{}", row.join(",")).map_err(io)?;
        }
        out.flush().map_err(io)
    }
}

/// `"<owner>.<field>"` or `"<owner>.<field>[i]"` split into the name without the index, owner,
/// field and component index; `Err` says what is malformed.
fn split_signal_name(name: &str) -> Result<(&str, &str, &str, Option<usize>), String> {
    let (base, index) = match name.strip_suffix(']').and_then(|s| s.rsplit_once('[')) {
        Some((b, i)) => (
            b,
            Some(
                i.parse::<usize>()
                    .map_err(|_| format!("`{i}` is not an index"))?,
            ),
        ),
        None => (name, None),
    };
    let (owner, field) = base
        .rsplit_once('.')
        .ok_or_else(|| "expected `<joint or object>.<quantity>`".to_string())?;
    Ok((base, owner, field, index))
}

#[cfg(test)]
// In tests an out-of-range index is a failure report like any assertion.
#[allow(clippy::indexing_slicing)]
mod tests {
    use super::*;

    /// States pushed across several chunks read back exactly, point by point; every chunk has
    /// exactly the capacity of its points (nothing reserved beyond the last chunk's).
    #[test]
    fn states_in_chunks_read_back_exactly() {
        let model = crate::dae::alloc_tests::balls_on_a_table().build().unwrap();
        let n = model.plan.nq + model.plan.nv;
        let per_chunk = points_per_chunk(n);
        assert!(per_chunk > 1 && per_chunk * n * 8 <= STATE_CHUNK_BYTES);
        let mut res = SimulationResult::new(model);
        let points = 2 * per_chunk + 3;
        let value = |k: usize, i: usize| (k * n + i) as f64 + 0.5;
        for k in 0..points {
            let y: Vec<f64> = (0..n).map(|i| value(k, i)).collect();
            res.push(1e-3 * k as f64, &y);
        }
        assert_eq!(res.states.len(), 3);
        assert!(res.states.iter().all(|c| c.capacity() == per_chunk * n));
        for k in 0..points {
            let y = res.state(k).unwrap();
            assert!(y.iter().enumerate().all(|(i, &x)| x == value(k, i)), "{k}");
        }
        assert_eq!(res.final_state().unwrap()[n - 1], value(points - 1, n - 1));
        assert!(res.state(points).is_none());
        assert_eq!(res.states_iter().count(), points);
    }
}
