//! DAE stage: the columns of the iteration matrix `∂F/∂y + c_j ∂F/∂y'` that the DAE computes
//! itself ([`crate::solver::DaeSystem::jacobian`]) instead of the solver's coloured difference
//! quotients: those of every joint tree that is one body on a FreeMotion joint to the world
//! (or to an object fixed to it) with nothing but uniform gravity, contacts and its own force
//! elements acting on it ([`FreeBody`]). Such a block costs 13 full residual evaluations by
//! quotients; here
//!
//! - its own 13 × 13 block is exact: the kinematic residual of `joints/free.rs` and the
//!   Newton–Euler residual of one rigid body about its frame origin as `dynamics/rnea.rs`
//!   forms it for a root body, in the frame of the joint's velocities ([`own_block`]). With
//!   the velocities resolved in obj1: `ṙ − v`, the quaternion rate `½ (0, ω) ⊗ q` with its
//!   norm-restoring term, and `I₁ a₁ + v₁ ×* I₁ v₁ − f₁` with `I₁ = R I Rᵀ` (`R = R(q̂)`,
//!   `q̂ = q/|q|` because `quat_to_matrix` normalises), `a₁ = (ω̇, v̇ − ω × v + g_J)`,
//!   `g_J = −R_treeᵀ g` (the world's base acceleration `−g` resolved in obj1) and `f₁` the
//!   external wrench resolved in obj1. With them resolved in the body: `ṙ − R v`,
//!   `½ q ⊗ (0, ω)`, and `I (a + (0, Rᵀ g_J)) + v ×* I v − f_ext` with `a = (ω̇, v̇)`;
//! - each pair of the contact set adds the derivative of its wrenches on its (≤ 2) bodies with
//!   respect to those bodies' states. Exact where the narrow phase is a closed form with a
//!   point contact — sphere–sphere, a sphere against a box or capsule fixed to the world
//!   (`contact/pair_jacobian.rs`: the chain rule through placement, normal, depth, contact
//!   point, relative velocity, force law and wrench, in tangent directions `δx`, `δθ`, `δω`,
//!   `δv` per body, mapped here to the states: `δx = R_tree δr`, `δθ = G(q) δq`
//!   ([`rotation_tangent`]), `δω = R_tree δω₁` (the same for `v`) for velocities in obj1,
//!   `δω = X δω₂ − X [ω₂]× δθ` (`X = R_tree R`) for velocities in the body; its world-resolved
//!   wrench turned into the rows' frame). Every other pair by pair-local difference quotients: one state
//!   perturbed, that body's placement and velocity recomputed, the pair's narrow phase
//!   (position columns only: the geometry does not depend on velocities, nor a centred
//!   sphere's on its quaternion) and force law evaluated again
//!   (`ContactState::pair_geometry`, `pair_wrenches`, which touch no pair state), with the
//!   solver's increment rule (`solver::dq_increment`; central where `h·y'_j = 0`); a pair whose
//!   shapes are apart (in the set by its hysteresis) adds nothing: its force is zero around
//!   the state, where a quotient across the touch found the linear law's full stiffness;
//! - its own force elements (a user law has no formula to differentiate) by quotients of those
//!   elements alone, with the same increments ([`own_force_columns`]).
//!
//! A block is computed here only if every body it touches through a contact is such a body
//! too (its column's rows are then all single-body rows) and none of its pairs' narrow phases
//! has stopped at its iteration limit (a rough geometry); otherwise it keeps the quotients
//! (`MultibodyDae::jacobian_structure`).
//! Allocation-free.

use super::increment_caps::{rotation_cap, with_step_floor};
use super::MultibodyDae;
use crate::contact::{pair_wrench_jacobian, ContactPlan, ContactState, PER_BODY};
use crate::dynamics::{kinematics, rnea, BodyId, InputTarget, Plan, Workspace};
use crate::scene::ValidForce;
use crate::solver::{capped_increment, JacobianArgs, JacobianSink, ResidualError};
use crate::spatial::{quat_to_matrix, Force, Inertia, Motion};
use nalgebra::{Matrix3, Matrix4, SMatrix, Vector3, Vector4};

/// A joint tree that is one body on a FreeMotion joint to the world (or to an object fixed to
/// it), with no input, loop, prescribed motion or point gravity acting on it, and no force
/// element but its own ones: force elements that act on this body alone and depend on its
/// state alone (an `ObjectForce` or world force/torque on one of its objects, a spring-damper
/// or bushing to the world).
#[derive(Clone, Copy, Debug, PartialEq)]
pub(super) struct FreeBody {
    /// The body.
    pub body: BodyId,
    /// Index in `y` of its first position (`r`, then the quaternion at +3).
    pub q: usize,
    /// Index in `y` of its first velocity (`ω`, then `v` at +3).
    pub v: usize,
    /// Its velocities are resolved in obj1 (else in its own frame; `joints/free.rs`).
    pub in_obj1: bool,
    /// Its own force elements: `own_forces[forces.0..forces.1]` of [`free_bodies`]' second
    /// result (indices into the scene's force elements).
    pub forces: (usize, usize),
}

/// The one body a force element acts on and depends on, if there is exactly one: `Ok(body)`;
/// `Err(bodies)` with the bodies it touches otherwise (a joint spring-damper is never one
/// body's own: it acts on joint coordinates, not on `f_ext`).
pub(super) fn own_body(plan: &Plan, f: &ValidForce) -> Result<BodyId, [Option<BodyId>; 2]> {
    let body = |o: usize| {
        plan.objects
            .get(crate::dynamics::ObjectId(o))
            .and_then(|op| op.body)
    };
    let objects = match f {
        ValidForce::SpringDamper { obj1, obj2, .. } | ValidForce::Bushing { obj1, obj2, .. } => {
            [Some(*obj1), Some(*obj2)]
        }
        ValidForce::ObjectForce { object, .. } => [Some(*object), None],
        ValidForce::WorldVector {
            object,
            resolved_in,
            ..
        } => [Some(*object), *resolved_in],
        ValidForce::JointSpringDamper { joint, .. } => {
            let b = plan
                .tree_joint_of
                .get(*joint)
                .copied()
                .flatten()
                .map(|tj| plan.joints[tj].body);
            return Err([b, None]);
        }
    };
    let [a, b] = objects.map(|o| o.and_then(body));
    match (a, b) {
        (Some(x), None) | (None, Some(x)) => Ok(x),
        (Some(x), Some(y)) if x == y => Ok(x),
        _ => Err([a, b]),
    }
}

/// For each joint tree (`of_body`: tree of each body, `n_trees` trees), the [`FreeBody`] it is,
/// if it is one, and the list its own force elements index.
pub(super) fn free_bodies(
    plan: &Plan,
    of_body: &[usize],
    n_trees: usize,
) -> (Vec<Option<FreeBody>>, Vec<usize>) {
    let nb = plan.bodies.len();
    let mut touched = vec![plan.point_gravity.is_some(); nb];
    let mut owner = vec![None; plan.scene.forces.len()];
    for (e, f) in plan.scene.forces.iter().enumerate() {
        match own_body(plan, f) {
            Ok(b) => owner[e] = Some(b),
            Err(bodies) => {
                for b in bodies.into_iter().flatten() {
                    touched[b.index()] = true;
                }
            }
        }
    }
    for inp in &plan.inputs {
        match inp.target {
            InputTarget::JointForce { joint, .. }
            | InputTarget::JointAcceleration { joint, .. } => {
                touched[plan.joints[joint].body.index()] = true;
            }
            InputTarget::ObjectWrench { object } => {
                if let Some(b) = plan.objects[object].body {
                    touched[b.index()] = true;
                }
            }
        }
    }
    for cut in &plan.loops.cuts {
        for b in [cut.body1, cut.body2].into_iter().flatten() {
            touched[b.index()] = true;
        }
    }
    let mut count = vec![0usize; n_trees];
    for &t in of_body {
        count[t] += 1;
    }
    let mut out = vec![None; n_trees];
    let mut own_forces = vec![];
    for (i, body) in plan.bodies.iter().enumerate() {
        let j = &plan.joints[body.joint];
        let prescribed = plan.prescribed[j.v_offset..j.v_offset + j.coord.nv()]
            .iter()
            .any(Option::is_some);
        if count[of_body[i]] == 1
            && body.parent.is_none()
            && j.coord.free_velocities().is_some()
            && !touched[i]
            && !prescribed
        {
            let first = own_forces.len();
            own_forces.extend((0..owner.len()).filter(|&e| owner[e] == Some(BodyId(i))));
            out[of_body[i]] = Some(FreeBody {
                body: BodyId(i),
                q: j.q_offset,
                v: plan.nq + j.v_offset,
                in_obj1: j.coord.free_velocities() == Some(true),
                forces: (first, own_forces.len()),
            });
        }
    }
    (out, own_forces)
}

/// `∂(R(u) a)/∂u` (3 × 4) of the rotation matrix formula of `quat_to_matrix` taken at `u`
/// without normalising, `R(u) a = a + 2w (v × a) + 2 (v (v·a) − a |v|²)` for `u = (w, v)`;
/// with `transpose`, of `R(u)ᵀ a` (the same with `−v × a`).
fn rotate_derivative(u: &Vector4<f64>, a: &Vector3<f64>, transpose: bool) -> SMatrix<f64, 3, 4> {
    let (w, v) = (u[0], Vector3::new(u[1], u[2], u[3]));
    let s = if transpose { -1.0 } else { 1.0 };
    let mut m = SMatrix::<f64, 3, 4>::zeros();
    m.set_column(0, &(v.cross(a) * (2.0 * s)));
    // ∂(v × a)/∂v = −[a]×; ∂(v (v·a))/∂v = (v·a) I + v aᵀ; ∂(a |v|²)/∂v = 2 a vᵀ.
    let dv = -a.cross_matrix() * (2.0 * w * s)
        + (Matrix3::identity() * v.dot(a) + v * a.transpose() - a * v.transpose() * 2.0) * 2.0;
    m.fixed_view_mut::<3, 3>(0, 1).copy_from(&dv);
    m
}

/// `G = ∂δθ/∂q` (3 × 4): the rotation of the body frame, resolved in it, of a change of the
/// (unnormalised) quaternion `q = (w, x, y, z)` whose rotation matrix is `R(q/|q|)`:
/// `dR = R [δθ]×` with `δθ = 2 vec(q̂* ⊗ dq)/|q| = (2/|q|) (−v̂ dw + (ŵ I − [v̂]×) dv)` for
/// `q̂ = (ŵ, v̂)` (a change along `q` itself only rescales it: `δθ = 0`).
fn rotation_tangent(q: &Vector4<f64>) -> SMatrix<f64, 3, 4> {
    let norm = q.norm();
    let u = q / norm;
    let v = Vector3::new(u[1], u[2], u[3]);
    let mut g = SMatrix::<f64, 3, 4>::zeros();
    g.set_column(0, &(-v * (2.0 / norm)));
    g.fixed_view_mut::<3, 3>(0, 1)
        .copy_from(&((Matrix3::identity() * u[0] - v.cross_matrix()) * (2.0 / norm)));
    g
}

