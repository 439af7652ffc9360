//! Load signals: the wrench obj1 exerts on obj2 through every tree joint and every rigid link
//! (`Fix` joint, parent link) between parts of a body, from the stored states on demand
//! (`dynamics/loads.rs` computes them; a run that reads none pays nothing).
//!
//! Names and convention (the cut joints' `<cut>.f`, `<cut>.t` of closed loops are the same
//! wrench, `results/mod.rs`):
//!
//! * per joint (tree joints of every kind, `Fix` joints): `<joint>.f` the force \[N\] on obj2
//!   and `<joint>.t` the torque [N·m] on obj2 about obj2's origin, both resolved in obj1's
//!   frame; `<joint>.f_abs`, `<joint>.t_abs` the same resolved in world; `<joint>.f_obj2`,
//!   `<joint>.t_obj2` the same resolved in obj2's frame (what a load cell on obj2 reads);
//! * per object with a parent (its parent link): `<object>.f_parent`, `<object>.t_parent`, the
//!   wrench the parent exerts on the object's side of the link (the object and everything
//!   rigidly attached to it but through the link), about the object's origin, resolved in the
//!   parent's frame; `<object>.f_parent_abs`, `<object>.t_parent_abs` resolved in world;
//!   `<object>.f_parent_own`, `<object>.t_parent_own` resolved in the object's own frame.
//!
//! `signal_at` takes them at the state of IDA's polynomial with `dense_output` (scenes without
//! collision pairs), else by the cubic of the output points, as the other signals.
//!
//! Contact forces enter from the run's contact record (`SimOptions::contact_results`), so a
//! scene with collision pairs needs it; input values are not recorded, so a scene with inputs
//! has no load signals ([`ResultError::LoadsUnavailable`]).

use super::{parabola_max, ResultError, Signal, SimulationResult, PAIR_VALUES};
use crate::dynamics::ids::JointId;
use crate::dynamics::loads::{
    link_ends, load_pass, rigid_link_wrench, tree_joint_wrench, LinkWrench, LoadError,
    ObjectWrench, RigidLink,
};
use crate::dynamics::{ObjectId, Workspace};
use nalgebra::Vector3;

/// The fields of a joint's load.
const JOINT_FIELDS: [&str; 6] = ["f", "t", "f_abs", "t_abs", "f_obj2", "t_obj2"];
/// The fields of a parent link's load, owned by the child object.
const PARENT_FIELDS: [&str; 6] = [
    "f_parent",
    "t_parent",
    "f_parent_abs",
    "t_parent_abs",
    "f_parent_own",
    "t_parent_own",
];

/// Values per tree joint and output point in [`TreeLoads`]: force and torque in obj1's frame,
/// in world, then in obj2's frame (the order of [`JOINT_FIELDS`]).
const PER_JOINT: usize = 18;

/// Field `i` of a load, in the order of [`JOINT_FIELDS`] and [`PARENT_FIELDS`]: force and
/// torque resolved in obj1's frame, in world, in obj2's frame.
fn field(w: &LinkWrench, i: usize) -> Vector3<f64> {
    let v = if i % 2 == 0 { &w.force } else { &w.torque };
    match i / 2 {
        0 => w.obj1_rot.tr_mul(v),
        1 => *v,
        _ => w.obj2_rot.tr_mul(v),
    }
}

/// The largest of `values` sampled at `time` and when: refined by [`parabola_max`] through it
/// and its neighbours when it is an interior sample (never below the sample itself).
fn peak_of(time: &[f64], values: &[f64]) -> (f64, f64) {
    let Some((k, &v)) = values
        .iter()
        .enumerate()
        .filter(|(_, v)| v.is_finite())
        .max_by(|a, b| a.1.total_cmp(b.1))
    else {
        return (f64::NAN, f64::NAN);
    };
    let at = |k: usize| time.get(k).copied().unwrap_or(f64::NAN);
    let (Some(&[t0, t1, t2]), Some(&[v0, _, v2])) = (
        k.checked_sub(1).and_then(|i| time.get(i..i + 3)),
        k.checked_sub(1).and_then(|i| values.get(i..i + 3)),
    ) else {
        return (at(k), v);
    };
    match parabola_max([t0, t1, t2], [v0, v, v2]) {
        Some((t, p)) if p >= v => (t, p),
        _ => (t1, v),
    }
}

