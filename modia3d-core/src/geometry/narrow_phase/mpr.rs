//! The improved Minkowski Portal Refinement (narrow phase of the geometry stage).
//!
//! Snethen's MPR (Game Programming Gems 7, 2008; libccd's layout) on the Minkowski difference
//! `M = core_b ⊖ core_a` (points `b − a`, resolved in world), with the improvements of Neumayr &
//! Otter (2017) used in Modia3D:
//! - no early exit when the origin is found outside `M`: the portal is refined in both cases, so
//!   separated shapes get a distance too;
//! - degenerate cases: coinciding centres (the centre ray is shifted), a support point on the
//!   centre ray (the answer is that point), a flat or collapsed portal (fallback below);
//! - an extra termination test: the new support point coincides with a portal vertex (no more
//!   progress possible, e.g. parallel faces).
//!
//! Result: with `m` the final outward portal normal, `δ_core = −h_M(m) = −m·s_M(m)`. For *every*
//! unit `m` this is a lower bound of the true signed core distance (`dist = max_m −h_M(m)` when
//! separated, `depth = min_m h_M(m)` when penetrating), so MPR never over-estimates `δ`; it is
//! exact when the closest features lie on the centre ray. The witness points come from the
//! barycentric coordinates of the origin's projection on the final portal. The margins are
//! subtracted at the end.
//!
//! Fallback for degenerate portals: parry's GJK/EPA on the same cores (it allocates, but only
//! there). When the cores come out separated and `exact_separation` is set, their distance is
//! made exact by GJK (`gjk_distance.rs`, allocation-free). Then MPR also keeps Snethen's early
//! exit: as soon as a support plane separates the origin from M, GJK takes over from that
//! plane's normal (if GJK stalls above 100·tol, a second GJK from the fully refined portal's
//! normal is tried and the better certificate kept).

use super::curved::{CoreContact, Profile, Supports};
use super::gjk_distance::{gjk_distance, Closest};
use super::{Method, NarrowPhaseOptions, SignedDistance};
use crate::geometry::collision_shape::CollisionShape;
use crate::geometry::error::GeometryError;
use crate::geometry::support::CoreShape;
use nalgebra::{Isometry3, Matrix3, Point3, Unit, Vector3};
use parry3d_f64::query::gjk::{GJKResult, VoronoiSimplex};

/// A support point of `M` with the two core points it came from (all in world \[m\]).
#[derive(Clone, Copy, Debug)]
struct Sv {
    v: Vector3<f64>,
    a: Point3<f64>,
    b: Point3<f64>,
}

/// The pair of cores MPR works on, each possibly inflated by a ball of radius `i*`; poses as
/// rotation matrices (cheaper than quaternions for the two rotations per support point).
struct Pair<'s> {
    a: &'s CoreShape,
    ra: Matrix3<f64>,
    ta: Vector3<f64>,
    ia: f64,
    b: &'s CoreShape,
    rb: Matrix3<f64>,
    tb: Vector3<f64>,
    ib: f64,
}

impl Pair<'_> {
    /// Support point of `M` in world direction `d` (unit or not).
    #[inline]
    fn support(&self, d: &Vector3<f64>) -> Sv {
        let (mut sa, mut sb) = (self.support_a(&-d), self.support_b(d));
        if self.ia > 0.0 || self.ib > 0.0 {
            let u = d.normalize();
            sa -= u * self.ia;
            sb += u * self.ib;
        }
        Sv {
            v: sb - sa,
            a: sa,
            b: sb,
        }
    }

    /// Support point of core A alone (no inflation) in world direction `d` \[m\].
    #[inline]
    fn support_a(&self, d: &Vector3<f64>) -> Point3<f64> {
        Point3::from(self.ra * self.a.support(&self.ra.tr_mul(d)).coords + self.ta)
    }

    /// Support point of core B alone (no inflation) in world direction `d` \[m\].
    #[inline]
    fn support_b(&self, d: &Vector3<f64>) -> Point3<f64> {
        Point3::from(self.rb * self.b.support(&self.rb.tr_mul(d)).coords + self.tb)
    }
}