/// Directional derivative of [`Inertia::bias_force`] at `m` along `dm` (the bias force is
/// quadratic in the velocity, so this is exact).
pub(super) fn bias_force_derivative(i: &Inertia, m: &Motion, dm: &Motion) -> Force {
    let c = &i.com;
    let wc = m.w.cross(c);
    let lin = (m.v + wc) * i.mass;
    let n_h = i.inertia_com * m.w + c.cross(&lin);
    let dwc = dm.w.cross(c);
    let dlin = (dm.v + dwc) * i.mass;
    let dn_h = i.inertia_com * dm.w + c.cross(&dlin);
    Force {
        n: dm.w.cross(&n_h) + m.w.cross(&dn_h) + (dm.v.cross(&wc) + m.v.cross(&dwc)) * i.mass,
        f: dm.w.cross(&lin) + m.w.cross(&dlin),
    }
}

/// Unit motion along coordinate `k` of `(ω, v)`.
fn unit_motion(k: usize) -> Motion {
    let mut m = Motion::zero();
    if k < 3 {
        m.w[k] = 1.0;
    } else {
        m.v[k - 3] = 1.0;
    }
    m
}

/// The `(n, f)` component `k` of a spatial force.
fn force_component(f: &Force, k: usize) -> f64 {
    if k < 3 {
        f.n[k]
    } else {
        f.f[k - 3]
    }
}

/// Local order of a free body's rows and columns: r 0..3, quaternion 3..7, ω 7..10, v 10..13.
const QQ: usize = 3;
/// See [`QQ`].
const VW: usize = 7;
/// See [`QQ`].
const VV: usize = 10;

/// The quaternion rows of a free body's block ([`QQ`]): `q̇ − ½ Ω q + k_n (|q|² − 1) q`, whose
/// exact rate `½ Ω(ω) q = ½ Ξ(q) ω` is given by the 4 × 4 `omega` (`Ω`) and 4 × 3 `xi` (`Ξ`).
fn quaternion_rows(
    a: &mut SMatrix<f64, 13, 13>,
    quat: &Vector4<f64>,
    omega: &Matrix4<f64>,
    xi: &SMatrix<f64, 4, 3>,
    c_j: f64,
) {
    let k_n = crate::joints::free::QUATERNION_NORM_RATE;
    let n2 = quat.norm_squared();
    let dq =
        -omega * 0.5 + (quat * quat.transpose() * 2.0 + Matrix4::identity() * (n2 - 1.0)) * k_n;
    for i in 0..4 {
        for k in 0..4 {
            a[(QQ + i, QQ + k)] = dq[(i, k)];
        }
        a[(QQ + i, QQ + i)] += c_j;
        for k in 0..3 {
            a[(QQ + i, VW + k)] = -0.5 * xi[(i, k)];
        }
    }
}

/// The 13 × 13 block of free body `fb` without its contacts, exact (see the module header),
/// passed to `out` column by column (rows `fb.q..fb.q + 7`, then `fb.v..fb.v + 6`).
pub(super) fn own_block(
    plan: &Plan,
    fb: &FreeBody,
    args: &JacobianArgs<'_>,
    out: &mut dyn JacobianSink,
) {
    let a = if fb.in_obj1 {
        own_block_obj1(plan, fb, args)
    } else {
        own_block_child(plan, fb, args)
    };
    let cols = a.as_slice();
    for c in 0..13 {
        let j = if c < 7 { fb.q + c } else { fb.v + c - 7 };
        let col = &cols[13 * c..13 * c + 13];
        out.add(fb.q, j, &col[..7]);
        out.add(fb.v, j, &col[7..]);
    }
}

/// [`own_block`] of a free body whose velocities `(ω, v)` are resolved in obj1
/// (`joints/free.rs`): its dynamic rows
/// `Sᵀ(I a + v ×* I v − f_ext)` are the Newton–Euler equations resolved in obj1:
/// `I₁ a₁ + v₁ ×* I₁ v₁ − f₁` with the rotated inertia `I₁ = R I Rᵀ`, `v₁ = (ω, v)` and
/// `a₁ = (ω̇, v̇ − ω × v − g₁)` (`g₁` gravity in obj1). They depend on the quaternion only
/// through `I₁`: a rotation `δθ₁` (resolved in obj1) changes `I₁ x` by `δθ₁ ⊛ I₁ x − I₁ (δθ₁ ⊛ x)`
/// (`⊛` turning both halves of a spatial vector), and `δθ₁ = R G δq` ([`rotation_tangent`]).
fn own_block_obj1(plan: &Plan, fb: &FreeBody, args: &JacobianArgs<'_>) -> SMatrix<f64, 13, 13> {
    let mut a = SMatrix::<f64, 13, 13>::zeros();
    let (y, yp, c_j) = (args.y, args.yp, args.c_j);
    let body = &plan.bodies[fb.body];
    let joint = &plan.joints[body.joint];
    let (qq, vw, vv) = (fb.q + 3, fb.v, fb.v + 3);
    let quat = Vector4::new(y[qq], y[qq + 1], y[qq + 2], y[qq + 3]);
    let rot = quat_to_matrix(quat.as_slice());
    let vec3 = |s: &[f64], i: usize| Vector3::new(s[i], s[i + 1], s[i + 2]);
    let (omega, vel) = (vec3(y, vw), vec3(y, vv));

    // Kinematic rows of r: ṙ − v.
    for i in 0..3 {
        a[(i, i)] += c_j;
        a[(i, VV + i)] = -1.0;
    }
    // Quaternion rows: q̇ − ½ (0, ω) ⊗ q + k_n (|q|² − 1) q.
    let (w, x, yy, z) = (quat[0], quat[1], quat[2], quat[3]);
    let omega_l = Matrix4::new(
        0.0, -omega.x, -omega.y, -omega.z, //
        omega.x, 0.0, -omega.z, omega.y, //
        omega.y, omega.z, 0.0, -omega.x, //
        omega.z, -omega.y, omega.x, 0.0,
    );
    let xi = SMatrix::<f64, 4, 3>::new(
        -x, -yy, -z, //
        w, z, -yy, //
        -z, w, x, //
        yy, -x, w,
    );
    quaternion_rows(&mut a, &quat, &omega_l, &xi, c_j);
    // Dynamic rows, resolved in obj1 (contacts and own force elements are added by the caller).
    let inertia = &body.inertia;
    let i1 = Inertia {
        mass: inertia.mass,
        com: rot * inertia.com,
        inertia_com: rot * inertia.inertia_com * rot.transpose(),
    };
    let g1 = -joint.tree.rot.tr_mul(&plan.gravity);
    let m = Motion { w: omega, v: vel };
    let acc = Motion {
        w: vec3(yp, vw),
        v: vec3(yp, vv) - omega.cross(&vel) + g1,
    };
    for k in 0..6 {
        let e = unit_motion(k);
        let mass = i1.mul_motion(&e);
        // ∂a₁/∂(ω, v) along e: (0, −e_ω × v − ω × e_v).
        let da = Motion {
            w: Vector3::zeros(),
            v: -e.w.cross(&vel) - omega.cross(&e.v),
        };
        let d = i1.mul_motion(&da) + bias_force_derivative(&i1, &m, &e);
        for i in 0..6 {
            a[(VW + i, VW + k)] = c_j * force_component(&mass, i) + force_component(&d, i);
        }
    }
    let (i_acc, i_m) = (i1.mul_motion(&acc), i1.mul_motion(&m));
    let mut d_theta = SMatrix::<f64, 6, 3>::zeros();
    for k in 0..3 {
        let mut e = Vector3::zeros();
        e[k] = 1.0;
        let turn_f = |f: &Force| Force {
            n: e.cross(&f.n),
            f: e.cross(&f.f),
        };
        let turn_m = |x: &Motion| Motion {
            w: e.cross(&x.w),
            v: e.cross(&x.v),
        };
        let d_ia = turn_f(&i_acc) - i1.mul_motion(&turn_m(&acc));
        let d_im = turn_f(&i_m) - i1.mul_motion(&turn_m(&m));
        let d = d_ia + m.cross_force(&d_im);
        for i in 0..6 {
            d_theta[(i, k)] = force_component(&d, i);
        }
    }
    let d_quat = d_theta * (rot * rotation_tangent(&quat));
    a.fixed_view_mut::<6, 4>(VW, QQ).copy_from(&d_quat);
    a
}

/// [`own_block`] of a free body whose velocities are resolved in its own frame: the kinematic
/// rows `ṙ − R(q̂) v` and `q̇ − ½ q ⊗ (0, ω)` (with the norm-restoring term), the dynamic rows
/// `I (a + (0, R(q̂)ᵀ g_J)) + v ×* I v` with `a = (ω̇, v̇)` (`S` the identity, `c_J` and
/// `v × v_J` vanish).
fn own_block_child(plan: &Plan, fb: &FreeBody, args: &JacobianArgs<'_>) -> SMatrix<f64, 13, 13> {
    let mut a = SMatrix::<f64, 13, 13>::zeros();
    let (y, c_j) = (args.y, args.c_j);
    let body = &plan.bodies[fb.body];
    let joint = &plan.joints[body.joint];
    let inertia = &body.inertia;
    let (qq, vw, vv) = (fb.q + 3, fb.v, fb.v + 3);
    let quat = Vector4::new(y[qq], y[qq + 1], y[qq + 2], y[qq + 3]);
    let n2 = quat.norm_squared();
    let norm = n2.sqrt();
    let u = quat / norm;
    // d(q/|q|)/dq.
    let p = (Matrix4::identity() - u * u.transpose()) / norm;
    let rot = quat_to_matrix(quat.as_slice());
    let omega = Vector3::new(y[vw], y[vw + 1], y[vw + 2]);
    let vel = Vector3::new(y[vv], y[vv + 1], y[vv + 2]);

    // Kinematic rows of r: ṙ − R(q̂) v.
    let d_rv = rotate_derivative(&u, &vel, false) * p;
    for i in 0..3 {
        a[(i, i)] += c_j;
        for k in 0..3 {
            a[(i, VV + k)] = -rot[(i, k)];
        }
        for k in 0..4 {
            a[(i, QQ + k)] = -d_rv[(i, k)];
        }
    }
    // Quaternion rows: q̇ − ½ Ω(ω) q + k_n (|q|² − 1) q.
    let (w, x, yy, z) = (quat[0], quat[1], quat[2], quat[3]);
    let omega_m = Matrix4::new(
        0.0, -omega.x, -omega.y, -omega.z, //
        omega.x, 0.0, omega.z, -omega.y, //
        omega.y, -omega.z, 0.0, omega.x, //
        omega.z, omega.y, -omega.x, 0.0,
    );
    let xi = SMatrix::<f64, 4, 3>::new(
        -x, -yy, -z, //
        w, -z, yy, //
        z, w, -x, //
        -yy, x, w,
    );
    quaternion_rows(&mut a, &quat, &omega_m, &xi, c_j);
    // Dynamic rows: I (v̇ + (0, R(q̂)ᵀ g_J)) + bias(v) (contacts are added by the caller).
    let m = Motion { w: omega, v: vel };
    for k in 0..6 {
        let e = unit_motion(k);
        let mass = inertia.mul_motion(&e);
        let bias = bias_force_derivative(inertia, &m, &e);
        for i in 0..6 {
            a[(VW + i, VW + k)] = c_j * force_component(&mass, i) + force_component(&bias, i);
        }
    }
    let g_joint = -joint.tree.rot.tr_mul(&plan.gravity);
    let d_grav = rotate_derivative(&u, &g_joint, true) * p;
    for k in 0..4 {
        let dm = Motion {
            w: Vector3::zeros(),
            v: d_grav.column(k).into_owned(),
        };
        let df = inertia.mul_motion(&dm);
        for i in 0..6 {
            a[(VW + i, QQ + k)] = force_component(&df, i);
        }
    }
    a
}

