//! Newton refinement of the contact normal of curved cores (narrow phase of the geometry
//! stage), after GJK or MPR stopped at their tolerance.
//!
//! Why: GJK certifies the *distance* of two cores to `tol = mpr_tolerance · size`, but the
//! distance is stationary in the normal, so on curved cores (ellipsoids, cylinder and cone
//! rims and sides, beams) a gap of `tol` leaves the normal off by up to `√(2·tol/ρ)` (ρ a
//! radius of curvature): 1e-6…1e-5 rad for millimetre shapes, and different at poses 1e-12 m
//! apart because GJK's simplex takes a different path. Under a stiff contact that jitter is a
//! tangential force noise that IDA's error test follows down to 1e-12…1e-18 s steps (random
//! scenes, BENCHMARKS.md "Random scenes"). MPR's portal normal has the same defect.
//!
//! What: the signed core distance is `δ = max_n ψ(n)` over unit `n` (a → b), with
//! `ψ(n) = n·w(n)`, `w(n) = s_B(−n) − s_A(n)` (support points; for separated cores ψ is the
//! gap of the two support planes, for overlapping ones minus the depth). On the unit sphere
//! the gradient of ψ is the tangential part of `w` and its Hessian is `−(R + ψ·I)`, with
//! `R = R_A + R_B` the support points' derivatives (radii of curvature, 2×2 in the tangent
//! plane). Newton's step on the sphere is `θ = (R + ψ·I)⁻¹ P·w`, `R` by central differences
//! of the support maps at `H` rad. A few steps take GJK's 1e-5 rad to rounding, and the
//! result is then as smooth in the poses as the shapes are.
//!
//! Flat features: where one core's support point jumps along a direction `e` under a turn of
//! `H` (a segment or a cylinder generator seen side-on, a box edge), the maximum of ψ lies on
//! the kink `n ⊥ e`: `n` is put on that great circle and Newton runs along it; that core's
//! witness point is the other core's support point moved by `−ψ·n` (checked to lie on the
//! feature). Where both cores jump (edge on edge) or one core jumps in two directions (a face,
//! `face_refined`'s case), GJK's answer stays: its simplex resolves polytopes exactly.
//! Every step must not lower ψ (a lower bound of δ for every `n`); otherwise the last good
//! iterate is kept, and with no good step the input is returned unchanged.

use nalgebra::{Matrix2, Point3, Vector2, Vector3};

/// Central-difference step of the support maps \[rad\]: support evaluations are exact to
/// ~1e-16 of the size, so `R` is good to ~1e-10 of the size, and the O(H²) truncation is
/// far below that.
const H: f64 = 1e-6;
/// A support point moving faster than `R_CAP` times the core's bounding radius per radian is a
/// jump over a flat feature, not curvature (the flattest ellipsoid of the fuzzer has a
/// curvature radius of ~1e3 bounding radii).
const R_CAP: f64 = 1e4;
/// Flat features are looked for within this angle of GJK's normal \[rad\] (100 times its
/// error), then within 10 times the last step.
const HD_FIRST: f64 = 1e-3;
/// Newton steps at most (2–3 are needed from GJK's 1e-5 rad).
const MAX_STEPS: usize = 6;
/// A step longer than this \[rad\] is not local: the iterate is not near the answer.
const MAX_TURN: f64 = 0.05;

/// The support maps of the two cores in world (the caller's poses): `a(d)` is core A's support
/// point in direction `d`, `b(d)` core B's; and their bounding radii \[m\].
pub(super) struct Supports<FA, FB> {
    pub a: FA,
    pub b: FB,
    pub radius_a: f64,
    pub radius_b: f64,
    /// What each core's support map can do, so that no support point is evaluated that
    /// cannot change the answer.
    pub profile_a: Profile,
    pub profile_b: Profile,
}

/// What a core's support map can do under small turns of the direction.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(super) enum Profile {
    /// One point (a sphere's or a rounded point's core): constant, no curvature, no jumps.
    Point,
    /// Strictly convex and smooth (an ellipsoid): curvature, never a jump.
    Smooth,
    /// With flat features (segments, frustum generators and caps, beam and box faces):
    /// curvature where curved, jumps over the flat features.
    Faceted,
}

