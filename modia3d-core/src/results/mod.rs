//! Results stage: time points and states of a run, signals by name computed on demand from the
//! stored states (so a run pays only for the signals asked for), statistics, events, CSV export.
// No panic on user input: indexing goes through `get` and iterators (issue 15's audit).
#![deny(clippy::indexing_slicing)]

mod animation;
mod gltf;
mod html;
mod mesh;
mod plot;
mod threejs;

use crate::dynamics::{kinematics, Plan, Workspace};
use crate::joints::Source;
use crate::model::Model;
use crate::solver::IdaStats;
use std::io::Write;

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
    /// Wall-clock time of the integration [s].
    pub wall_time: f64,
}

/// An event: a located root at which the integration restarted.
#[derive(Clone, Debug, PartialEq)]
pub struct Event {
    /// Time [s].
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
    /// Writing a file failed.
    #[error("cannot write `{path}`: {source}")]
    Io {
        /// The path.
        path: String,
        /// The cause.
        source: std::io::Error,
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

/// The outcome of a simulation: output time points, states `y = [q; v]` at each, statistics
/// and events. Signals are derived on demand.
#[derive(Clone, Debug)]
pub struct SimulationResult {
    model: Model,
    time: Vec<f64>,
    states: Vec<f64>,
    /// Counters of the run.
    pub stats: SimStats,
    /// Events in time order.
    pub events: Vec<Event>,
    contacts: Option<ContactRecord>,
    /// Constraint multipliers `λ` of closed loops (`Plan::loops.m()` per time point).
    multipliers: Vec<f64>,
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
            contacts: None,
            multipliers: vec![],
        }
    }

    pub(crate) fn push_multipliers(&mut self, lambda: &[f64]) {
        self.multipliers.extend_from_slice(lambda);
    }

    /// `<cut>.f` (force on obj2 [N]) and `<cut>.t` (torque on obj2 [N·m]) of cut joint `owner`,
    /// both resolved in obj1's frame; the force acts at obj2's origin, obj1 feels the opposite.
    fn loop_signal(&self, owner: &str, field: &str) -> Option<Signal> {
        let plan = &*self.model.plan;
        let c = plan.loops.cuts.iter().position(|c| c.name == owner)?;
        let unit = match field {
            "f" => "N",
            "t" => "N·m",
            _ => return None,
        };
        let (nq, m) = (plan.nq, plan.loops.m());
        let mut ws = Workspace::new(plan);
        let mut data = Vec::with_capacity(3 * self.time.len());
        for (k, y) in self.states_iter().enumerate() {
            let (q, v) = y.split_at(nq);
            kinematics::position_velocity(plan, &mut ws, q, v);
            let lambda = self.multipliers.get(k * m..(k + 1) * m)?;
            let (f, t) = crate::dynamics::loops::cut_wrench(plan, &ws, c, lambda);
            data.extend_from_slice(if field == "f" {
                f.as_slice()
            } else {
                t.as_slice()
            });
        }
        Some(Signal {
            name: format!("{owner}.{field}"),
            unit,
            dim: 3,
            data,
        })
    }

    pub(crate) fn enable_contact_record(&mut self) {
        if self.model.contact.is_some() {
            self.contacts = Some(ContactRecord::default());
        }
    }

