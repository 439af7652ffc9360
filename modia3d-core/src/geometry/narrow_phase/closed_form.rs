//! Exact closed forms of the narrow phase (geometry stage): sphere–sphere, sphere–box,
//! sphere–cylinder, sphere–capsule, capsule–capsule, and an ellipsoid on a face of a box. All work on the cores (a point for a
//! sphere, a segment for a capsule, the shrunk box or cylinder) and subtract the margins, so they
//! are exact for the smoothed shapes and smooth in the pose wherever the closest core points are
//! unique.

use super::SignedDistance;
use crate::geometry::collision_shape::CollisionShape;
use crate::geometry::pose::{rotate, to_local, to_world};
use crate::geometry::support::CoreShape;
use nalgebra::{Isometry3, Point3, Vector3};

/// A unit vector perpendicular to `v` (deterministic; `v` need not be unit).
fn any_perpendicular(v: &Vector3<f64>) -> Vector3<f64> {
    let a = v.abs();
    let e = if a.x <= a.y && a.x <= a.z {
        Vector3::x()
    } else if a.y <= a.z {
        Vector3::y()
    } else {
        Vector3::z()
    };
    v.cross(&e).try_normalize(0.0).unwrap_or_else(Vector3::z)
}

/// Build the result from closest core points `ca`, `cb` (world), core distance `d ≥ 0` or
/// penetration `d < 0` along unit normal `n` (a → b), and the margins.
fn assemble(
    ca: Point3<f64>,
    cb: Point3<f64>,
    d: f64,
    n: Vector3<f64>,
    ra: f64,
    rb: f64,
) -> SignedDistance {
    SignedDistance {
        distance: d - ra - rb,
        normal: n,
        point_a: ca + n * ra,
        point_b: cb - n * rb,
    }
}

/// Sphere `a` against sphere `b`. Coinciding centres: normal +z (arbitrary, documented).
pub(super) fn sphere_sphere(
    a: &CollisionShape,
    pose_a: &Isometry3<f64>,
    b: &CollisionShape,
    pose_b: &Isometry3<f64>,
) -> SignedDistance {
    let ca = to_world(pose_a, &a.centre());
    let cb = to_world(pose_b, &b.centre());
    let d = cb - ca;
    let dist = d.norm();
    let n = if dist > 0.0 { d / dist } else { Vector3::z() };
    assemble(ca, cb, dist, n, a.margin(), b.margin())
}

/// Closest point of `core` (box, cylinder-frustum with equal radii, segment or point) to the
/// point `p` (shape frame), with the signed distance (< 0 inside) and the outward unit normal at
/// the closest point (from core towards `p`), all in the shape frame.
fn closest_on_core(core: &CoreShape, p: &Point3<f64>) -> (Point3<f64>, f64, Vector3<f64>) {
    match core {
        CoreShape::Point { centre } => {
            let d = p - centre;
            let dist = d.norm();
            let n = if dist > 0.0 { d / dist } else { Vector3::z() };
            (*centre, dist, n)
        }
        CoreShape::Segment { axis, half_length } => {
            let k = axis.index();
            let mut q = Point3::origin();
            q[k] = p[k].clamp(-half_length, *half_length);
            let d = p - q;
            let dist = d.norm();
            let n = if dist > 0.0 {
                d / dist
            } else {
                any_perpendicular(&axis.unit())
            };
            (q, dist, n)
        }
        CoreShape::Box { half_extents: h } => {
            let q = Point3::from(p.coords.zip_map(h, |x, hi| x.clamp(-hi, hi)));
            let d = p - q;
            let dist = d.norm();
            if dist > 0.0 {
                return (q, dist, d / dist);
            }
            // Inside: the nearest face.
            let gaps = h - p.coords.abs();
            let i = gaps.imin();
            let mut n = Vector3::zeros();
            n[i] = if p[i] >= 0.0 { 1.0 } else { -1.0 };
            let mut q = *p;
            q[i] = n[i] * h[i];
            (q, -gaps[i], n)
        }
        CoreShape::Frustum {
            axis, z0, z1, r0, ..
        } => {
            // Cylinder core (r0 = r1).
            let k = axis.index();
            let mut radial = p.coords;
            radial[k] = 0.0;
            let rho = radial.norm();
            let u = if rho > 0.0 {
                radial / rho
            } else {
                any_perpendicular(&axis.unit())
            };
            let z = p[k];
            let zc = z.clamp(*z0, *z1);
            let rc = rho.min(*r0);
            let mut q = Point3::from(u * rc);
            q[k] = zc;
            let d = p - q;
            let dist = d.norm();
            if dist > 0.0 {
                return (q, dist, d / dist);
            }
            // Inside: nearest of lateral surface, bottom, top.
            let (g_lat, g_bot, g_top) = (r0 - rho, z - z0, z1 - z);
            if g_lat <= g_bot && g_lat <= g_top {
                let mut q = Point3::from(u * *r0);
                q[k] = z;
                (q, -g_lat, u)
            } else {
                let (zf, s, g) = if g_bot <= g_top {
                    (*z0, -1.0, g_bot)
                } else {
                    (*z1, 1.0, g_top)
                };
                let mut q = *p;
                q[k] = zf;
                (q, -g, axis.unit() * s)
            }
        }
        CoreShape::Ellipsoid { .. } | CoreShape::Beam { .. } | CoreShape::Hull { .. } => {
            unreachable!("closed forms are dispatched for point, segment, box and cylinder cores")
        }
    }
}

