//! Contact stage: exact derivatives of one pair's contact wrenches with respect to its bodies'
//! placements and velocities, for the pairs whose narrow phase is a closed form with a point
//! contact: sphere–sphere (both may move) and a sphere against a box or capsule fixed to the
//! world (`geometry/narrow_phase/closed_form.rs`, `sphere_sphere` and `sphere_core`; their
//! contact point is the witness midpoint, `geometry/narrow_phase/contact_point.rs`). The
//! Jacobian (`dae/jacobian.rs`) uses them in place of pair-local difference quotients; every
//! other pair returns `false` and keeps the quotients.
//!
//! Forward mode by hand, chain rule through each stage of what `ContactState::pair_wrenches`
//! computes: every quantity `x` is carried with its tangent `dx` (3 × N or 1 × N) over the
//! tangent directions of the moving bodies, [`PER_BODY`] per body from its offset:
//! `δx` (origin, world, [m]), `δθ` (a rotation of the body frame, resolved in it, [rad]:
//! `R ← R (I + [δθ]×)`), `δω`, `δv` (the body's angular velocity and the velocity of its
//! origin, resolved in world; `dae/jacobian.rs` maps them to the free joint's velocities,
//! which are resolved in obj1). Stages:
//!
//! 1. placement: sphere centre `c = x + R s` (`s` its place in the body): `dc = δx − R [s]× δθ`;
//!    world velocities `ω`, `v` (tangents `δω`, `δv`: they do not turn with the body);
//! 2. geometry: sphere–sphere `n = (c_b − c_a)/|c_b − c_a|`, `dn = (I − n nᵀ)/dist · d(c_b − c_a)`;
//!    sphere–core, with `p` the centre in the core's frame and `m` the core's outward normal
//!    there, `d dist = mᵀ dp` and `dm = N dp` with `N = (I − m mᵀ)/dist` (point core),
//!    `(I − m mᵀ − a aᵀ)/dist` (segment of axis `a`, closest point inside), `(diag(clamped) −
//!    m mᵀ)/dist` (box, outside its core), 0 (box, inside its core: the nearest face's normal);
//!    `δ = max(0, −distance)`, the contact point the witness midpoint `c − m (r_s + dist −
//!    r_c)/2`;
//! 3. force law (`contact/response.rs`, `spread = 0`): point velocities `v_i = v0_i + ω_i ×
//!    (p − x_i)`, `δ̇ = −(v₂ − v₁)·n`, `f_n = k δⁿ · soft_clamp(1 + d δ̇)`, friction
//!    `−μ f_n v_t / reg(|v_t|)`, rolling resistance `−μ_r μ_geo f_n ω_rel / reg(|ω_rel|)`;
//! 4. wrench about each body's origin, resolved in world, `(τ + (p − x) × f, f)` (the free
//!    joint's dynamic rows are resolved in obj1, `dae/jacobian.rs` turns them there).
//!
//! At a kink (δ = 0, the soft clamp's and the regularisations' band ends, a closest point at
//! a core's edge) the derivative is the one-sided one of the branch the evaluation takes.
//! Coincident centres (dist = 0) return `false`. Allocation-free (fixed-size matrices).

use super::contact_set::ContactState;
use super::preprocess::ContactPlan;
use super::regularise::{reg, reg_slope, soft_clamp, soft_clamp_slope};
use crate::dynamics::{BodyId, Workspace};
use crate::geometry::{CoreShape, ShapeKind};
use crate::spatial::Force;
use nalgebra::{Matrix3, SMatrix, Vector3};

/// Tangent directions per moving body: `δx` (3), `δθ` (3), `δω` (3), `δv` (3).
pub(crate) const PER_BODY: usize = 12;

/// Offset of `δθ` within a body's tangent directions.
const TH: usize = 3;
/// Offset of `δω`.
const OM: usize = 6;
/// Offset of `δv`.
const VE: usize = 9;

type T3<const N: usize> = SMatrix<f64, 3, N>;
type T1<const N: usize> = SMatrix<f64, 1, N>;

/// One side of a pair: its body's placement and world velocities with their tangents (all
/// zero for a shape fixed to the world).
struct Side<const N: usize> {
    moving: bool,
    /// Body origin (world) and its tangent.
    x: Vector3<f64>,
    dx: T3<N>,
    /// Body frame → world.
    rot: Matrix3<f64>,
    /// First column of this body's `δθ` (its tangent is the identity there).
    th: usize,
    /// Angular velocity and velocity of the origin (world) and their tangents.
    w: Vector3<f64>,
    dw: T3<N>,
    v0: Vector3<f64>,
    dv0: T3<N>,
}

