//! Axis-aligned bounding boxes of collision shapes in world (geometry stage, broad phase input).

use super::collision_shape::CollisionShape;
use super::support::CoreShape;
use nalgebra::{Isometry3, Vector3};
pub use parry3d_f64::bounding_volume::Aabb;

/// The tight world AABB of `shape` at `pose` (shape frame → world), resolved in world \[m\].
///
/// Exact for every shape: the extent along world axis `i` is the support function in `±e_i`
/// (boxes and ellipsoids in closed form, the rest by six support points), plus the margin.
#[inline]
pub fn world_aabb(shape: &CollisionShape, pose: &Isometry3<f64>) -> Aabb {
    let m = shape.margin();
    // The rotation matrix, for the cores that need it (a point needs none).
    let r = || *pose.rotation.to_rotation_matrix().matrix();
    let (c, half) = match shape.core() {
        CoreShape::Point { centre } => (super::pose::to_world(pose, centre), Vector3::zeros()),
        CoreShape::Box { half_extents } => {
            (pose.translation.vector.into(), r().abs() * half_extents)
        }
        CoreShape::Ellipsoid { semi_axes } => {
            // Support function in e_i: |A Rᵀ e_i| = norm of row i of R·A.
            let ra = r() * nalgebra::Matrix3::from_diagonal(semi_axes);
            let half = Vector3::new(ra.row(0).norm(), ra.row(1).norm(), ra.row(2).norm());
            (pose.translation.vector.into(), half)
        }
        CoreShape::Segment { .. }
        | CoreShape::Frustum { .. }
        | CoreShape::Beam { .. }
        | CoreShape::Hull { .. } => {
            let r = r();
            let mut lo = Vector3::zeros();
            let mut hi = Vector3::zeros();
            for i in 0..3 {
                // Local direction of world axis i is row i of R.
                let d: Vector3<f64> = r.row(i).transpose();
                hi[i] = (pose * shape.core().support(&d))[i];
                lo[i] = (pose * shape.core().support(&-d))[i];
            }
            (((hi + lo) * 0.5).into(), (hi - lo) * 0.5)
        }
    };
    let half = half + Vector3::repeat(m);
    Aabb::new(c - half, c + half)
}

/// World AABBs of all `shapes` at their `poses` into `out` (cleared first; no allocation once
/// `out` has the capacity). Panics if the slices differ in length.
pub fn world_aabbs_into(shapes: &[CollisionShape], poses: &[Isometry3<f64>], out: &mut Vec<Aabb>) {
    assert_eq!(shapes.len(), poses.len(), "one pose per shape");
    out.clear();
    out.extend(shapes.iter().zip(poses).map(|(s, p)| world_aabb(s, p)));
}

/// Euclidean distance between two AABBs \[m\]; 0 when they overlap or touch.
#[inline]
pub fn aabb_distance(a: &Aabb, b: &Aabb) -> f64 {
    let gap = (a.mins - b.maxs)
        .sup(&(b.mins - a.maxs))
        .sup(&Vector3::zeros());
    gap.norm()
}

/// `true` when the two AABBs overlap or touch.
#[inline]
pub fn aabbs_overlap(a: &Aabb, b: &Aabb) -> bool {
    a.mins.x <= b.maxs.x
        && b.mins.x <= a.maxs.x
        && a.mins.y <= b.maxs.y
        && b.mins.y <= a.maxs.y
        && a.mins.z <= b.maxs.z
        && b.mins.z <= a.maxs.z
}