/// Sets body `b` (a root body on its joint) to positions `q` and velocities `v` of that
/// joint in the workspace: its placement and velocity, as `kinematics::position_velocity`.
fn place_root_body(plan: &Plan, ws: &mut Workspace, b: BodyId, q: &[f64], v: &[f64]) {
    let j = &plan.joints[plan.bodies[b].joint];
    let xj = j.coord.transform(q);
    let x = j.tree.then(&xj);
    ws.x[b] = x;
    ws.xj[b] = xj;
    ws.world[b] = x;
    ws.vel[b] = j.coord.motion(q, v);
}

/// Adds the derivatives of free body `fb`'s own force elements (`elements`, see [`FreeBody`])
/// to its dynamic rows, by difference quotients of those elements alone: each of the body's 13
/// states perturbed by the solver's increment (central where `h·y'_j = 0`, as the pair-local
/// quotients), its placement and velocity recomputed, the elements evaluated again. A user
/// law has no formula to differentiate; evaluating only the body's own elements costs a few
/// law calls instead of the whole residual, and keeps the body's exact block (a coloured
/// quotient of the whole residual perturbs its contacts too). `ws` is left as it was; a law
/// that fails at a perturbed state makes the step be retried (`Recoverable`).
fn own_force_columns(
    plan: &Plan,
    ws: &mut Workspace,
    fb: &FreeBody,
    elements: &[usize],
    args: &JacobianArgs<'_>,
    out: &mut dyn JacobianSink,
) -> Result<(), ResidualError> {
    let b = fb.body;
    let (nq, nv) = (plan.nq, plan.nv);
    let (yq, yv) = (&args.y[..nq], &args.y[nq..nq + nv]);
    let saved = (ws.x[b], ws.world[b], ws.vel[b], ws.f_ext[b]);
    let eval = |ws: &mut Workspace, c: usize, step: f64| {
        place_perturbed(plan, ws, fb, args.y, c, step);
        ws.f_ext[b] = Force::default();
        for &e in elements {
            crate::dynamics::forces::apply_element(plan, ws, args.t, yq, yv, e);
        }
        in_rows(plan, ws, fb, &ws.f_ext[b])
    };
    let base = eval(ws, 0, 0.0);
    for c in 0..13 {
        let j = if c < 7 { fb.q + c } else { fb.v + c - 7 };
        let inc = args.increment(j);
        let plus = eval(ws, c, inc);
        let (minus, inv) = match central_back(args, j, inc) {
            Some(back) => (eval(ws, c, back), 1.0 / (inc - back)),
            None => (base, 1.0 / inc),
        };
        out.add(fb.v, j, &residual_quotient(&plus, &minus, inv));
    }
    (ws.x[b], ws.world[b], ws.vel[b], ws.f_ext[b]) = saved;
    if ws.fault.take().is_some() {
        return Err(ResidualError::Recoverable);
    }
    Ok(())
}

/// The backward increment of a central quotient of unknown `j` whose forward increment is
/// `inc`, where `h·y'_j = 0` (there the one-sided increment's sign is arbitrary, so
/// mirror-image states would get a forward and a backward quotient); `None` where the quotient
/// is one-sided.
pub(super) fn central_back(args: &JacobianArgs<'_>, j: usize, inc: f64) -> Option<f64> {
    (args.h * args.yp[j] == 0.0).then(|| {
        let y0 = args.y[j];
        (y0 - inc) - y0
    })
}

/// Wrench `f` on free body `fb` (about its origin, resolved in it, as `Workspace::f_ext`) in
/// the frame of its dynamic rows (`Sᵀ f`): resolved in obj1 of its joint at the body's
/// placement in `ws` if its velocities are (see [`own_block`]), else as it is.
fn in_rows(plan: &Plan, ws: &Workspace, fb: &FreeBody, f: &Force) -> Force {
    if !fb.in_obj1 {
        return *f;
    }
    let rot = plan.joints[plan.bodies[fb.body].joint]
        .tree
        .rot
        .tr_mul(&ws.world[fb.body].rot);
    Force {
        n: rot * f.n,
        f: rot * f.f,
    }
}

/// The quotient `(plus − minus)·inv` of a body's external wrench (in its rows' frame,
/// [`in_rows`]), as the residual's dynamic rows see it (they have `− f_ext`).
fn residual_quotient(plus: &Force, minus: &Force, inv: f64) -> [f64; 6] {
    std::array::from_fn(|i| (force_component(minus, i) - force_component(plus, i)) * inv)
}

/// Places free body `fb` in `ws` at the states `y` with its `c`-th state (local order: `r`,
/// quaternion, `ω`, `v`) moved by `step`.
fn place_perturbed(plan: &Plan, ws: &mut Workspace, fb: &FreeBody, y: &[f64], c: usize, step: f64) {
    let mut q = [0.0; 7];
    let mut v = [0.0; 6];
    q.copy_from_slice(&y[fb.q..fb.q + 7]);
    v.copy_from_slice(&y[fb.v..fb.v + 6]);
    if c < 7 {
        q[c] += step;
    } else {
        v[c - 7] += step;
    }
    place_root_body(plan, ws, fb.body, &q, &v);
}

/// What the contact columns need of the DAE.
pub(super) struct ContactColumns<'a> {
    pub plan: &'a Plan,
    pub cp: &'a ContactPlan,
    pub cs: &'a ContactState,
    /// Tree of each body.
    pub of_body: &'a [usize],
    /// [`FreeBody`] of each tree, if it is one.
    pub free: &'a [Option<FreeBody>],
    /// Trees whose columns are computed here.
    pub analytic: &'a [bool],
}

impl ContactColumns<'_> {
    fn free_of(&self, b: Option<BodyId>) -> Option<FreeBody> {
        b.and_then(|b| self.free[self.of_body[b.index()]])
    }
    fn is_analytic(&self, b: Option<BodyId>) -> bool {
        b.is_some_and(|b| self.analytic[self.of_body[b.index()]])
    }

    /// Adds the exact derivatives of the `k`-th pair's wrenches on its bodies `bodies` (of
    /// shapes a and b) to the columns of those that are analytic ([`pair_wrench_jacobian`],
    /// tangent directions of body a from 0, of body b after it; `N` = [`PER_BODY`] per moving
    /// body); `false` (nothing added) where the pair has no closed form there.
    fn add_exact<const N: usize>(
        &self,
        ws: &Workspace,
        args: &JacobianArgs<'_>,
        k: usize,
        bodies: [Option<BodyId>; 2],
        out: &mut dyn JacobianSink,
    ) -> bool {
        let offset = [
            bodies[0].map(|_| 0),
            bodies[1].map(|_| if bodies[0].is_some() { PER_BODY } else { 0 }),
        ];
        let mut d = [SMatrix::<f64, 6, N>::zeros(); 2];
        let mut values = [Force::default(); 2];
        if !pair_wrench_jacobian(self.cp, self.cs, ws, k, offset, &mut d, &mut values) {
            return false;
        }
        let plan = self.plan;
        let tree_rot = |b: BodyId| plan.joints[plan.bodies[b].joint].tree.rot;
        for (col_body, o) in bodies.into_iter().zip(offset) {
            let (Some(fb), Some(o), true) = (self.free_of(col_body), o, self.is_analytic(col_body))
            else {
                continue;
            };
            let y = args.y;
            let g = rotation_tangent(&Vector4::new(
                y[fb.q + 3],
                y[fb.q + 4],
                y[fb.q + 5],
                y[fb.q + 6],
            ));
            // The pair's tangent directions (δx, δθ, δω, δv: world, body, world, world) per
            // state of the column body (12 × 13): δx = R_tree δr, δθ = G δq; velocities in obj1
            // give δω = R_tree δω₁ (the same for v); in the body frame (X = R_tree R) δω =
            // X δω₂ − X [ω₂]× δθ (the same for v).
            let mut t = SMatrix::<f64, 12, 13>::zeros();
            t.fixed_view_mut::<3, 3>(0, 0).copy_from(&tree_rot(fb.body));
            t.fixed_view_mut::<3, 4>(3, 3).copy_from(&g);
            let x = if fb.in_obj1 {
                tree_rot(fb.body)
            } else {
                let (x, vel) = (ws.world[fb.body].rot, ws.vel[fb.body]);
                t.fixed_view_mut::<3, 4>(6, 3)
                    .copy_from(&(-x * vel.w.cross_matrix() * g));
                t.fixed_view_mut::<3, 4>(9, 3)
                    .copy_from(&(-x * vel.v.cross_matrix() * g));
                x
            };
            t.fixed_view_mut::<3, 3>(6, 7).copy_from(&x);
            t.fixed_view_mut::<3, 3>(9, 10).copy_from(&x);
            for (row_body, (dr, val)) in bodies.into_iter().zip(d.iter().zip(&values)) {
                let Some(rb) = self.free_of(row_body) else {
                    continue;
                };
                // The rows' frame: obj1 (`R_treeᵀ` of the world wrench) or the body's own
                // (`Xᵀ`, which turns with the body: `d(Xᵀ a) = Xᵀ da + [Xᵀ a]× δθ`).
                let rr = if rb.in_obj1 {
                    tree_rot(rb.body).transpose()
                } else {
                    ws.world[rb.body].rot.transpose()
                };
                let w = dr.fixed_view::<6, 12>(0, o) * t;
                let mut cols = SMatrix::<f64, 6, 13>::zeros();
                for h in [0, 3] {
                    cols.fixed_view_mut::<3, 13>(h, 0)
                        .copy_from(&(rr * w.fixed_view::<3, 13>(h, 0)));
                }
                if !rb.in_obj1 && rb.body == fb.body {
                    for (h, a) in [(0, val.n), (3, val.f)] {
                        let turn = (rr * a).cross_matrix() * g;
                        let mut block = cols.fixed_view_mut::<3, 4>(h, 3);
                        block += turn;
                    }
                }
                // The residual has − f_ext.
                cols = -cols;
                for c in 0..13 {
                    let j = if c < 7 { fb.q + c } else { fb.v + c - 7 };
                    out.add(rb.v, j, cols.column(c).as_slice());
                }
            }
        }
        true
    }

    /// Adds the pair-local quotients of every pair in the contact set that touches an
    /// analytic block; `ws` holds the placements and velocities at `args.y` and is left so.
    pub(super) fn add(
        &self,
        ws: &mut Workspace,
        args: &JacobianArgs<'_>,
        out: &mut dyn JacobianSink,
    ) -> Result<(), ResidualError> {
        let (plan, cp, cs) = (self.plan, self.cp, self.cs);
        let fatal = |e: crate::contact::ContactError| ResidualError::Fatal(e.to_string());
        for k in 0..cs.n_in_contact() {
            let (ba, bb) = cs.active_bodies(cp, k);
            if !self.is_analytic(ba) && !self.is_analytic(bb) {
                continue;
            }
            let exact = match (ba, bb) {
                (Some(_), Some(_)) => self.add_exact::<24>(ws, args, k, [ba, bb], out),
                (Some(_), None) | (None, Some(_)) => {
                    self.add_exact::<12>(ws, args, k, [ba, bb], out)
                }
                (None, None) => true,
            };
            if exact {
                continue;
            }
            let geo0 = cs.pair_geometry(plan, cp, ws, k, args.t).map_err(fatal)?;
            // Apart (within the set's hysteresis), the pair exerts no force on a whole
            // neighbourhood of the state, so its derivatives are zero; a quotient whose
            // increment crossed the touch found the law's full stiffness instead.
            if geo0.0.distance > 0.0 {
                continue;
            }
            // The wrenches on the free bodies in their rows' frames ([`in_rows`]), at the
            // placements in `ws`.
            let obj1 = |ws: &Workspace, (fa, fb): (Option<Force>, Option<Force>)| {
                let turn = |body: Option<BodyId>, f: Option<Force>| match (self.free_of(body), f) {
                    (Some(fb), Some(f)) => Some(in_rows(plan, ws, &fb, &f)),
                    (_, f) => f,
                };
                (turn(ba, fa), turn(bb, fb))
            };
            let base = obj1(ws, cs.pair_wrenches(cp, ws, k, &geo0));
            for col_body in [ba, bb] {
                if !self.is_analytic(col_body) {
                    continue;
                }
                let Some(fb) = self.free_of(col_body) else {
                    continue;
                };
                let b = fb.body;
                let saved = (ws.x[b], ws.world[b], ws.vel[b]);
                // A centred sphere's geometry does not turn with its body: the quaternion
                // columns then reuse the unperturbed narrow phase, like the velocity columns.
                let round = cs.rotation_free(cp, k, b);
                let cap_q = rotation_cap(
                    cp,
                    cs,
                    k,
                    b,
                    -geo0.0.distance,
                    &geo0.1.point,
                    &ws.world[b].pos,
                );
                for c in 0..13 {
                    let j = if c < 7 { fb.q + c } else { fb.v + c - 7 };
                    let inc = if (3..7).contains(&c) {
                        let cap = with_step_floor(cap_q, args, j);
                        capped_increment(args.increment(j), cap, args.y[j])
                    } else {
                        args.increment(j)
                    };
                    let mut eval = |step: f64| {
                        place_perturbed(plan, ws, &fb, args.y, c, step);
                        let pert = if c < 3 || (c < 7 && !round) {
                            cs.pair_geometry(plan, cp, ws, k, args.t)
                                .map(|g| cs.pair_wrenches(cp, ws, k, &g))
                        } else {
                            Ok(cs.pair_wrenches(cp, ws, k, &geo0))
                        };
                        let pert = pert.map(|w| obj1(ws, w));
                        (ws.x[b], ws.world[b], ws.vel[b]) = saved;
                        pert.map_err(fatal)
                    };
                    let plus = eval(inc)?;
                    // Where h·y'_j = 0 the one-sided increment's sign is arbitrary (+), so two
                    // mirror-image states would get a forward and a backward quotient: there
                    // the quotient is central (e.g. the rack's resting balls at the start).
                    // Measured: billiards16 (tests/contact_billiards.rs) ends 9.0e-5 m from
                    // mirror-symmetric at 5 s with this, 1.4e-4 m without (main: 6.9e-5 m).
                    let (minus, inv) = match central_back(args, j, inc) {
                        Some(back) => (eval(back)?, 1.0 / (inc - back)),
                        None => (base, 1.0 / inc),
                    };
                    for (row_body, f, f0) in [(ba, plus.0, minus.0), (bb, plus.1, minus.1)] {
                        let (Some(rb), Some(f), Some(f0)) = (self.free_of(row_body), f, f0) else {
                            continue;
                        };
                        out.add(rb.v, j, &residual_quotient(&f, &f0, inv));
                    }
                }
            }
        }
        Ok(())
    }
}

