//! Recursive Newton–Euler inverse dynamics (Featherstone, "Rigid Body Dynamics Algorithms",
//! Table 5.1): given positions and velocities (already in the workspace from
//! `kinematics::position_velocity`) and accelerations `v̇`, the generalised forces
//! `τ = M(q) v̇ + C(q, v) − τ_ext` that the joints must transmit. O(n), no allocation.

use super::spatial::Motion;
use super::{JointCoord, Plan, Workspace};
use nalgebra::Vector3;

/// Fills `tau` (len nv) with the joint forces for accelerations `vd`; `gravity` resolved in
/// world [m/s²]. External body forces are taken from `ws.f_ext`.
pub fn inverse_dynamics(
    plan: &Plan,
    ws: &mut Workspace,
    vd: &[f64],
    gravity: &Vector3<f64>,
    tau: &mut [f64],
) {
    // The world accelerates upwards at −g: gravity enters every body through this.
    let a_world = Motion {
        w: Vector3::zeros(),
        v: -gravity,
    };
    for (i, b) in plan.bodies.iter().enumerate() {
        let j = &plan.joints[b.joint];
        let vo = j.v_offset;
        let s_qdd = match j.coord {
            JointCoord::Revolute { axis } => Motion {
                w: axis * vd[vo],
                v: Vector3::zeros(),
            },
            JointCoord::Prismatic { axis } => Motion {
                w: Vector3::zeros(),
                v: axis * vd[vo],
            },
            JointCoord::Free => Motion {
                w: Vector3::new(vd[vo], vd[vo + 1], vd[vo + 2]),
                v: Vector3::new(vd[vo + 3], vd[vo + 4], vd[vo + 5]),
            },
        };
        let a_parent = match b.parent {
            Some(p) => ws.acc[p],
            None => a_world,
        };
        let vel = ws.vel[i];
        let a = ws.x[i].motion_to_child(&a_parent) + s_qdd + vel.cross_motion(&ws.vj[i]);
        ws.acc[i] = a;
        let inertia = &b.inertia;
        ws.f[i] = inertia.mul_motion(&a) + inertia.bias_force(&vel) - ws.f_ext[i];
    }
    for (i, b) in plan.bodies.iter().enumerate().rev() {
        let j = &plan.joints[b.joint];
        let vo = j.v_offset;
        let f = ws.f[i];
        match j.coord {
            JointCoord::Revolute { axis } => tau[vo] = axis.dot(&f.n),
            JointCoord::Prismatic { axis } => tau[vo] = axis.dot(&f.f),
            JointCoord::Free => {
                for k in 0..3 {
                    tau[vo + k] = f.n[k];
                    tau[vo + 3 + k] = f.f[k];
                }
            }
        }
        if let Some(p) = b.parent {
            let fp = ws.x[i].force_to_parent(&f);
            ws.f[p] = ws.f[p] + fp;
        }
    }
}