impl<const N: usize> Side<N> {
    fn new(ws: &Workspace, body: Option<BodyId>, offset: Option<usize>) -> Self {
        let mut s: Side<N> = Side {
            moving: false,
            x: Vector3::zeros(),
            dx: T3::zeros(),
            rot: Matrix3::identity(),
            th: 0,
            w: Vector3::zeros(),
            dw: T3::zeros(),
            v0: Vector3::zeros(),
            dv0: T3::zeros(),
        };
        if let (Some(b), Some(o)) = (body, offset) {
            let (x, vel) = (&ws.world[b], &ws.vel[b]);
            let i3 = Matrix3::identity();
            s.moving = true;
            s.x = x.pos;
            s.rot = x.rot;
            s.dx.fixed_view_mut::<3, 3>(0, o).copy_from(&i3);
            s.th = o + TH;
            s.w = x.rot * vel.w;
            s.v0 = x.rot * vel.v;
            s.dw.fixed_view_mut::<3, 3>(0, o + OM).copy_from(&i3);
            s.dv0.fixed_view_mut::<3, 3>(0, o + VE).copy_from(&i3);
        }
        s
    }

    /// Centre of a sphere placed at `s` in the body (plus its core's `centre`, unrotated, as
    /// `shape_pose` places a round shape) and its tangent.
    fn sphere_centre(&self, s: &Vector3<f64>, centre: &Vector3<f64>) -> (Vector3<f64>, T3<N>) {
        let c = self.x + self.rot * s + centre;
        let mut dc = self.dx;
        if self.moving && *s != Vector3::zeros() {
            self.add_theta(&(-self.rot * s.cross_matrix()), &mut dc);
        }
        (c, dc)
    }

    /// `t += m δθ`: `m` (3 × 3) added to this body's `δθ` columns.
    fn add_theta(&self, m: &Matrix3<f64>, t: &mut T3<N>) {
        let mut block = t.fixed_view_mut::<3, 3>(0, self.th);
        block += m;
    }

    /// Velocity of the material point at `p` (tangent `dp`), world.
    fn point_velocity(&self, p: &Vector3<f64>, dp: &T3<N>) -> (Vector3<f64>, T3<N>) {
        if !self.moving {
            return (Vector3::zeros(), T3::zeros());
        }
        let arm = p - self.x;
        let v = self.v0 + self.w.cross(&arm);
        let dv = self.dv0 - arm.cross_matrix() * self.dw + self.w.cross_matrix() * (dp - self.dx);
        (v, dv)
    }

    /// The wrench of force `f` at `p` and torque `tau` (world, with tangents `dp`, `df`,
    /// `dtau`) about the body's origin, resolved in world, and its tangent (6 × N: `(n, f)`)
    /// into `out`.
    #[allow(clippy::too_many_arguments)]
    #[allow(clippy::too_many_arguments)]
    fn wrench(
        &self,
        p: &Vector3<f64>,
        dp: &T3<N>,
        f: &Vector3<f64>,
        df: &T3<N>,
        tau: &Vector3<f64>,
        dtau: &T3<N>,
        out: &mut SMatrix<f64, 6, N>,
    ) -> Force {
        let arm = p - self.x;
        let dn_world = dtau + arm.cross_matrix() * df - f.cross_matrix() * (dp - self.dx);
        out.fixed_view_mut::<3, N>(0, 0).copy_from(&dn_world);
        out.fixed_view_mut::<3, N>(3, 0).copy_from(df);
        Force {
            n: tau + arm.cross(f),
            f: *f,
        }
    }
}

