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

impl Simplex {
    /// Closest point of the simplex to the origin; keeps only the supporting vertices.
    /// Returns `None` when the origin is inside a full tetrahedron.
    fn reduce(&mut self) -> Option<Vector3<f64>> {
        match self.n {
            1 => {
                self.lambda[0] = 1.0;
            }
            2 => self.segment(0, 1),
            3 => self.triangle(0, 1, 2),
            _ => {
                // Tetrahedron: the origin is outside the faces whose plane separates it from
                // the opposite vertex; the closest point lies on one of those faces.
                let faces = [(0, 1, 2, 3), (0, 1, 3, 2), (0, 2, 3, 1), (1, 2, 3, 0)];
                let mut best: Option<(f64, Simplex)> = None;
                for (i, j, k, l) in faces {
                    let (p, q, r, s) = (self.v[i].w, self.v[j].w, self.v[k].w, self.v[l].w);
                    let nrm = (q - p).cross(&(r - p));
                    let so = nrm.dot(&-p);
                    let ss = nrm.dot(&(s - p));
                    if so * ss >= 0.0 && ss != 0.0 {
                        continue; // origin on the inner side of this face
                    }
                    let mut t = Simplex {
                        v: [self.v[i], self.v[j], self.v[k], self.v[i]],
                        lambda: [0.0; 4],
                        n: 3,
                    };
                    t.triangle(0, 1, 2);
                    let d = t.point().norm_squared();
                    if best.as_ref().is_none_or(|(bd, _)| d < *bd) {
                        best = Some((d, t));
                    }
                }
                let (_, t) = best?;
                *self = t;
            }
        }
        Some(self.point())
    }

    fn point(&self) -> Vector3<f64> {
        (0..self.n).map(|i| self.v[i].w * self.lambda[i]).sum()
    }

    fn keep(&mut self, idx: &[usize], lambda: &[f64]) {
        let v = self.v;
        for (k, (&i, &l)) in idx.iter().zip(lambda).enumerate() {
            self.v[k] = v[i];
            self.lambda[k] = l;
        }
        self.n = idx.len();
    }

    fn segment(&mut self, i: usize, j: usize) {
        let (a, b) = (self.v[i].w, self.v[j].w);
        let ab = b - a;
        let den = ab.norm_squared();
        let t = if den > 0.0 {
            (-a.dot(&ab) / den).clamp(0.0, 1.0)
        } else {
            0.0
        };
        if t <= 0.0 {
            self.keep(&[i], &[1.0]);
        } else if t >= 1.0 {
            self.keep(&[j], &[1.0]);
        } else {
            self.keep(&[i, j], &[1.0 - t, t]);
        }
    }

    /// Ericson's ClosestPtPointTriangle with the origin as the query point.
    fn triangle(&mut self, i: usize, j: usize, k: usize) {
        let (a, b, c) = (self.v[i].w, self.v[j].w, self.v[k].w);
        let (ab, ac, ap) = (b - a, c - a, -a);
        let (d1, d2) = (ab.dot(&ap), ac.dot(&ap));
        if d1 <= 0.0 && d2 <= 0.0 {
            return self.keep(&[i], &[1.0]);
        }
        let bp = -b;
        let (d3, d4) = (ab.dot(&bp), ac.dot(&bp));
        if d3 >= 0.0 && d4 <= d3 {
            return self.keep(&[j], &[1.0]);
        }
        let vc = d1 * d4 - d3 * d2;
        if vc <= 0.0 && d1 >= 0.0 && d3 <= 0.0 {
            let v = d1 / (d1 - d3);
            return self.keep(&[i, j], &[1.0 - v, v]);
        }
        let cp = -c;
        let (d5, d6) = (ab.dot(&cp), ac.dot(&cp));
        if d6 >= 0.0 && d5 <= d6 {
            return self.keep(&[k], &[1.0]);
        }
        let vb = d5 * d2 - d1 * d6;
        if vb <= 0.0 && d2 >= 0.0 && d6 <= 0.0 {
            let w = d2 / (d2 - d6);
            return self.keep(&[i, k], &[1.0 - w, w]);
        }
        let va = d3 * d6 - d5 * d4;
        if va <= 0.0 && (d4 - d3) >= 0.0 && (d5 - d6) >= 0.0 {
            let w = (d4 - d3) / ((d4 - d3) + (d5 - d6));
            return self.keep(&[j, k], &[1.0 - w, w]);
        }
        let s = va + vb + vc;
        if s.is_nan() || s <= 0.0 {
            // Degenerate (collinear) triangle: the best of its edges.
            let mut e = Simplex {
                v: self.v,
                lambda: [0.0; 4],
                n: self.n,
            };
            e.segment(i, j);
            let mut f = Simplex {
                v: self.v,
                lambda: [0.0; 4],
                n: self.n,
            };
            f.segment(j, k);
            *self = if e.point().norm_squared() <= f.point().norm_squared() {
                e
            } else {
                f
            };
            return;
        }
        let (mut v, mut w) = (vb / s, vc / s);
        // One step of iterative refinement: the formulas above lose accuracy by cancellation on
        // thin triangles (which GJK produces near curved features); the residual of the
        // orthogonality conditions p·ab = p·ac = 0 is computed accurately and corrected for.
        let (g00, g01, g11) = (ab.dot(&ab), ab.dot(&ac), ac.dot(&ac));
        let det = g00 * g11 - g01 * g01;
        if det > 0.0 {
            let p = a + ab * v + ac * w;
            let (r0, r1) = (-p.dot(&ab), -p.dot(&ac));
            let dv = (g11 * r0 - g01 * r1) / det;
            let dw = (g00 * r1 - g01 * r0) / det;
            let (v2, w2) = (v + dv, w + dw);
            if v2 >= 0.0 && w2 >= 0.0 && v2 + w2 <= 1.0 {
                (v, w) = (v2, w2);
            }
        }
        self.keep(&[i, j, k], &[1.0 - v - w, v, w]);
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
