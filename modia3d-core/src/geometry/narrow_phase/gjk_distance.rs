//! Exact distance of two separated convex cores by GJK (narrow phase of the geometry stage):
//! the refinement step of the improved MPR for separated cores.
//!
//! Why not parry's `gjk::closest_points`: its simplex rejects a new support point closer than
//! √(10 ε) ≈ 5e-8 m (absolute) to the current simplex, and it stops at a relative gap of
//! ≈ 1.5e-7; on curved cores (cylinder rims, cones, ellipsoids) that leaves errors up to ~2e-5
//! of the size. Here the closest point on the simplex is computed by Ericson's Voronoi-region
//! tests (Real-Time Collision Detection §5.1.2, §5.1.5, §5.1.6) with no absolute thresholds, and
//! the loop stops on an absolute gap `upper − lower ≤ tol` between the distance of the current
//! simplex (an upper bound: a point of the Minkowski difference) and the support plane bound
//! `v̂·w` (a lower bound), so the returned distance is certified to `tol`.
//!
//! Near curved features (cylinder rims, cone generators, ellipsoids) GJK builds very thin
//! triangles, on which the Voronoi formulas lose digits by cancellation; without care the loop
//! stalls at certified gaps of ~1e-8 of the size. One step of iterative refinement of the
//! triangle projection removes that (measured: gaps ≤ tol = 1e-11 · size for all kinds). Should
//! the loop still stall, it restarts (at most `MAX_RESTARTS` times) from the best direction
//! found, and returns the iterate with the smallest certified gap.

use crate::geometry::support::CoreShape;
use nalgebra::{Isometry3, Matrix3, Point3, Vector3};

/// Closest points of separated cores.
pub(super) struct Closest {
    /// Distance \[m\] (upper bound, within `tol` of the true distance).
    pub distance: f64,
    /// Unit normal from core a to core b, in a's frame.
    pub normal: Vector3<f64>,
    /// Closest point on core a, in a's frame \[m\].
    pub point_a: Point3<f64>,
    /// Closest point on core b, in a's frame \[m\].
    pub point_b: Point3<f64>,
    /// Certified gap `distance − lower bound` \[m\].
    pub gap: f64,
    /// GJK ran out of iterations before the gap closed to the tolerance.
    pub at_limit: bool,
}

/// A vertex of the simplex in `M = b − a` with its two core points (a's frame).
#[derive(Clone, Copy)]
struct V {
    w: Vector3<f64>,
    a: Vector3<f64>,
    b: Vector3<f64>,
}

/// Simplex of up to 4 vertices; after `reduce` only the vertices that carry the closest point
/// remain, with their barycentric weights.
struct Simplex {
    v: [V; 4],
    lambda: [f64; 4],
    n: usize,
}

/// The closest point of a segment or triangle to the origin: the vertices that carry it (as
/// positions in the segment's or triangle's vertex list, increasing) and their weights.
#[derive(Clone, Copy)]
struct Pick {
    idx: [usize; 3],
    lambda: [f64; 3],
    n: usize,
}

impl Pick {
    fn one(i: usize) -> Pick {
        Pick {
            idx: [i, 0, 0],
            lambda: [1.0, 0.0, 0.0],
            n: 1,
        }
    }
    fn two(i: usize, j: usize, li: f64, lj: f64) -> Pick {
        Pick {
            idx: [i, j, 0],
            lambda: [li, lj, 0.0],
            n: 2,
        }
    }
    /// The point it picks of the vertices `w` (the same sum, in the same order, as
    /// [`Simplex::point`] after keeping them).
    fn point(&self, w: &[Vector3<f64>]) -> Vector3<f64> {
        (0..self.n).map(|k| w[self.idx[k]] * self.lambda[k]).sum()
    }
}

/// Closest point of segment `[a, b]` to the origin.
fn segment_pick(a: &Vector3<f64>, b: &Vector3<f64>) -> Pick {
    let ab = b - a;
    let den = ab.norm_squared();
    let t = if den > 0.0 {
        (-a.dot(&ab) / den).clamp(0.0, 1.0)
    } else {
        0.0
    };
    if t <= 0.0 {
        Pick::one(0)
    } else if t >= 1.0 {
        Pick::one(1)
    } else {
        Pick::two(0, 1, 1.0 - t, t)
    }
}