impl MultibodyDae {
    /// The analytic columns ([`crate::solver::DaeSystem::jacobian`]): see the module header.
    pub(super) fn analytic_jacobian(
        &mut self,
        args: &JacobianArgs<'_>,
        out: &mut dyn JacobianSink,
    ) -> Result<(), ResidualError> {
        self.hinge_jacobian(args, out)?;
        let n_trees = self.blocks.as_ref().map(|tb| tb.n_trees);
        if n_trees.is_some_and(|n| self.analytic.get(n).copied().unwrap_or(false)) {
            self.component_columns(args, out)?;
        }
        let Some(tb) = &self.blocks else {
            return Ok(());
        };
        let plan = &*self.plan;
        let (nq, nv) = (plan.nq, plan.nv);
        for (t, fb) in tb.free.iter().enumerate() {
            if let (Some(fb), true) = (fb, self.analytic.get(t).copied().unwrap_or(false)) {
                own_block(plan, fb, args, out);
                let elements = &tb.own_forces[fb.forces.0..fb.forces.1];
                if !elements.is_empty() {
                    own_force_columns(plan, &mut self.ws, fb, elements, args, out)?;
                }
            }
        }
        let (Some(cs), Some(cp)) = (self.contact.as_ref(), self.contact_plan.as_deref()) else {
            return Ok(());
        };
        if cs.n_in_contact() == 0 {
            return Ok(());
        }
        kinematics::position_velocity(plan, &mut self.ws, &args.y[..nq], &args.y[nq..nq + nv]);
        ContactColumns {
            plan,
            cp,
            cs,
            of_body: &tb.of_body,
            free: &tb.free,
            analytic: &self.analytic,
        }
        .add(&mut self.ws, args, out)
    }
}

impl MultibodyDae {
    /// The columns of the components' states (block `n_trees`, analytic when every component
    /// gives its partial derivatives: `ComponentState::state_columns`): their own rows, and the
    /// negative of their flange forces' derivatives in the joints' rows (the residual's
    /// `… − τ`), except where a prescribed motion replaces the row.
    fn component_columns(
        &mut self,
        args: &JacobianArgs<'_>,
        out: &mut dyn JacobianSink,
    ) -> Result<(), ResidualError> {
        let plan = &*self.plan;
        let Some(cs) = self.comps.as_deref_mut() else {
            return Ok(());
        };
        let (nq, nv) = (plan.nq, plan.nv);
        let xo = plan.x_offset();
        use crate::dynamics::components::{ColumnRow, Point};
        let at = Point {
            t: args.t,
            q: &args.y[..nq],
            v: &args.y[nq..nq + nv],
            a: &args.yp[nq..nq + nv],
            x: &args.y[xo..xo + plan.components.nx],
        };
        // The flange forces' derivatives enter the joints' rows through the residual's row
        // operation (`rnea::residual_rows_of_applied`), at these positions.
        kinematics::position_velocity(plan, &mut self.ws, at.q, at.v);
        let ws = &self.ws;
        let (dtau, g, d_res) = (
            &mut self.comp_dtau,
            &mut self.comp_pass,
            &mut self.comp_rows,
        );
        dtau.fill(0.0);
        let mut any = false;
        let result = cs.state_columns(&plan.components, &at, args.c_j, |row, j, v| match row {
            ColumnRow::State(i) => out.add(xo + i, xo + j, &[v]),
            ColumnRow::Force(vi) => {
                dtau[vi] += v;
                any = true;
            }
            ColumnRow::Done => {
                if any {
                    rnea::residual_rows_of_applied(plan, ws, at.q, dtau, g, d_res);
                    for (vi, &d) in d_res.iter().enumerate() {
                        if d != 0.0 {
                            out.add(nq + vi, xo + j, &[d]);
                        }
                    }
                    dtau.fill(0.0);
                    any = false;
                }
            }
        });
        if let Err(f) = result {
            self.ws.fault.get_or_insert(f);
        }
        super::fault_check(&self.ws)
    }
}

#[cfg(test)]
pub(super) mod tests {
    use super::super::MultibodyDae;
    use crate::solver::{BlockStructure, DaeSystem, JacobianArgs};
    use crate::{FreeRotation, Joint, JointKind, Object3D, SceneDesc, SceneOptions, Shape, Solid};
    use nalgebra::{Matrix3, UnitQuaternion, Vector3};

    const D: f64 = 0.06;

    fn free(name: &str, r: [f64; 3]) -> Joint {
        Joint::new(
            &format!("{name}.free"),
            "world",
            name,
            JointKind::FreeMotion {
                r: Vector3::from(r),
                rot: FreeRotation::Cardan([0.0; 3]),
                v: Vector3::zeros(),
                w: Vector3::zeros(),
            },
        )
    }

    /// Steel on steel (friction μ_k 0.5, rolling resistance 0.001): a table (top at z = 0),
    /// a capsule cushion along y whose axis is at x = 0.5 m, z = 0.03 m, four balls (Ø 0.06 m)
    /// and a 0.05 m cube. The state is set by [`state`].
    fn scene() -> SceneDesc {
        scene_with(false)
    }

    /// [`scene`] with `SceneOptions::exact_restitution` set to `exact`.
    fn scene_with(exact: bool) -> SceneDesc {
        let mut s = SceneDesc::new();
        let options = SceneOptions {
            exact_restitution: exact,
            ..SceneOptions::default()
        };
        s.add(Object3D::new("world").scene(options))
            .add(
                Object3D::new("table")
                    .parent("world")
                    .translation([0.0, 0.0, -0.05])
                    .solid(
                        Solid::new(Shape::Box {
                            lengths: Vector3::new(2.0, 2.0, 0.1),
                        })
                        .material("Steel")
                        .collision(true),
                    ),
            )
            .add(
                Object3D::new("cushion")
                    .parent("world")
                    .translation([0.5, 0.0, 0.03])
                    .solid(
                        Solid::new(Shape::Capsule {
                            axis: crate::geometry::Axis::Y,
                            diameter: 0.02,
                            length: 1.0,
                        })
                        .material("Steel")
                        .collision(true),
                    ),
            );
        // b2 carries its centre of mass off its origin and the cube is not round, so their
        // free joints resolve their velocities in their own frames, the other balls' in the
        // world (`joints/free.rs`): both kinds of rows and columns meet in the pair b1–b2. b0
        // and b3 have three different moments of inertia, so their inertia in the world turns
        // with their quaternions. (With the cube resolved in the world, its quotient columns
        // matched as well: measured while the rule was being chosen.)
        let off_centre = |solid: Solid, m: f64| {
            solid.mass_properties(
                m,
                Vector3::new(2e-3, -1e-3, 1.5e-3),
                Matrix3::identity() * 1e-4 * m,
            )
        };
        for i in 0..4 {
            let name = format!("b{i}");
            let mut ball = Solid::new(Shape::Sphere { diameter: D })
                .material("Steel")
                .collision(true);
            if i == 2 {
                ball = off_centre(ball, 0.5);
            }
            if i == 0 || i == 3 {
                // Centred, with an inertia of three different moments (in the world's
                // frame its inertia turns with the quaternion).
                ball = ball.mass_properties(
                    0.4,
                    Vector3::zeros(),
                    Matrix3::from_diagonal(&Vector3::new(1.0, 2.0, 3.0)) * 1e-5,
                );
            }
            s.add(Object3D::new(&name).solid(ball))
                .add_joint(free(&name, [-0.5 + 0.2 * i as f64, 0.0, 0.5]));
        }
        s.add(
            Object3D::new("cube").solid(
                Solid::new(Shape::Box {
                    lengths: Vector3::new(0.05, 0.05, 0.05),
                })
                .material("Steel")
                .collision(true),
            ),
        )
        .add_joint(free("cube", [-0.5, 0.5, 0.5]));
        s
    }

