//! Recursive Newton–Euler inverse dynamics (Featherstone, "Rigid Body Dynamics Algorithms",
//! Table 5.1): given positions and velocities (already in the workspace from
//! `kinematics::position_velocity`) and accelerations `v̇`, the generalised forces
//! `τ = M(q) v̇ + C(q, v) − τ_ext` that the joints must transmit. O(n), no allocation.

use super::spatial::Motion;
use super::{Plan, Workspace};
use nalgebra::Vector3;

/// Fills `tau` (len nv) with the joint forces for accelerations `vd` at positions `q` (the
/// ones `kinematics::position_velocity` was called with); `gravity` resolved in world [m/s²].
/// External body forces are taken from `ws.f_ext`.
pub fn inverse_dynamics(
    plan: &Plan,
    ws: &mut Workspace,
    q: &[f64],
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
        let qj = &q[j.q_offset..j.q_offset + j.coord.nq()];
        let s_qdd = j
            .coord
            .motion(qj, &vd[j.v_offset..j.v_offset + j.coord.nv()]);
        let a_parent = match b.parent {
            Some(p) => ws.acc[p],
            None => a_world,
        };
        let vel = ws.vel[i];
        let mut a = ws.x[i].motion_to_child(&a_parent) + s_qdd + vel.cross_motion(&ws.vj[i]);
        if j.coord.has_bias() {
            a = a + ws.cj[i];
        }
        ws.acc[i] = a;
        let inertia = &b.inertia;
        ws.f[i] = inertia.mul_motion(&a) + inertia.bias_force(&vel) - ws.f_ext[i];
    }
    for (i, b) in plan.bodies.iter().enumerate().rev() {
        let j = &plan.joints[b.joint];
        let f = ws.f[i];
        let qj = &q[j.q_offset..j.q_offset + j.coord.nq()];
        j.coord
            .project(qj, &f, &mut tau[j.v_offset..j.v_offset + j.coord.nv()]);
        if let Some(p) = b.parent {
            let fp = ws.x[i].force_to_parent(&f);
            ws.f[p] = ws.f[p] + fp;
        }
    }
}
