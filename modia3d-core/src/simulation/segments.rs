//! Driver: segmented simulation (dynamic structure, Modia3D's gripping). An action — attach a
//! free object rigidly to another, release an attached object, delete an object — changes the
//! structure between IDA segments:
//!
//! 1. the scene description of the current model is edited (attach: the object's FreeMotion
//!    joint removed and the object parented to `to` at their current relative pose; release:
//!    the parent link removed and a FreeMotion joint relative to the world added, its initial
//!    values the current absolute pose and velocity; delete: the object, its parent-link
//!    descendants, their joints, force elements and inputs removed) and built again: a new
//!    [`Model`] with its own state layout;
//! 2. positions: every joint the new model shares (by name) with the old one keeps its
//!    coordinates, a new FreeMotion takes the current pose, so every object keeps its pose;
//! 3. velocities: the new generalised velocities are the momentum-conserving projection of the
//!    old motion (a perfectly plastic impulse), `v⁺ = argmin Σₒ ‖V_o(v⁺) − V_o⁻‖²_{I_o}` over
//!    the objects `o` with mass (`V_o` an object's twist at its centre of mass, `I_o` its
//!    inertia), i.e. `M⁺ v⁺ = Σₒ J_oᵀ I_o V_o⁻` with `M⁺ = Σₒ J_oᵀ I_o J_o` the new mass
//!    matrix; prescribed coordinates keep their velocities and are moved to the right-hand
//!    side. When the old motion is one the new structure can make (release, delete) it is
//!    reproduced exactly; on an attach the residual is orthogonal, in the kinetic-energy
//!    metric, to every motion the new structure can make, so the momentum conjugate to each of
//!    them is conserved — in particular the total linear and angular momentum whenever a rigid
//!    motion of the whole system is one of them (a free-floating system), and the angular
//!    momentum about the axis of a world joint that carries everything. Kinetic energy never
//!    increases. This is `v⁺ = (Tᵀ M⁻ T)⁻¹ Tᵀ M⁻ v⁻` with `T` the map from new to old
//!    velocities, computed object by object so that no `T` in joint coordinates is needed.
//! 4. IDA is started anew (its vector length changes) with consistent derivatives, inputs
//!    carried over by name; the action is an event of the log, and the results continue in
//!    one [`SimulationResult`](crate::SimulationResult) (`results/segments.rs`).
//!
//! The gap rule (Modia3D's `gap`): an attach happens only when the two objects are at most
//! `gap` apart: the signed distance of their solids' shapes (the narrow phase; negative when
//! they overlap), or, when one has no shape, the distance of their frame origins; otherwise
//! [`ActionError::OutOfGap`] names both and the distance.
// No panic on user input: indexing goes through `get` and iterators (issue 15's audit).
#![deny(clippy::indexing_slicing)]

use super::{derivative_error, ida_options, record, SimErrorKind, Simulation};
use crate::dae::MultibodyDae;
use crate::dynamics::ids::ObjectId;
use crate::dynamics::{kinematics, Plan, Workspace};
use crate::geometry::{signed_distance, CollisionShape, NarrowPhaseOptions};
use crate::model::Model;
use crate::results::Event;
use crate::scene::{
    did_you_mean, Action, ActionKind, Feature, ForceElement, FreeRotation, InputKind, Joint,
    JointKind, Rotation, SceneDesc, SceneErrors,
};
use crate::solver::{DaeSystem, Ida, IdaStats};
use crate::spatial::Transform;
use nalgebra::{
    DMatrix, DVector, Isometry3, Matrix3, Rotation3, Translation3, UnitQuaternion, Vector3,
};
use std::sync::Arc;