    /// Deterministic pseudo-random numbers in [−1, 1) (xorshift).
    fn rng(seed: u64) -> impl FnMut() -> f64 {
        // Twice a number in [−0.5, 0.5): exact, the same sequence as before the shared helper.
        let mut u = crate::test_rng::uniform(seed);
        move || 2.0 * u()
    }

    /// A state of [`scene`]: `b0` in flight; `b1` and `b2` on the table and pressed into each
    /// other; `b3` on the table against the cushion; the cube on the table, tilted by ~1e-4 rad
    /// (one corner lower). Penetrations 1e-6 m; velocities and spins random
    /// (sliding), or with `rolling` the balls on the table roll (v = ω × r at the contact).
    /// Quaternions random with a norm off 1 by up to 1e-3 (the norm-restoring term).
    fn state(dae: &MultibodyDae, seed: u64, rolling: bool) -> Vec<f64> {
        state_with(dae, seed, rolling, false)
    }

    /// [`state`], with `b0_at_cube` b0 on the table pressed against the cube's side instead
    /// of in flight.
    fn state_with(dae: &MultibodyDae, seed: u64, rolling: bool, b0_at_cube: bool) -> Vec<f64> {
        let plan = dae.plan();
        let mut rnd = rng(seed);
        let mut y = plan.y0();
        let r = 0.5 * D;
        let pen = 1e-6;
        let cushion_x = 0.5 - 0.01 - r + pen;
        let b0 = if b0_at_cube {
            [-0.5 + 0.025 + r - pen, 0.5, r - pen]
        } else {
            [0.0, 0.3, 0.4]
        };
        let pos = [
            b0,
            [0.0, 0.0, r - pen],
            [2.0 * r - pen, 0.0, r - pen],
            [cushion_x, 0.2, r - pen],
            [-0.5, 0.5, 0.025 - pen],
        ];
        let names = ["b0.free", "b1.free", "b2.free", "b3.free", "cube.free"];
        for j in plan.joints.iter() {
            // Joints of other scenes built on this one (the arm of `scene_with_arm`) keep
            // their initial values.
            let Some(k) = names.iter().position(|n| *n == j.name) else {
                continue;
            };
            let (q, v) = (j.q_offset, plan.nq + j.v_offset);
            y[q..q + 3].copy_from_slice(&pos[k]);
            let quat = if k == 4 {
                // The cube: tilted by ~1e-4 rad about a generic axis, so its bottom face meets
                // the table at a slant. (About x alone, the state would sit on the model's
                // kink of a symmetric box: rotating about y lowers one corner or the other,
                // and the one-sided slopes differ; central differences average them.)
                UnitQuaternion::from_euler_angles(1e-4, 0.6e-4, 0.4)
            } else {
                UnitQuaternion::from_euler_angles(3.0 * rnd(), 1.5 * rnd(), 3.0 * rnd())
            };
            let scale = 1.0 + 1e-3 * rnd();
            y[q + 3] = quat.w * scale;
            y[q + 4] = quat.i * scale;
            y[q + 5] = quat.j * scale;
            y[q + 6] = quat.k * scale;
            // The free joint's velocities, resolved in the world.
            let w = Vector3::new(rnd(), rnd(), rnd()) * 20.0;
            let mut vel = Vector3::new(rnd(), rnd(), rnd() * 0.1);
            if rolling && (1..4).contains(&k) {
                // v_contact = v + ω × (−r e_z) = 0: v = ω × r e_z.
                vel = w.cross(&Vector3::new(0.0, 0.0, r));
            }
            // Resolved in the body's own frame where its joint resolves them there.
            let (w, vel) = if j.coord.free_velocities() == Some(true) {
                (w, vel)
            } else {
                let inv = UnitQuaternion::from_quaternion(quat.into_inner()).inverse();
                (inv * w, inv * vel)
            };
            y[v..v + 3].copy_from_slice(w.as_slice());
            y[v + 3..v + 6].copy_from_slice(vel.as_slice());
        }
        y
    }

    /// The analytic columns of `dae` at (`y`, `yp`) as a dense matrix, and which columns
    /// they are.
    fn analytic_columns(
        dae: &mut MultibodyDae,
        y: &[f64],
        yp: &[f64],
        c_j: f64,
    ) -> (Vec<Vec<f64>>, Vec<bool>) {
        let n = y.len();
        let mut s = BlockStructure::default();
        assert!(dae.jacobian_structure(&mut s));
        let cols: Vec<bool> = (0..n).map(|j| s.analytic[s.block_of[j]]).collect();
        let zero_size = vec![1e-2; n];
        let args = JacobianArgs {
            t: 0.0,
            c_j,
            h: 1e-4,
            y,
            yp,
            zero_size: &zero_size,
        };
        let mut a = vec![vec![0.0; n]; n];
        dae.jacobian(&args, &mut |i: usize, j: usize, d: f64| {
            assert!(cols[j], "entry ({i}, {j}) in a column that is not analytic");
            a[i][j] += d;
        })
        .unwrap();
        (a, cols)
    }

    /// `∂F/∂y + c_j ∂F/∂y'` by central differences of the full residual, increment `eta`.
    fn central(dae: &mut MultibodyDae, y: &[f64], yp: &[f64], c_j: f64, j: usize) -> Vec<f64> {
        central_with(dae, (y, yp), c_j, j, 1e-9)
    }

    /// [`central`] with the increment `rel · max(|y_j|, 1)`.
    pub(in crate::dae) fn central_with(
        dae: &mut MultibodyDae,
        (y, yp): (&[f64], &[f64]),
        c_j: f64,
        j: usize,
        rel: f64,
    ) -> Vec<f64> {
        let n = y.len();
        let eta = rel * y[j].abs().max(1.0);
        let (mut yy, mut ypp) = (y.to_vec(), yp.to_vec());
        let (mut rp, mut rm) = (vec![0.0; n], vec![0.0; n]);
        yy[j] = y[j] + eta;
        ypp[j] = yp[j] + c_j * eta;
        dae.residual(0.0, &yy, &ypp, &mut rp).unwrap();
        yy[j] = y[j] - eta;
        ypp[j] = yp[j] - c_j * eta;
        dae.residual(0.0, &yy, &ypp, &mut rm).unwrap();
        (0..n).map(|i| (rp[i] - rm[i]) / (2.0 * eta)).collect()
    }

    /// The analytic columns against central differences of the full residual at random states
    /// of [`scene`] (a ball in flight, two balls pressed together on the table, one against
    /// the cushion, a tilted cube; sliding and rolling), entry by entry.
    ///
    /// Tolerance per row `i`: `1e-3 · max_j |R_ij|` (R the central differences). The own
    /// blocks and the ball pairs are exact, so what differs is the cube's pair-local one-sided
    /// quotient's truncation,
    /// `η/2·|∂²f/∂y²|`: for the Hertz force `f ∝ δ^1.5` relative `η/(4δ)` = 4e-5 at the
    /// increment η = √ε·1e-2 = 1.5e-10 m and depth δ = 1e-6 m, and the central reference's
    /// `(1e-9)²/δ²` = 1e-6; 1e-3 leaves room for the friction's regularisation and the cube's
    /// patch, and is still far below any missing or wrong term (those are O(1) of the row).
    /// The ball in flight (b0, no contact) is checked at 1e-6: the quotient's rounding only.
    #[test]
    fn analytic_columns_match_central_differences() {
        let model = scene().build().unwrap();
        let mut dae = MultibodyDae::new(model.plan.clone(), model.contact.clone());
        let n = dae.len();
        let c_j = 2.5e3;
        for (seed, rolling) in [(1, false), (2, true), (3, false), (4, true)] {
            let y = state(&dae, seed, rolling);
            dae.handle_event(0.0, &y).unwrap();
            let cs = dae.contact().unwrap();
            // b1–table, b2–table, b1–b2, b3–table, b3–cushion, cube–table.
            assert_eq!(cs.n_in_contact(), 6, "seed {seed}");
            let mut rnd = rng(seed + 100);
            let yp: Vec<f64> = (0..n).map(|_| rnd()).collect();
            let (a, cols) = analytic_columns(&mut dae, &y, &yp, c_j);
            assert!(cols.iter().all(|&c| c), "every block is a free body");
            let frames: Vec<bool> = dae
                .blocks
                .as_ref()
                .unwrap()
                .free
                .iter()
                .flatten()
                .map(|f| f.in_obj1)
                .collect();
            assert_eq!(
                frames,
                [true, true, false, true, false],
                "b2 and the cube (not round) in their own frames"
            );
            let r: Vec<Vec<f64>> = (0..n).map(|j| central(&mut dae, &y, &yp, c_j, j)).collect();
            let b0 = dae
                .plan()
                .joints
                .iter()
                .find(|j| j.name == "b0.free")
                .unwrap();
            let in_flight = |i: usize| {
                (b0.q_offset..b0.q_offset + 7).contains(&i)
                    || (dae.plan().nq + b0.v_offset..dae.plan().nq + b0.v_offset + 6).contains(&i)
            };
            let mut worst = 0.0f64;
            for i in 0..n {
                let scale = (0..n).map(|j| r[j][i].abs()).fold(0.0, f64::max);
                let rel = if in_flight(i) { 1e-6 } else { 1e-3 };
                for j in 0..n {
                    let err = (a[i][j] - r[j][i]).abs();
                    worst = worst.max(err / scale.max(1e-300));
                    assert!(
                        err <= rel * scale + 1e-9,
                        "seed {seed}, rolling {rolling}: entry ({i}, {j}): analytic {:e}, central {:e}, row scale {scale:e}",
                        a[i][j],
                        r[j][i]
                    );
                }
            }
            eprintln!("seed {seed}: worst relative error {worst:e}");
        }
    }

