//! Geometry stage: shapes, mass properties, support maps, smoothing, bounding boxes, broad and
//! narrow phase. Touches nothing outside itself.

pub mod aabb;
pub mod broad_phase;
pub mod collision_shape;
pub mod error;
pub mod mesh_file;
pub mod narrow_phase;
pub mod shapes;
pub mod smoothing;
pub mod support;

pub use aabb::{aabb_distance, aabbs_overlap, world_aabb, Aabb};
pub use broad_phase::BroadPhase;
pub use collision_shape::CollisionShape;
pub use error::GeometryError;
pub use mesh_file::{convex_hull_from_obj, obj_vertices};
pub use narrow_phase::{signed_distance, NarrowPhaseOptions, SignedDistance};
pub use shapes::{Axis, Shape, ShapeKind, UnitMassProperties};
pub use smoothing::{effective_smoothing_radius, DEFAULT_SMOOTHING_RADIUS};
pub use support::CoreShape;