/// Why an action (attach, release, delete) could not be carried out. The simulation is left
/// unchanged by every error except [`ActionError::Restart`].
#[derive(thiserror::Error, Debug, Clone, PartialEq)]
pub enum ActionError {
    /// The action names an object the current structure does not have (never declared, or
    /// deleted by an earlier action).
    #[error("no object `{object}` in the current structure{}", match .hint { Some(h) => format!(" (hint: did you mean `{h}`?)"), None => " (it may have been deleted by an earlier action)".into() })]
    UnknownObject {
        /// The name given.
        object: String,
        /// A close existing name.
        hint: Option<String>,
    },
    /// Attach of an object that no FreeMotion joint moves.
    #[error("cannot attach `{object}`: it is not obj2 of a FreeMotion joint; only a free object (declared with a FreeMotion, or released) can be attached")]
    NotFree {
        /// The object.
        object: String,
    },
    /// Attach while the two objects are farther apart than the gap.
    #[error("cannot attach `{object}` to `{to}`: they are {distance:.4e} m apart, more than the gap {gap:.4e} m; attach when they are closer, or widen the gap")]
    OutOfGap {
        /// The object to attach.
        object: String,
        /// The object to attach it to.
        to: String,
        /// Their distance \[m\] (signed distance of the shapes, or of the frame origins).
        distance: f64,
        /// The gap \[m\].
        gap: f64,
    },
    /// Release of an object that has no parent link.
    #[error("cannot release `{object}`: it has no parent link; only an object fixed by a parent (e.g. by an attach) can be released")]
    NotAttached {
        /// The object.
        object: String,
    },
    /// The action names the world (the `Scene` object).
    #[error("cannot {action} the world object `{object}`")]
    World {
        /// `"attach"`, `"release"` or `"delete"`.
        action: &'static str,
        /// The world's name.
        object: String,
    },
    /// The structure after the action is not a valid scene (e.g. deleting an object leaves a
    /// part unconnected, or an attach closes a rigid loop).
    #[error("the structure after {action} is invalid: {errors}")]
    Rebuild {
        /// The action, e.g. ``delete `link2` ``.
        action: String,
        /// What is wrong with it.
        errors: SceneErrors,
    },
    /// The new structure has no consistent start (e.g. a singular mass matrix).
    #[error("{action}: no consistent restart: {kind}")]
    Restart {
        /// The action.
        action: String,
        /// Why.
        kind: Box<SimErrorKind>,
    },
}

/// The driver's record of structure changes.
pub(super) struct SegmentState {
    /// The model the run started with (what [`Simulation::reset`] returns to).
    pub(super) initial: Model,
    /// IDA's counters of the finished segments.
    pub(super) solver_base: IdaStats,
    /// The scene's actions, by time (stable: declaration order at equal times).
    schedule: Vec<Action>,
    /// Index of the next action of `schedule`.
    next: usize,
    /// FreeMotion joints removed by attaches: (object, joint name), so that a release gives
    /// the object its joint (and signals) back.
    freed: Vec<(String, String)>,
}

impl SegmentState {
    pub(super) fn new(model: &Model) -> Self {
        let mut schedule = model.desc.actions.clone();
        schedule.sort_by(|a, b| a.at.total_cmp(&b.at));
        SegmentState {
            initial: model.clone(),
            solver_base: IdaStats::default(),
            schedule,
            next: 0,
            freed: vec![],
        }
    }
}

/// A structure change worked out on the description, not yet applied.
struct Change {
    desc: SceneDesc,
    /// What happened, for the event log.
    description: String,
    /// `freed` after the change.
    freed: Vec<(String, String)>,
}

impl Simulation {
    /// Fixes the free object `object` rigidly to `to` at their current relative pose
    /// (gripping), if they are at most `gap` \[m\] apart (`f64::INFINITY`: always). The
    /// velocities jump as in a perfectly plastic impact (momentum conserved, see the module
    /// docs of `simulation/segments.rs`); the run goes on from the current time with the new
    /// structure, and the results continue in one result.
    pub fn attach(&mut self, object: &str, to: &str, gap: f64) -> Result<(), ActionError> {
        self.apply(&Action::attach("attach", self.time(), object, to, gap))
    }

    /// Releases `object` (attached, or rigidly parented) into free motion relative to the world,
    /// at its current pose and velocity (no jump). Its FreeMotion joint is the one an attach
    /// removed (same name and signals), else `<object>_free`.
    pub fn release(&mut self, object: &str) -> Result<(), ActionError> {
        self.apply(&Action::release("release", self.time(), object))
    }

    /// Deletes `object`, the objects parented to it (transitively), their joints, force
    /// elements and inputs; the others keep their motion. The state shrinks accordingly.
    pub fn delete(&mut self, object: &str) -> Result<(), ActionError> {
        self.apply(&Action::delete("delete", self.time(), object))
    }

    /// The model of the current structure (the initial one until an action changes it).
    pub fn model(&self) -> &Model {
        &self.model
    }