    pub(crate) fn push_contacts(&mut self, cs: &crate::contact::ContactState) {
        let Some(rec) = self.contacts.as_mut() else {
            return;
        };
        for ps in &cs.pairs {
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

    /// Names `"<a>|<b>"` of the candidate collision pairs (owners of the contact signals).
    pub fn contact_pairs(&self) -> Vec<String> {
        match &self.model.contact {
            Some(cp) => (0..cp.pairs.len())
                .map(|p| cp.pair_name(&self.model.plan.scene, p))
                .collect(),
            None => vec![],
        }
    }

    fn contact_signal(&self, owner: &str, field: &str) -> Option<Signal> {
        let rec = self.contacts.as_ref()?;
        let p = self.contact_pairs().iter().position(|n| n == owner)?;
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
        let np = self.model.contact.as_ref()?.pairs.len();
        let stride = np * PAIR_VALUES;
        let base = p * PAIR_VALUES + off;
        let mut data = Vec::with_capacity(dim * self.time.len());
        for k in 0..self.time.len() {
            let at = k * stride + base;
            data.extend_from_slice(rec.data.get(at..at + dim)?);
        }
        Some(Signal {
            name: format!("{owner}.{field}"),
            unit,
            dim,
            data,
        })
    }

    pub(crate) fn push(&mut self, t: f64, y: &[f64]) {
        self.time.push(t);
        self.states.extend_from_slice(y);
    }

    /// Output time points [s].
    pub fn time(&self) -> &[f64] {
        &self.time
    }

    /// Number of unknowns per time point (`nq + nv`).
    pub fn state_len(&self) -> usize {
        self.model.plan.nq + self.model.plan.nv
    }

    /// State `y = [q; v]` at time point `k`; `None` if `k` is not a recorded time point
    /// (`k >= time().len()`). Never panics.
    pub fn state(&self, k: usize) -> Option<&[f64]> {
        if k >= self.time.len() {
            return None;
        }
        let n = self.state_len();
        // k < time().len(), and `states` holds n values per time point: no overflow.
        self.states.get(k * n..(k + 1) * n)
    }

    /// The states at every time point, in order.
    fn states_iter(&self) -> impl Iterator<Item = &[f64]> + '_ {
        (0..self.time.len()).filter_map(|k| self.state(k))
    }

    /// The final state, if any time point was recorded.
    pub fn final_state(&self) -> Option<&[f64]> {
        self.time.len().checked_sub(1).and_then(|k| self.state(k))
    }

    /// The plan the run was made with.
    pub fn plan(&self) -> &Plan {
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

    /// Names of all signals: joint coordinates (each kind's, e.g. `rev.phi`, `rev.w`;
    /// `slide.s`, `slide.v`; `free.r`, `free.q`, `free.w`, `free.v`) and object motions (`obj.r_abs`, `obj.v_abs`,
    /// `obj.w_abs`, `obj.R_abs`).
    pub fn signal_names(&self) -> Vec<String> {
        let mut names = vec![];
        names.extend(self.joint_signal_names());
        for o in &self.model.plan.objects {
            for s in ["r_abs", "v_abs", "w_abs", "R_abs"] {
                names.push(format!("{}.{s}", o.name));
            }
        }
        for c in &self.model.plan.loops.cuts {
            names.push(format!("{}.f", c.name));
            names.push(format!("{}.t", c.name));
        }
        if self.contacts.is_some() {
            for p in self.contact_pairs() {
                for f in [
                    "in_contact",
                    "penetration",
                    "f_n",
                    "friction_force",
                    "rolling_torque",
                    "point",
                    "normal",
                ] {
                    names.push(format!("{p}.{f}"));
                }
            }
        }
        names
    }

    /// A signal by name, optionally with a component index: `"rev.phi"`, `"ball.r_abs"`,
    /// `"ball.r_abs[2]"`. Object signals are resolved in world: `r_abs` [m], `v_abs` [m/s],
    /// `w_abs` [rad/s], `R_abs` (rotation matrix, row-major, columns = object axes).
    /// With [`crate::SimOptions::contact_results`], per collision pair `"<a>|<b>"` (see
    /// [`Self::contact_pairs`]; normal from `a` to `b`, forces and torque on `b`, all in world):
    /// `in_contact` (1/0), `penetration` [m], `f_n` [N], `friction_force` [N],
    /// `rolling_torque` [N·m], `point` [m], `normal` [1]; zero while not in contact.
    /// Per cut joint of a closed loop (see `Model::loops`): `<joint>.f`, the constraint force
    /// [N] on obj2 at obj2's origin, and `<joint>.t`, the constraint torque [N·m] on obj2, both
    /// resolved in obj1's frame (obj1 feels the opposite).
    pub fn signal(&self, name: &str) -> Result<Signal, ResultError> {
        let unknown = |reason: String| ResultError::UnknownSignal {
            name: name.to_string(),
            reason,
        };
        let (base, index) = match name.strip_suffix(']').and_then(|s| s.rsplit_once('[')) {
            Some((b, i)) => (
                b,
                Some(
                    i.parse::<usize>()
                        .map_err(|_| unknown(format!("`{i}` is not an index")))?,
                ),
            ),
            None => (name, None),
        };
        let (owner, field) = base
            .rsplit_once('.')
            .ok_or_else(|| unknown("expected `<joint or object>.<quantity>`".into()))?;
        let full = self
            .full_signal(owner, field)
            .or_else(|| self.contact_signal(owner, field))
            .or_else(|| self.loop_signal(owner, field))
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

    fn full_signal(&self, owner: &str, field: &str) -> Option<Signal> {
        let plan = &*self.model.plan;
        let nq = plan.nq;
        let nt = self.time.len();
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
            for y in self.states_iter() {
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
        for y in self.states_iter() {
            let (q, v) = y.split_at(nq);
            kinematics::position_velocity(plan, &mut ws, q, v);
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

    /// Writes time and every joint coordinate and object position (`r_abs`) as CSV with a
    /// header of signal names and units.
    pub fn write_csv(&self, path: impl AsRef<std::path::Path>) -> Result<(), ResultError> {
        let path = path.as_ref();
        let io = |source| ResultError::Io {
            path: path.display().to_string(),
            source,
        };
        let mut names: Vec<String> = vec![];
        names.extend(self.joint_signal_names());
        for o in &self.model.plan.objects {
            if o.body.is_some() {
                names.push(format!("{}.r_abs", o.name));
            }
        }
        let signals: Vec<Signal> = names
            .iter()
            .map(|n| self.signal(n))
            .collect::<Result<_, _>>()?;
        let mut out = std::io::BufWriter::new(std::fs::File::create(path).map_err(io)?);
        let mut header = vec!["time [s]".to_string()];
        for s in &signals {
            if s.dim == 1 {
                header.push(format!("{} [{}]", s.name, s.unit));
            } else {
                header.extend((0..s.dim).map(|i| format!("{}[{i}] [{}]", s.name, s.unit)));
            }
        }
        writeln!(out, "{}", header.join(",")).map_err(io)?;
        for (k, t) in self.time.iter().enumerate() {
            let mut row = vec![format!("{t:.17e}")];
            for s in &signals {
                row.extend(s.at(k).unwrap_or(&[]).iter().map(|x| format!("{x:.17e}")));
            }
            writeln!(out, "{}", row.join(",")).map_err(io)?;
        }
        out.flush().map_err(io)
    }
}