/// Ericson's ClosestPtPointTriangle with the origin as the query point.
fn triangle_pick(w: &[Vector3<f64>; 3]) -> Pick {
    let [a, b, c] = w;
    let (ab, ac, ap) = (b - a, c - a, -a);
    let (d1, d2) = (ab.dot(&ap), ac.dot(&ap));
    if d1 <= 0.0 && d2 <= 0.0 {
        return Pick::one(0);
    }
    let bp = -b;
    let (d3, d4) = (ab.dot(&bp), ac.dot(&bp));
    if d3 >= 0.0 && d4 <= d3 {
        return Pick::one(1);
    }
    let vc = d1 * d4 - d3 * d2;
    if vc <= 0.0 && d1 >= 0.0 && d3 <= 0.0 {
        let v = d1 / (d1 - d3);
        return Pick::two(0, 1, 1.0 - v, v);
    }
    let cp = -c;
    let (d5, d6) = (ab.dot(&cp), ac.dot(&cp));
    if d6 >= 0.0 && d5 <= d6 {
        return Pick::one(2);
    }
    let vb = d5 * d2 - d1 * d6;
    if vb <= 0.0 && d2 >= 0.0 && d6 <= 0.0 {
        let w = d2 / (d2 - d6);
        return Pick::two(0, 2, 1.0 - w, w);
    }
    let va = d3 * d6 - d5 * d4;
    if va <= 0.0 && (d4 - d3) >= 0.0 && (d5 - d6) >= 0.0 {
        let w = (d4 - d3) / ((d4 - d3) + (d5 - d6));
        return Pick::two(1, 2, 1.0 - w, w);
    }
    let s = va + vb + vc;
    if s.is_nan() || s <= 0.0 {
        // Degenerate (collinear) triangle: the best of its edges.
        let e = segment_pick(a, b);
        let mut f = segment_pick(b, c);
        for k in 0..f.n {
            f.idx[k] += 1;
        }
        return if e.point(w).norm_squared() <= f.point(w).norm_squared() {
            e
        } else {
            f
        };
    }
    let (mut v, mut wk) = (vb / s, vc / s);
    // One step of iterative refinement: the formulas above lose accuracy by cancellation on
    // thin triangles (which GJK produces near curved features); the residual of the
    // orthogonality conditions p·ab = p·ac = 0 is computed accurately and corrected for.
    let (g00, g01, g11) = (ab.dot(&ab), ab.dot(&ac), ac.dot(&ac));
    let det = g00 * g11 - g01 * g01;
    if det > 0.0 {
        let p = a + ab * v + ac * wk;
        let (r0, r1) = (-p.dot(&ab), -p.dot(&ac));
        let dv = (g11 * r0 - g01 * r1) / det;
        let dw = (g00 * r1 - g01 * r0) / det;
        let (v2, w2) = (v + dv, wk + dw);
        if v2 >= 0.0 && w2 >= 0.0 && v2 + w2 <= 1.0 {
            (v, wk) = (v2, w2);
        }
    }
    Pick {
        idx: [0, 1, 2],
        lambda: [1.0 - v - wk, v, wk],
        n: 3,
    }
}

impl Simplex {
    /// Closest point of the simplex to the origin; keeps only the supporting vertices.
    /// Returns `None` when the origin is inside a full tetrahedron.
    fn reduce(&mut self) -> Option<Vector3<f64>> {
        match self.n {
            1 => {
                self.lambda[0] = 1.0;
            }
            2 => {
                let p = segment_pick(&self.v[0].w, &self.v[1].w);
                self.keep([0, 1], &p);
            }
            3 => {
                let p = triangle_pick(&[self.v[0].w, self.v[1].w, self.v[2].w]);
                self.keep([0, 1, 2], &p);
            }
            _ => {
                // Tetrahedron: the origin is outside the faces whose plane separates it from
                // the opposite vertex; the closest point lies on one of those faces.
                let faces = [(0, 1, 2, 3), (0, 1, 3, 2), (0, 2, 3, 1), (1, 2, 3, 0)];
                let mut best: Option<(f64, [usize; 3], Pick)> = None;
                for (i, j, k, l) in faces {
                    let (p, q, r, s) = (self.v[i].w, self.v[j].w, self.v[k].w, self.v[l].w);
                    let nrm = (q - p).cross(&(r - p));
                    let so = nrm.dot(&-p);
                    let ss = nrm.dot(&(s - p));
                    if so * ss >= 0.0 && ss != 0.0 {
                        continue; // origin on the inner side of this face
                    }
                    let w = [p, q, r];
                    let t = triangle_pick(&w);
                    let d = t.point(&w).norm_squared();
                    if best.as_ref().is_none_or(|(bd, _, _)| d < *bd) {
                        best = Some((d, [i, j, k], t));
                    }
                }
                let (_, face, t) = best?;
                self.keep(face, &t);
            }
        }
        Some(self.point())
    }