    /// `advance` with the scene's scheduled actions carried out at their times on the way.
    pub(super) fn advance_with_actions(&mut self, t: f64) -> Result<(), SimErrorKind> {
        let eps = 1e-12 * self.opts.stop_time.abs().max(1.0);
        while let Some(a) = self
            .segments
            .schedule
            .get(self.segments.next)
            .filter(|a| a.at <= t + eps)
            .cloned()
        {
            self.advance(a.at.max(self.time()))?;
            self.segments.next += 1;
            self.apply(&a).map_err(|e| SimErrorKind::Action {
                t: self.time(),
                error: Box::new(e),
            })?;
        }
        self.advance(t)
    }

    /// Time \[s\] of the next scheduled action not carried out yet.
    pub(super) fn next_action_time(&self) -> Option<f64> {
        self.segments.schedule.get(self.segments.next).map(|a| a.at)
    }

    /// Carries out `action` at the current time (see the module docs).
    fn apply(&mut self, action: &Action) -> Result<(), ActionError> {
        let t = self.time();
        let old = self.model.plan.clone();
        let y_old = self.ida.y().to_vec();
        let (q_old, v_old) = split_state(&old, &y_old);
        let mut ws_old = Workspace::new(&old);
        kinematics::position_velocity(&old, &mut ws_old, q_old, v_old);
        let now = Now {
            plan: &old,
            ws: &ws_old,
        };
        let change = edit(&self.model.desc, &self.segments.freed, action, &now)?;
        let rebuild = |errors: SceneErrors| ActionError::Rebuild {
            action: action.describe(),
            errors,
        };
        let mut plan = Plan::compile(change.desc.validated().map_err(rebuild)?);
        plan.q0 = map_positions(&old, q_old, &plan);
        plan.v0 = project_velocities(&now, v_old, &plan);
        let mut model = Model::finish(plan, false).map_err(rebuild)?;
        model.desc = Arc::new(change.desc);
        let description = format!("action `{}`: {}", action.name, change.description);
        self.start_segment(model, t, description)
            .map_err(|kind| ActionError::Restart {
                action: action.describe(),
                kind: Box::new(kind),
            })?;
        self.segments.freed = change.freed;
        Ok(())
    }

    /// Starts IDA on `model` at `t` \[s\] from its `y0` (inputs carried over by name), then
    /// switches the run to it: the old segment's counters kept, the action logged.
    fn start_segment(
        &mut self,
        model: Model,
        t: f64,
        description: String,
    ) -> Result<(), SimErrorKind> {
        let mut dae = MultibodyDae::new(model.plan.clone(), model.contact.clone());
        dae.set_analytic_jacobian(self.opts.analytic_jacobian);
        dae.set_contact_tightening(self.opts.effective_contact_tightening());
        dae.set_tolerance(self.opts.rtol);
        let old_inputs = self.ida.system_mut().inputs_mut().to_vec();
        for inp in &model.plan.inputs {
            let before = self.model.plan.inputs.iter().find(|i| i.name == inp.name);
            let values = before.and_then(|b| old_inputs.get(b.offset..b.offset + b.len));
            let slot = dae.inputs_mut().get_mut(inp.offset..inp.offset + inp.len);
            if let (Some(values), Some(slot)) = (values, slot) {
                if values.len() == slot.len() {
                    slot.copy_from_slice(values);
                }
            }
        }
        let mut y = model.plan.y0();
        y.resize(DaeSystem::len(&dae), 0.0);
        carry_components(&self.model.plan, self.ida.y(), &model.plan, &mut y);
        if let (Some(old), Some(new)) = (
            self.ida
                .system_mut()
                .component_discrete_mut()
                .map(|d| d.to_vec()),
            dae.component_discrete_mut(),
        ) {
            carry_discrete(&self.model.plan, &old, &model.plan, new);
        }
        dae.handle_event(t, &y)?;
        let yp = dae
            .consistent_derivative(t, &mut y)
            .map_err(|e| derivative_error(e, t))?;
        let roots = dae.num_roots_public();
        let ida_opts = ida_options(&model.plan, &self.opts, y.len(), &dae);
        let ida = Ida::new(dae, t, &y, &yp, &ida_opts)?;
        // Nothing fails from here on: the run switches to the new structure.
        let old_ida = std::mem::replace(&mut self.ida, ida);
        self.phase_scratch.forget();
        self.guard_due = true;
        self.segments.solver_base += old_ida.stats();
        self.model = model.clone();
        self.result.begin_segment(model, t);
        self.result.phase_event(self.ida.system(), t);
        tracing::info!(t, %description, "structure changed");
        self.result.events.push(Event {
            t,
            description,
            started: vec![],
            ended: vec![],
        });
        record(
            self.ida.system_mut(),
            &mut self.result,
            t,
            &y,
            self.opts.contact_results,
        );
        self.result.stats.root_functions = roots;
        self.h_max = self.opts.max_step;
        self.inputs_changed = false;
        self.stalled = 0;
        self.update_stats();
        Ok(())
    }
}