/// Sphere `a` against a box, cylinder, capsule or sphere `b` (closest point of `b`'s core to
/// the sphere centre). Exact, smooth outside the core's medial axis.
pub(super) fn sphere_core(
    a: &CollisionShape,
    pose_a: &Isometry3<f64>,
    b: &CollisionShape,
    pose_b: &Isometry3<f64>,
) -> SignedDistance {
    let ca = to_world(pose_a, &a.centre());
    let p_local = to_local(pose_b, &ca);
    let (q, dist, n_local) = closest_on_core(b.core(), &p_local);
    // n_local points from b's core to a's centre; the normal a → b is its opposite.
    let n = -rotate(pose_b, &n_local);
    assemble(ca, to_world(pose_b, &q), dist, n, a.margin(), b.margin())
}

/// Capsule `a` against capsule `b`: closest points of the two core segments (Ericson,
/// Real-Time Collision Detection §5.1.9). Intersecting segments: normal along the cross product
/// of their directions (parallel: any perpendicular) — a documented arbitrary choice.
pub(super) fn capsule_capsule(
    a: &CollisionShape,
    pose_a: &Isometry3<f64>,
    b: &CollisionShape,
    pose_b: &Isometry3<f64>,
) -> SignedDistance {
    let seg = |s: &CollisionShape, pose: &Isometry3<f64>| match s.core() {
        CoreShape::Segment { axis, half_length } => {
            let e = pose.rotation * axis.unit() * *half_length;
            let c = pose.translation.vector;
            (Point3::from(c - e), 2.0 * e)
        }
        _ => unreachable!("capsule cores are segments"),
    };
    let (p1, d1) = seg(a, pose_a);
    let (p2, d2) = seg(b, pose_b);
    let r = p1 - p2;
    let (aa, ee, f) = (d1.dot(&d1), d2.dot(&d2), d2.dot(&r));
    let eps = 1e-30;
    let (s, t);
    if aa <= eps && ee <= eps {
        s = 0.0;
        t = 0.0;
    } else if aa <= eps {
        s = 0.0;
        t = (f / ee).clamp(0.0, 1.0);
    } else {
        let c = d1.dot(&r);
        if ee <= eps {
            t = 0.0;
            s = (-c / aa).clamp(0.0, 1.0);
        } else {
            let bb = d1.dot(&d2);
            let den = aa * ee - bb * bb;
            let mut s0 = if den > 1e-14 * aa * ee {
                ((bb * f - c * ee) / den).clamp(0.0, 1.0)
            } else {
                0.5 // parallel: any s; the midpoint keeps the witness central
            };
            let mut t0 = (bb * s0 + f) / ee;
            if t0 < 0.0 {
                t0 = 0.0;
                s0 = (-c / aa).clamp(0.0, 1.0);
            } else if t0 > 1.0 {
                t0 = 1.0;
                s0 = ((bb - c) / aa).clamp(0.0, 1.0);
            }
            s = s0;
            t = t0;
        }
    }
    let ca = p1 + d1 * s;
    let cb = p2 + d2 * t;
    let d = cb - ca;
    let dist = d.norm();
    let n = if dist > 0.0 {
        d / dist
    } else {
        d1.cross(&d2)
            .try_normalize(0.0)
            .unwrap_or_else(|| any_perpendicular(&(d1 + d2 + Vector3::new(0.0, 0.0, 1e-300))))
    };
    assemble(ca, cb, dist, n, a.margin(), b.margin())
}