/// A core distance, normal and witness points (world): `(δ, n, p_a, p_b)`.
pub(super) type CoreContact = (f64, Vector3<f64>, Point3<f64>, Point3<f64>);

/// Support points at `n` and how each moves under turns of `n` towards `t1` and `t2`.
struct Local {
    n: Vector3<f64>,
    t: [Vector3<f64>; 2],
    sa: Point3<f64>,
    sb: Point3<f64>,
    psi: f64,
    /// Tangential part of `w` in the basis `t` \[m\] (the gradient of ψ).
    g: Vector2<f64>,
    /// `R = R_A + R_B` in the basis `t` \[m\].
    r: Matrix2<f64>,
    /// The flat feature of A (its support's jump across the probe that found it, world) if
    /// its support jumps.
    jump_a: Option<Vector3<f64>>,
    jump_b: Option<Vector3<f64>>,
    /// The two ends of A's (B's) flat feature.
    ends_a: (Point3<f64>, Point3<f64>),
    ends_b: (Point3<f64>, Point3<f64>),
    /// The jump of A (B) is within `±H` of `n` (else only within `±hd`: the support is smooth
    /// at `n` itself).
    near_a: bool,
    near_b: bool,
    /// A side's support jumps in two directions (a face or a vertex): no refinement.
    face: bool,
}

/// Unit vectors `t1, t2` completing `n` to a right-handed orthonormal basis.
fn tangents(n: &Vector3<f64>) -> [Vector3<f64>; 2] {
    // Frisvad / Duff et al. (2017), "Building an Orthonormal Basis, Revisited".
    let s = if n.z >= 0.0 { 1.0 } else { -1.0 };
    let a = -1.0 / (s + n.z);
    let b = n.x * n.y * a;
    [
        Vector3::new(1.0 + s * n.x * n.x * a, s * b, -s * n.x),
        Vector3::new(b, s + n.y * n.y * a, -n.y),
    ]
}

