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

/// The convex core of a collision shape, in the shape frame. All lengths in \[m\].
#[derive(Clone, Debug, PartialEq)]
pub enum CoreShape {
    /// A single point at `centre` (core of a sphere).
    Point {
        /// Position in the shape frame \[m\].
        centre: Point3<f64>,
    },
    /// A segment from `-half_length` to `+half_length` along `axis` (core of a capsule).
    Segment {
        /// Direction of the segment.
        axis: Axis,
        /// Half length \[m\] (0 is allowed: then it is a point).
        half_length: f64,
    },
    /// A box centred at the origin (core of a smoothed box).
    Box {
        /// Half edge lengths along x, y, z \[m\], each ≥ 0.
        half_extents: Vector3<f64>,
    },
    /// A circular frustum along `axis`: disk of radius `r0` at `axis = z0`, disk of radius `r1`
    /// at `axis = z1 ≥ z0`. Core of cylinders (`r0 = r1`) and cones.
    Frustum {
        /// Axis of the frustum.
        axis: Axis,
        /// Axial position of the first disk \[m\].
        z0: f64,
        /// Axial position of the second disk \[m\].
        z1: f64,
        /// Radius of the first disk \[m\], ≥ 0.
        r0: f64,
        /// Radius of the second disk \[m\], ≥ 0.
        r1: f64,
    },
    /// Core of a [`Shape::Beam`](super::Shape::Beam): the Minkowski sum of a segment
    /// `±half_length` along `axis`, a segment `±half_thickness` along the beam's thickness
    /// direction and a disk of radius `radius` in the plane of `axis` and the width direction
    /// (see [`Axis::beam_directions`]). A stadium extruded along the thickness.
    Beam {
        /// Longitudinal axis.
        axis: Axis,
        /// Half the length of the straight part \[m\], ≥ 0.
        half_length: f64,
        /// Half the thickness \[m\], ≥ 0.
        half_thickness: f64,
        /// Radius of the ends \[m\], ≥ 0.
        radius: f64,
    },
    /// An ellipsoid centred at the origin with semi-axes along x, y, z \[m\].
    Ellipsoid {
        /// Semi-axes (half the full axis lengths) \[m\], each > 0.
        semi_axes: Vector3<f64>,
    },
    /// The convex hull of `vertices` (each of them is a vertex of the hull) \[m\].
    Hull {
        /// Vertices of the hull, in the shape frame \[m\].
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

/// Ramp weight of a feature point lying `below` \[m\] under the support plane, for a band \[m\]:
/// 1 on the plane, 0 at `band` and deeper (linear in between).
#[inline]
fn ramp(below: f64, band: f64) -> f64 {
    (1.0 - below / band).clamp(0.0, 1.0)
}

/// Weighted centroid of the segment `{-h, +h}` (as a coordinate) in a direction with component
/// `d` (endpoint heights `±h·d`): `(centroid, variance)`.
#[inline]
fn soft_segment(h: f64, d: f64, band: f64) -> (f64, f64) {
    // The continuous segment with density max(0, 1 − height/band), height = |d|·u above the
    // support end (u ∈ [0, 2h] from it): the centre of pressure of a thin elastic layer along
    // the segment, C¹ in `d` (the two-endpoint ramp it replaces had a kink where the upper end
    // lifts off, which Newton's method trips over at nanometre penetrations).
    let l = 2.0 * h;
    let a = d.abs() * l / band;
    let (u_mean, u2_mean) = if a <= 1.0 {
        let m = 1.0 - 0.5 * a;
        (l * (0.5 - a / 3.0) / m, l * l * (1.0 / 3.0 - 0.25 * a) / m)
    } else {
        let e = l / a; // the loaded length
        (e / 3.0, e * e / 6.0)
    };
    let c = (h - u_mean).copysign(d);
    (c, (u2_mean - u_mean * u_mean).max(0.0))
}

/// Centroid of the rim of a disk of radius `r` in a direction whose in-plane part has length
/// `s`, weighted by the ramp of the rim points' depth `r·s·(1 − cos φ)` below the support plane,
/// as a fraction of `r` towards the in-plane direction (0 for a face-on disk, → 1 edge-on).
fn soft_rim_fraction(r: f64, s: f64, band: f64) -> f64 {
    let a = r * s / band;
    if a <= 0.5 {
        // The whole rim carries weight 1 − a(1 − cos φ) > 0.
        a / (2.0 * (1.0 - a))
    } else {
        // Weight zero beyond cos φ0 = 1 − 1/a.
        let phi0 = (1.0 - 1.0 / a).clamp(-1.0, 1.0).acos();
        let (sn, cs) = phi0.sin_cos();
        let num = 2.0 * (1.0 - a) * sn + a * (phi0 + sn * cs);
        let den = 2.0 * (1.0 - a) * phi0 + 2.0 * a * sn;
        if den > 0.0 {
            (num / den).clamp(0.0, 1.0)
        } else {
            1.0
        }
    }
}

/// The point at distance `rad` from the origin in the plane of axes `k`, `kw` in the direction
/// of `dir`'s part in that plane (the origin when that part is zero).
#[inline]
fn disk_point(k: usize, kw: usize, dir: &Vector3<f64>, rad: f64) -> Point3<f64> {
    let rn = dir[k].hypot(dir[kw]);
    let mut p = Point3::origin();
    if rn > 0.0 {
        p[k] = rad * dir[k] / rn;
        p[kw] = rad * dir[kw] / rn;
    }
    p
}

impl CoreShape {
    /// The "soft" support feature in unit direction `dir` (shape frame): the centroid of the
    /// points of the core lying at most `band` \[m\] below the support plane `dir·x = h(dir)`,
    /// each weighted by `1 − depth/band` (the linear pressure law of a thin elastic layer that
    /// penetrates `band` deep), and the feature's spread (weighted variance in the tangent
    /// plane, approximately) \[m²\].
    ///
    /// Unlike [`Self::support`] this is continuous in `dir`: for a box face-on it is the
    /// centre of the face, tilting the box moves it continuously towards the lower edge and
    /// corner, which it reaches when the tilt lifts the other side by `band`. Boxes and
    /// frustums are handled as Minkowski sums of segments (and disks), each part with its own
    /// ramp (a box's segments as continuous ones, so the centroid is C¹ in `dir`); hulls by
    /// their vertices; points and ellipsoids (smooth) return the support point.
    /// `band > 0`. No allocation.
    pub fn soft_support(&self, dir: &Vector3<f64>, band: f64) -> (Point3<f64>, f64) {
        match self {
            CoreShape::Point { .. } | CoreShape::Ellipsoid { .. } => (self.support(dir), 0.0),
            CoreShape::Segment { axis, half_length } => {
                let k = axis.index();
                let (c, var) = soft_segment(*half_length, dir[k], band);
                let mut p = Point3::origin();
                p[k] = c;
                (p, var)
            }
            CoreShape::Box { half_extents: h } => {
                let mut p = Point3::origin();
                let mut var = 0.0;
                for k in 0..3 {
                    let (c, v) = soft_segment(h[k], dir[k], band);
                    p[k] = c;
                    var += v;
                }
                (p, var)
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
                let u = if rn > 0.0 {
                    radial / rn
                } else {
                    Vector3::zeros()
                };
                // The two rims: height of their support points, weight by the ramp.
                let (h0, h1) = (da * z0 + rn * r0, da * z1 + rn * r1);
                let h = h0.max(h1);
                let (w0, w1) = (ramp(h - h0, band), ramp(h - h1, band));
                let (g0, g1) = (
                    soft_rim_fraction(*r0, rn, band),
                    soft_rim_fraction(*r1, rn, band),
                );
                let sum = w0 + w1;
                let z = (w0 * z0 + w1 * z1) / sum;
                let rad = (w0 * r0 * g0 + w1 * r1 * g1) / sum;
                let mut p = Point3::from(u * rad);
                p[k] = z;
                // Axial spread plus the rims' in-plane spread (their radius squared, less the
                // part already in the centroid).
                let var_axial = (w0 * (z0 - z).powi(2) + w1 * (z1 - z).powi(2)) / sum;
                let var_rim = (w0 * r0 * r0 + w1 * r1 * r1) / sum - rad * rad;
                (p, var_axial + var_rim.max(0.0))
            }
            CoreShape::Beam {
                axis,
                half_length,
                half_thickness,
                radius,
            } => {
                // Minkowski sum: the parts' soft centroids add, as for the box.
                let (k, (kw, kt)) = (axis.index(), axis.beam_directions());
                let (cu, vu) = soft_segment(*half_length, dir[k], band);
                let (ct, vt) = soft_segment(*half_thickness, dir[kt], band);
                let rn = dir[k].hypot(dir[kw]);
                let rad = radius * soft_rim_fraction(*radius, rn, band);
                let mut p = disk_point(k, kw, dir, rad);
                p[k] += cu;
                p[kt] = ct;
                (p, vu + vt + (radius * radius - rad * rad).max(0.0))
            }
            CoreShape::Hull { vertices } => {
                let h = vertices
                    .iter()
                    .map(|v| dir.dot(&v.coords))
                    .fold(f64::NEG_INFINITY, f64::max);
                let (mut c, mut sw, mut s2) = (Vector3::zeros(), 0.0, 0.0);
                for v in vertices {
                    let w = ramp(h - dir.dot(&v.coords), band);
                    c += v.coords * w;
                    s2 += v.coords.norm_squared() * w;
                    sw += w;
                }
                let c = c / sw;
                (Point3::from(c), (s2 / sw - c.norm_squared()).max(0.0))
            }
        }
    }

    /// The flat face of the core whose outward normal lies within ~1.4e-6 rad of the unit
    /// direction `dir` (shape frame), as that exact normal; `None` if there is none. Boxes have
    /// six faces, frustums their two caps (of non-zero radius), beams their two flat sides;
    /// points, segments, ellipsoids and hulls report none.
    pub fn face_normal_near(&self, dir: &Vector3<f64>) -> Option<Vector3<f64>> {
        // 1 − cos θ ≤ 1e-12, θ ≤ 1.4e-6 rad.
        const NEAR: f64 = 1e-12;
        let along = |k: usize| -> Option<Vector3<f64>> {
            (1.0 - dir[k].abs() <= NEAR).then(|| {
                let mut f = Vector3::zeros();
                f[k] = sgn(dir[k]);
                f
            })
        };
        match self {
            CoreShape::Box { .. } => (0..3).find_map(along),
            CoreShape::Frustum { axis, r0, r1, .. } => {
                let f = along(axis.index())?;
                let r = if f[axis.index()] > 0.0 { *r1 } else { *r0 };
                (r > 0.0).then_some(f)
            }
            CoreShape::Beam { axis, .. } => along(axis.beam_directions().1),
            CoreShape::Point { .. }
            | CoreShape::Segment { .. }
            | CoreShape::Ellipsoid { .. }
            | CoreShape::Hull { .. } => None,
        }
    }

    /// Support point in the shape frame: a point of the core maximising `dir·x` \[m\].
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
            CoreShape::Beam {
                axis,
                half_length,
                half_thickness,
                radius,
            } => {
                let (k, (kw, kt)) = (axis.index(), axis.beam_directions());
                let mut p = disk_point(k, kw, dir, *radius);
                p[k] += sgn(dir[k]) * half_length;
                p[kt] = sgn(dir[kt]) * half_thickness;
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
    /// in the shape frame \[m\]; the start of MPR's centre ray.
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
            CoreShape::Segment { .. }
            | CoreShape::Box { .. }
            | CoreShape::Beam { .. }
            | CoreShape::Ellipsoid { .. } => Point3::origin(),
        }
    }
}

impl SupportMap for CoreShape {
    #[inline]
    fn local_support_point(&self, dir: &Vector3<f64>) -> Point3<f64> {
        self.support(dir)
    }
}

#[cfg(test)]
mod soft_segment_tests {
    use super::soft_segment;