/// Box `a` against a shape `b` whose core has a unique support point in every direction (an
/// ellipsoid), where the closest (or deepest) points lie on a face of the box: `None` when they
/// do not (an edge or corner of the box is nearest, or the overlap is deeper than half the box
/// along the face normal), and the caller uses MPR.
///
/// For every face normal `m` of the box (outwards, world) the gap of the two support planes
/// `ψ(m) = m·s_B(−m) − (m·c_A + h_m) − r_A − r_B` (`s_B` b's core support point, `h_m` the core
/// box's half extent along `m`, `r` the margins) is a lower bound of the signed distance
/// `δ = max_n ψ(n)`. The face with the largest `ψ` is the answer when `s_B(−m)` projects inside
/// that face of the core box: then `b`'s point and its projection on the face are a pair of
/// points whose difference is normal to both surfaces, the optimality condition of the distance
/// of two convex sets: for separated shapes the global one. For an overlap of depth `D` it is a
/// local minimum of the Minkowski difference's support function `h_M`; it is the global one
/// when `D ≤ ρ`, `ρ` the smallest radius of curvature of b: b then contains the ball of radius
/// `ρ` touching its surface from inside at its deepest point (Blaschke's rolling theorem), whose
/// centre `q` lies `ρ − D` outside the face, so `h_M(n) ≥ h_A(n) − n·q + ρ ≥ −(ρ − D) + ρ = D`
/// for every direction `n`. Or when b's deepest point `p` lies at least `D` inside every other
/// face of the box (the opposite one and the sides): the Minkowski difference contains `A − p`,
/// whose support function is at least the distance of `p` to the box's boundary, `D`. Other
/// overlaps go to MPR. Why: on a table an ellipsoid's MPR/GJK normal jitters by 1e-6–5e-5
/// rad between poses 1e-9 m apart, and IDA's steps collapsed under it (random scenes,
/// BENCHMARKS.md "Random scenes"); here the normal is the face's and the depth is as smooth in
/// the pose as b's support map.
pub(super) fn box_face(
    a: &CollisionShape,
    pose_a: &Isometry3<f64>,
    b: &CollisionShape,
    pose_b: &Isometry3<f64>,
) -> Option<SignedDistance> {
    let CoreShape::Box { half_extents } = a.core() else {
        return None;
    };
    let (ra, rb) = (a.margin(), b.margin());
    // The smallest radius of curvature of b's surface: `s_min²/s_max` of the core ellipsoid,
    // plus the margin.
    let CoreShape::Ellipsoid { semi_axes } = b.core() else {
        return None;
    };
    let rho = semi_axes.min().powi(2) / semi_axes.max() + rb;
    let c_a = pose_a.translation.vector;
    let mut best: Option<(f64, Vector3<f64>, Point3<f64>, usize)> = None;
    for i in 0..3 {
        for sign in [1.0, -1.0] {
            let m = rotate(pose_a, &(Vector3::ith(i, sign)));
            let p = b.core_support_world(pose_b, &-m);
            let psi = m.dot(&(p.coords - c_a)) - half_extents[i] - ra - rb;
            if best.as_ref().is_none_or(|(x, ..)| psi > *x) {
                best = Some((psi, m, p, i));
            }
        }
    }
    let (psi, m, p, i) = best?;
    if !psi.is_finite() {
        return None;
    }
    let local = to_local(pose_a, &p);
    let inside = (0..3)
        .filter(|&j| j != i)
        .all(|j| local[j].abs() <= half_extents[j]);
    if !inside {
        return None;
    }
    // An overlap needs a certificate that no other way out is shorter (a large ellipsoid over
    // a small box has one): b's curvature, or b's deepest point lying deeper below the face
    // than towards any other face of the box.
    let depth = -psi;
    if depth > 0.0 && depth > rho {
        let sides = (0..3)
            .filter(|&j| j != i)
            .map(|j| half_extents[j] + ra - local[j].abs())
            .fold(half_extents[i] + ra, f64::min);
        if depth > sides {
            return None;
        }
    }
    // The witness on a's surface: b's point projected on the (rounded box's) face plane.
    let point_b = p - m * rb;
    let point_a = point_b - m * psi;
    Some(SignedDistance {
        distance: psi,
        normal: m,
        point_a,
        point_b,
    })
}
