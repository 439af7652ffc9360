//! Collision shapes: a [`Shape`] prepared once for collision queries (geometry stage).
//!
//! `CollisionShape = core ⊕ ball(margin)`: the core's support map (see [`CoreShape`]) plus a
//! margin radius. Spheres are a point swept by their radius and capsules a segment swept by their
//! radius (this is what makes MPR exact for them); boxes, cylinders, cones, beams and convex
//! hulls are shrunk by their smoothing radius and swept by it (see [`super::smoothing`]); ellipsoids have
//! margin 0.

use super::error::GeometryError;
use super::shapes::{Shape, ShapeKind};
use super::smoothing::effective_smoothing_radius;
use super::support::CoreShape;
use nalgebra::{Isometry3, Point3, Vector3};

/// A shape ready for the broad and narrow phase. Built once per solid (allocates for convex
/// hulls only); all queries on it are allocation-free.
#[derive(Clone, Debug, PartialEq)]
pub struct CollisionShape {
    kind: ShapeKind,
    core: CoreShape,
    margin: f64,
    smoothing_radius: f64,
    centre: Point3<f64>,
    local_half_extents: Vector3<f64>,
    local_aabb_centre: Point3<f64>,
    bounding_radius: f64,
}

impl CollisionShape {
    /// Build from `shape` with the default smoothing radius (1 mm, clamped, see
    /// [`effective_smoothing_radius`]).
    pub fn new(shape: &Shape) -> Result<Self, GeometryError> {
        Self::with_smoothing(shape, super::smoothing::DEFAULT_SMOOTHING_RADIUS)
    }

    /// Build from `shape`, asking for the smoothing radius `smoothing_radius` \[m\] (clamped to
    /// 10 % of the smallest dimension; ignored for smooth shapes). Errors for non-finite or
    /// non-positive dimensions and for degenerate convex hulls.
    pub fn with_smoothing(shape: &Shape, smoothing_radius: f64) -> Result<Self, GeometryError> {
        for (name, value) in shape.dimensions() {
            if !(value.is_finite() && value > 0.0) {
                return Err(GeometryError::InvalidDimension { name, value });
            }
        }
        // The lengths that may be 0 (a pointed cone's top); `dimensions` leaves them out.
        for (name, value) in shape.non_negative_lengths() {
            if !(value.is_finite() && value >= 0.0) {
                return Err(GeometryError::InvalidDimension { name, value });
            }
        }
        let r = effective_smoothing_radius(shape, smoothing_radius)?;
        // The kind's core (`geometry/kinds/<kind>.rs`, `core`).
        let (core, margin) = shape.core(r)?;
        let centre = core.interior_point();
        // Local AABB of the core (support along ±axes) grown by the margin.
        let mut lo = Vector3::zeros();
        let mut hi = Vector3::zeros();
        for i in 0..3 {
            let mut e = Vector3::zeros();
            e[i] = 1.0;
            hi[i] = core.support(&e)[i] + margin;
            lo[i] = core.support(&-e)[i] - margin;
        }
        let bounding_radius = match &core {
            CoreShape::Hull { vertices } => vertices
                .iter()
                .map(|v| (v - centre).norm())
                .fold(0.0, f64::max),
            // The farthest point of the core's AABB from the centre bounds all other cores.
            CoreShape::Point { .. }
            | CoreShape::Segment { .. }
            | CoreShape::Box { .. }
            | CoreShape::Frustum { .. }
            | CoreShape::Beam { .. }
            | CoreShape::Ellipsoid { .. } => {
                let d = (hi - centre.coords).abs().sup(&(lo - centre.coords).abs());
                (d - Vector3::repeat(margin)).norm()
            }
        } + margin;
        Ok(CollisionShape {
            kind: shape.kind(),
            core,
            margin,
            smoothing_radius: r,
            centre,
            local_half_extents: 0.5 * (hi - lo),
            local_aabb_centre: Point3::from(0.5 * (hi + lo)),
            bounding_radius,
        })
    }

    /// The kind of the original shape (used by the narrow-phase dispatch).
    pub fn kind(&self) -> ShapeKind {
        self.kind
    }

    /// The core, in the shape frame.
    pub fn core(&self) -> &CoreShape {
        &self.core
    }

    /// Radius of the ball swept over the core \[m\]: the radius of a sphere or capsule, the
    /// smoothing radius of a box, cylinder, cone or convex hull, 0 for an ellipsoid.
    pub fn margin(&self) -> f64 {
        self.margin
    }

    /// The smoothing radius actually used \[m\] (0 for sphere, capsule and ellipsoid).
    pub fn smoothing_radius(&self) -> f64 {
        self.smoothing_radius
    }

    /// An interior point of the core, in the shape frame \[m\] (start of MPR's centre ray).
    pub fn centre(&self) -> Point3<f64> {
        self.centre
    }

    /// Radius of a ball about [`centre`](Self::centre) that contains the whole shape \[m\].
    pub fn bounding_radius(&self) -> f64 {
        self.bounding_radius
    }

    /// Half extents of the shape's AABB in its own frame (margin included) \[m\].
    pub fn local_half_extents(&self) -> Vector3<f64> {
        self.local_half_extents
    }

    /// Centre of the shape's AABB in its own frame \[m\].
    pub fn local_aabb_centre(&self) -> Point3<f64> {
        self.local_aabb_centre
    }

    /// Support point of the core at `pose` in world direction `dir`, resolved in world \[m\].
    #[inline]
    pub fn core_support_world(&self, pose: &Isometry3<f64>, dir: &Vector3<f64>) -> Point3<f64> {
        let local = pose.rotation.inverse_transform_vector(dir);
        pose * self.core.support(&local)
    }

    /// Support point of the whole shape (core plus margin) in the shape frame, for a unit or
    /// non-unit direction `dir` resolved in the shape frame \[m\].
    pub fn support(&self, dir: &Vector3<f64>) -> Point3<f64> {
        let p = self.core.support(dir);
        match dir.try_normalize(0.0) {
            Some(u) => p + u * self.margin,
            None => p,
        }
    }
}