/// The components' continuous states of `y_old` (of `old`) written into `y` (of `new`), by
/// component name (components keep their states across structure changes; a new one starts
/// at its initial values).
fn carry_components(old: &Plan, y_old: &[f64], new: &Plan, y: &mut [f64]) {
    let (xo_old, xo) = (old.x_offset(), new.x_offset());
    let xs = new.components.x0.iter().copied();
    for (slot, v) in y.iter_mut().skip(xo).zip(xs) {
        *slot = v;
    }
    for c in &new.components.comps {
        if let Some(o) = old.components.comps.iter().find(|o| o.name == c.name) {
            if o.x.len() == c.x.len() {
                let src = y_old.get(xo_old + o.x.start..xo_old + o.x.end);
                if let (Some(src), Some(dst)) = (src, y.get_mut(xo + c.x.start..xo + c.x.end)) {
                    dst.copy_from_slice(src);
                }
            }
        }
    }
}

/// The components' discrete states carried as [`carry_components`] carries the continuous.
fn carry_discrete(old: &Plan, d_old: &[f64], new: &Plan, d: &mut [f64]) {
    for c in &new.components.comps {
        if let Some(o) = old.components.comps.iter().find(|o| o.name == c.name) {
            if let (Some(dst), Some(src)) = (d.get_mut(c.d.clone()), d_old.get(o.d.clone())) {
                if dst.len() == src.len() {
                    dst.copy_from_slice(src);
                }
            }
        }
    }
}

/// `[q; v]` of a state vector (IDA's vector may carry loop multipliers or a dummy state).
fn split_state<'y>(plan: &Plan, y: &'y [f64]) -> (&'y [f64], &'y [f64]) {
    let q = y.get(..plan.nq).unwrap_or(&[]);
    let v = y.get(plan.nq..plan.nq + plan.nv).unwrap_or(&[]);
    (q, v)
}

/// The old structure at the action's time: its plan and kinematics.
struct Now<'a> {
    plan: &'a Plan,
    ws: &'a Workspace,
}

impl Now<'_> {
    /// Object `name`'s placement in world and its index, if it exists.
    fn pose(&self, name: &str) -> Option<(ObjectId, Transform)> {
        let o = self.plan.object_index(name)?;
        Some((o, kinematics::object_in_world(self.plan, self.ws, o)))
    }

    /// Velocity [m/s] and angular velocity [rad/s] of point `p` (world \[m\]) of object `o`,
    /// resolved in world.
    fn velocity(&self, o: ObjectId, p: &Vector3<f64>) -> (Vector3<f64>, Vector3<f64>) {
        let body = self.plan.objects.get(o).and_then(|op| op.body);
        kinematics::point_velocity(self.ws, body, p)
    }
}