impl<FA, FB> Supports<FA, FB>
where
    FA: Fn(&Vector3<f64>) -> Point3<f64>,
    FB: Fn(&Vector3<f64>) -> Point3<f64>,
{
    /// Support points at `n`, `R` from differences at `H`, and the flat features within `hd`
    /// \[rad\] of `n` (`hd ≥ H`): a support point that moves more than `R_CAP` bounding radii
    /// per radian over `±H`, or over `±hd` more than twice what `±H` extrapolates to, jumped.
    fn local(&self, n: Vector3<f64>, hd: f64) -> Local {
        let t = tangents(&n);
        let (sa, sb) = ((self.a)(&n), (self.b)(&-n));
        let w = sb - sa;
        let mut r = Matrix2::zeros();
        let (mut jump_a, mut jump_b) = (None, None);
        let (mut near_a, mut near_b) = (false, false);
        let (mut ends_a, mut ends_b) = ((sa, sa), (sb, sb));
        // A side's jump over a flat feature in direction t_j (difference vector and ends).
        let jump = |f: &dyn Fn(&Vector3<f64>) -> Point3<f64>,
                    sign: f64,
                    tj: &Vector3<f64>,
                    radius: f64,
                    (p, m): (Point3<f64>, Point3<f64>)|
         -> Option<(Vector3<f64>, Point3<f64>, Point3<f64>)> {
            let d = p - m;
            if d.norm() > 2.0 * H * R_CAP * radius {
                return Some((d, m, p));
            }
            if hd > H {
                let (big_p, big_m) = (
                    f(&((n + tj * hd).normalize() * sign)),
                    f(&((n - tj * hd).normalize() * sign)),
                );
                let big = big_p - big_m;
                if big.norm() > 2.0 * (hd / H) * d.norm() + 1e-9 * radius {
                    return Some((big, big_m, big_p));
                }
            }
            None
        };
        // Jumps of one side in two directions that are not parallel: a face (or a vertex
        // between faces), `face_refined`'s and GJK's case.
        let mut face = false;
        let mut keep =
            |slot: &mut Option<Vector3<f64>>,
             ends: &mut (Point3<f64>, Point3<f64>),
             (d, m, p): (Vector3<f64>, Point3<f64>, Point3<f64>)| {
                if let Some(v) = *slot {
                    face |= d.cross(&v).norm() > 0.1 * d.norm() * v.norm();
                }
                if slot.is_none_or(|v| d.norm() > v.norm()) {
                    *slot = Some(d);
                    *ends = (m, p);
                }
            };
        for j in 0..2 {
            let (np, nm) = ((n + t[j] * H).normalize(), (n - t[j] * H).normalize());
            // A point's support does not move: no probes.
            let (ap, am) = match self.profile_a {
                Profile::Point => (sa, sa),
                _ => ((self.a)(&np), (self.a)(&nm)),
            };
            let (bp, bm) = match self.profile_b {
                Profile::Point => (sb, sb),
                _ => ((self.b)(&-np), (self.b)(&-nm)),
            };
            let mut dw = Vector3::zeros();
            // A jump within ±H does not enter R; one only within ±hd does (the support is
            // smooth at n, the kink is near). Only faceted cores jump.
            let (da, db) = (ap - am, bp - bm);
            let (mut skip_a, mut skip_b) = (false, false);
            if self.profile_a == Profile::Faceted {
                if let Some(f) = jump(&self.a, 1.0, &t[j], self.radius_a, (ap, am)) {
                    skip_a = f.0 == da;
                    keep(&mut jump_a, &mut ends_a, f);
                }
            }
            if self.profile_b == Profile::Faceted {
                if let Some(f) = jump(&self.b, -1.0, &t[j], self.radius_b, (bp, bm)) {
                    skip_b = f.0 == db;
                    keep(&mut jump_b, &mut ends_b, f);
                }
            }
            near_a |= skip_a;
            near_b |= skip_b;
            if !skip_a {
                dw -= da;
            }
            if !skip_b {
                dw += db;
            }
            // d w / d θ_j = −R t_j.
            for i in 0..2 {
                r[(i, j)] = -t[i].dot(&dw) / (2.0 * H);
            }
            // Both supports jump at `n` (flat on flat: a cylinder lying across another): no
            // step applies and no witness is taken at such an iterate (`refine`,
            // `witnesses`), so the other tangent's probes would change nothing.
            if near_a && near_b {
                break;
            }
        }
        let r = (r + r.transpose()) * 0.5;
        Local {
            n,
            t,
            sa,
            sb,
            psi: n.dot(&w),
            g: Vector2::new(t[0].dot(&w), t[1].dot(&w)),
            r,
            jump_a,
            jump_b,
            ends_a,
            ends_b,
            near_a,
            near_b,
            face,
        }
    }

    /// Refines `(δ, n, p_a, p_b)` (GJK's or MPR's answer for the cores, world, `n` unit a → b)
    /// by Newton's method on ψ (see the module documentation); `None` where it does not apply
    /// or makes no progress (the caller keeps its answer).
    pub(super) fn refine(&self, n0: &Vector3<f64>, size: f64) -> Option<CoreContact> {
        let mut cur = self.local(*n0, HD_FIRST);
        let mut best: Option<CoreContact> = None;
        for _ in 0..MAX_STEPS {
            if cur.face {
                return best;
            }
            // Candidate steps in order: Newton on the smooth ψ where no support jumps within
            // ±H, then (one side with a flat feature nearby) Newton on its kink.
            let near = cur.near_a || cur.near_b;
            let smooth = (!near).then(|| self.smooth_step(&cur, size)).flatten();
            let kink = || match (cur.jump_a, cur.jump_b) {
                (Some(e), None) => self.kink_step(&cur, &e, true, size),
                (None, Some(e)) => self.kink_step(&cur, &e, false, size),
                _ => None,
            };
            let attempt = |step: Vector3<f64>| {
                // NaN steps fail too.
                if step.norm().partial_cmp(&MAX_TURN) != Some(std::cmp::Ordering::Less) {
                    return None;
                }
                let hd = (10.0 * step.norm()).clamp(H, HD_FIRST);
                let next = self.local((cur.n + step).normalize(), hd);
                // A NaN ψ is no progress either.
                if next.psi.is_nan() || next.psi < cur.psi - 1e-14 * size {
                    return None;
                }
                let r = self.witnesses(&next)?;
                Some((step.norm(), next, r))
            };
            let accepted = smooth
                .and_then(attempt)
                .or_else(|| kink().and_then(attempt));
            let Some((len, next, r)) = accepted else {
                return best;
            };
            cur = next;
            best = Some(r);
            if len <= 1e-14 {
                break;
            }
        }
        best
    }

    /// Newton's step on ψ where both supports are smooth at `n` (tangent vector, world).
    fn smooth_step(&self, cur: &Local, size: f64) -> Option<Vector3<f64>> {
        let m = cur.r + Matrix2::identity() * cur.psi;
        // Not a maximum of ψ there (overlap deeper than the curvature radii, or flat on flat
        // touching): Newton does not apply.
        if !(m[(0, 0)] > 0.0 && m.determinant() > 1e-20 * size * size) {
            return None;
        }
        let th = m.try_inverse()? * cur.g;
        Some(cur.t[0] * th.x + cur.t[1] * th.y)
    }

    /// Newton's step on the kink of the flat feature `e` of side A (`on_a`) or B: `n` put on
    /// the plane `n ⊥ e`, then along that great circle (the change of `n`, world).
    fn kink_step(
        &self,
        cur: &Local,
        e: &Vector3<f64>,
        on_a: bool,
        size: f64,
    ) -> Option<Vector3<f64>> {
        let radius = if on_a { self.radius_a } else { self.radius_b };
        // The flat side's support point for normal direction `d` (a → b).
        let side = |d: &Vector3<f64>| {
            if on_a {
                (self.a)(d)
            } else {
                (self.b)(&-d)
            }
        };
        // The feature's exact direction at `n`: the jump of the support across the kink along
        // the estimate (both ends at the same azimuth of a rim, so a cone's generator comes
        // out right too), by the smallest probe that crosses the kink (the estimate may lie up
        // to the jump probe's angle off it).
        let feature = |n: &Vector3<f64>, e: &Vector3<f64>| {
            [H, 1e-5, 1e-4, HD_FIRST].into_iter().find_map(|h| {
                let d = side(&(n + e * h).normalize()) - side(&(n - e * h).normalize());
                (d.norm() > 2.0 * h * R_CAP * radius).then(|| d.normalize())
            })
        };
        // On the kink n ⊥ e (twice: the second direction is exact to ~H).
        let mut e = e.normalize();
        let mut n1 = cur.n;
        for _ in 0..2 {
            n1 = (n1 - e * n1.dot(&e)).normalize();
            e = feature(&n1, &e)?;
        }
        let n1 = (n1 - e * n1.dot(&e)).normalize();
        let u = e.cross(&n1).try_normalize(1e-12)?;
        // ψ's derivative along the circle (u·w; the feature's ends have the same u·p, so which
        // end the support returns does not matter) and its derivative by differences.
        let grad = |th: f64| {
            let nt = (n1 + u * th).normalize();
            let ut = e.cross(&nt).normalize();
            ut.dot(&((self.b)(&-nt) - (self.a)(&nt)))
        };
        let m = -(grad(H) - grad(-H)) / (2.0 * H);
        // A NaN curvature fails too.
        if m.partial_cmp(&(1e-10 * size)) != Some(std::cmp::Ordering::Greater) {
            return None;
        }
        Some(n1 - cur.n + u * (grad(0.0) / m))
    }

    /// Distance, normal and witness points at the iterate: both support points where neither
    /// core's support jumps within ±H; else the other core's support point and its image
    /// `∓ψ·n` on the flat feature (`None` when that image lies off the feature: the kink is not
    /// the answer, or both jump).
    fn witnesses(&self, l: &Local) -> Option<CoreContact> {
        let on = |p: &Point3<f64>, (e0, e1): &(Point3<f64>, Point3<f64>)| {
            let e = e1 - e0;
            let s = (p - e0).dot(&e) / e.norm_squared();
            (-1e-9..=1.0 + 1e-9).contains(&s)
        };
        match (l.near_a, l.near_b) {
            (false, false) => Some((l.psi, l.n, l.sa, l.sb)),
            (true, false) => {
                let pa = l.sb - l.n * l.psi;
                on(&pa, &l.ends_a).then_some((l.psi, l.n, pa, l.sb))
            }
            (false, true) => {
                let pb = l.sa + l.n * l.psi;
                on(&pb, &l.ends_b).then_some((l.psi, l.n, l.sa, pb))
            }
            (true, true) => None,
        }
    }
}