/// Every tree joint's load at every output point (`PER_JOINT` values per joint, joints in
/// plan order, point after point), or the first point whose loads could not be computed, with
/// the reason.
pub(super) type TreeLoads = Result<Vec<f64>, Box<(f64, LoadError)>>;

/// The largest load one joint carried over a run ([`SimulationResult::joint_load_peaks`]).
#[derive(Clone, Debug, PartialEq)]
pub struct JointLoadPeak {
    /// The joint (a tree joint of any kind, a `Fix` joint or a loop's cut joint).
    pub joint: String,
    /// The largest magnitude of the force obj1 exerts on obj2 through it \[N\].
    pub max_force: f64,
    /// When it occurred \[s\].
    pub t_max_force: f64,
    /// The largest magnitude of the torque on obj2 about obj2's origin [N·m].
    pub max_torque: f64,
    /// When it occurred \[s\].
    pub t_max_torque: f64,
}

/// Whose load a signal asks for.
#[derive(Clone, Copy)]
enum Owner {
    Tree(JointId),
    Link(RigidLink),
}

impl SimulationResult {
    /// The owner and field index (into [`JOINT_FIELDS`] / [`PARENT_FIELDS`]) of a load signal.
    fn load_owner(&self, owner: &str, field: &str) -> Option<(Owner, usize)> {
        let plan = &*self.model.plan;
        if let Some(i) = JOINT_FIELDS.iter().position(|f| *f == field) {
            if let Some(j) = plan.joint_index(owner) {
                return Some((Owner::Tree(j), i));
            }
            let sj = plan.scene.joints.iter().position(|j| {
                j.name == owner
                    && j.kind.is_rigid()
                    && !plan.loops.cuts.iter().any(|c| c.name == owner)
            })?;
            return Some((Owner::Link(RigidLink::Fix(sj)), i));
        }
        let i = PARENT_FIELDS.iter().position(|f| *f == field)?;
        let o = plan.object_index(owner)?;
        plan.scene.objects.get(o.index())?.parent?;
        Some((Owner::Link(RigidLink::Parent(o.index())), i))
    }

    /// Why this result has no load signals, if it has none: `Some(Err)` for a scene with
    /// collision pairs whose run did not record the contacts, `Some(Ok(reason))` for a scene
    /// with inputs.
    fn loads_unavailable(&self, name: &str) -> Option<Result<String, ResultError>> {
        let plan = &*self.model.plan;
        if !plan.inputs.is_empty() {
            let inputs: Vec<&str> = plan.inputs.iter().map(|i| i.name.as_str()).collect();
            return Some(Ok(format!(
                "the scene has inputs ({}), whose values a result does not record; \
                 without inputs the loads are computed from the stored states",
                inputs.join(", ")
            )));
        }
        if self.model.contact.is_some() && self.contacts.is_none() {
            return Some(Err(ResultError::ContactResultsOff {
                what: format!("signal `{name}` (a joint load includes the contact forces)"),
            }));
        }
        None
    }

    /// The joint limits' generalised forces recorded at time point `k`: (velocity index,
    /// value).
    fn limit_forces_at(&self, k: usize) -> Vec<(usize, f64)> {
        let n = self.limit_v.len();
        let recorded = self.limit_forces.get(k * n..(k + 1) * n).unwrap_or(&[]);
        let mut forces: Vec<(usize, f64)> = self
            .limit_v
            .iter()
            .copied()
            .zip(recorded.iter().copied())
            .collect();
        // The components' flange forces (their geared inertias are in the mass matrix).
        let fv = &self.model.plan.components.flange_v;
        let nf = fv.len();
        let flanges = self.flange_forces.get(k * nf..(k + 1) * nf).unwrap_or(&[]);
        forces.extend(fv.iter().copied().zip(flanges.iter().copied()));
        forces
    }