/// The description after `action` (see the module docs), or why it cannot be done.
fn edit(
    desc: &SceneDesc,
    freed: &[(String, String)],
    action: &Action,
    now: &Now,
) -> Result<Change, ActionError> {
    let mut desc = desc.clone();
    // The schedule lives in the driver; a later action may name an object deleted by now.
    desc.actions.clear();
    let mut freed = freed.to_vec();
    let index = |desc: &SceneDesc, name: &str| {
        desc.objects
            .iter()
            .position(|o| o.name == name)
            .ok_or_else(|| ActionError::UnknownObject {
                object: name.into(),
                hint: did_you_mean(name, desc.objects.iter().map(|o| o.name.as_str())),
            })
    };
    let world = desc
        .objects
        .iter()
        .find(|o| matches!(o.feature, Feature::Scene(_)))
        .map(|o| o.name.clone())
        .unwrap_or_default();
    let object = action.object();
    let i = index(&desc, object)?;
    let verb = match action.kind {
        ActionKind::Attach { .. } => "attach",
        ActionKind::Release { .. } => "release",
        ActionKind::Delete { .. } => "delete",
    };
    if object == world {
        return Err(ActionError::World {
            action: verb,
            object: object.into(),
        });
    }
    let description = match &action.kind {
        ActionKind::Attach { to, gap, .. } => {
            index(&desc, to)?;
            let free = desc
                .joints
                .iter()
                .position(|j| j.obj2 == object && matches!(j.kind, JointKind::FreeMotion { .. }))
                .ok_or_else(|| ActionError::NotFree {
                    object: object.into(),
                })?;
            let unknown = |name: &str| ActionError::UnknownObject {
                object: name.into(),
                hint: None,
            };
            let (_, x_obj) = now.pose(object).ok_or_else(|| unknown(object))?;
            let (_, x_to) = now.pose(to).ok_or_else(|| unknown(to))?;
            let distance = gap_distance(&desc, object, &x_obj, to, &x_to);
            if distance > *gap {
                return Err(ActionError::OutOfGap {
                    object: object.into(),
                    to: to.clone(),
                    distance,
                    gap: *gap,
                });
            }
            let joint = desc.joints.remove(free);
            freed.retain(|(o, _)| o != object);
            freed.push((object.to_string(), joint.name));
            // The current pose of `object` in `to`'s frame.
            let rot = x_to.rot.transpose() * x_obj.rot;
            let pos = x_to.rot.transpose() * (x_obj.pos - x_to.pos);
            if let Some(o) = desc.objects.get_mut(i) {
                o.parent = Some(to.clone());
                o.translation = pos;
                o.rotation = Rotation::Matrix(rot);
            }
            format!("attach `{object}` to `{to}` (distance {distance:.3e} m, gap {gap:.3e} m)")
        }
        ActionKind::Release { .. } => {
            if desc
                .objects
                .get(i)
                .and_then(|o| o.parent.as_ref())
                .is_none()
            {
                return Err(ActionError::NotAttached {
                    object: object.into(),
                });
            }
            let (o, x) = now.pose(object).ok_or_else(|| ActionError::UnknownObject {
                object: object.into(),
                hint: None,
            })?;
            let (v, w) = now.velocity(o, &x.pos);
            let name = freed
                .iter()
                .find(|(f, _)| f == object)
                .map(|(_, j)| j.clone())
                .unwrap_or_else(|| unique_name(&desc, &format!("{object}_free")));
            freed.retain(|(f, _)| f != object);
            if let Some(obj) = desc.objects.get_mut(i) {
                obj.parent = None;
                obj.translation = Vector3::zeros();
                obj.rotation = Rotation::Identity;
            }
            let rot =
                UnitQuaternion::from_rotation_matrix(&Rotation3::from_matrix_unchecked(x.rot));
            desc.joints.push(Joint::new(
                &name,
                &world,
                object,
                JointKind::FreeMotion {
                    r: x.pos,
                    rot: FreeRotation::Quaternion(rot),
                    v,
                    w: x.rot.transpose() * w,
                },
            ));
            format!("release `{object}` (FreeMotion `{name}`)")
        }
        ActionKind::Delete { .. } => {
            let gone = descendants(&desc, object);
            delete_objects(&mut desc, &gone);
            freed.retain(|(o, _)| !gone.contains(o));
            format!("delete {}", quoted(&gone))
        }
    };
    Ok(Change {
        desc,
        description,
        freed,
    })
}

/// `object` and every object parented to it, transitively.
fn descendants(desc: &SceneDesc, object: &str) -> Vec<String> {
    let mut gone = vec![object.to_string()];
    let mut k = 0;
    while let Some(name) = gone.get(k).cloned() {
        for o in &desc.objects {
            if o.parent.as_deref() == Some(name.as_str()) && !gone.contains(&o.name) {
                gone.push(o.name.clone());
            }
        }
        k += 1;
    }
    gone
}

