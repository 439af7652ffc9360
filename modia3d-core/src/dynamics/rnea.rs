//! Recursive Newton–Euler inverse dynamics (Featherstone, "Rigid Body Dynamics Algorithms",
//! Table 5.1): given positions and velocities (already in the workspace from
//! `kinematics::position_velocity`) and accelerations `v̇`, the generalised forces
//! `τ = M(q) v̇ + C(q, v) − τ_ext` that the joints must transmit. O(n), no allocation.

use super::{Plan, Workspace};
use crate::spatial::{Force, Motion};
use nalgebra::Vector3;

/// Fills `tau` (len nv) with the joint forces for accelerations `vd` at positions `q` (the
/// ones `kinematics::position_velocity` was called with); `gravity` resolved in world [m/s²].
/// External body forces are taken from `ws.f_ext`.
pub(crate) fn inverse_dynamics(
    plan: &Plan,
    ws: &mut Workspace,
    q: &[f64],
    vd: &[f64],
    gravity: &Vector3<f64>,
    tau: &mut [f64],
) {
    newton_euler(plan, ws, q, vd, gravity, tau, false, None);
}

/// The dynamic rows of the DAE residual: [`inverse_dynamics`] minus `τ_applied`, except that
/// each body passes on to its parent its force `f` less `S R`, with `R = Sᵀ f − τ_applied`
/// its joint's own residual rows (zero at the solution; a prescribed coordinate's row, `v̇ − a`,
/// is not one of them and passes its force on whole). This subtracts `X_childᵀ S R` from the
/// parent's rows: a row operation on `F`, the same DAE (the same solution, `y` and its error
/// test unchanged), with `W = S` (any matrix would keep the solution). Why: in generalised
/// coordinates a light body carrying a heavy one has the heavy body's terms in its own rows
/// even where the joint between them lets the heavy body stay put (a free joint transmits
/// nothing; a revolute joint on the light body's axis transmits no moment about it); their
/// rounding, ~1e-16 of them, exceeded the light body's own terms (a 1 µg link under an 80 kg
/// load by a free joint: `M_ii·(M⁻¹)_ii` ~1e11), and Newton's method failed at every other
/// step. With `S` orthonormal (every kind but a universal joint with skew axes) `f − S R` is
/// the force the joint transmits (plus `S τ_applied`): what the parent feels. The residual is
/// still `τ − τ_applied` (`τ` into `tau` here, `τ_applied` subtracted by the caller), and the
/// mass matrix (`mass_matrix.rs`), which must stay symmetric, uses [`inverse_dynamics`].
///
/// With `live`, only the bodies flagged there (whole joint trees: a flagged body's parent
/// must be flagged too): their rows of `tau` get the same bits as without, the other rows are
/// left as they were. For the quotient residuals of the Jacobian, whose perturbation changes
/// the rows of a few trees only.
pub(crate) fn residual_dynamics(
    plan: &Plan,
    ws: &mut Workspace,
    (q, vd): (&[f64], &[f64]),
    gravity: &Vector3<f64>,
    tau: &mut [f64],
    live: Option<&[bool]>,
) {
    newton_euler(plan, ws, q, vd, gravity, tau, true, live);
}