    /// The exact pair blocks (`contact/pair_jacobian.rs`, mapped to the states by
    /// `ContactColumns::add_exact`) against central differences of `pair_wrenches` itself
    /// (the pair's narrow phase and force law, at states perturbed one coordinate at a time),
    /// for every pair of [`state`]'s contact set that has a closed form (ball–ball, ball–table,
    /// ball–cushion; the cube–table pair must decline), at random sliding and spinning states
    /// (velocities ~1 m/s, spins ~20 rad/s, so the pairs approach or separate) and rolling
    /// ones, with exact restitution off and on (the damping factor `d` from the exact relation or
    /// the paper's).
    ///
    /// Tolerance per row: `2e-6 · max_j |C_ij|` over the pair's columns (C the central
    /// differences at increment η = 3e-10). That is 10 × the error of the reference itself,
    /// measured by varying η: the worst entry differs by 4e-6 of its row at η = 1e-8, 2e-6 at
    /// 1e-9, 2.0e-7 at 3e-10, 3.3e-7 at 1e-10, 7.2e-7 at 3e-11 and > 1e-6 at 1e-11 — the V of
    /// the quotient's truncation (∝ η²) and rounding (∝ 1/η), whose bottom is the
    /// reference's accuracy here; a missing or wrong term is O(1) of its row.
    #[test]
    fn exact_pair_blocks_match_central_differences_of_the_pair_wrenches() {
        use crate::dynamics::kinematics;
        for exact in [false, true] {
            let model = scene_with(exact).build().unwrap();
            let mut dae = MultibodyDae::new(model.plan.clone(), model.contact.clone());
            let n = dae.len();
            let plan = dae.plan.clone();
            let (nq, nv) = (plan.nq, plan.nv);
            let cube = plan
                .bodies
                .iter()
                .position(|b| plan.joints[b.joint].name == "cube.free");
            let mut worst = 0.0f64;
            for (seed, rolling) in [
                (11, false),
                (12, true),
                (13, false),
                (14, true),
                (15, false),
            ] {
                let y = state(&dae, seed, rolling);
                dae.handle_event(0.0, &y).unwrap();
                let mut s = BlockStructure::default();
                assert!(dae.jacobian_structure(&mut s));
                kinematics::position_velocity(&plan, &mut dae.ws, &y[..nq], &y[nq..nq + nv]);
                let (cs, cp) = (
                    dae.contact.as_ref().unwrap(),
                    dae.contact_plan.as_deref().unwrap(),
                );
                let tb = dae.blocks.as_ref().unwrap();
                let cols = super::ContactColumns {
                    plan: &plan,
                    cp,
                    cs,
                    of_body: &tb.of_body,
                    free: &tb.free,
                    analytic: &dae.analytic,
                };
                let zero_size = vec![1e-2; n];
                let yp = vec![0.0; n];
                let args = JacobianArgs {
                    t: 0.0,
                    c_j: 1.0,
                    h: 1e-4,
                    y: &y,
                    yp: &yp,
                    zero_size: &zero_size,
                };
                let mut n_exact = 0;
                for k in 0..cs.n_in_contact() {
                    let (ba, bb) = cs.active_bodies(cp, k);
                    let mut a = vec![vec![0.0; n]; n];
                    let mut sink = |i: usize, j: usize, d: f64| a[i][j] += d;
                    let added = if ba.is_some() && bb.is_some() {
                        cols.add_exact::<24>(&dae.ws, &args, k, [ba, bb], &mut sink)
                    } else {
                        cols.add_exact::<12>(&dae.ws, &args, k, [ba, bb], &mut sink)
                    };
                    let with_cube = [ba, bb].iter().any(|b| b.map(|b| b.index()) == cube);
                    assert_eq!(added, !with_cube, "seed {seed}, pair {k}");
                    if !added {
                        continue;
                    }
                    n_exact += 1;
                    let bodies: Vec<_> = [ba, bb].into_iter().flatten().collect();
                    let mut columns = vec![];
                    for b in &bodies {
                        let fb = tb.free[tb.of_body[b.index()]].unwrap();
                        columns.extend((0..7).map(|c| fb.q + c).chain((0..6).map(|c| fb.v + c)));
                    }
                    // Central differences of −(wrench) on each of the pair's bodies.
                    let mut central = vec![vec![0.0; n]; n];
                    let mut ws = dae.ws.clone();
                    for &j in &columns {
                        let eta = 3e-10;
                        let mut eval = |step: f64| {
                            let mut yy = y.clone();
                            yy[j] += step;
                            kinematics::position_velocity(
                                &plan,
                                &mut ws,
                                &yy[..nq],
                                &yy[nq..nq + nv],
                            );
                            let g = cs.pair_geometry(&plan, cp, &ws, k, 0.0).unwrap();
                            // The rows' frame of each free body (`in_rows`).
                            let (fa, fb) = cs.pair_wrenches(cp, &ws, k, &g);
                            let turn =
                                |b: Option<crate::dynamics::BodyId>,
                                 f: Option<crate::spatial::Force>| {
                                    match (b.and_then(|b| tb.free[tb.of_body[b.index()]]), f) {
                                        (Some(fb), Some(f)) => {
                                            Some(super::in_rows(&plan, &ws, &fb, &f))
                                        }
                                        (_, f) => f,
                                    }
                                };
                            (yy[j] - y[j], (turn(ba, fa), turn(bb, fb)))
                        };
                        let ((hp, wp), (hm, wm)) = (eval(eta), eval(-eta));
                        for (b, fp, fm) in [(ba, wp.0, wm.0), (bb, wp.1, wm.1)] {
                            let (Some(b), Some(fp), Some(fm)) = (b, fp, fm) else {
                                continue;
                            };
                            let rv = tb.free[tb.of_body[b.index()]].unwrap().v;
                            for i in 0..6 {
                                let (p, m) = (
                                    super::force_component(&fp, i),
                                    super::force_component(&fm, i),
                                );
                                central[rv + i][j] = -(p - m) / (hp - hm);
                            }
                        }
                    }
                    for b in &bodies {
                        let rv = tb.free[tb.of_body[b.index()]].unwrap().v;
                        for i in rv..rv + 6 {
                            let scale = columns
                                .iter()
                                .map(|&j| central[i][j].abs())
                                .fold(0.0, f64::max);
                            for &j in &columns {
                                let err = (a[i][j] - central[i][j]).abs();
                                worst = worst.max(err / scale.max(1e-300));
                                assert!(
                                    err <= 2e-6 * scale + 1e-12,
                                    "exact {exact}, seed {seed}, pair {k}: entry ({i}, {j}): exact {:e}, central {:e}, row scale {scale:e}",
                                    a[i][j],
                                    central[i][j]
                                );
                            }
                        }
                    }
                }
                // b1–table, b2–table, b1–b2, b3–table, b3–cushion.
                assert_eq!(n_exact, 5, "seed {seed}");
            }
            eprintln!("exact restitution {exact}: worst relative error {worst:e}");
        }
    }

    /// A mixed scene: the cube is driven by an input wrench (its block keeps the difference
    /// quotients) and b0 presses against it, so b0's columns, whose contact rows include the
    /// cube's, are quotients too; b1, b2, b3 stay analytic and match central differences as
    /// in [`analytic_columns_match_central_differences`].
    #[test]
    fn a_contact_with_a_quotient_block_keeps_quotients() {
        let mut desc = scene();
        desc.add_input(crate::scene::Input::object_wrench("push", "cube"));
        let model = desc.build().unwrap();
        let mut dae = MultibodyDae::new(model.plan.clone(), model.contact.clone());
        let n = dae.len();
        let y = state_with(&dae, 7, false, true);
        dae.handle_event(0.0, &y).unwrap();
        // b0–table, b0–cube, b1–table, b2–table, b1–b2, b3–table, b3–cushion, cube–table.
        assert_eq!(dae.contact().unwrap().n_in_contact(), 8);
        let mut rnd = rng(77);
        let yp: Vec<f64> = (0..n).map(|_| rnd()).collect();
        let (a, cols) = analytic_columns(&mut dae, &y, &yp, 1e3);
        let plan = dae.plan();
        for j in plan.joints.iter() {
            let analytic = cols[j.q_offset];
            let expected = !matches!(j.name.as_str(), "b0.free" | "cube.free");
            assert_eq!(analytic, expected, "{}", j.name);
        }
        let r: Vec<Vec<f64>> = (0..n)
            .map(|j| {
                if cols[j] {
                    central(&mut dae, &y, &yp, 1e3, j)
                } else {
                    vec![0.0; n]
                }
            })
            .collect();
        for i in 0..n {
            let scale = (0..n).map(|k| r[k][i].abs()).fold(0.0, f64::max);
            for j in (0..n).filter(|&j| cols[j]) {
                assert!(
                    (a[i][j] - r[j][i]).abs() <= 1e-3 * scale + 1e-9,
                    "entry ({i}, {j}): analytic {:e}, central {:e}",
                    a[i][j],
                    r[j][i]
                );
            }
        }
    }

    /// A free body's own force elements (`own_force_columns`): the cube hangs on a
    /// spring-damper to the world and feels a user drag law (an `ObjectForce` closure of its
    /// velocity and a `WorldForce` closure of its position), all of which act on it alone, so
    /// every block stays analytic; the columns match central differences of the whole residual
    /// to the tolerance of [`analytic_columns_match_central_differences`] (the elements'
    /// quotients use the solver's increment, as the pair-local ones).
    #[test]
    fn own_force_elements_keep_a_free_body_analytic() {
        let mut desc = scene();
        desc.add_force(crate::ForceElement::SpringDamper {
            name: "hang".into(),
            obj1: "world".into(),
            obj2: "cube".into(),
            stiffness: 1e3,
            damping: 5.0,
            length0: 0.2,
        });
        desc.add_force(crate::ForceElement::ObjectForce {
            object: "cube".into(),
            law: crate::ForceFn::new(|_, m| crate::Wrench {
                force: -3.0 * m.v_abs * m.v_abs.norm(),
                torque: -0.2 * m.w_abs,
            }),
        });
        let model = desc.build().unwrap();
        let mut dae = MultibodyDae::new(model.plan.clone(), model.contact.clone());
        let n = dae.len();
        let c_j = 2.5e3;
        let y = state(&dae, 3, false);
        dae.handle_event(0.0, &y).unwrap();
        let mut rnd = rng(103);
        let yp: Vec<f64> = (0..n).map(|_| rnd()).collect();
        let (a, cols) = analytic_columns(&mut dae, &y, &yp, c_j);
        assert!(cols.iter().all(|&c| c), "every block is a free body");
        let tb = dae.blocks.as_ref().unwrap();
        let with_forces = tb.free.iter().flatten().filter(|f| f.forces.1 > f.forces.0);
        assert_eq!(with_forces.count(), 1, "the cube has its own elements");
        let r: Vec<Vec<f64>> = (0..n).map(|j| central(&mut dae, &y, &yp, c_j, j)).collect();
        for i in 0..n {
            let scale = (0..n).map(|j| r[j][i].abs()).fold(0.0, f64::max);
            for j in 0..n {
                assert!(
                    (a[i][j] - r[j][i]).abs() <= 1e-3 * scale + 1e-9,
                    "entry ({i}, {j}): analytic {:e}, central {:e}, row scale {scale:e}",
                    a[i][j],
                    r[j][i]
                );
            }
        }
    }