/// Outward unit normal `m` of `core` at its closest point to `p` (shape frame), the distance
/// (< 0 inside) and `N = ∂m/∂p`, branch for branch as `closed_form.rs`'s `closest_on_core`;
/// `None` for other cores and where the normal is not defined (`p` on a segment or point).
fn core_normal(core: &CoreShape, p: &Vector3<f64>) -> Option<(Vector3<f64>, f64, Matrix3<f64>)> {
    match core {
        CoreShape::Point { centre } => {
            let d = p - centre.coords;
            let dist = d.norm();
            (dist > 0.0).then(|| {
                let m = d / dist;
                (m, dist, (Matrix3::identity() - m * m.transpose()) / dist)
            })
        }
        CoreShape::Segment { axis, half_length } => {
            let k = axis.index();
            let mut d = *p;
            d[k] = p[k] - p[k].clamp(-half_length, *half_length);
            let dist = d.norm();
            (dist > 0.0).then(|| {
                let m = d / dist;
                let mut nm = Matrix3::identity() - m * m.transpose();
                if p[k].abs() <= *half_length {
                    nm[(k, k)] -= 1.0;
                }
                (m, dist, nm / dist)
            })
        }
        CoreShape::Box { half_extents: h } => {
            let d = p - p.zip_map(h, |x, hi| x.clamp(-hi, hi));
            let dist = d.norm();
            if dist > 0.0 {
                let m = d / dist;
                let clamped =
                    Matrix3::from_diagonal(&p.zip_map(
                        h,
                        |x, hi| {
                            if x.abs() <= hi {
                                0.0
                            } else {
                                1.0
                            }
                        },
                    ));
                return Some((m, dist, (clamped - m * m.transpose()) / dist));
            }
            let gaps = h - p.abs();
            let i = gaps.imin();
            let mut m = Vector3::zeros();
            m[i] = if p[i] >= 0.0 { 1.0 } else { -1.0 };
            Some((m, -gaps[i], Matrix3::zeros()))
        }
        _ => None,
    }
}