    fn point(&self) -> Vector3<f64> {
        (0..self.n).map(|i| self.v[i].w * self.lambda[i]).sum()
    }

    /// Keeps the vertices `p` picks of those at `of` (increasing positions in the simplex),
    /// in place: a kept vertex moves to a position at or before its own, so moving them in
    /// order overwrites only vertices already moved or dropped.
    fn keep<const N: usize>(&mut self, of: [usize; N], p: &Pick) {
        for k in 0..p.n {
            let from = of[p.idx[k]];
            self.v[k] = self.v[from];
            self.lambda[k] = p.lambda[k];
        }
        self.n = p.n;
    }
}

/// `pos12` as a rotation matrix and translation (rotating by a matrix is cheaper than by the
/// quaternion, and GJK rotates twice per support point).
struct Frame12 {
    r: Matrix3<f64>,
    t: Vector3<f64>,
}

#[inline]
fn support(f: &Frame12, a: &CoreShape, b: &CoreShape, d: &Vector3<f64>) -> V {
    // Support of M = b − a in direction d, all in a's frame.
    let pa = a.support(&-d).coords;
    let pb = f.r * b.support(&f.r.tr_mul(d)).coords + f.t;
    V {
        w: pb - pa,
        a: pa,
        b: pb,
    }
}

/// Distance of core `a` and core `b` placed at `pos12` in a's frame, started in direction
/// `init` (a → b, a's frame). `None` when the cores touch or overlap (distance below `tol`).
/// Restarts allowed after GJK stalls in floating point.
const MAX_RESTARTS: u32 = 2;

pub(super) fn gjk_distance(
    pos12: &Isometry3<f64>,
    a: &CoreShape,
    b: &CoreShape,
    init: &Vector3<f64>,
    tol: f64,
    max_iterations: u32,
) -> Option<Closest> {
    let f = Frame12 {
        r: *pos12.rotation.to_rotation_matrix().matrix(),
        t: pos12.translation.vector,
    };
    let first = support(&f, a, b, &-init);
    let mut s = Simplex {
        v: [first; 4],
        lambda: [1.0, 0.0, 0.0, 0.0],
        n: 1,
    };
    // The iterate with the smallest certified gap `upper − lower` is returned: near the end on
    // flat-faced cores the simplex gets nearly degenerate and later iterates can lose accuracy
    // in the normal (the gap of a normal error θ on a face of extent L is θ·L).
    let mut best: Option<(f64, Closest)> = None;
    let mut last_upper = f64::INFINITY;
    let mut restarts = 0;
    let mut exhausted = true;
    for _ in 0..max_iterations {
        let v = s.reduce()?;
        let upper = v.norm();
        if upper <= tol {
            return None;
        }
        // Stalled: no decrease of the upper bound, or a support point already in the simplex
        // while the gap is still open (both mean a nearly degenerate simplex in floating point).
        let mut stalled = upper >= last_upper;
        if !stalled {
            last_upper = upper;
            let w = support(&f, a, b, &-v);
            let gap = upper - v.dot(&w.w) / upper;
            if best.as_ref().is_none_or(|(g, _)| gap < *g) {
                let (mut pa, mut pb) = (Vector3::zeros(), Vector3::zeros());
                for i in 0..s.n {
                    pa += s.v[i].a * s.lambda[i];
                    pb += s.v[i].b * s.lambda[i];
                }
                let c = Closest {
                    distance: upper,
                    normal: v / upper,
                    point_a: Point3::from(pa),
                    point_b: Point3::from(pb),
                    gap,
                    at_limit: false,
                };
                best = Some((gap, c));
            }
            if gap <= tol {
                exhausted = false;
                break;
            }
            if (0..s.n).any(|i| s.v[i].w == w.w) {
                stalled = true;
            } else {
                s.v[s.n] = w;
                s.n += 1;
            }
        }
        if stalled {
            // Restart (a few times at most) from the single support point in the direction of
            // the best certified iterate so far.
            let Some((g, c)) = best.as_ref() else {
                exhausted = false;
                break;
            };
            if *g <= tol || restarts == MAX_RESTARTS {
                exhausted = false;
                break;
            }
            restarts += 1;
            let first = support(&f, a, b, &-c.normal);
            s = Simplex {
                v: [first; 4],
                lambda: [1.0, 0.0, 0.0, 0.0],
                n: 1,
            };
            last_upper = f64::INFINITY;
        }
    }
    best.map(|(g, mut c)| {
        c.at_limit = exhausted && g > tol;
        c
    })
}
