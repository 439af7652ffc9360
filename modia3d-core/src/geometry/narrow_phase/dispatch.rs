//! The one dispatch `match` of the narrow phase (geometry stage): closed forms where they exist,
//! the improved MPR for every other pair of kinds.

use super::closed_form::{box_face, capsule_capsule, sphere_core, sphere_sphere};
use super::mpr::mpr_signed_distance;
use super::{Method, NarrowPhaseOptions, SignedDistance};
use crate::geometry::collision_shape::CollisionShape;
use crate::geometry::error::GeometryError;
use crate::geometry::shapes::ShapeKind as K;
use nalgebra::Isometry3;

/// Signed distance, unit normal (a → b, resolved in world) and surface witness points (world,
/// \[m\]) of shape `a` at `pose_a` and shape `b` at `pose_b` (poses: shape frame → world).
///
/// Exact closed forms for sphere–sphere, sphere–box, sphere–cylinder, sphere–capsule,
/// capsule–capsule and an ellipsoid on a face of a box (either order); the improved MPR
/// otherwise, or always with
/// `opts.force_mpr`. Allocation-free except in MPR's degenerate-case fallback (parry's EPA).
pub fn signed_distance(
    a: &CollisionShape,
    pose_a: &Isometry3<f64>,
    b: &CollisionShape,
    pose_b: &Isometry3<f64>,
    opts: &NarrowPhaseOptions,
) -> Result<SignedDistance, GeometryError> {
    signed_distance_method(a, pose_a, b, pose_b, opts).map(|r| r.0)
}

/// [`signed_distance`] and the method that produced it ([`Method::ClosedForm`] for the closed
/// forms; [`Method::IterationLimit`] when MPR or GJK stopped at its iteration limit).
pub fn signed_distance_method(
    a: &CollisionShape,
    pose_a: &Isometry3<f64>,
    b: &CollisionShape,
    pose_b: &Isometry3<f64>,
    opts: &NarrowPhaseOptions,
) -> Result<(SignedDistance, Method), GeometryError> {
    let r = match (a.kind(), b.kind()) {
        _ if opts.force_mpr => return mpr_signed_distance(a, pose_a, b, pose_b, opts),
        (K::Sphere, K::Sphere) => sphere_sphere(a, pose_a, b, pose_b),
        (K::Sphere, K::Box | K::Cylinder | K::Capsule) => sphere_core(a, pose_a, b, pose_b),
        (K::Box | K::Cylinder | K::Capsule, K::Sphere) => {
            sphere_core(b, pose_b, a, pose_a).flipped()
        }
        (K::Capsule, K::Capsule) => capsule_capsule(a, pose_a, b, pose_b),
        // On a face of the box exactly; near its edges and corners MPR.
        (K::Box, K::Ellipsoid) => match box_face(a, pose_a, b, pose_b) {
            Some(r) => r,
            None => return mpr_signed_distance(a, pose_a, b, pose_b, opts),
        },
        (K::Ellipsoid, K::Box) => match box_face(b, pose_b, a, pose_a) {
            Some(r) => r.flipped(),
            None => return mpr_signed_distance(a, pose_a, b, pose_b, opts),
        },
        _ => return mpr_signed_distance(a, pose_a, b, pose_b, opts),
    };
    if r.distance.is_finite() {
        Ok((r, Method::ClosedForm))
    } else {
        Err(GeometryError::NotFinite)
    }
}

/// Whether every query of a pair of these kinds takes a closed form of [`signed_distance`]
/// (exact and smooth in the poses up to rounding). The other pairs go to MPR for some or all
/// poses (the ellipsoid on a box off the box's faces), whose normal jitters by 1e-6–1e-5 rad
/// between poses 1e-9 m apart (`simulation/diagnosis.rs`, `ROUGHNESS_TESTS`): the DAE does
/// not ask their bodies' error test for more than that carries
/// (`ITERATIVE_CONTACT_RTOL_FLOOR` in `dae/mod.rs`).
pub fn exact(a: K, b: K) -> bool {
    matches!(
        (a, b),
        (K::Sphere, K::Sphere | K::Box | K::Cylinder | K::Capsule)
            | (K::Box | K::Cylinder | K::Capsule, K::Sphere)
            | (K::Capsule, K::Capsule)
    )
}