/// Cores with curved boundary parts (where GJK's and MPR's normals are only as good as the
/// square root of their tolerance; `curved.rs`).
fn curved(c: &CoreShape) -> bool {
    matches!(
        c,
        CoreShape::Ellipsoid { .. } | CoreShape::Frustum { .. } | CoreShape::Beam { .. }
    )
}

/// What the core's support map can do under small turns (`curved.rs` probes only what can
/// change the answer).
fn profile(c: &CoreShape) -> Profile {
    match c {
        CoreShape::Point { .. } => Profile::Point,
        CoreShape::Ellipsoid { .. } => Profile::Smooth,
        CoreShape::Segment { .. }
        | CoreShape::Box { .. }
        | CoreShape::Frustum { .. }
        | CoreShape::Beam { .. }
        | CoreShape::Hull { .. } => Profile::Faceted,
    }
}

/// `r` (the cores' distance, normal a → b and witness points, world), its normal refined by
/// Newton's method where a core is curved (`curved.rs`); `r` itself for polytopes, inflated
/// cores, or where the refinement does not apply.
fn curved_refined(
    pair: &Pair<'_>,
    a: &CollisionShape,
    b: &CollisionShape,
    size: f64,
    r: CoreContact,
) -> CoreContact {
    if !(curved(pair.a) || curved(pair.b)) || pair.ia > 0.0 || pair.ib > 0.0 {
        return r;
    }
    let s = Supports {
        a: |d: &Vector3<f64>| pair.support_a(d),
        b: |d: &Vector3<f64>| pair.support_b(d),
        radius_a: a.bounding_radius(),
        radius_b: b.bounding_radius(),
        profile_a: profile(pair.a),
        profile_b: profile(pair.b),
    };
    s.refine(&r.1, size).unwrap_or(r)
}

fn lower_dimensional(c: &CoreShape) -> bool {
    matches!(c, CoreShape::Point { .. } | CoreShape::Segment { .. })
}

/// Outcome of the core MPR.
enum Portal {
    /// Converged (or stopped) on a portal: outward normal `m`, support value `h = h_M(m)`,
    /// witness core points.
    Done {
        m: Vector3<f64>,
        h: f64,
        a: Point3<f64>,
        b: Point3<f64>,
        /// Refinement stopped at the iteration limit (the tolerance was not met).
        at_limit: bool,
    },
    /// A support plane with outward normal `m` has all of `M` strictly on its inner side, so
    /// the origin is outside: the cores are separated (only with `early_exit`).
    Separated { m: Vector3<f64> },
    /// Degenerate geometry: use the fallback.
    Degenerate,
}

