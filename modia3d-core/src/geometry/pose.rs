//! Applying a pose (shape frame → world) with a shortcut for poses without rotation (geometry
//! stage; touches nothing else).
//!
//! The collision stage places every sphere with the identity rotation (its geometry does not
//! depend on it) and axis-aligned fixed shapes (tables, walls) have it too. Rotating by the
//! identity quaternion costs two cross products and gives the vector back exactly (nalgebra
//! computes `v + w·t + u × t` with `t = 2 u × v = 0`), so skipping it changes no bit of the
//! result.

use nalgebra::{Isometry3, Point3, Vector3};

/// `true` when the pose's rotation is the identity (`±1` quaternion).
#[inline]
fn unrotated(pose: &Isometry3<f64>) -> bool {
    let q = pose.rotation.quaternion();
    q.i == 0.0 && q.j == 0.0 && q.k == 0.0
}

/// `pose · p`: a point of the shape frame in world [m].
#[inline]
pub(crate) fn to_world(pose: &Isometry3<f64>, p: &Point3<f64>) -> Point3<f64> {
    if unrotated(pose) {
        p + pose.translation.vector
    } else {
        pose * p
    }
}

/// `pose⁻¹ · p`: a world point in the shape frame [m].
#[inline]
pub(crate) fn to_local(pose: &Isometry3<f64>, p: &Point3<f64>) -> Point3<f64> {
    if unrotated(pose) {
        p - pose.translation.vector
    } else {
        pose.inverse_transform_point(p)
    }
}

/// `R · v`: a direction of the shape frame in world.
#[inline]
pub(crate) fn rotate(pose: &Isometry3<f64>, v: &Vector3<f64>) -> Vector3<f64> {
    if unrotated(pose) {
        *v
    } else {
        pose.rotation * v
    }
}