    /// The centroid of the continuous layer: face-on `0`; small tilt `d·L²/(12·band)` (the
    /// centre of pressure of a linear pressure over the whole segment, from ∫x(δ + d·x)dx over
    /// [−L/2, L/2]); past lift-off a third of the loaded length from the low end; and C¹ at
    /// lift-off (one-sided difference quotients agree to the O(ε) of the quotients).
    #[test]
    fn winkler_centroid_values_and_smoothness() {
        let (h, band) = (0.05, 1e-9);
        let l = 2.0 * h;
        assert_eq!(soft_segment(h, 0.0, band).0, 0.0);
        let d = 1e-12; // a = d·L/band = 1e-4
        let (c, _) = soft_segment(h, d, band);
        let winkler = d * l * l / (12.0 * band);
        assert!((c - winkler).abs() < 1e-3 * winkler, "{c} vs {winkler}");
        assert!((soft_segment(h, -d, band).0 + c).abs() < 1e-15);
        let d = 4.0 * band / l; // a = 4: loaded length L/4
        let (c, _) = soft_segment(h, d, band);
        assert!((c - (h - l / 12.0)).abs() < 1e-12 * h);
        // Lift-off at a = 1, d1 = band/L.
        let d1 = band / l;
        let e = 1e-6 * d1;
        let slope = |x0: f64, x1: f64| {
            (soft_segment(h, x1, band).0 - soft_segment(h, x0, band).0) / (x1 - x0)
        };
        let (left, right) = (slope(d1 - e, d1), slope(d1, d1 + e));
        assert!(
            (left - right).abs() < 1e-4 * left.abs(),
            "{left} vs {right}"
        );
    }
}
