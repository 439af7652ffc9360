//! Mass matrix and consistent accelerations, for initial values and event restarts (not on the
//! residual's hot path): `M(q)` column by column with inverse dynamics, and `M v̇ = τ − C`.
//! `M` is block diagonal over the independent joint trees ([`Plan::velocity_groups`]), so it
//! is formed and factored tree by tree: a scene of many free bodies costs O(bodies) per restart
//! in the factorisation instead of O(bodies³).

use super::forces::applied_forces;
use super::kinematics::position_velocity;
use super::{Plan, Workspace};
use crate::scene::{SceneError, SceneErrors};
use crate::spatial::Force;
use nalgebra::{DMatrix, Vector3};

/// The diagonal blocks of `M(q)`, one per joint tree: the tree's velocity indices (ascending)
/// and its symmetric block. Inverse dynamics with no velocity, gravity or external force is
/// `τ = M v̇`, and `M` is block diagonal over the trees, so one call with a unit acceleration in
/// the `c`-th coordinate of every tree at once yields column `c` of every block: the cost is
/// (largest tree's coordinates) inverse-dynamics calls, not `nv`.
pub(crate) fn tree_mass_matrices(
    plan: &Plan,
    ws: &mut Workspace,
    q: &[f64],
) -> Vec<(Vec<usize>, DMatrix<f64>)> {
    let nv = plan.nv;
    let zero_v = vec![0.0; nv];
    position_velocity(plan, ws, q, &zero_v);
    ws.f_ext.fill(Force::default());
    let groups = plan.velocity_groups();
    let width = groups.iter().map(Vec::len).max().unwrap_or(0);
    let mut blocks: Vec<DMatrix<f64>> = groups
        .iter()
        .map(|g| DMatrix::zeros(g.len(), g.len()))
        .collect();
    let mut e = vec![0.0; nv];
    let mut col = vec![0.0; nv];
    for c in 0..width {
        e.fill(0.0);
        for g in groups.iter().filter(|g| c < g.len()) {
            e[g[c]] = 1.0;
        }
        super::rnea::inverse_dynamics(plan, ws, q, &e, &Vector3::zeros(), &mut col);
        for (g, m) in groups.iter().zip(&mut blocks).filter(|(g, _)| c < g.len()) {
            for (r, &i) in g.iter().enumerate() {
                m[(r, c)] = col[i];
            }
        }
    }
    groups
        .into_iter()
        .zip(blocks)
        .map(|(g, m)| {
            // Symmetrise the round-off.
            let mt = m.transpose();
            (g, (m + mt) * 0.5)
        })
        .collect()
}

/// Relative size below which a Cholesky pivot counts as zero (see [`cholesky_in_place`]).
const PIVOT_TOLERANCE: f64 = 1e-12;