    /// A pair of the contact set whose shapes are apart (within the hysteresis) exerts no force
    /// on a neighbourhood of the state, so it adds nothing to the columns: the cube lifted
    /// 5e-11 m off the table and falling (the quotient's increment of its height, −1.5e-10 m,
    /// would cross the touch and find the linear law's full stiffness, ~1e10 N/m on the
    /// cube's rows). Its dynamic rows then get nothing from its position columns `r` (its own
    /// block has none there: gravity turns with the quaternion only). Under the paper's law,
    /// whose jump at the touch this guards against (the volume law's force starts at zero).
    #[test]
    fn a_pair_apart_in_the_set_adds_no_stiffness() {
        let mut s = scene();
        if let crate::scene::Feature::Scene(o) = &mut s.objects[0].feature {
            o.contact_profile = crate::scene::ContactProfile::Paper2019;
        }
        let model = s.build().unwrap();
        let mut dae = MultibodyDae::new(model.plan.clone(), model.contact.clone());
        let n = dae.len();
        let mut y = state(&dae, 3, false);
        dae.handle_event(0.0, &y).unwrap();
        let n_set = dae.contact().unwrap().n_in_contact();
        let (cube, body) = dae
            .plan()
            .joints
            .iter()
            .find(|j| j.name == "cube.free")
            .map(|j| ((j.q_offset, dae.plan().nq + j.v_offset), j.body))
            .unwrap();
        // The cube–table pair's signed distance [m] and the size of the set.
        let distance = |dae: &mut MultibodyDae, y: &[f64]| {
            let mut r = vec![0.0; n];
            dae.residual(0.0, y, &vec![0.0; n], &mut r).unwrap();
            let (cs, cp) = (dae.contact().unwrap(), dae.contact_plan().unwrap());
            let d = cs
                .active_pairs()
                .find(|(_, pp, _)| {
                    [pp.a, pp.b]
                        .iter()
                        .any(|&s| cp.shapes[s].body == Some(body))
                })
                .map(|(_, _, ps)| ps.geometry.distance)
                .unwrap();
            (d, cs.n_in_contact())
        };
        let (d0, _) = distance(&mut dae, &y);
        y[cube.0 + 2] += -d0 + 5e-11;
        let (d, in_set) = distance(&mut dae, &y);
        assert_eq!(in_set, n_set, "the lifted cube stays in the set");
        assert!(
            d > 0.0 && d < 1e-10,
            "the cube is apart by less than the increment: {d:e}"
        );
        let mut yp = vec![0.0; n];
        yp[cube.0 + 2] = -1.0;
        let (a, cols) = analytic_columns(&mut dae, &y, &yp, 2.5e3);
        assert!(cols[cube.0], "the cube's block is analytic");
        for (i, row) in a.iter().enumerate().skip(cube.1).take(6) {
            for (j, x) in row.iter().enumerate().skip(cube.0).take(3) {
                assert!(*x == 0.0, "entry ({i}, {j}) = {x:e}");
            }
        }
    }

    /// [`scene`] with an arm: a rod on a revolute joint about x at (0, −0.5, 0.2) m, carrying
    /// a 0.04 m cube on a free joint (relative to the rod) that rests on the table 1e-6 m deep
    /// at phi = 0, and an ellipsoid on a prismatic joint along z at (0.3, −0.5, 0) m that
    /// rests on the table beside it. Neither tree is a free body: their columns are coloured
    /// difference quotients of the whole residual.
    fn scene_with_arm() -> SceneDesc {
        let mut s = scene();
        let pen = 1e-6;
        s.add(
            Object3D::new("rod_mount")
                .parent("world")
                .translation([0.0, -0.5, 0.2]),
        )
        .add(
            Object3D::new("egg_mount")
                .parent("world")
                .translation([0.3, -0.5, 0.0]),
        )
        .add(
            Object3D::new("rod").solid(
                Solid::new(Shape::Cylinder {
                    axis: crate::geometry::Axis::Z,
                    diameter: 0.01,
                    length: 0.1,
                })
                .material("Steel"),
            ),
        )
        .add_joint(Joint::new(
            "rod.rev",
            "rod_mount",
            "rod",
            JointKind::Revolute {
                axis: Vector3::x(),
                phi: 0.0,
                w: 0.3,
            },
        ))
        .add(
            Object3D::new("tip").solid(
                Solid::new(Shape::Box {
                    lengths: Vector3::new(0.04, 0.04, 0.04),
                })
                .material("Steel")
                .collision(true),
            ),
        )
        .add_joint(Joint::new(
            "tip.free",
            "rod",
            "tip",
            JointKind::FreeMotion {
                r: Vector3::new(0.0, 0.0, -0.2 + 0.02 - pen),
                rot: FreeRotation::Cardan([2e-4, -1e-4, 0.3]),
                v: Vector3::new(0.01, 0.0, 0.0),
                w: Vector3::new(0.0, 0.0, 0.5),
            },
        ))
        .add(
            Object3D::new("egg").solid(
                Solid::new(Shape::Ellipsoid {
                    lengths: Vector3::new(0.06, 0.04, 0.03),
                })
                .material("Steel")
                .collision(true),
            ),
        )
        .add_joint(
            Joint::new(
                "egg.slide",
                "egg_mount",
                "egg",
                JointKind::Prismatic {
                    axis: Vector3::z(),
                    s: 0.015 - pen,
                    v: -0.01,
                },
            )
            .can_collide(true),
        );
        s
    }

    /// Two links on revolute joints driven by every block that has states or feedthrough
    /// (an elastic-gear DC drive under a PI speed loop and a limiter, a rigid drive under a
    /// `LimPID`, a `PID`, a `FirstOrder`, an `Integrator`, sums and expression inputs), so the
    /// chain rule runs through outputs with and without feedthrough, expressions, flange forces
    /// into both joints' rows and the limits' modes.
    fn servo_scene() -> SceneDesc {
        use crate::scene::blocks::{
            Add3, Drive, Feedback, FirstOrder, Gain, Integrator, LimPID, Limiter, Ramp, PI, PID,
        };
        use crate::scene::{ComponentDecl, Src};
        let mut s = SceneDesc::new();
        s.add(Object3D::new("world").scene(SceneOptions::default()));
        for (link, joint, parent) in [("l1", "rev1", "world"), ("l2", "rev2", "p1")] {
            s.add(Object3D::new(link).solid(Solid::new(Shape::Sphere { diameter: 0.1 }).mass(1.0)))
                .add(
                    Object3D::new(&format!("p{}", &link[1..]))
                        .parent(link)
                        .translation([0.3, 0.0, 0.0]),
                )
                .add_joint(Joint::new(joint, parent, link, JointKind::revolute(2)));
        }
        s.add_component(ComponentDecl::new(
            "ramp",
            Ramp {
                height: 1.0,
                duration: 2.0,
                offset: 0.0,
                startTime: 0.0,
            },
        ))
        .add_component(
            ComponentDecl::new(
                "filt",
                FirstOrder {
                    k: 1.0,
                    T: 0.05,
                    y_start: 0.0,
                },
            )
            .input("u", "ramp.y"),
        )
        .add_component(
            ComponentDecl::new("err", Feedback)
                .input("u1", "filt.y")
                .input("u2", "rev1.phi"),
        )
        .add_component(ComponentDecl::new("p", Gain { k: 30.0 }).input("u", "err.y"))
        .add_component(
            ComponentDecl::new("werr", Feedback)
                .input("u1", "p.y")
                .input(
                    "u2",
                    Src::expr(&["drive1.motor_w", "rev1.w"], |_, v| {
                        0.01 * v[0] + 0.2 * v[1] * v[1]
                    }),
                ),
        )
        .add_component(ComponentDecl::new("pi", PI::new(2.0, 0.05)).input("u", "werr.y"))
        .add_component(ComponentDecl::new("lim", Limiter::new(-20.0, 20.0)).input("u", "pi.y"))
        .add_component(
            ComponentDecl::new(
                "drive1",
                Drive::rigid("rev1", 100.0, 2e-5)
                    .elastic(2e3, 0.5)
                    .dc_motor(1.2, 2e-3, 0.05),
            )
            .input("v", "lim.y"),
        )
        .add_component(
            ComponentDecl::new(
                "pid2",
                LimPID {
                    k: 4.0,
                    yMax: 0.5,
                    yMin: -0.5,
                    wd: 0.5,
                    ..LimPID::default()
                },
            )
            .input(
                "u_s",
                Src::expr(&["ramp.y", "time"], |t, v| v[0] * (1.0 + t)),
            )
            .input("u_m", "rev2.phi"),
        )
        .add_component(ComponentDecl::new("pid3", PID::default()).input("u", "err.y"))
        .add_component(
            ComponentDecl::new(
                "int",
                Integrator {
                    k: 3.0,
                    y_start: 0.0,
                },
            )
            .input("u", "pid3.y"),
        )
        .add_component(
            ComponentDecl::new("sum", Add3::default())
                .input("u1", "pid2.y")
                .input("u2", "int.y")
                .input("u3", "drive1.tau_load"),
        )
        .add_component(
            ComponentDecl::new("drive2", Drive::rigid("rev2", 20.0, 1e-4))
                .input("tau", Src::expr(&["sum.y"], |_, v| 0.1 * v[0])),
        );
        s
    }

    /// The components' states' columns from their partial derivatives (chain rule through the
    /// signals, `ComponentState::state_columns`) against central differences of the full
    /// residual, at random states with the limits inside and saturated, entry by entry.
    /// Tolerance per column: `1e-6 · max_i |C_ij|` plus 1e-9 absolute: the reference's
    /// truncation at the increment 1e-6·max(|x_j|, 1) of residuals that are at most quadratic
    /// in the states (the expression `0.2·w²` is the only curvature, and the states do not
    /// enter it) is rounding only, ~1e-10 of the column; the expressions' own central
    /// differences inside the chain rule err by ~1e-10; a missing or wrong term is O(1).
    #[test]
    #[allow(clippy::needless_range_loop)] // entry (i, j) of two matrices, by index
    fn component_state_columns_match_central_differences() {
        let model = servo_scene().build().unwrap();
        let mut dae = MultibodyDae::new(model.plan.clone(), model.contact.clone());
        let n = dae.len();
        let xo = dae.plan().x_offset();
        let nx = n - xo;
        assert_eq!(nx, 10, "filt, pi, drive1 (3), pid2 (2), pid3 (2) and int");
        let c_j = 1.7e3;
        let mut saturated = 0;
        for seed in 1..=6u64 {
            let mut rnd = rng(seed);
            let mut y = model.plan.y0();
            y.resize(n, 0.0);
            for v in y.iter_mut() {
                *v = rnd() * if seed % 2 == 0 { 10.0 } else { 0.5 };
            }
            dae.component_event(0.3, &y).unwrap();
            let yp: Vec<f64> = (0..n).map(|_| rnd()).collect();
            let (a, cols) = analytic_columns(&mut dae, &y, &yp, c_j);
            assert!(
                cols[xo..].iter().all(|&c| c),
                "the states' columns are analytic"
            );
            for j in xo..n {
                let r = central_with(&mut dae, (&y, &yp), c_j, j, 1e-6);
                let scale = r.iter().fold(0.0f64, |m, v| m.max(v.abs()));
                for i in 0..n {
                    let err = (a[i][j] - r[i]).abs();
                    assert!(
                        err <= 1e-6 * scale + 1e-9,
                        "seed {seed}: entry ({i}, {j}): analytic {:e}, central {:e}, column scale {scale:e}",
                        a[i][j],
                        r[i]
                    );
                }
            }
            // Some entries reach the joints' rows (the flange forces' derivatives).
            let nq = dae.plan().nq;
            assert!((xo..n).any(|j| a[nq][j] != 0.0) && (xo..n).any(|j| a[nq + 1][j] != 0.0));
            let modes = dae.component_discrete_mut().unwrap_or(&mut []);
            saturated += usize::from(modes.iter().any(|d| d.abs() > 0.5));
        }
        assert!(saturated >= 1, "a limit saturated at some state");
    }