/// Removes the objects `gone`, their joints, and the force elements and inputs on either.
fn delete_objects(desc: &mut SceneDesc, gone: &[String]) {
    let hit = |n: &str| gone.iter().any(|g| g == n);
    desc.objects.retain(|o| !hit(&o.name));
    let (removed, kept): (Vec<Joint>, Vec<Joint>) = std::mem::take(&mut desc.joints)
        .into_iter()
        .partition(|j| hit(&j.obj1) || hit(&j.obj2));
    desc.joints = kept;
    let joint_gone = |n: &str| removed.iter().any(|j| j.name == n);
    desc.forces.retain(|f| match f {
        ForceElement::SpringDamper { obj1, obj2, .. }
        | ForceElement::SpringDamperPtP { obj1, obj2, .. } => !hit(obj1) && !hit(obj2),
        ForceElement::Bushing(b) => !hit(&b.obj1) && !hit(&b.obj2),
        ForceElement::JointSpringDamper { joint, .. } => !joint_gone(joint),
        ForceElement::ObjectForce { object, .. } => !hit(object),
        ForceElement::WorldForce {
            object,
            resolved_in,
            ..
        }
        | ForceElement::WorldTorque {
            object,
            resolved_in,
            ..
        } => !hit(object) && !resolved_in.as_deref().is_some_and(hit),
    });
    desc.inputs.retain(|i| match &i.kind {
        InputKind::JointForce { joint, .. } | InputKind::JointAcceleration { joint, .. } => {
            !joint_gone(joint)
        }
        InputKind::ObjectWrench { object } => !hit(object),
    });
}

/// `` `a`, `b` `` for the event log.
fn quoted(names: &[String]) -> String {
    names
        .iter()
        .map(|n| format!("`{n}`"))
        .collect::<Vec<_>>()
        .join(", ")
}

/// `base`, or `base_2`, `base_3`… if the name is taken by an object or joint.
fn unique_name(desc: &SceneDesc, base: &str) -> String {
    let taken = |n: &str| {
        desc.objects.iter().any(|o| o.name == n) || desc.joints.iter().any(|j| j.name == n)
    };
    let mut name = base.to_string();
    let mut k = 2;
    while taken(&name) {
        name = format!("{base}_{k}");
        k += 1;
    }
    name
}

/// The gap distance of objects `a` and `b` at placements `xa`, `xb` (see the module docs) \[m\].
fn gap_distance(desc: &SceneDesc, a: &str, xa: &Transform, b: &str, xb: &Transform) -> f64 {
    let shape = |name: &str| {
        desc.objects
            .iter()
            .find(|o| o.name == name)
            .and_then(|o| match &o.feature {
                Feature::Solid(s) => s.shape.clone(),
                _ => None,
            })
    };
    let iso = |x: &Transform| {
        Isometry3::from_parts(
            Translation3::from(x.pos),
            UnitQuaternion::from_rotation_matrix(&Rotation3::from_matrix_unchecked(x.rot)),
        )
    };
    let origins = (xa.pos - xb.pos).norm();
    let (Some(sa), Some(sb)) = (shape(a), shape(b)) else {
        return origins;
    };
    let (Ok(ca), Ok(cb)) = (CollisionShape::new(&sa), CollisionShape::new(&sb)) else {
        return origins;
    };
    signed_distance(&ca, &iso(xa), &cb, &iso(xb), &NarrowPhaseOptions::default())
        .map_or(origins, |d| d.distance)
}

/// The new positions: each joint shared by name with the old plan keeps its coordinates; a
/// new joint its `q0` (a released object's FreeMotion: its current pose).
fn map_positions(old: &Plan, q_old: &[f64], new: &Plan) -> Vec<f64> {
    let mut q = new.q0.clone();
    for j in new.joints.iter() {
        let Some(oj) = old.joint_index(&j.name).and_then(|i| old.joints.get(i)) else {
            continue;
        };
        let n = j.coord.nq();
        let from = q_old.get(oj.q_offset..oj.q_offset + n);
        let to = q.get_mut(j.q_offset..j.q_offset + n);
        if let (Some(from), Some(to), true) = (from, to, oj.coord.nq() == n) {
            to.copy_from_slice(from);
        }
    }
    q
}

/// A solid of the new structure for the projection: mass, world inertia about its centre of
/// mass, its centre of mass \[m\] and old twist there (world).
struct Part {
    mass: f64,
    inertia: Matrix3<f64>,
    com: Vector3<f64>,
    body: Option<crate::dynamics::ids::BodyId>,
    v_old: Vector3<f64>,
    w_old: Vector3<f64>,
}

