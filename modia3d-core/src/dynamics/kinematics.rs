//! Forward kinematics: joint positions and velocities → body placements and spatial velocities
//! (parents first), and the kinematic part of the residual `q̇ − q̇(q, v)`.

use super::spatial::{axis_angle, quat_rate, quat_to_matrix, Motion, Transform};
use super::{JointCoord, Plan, Workspace};
use nalgebra::Vector3;

/// Rate [1/s] at which the free-motion quaternion is pulled back to unit norm; the exact
/// kinematics preserve the norm, so this only damps the integration error.
const QUATERNION_NORM_RATE: f64 = 1.0;

/// Computes `ws.x`, `ws.world`, `ws.vj`, `ws.vel` from `q`, `v`.
pub fn position_velocity(plan: &Plan, ws: &mut Workspace, q: &[f64], v: &[f64]) {
    for (i, b) in plan.bodies.iter().enumerate() {
        let j = &plan.joints[b.joint];
        let (qo, vo) = (j.q_offset, j.v_offset);
        let (xj, vj) = match j.coord {
            JointCoord::Revolute { axis } => (
                Transform {
                    rot: axis_angle(&axis, q[qo]),
                    pos: Vector3::zeros(),
                },
                Motion {
                    w: axis * v[vo],
                    v: Vector3::zeros(),
                },
            ),
            JointCoord::Prismatic { axis } => (
                Transform {
                    rot: nalgebra::Matrix3::identity(),
                    pos: axis * q[qo],
                },
                Motion {
                    w: Vector3::zeros(),
                    v: axis * v[vo],
                },
            ),
            JointCoord::Free => (
                Transform {
                    rot: quat_to_matrix(&q[qo + 3..qo + 7]),
                    pos: Vector3::new(q[qo], q[qo + 1], q[qo + 2]),
                },
                Motion {
                    w: Vector3::new(v[vo], v[vo + 1], v[vo + 2]),
                    v: Vector3::new(v[vo + 3], v[vo + 4], v[vo + 5]),
                },
            ),
        };
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

/// Kinematic residual `q̇ − q̇(q, v)` into `res` (len nq).
pub fn position_residual(plan: &Plan, q: &[f64], v: &[f64], qd: &[f64], res: &mut [f64]) {
    for j in &plan.joints {
        let (qo, vo) = (j.q_offset, j.v_offset);
        match j.coord {
            JointCoord::Revolute { .. } | JointCoord::Prismatic { .. } => {
                res[qo] = qd[qo] - v[vo];
            }
            JointCoord::Free => {
                let quat = &q[qo + 3..qo + 7];
                let rot = quat_to_matrix(quat);
                let w = Vector3::new(v[vo], v[vo + 1], v[vo + 2]);
                let lin = Vector3::new(v[vo + 3], v[vo + 4], v[vo + 5]);
                let rd = rot * lin;
                for k in 0..3 {
                    res[qo + k] = qd[qo + k] - rd[k];
                }
                let qr = quat_rate(quat, &w);
                let n2 = quat.iter().map(|x| x * x).sum::<f64>();
                let pull = QUATERNION_NORM_RATE * (n2 - 1.0);
                for k in 0..4 {
                    res[qo + 3 + k] = qd[qo + 3 + k] - (qr[k] - pull * quat[k]);
                }
            }
        }
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
pub fn object_in_world(plan: &Plan, ws: &Workspace, o: usize) -> Transform {
    let op = &plan.objects[o];
    match op.body {
        Some(b) => ws.world[b].then(&op.in_body),
        None => op.in_body,
    }
}

/// Velocity [m/s] and angular velocity [rad/s], both resolved in world, of the material point
/// `p` (given in world \[m\]) of body `b` (`None` = world: at rest).
#[inline]
pub fn point_velocity(
    ws: &Workspace,
    b: Option<usize>,
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