/// Cholesky factorisation `M = L Lᵀ` in place (lower triangle); `Err(k)` names the first
/// pivot that is not clearly positive.
///
/// The pivot of coordinate `k` is the part of its inertia `M_kk` that the earlier coordinates
/// do not already carry; it is compared with `M_kk` itself, not with the largest entry of the
/// matrix, so the test is relative to each coordinate's own scale (a 2 mm ball on a joint of a
/// 0.2 m steel block, or the rotations of a free 3 µm sphere, whose entries are 1e-13 of the
/// others, are not singular; a massless body, a point mass on a rotation through it or a
/// coordinate that only duplicates others is).
pub(crate) fn cholesky_in_place(m: &mut DMatrix<f64>) -> Result<(), usize> {
    let n = m.nrows();
    for k in 0..n {
        let own = m[(k, k)];
        let mut d = own;
        for p in 0..k {
            d -= m[(k, p)] * m[(k, p)];
        }
        if d.is_nan() || d <= PIVOT_TOLERANCE * own {
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

/// The block `m` of tree `group` (see [`tree_mass_matrices`]) restricted to the coordinates
/// that are not prescribed: their positions in `group`, and its Cholesky factor, or the global
/// velocity index of the first pivot that is not clearly positive.
pub(crate) fn free_cholesky(
    plan: &Plan,
    group: &[usize],
    m: &DMatrix<f64>,
) -> (Vec<usize>, Result<DMatrix<f64>, usize>) {
    let free: Vec<usize> = (0..group.len())
        .filter(|&r| plan.prescribed[group[r]].is_none())
        .collect();
    let mut mf = m.select_rows(&free).select_columns(&free);
    let factor = cholesky_in_place(&mut mf)
        .map(|()| mf)
        .map_err(|kf| group[free[kf]]);
    (free, factor)
}

/// Accelerations `v̇` consistent with `q`, `v` at time `t` \[s\]: solves `M v̇ = τ_applied − C`,
/// where `C` holds gravity, velocity terms and external forces, with `extra` adding further
/// external forces (those of later stages of the pipeline) to `ws.f_ext` after the applied forces
/// (the workspace then holds positions and velocities at `q`, `v`). With closed loops the
/// constraint multipliers `λ` come with them (`dynamics/loops.rs`, KKT system); empty without.
/// `None` if `M` (or the KKT matrix) is singular.
pub(crate) fn consistent_accelerations_with(
    plan: &Plan,
    ws: &mut Workspace,
    t: f64,
    q: &[f64],
    v: &[f64],
    extra: &mut dyn FnMut(&Plan, &mut Workspace),
) -> Option<(Vec<f64>, Vec<f64>)> {
    accelerations_with(plan, ws, t, q, v, extra, true)
}

/// [`consistent_accelerations_with`] with the loops' constraint forces among the external
/// forces that `extra` adds (the multipliers `λ` known, e.g. stored by a run): `M v̇ = τ_applied
/// − C` per joint tree, no KKT system. For the joint loads of a result (`dynamics/loads.rs`),
/// which must agree with the cut joints' forces of the same `λ`.
pub(crate) fn accelerations_given_loop_forces(
    plan: &Plan,
    ws: &mut Workspace,
    t: f64,
    q: &[f64],
    v: &[f64],
    extra: &mut dyn FnMut(&Plan, &mut Workspace),
) -> Option<Vec<f64>> {
    accelerations_with(plan, ws, t, q, v, extra, false).map(|(vd, _)| vd)
}

/// [`consistent_accelerations_with`]; with `kkt` false the loops are left to `extra`.
fn accelerations_with(
    plan: &Plan,
    ws: &mut Workspace,
    t: f64,
    q: &[f64],
    v: &[f64],
    extra: &mut dyn FnMut(&Plan, &mut Workspace),
    kkt: bool,
) -> Option<(Vec<f64>, Vec<f64>)> {
    let nv = plan.nv;
    let blocks = tree_mass_matrices(plan, ws, q);
    position_velocity(plan, ws, q, v);
    applied_forces(plan, ws, t, q, v);
    extra(plan, ws);
    let mut bias = vec![0.0; nv];
    super::rnea::inverse_dynamics(plan, ws, q, &vec![0.0; nv], &plan.gravity, &mut bias);
    let mut vd = vec![0.0; nv];
    for (k, p) in plan.prescribed.iter().enumerate() {
        if let Some(i) = p {
            vd[k] = ws.inputs[*i];
        }
    }
    if kkt && !plan.loops.is_empty() {
        let rhs: Vec<f64> = (0..nv).map(|k| ws.tau_applied[k] - bias[k]).collect();
        let lambda = super::loops::kkt_accelerations(plan, ws, q, v, &blocks, &rhs, &mut vd)?;
        return Some((vd, lambda));
    }
    // Per tree: prescribed accelerations are known; solve M_FF v̇_F = τ_F − C_F − M_FP a_P
    // for the rest of the tree.
    for (group, m) in blocks {
        let (free, mf) = free_cholesky(plan, &group, &m);
        if free.is_empty() {
            continue;
        }
        let Ok(mf) = mf else {
            // Singular by the pivot test: the row-operated system of the residual, where it is
            // regular (a light body carrying a heavy one), else no consistent accelerations.
            let vd_f = row_operated_accelerations(plan, ws, q, &group, &free, &vd)?;
            for (i, &r) in free.iter().enumerate() {
                vd[group[r]] = vd_f[i];
            }
            continue;
        };
        let mut y: Vec<f64> = free
            .iter()
            .map(|&r| {
                let k = group[r];
                let coupling: f64 = (0..group.len()).map(|c| m[(r, c)] * vd[group[c]]).sum();
                ws.tau_applied[k] - bias[k] - coupling
            })
            .collect();
        let n = free.len();
        // Forward and back substitution with the lower factor.
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
        for (i, &r) in free.iter().enumerate() {
            vd[group[r]] = y[i];
        }
    }
    Some((vd, vec![]))
}

/// `M' = L(q) M(q)` of joint tree `group` (velocity indices) restricted to its coordinates
/// `free` (positions in `group`), the matrix of the residual's own rows
/// (`rnea::residual_dynamics`: each joint's residual rows taken out of the force it passes on,
/// `F' = L F`, the same solution) in the accelerations; no longer symmetric. Equilibrated (rows,
/// then columns, to unit largest entries) and factored by LU with partial pivoting; returns
/// the factors, the row scales and the column scales, or the global velocity index of a
/// coordinate whose row vanishes or whose pivot is below [`PIVOT_TOLERANCE`] (relative to each
/// row's and coordinate's own scale, as the Cholesky test is). Where `M`'s ill-conditioning comes from a light body carrying a heavy one through
/// a joint that lets the heavy one stay put, `M'` is block triangular in them and regular;
/// where a coordinate truly has no inertia (a massless body, or one whose coordinate only
/// duplicates another's), its row of `M'` vanishes as its row of `M` does. `ws` is not
/// changed (a copy is set to zero velocity and force; `M'` depends on `q` alone). Allocates.
type RowOperatedLu = (
    nalgebra::LU<f64, nalgebra::Dyn, nalgebra::Dyn>,
    Vec<f64>,
    Vec<f64>,
);

fn row_operated_lu(
    plan: &Plan,
    ws: &Workspace,
    q: &[f64],
    group: &[usize],
    free: &[usize],
) -> Result<RowOperatedLu, usize> {
    let nv = plan.nv;
    let mut w0 = ws.clone();
    position_velocity(plan, &mut w0, q, &vec![0.0; nv]);
    w0.f_ext.fill(Force::default());
    w0.tau_applied.fill(0.0);
    let n = free.len();
    let mut mp = DMatrix::zeros(n, n);
    let (mut e, mut rows) = (vec![0.0; nv], vec![0.0; nv]);
    for (c, &rc) in free.iter().enumerate() {
        e.fill(0.0);
        e[group[rc]] = 1.0;
        super::rnea::residual_dynamics(plan, &mut w0, (q, &e), &Vector3::zeros(), &mut rows, None);
        for (r, &rr) in free.iter().enumerate() {
            mp[(r, c)] = rows[group[rr]];
        }
    }
    let mut row_scale = vec![0.0; n];
    for (r, rs) in row_scale.iter_mut().enumerate() {
        *rs = mp.row(r).amax();
        if !(*rs > 0.0 && rs.is_finite()) {
            return Err(group[free[r]]);
        }
        mp.row_mut(r).scale_mut(1.0 / *rs);
    }
    let col_scale: Vec<f64> = (0..n).map(|c| mp.column(c).amax()).collect();
    for (c, &cs) in col_scale.iter().enumerate() {
        if cs.is_nan() || cs <= 0.0 {
            return Err(group[free[c]]);
        }
        mp.column_mut(c).scale_mut(1.0 / cs);
    }
    let lu = mp.lu();
    let u = lu.u();
    if let Some(i) = (0..n).find(|&i| u[(i, i)].is_nan() || u[(i, i)].abs() <= PIVOT_TOLERANCE) {
        return Err(group[free[i]]);
    }
    Ok((lu, row_scale, col_scale))
}

/// The free accelerations of joint tree `group` (`free`: the positions in `group` of its
/// coordinates that are not prescribed; `vd`: the prescribed accelerations set) from the
/// residual's own rows `F'(v̇) = M' v̇ + b' = 0` ([`row_operated_lu`]), for a tree whose
/// Cholesky factor of `M` failed its pivot test (random scenes: runs that reached an event
/// failed at the restart as singular, `M_ii·(M⁻¹)_ii` ~1e13). `ws` holds positions,
/// velocities and forces at the state (the caller's). `None` if `M'` is singular too.
fn row_operated_accelerations(
    plan: &Plan,
    ws: &mut Workspace,
    q: &[f64],
    group: &[usize],
    free: &[usize],
    vd: &[f64],
) -> Option<Vec<f64>> {
    let (lu, row_scale, col_scale) = row_operated_lu(plan, ws, q, group, free).ok()?;
    // b' + M'·(prescribed part): the rows at v̇ = (prescribed, 0) with the state's forces.
    let mut vd0 = vec![0.0; plan.nv];
    for &k in group {
        if plan.prescribed[k].is_some() {
            vd0[k] = vd[k];
        }
    }
    let mut rows = vec![0.0; plan.nv];
    super::rnea::residual_dynamics(plan, ws, (q, &vd0), &plan.gravity, &mut rows, None);
    let rhs = nalgebra::DVector::from_iterator(
        free.len(),
        free.iter()
            .zip(&row_scale)
            .map(|(&r, s)| (ws.tau_applied[group[r]] - rows[group[r]]) / s),
    );
    let y = lu.solve(&rhs)?;
    let x: Vec<f64> = y.iter().zip(&col_scale).map(|(y, s)| y / s).collect();
    x.iter().all(|v| v.is_finite()).then_some(x)
}

/// Whether tree `group`'s coordinates that are not prescribed have no consistent
/// accelerations at `q`: the Cholesky factor of `m` (its block of `M`) fails its pivot test
/// ([`free_cholesky`]) and so does the residual's row-operated matrix ([`row_operated_lu`]).
/// Returns the global velocity index of the coordinate the latter names then (a row that
/// vanishes is the coordinate without inertia of its own: a massless link's, not the load's
/// it carries).
pub(crate) fn singular_coordinate(
    plan: &Plan,
    ws: &Workspace,
    q: &[f64],
    group: &[usize],
    m: &DMatrix<f64>,
) -> Option<usize> {
    let (free, factor) = free_cholesky(plan, group, m);
    factor.err()?;
    row_operated_lu(plan, ws, q, group, &free).err()
}

/// The mass matrix of the coordinates that are not prescribed must be positive definite at
/// the initial state (or, where its Cholesky pivot test fails, the residual's row-operated
/// matrix must be regular: `mass_matrix::singular_coordinate`); otherwise names the joint
/// whose coordinate has no inertia.
///
/// (Beside the mass matrix it forms: the plan only lays the tree out.) This is the one scene
/// check after validation: it needs the compiled plan and the
/// dynamics (an inverse-dynamics pass per coordinate). It runs only on a scene without
/// any other error, so its error never hides another one; and a body without mass is a
/// consequence of values validation has already accepted, so the user fixes it in one
/// further edit rather than seeing a new kind of error appear after each round.
pub(crate) fn check_inertia(plan: &Plan) -> Result<(), SceneErrors> {
    let mut ws = super::Workspace::new(plan);
    let singular = tree_mass_matrices(plan, &mut ws, &plan.q0)
        .into_iter()
        .find_map(|(group, m)| singular_coordinate(plan, &ws, &plan.q0, &group, &m));
    if let Some(k) = singular {
        let j = plan
            .joints
            .iter()
            .find(|j| k >= j.v_offset && k < j.v_offset + j.coord.nv())
            .expect("every velocity belongs to a joint");
        let body = &plan.bodies[j.body];
        let problem = if body.inertia.mass == 0.0 {
            "has no mass"
        } else {
            "has a singular inertia for its degrees of freedom"
        };
        return Err(SceneErrors(vec![SceneError::SingularMass {
            joint: j.name.clone(),
            objects: body
                .objects
                .iter()
                .map(|&o| plan.objects[o].name.clone())
                .collect(),
            problem,
        }]));
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::dynamics::{kinematics, rnea};
    use crate::spatial::Force;
    use crate::{FreeRotation, Joint, JointKind, Object3D, SceneDesc, SceneOptions, Shape, Solid};
    use nalgebra::Vector3;

    /// The joint-space mass matrix `M(q)` (nv × nv), assembled from the blocks of
    /// [`tree_mass_matrices`] (zero between trees).
    fn mass_matrix(plan: &Plan, ws: &mut Workspace, q: &[f64]) -> DMatrix<f64> {
        let mut m = DMatrix::zeros(plan.nv, plan.nv);
        for (group, block) in tree_mass_matrices(plan, ws, q) {
            for (c, &j) in group.iter().enumerate() {
                for (r, &i) in group.iter().enumerate() {
                    m[(i, j)] = block[(r, c)];
                }
            }
        }
        m
    }

    /// `M(q)` assembled tree by tree (one inverse-dynamics call per coordinate index shared by
    /// all trees) equals the definition column by column — inverse dynamics with unit
    /// acceleration k, no velocity, gravity or external force — for a scene of several trees of
    /// different shapes (a two-link arm, twelve free balls): to round-off (1e-12 of the largest
    /// diagonal entry: the columns are sums of a few dozen products of O(1) terms), and zero
    /// between trees.
    #[test]
    fn tree_blocked_mass_matrix_matches_the_column_definition() {
        let mut scene = SceneDesc::new();
        scene.add(Object3D::new("world").scene(SceneOptions::default()));
        for i in 0..12 {
            let name = format!("ball{i}");
            let (x, y) = ((i % 4) as f64 * 0.06, (i / 4) as f64 * 0.06);
            scene
                .add(
                    Object3D::new(&name)
                        .solid(Solid::new(Shape::Sphere { diameter: 0.05 }).material("Steel")),
                )
                .add_joint(Joint::new(
                    &format!("free{i}"),
                    "world",
                    &name,
                    JointKind::FreeMotion {
                        r: Vector3::new(x, y, 0.1 + 0.01 * i as f64),
                        rot: FreeRotation::Cardan([0.1 * i as f64, 0.0, 0.0]),
                        v: Vector3::zeros(),
                        w: Vector3::zeros(),
                    },
                ));
        }
        scene
            .add(
                Object3D::new("link1").solid(
                    Solid::new(Shape::Box {
                        lengths: Vector3::new(0.3, 0.05, 0.05),
                    })
                    .material("Steel"),
                ),
            )
            .add(
                Object3D::new("link2").solid(
                    Solid::new(Shape::Box {
                        lengths: Vector3::new(0.2, 0.04, 0.04),
                    })
                    .material("Steel"),
                ),
            )
            .add(
                Object3D::new("tip")
                    .parent("link1")
                    .translation([0.3, 0.0, 0.0]),
            )
            .add_joint(
                Joint::new("j1", "world", "link1", JointKind::revolute(3)).init_position(0.4),
            )
            .add_joint(
                Joint::new("j2", "tip", "link2", JointKind::revolute(2)).init_position(-0.7),
            );
        let model = scene.build().unwrap();
        let plan = &*model.plan;
        let q = &plan.q0;
        let mut ws = Workspace::new(plan);
        let m = mass_matrix(plan, &mut ws, q);
        let nv = plan.nv;
        kinematics::position_velocity(plan, &mut ws, q, &vec![0.0; nv]);
        ws.f_ext.fill(Force::default());
        let (mut e, mut col) = (vec![0.0; nv], vec![0.0; nv]);
        let scale = (0..nv).map(|i| m[(i, i)].abs()).fold(0.0, f64::max);
        let mut max_err = 0.0f64;
        for k in 0..nv {
            e[k] = 1.0;
            rnea::inverse_dynamics(plan, &mut ws, q, &e, &Vector3::zeros(), &mut col);
            e[k] = 0.0;
            for i in 0..nv {
                max_err = max_err.max((m[(i, k)] - col[i]).abs());
            }
        }
        assert_eq!(plan.velocity_groups().len(), 13, "12 balls and one arm");
        assert!(
            max_err < 1e-12 * scale,
            "max |ΔM| = {max_err:e} (scale {scale:e})"
        );
    }
}