/// The momentum-conserving velocities of the new structure `new` (at its `q0`) for the old
/// motion `now` (see the module docs).
fn project_velocities(now: &Now, v_old: &[f64], new: &Plan) -> Vec<f64> {
    let nv = new.nv;
    let mut ws = Workspace::new(new);
    let zero = vec![0.0; nv];
    kinematics::position_velocity(new, &mut ws, &new.q0, &zero);
    let mut parts = vec![];
    for (o, op) in new.objects.iter_ids() {
        let Some(solid) = new
            .scene
            .objects
            .get(o.index())
            .and_then(|v| v.solid.as_ref())
        else {
            continue;
        };
        let Some((old_o, _)) = now.pose(&op.name) else {
            continue;
        };
        let x = kinematics::object_in_world(new, &ws, o);
        let com = x.pos + x.rot * solid.mass.com;
        let (v_old, w_old) = now.velocity(old_o, &com);
        parts.push(Part {
            mass: solid.mass.mass,
            inertia: x.rot * solid.mass.inertia * x.rot.transpose(),
            com,
            body: op.body,
            v_old,
            w_old,
        });
    }
    // Each new coordinate's unit velocity → the parts' twists (J_o e_j).
    let mut cols = Vec::with_capacity(nv);
    let mut e = zero.clone();
    for j in 0..nv {
        if let Some(x) = e.get_mut(j) {
            *x = 1.0;
        }
        kinematics::position_velocity(new, &mut ws, &new.q0, &e);
        let twists: Vec<_> = parts
            .iter()
            .map(|p| kinematics::point_velocity(&ws, p.body, &p.com))
            .collect();
        cols.push(twists);
        if let Some(x) = e.get_mut(j) {
            *x = 0.0;
        }
    }
    let energy = |p: &Part, (va, wa): &(Vector3<f64>, Vector3<f64>), vb: &Vector3<f64>, wb| {
        p.mass * va.dot(vb) + wa.dot(&(p.inertia * wb))
    };
    let m = DMatrix::from_fn(nv, nv, |i, j| match (cols.get(i), cols.get(j)) {
        (Some(ci), Some(cj)) => parts
            .iter()
            .zip(ci.iter().zip(cj))
            .map(|(p, (a, b))| energy(p, a, &b.0, &b.1))
            .sum(),
        _ => 0.0,
    });
    let p = DVector::from_fn(nv, |i, _| {
        cols.get(i).map_or(0.0, |ci| {
            parts
                .iter()
                .zip(ci)
                .map(|(p, a)| energy(p, a, &p.v_old, &p.w_old))
                .sum()
        })
    });
    // Prescribed coordinates keep their velocity (by joint name); the others are solved for.
    let mut v = DVector::from_vec(prescribed_velocities(now.plan, v_old, new));
    let free: Vec<usize> = (0..nv)
        .filter(|&k| new.prescribed.get(k).is_some_and(|p| p.is_none()))
        .collect();
    let rhs = &p - &m * &v;
    let m_ff = DMatrix::from_fn(free.len(), free.len(), |a, b| {
        match (free.get(a), free.get(b)) {
            (Some(&i), Some(&j)) => m.get((i, j)).copied().unwrap_or(0.0),
            _ => 0.0,
        }
    });
    let r_f = DVector::from_fn(free.len(), |a, _| {
        free.get(a)
            .and_then(|&i| rhs.get(i))
            .copied()
            .unwrap_or(0.0)
    });
    // M⁺ is positive definite on the free coordinates (checked by `mass_matrix::check_inertia` when
    // the segment's model is finished); if not, that check reports it, so keep v = 0 here.
    if let Some(ch) = m_ff.cholesky() {
        let v_f = ch.solve(&r_f);
        for (a, &i) in free.iter().enumerate() {
            if let (Some(x), Some(&val)) = (v.get_mut(i), v_f.get(a)) {
                *x = val;
            }
        }
    }
    v.as_slice().to_vec()
}

/// The velocities of the new plan's prescribed coordinates, taken from the old joint of the
/// same name (0 for the others and for new joints).
fn prescribed_velocities(old: &Plan, v_old: &[f64], new: &Plan) -> Vec<f64> {
    let mut v = vec![0.0; new.nv];
    for j in new.joints.iter() {
        let Some(oj) = old.joint_index(&j.name).and_then(|i| old.joints.get(i)) else {
            continue;
        };
        for k in 0..j.coord.nv().min(oj.coord.nv()) {
            let prescribed = new
                .prescribed
                .get(j.v_offset + k)
                .is_some_and(|p| p.is_some());
            if let (true, Some(x), Some(&val)) = (
                prescribed,
                v.get_mut(j.v_offset + k),
                v_old.get(oj.v_offset + k),
            ) {
                *x = val;
            }
        }
    }
    v
}
