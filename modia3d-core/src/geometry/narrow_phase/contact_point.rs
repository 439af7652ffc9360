//! The point where a single contact force acts (narrow phase of the geometry stage): continuous
//! and centred on flat contacts, unlike the witness points.
//!
//! Why: for two smoothed shapes penetrating less than the sum of their smoothing radii the cores
//! are separated and the exact distance comes from GJK, whose witness points on two parallel
//! faces are an arbitrary point of the faces' overlap (in practice a corner, and a different
//! corner from one evaluation to the next). A single force acting there makes a box lying flat
//! rock from corner to corner: the residual is discontinuous and the integrator stalls
//! (measured: a 0.2×0.1×0.05 m wooden box dropped flat had its contact point jump between the
//! four corners within 10 µs, and IDA gave up 0.2 ms after the impact).
//!
//! Here each shape's *soft support feature* along the normal is taken (see
//! [`CoreShape::soft_support`]): the centroid of the core points within `band` of the support
//! plane, weighted linearly by their depth, with `band` the penetration depth. This is the
//! centre of pressure of a thin elastic layer (Winkler foundation) evaluated on the feature's
//! vertices/rims: a box lying flat gets the centre of its face (no spurious moment), a tilt
//! moves the point continuously towards the lower side (a restoring moment, rotational stiffness
//! ≈ k·a²/3 for a face of half width a and normal stiffness k, the layer's), and once the tilt lifts the other
//! side by more than the depth it is the lowest edge or corner, as before. The two features are
//! combined by weights that favour the smaller one (a small box on a large table: the box's face
//! centre), and the point is put on the mid-plane between the two witness points. The signed
//! distance and the normal stay the exact ones.

use super::SignedDistance;
use crate::geometry::collision_shape::CollisionShape;
use crate::geometry::shapes::ShapeKind as K;
use nalgebra::{Isometry3, Point3};

/// Point of application [m, world] of the contact force of `a` at `pose_a` and `b` at `pose_b`
/// with narrow-phase result `sd` (of the same call). For pairs with a sphere, and two capsules,
/// it is the midpoint of the witness points (their features are points or exact already); for
/// every other pair see the module documentation. Allocation-free.
pub fn contact_point(
    a: &CollisionShape,
    pose_a: &Isometry3<f64>,
    b: &CollisionShape,
    pose_b: &Isometry3<f64>,
    sd: &SignedDistance,
) -> Point3<f64> {
    contact_patch(a, pose_a, b, pose_b, sd).point
}

/// Where and how a contact force acts: see [`contact_patch`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ContactPatch {
    /// Point of application \[m, world\] ([`contact_point`]).
    pub point: Point3<f64>,
    /// Spread of the pressure around the point: the variance \[m²\] of the combined soft
    /// support feature (the smaller feature's, by the same weights as the point), summed over
    /// the core's axes; 0 for point features.
    pub spread: f64,
}

/// [`contact_point`] with the spread of the pressure around it ([`ContactPatch`]); the contact
/// law (`contact/response.rs`) damps the patch's rocking by `spread`. Pairs with a sphere, and
/// two capsules, are point contacts (spread 0). Allocation-free.
pub fn contact_patch(
    a: &CollisionShape,
    pose_a: &Isometry3<f64>,
    b: &CollisionShape,
    pose_b: &Isometry3<f64>,
    sd: &SignedDistance,
) -> ContactPatch {
    let mid = Point3::from((sd.point_a.coords + sd.point_b.coords) * 0.5);
    let closed_form = matches!(
        (a.kind(), b.kind()),
        (K::Sphere, _) | (_, K::Sphere) | (K::Capsule, K::Capsule)
    );
    if closed_form {
        return ContactPatch {
            point: mid,
            spread: 0.0,
        };
    }
    // Depth of the full (smoothed) shapes; a floor keeps the ramp defined at touch (the force
    // is ~0 there anyway).
    let size = a.bounding_radius() + b.bounding_radius();
    let band = (-sd.distance).max(1e-12 * size);
    let n = sd.normal;
    let (da, db) = (
        pose_a.rotation.inverse_transform_vector(&n),
        pose_b.rotation.inverse_transform_vector(&-n),
    );
    let (ca, va) = a.core().soft_support(&da, band);
    let (cb, vb) = b.core().soft_support(&db, band);
    let (ca, cb) = (pose_a * ca, pose_b * cb);
    // Weights ∝ the other feature's spread⁴: the smaller feature decides (a 0.2 m box on a 2 m
    // table: the table's centroid gets a weight of ~1e-4, so ~1e-5 m of shift).
    let (wa, wb) = (vb * vb, va * va);
    let (p, spread) = if wa + wb > 0.0 {
        (
            Point3::from((ca.coords * wa + cb.coords * wb) / (wa + wb)),
            (va * wa + vb * wb) / (wa + wb),
        )
    } else {
        (Point3::from((ca.coords + cb.coords) * 0.5), 0.0)
    };
    // Onto the mid-plane of the two witness points.
    ContactPatch {
        point: p - n * n.dot(&(p - mid)),
        spread,
    }
}