/// Signed distance of `a` at `pose_a` and `b` at `pose_b` by the improved MPR (whatever their
/// kinds), plus which method finally produced it. See the module documentation.
pub fn mpr_signed_distance(
    a: &CollisionShape,
    pose_a: &Isometry3<f64>,
    b: &CollisionShape,
    pose_b: &Isometry3<f64>,
    opts: &NarrowPhaseOptions,
) -> Result<(SignedDistance, Method), GeometryError> {
    // Points and segments have no interior; if both cores are such, M is flat or lower
    // dimensional and has no portal. Then MPR runs on the full sphere/capsule (inflated core).
    let both_thin = lower_dimensional(a.core()) && lower_dimensional(b.core());
    let (ia, ib) = if both_thin {
        (a.margin(), b.margin())
    } else {
        (0.0, 0.0)
    };
    let pair = Pair {
        a: a.core(),
        ra: *pose_a.rotation.to_rotation_matrix().matrix(),
        ta: pose_a.translation.vector,
        ia,
        b: b.core(),
        rb: *pose_b.rotation.to_rotation_matrix().matrix(),
        tb: pose_b.translation.vector,
        ib,
    };
    let size = a.bounding_radius() + b.bounding_radius();
    if !(size.is_finite()
        && pose_a.translation.vector.iter().all(|x| x.is_finite())
        && pose_b.translation.vector.iter().all(|x| x.is_finite()))
    {
        return Err(GeometryError::NotFinite);
    }
    let (mut ra, mut rb) = (a.margin() - ia, b.margin() - ib);
    let tol = opts.mpr_tolerance * size;
    let (ca0, cb0) = (pose_a * a.centre(), pose_b * b.centre());
    // With `exact_separation` the distance of separated cores comes from GJK anyway, so MPR may
    // stop as soon as a support plane separates the origin from M (Snethen's original early
    // exit); GJK then starts from that plane's normal.
    let early = opts.exact_separation && !both_thin;
    let mut portal = mpr_core(&pair, ca0, cb0, size, opts, early);
    if let Portal::Separated { m } = portal {
        let pos12 = pose_a.inv_mul(pose_b);
        let init = pose_a.rotation.inverse_transform_vector(&-m);
        let mut first = gjk_distance(&pos12, a.core(), b.core(), &init, tol, opts.max_iterations);
        if first.as_ref().is_some_and(|c| c.gap > 100.0 * tol) {
            // GJK stalled in floating point (thin simplex near curved rims): a second start
            // from the normal of the fully refined portal often gets further; keep the better.
            if let Portal::Done { m, .. } = mpr_core(&pair, ca0, cb0, size, opts, false) {
                let init2 = pose_a.rotation.inverse_transform_vector(&-m);
                let second =
                    gjk_distance(&pos12, a.core(), b.core(), &init2, tol, opts.max_iterations);
                if let (Some(c1), Some(c2)) = (&first, second) {
                    if c2.gap < c1.gap {
                        first = Some(c2);
                    }
                }
            }
        }
        match first {
            Some(c) => {
                let (dist, n, ca, cb) = gjk_refined(&pair, a, pose_a, b, pose_b, &c, size, tol);
                return finite(
                    SignedDistance {
                        distance: dist - a.margin() - b.margin(),
                        normal: n,
                        point_a: ca + n * a.margin(),
                        point_b: cb - n * b.margin(),
                    },
                    limited(Method::MprThenGjk, c.at_limit),
                );
            }
            // Touching within the tolerance: let MPR run to the end.
            None => portal = mpr_core(&pair, ca0, cb0, size, opts, false),
        }
    }
    let (mut method, m, h, ca, cb) = match portal {
        Portal::Done {
            m,
            h,
            a,
            b,
            at_limit,
        } => (limited(Method::Mpr, at_limit), m, h, a, b),
        Portal::Separated { .. } | Portal::Degenerate => {
            return fallback(a, pose_a, b, pose_b).map(|r| (r, Method::Fallback))
        }
    };
    let mut n = -m;
    let mut delta = -h;
    let (mut ca, mut cb) = (ca, cb);
    // `delta > 0`: the cores are separated (MPR's sign is reliable: at convergence the origin
    // lies beyond the portal exactly when it is outside M). For inflated point/segment cores
    // MPR's sign refers to the full shapes, so GJK on the true cores decides (it is cheap there).
    if (delta > 0.0 || both_thin) && opts.exact_separation {
        let pos12 = pose_a.inv_mul(pose_b);
        let init = pose_a.rotation.inverse_transform_vector(&n);
        if let Some(c) = gjk_distance(&pos12, a.core(), b.core(), &init, tol, opts.max_iterations) {
            (delta, n, ca, cb) = gjk_refined(&pair, a, pose_a, b, pose_b, &c, size, tol);
            (ra, rb) = (a.margin(), b.margin());
            method = limited(Method::MprThenGjk, c.at_limit);
        }
    } else if delta <= 0.0 && !both_thin && method == Method::Mpr {
        // Overlapping cores: MPR's portal normal, refined on curved cores as GJK's is.
        (delta, n, ca, cb) = curved_refined(&pair, a, b, size, (delta, n, ca, cb));
    }
    finite(
        SignedDistance {
            distance: delta - ra - rb,
            normal: n,
            point_a: ca + n * ra,
            point_b: cb - n * rb,
        },
        method,
    )
}

