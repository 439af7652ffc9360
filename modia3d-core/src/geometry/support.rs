//! Support maps of the *cores* of collision shapes (geometry stage; touches nothing else).
//!
//! A collision shape is `core ⊕ ball(margin)` (Minkowski sum). The cores are the convex sets
//! below, each given in the shape frame of its [`Shape`](super::Shape). The support point
//! `s(d) = argmax_{x ∈ core} d·x` is written in closed form for every core; parry's own shapes
//! are deliberately *not* used at run time because parry's `Cylinder`/`Cone` lie along y and are
//! centred at half height and parry has neither a frustum nor an ellipsoid. The equivalence with
//! parry's shapes (rotated and shifted) is checked in `tests/geometry_support.rs`.
//!
//! [`CoreShape`] also implements parry's [`SupportMap`] so that parry's GJK can run on it (used
//! for the exact distance of separated cores and as fallback, see `narrow_phase`).

use super::shapes::Axis;
use nalgebra::{Point3, Vector3};
use parry3d_f64::shape::SupportMap;

/// The convex core of a collision shape, in the shape frame. All lengths in [m].
#[derive(Clone, Debug, PartialEq)]
pub enum CoreShape {
    /// A single point at `centre` (core of a sphere).
    Point {
        /// Position in the shape frame [m].
        centre: Point3<f64>,
    },
    /// A segment from `-half_length` to `+half_length` along `axis` (core of a capsule).
    Segment {
        /// Direction of the segment.
        axis: Axis,
        /// Half length [m] (0 is allowed: then it is a point).
        half_length: f64,
    },
    /// A box centred at the origin (core of a smoothed box).
    Box {
        /// Half edge lengths along x, y, z [m], each ≥ 0.
        half_extents: Vector3<f64>,
    },
    /// A circular frustum along `axis`: disk of radius `r0` at `axis = z0`, disk of radius `r1`
    /// at `axis = z1 ≥ z0`. Core of cylinders (`r0 = r1`) and cones.
    Frustum {
        /// Axis of the frustum.
        axis: Axis,
        /// Axial position of the first disk [m].
        z0: f64,
        /// Axial position of the second disk [m].
        z1: f64,
        /// Radius of the first disk [m], ≥ 0.
        r0: f64,
        /// Radius of the second disk [m], ≥ 0.
        r1: f64,
    },
    /// An ellipsoid centred at the origin with semi-axes along x, y, z [m].
    Ellipsoid {
        /// Semi-axes (half the full axis lengths) [m], each > 0.
        semi_axes: Vector3<f64>,
    },
    /// The convex hull of `vertices` (each of them is a vertex of the hull) [m].
    Hull {
        /// Vertices of the hull, in the shape frame [m].
        vertices: Vec<Point3<f64>>,
    },
}

/// `+1` for `x ≥ 0`, `-1` otherwise (a deterministic sign for support points: the choice at
/// `x = 0` does not change `d·s(d)`).
#[inline]
fn sgn(x: f64) -> f64 {
    if x >= 0.0 {
        1.0
    } else {
        -1.0
    }
}

impl CoreShape {
    /// Support point in the shape frame: a point of the core maximising `dir·x` [m].
    /// `dir` is resolved in the shape frame and need not be unit; for `dir = 0` some point of the
    /// core is returned.
    #[inline]
    pub fn support(&self, dir: &Vector3<f64>) -> Point3<f64> {
        match self {
            CoreShape::Point { centre } => *centre,
            CoreShape::Segment { axis, half_length } => {
                let mut p = Point3::origin();
                p[axis.index()] = sgn(dir[axis.index()]) * half_length;
                p
            }
            CoreShape::Box { half_extents: h } => {
                Point3::new(sgn(dir.x) * h.x, sgn(dir.y) * h.y, sgn(dir.z) * h.z)
            }
            CoreShape::Frustum {
                axis,
                z0,
                z1,
                r0,
                r1,
            } => {
                let k = axis.index();
                let da = dir[k];
                let mut radial = *dir;
                radial[k] = 0.0;
                let rn = radial.norm();
                // Candidate rim points of both disks; pick the one further along `dir`.
                let (u, rad_dot) = if rn > 0.0 {
                    (radial / rn, rn)
                } else {
                    (Vector3::zeros(), 0.0)
                };
                let h0 = da * z0 + rad_dot * r0;
                let h1 = da * z1 + rad_dot * r1;
                let (z, r) = if h1 >= h0 { (*z1, *r1) } else { (*z0, *r0) };
                let mut p = Point3::from(u * r);
                p[k] = z;
                p
            }
            CoreShape::Ellipsoid { semi_axes: a } => {
                // x = A² d / |A d| with A = diag(a).
                let ad = a.component_mul(dir);
                let n = ad.norm();
                if n > 0.0 {
                    Point3::from(a.component_mul(&ad) / n)
                } else {
                    Point3::new(a.x, 0.0, 0.0)
                }
            }
            CoreShape::Hull { vertices } => {
                let mut best = vertices[0];
                let mut best_h = dir.dot(&best.coords);
                for v in &vertices[1..] {
                    let h = dir.dot(&v.coords);
                    if h > best_h {
                        best_h = h;
                        best = *v;
                    }
                }
                best
            }
        }
    }

    /// A point in the interior (or the relative interior, for points and segments) of the core,
    /// in the shape frame [m]; the start of MPR's centre ray.
    pub fn interior_point(&self) -> Point3<f64> {
        match self {
            CoreShape::Point { centre } => *centre,
            CoreShape::Frustum { axis, z0, z1, .. } => {
                let mut p = Point3::origin();
                p[axis.index()] = 0.5 * (z0 + z1);
                p
            }
            CoreShape::Hull { vertices } => {
                let s: Vector3<f64> = vertices.iter().map(|v| v.coords).sum();
                Point3::from(s / vertices.len() as f64)
            }
            CoreShape::Segment { .. } | CoreShape::Box { .. } | CoreShape::Ellipsoid { .. } => {
                Point3::origin()
            }
        }
    }
}

impl SupportMap for CoreShape {
    #[inline]
    fn local_support_point(&self, dir: &Vector3<f64>) -> Point3<f64> {
        self.support(dir)
    }
}
