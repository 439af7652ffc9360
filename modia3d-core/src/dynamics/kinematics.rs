//! Forward kinematics: joint positions and velocities → body placements and spatial velocities
//! (parents first), and the kinematic part of the residual `q̇ − q̇(q, v)`.

use super::spatial::Transform;
use super::{BodyId, ObjectId, Plan, Workspace};
use nalgebra::Vector3;

/// Computes `ws.x`, `ws.world`, `ws.vj`, `ws.vel` (and `ws.cj` of joints whose motion
/// subspace depends on `q`) from `q`, `v`; each joint's kind gives its transform and motion.
pub fn position_velocity(plan: &Plan, ws: &mut Workspace, q: &[f64], v: &[f64]) {
    for (i, b) in plan.bodies.iter().enumerate() {
        let j = &plan.joints[b.joint];
        let qj = &q[j.q_offset..j.q_offset + j.coord.nq()];
        let vj_ = &v[j.v_offset..j.v_offset + j.coord.nv()];
        let xj = j.coord.transform(qj);
        let vj = j.coord.motion(qj, vj_);
        if j.coord.has_bias() {
            ws.cj[i] = j.coord.bias(qj, vj_);
        }
        let x = j.tree.then(&xj);
        ws.x[i] = x;
        ws.vj[i] = vj;
        match b.parent {
            Some(p) => {
                ws.world[i] = ws.world[p].then(&x);
                ws.vel[i] = x.motion_to_child(&ws.vel[p]) + vj;
            }
            None => {
                ws.world[i] = x;
                ws.vel[i] = vj;
            }
        }
    }
}

/// Kinematic residual `q̇ − q̇(q, v)` into `res` (len nq), joint by joint.
pub fn position_residual(plan: &Plan, q: &[f64], v: &[f64], qd: &[f64], res: &mut [f64]) {
    for j in &plan.joints {
        let (qr, vr) = (
            j.q_offset..j.q_offset + j.coord.nq(),
            j.v_offset..j.v_offset + j.coord.nv(),
        );
        j.coord
            .position_residual(&q[qr.clone()], &v[vr], &qd[qr.clone()], &mut res[qr]);
    }
}

/// `q̇(q, v)` into `qd` (len nq): the derivative of the positions implied by the velocities.
/// Allocates; for initial values and restarts only.
pub fn position_derivative(plan: &Plan, q: &[f64], v: &[f64], qd: &mut [f64]) {
    position_residual(plan, q, v, &vec![0.0; plan.nq], qd);
    qd.iter_mut().for_each(|x| *x = -*x);
}

/// Placement of object `o` in world at the current workspace state.
#[inline]
pub fn object_in_world(plan: &Plan, ws: &Workspace, o: ObjectId) -> Transform {
    let op = &plan.objects[o];
    match op.body {
        Some(b) => ws.world[b].then(&op.in_body),
        None => op.in_body,
    }
}

/// Velocity [m/s] and angular velocity [rad/s], both resolved in world, of the material point
/// `p` (given in world [m]) of body `b` (`None` = world: at rest).
#[inline]
pub fn point_velocity(
    ws: &Workspace,
    b: Option<BodyId>,
    p: &Vector3<f64>,
) -> (Vector3<f64>, Vector3<f64>) {
    match b {
        None => (Vector3::zeros(), Vector3::zeros()),
        Some(b) => {
            let r = &ws.world[b].rot;
            let w = r * ws.vel[b].w;
            let v0 = r * ws.vel[b].v;
            (v0 + w.cross(&(p - ws.world[b].pos)), w)
        }
    }
}