    /// The contact wrenches on objects recorded at time point `k` (with `contact_results`).
    fn contact_wrenches_at(&self, k: usize) -> Vec<ObjectWrench> {
        let (Some(rec), Some(cp)) = (self.contacts.as_ref(), self.model.contact.as_deref()) else {
            return vec![];
        };
        let stride = cp.n_pairs * PAIR_VALUES;
        let mut out = vec![];
        for (p, pp) in cp.candidate_pairs().enumerate() {
            let at = k * stride + p * PAIR_VALUES;
            let Some(x) = rec.data.get(at..at + PAIR_VALUES) else {
                break;
            };
            // in_contact, penetration, f_n, friction, rolling torque, point, normal: on shape b,
            // the opposite on a.
            let Ok([on, _, f_n, fx, fy, fz, tx, ty, tz, px, py, pz, nx, ny, nz]) =
                <[f64; PAIR_VALUES]>::try_from(x)
            else {
                break;
            };
            if on != 1.0 {
                continue;
            }
            let torque = Vector3::new(tx, ty, tz);
            let point = Vector3::new(px, py, pz);
            let force = Vector3::new(nx, ny, nz) * f_n + Vector3::new(fx, fy, fz);
            let (Some(sa), Some(sb)) = (cp.shapes.get(pp.a), cp.shapes.get(pp.b)) else {
                continue;
            };
            out.push(ObjectWrench {
                object: ObjectId(sb.object),
                point,
                force,
                torque,
            });
            out.push(ObjectWrench {
                object: ObjectId(sa.object),
                point,
                force: -force,
                torque: -torque,
            });
        }
        out
    }

    /// A load signal (see the module docs); `None` if `owner.field` is none.
    pub(super) fn load_signal(
        &self,
        owner: &str,
        field: &str,
    ) -> Option<Result<Signal, ResultError>> {
        let (who, i) = self.load_owner(owner, field)?;
        let name = format!("{owner}.{field}");
        if let Some(e) = self.loads_error(&name) {
            return Some(Err(e));
        }
        let plan = &*self.model.plan;
        let (nq, m) = (plan.nq, plan.loops.m());
        if let Owner::Tree(j) = who {
            // From the table of every tree joint's loads: one pass per point for all of them.
            let table = match self.tree_loads.get_or_init(|| self.tree_loads_table()) {
                Ok(table) => table,
                Err(failure) => {
                    let (t, e) = &**failure;
                    return Some(Err(load_error(e.clone(), *t, &name)));
                }
            };
            let nj = plan.joints.len();
            let off = j.index() * PER_JOINT + 3 * i;
            let data = (0..self.time.len())
                .flat_map(|k| {
                    let at = (k * nj) * PER_JOINT + off;
                    table
                        .get(at..at + 3)
                        .unwrap_or(&[f64::NAN; 3])
                        .iter()
                        .copied()
                })
                .collect();
            return Some(Ok(Signal {
                name,
                unit: if i % 2 == 0 { "N" } else { "N·m" },
                dim: 3,
                data,
            }));
        }
        let mut ws = Workspace::new(plan);
        let mut data = Vec::with_capacity(3 * self.time.len());
        for (k, y) in self.states_iter().enumerate() {
            let t = self.time.get(k).copied().unwrap_or(f64::NAN);
            let Some(lambda) = self.multipliers.get(k * m..(k + 1) * m) else {
                return Some(Err(load_error(LoadError::Singular, t, &name)));
            };
            let contacts = self.contact_wrenches_at(k);
            let stops = self.limit_forces_at(k);
            let (q, v) = y.split_at(nq);
            match self.load_at(
                &mut ws,
                (who, i),
                (t, q, v),
                lambda,
                (&contacts, &stops),
                &name,
            )? {
                Ok(value) => data.extend_from_slice(value.as_slice()),
                Err(e) => return Some(Err(e)),
            }
        }
        Some(Ok(Signal {
            name,
            unit: if i % 2 == 0 { "N" } else { "N·m" },
            dim: 3,
            data,
        }))
    }