/// The derivatives of the wrenches (about the body origins, resolved in world, `(n, f)`) of
/// the `k`-th pair in the contact set on the bodies of its shapes a and b, with respect to the
/// tangent directions (module header) of those bodies: body a's from `offset[0]`, body b's
/// from `offset[1]` (`None` for a shape fixed to the world; each needs [`PER_BODY`] columns
/// within `N`). At the workspace's placements and velocities (`position_velocity` done), for
/// the pair's constants and damping factor; the wrenches themselves into `values` (for the
/// moving bodies). `false` (and `out`, `values` undefined) for a pair without a closed form
/// here (see the module header): the caller keeps its quotients.
pub(crate) fn pair_wrench_jacobian<const N: usize>(
    cp: &ContactPlan,
    cs: &ContactState,
    ws: &Workspace,
    k: usize,
    offset: [Option<usize>; 2],
    out: &mut [SMatrix<f64, 6, N>; 2],
    values: &mut [Force; 2],
) -> bool {
    let (pp, ps) = cs.active_pair(k);
    if cp.narrow.force_mpr {
        return false;
    }
    let (sa, sb) = (&cp.shapes[pp.a], &cp.shapes[pp.b]);
    let sides = [
        Side::<N>::new(ws, sa.body, offset[0]),
        Side::<N>::new(ws, sb.body, offset[1]),
    ];
    if sa.body.is_some() != sides[0].moving || sb.body.is_some() != sides[1].moving {
        return false;
    }
    // A sphere's centre: the body's placement, or the fixed pose's.
    let centre = |i: usize| {
        let sp = [sa, sb][i];
        let ctr = sp.shape.centre().coords;
        if sides[i].moving {
            sides[i].sphere_centre(&sp.in_body.pos, &ctr)
        } else {
            (
                cs.pose([pp.a, pp.b][i]) * sp.shape.centre().coords,
                T3::zeros(),
            )
        }
    };
    let (ka, kb) = (sa.shape.kind(), sb.shape.kind());
    let (ra, rb) = (sa.shape.margin(), sb.shape.margin());
    // Normal a → b, distance (signed), contact point, with tangents.
    let (n, dn, distance, ddist, p, dp);
    match (ka, kb) {
        (ShapeKind::Sphere, ShapeKind::Sphere) => {
            if !(sa.round && sb.round) {
                return false;
            }
            let ((ca, dca), (cb, dcb)) = (centre(0), centre(1));
            let d = cb - ca;
            let dd = dcb - dca;
            let dist = d.norm();
            if dist <= 0.0 {
                return false;
            }
            n = d / dist;
            dn = (Matrix3::identity() - n * n.transpose()) / dist * dd;
            ddist = n.transpose() * dd;
            distance = dist - ra - rb;
            p = (ca + n * ra + cb - n * rb) * 0.5;
            dp = (dca + dcb) * 0.5 + dn * (0.5 * (ra - rb));
        }
        (ShapeKind::Sphere, ShapeKind::Box | ShapeKind::Capsule)
        | (ShapeKind::Box | ShapeKind::Capsule, ShapeKind::Sphere) => {
            // The sphere is side `i`, the core side `j`, fixed to the world.
            let (i, j, sign) = if ka == ShapeKind::Sphere {
                (0, 1, -1.0)
            } else {
                (1, 0, 1.0)
            };
            let (ss, sc) = ([sa, sb][i], [sa, sb][j]);
            if sides[j].moving || !ss.round {
                return false;
            }
            let (c, dc) = centre(i);
            let pose = cs.pose([pp.a, pp.b][j]);
            let r = pose.rotation.to_rotation_matrix().into_inner();
            let local = r.transpose() * (c - pose.translation.vector);
            let Some((m_local, dist, nm)) = core_normal(sc.shape.core(), &local) else {
                return false;
            };
            let m = r * m_local;
            let dm = r * nm * r.transpose() * dc;
            let (rs, rc) = (ss.shape.margin(), sc.shape.margin());
            n = m * sign;
            dn = dm * sign;
            ddist = m.transpose() * dc;
            distance = dist - rs - rc;
            let lever = 0.5 * (rs + dist - rc);
            p = c - m * lever;
            dp = dc - dm * lever - m * ddist * 0.5;
        }
        _ => return false,
    }

    // Force law (contact/response.rs, spread 0).
    let delta = (-distance).max(0.0);
    let ddelta: T1<N> = if -distance > 0.0 { -ddist } else { T1::zeros() };
    let ((v1, dv1), (v2, dv2)) = (
        sides[0].point_velocity(&p, &dp),
        sides[1].point_velocity(&p, &dp),
    );
    let v_rel = v2 - v1;
    let dv_rel = dv2 - dv1;
    let vn = v_rel.dot(&n);
    let dvn = n.transpose() * dv_rel + v_rel.transpose() * dn;
    let v_t = v_rel - n * vn;
    let dv_t = dv_rel - dn * vn - n * dvn;
    let w_rel = sides[1].w - sides[0].w;
    let dw_rel = sides[1].dw - sides[0].dw;
    let (delta_pow, slope_pow) = if pp.n_geo == 1.5 {
        let s = delta.sqrt();
        (delta * s, 1.5 * s)
    } else if pp.n_geo == 1.0 {
        (delta, 1.0)
    } else if delta > 0.0 {
        (delta.powf(pp.n_geo), pp.n_geo * delta.powf(pp.n_geo - 1.0))
    } else {
        (0.0, 0.0)
    };
    let kk = cp.k_red * pp.c_res * pp.c_geo;
    let f_el = kk * delta_pow;
    let df_el = ddelta * (kk * slope_pow);
    let x = 1.0 - ps.d * vn;
    let clamp = soft_clamp(x);
    let f_n = f_el * clamp;
    let df_n = df_el * clamp - dvn * (f_el * soft_clamp_slope(x) * ps.d);
    // `−μ f_n u / reg(|u|)` and its tangent.
    let regularised = |mu: f64, u: &Vector3<f64>, du: &T3<N>, u_min: f64| {
        let a = u.norm();
        let g = reg(a, u_min);
        let coef = -mu * f_n / g;
        let da: T1<N> = if a > 0.0 {
            u.transpose() * du / a
        } else {
            T1::zeros()
        };
        let dcoef = (df_n / g - da * (f_n * reg_slope(a, u_min) / (g * g))) * -mu;
        (u * coef, u * dcoef + du * coef)
    };
    let (fr, dfr) = if pp.mu_k > 0.0 {
        regularised(pp.mu_k, &v_t, &dv_t, pp.v_slip)
    } else {
        (Vector3::zeros(), T3::zeros())
    };
    let (tau, dtau) = if pp.mu_r > 0.0 {
        regularised(pp.mu_r * pp.mu_geo, &w_rel, &dw_rel, pp.w_min)
    } else {
        (Vector3::zeros(), T3::zeros())
    };
    let f = n * f_n + fr;
    let df = dn * f_n + n * df_n + dfr;
    // Body b receives (f, τ), body a the opposite.
    if sides[1].moving {
        values[1] = sides[1].wrench(&p, &dp, &f, &df, &tau, &dtau, &mut out[1]);
    }
    if sides[0].moving {
        values[0] = sides[0].wrench(&p, &dp, &-f, &-df, &-tau, &-dtau, &mut out[0]);
    }
    true
}
