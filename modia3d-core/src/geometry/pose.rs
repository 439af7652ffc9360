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

#[cfg(test)]
mod tests {
    use super::*;
    use nalgebra::{Quaternion, Translation3, UnitQuaternion};

    /// The shortcut gives nalgebra's own result to the bit for both identity quaternions
    /// (`w = ±1`), and falls through to it for a rotated pose.
    #[test]
    fn shortcut_equals_the_quaternion_to_the_bit() {
        let t = Translation3::new(0.3, -1.7e-3, 12.5);
        let poses = [
            Isometry3::from_parts(t, UnitQuaternion::identity()),
            Isometry3::from_parts(
                t,
                UnitQuaternion::new_unchecked(Quaternion::new(-1.0, 0.0, 0.0, 0.0)),
            ),
            Isometry3::from_parts(t, UnitQuaternion::from_euler_angles(0.1, -0.7, 2.0)),
        ];
        let mut x = 0.123_456_789f64;
        let mut next = || {
            // A deterministic spread of magnitudes and signs (logistic map).
            x = 3.99 * x * (1.0 - x);
            (x - 0.5) * 10f64.powi((x * 12.0) as i32 - 6)
        };
        for pose in &poses {
            for _ in 0..1000 {
                let p = Point3::new(next(), next(), next());
                let v = Vector3::new(next(), next(), next());
                assert_eq!(to_world(pose, &p), pose * p);
                assert_eq!(to_local(pose, &p), pose.inverse_transform_point(&p));
                assert_eq!(rotate(pose, &v), pose.rotation * v);
            }
        }
    }
}
