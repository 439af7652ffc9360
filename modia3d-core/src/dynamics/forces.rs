//! Applied forces: force elements and user force laws → external body forces (`ws.f_ext`,
//! about body origins, resolved in body frames) and generalised joint forces (`ws.tau_applied`).
//! Needs `kinematics::position_velocity` first. No allocation.

use super::kinematics::{object_in_world, point_velocity};
use super::spatial::Force;
use super::{BodyId, InputTarget, ObjectId, Plan, Workspace};
use crate::scene::ValidForce;
use crate::scene::{ObjectMotion, Wrench};
use nalgebra::Vector3;
use std::panic::{catch_unwind, AssertUnwindSafe};

/// A user force law that failed: a panic caught at its call, or a non-finite wrench. Its
/// contribution is left out of that evaluation; the driver ends the run with it.
#[derive(Clone, Debug, PartialEq)]
pub struct UserFault {
    /// The object the law acts on.
    pub object: String,
    /// Index of the force element (in the scene's order of force elements).
    pub element: usize,
    /// Time [s] of the call.
    pub t: f64,
    /// What went wrong.
    pub kind: FaultKind,
}

/// How a user force law failed.
#[derive(Clone, Debug, PartialEq)]
pub enum FaultKind {
    /// It panicked, with this payload as text.
    Panic(String),
    /// It returned a NaN or infinite component: force [N] and torque [N·m], in world.
    NonFinite {
        /// The force returned [N].
        force: [f64; 3],
        /// The torque returned [N·m].
        torque: [f64; 3],
    },
}

impl UserFault {
    /// The element in words: `ObjectForce on `ball` (force element 2)`.
    pub fn element_name(&self) -> String {
        format!(
            "ObjectForce on `{}` (force element {})",
            self.object, self.element
        )
    }
}

/// The text of a panic payload (`&str` or `String`; otherwise a placeholder).
pub fn panic_text(payload: &(dyn std::any::Any + Send)) -> String {
    payload
        .downcast_ref::<&str>()
        .map(|s| s.to_string())
        .or_else(|| payload.downcast_ref::<String>().cloned())
        .unwrap_or_else(|| "(a panic without a text payload)".into())
}

/// Adds a force `force` [N] acting at the world point `point` [m] and a pure torque `torque`
/// [N·m], all resolved in world, to body `b` (nothing for the world).
#[inline]
pub fn add_world_wrench(
    ws: &mut Workspace,
    b: Option<BodyId>,
    point: &Vector3<f64>,
    force: &Vector3<f64>,
    torque: &Vector3<f64>,
) {
    if let Some(b) = b {
        let x = &ws.world[b];
        let n_world = torque + (point - x.pos).cross(force);
        let f = Force {
            n: x.rot.tr_mul(&n_world),
            f: x.rot.tr_mul(force),
        };
        ws.f_ext[b] = ws.f_ext[b] + f;
    }
}

/// The motion of object `o` at the current workspace state.
pub fn object_motion(plan: &Plan, ws: &Workspace, o: usize) -> ObjectMotion {
    let x = object_in_world(plan, ws, ObjectId(o));
    let (v, w) = point_velocity(ws, plan.objects[o].body, &x.pos);
    ObjectMotion {
        r_abs: x.pos,
        rot_abs: x.rot,
        v_abs: v,
        w_abs: w,
    }
}

/// Clears and fills `ws.f_ext` and `ws.tau_applied` at time `t` [s].
pub fn applied_forces(plan: &Plan, ws: &mut Workspace, t: f64, q: &[f64], v: &[f64]) {
    ws.f_ext.fill(Force::default());
    ws.tau_applied.fill(0.0);
    for (e, f) in plan.scene.forces.iter().enumerate() {
        match f {
            ValidForce::SpringDamper {
                obj1,
                obj2,
                stiffness,
                damping,
                length0,
            } => {
                let m1 = object_motion(plan, ws, *obj1);
                let m2 = object_motion(plan, ws, *obj2);
                let d = m2.r_abs - m1.r_abs;
                let len = d.norm();
                if len == 0.0 {
                    continue; // direction undefined; no force (a rod of zero length)
                }
                let e = d / len;
                let len_dot = e.dot(&(m2.v_abs - m1.v_abs));
                let tension = stiffness * (len - length0) + damping * len_dot;
                let f2 = -e * tension; // on obj2, towards obj1 when stretched
                let zero = Vector3::zeros();
                add_world_wrench(ws, plan.objects[*obj2].body, &m2.r_abs, &f2, &zero);
                add_world_wrench(ws, plan.objects[*obj1].body, &m1.r_abs, &-f2, &zero);
            }
            ValidForce::JointSpringDamper {
                joint,
                coordinate,
                stiffness,
                damping,
                offset,
            } => {
                // Validation admits only joints with scalar coordinates, which are in the tree.
                let Some(tj) = plan.tree_joint_of[*joint] else {
                    continue;
                };
                let j = &plan.joints[tj];
                let c = &j.coord.coordinates()[*coordinate];
                let (qi, vi) = (j.q_offset + c.q, j.v_offset + c.v);
                ws.tau_applied[vi] += -stiffness * (q[qi] - offset) - damping * v[vi];
            }
            ValidForce::ObjectForce { object, law } => {
                let m = object_motion(plan, ws, *object);
                // User code: a panic is caught here, at the call, whichever stage called
                // (residual, consistent derivatives, restarts), and never unwinds further.
                let outcome = catch_unwind(AssertUnwindSafe(|| (law.0)(t, &m)));
                let fault = match outcome {
                    Ok(Wrench { force, torque })
                        if force.iter().chain(torque.iter()).all(|x| x.is_finite()) =>
                    {
                        let body = plan.objects[*object].body;
                        add_world_wrench(ws, body, &m.r_abs, &force, &torque);
                        continue;
                    }
                    Ok(w) => FaultKind::NonFinite {
                        force: [w.force.x, w.force.y, w.force.z],
                        torque: [w.torque.x, w.torque.y, w.torque.z],
                    },
                    Err(payload) => FaultKind::Panic(panic_text(payload.as_ref())),
                };
                ws.fault.get_or_insert(UserFault {
                    object: plan.objects[*object].name.clone(),
                    element: e,
                    t,
                    kind: fault,
                });
            }
        }
    }
    for inp in &plan.inputs {
        let u = &ws.inputs[inp.offset..inp.offset + inp.len];
        match inp.target {
            InputTarget::JointForce { joint, coordinate } => {
                let j = &plan.joints[joint];
                let (k, f) = (j.v_offset + j.coord.coordinates()[coordinate].v, u[0]);
                ws.tau_applied[k] += f;
            }
            // Enforced in the residual (the acceleration row is replaced).
            InputTarget::JointAcceleration { .. } => {}
            InputTarget::ObjectWrench { object } => {
                let force = Vector3::new(u[0], u[1], u[2]);
                let torque = Vector3::new(u[3], u[4], u[5]);
                let at = object_in_world(plan, ws, object).pos;
                add_world_wrench(ws, plan.objects[object].body, &at, &force, &torque);
            }
        }
    }
}
