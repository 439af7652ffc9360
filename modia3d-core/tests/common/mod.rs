//! Shared helpers of the geometry tests: a small deterministic RNG, random shapes and poses, and
//! the equivalent parry shapes used as oracle.
#![allow(dead_code)]

use modia3d_core::geometry::{Axis, CollisionShape, CoreShape, Shape, ShapeKind};
use nalgebra::{Isometry3, Point3, Translation3, UnitQuaternion, Vector3};
use parry3d_f64::shape::{
    Ball, Capsule, Cone, ConvexPolyhedron, Cuboid, Cylinder, RoundShape, SharedShape,
};

/// SplitMix64: deterministic, dependency-free.
pub struct Rng(pub u64);

impl Rng {
    pub fn next_u64(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^ (z >> 31)
    }
    /// Uniform in [0, 1).
    pub fn f(&mut self) -> f64 {
        (self.next_u64() >> 11) as f64 / (1u64 << 53) as f64
    }
    pub fn range(&mut self, lo: f64, hi: f64) -> f64 {
        lo + (hi - lo) * self.f()
    }
    pub fn unit_vector(&mut self) -> Vector3<f64> {
        loop {
            let v = Vector3::new(
                self.range(-1.0, 1.0),
                self.range(-1.0, 1.0),
                self.range(-1.0, 1.0),
            );
            let n = v.norm();
            if n > 0.1 && n <= 1.0 {
                return v / n;
            }
        }
    }
    pub fn rotation(&mut self) -> UnitQuaternion<f64> {
        let axis = nalgebra::Unit::new_normalize(self.unit_vector());
        UnitQuaternion::from_axis_angle(&axis, self.range(0.0, std::f64::consts::PI))
    }
    pub fn axis(&mut self) -> Axis {
        match self.next_u64() % 3 {
            0 => Axis::X,
            1 => Axis::Y,
            _ => Axis::Z,
        }
    }
}

pub const KINDS: [ShapeKind; 7] = [
    ShapeKind::Sphere,
    ShapeKind::Box,
    ShapeKind::Cylinder,
    ShapeKind::Capsule,
    ShapeKind::Cone,
    ShapeKind::Ellipsoid,
    ShapeKind::ConvexHull,
];

/// A random shape of the given kind, dimensions in [0.2, 1] m (cones pointed, so that parry's
/// `Cone` is an equivalent).
pub fn random_shape(rng: &mut Rng, kind: ShapeKind) -> Shape {
    let mut d = || rng.range(0.2, 1.0);
    match kind {
        ShapeKind::Sphere => Shape::Sphere { diameter: d() },
        ShapeKind::Box => Shape::Box {
            lengths: Vector3::new(d(), d(), d()),
        },
        ShapeKind::Ellipsoid => Shape::Ellipsoid {
            lengths: Vector3::new(d(), d(), d()),
        },
        ShapeKind::Cylinder => {
            let (a, b) = (d(), d());
            Shape::Cylinder {
                axis: rng.axis(),
                diameter: a,
                length: b,
            }
        }
        ShapeKind::Capsule => {
            let (a, b) = (d(), d());
            Shape::Capsule {
                axis: rng.axis(),
                diameter: a,
                length: b,
            }
        }
        ShapeKind::Cone => {
            let (a, b) = (d(), d());
            Shape::Cone {
                axis: rng.axis(),
                diameter: a,
                length: b,
                top_diameter: 0.0,
            }
        }
        ShapeKind::ConvexHull => {
            // Points on a random ellipsoid-ish cloud: a generic polyhedron.
            let (a, b, c) = (d(), d(), d());
            let mut pts = Vec::new();
            for _ in 0..14 {
                let u = rng.unit_vector();
                pts.push(Point3::new(0.5 * a * u.x, 0.5 * b * u.y, 0.5 * c * u.z));
            }
            Shape::ConvexHull { points: pts }
        }
        ShapeKind::Beam => {
            let (l, w, t) = (d(), d(), d());
            Shape::Beam {
                axis: rng.axis(),
                length: l,
                width: w,
                thickness: t,
            }
        }
        ShapeKind::Mesh => unreachable!("meshes are read from files (tests/shapes.rs)"),
    }
}

/// Rotation taking parry's y axis to our `axis`.
pub fn y_to(axis: Axis) -> UnitQuaternion<f64> {
    UnitQuaternion::rotation_between(&Vector3::y(), &axis.unit()).unwrap_or_else(|| {
        // y → y: identity (rotation_between handles it); this branch is never taken for x, z.
        UnitQuaternion::identity()
    })
}

/// The parry shape equivalent to `cs` (a round shape on the same core, border = margin) and the
/// fixed local pose of the parry shape in our shape frame. `None` for ellipsoids (parry has none).
pub fn parry_equivalent(cs: &CollisionShape) -> Option<(SharedShape, Isometry3<f64>)> {
    let r = cs.margin();
    let id = Isometry3::identity();
    Some(match cs.core() {
        CoreShape::Point { centre } => (
            SharedShape::new(Ball::new(r)),
            Isometry3::from_parts(
                Translation3::from(centre.coords),
                UnitQuaternion::identity(),
            ),
        ),
        CoreShape::Segment { axis, half_length } => {
            let e = axis.unit() * *half_length;
            (
                SharedShape::new(Capsule::new(Point3::from(-e), Point3::from(e), r)),
                id,
            )
        }
        CoreShape::Box { half_extents } => (
            SharedShape::new(RoundShape {
                inner_shape: Cuboid::new(*half_extents),
                border_radius: r,
            }),
            id,
        ),
        CoreShape::Frustum {
            axis,
            z0,
            z1,
            r0,
            r1,
        } => {
            let hh = 0.5 * (z1 - z0);
            let pose = Isometry3::from_parts(
                Translation3::from(axis.unit() * (0.5 * (z0 + z1))),
                y_to(*axis),
            );
            if (r0 - r1).abs() < 1e-15 {
                (
                    SharedShape::new(RoundShape {
                        inner_shape: Cylinder::new(hh, *r0),
                        border_radius: r,
                    }),
                    pose,
                )
            } else {
                assert_eq!(*r1, 0.0, "only pointed cones have a parry equivalent");
                (
                    SharedShape::new(RoundShape {
                        inner_shape: Cone::new(hh, *r0),
                        border_radius: r,
                    }),
                    pose,
                )
            }
        }
        // No parry shape is a stadium slab (tests/shapes.rs compares the beam with a hull).
        CoreShape::Ellipsoid { .. } | CoreShape::Beam { .. } => return None,
        CoreShape::Hull { vertices } => (
            SharedShape::new(RoundShape {
                inner_shape: ConvexPolyhedron::from_convex_hull(vertices).unwrap(),
                border_radius: r,
            }),
            id,
        ),
    })
}

/// Random pose: random rotation, translation in a cube of half width `w` \[m\].
pub fn random_pose(rng: &mut Rng, w: f64) -> Isometry3<f64> {
    Isometry3::from_parts(
        Translation3::new(rng.range(-w, w), rng.range(-w, w), rng.range(-w, w)),
        rng.rotation(),
    )
}

/// Quantiles (0, 50, 90, 99, 100 %) of a sample, for reporting.
pub fn quantiles(v: &mut [f64]) -> [f64; 5] {
    if v.is_empty() {
        return [f64::NAN; 5];
    }
    v.sort_by(|a, b| a.total_cmp(b));
    let q = |p: f64| v[((v.len() - 1) as f64 * p).round() as usize];
    [q(0.0), q(0.5), q(0.9), q(0.99), q(1.0)]
}