/// The change `d_res` (len nv) of [`residual_dynamics`]' rows, after the caller subtracts
/// `τ_applied` and replaces prescribed rows, when `τ_applied` changes by `dtau` (len nv) at
/// the positions placed in `ws`: `−dτ` in each coordinate's own row, and the decoupling's row
/// operation passes each joint's row change on to its ancestors' rows, as the residual does.
/// Linear in `dtau` (the bodies' own forces do not depend on it); for the Jacobian columns
/// of the components' states, whose flange forces enter `τ_applied`. `g` (len bodies) is
/// scratch. Allocation-free.
pub(crate) fn residual_rows_of_applied(
    plan: &Plan,
    ws: &Workspace,
    q: &[f64],
    dtau: &[f64],
    g: &mut [Force],
    d_res: &mut [f64],
) {
    g.fill(Force::default());
    for (i, b) in plan.bodies.iter().enumerate().rev() {
        let j = &plan.joints[b.joint];
        let qj = &q[j.q_offset..j.q_offset + j.coord.nq()];
        let (v0, nvj) = (j.v_offset, j.coord.nv());
        let d = &mut d_res[v0..v0 + nvj];
        j.coord.project_at(&ws.xj[i], qj, &g[i], d);
        let mut r = [0.0; 6];
        for (k, (dk, rk)) in d.iter_mut().zip(r.iter_mut()).enumerate() {
            if plan.prescribed[v0 + k].is_none() {
                *dk -= dtau[v0 + k];
                *rk = *dk;
            } else {
                // The row is `v̇ − a`; its force passes on whole.
                *dk = 0.0;
            }
        }
        if let Some(p) = b.parent {
            let s_r = j.coord.motion_at(&ws.xj[i], qj, &r[..nvj]);
            let pass = Force {
                n: g[i].n - s_r.w,
                f: g[i].f - s_r.v,
            };
            let fp = ws.x[i].force_to_parent(&pass);
            g[p.index()] = g[p.index()] + fp;
        }
    }
}

/// [`inverse_dynamics`]; with `decouple`, each joint's residual rows are taken out of the
/// force it passes to its parent ([`residual_dynamics`]); with `live`, only the flagged bodies
/// ([`residual_dynamics`]).
#[inline]
#[allow(clippy::too_many_arguments)] // the three entry points' options in one loop
fn newton_euler(
    plan: &Plan,
    ws: &mut Workspace,
    q: &[f64],
    vd: &[f64],
    gravity: &Vector3<f64>,
    tau: &mut [f64],
    decouple: bool,
    live: Option<&[bool]>,
) {
    let skip = |i: usize| live.is_some_and(|l| !l[i]);
    // The world accelerates upwards at −g: gravity enters every body through this.
    let a_world = Motion {
        w: Vector3::zeros(),
        v: -gravity,
    };
    for (i, b) in plan.bodies.iter().enumerate() {
        if skip(i) {
            continue;
        }
        let j = &plan.joints[b.joint];
        let qj = &q[j.q_offset..j.q_offset + j.coord.nq()];
        // The joint transform of the kinematics at the same `q` (every caller places the
        // bodies first): a free joint in obj1 turns `v̇` with its rotation.
        let xj = &ws.xj[i];
        let s_qdd = j
            .coord
            .motion_at(xj, qj, &vd[j.v_offset..j.v_offset + j.coord.nv()]);
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
        if skip(i) {
            continue;
        }
        let j = &plan.joints[b.joint];
        let f = ws.f[i];
        let qj = &q[j.q_offset..j.q_offset + j.coord.nq()];
        let (v0, nvj) = (j.v_offset, j.coord.nv());
        let tau_j = &mut tau[v0..v0 + nvj];
        j.coord.project_at(&ws.xj[i], qj, &f, tau_j);
        // Inertias geared to the coordinates by components' flanges (a drive's N²·J_motor).
        if !plan.armature.is_empty() {
            for (k, t) in tau_j.iter_mut().enumerate() {
                *t += plan.armature[v0 + k] * vd[v0 + k];
            }
        }
        if let Some(p) = b.parent {
            let mut pass = f;
            if decouple {
                // The joint's residual rows R = Sᵀ f − τ_applied (a prescribed coordinate's
                // row is v̇ − a, not this: it passes its force on whole), subtracted as S R.
                let mut r = [0.0; 6];
                for (k, rk) in r.iter_mut().enumerate().take(nvj) {
                    if plan.prescribed[v0 + k].is_none() {
                        *rk = tau_j[k] - ws.tau_applied[v0 + k];
                    }
                }
                let s_r = j.coord.motion_at(&ws.xj[i], qj, &r[..nvj]);
                pass = Force {
                    n: f.n - s_r.w,
                    f: f.f - s_r.v,
                };
            }
            let fp = ws.x[i].force_to_parent(&pass);
            ws.f[p] = ws.f[p] + fp;
        }
    }
}
