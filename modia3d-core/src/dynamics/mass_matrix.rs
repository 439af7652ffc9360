//! Mass matrix and consistent accelerations, for initial values and event restarts (not on the
//! residual's hot path): `M(q)` column by column with inverse dynamics, and `M v̇ = τ − C`.

use super::forces::applied_forces;
use super::kinematics::position_velocity;
use super::spatial::Force;
use super::{Plan, Workspace};
use nalgebra::{DMatrix, DVector, Vector3};

/// The joint-space mass matrix `M(q)` (nv × nv).
pub fn mass_matrix(plan: &Plan, ws: &mut Workspace, q: &[f64]) -> DMatrix<f64> {
    let nv = plan.nv;
    let zero_v = vec![0.0; nv];
    position_velocity(plan, ws, q, &zero_v);
    ws.f_ext.fill(Force::default());
    let mut m = DMatrix::zeros(nv, nv);
    let mut e = vec![0.0; nv];
    let mut col = vec![0.0; nv];
    for k in 0..nv {
        e[k] = 1.0;
        super::rnea::inverse_dynamics(plan, ws, &e, &Vector3::zeros(), &mut col);
        e[k] = 0.0;
        m.column_mut(k).copy_from_slice(&col);
    }
    // Symmetrise the round-off.
    let mt = m.transpose();
    (m + mt) * 0.5
}

/// Cholesky factorisation `M = L Lᵀ` in place (lower triangle); `Err(k)` names the first
/// pivot that is not clearly positive (relative to the largest diagonal entry).
pub fn cholesky_in_place(m: &mut DMatrix<f64>) -> Result<(), usize> {
    let n = m.nrows();
    let scale = (0..n).map(|i| m[(i, i)].abs()).fold(0.0, f64::max);
    for k in 0..n {
        let mut d = m[(k, k)];
        for p in 0..k {
            d -= m[(k, p)] * m[(k, p)];
        }
        if d.is_nan() || d <= 1e-12 * scale {
            return Err(k);
        }
        let d = d.sqrt();
        m[(k, k)] = d;
        for i in k + 1..n {
            let mut s = m[(i, k)];
            for p in 0..k {
                s -= m[(i, p)] * m[(k, p)];
            }
            m[(i, k)] = s / d;
        }
    }
    Ok(())
}

/// Accelerations `v̇` consistent with `q`, `v` at time `t` [s]: solves `M v̇ = τ_applied − C`,
/// where `C` holds gravity, velocity terms and external forces. `None` if `M` is singular.
pub fn consistent_accelerations(
    plan: &Plan,
    ws: &mut Workspace,
    t: f64,
    q: &[f64],
    v: &[f64],
) -> Option<Vec<f64>> {
    consistent_accelerations_with(plan, ws, t, q, v, &mut |_, _| {})
}

/// As [`consistent_accelerations`], with `extra` adding further external forces (contact
/// forces) to `ws.f_ext` after the applied forces (the workspace then holds positions and
/// velocities at `q`, `v`).
pub fn consistent_accelerations_with(
    plan: &Plan,
    ws: &mut Workspace,
    t: f64,
    q: &[f64],
    v: &[f64],
    extra: &mut dyn FnMut(&Plan, &mut Workspace),
) -> Option<Vec<f64>> {
    let nv = plan.nv;
    let m = mass_matrix(plan, ws, q);
    position_velocity(plan, ws, q, v);
    applied_forces(plan, ws, t, q, v);
    extra(plan, ws);
    let mut bias = vec![0.0; nv];
    super::rnea::inverse_dynamics(plan, ws, &vec![0.0; nv], &plan.gravity, &mut bias);
    // Prescribed accelerations are known; solve M_FF v̇_F = τ_F − C_F − M_FP a_P for the rest.
    let mut vd = vec![0.0; nv];
    for (k, p) in plan.prescribed.iter().enumerate() {
        if let Some(i) = p {
            vd[k] = ws.inputs[*i];
        }
    }
    let free: Vec<usize> = (0..nv).filter(|&k| plan.prescribed[k].is_none()).collect();
    let rhs = DVector::from_iterator(
        free.len(),
        free.iter().map(|&k| {
            let coupling: f64 = (0..nv).map(|p| m[(k, p)] * vd[p]).sum();
            ws.tau_applied[k] - bias[k] - coupling
        }),
    );
    let mut mf = m.select_rows(&free).select_columns(&free);
    cholesky_in_place(&mut mf).ok()?;
    let n = free.len();
    // Forward and back substitution with the lower factor.
    let mut y = rhs;
    for i in 0..n {
        for p in 0..i {
            y[i] -= mf[(i, p)] * y[p];
        }
        y[i] /= mf[(i, i)];
    }
    for i in (0..n).rev() {
        for p in i + 1..n {
            y[i] -= mf[(p, i)] * y[p];
        }
        y[i] /= mf[(i, i)];
    }
    for (i, &k) in free.iter().enumerate() {
        vd[k] = y[i];
    }
    Some(vd)
}