    /// The load signal `name` (optionally `[i]`) at `t` \[s\] from the state that IDA's
    /// interpolating polynomial gives (`SimOptions::dense_output`), as joint and object signals
    /// are; `None` without dense output, outside it, for a scene with collision pairs or joint
    /// limits (whose contact and stop forces are recorded at the output points only: the cubic
    /// of the output points answers) and for other signals.
    pub(super) fn dense_load_at(
        &self,
        name: &str,
        t: f64,
    ) -> Option<Result<Vec<f64>, ResultError>> {
        if self.model.contact.is_some() {
            return None;
        }
        let (base, owner, field, index) = super::split_signal_name(name).ok()?;
        let (who, i) = self.load_owner(owner, field)?;
        if let Some(e) = self.loads_error(base) {
            return Some(Err(e));
        }
        let plan = &*self.model.plan;
        let (nq, nv, m) = (plan.nq, plan.nv, plan.loops.m());
        let y = self.dense.state_at(t, nq + nv + m)?;
        let (q, rest) = y.split_at(nq);
        let (v, lambda) = rest.split_at(nv.min(rest.len()));
        if v.len() != nv || lambda.len() != m {
            return None;
        }
        if !self.limit_v.is_empty() {
            // The stops' forces exist at output points only (as contact forces): the cubic.
            return None;
        }
        let mut ws = Workspace::new(plan);
        let value = match self.load_at(&mut ws, (who, i), (t, q, v), lambda, (&[], &[]), base)? {
            Ok(value) => value,
            Err(e) => return Some(Err(e)),
        };
        Some(Ok(match index {
            None => value.as_slice().to_vec(),
            Some(k) => vec![*value.get(k)?],
        }))
    }

    /// Every tree joint's load at every output point ([`TreeLoads`]).
    fn tree_loads_table(&self) -> TreeLoads {
        let plan = &*self.model.plan;
        let (nq, m, nj) = (plan.nq, plan.loops.m(), plan.joints.len());
        let mut ws = Workspace::new(plan);
        let mut table = Vec::with_capacity(PER_JOINT * nj * self.time.len());
        for (k, y) in self.states_iter().enumerate() {
            let t = self.time.get(k).copied().unwrap_or(f64::NAN);
            let Some(lambda) = self.multipliers.get(k * m..(k + 1) * m) else {
                return Err(Box::new((t, LoadError::Singular)));
            };
            let (q, v) = y.split_at(nq);
            let contacts = self.contact_wrenches_at(k);
            let stops = self.limit_forces_at(k);
            load_pass(plan, &mut ws, (t, q, v), lambda, &contacts, &stops)
                .map_err(|e| Box::new((t, e)))?;
            for j in 0..nj {
                let w = tree_joint_wrench(plan, &ws, JointId(j));
                for i in 0..JOINT_FIELDS.len() {
                    table.extend_from_slice(field(&w, i).as_slice());
                }
            }
        }
        Ok(table)
    }

    /// [`Self::loads_unavailable`] as the error of signal `name`.
    fn loads_error(&self, name: &str) -> Option<ResultError> {
        match self.loads_unavailable(name)? {
            Err(e) => Some(e),
            Ok(reason) => Some(ResultError::LoadsUnavailable {
                signal: name.to_string(),
                reason,
            }),
        }
    }

    /// Field `i` of the load of `who` at one state; `None` if `who` is no load's owner, the
    /// error of signal `name` if the state has no accelerations.
    fn load_at(
        &self,
        ws: &mut Workspace,
        (who, i): (Owner, usize),
        (t, q, v): (f64, &[f64], &[f64]),
        lambda: &[f64],
        (contacts, stops): (&[ObjectWrench], &[(usize, f64)]),
        name: &str,
    ) -> Option<Result<Vector3<f64>, ResultError>> {
        let plan = &*self.model.plan;
        let wrench = load_pass(plan, ws, (t, q, v), lambda, contacts, stops).and_then(|()| {
            Ok(match who {
                Owner::Tree(j) => Some(tree_joint_wrench(plan, ws, j)),
                Owner::Link(link) => {
                    rigid_link_wrench(plan, ws, link, (t, q, v), lambda, contacts)?
                }
            })
        });
        let w: LinkWrench = match wrench {
            Ok(Some(w)) => w,
            Ok(None) => return None,
            Err(e) => return Some(Err(load_error(e, t, name))),
        };
        Some(Ok(field(&w, i)))
    }