/// GJK's answer `c` for separated cores (resolved in a's frame) in world, made exact on a flat
/// face ([`face_refined`]) or, where no face applies, its normal refined on curved cores
/// ([`curved_refined`]); not after an iteration limit, where the result stays GJK's bounded
/// iterate.
#[allow(clippy::too_many_arguments)]
fn gjk_refined(
    pair: &Pair<'_>,
    a: &CollisionShape,
    pose_a: &Isometry3<f64>,
    b: &CollisionShape,
    pose_b: &Isometry3<f64>,
    c: &Closest,
    size: f64,
    tol: f64,
) -> CoreContact {
    let n = pose_a.rotation * c.normal;
    let (pa, pb) = (pose_a * c.point_a, pose_a * c.point_b);
    let r = face_refined(a, pose_a, b, pose_b, c.distance, n, pa, pb, tol);
    if r.1 == n && !c.at_limit {
        curved_refined(pair, a, b, size, r)
    } else {
        r
    }
}

/// GJK's result for separated cores (core distance `dist` \[m\], unit normal `n` a → b and
/// witness points, world; GJK stops within `tol` \[m\], `mpr_tolerance · size`), made exact
/// where the normal lies within ~1.4e-6 rad of a flat face of either core
/// ([`CoreShape::face_normal_near`]). For separated convex sets the gap of the support planes
/// along any direction is a lower bound of their distance, GJK's distance an upper bound,
/// and the true normal attains the bound: a face whose gap reaches GJK's distance within its
/// tolerance has the true normal up to that tolerance, and where the closest features are a
/// face and a point, edge or face above its interior (a box lying on a table) it is exactly
/// the true normal, with the exact distance and witness points. Of two such faces the one with
/// the larger gap is taken. Why: GJK's normal is up to ~1e-10 rad off, and on a face lying on
/// a face at nanometre penetration the centre of pressure ([`super::contact_patch`]) moves by
/// `l²/(12·δ)` ≈ 1e6 m per radian of normal (a 0.1 m steel cube at rest, δ = 7e-10 m): GJK's
/// normal made the contact point of a resting cube jump by ±0.15 mm from one evaluation to the
/// next, and IDA failed to converge on every other step.
#[allow(clippy::too_many_arguments)]
fn face_refined(
    a: &CollisionShape,
    pose_a: &Isometry3<f64>,
    b: &CollisionShape,
    pose_b: &Isometry3<f64>,
    dist: f64,
    n: Vector3<f64>,
    ca: Point3<f64>,
    cb: Point3<f64>,
    tol: f64,
) -> (f64, Vector3<f64>, Point3<f64>, Point3<f64>) {
    let sup = |s: &CollisionShape, pose: &Isometry3<f64>, d: &Vector3<f64>| {
        pose * s.core().support(&pose.rotation.inverse_transform_vector(d))
    };
    let mut best = (dist, n, ca, cb);
    let mut floor = dist - tol;
    for (on_a, shape, pose, out) in [(true, a, pose_a, n), (false, b, pose_b, -n)] {
        let Some(f) = shape
            .core()
            .face_normal_near(&pose.rotation.inverse_transform_vector(&out))
        else {
            continue;
        };
        let f = pose.rotation * f;
        let nf = if on_a { f } else { -f };
        let (pa, pb) = (sup(a, pose_a, &nf), sup(b, pose_b, &-nf));
        let gap = nf.dot(&(pb - pa));
        if gap >= floor {
            // Witness points: the other shape's support point and its projection onto the face.
            let (wa, wb) = if on_a {
                (pb - nf * gap, pb)
            } else {
                (pa, pa + nf * gap)
            };
            best = (gap, nf, wa, wb);
            floor = gap;
        }
    }
    best
}

/// `m`, or [`Method::IterationLimit`] when the algorithm stopped at its iteration limit.
fn limited(m: Method, at_limit: bool) -> Method {
    if at_limit {
        Method::IterationLimit
    } else {
        m
    }
}