    /// A component without partial derivatives keeps the states' columns quotients.
    #[test]
    fn a_component_without_a_jacobian_keeps_quotients() {
        #[derive(Debug)]
        struct Plain;
        impl crate::scene::Component for Plain {
            fn kind(&self) -> &'static str {
                "Plain"
            }
            fn inputs(&self) -> Vec<crate::scene::PortSpec> {
                vec![]
            }
            fn outputs(&self) -> Vec<crate::scene::OutputSpec> {
                vec![]
            }
            fn states(&self) -> Vec<crate::scene::StateSpec> {
                vec![crate::scene::StateSpec::new("x", "1", 1.0, 1.0)]
            }
            fn outputs_at(&self, _io: &crate::scene::ComponentIo<'_>, _y: &mut [f64]) {}
            fn derivatives(
                &self,
                io: &crate::scene::ComponentIo<'_>,
                xd: &mut [f64],
                _f: &mut [f64],
            ) {
                xd[0] = -io.x[0];
            }
        }
        let mut s = servo_scene();
        s.add_component(crate::scene::ComponentDecl::new("plain", Plain));
        let model = s.build().unwrap();
        let mut dae = MultibodyDae::new(model.plan.clone(), model.contact.clone());
        let mut st = BlockStructure::default();
        assert!(dae.jacobian_structure(&mut st));
        let xo = dae.plan().x_offset();
        assert!(!st.analytic[st.block_of[xo]]);
    }

    /// A source (no states, no inputs) has no partial derivatives to give: one written without
    /// `provides_jacobian` leaves the states' columns analytic.
    #[test]
    fn a_source_needs_no_jacobian() {
        #[derive(Debug)]
        struct Clock;
        impl crate::scene::Component for Clock {
            fn kind(&self) -> &'static str {
                "Clock"
            }
            fn inputs(&self) -> Vec<crate::scene::PortSpec> {
                vec![]
            }
            fn outputs(&self) -> Vec<crate::scene::OutputSpec> {
                vec![crate::scene::OutputSpec::new("y", "s", false)]
            }
            fn outputs_at(&self, io: &crate::scene::ComponentIo<'_>, y: &mut [f64]) {
                y[0] = io.t;
            }
        }
        let mut s = servo_scene();
        s.add_component(crate::scene::ComponentDecl::new("clock", Clock));
        let model = s.build().unwrap();
        let mut dae = MultibodyDae::new(model.plan.clone(), model.contact.clone());
        let mut st = BlockStructure::default();
        assert!(dae.jacobian_structure(&mut st));
        let xo = dae.plan().x_offset();
        assert!(st.analytic[st.block_of[xo]]);
    }

    /// `DaeSystem::quotient_residual` gives the bits of `residual` at every one-coordinate
    /// perturbation of a state with eight contacts, and at perturbations of one coordinate of
    /// every tree at once (a colour), called in a row after one `begin_quotients` as the
    /// Jacobian calls them. A quotient places only the touched bodies (the others restored
    /// from the Jacobian's point: the test fails without the restore), reuses the narrow
    /// phase of pairs of unmoved bodies, and computes the dynamics rows of the trees touched
    /// or coupled to them by a pair in the set (b1–b2) only (the test fails without the
    /// contact couplings). The tip's pair must be recomputed when the rod turns (its body is
    /// the rod's child): the rod's angle changes the tip's rows, so a reuse there would show.
    /// Exact equality: every skipped quantity is a function of inputs the perturbation leaves
    /// as they were, computed by the same operations.
    #[test]
    fn quotient_residuals_match_the_full_residual_bit_for_bit() {
        let model = scene_with_arm().build().unwrap();
        let mut dae = MultibodyDae::new(model.plan.clone(), model.contact.clone());
        let n = dae.len();
        let plan = dae.plan().clone();
        let joint = |name: &str| plan.joints.iter().find(|j| j.name == name).unwrap();
        let (rod, tip) = (joint("rod.rev"), joint("tip.free"));
        for seed in [1, 2] {
            let y = state(&dae, seed, seed == 2);
            dae.handle_event(0.0, &y).unwrap();
            // The six pairs of `scene`, the tip and the egg on the table.
            assert_eq!(dae.contact().unwrap().n_in_contact(), 8, "seed {seed}");
            let mut rnd = rng(seed + 50);
            let yp: Vec<f64> = (0..n).map(|_| rnd()).collect();
            let c_j = 2.5e3;
            let mut base = vec![0.0; n];
            dae.residual(0.0, &y, &yp, &mut base).unwrap();
            let mut sets: Vec<Vec<usize>> = (0..n).map(|j| vec![j]).collect();
            // One coordinate of each joint at a time, as a colour perturbs them together.
            for k in 0..7 {
                let mut set = vec![];
                for j in plan.joints.iter() {
                    if k < j.coord.nq() {
                        set.push(j.q_offset + k);
                    }
                    if k < j.coord.nv() {
                        set.push(plan.nq + j.v_offset + k);
                    }
                }
                sets.push(set);
            }
            let perturbed = |set: &[usize]| {
                let (mut y2, mut yp2) = (y.clone(), yp.clone());
                for &j in set {
                    let inc = 1e-7 * (1.0 + y[j].abs());
                    y2[j] += inc;
                    yp2[j] += c_j * inc;
                }
                (y2, yp2)
            };
            // The full residuals first, then the quotients in a row after one
            // `begin_quotients`, as the Jacobian calls them: each quotient must undo what the
            // one before it perturbed.
            let full: Vec<Vec<f64>> = sets
                .iter()
                .map(|set| {
                    let (y2, yp2) = perturbed(set);
                    let mut r = vec![0.0; n];
                    dae.residual(0.0, &y2, &yp2, &mut r).unwrap();
                    r
                })
                .collect();
            dae.begin_quotients(0.0, &y, &yp).unwrap();
            let mut quot = vec![0.0; n];
            for (set, full) in sets.iter().zip(&full) {
                let (y2, yp2) = perturbed(set);
                dae.quotient_residual(0.0, &y2, &yp2, &mut quot, set)
                    .unwrap();
                for i in 0..n {
                    assert_eq!(
                        full[i].to_bits(),
                        quot[i].to_bits(),
                        "seed {seed}, perturbed {set:?}: row {i}: {:e} vs {:e}",
                        full[i],
                        quot[i]
                    );
                }
                if set == &[rod.q_offset] {
                    let rows = plan.nq + tip.v_offset..plan.nq + tip.v_offset + 6;
                    assert!(
                        rows.clone().any(|i| full[i] != base[i]),
                        "turning the rod changes the tip's rows"
                    );
                }
            }
        }
    }

    /// `yp_jacobian` against difference quotients in `y'` alone: the residual is linear in
    /// `y'` (identity in the position rows, `M(q)` in the velocity rows), so a quotient with an
    /// increment of 1 is exact up to the residual's round-off. Tolerance 1e-9 of the largest
    /// entry of the column plus 1e-9: the residual's terms are O(100) and lose ~1e-13 each.
    #[test]
    fn yp_jacobian_is_the_derivative_in_y_prime() {
        let model = scene_with_arm().build().unwrap();
        let mut dae = MultibodyDae::new(model.plan.clone(), model.contact.clone());
        let n = dae.len();
        for seed in [1, 2] {
            let y = state(&dae, seed, seed == 2);
            dae.handle_event(0.0, &y).unwrap();
            let mut rnd = rng(seed + 70);
            let yp: Vec<f64> = (0..n).map(|_| rnd()).collect();
            assert_yp_jacobian_is_exact(&mut dae, &y, &yp, &format!("seed {seed}"));
        }
    }

    /// The trees whose mass columns `yp_jacobian` forms directly (`free_mass_columns`) are
    /// exactly the root bodies alone on a free joint: every free joint of [`scene_with_arm`]
    /// but the cube's on the rod (whose columns come from the Newton–Euler passes), in both
    /// frames of the velocities (the off-centre ball and the cube keep the child frame). The
    /// entries themselves are checked by `yp_jacobian_is_the_derivative_in_y_prime`.
    #[test]
    fn lone_free_bodies_get_their_mass_columns_directly() {
        let model = scene_with_arm().build().unwrap();
        let dae = MultibodyDae::new(model.plan.clone(), model.contact.clone());
        let plan = &dae.plan;
        let mut direct: Vec<&str> = dae
            .mass
            .lone_free
            .iter()
            .flatten()
            .map(|&j| plan.joints[j].name.as_str())
            .collect();
        let mut free: Vec<&str> = plan
            .joints
            .iter()
            .filter(|j| j.coord.free_velocities().is_some() && j.name != "tip.free")
            .map(|j| j.name.as_str())
            .collect();
        direct.sort_unstable();
        free.sort_unstable();
        assert_eq!(direct, free);
        let frames: Vec<bool> = direct
            .iter()
            .filter_map(|n| plan.joints.iter().find(|j| j.name == *n))
            .map(|j| j.coord.free_velocities() == Some(true))
            .collect();
        assert!(
            frames.contains(&true) && frames.contains(&false),
            "{frames:?}"
        );
    }

    /// Asserts that `dae.yp_jacobian` at (`y`, `yp`) equals the quotients of the residual
    /// in `y'` with increment 1 to `1e-9` of each column's largest change plus 1e-9 (the
    /// residual is linear in `y'`, so only its rounding differs).
    pub(in crate::dae) fn assert_yp_jacobian_is_exact(
        dae: &mut MultibodyDae,
        y: &[f64],
        yp: &[f64],
        what: &str,
    ) {
        let n = dae.len();
        let mut d = vec![0.0; n * n];
        let zero_size = vec![1e-6; n];
        let args = JacobianArgs {
            t: 0.0,
            c_j: 1.0,
            h: 1e-3,
            y,
            yp,
            zero_size: &zero_size,
        };
        let mut sink = |i: usize, j: usize, v: f64| d[j * n + i] += v;
        assert!(dae.yp_jacobian(&args, &mut sink).unwrap());
        let mut base = vec![0.0; n];
        dae.residual(0.0, y, yp, &mut base).unwrap();
        for j in 0..n {
            let mut yp2 = yp.to_vec();
            yp2[j] += 1.0;
            let mut r = vec![0.0; n];
            dae.residual(0.0, y, &yp2, &mut r).unwrap();
            let big = (0..n).map(|i| (r[i] - base[i]).abs()).fold(0.0, f64::max);
            for i in 0..n {
                let q = r[i] - base[i];
                assert!(
                    (q - d[j * n + i]).abs() <= 1e-9 * big + 1e-9,
                    "{what}: entry ({i}, {j}): quotient {q:e}, yp_jacobian {:e}",
                    d[j * n + i]
                );
            }
        }
    }
}