    /// Every joint's largest load over the run, joints in the order of
    /// [`Self::signal_names`]: the largest magnitude of `<joint>.f_abs` and of `<joint>.t_abs`
    /// over the output points, refined by the parabola through the largest sample and its two
    /// neighbours (exact for a peak that is locally quadratic; a peak between output points
    /// that no sample comes near is missed — `SimOptions::output_steps(true)` samples every
    /// step). Computed on demand as the load signals are, with their errors
    /// ([`ResultError::LoadsUnavailable`], [`ResultError::ContactResultsOff`]).
    pub fn joint_load_peaks(&self) -> Result<Vec<JointLoadPeak>, ResultError> {
        if let Some(e) = self.loads_error("joint_load_peaks()") {
            return Err(e);
        }
        let mut joints: Vec<String> = self
            .load_signal_names()
            .iter()
            .filter_map(|n| n.strip_suffix(".f_abs"))
            .map(str::to_string)
            .collect();
        let plan = &*self.model.plan;
        joints.extend(plan.loops.cuts.iter().map(|c| c.name.clone()));
        let peak = |name: &str| -> Result<(f64, f64), ResultError> {
            let s = self.signal(name)?;
            let mags: Vec<f64> = (0..self.time.len())
                .map(|k| {
                    s.at(k)
                        .map_or(f64::NAN, |v| v.iter().map(|x| x * x).sum::<f64>().sqrt())
                })
                .collect();
            Ok(peak_of(&self.time, &mags))
        };
        joints
            .into_iter()
            .map(|joint| {
                let (t_max_force, max_force) = peak(&format!("{joint}.f_abs"))?;
                let (t_max_torque, max_torque) = peak(&format!("{joint}.t_abs"))?;
                Ok(JointLoadPeak {
                    joint,
                    max_force,
                    t_max_force,
                    max_torque,
                    t_max_torque,
                })
            })
            .collect()
    }

    /// Names of the load signals this result can give (none when they are unavailable: see
    /// the module docs): every tree joint's and `Fix` joint's, every parent link's.
    pub(super) fn load_signal_names(&self) -> Vec<String> {
        if self.loads_unavailable("").is_some() {
            return vec![];
        }
        let plan = &*self.model.plan;
        let mut names = vec![];
        // Rigid links are listed where obj2 moves (as `signal_names` lists only what moves);
        // those within the world's cluster stay readable by name.
        let moves = |o: usize| {
            plan.objects
                .get(ObjectId(o))
                .is_some_and(|x| x.body.is_some())
        };
        for j in &plan.joints {
            names.extend(JOINT_FIELDS.iter().map(|f| format!("{}.{f}", j.name)));
        }
        for (sj, j) in plan.scene.joints.iter().enumerate() {
            let cut = plan.loops.cuts.iter().any(|c| c.scene_joint == sj);
            if j.kind.is_rigid() && !cut && moves(j.obj2) {
                names.extend(JOINT_FIELDS.iter().map(|f| format!("{}.{f}", j.name)));
            }
        }
        for (o, obj) in plan.scene.objects.iter().enumerate() {
            if link_ends(plan, RigidLink::Parent(o)).is_some() && moves(o) {
                names.extend(PARENT_FIELDS.iter().map(|f| format!("{}.{f}", obj.name)));
            }
        }
        names
    }
}

/// The error of load signal `name` whose state at `t` \[s\] gave `e`.
fn load_error(e: LoadError, t: f64, name: &str) -> ResultError {
    let reason = match e {
        LoadError::Singular => format!(
            "the mass matrix is singular at t = {t} s (or the run recorded no loop multipliers \
             there): no accelerations to compute the loads from"
        ),
        LoadError::User(f) => format!(
            "{} failed at t = {t} s when the loads were computed: {:?}",
            f.element_name(),
            f.kind
        ),
    };
    ResultError::LoadsUnavailable {
        signal: name.to_string(),
        reason,
    }
}