/// The result if it is finite, else `NotFinite`.
fn finite(r: SignedDistance, m: Method) -> Result<(SignedDistance, Method), GeometryError> {
    let ok = r.distance.is_finite()
        && r.normal.iter().all(|x| x.is_finite())
        && r.point_a
            .iter()
            .chain(r.point_b.iter())
            .all(|x| x.is_finite());
    if ok {
        Ok((r, m))
    } else {
        Err(GeometryError::NotFinite)
    }
}

/// MPR on the cores: portal discovery and refinement along the centre ray.
fn mpr_core(
    pair: &Pair<'_>,
    ca: Point3<f64>,
    cb: Point3<f64>,
    size: f64,
    opts: &NarrowPhaseOptions,
    early_exit: bool,
) -> Portal {
    let tol = opts.mpr_tolerance * size;
    let eps = 1e-14 * size; // lengths below this are "zero"
    let eps2 = eps * size; // for cross products (areas)
    let mut v0 = Sv {
        v: cb - ca,
        a: ca,
        b: cb,
    };
    if v0.v.norm() < 1e3 * eps {
        // Coinciding centres: any ray from an interior point works; shift the start a little
        // (it stays inside M, whose inner radius is far larger) so that the ray has a direction.
        v0.v = Vector3::new(1e3 * eps, 0.0, 0.0);
    }
    let point_result = |s: &Sv, m: Vector3<f64>| Portal::Done {
        h: m.dot(&s.v),
        m,
        a: s.a,
        b: s.b,
        at_limit: false,
    };

    // Phase 1: portal discovery.
    let dir = -v0.v.normalize();
    let mut v1 = pair.support(&dir);
    // Strictly separating support plane (see `Portal::Separated`).
    let sep = |d: &Vector3<f64>, s: &Sv| early_exit && d.dot(&s.v) < -eps * d.norm();
    if sep(&dir, &v1) {
        return Portal::Separated { m: dir };
    }
    let n = v1.v.cross(&v0.v);
    if n.norm() <= eps2 {
        // v1 lies on the centre ray: it is the boundary point hit by the ray, and the support
        // plane through it has normal `dir`.
        return point_result(&v1, dir);
    }
    let d2 = n.normalize();
    let mut v2 = pair.support(&d2);
    if sep(&d2, &v2) {
        return Portal::Separated { m: d2 };
    }
    let mut n = (v1.v - v0.v).cross(&(v2.v - v0.v));
    if n.norm() <= eps2 {
        return Portal::Degenerate;
    }
    if n.dot(&v0.v) > 0.0 {
        std::mem::swap(&mut v1, &mut v2);
        n = -n;
    }
    let mut v3 = None;
    for _ in 0..opts.max_iterations {
        let Some(nu) = n.try_normalize(eps2) else {
            return Portal::Degenerate;
        };
        let s = pair.support(&nu);
        if sep(&nu, &s) {
            return Portal::Separated { m: nu };
        }
        if v1.v.cross(&s.v).dot(&v0.v) < 0.0 {
            v2 = s;
            n = (v1.v - v0.v).cross(&(s.v - v0.v));
            continue;
        }
        if s.v.cross(&v2.v).dot(&v0.v) < 0.0 {
            v1 = s;
            n = (s.v - v0.v).cross(&(v2.v - v0.v));
            continue;
        }
        v3 = Some(s);
        break;
    }
    let Some(mut v3) = v3 else {
        return Portal::Degenerate;
    };
    // Phase 2: portal refinement.
    let mut last = None;
    for _ in 0..opts.max_iterations {
        let mut m = (v2.v - v1.v).cross(&(v3.v - v1.v));
        let Some(mu) = m.try_normalize(eps2) else {
            // Collapsed portal: if it shrank to (almost) a point, that point is the answer.
            return match last {
                Some((m, s)) => point_result(&s, m),
                None => Portal::Degenerate,
            };
        };
        m = mu;
        if m.dot(&(v1.v - v0.v)) < 0.0 {
            m = -m;
        }
        let v4 = pair.support(&m);
        if sep(&m, &v4) {
            return Portal::Separated { m };
        }
        last = Some((m, v4));
        let gain = m.dot(&(v4.v - v1.v));
        let stuck = (v4.v - v1.v).norm() <= tol
            || (v4.v - v2.v).norm() <= tol
            || (v4.v - v3.v).norm() <= tol;
        if gain <= tol || stuck {
            return finish(&v1, &v2, &v3, m, m.dot(&v4.v), false);
        }
        // Expand: replace the vertex so that the centre ray still passes the new portal.
        let v4v0 = v4.v.cross(&v0.v);
        if v1.v.dot(&v4v0) > 0.0 {
            if v2.v.dot(&v4v0) > 0.0 {
                v1 = v4;
            } else {
                v3 = v4;
            }
        } else if v3.v.dot(&v4v0) > 0.0 {
            v2 = v4;
        } else {
            v1 = v4;
        }
    }
    // Iteration limit: −h_M(m) is still a lower bound; return it, marked as stopped early.
    match last {
        Some((m, s)) => finish(&v1, &v2, &v3, m, m.dot(&s.v), true),
        None => Portal::Degenerate,
    }
}

