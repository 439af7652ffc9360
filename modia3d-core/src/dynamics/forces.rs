//! Applied forces: force elements and user force laws → external body forces (`ws.f_ext`,
//! about body origins, resolved in body frames) and generalised joint forces (`ws.tau_applied`).
//! Needs `kinematics::position_velocity` first. No allocation.

use super::kinematics::{object_in_world, point_velocity};
use super::spatial::Force;
use super::{ForcePlan, InputTarget, Plan, Workspace};
use crate::scene::{ObjectMotion, Wrench};
use nalgebra::Vector3;

/// Adds a force `force` [N] acting at the world point `point` [m] and a pure torque `torque`
/// [N·m], all resolved in world, to body `b` (nothing for the world).
#[inline]
pub fn add_world_wrench(
    ws: &mut Workspace,
    b: Option<usize>,
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
    let x = object_in_world(plan, ws, o);
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
    for f in &plan.forces {
        match f {
            ForcePlan::SpringDamper {
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
            ForcePlan::JointSpringDamper {
                joint,
                stiffness,
                damping,
                offset,
            } => {
                let j = &plan.joints[*joint];
                ws.tau_applied[j.v_offset] +=
                    -stiffness * (q[j.q_offset] - offset) - damping * v[j.v_offset];
            }
            ForcePlan::ObjectForce { object, law } => {
                let m = object_motion(plan, ws, *object);
                let Wrench { force, torque } = (law.0)(t, &m);
                add_world_wrench(ws, plan.objects[*object].body, &m.r_abs, &force, &torque);
            }
        }
    }
    for inp in &plan.inputs {
        let u = &ws.inputs[inp.offset..inp.offset + inp.len];
        match inp.target {
            InputTarget::JointForce { joint } => {
                let (k, f) = (plan.joints[joint].v_offset, u[0]);
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
