//! Overlap of two undeformed solids (geometry stage; touches nothing else): the volume, its
//! centroid, its second-moment tensor and the area vector of the overlap's boundary, what the
//! volume contact law of pairs without a sphere needs (docs/contact-model.md, "Volume law").
//!
//! - [`polytope`]: convex polytopes (boxes, convex hulls, convex parts of meshes) against each
//!   other, by clipping one with the face planes of the other and integrating over the closed
//!   polygon set (divergence theorem);
//! - [`round`]: a cylinder or cone (circular frustum) against a half-space (a flat face of a
//!   polytope), in closed form per cross-section and by Gauss–Legendre quadrature along the
//!   axis.
//!
//! Every query is allocation-free once its [`OverlapScratch`] has grown to the largest shapes it
//! meets (the plan sizes it when it is built).

pub mod polytope;
pub mod round;

/// The fixed-seed random poses of both files' tests.
#[cfg(test)]
mod test_rng {
    use nalgebra::{Isometry3, Quaternion, UnitQuaternion, Vector3};

    /// splitmix64: a fixed-seed generator, uniform in [0, 1).
    pub(super) struct Rng(pub(super) u64);

    impl Rng {
        pub(super) fn next(&mut self) -> f64 {
            self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
            let mut z = self.0;
            z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
            z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
            ((z ^ (z >> 31)) >> 11) as f64 / (1u64 << 53) as f64
        }
        pub(super) fn range(&mut self, lo: f64, hi: f64) -> f64 {
            lo + (hi - lo) * self.next()
        }
        pub(super) fn vec(&mut self, lo: f64, hi: f64) -> Vector3<f64> {
            Vector3::new(self.range(lo, hi), self.range(lo, hi), self.range(lo, hi))
        }
        /// A random rotation (a quaternion drawn in the unit ball, normalised).
        pub(super) fn rotation(&mut self) -> UnitQuaternion<f64> {
            loop {
                let q = Quaternion::new(
                    self.range(-1.0, 1.0),
                    self.range(-1.0, 1.0),
                    self.range(-1.0, 1.0),
                    self.range(-1.0, 1.0),
                );
                if q.norm() > 0.1 && q.norm() < 1.0 {
                    return UnitQuaternion::from_quaternion(q);
                }
            }
        }
        pub(super) fn pose(&mut self, spread: f64) -> Isometry3<f64> {
            Isometry3::from_parts(self.vec(-spread, spread).into(), self.rotation())
        }
        pub(super) fn unit(&mut self) -> Vector3<f64> {
            self.rotation() * Vector3::z()
        }
    }
}

pub use polytope::{polytope_overlap, OverlapScratch, Polytope};
pub use round::{
    frustum_halfspace_overlap, frustum_planes_gap, frustum_planes_overlap, Frustum, PlanesGap,
};

use nalgebra::{Matrix3, Point3, Vector3};

/// The overlap `O = A ∩ B` of two solids `A` and `B` at given poses, all resolved in world.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Overlap {
    /// Volume of `O` \[m³\] (0 when the solids do not overlap).
    pub volume: f64,
    /// Centroid of `O` \[m, world\] (meaningless when `volume == 0`).
    pub centroid: Point3<f64>,
    /// Second moment of `O` about its centroid, `∫_O r rᵀ dV` with `r = x − centroid`
    /// \[m⁵, world\] (symmetric, positive semidefinite; not the inertia tensor).
    pub second_moment: Matrix3<f64>,
    /// Area vector of the part of `A`'s boundary inside `B`: `∫_{∂A ∩ B} n_A dA` \[m², world\]
    /// with `n_A` the outward unit normal of `A`. It equals `−∂V/∂x_B` (the gradient of the
    /// volume with respect to a translation of `B`), so it points from `A` into `B`; its norm
    /// is the overlap's area projected on the plane across it.
    pub area_vector: Vector3<f64>,
}

impl Overlap {
    /// No overlap.
    pub const NONE: Overlap = Overlap {
        volume: 0.0,
        centroid: Point3::new(0.0, 0.0, 0.0),
        second_moment: Matrix3::new(0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0),
        area_vector: Vector3::new(0.0, 0.0, 0.0),
    };
}