/// Result from the final portal: witness points by the barycentric coordinates of the origin's
/// projection onto the portal plane (clamped into the triangle).
fn finish(v1: &Sv, v2: &Sv, v3: &Sv, m: Vector3<f64>, h: f64, at_limit: bool) -> Portal {
    let p = m * m.dot(&v1.v);
    let [l1, l2, l3] = barycentric_clamped(&p, &v1.v, &v2.v, &v3.v);
    Portal::Done {
        m,
        h,
        a: Point3::from(v1.a.coords * l1 + v2.a.coords * l2 + v3.a.coords * l3),
        b: Point3::from(v1.b.coords * l1 + v2.b.coords * l2 + v3.b.coords * l3),
        at_limit,
    }
}

/// Barycentric coordinates of `p` in triangle `(a, b, c)`, negative ones clamped to 0 and the
/// rest renormalised; the centroid for a degenerate triangle.
fn barycentric_clamped(
    p: &Vector3<f64>,
    a: &Vector3<f64>,
    b: &Vector3<f64>,
    c: &Vector3<f64>,
) -> [f64; 3] {
    let (e0, e1, e2) = (b - a, c - a, p - a);
    let (d00, d01, d11) = (e0.dot(&e0), e0.dot(&e1), e1.dot(&e1));
    let (d20, d21) = (e2.dot(&e0), e2.dot(&e1));
    let den = d00 * d11 - d01 * d01;
    if den.is_nan() || den <= 0.0 {
        return [1.0 / 3.0; 3];
    }
    let v = (d11 * d20 - d01 * d21) / den;
    let w = (d00 * d21 - d01 * d20) / den;
    let l = [(1.0 - v - w).max(0.0), v.max(0.0), w.max(0.0)];
    let s = l[0] + l[1] + l[2];
    [l[0] / s, l[1] / s, l[2] / s]
}

/// Parry's GJK/EPA on the cores, margins subtracted afterwards (degenerate MPR cases only).
fn fallback(
    a: &CollisionShape,
    pose_a: &Isometry3<f64>,
    b: &CollisionShape,
    pose_b: &Isometry3<f64>,
) -> Result<SignedDistance, GeometryError> {
    let pos12 = pose_a.inv_mul(pose_b);
    let init = Unit::try_new(
        pose_a
            .rotation
            .inverse_transform_vector(&(pose_b * b.centre() - pose_a * a.centre())),
        1e-300,
    );
    let mut simplex = VoronoiSimplex::new();
    match parry3d_f64::query::details::contact_support_map_support_map_with_params(
        &pos12,
        a.core(),
        b.core(),
        f64::MAX,
        &mut simplex,
        init,
    ) {
        GJKResult::ClosestPoints(p1, p2, n1) => {
            let dist = (p2 - p1).dot(&n1);
            let n = pose_a.rotation * n1.into_inner();
            Ok(SignedDistance {
                distance: dist - a.margin() - b.margin(),
                normal: n,
                point_a: pose_a * p1 + n * a.margin(),
                point_b: pose_a * p2 - n * b.margin(),
            })
        }
        _ => Err(GeometryError::NoConvergence(a.kind(), b.kind())),
    }
}
