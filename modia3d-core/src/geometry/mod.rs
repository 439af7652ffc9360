//! Geometry stage: shapes, mass properties, support maps, smoothing, bounding boxes, broad and
//! narrow phase. Touches nothing outside itself.
//!
//! Pipeline (`docs/contact-model.md` §2), one file per step:
//! - [`shapes`]: the user's [`Shape`]; its kinds are listed once (`shape_kind.rs`), each
//!   variant with a file in `kinds/` that states every geometry fact of it (its row of
//!   [`SHAPE_KINDS`], exact mass properties, core, volume-law solid, contact radius, display
//!   mesh, …; `kinds/mod.rs` dispatches to them);
//! - [`collision_shape`]: [`CollisionShape`] = core ⊕ ball(margin), built once per solid, with
//!   [`smoothing`] (rounded edges of boxes, cylinders, cones, hulls) and [`support`] (closed-form
//!   support maps of the cores); [`mesh_file`]: triangle meshes from OBJ/STL files, their
//!   mass properties and convex parts;
//! - [`aabb`]: tight world AABBs and the distance between separated AABBs (`δ_AABB`);
//! - [`broad_phase`]: sort and sweep with temporal coherence → candidate pairs;
//! - [`narrow_phase`]: [`signed_distance`] — one dispatch `match`: closed forms
//!   (sphere/box/cylinder/capsule pairs) or the improved MPR, with GJK for the exact distance of
//!   separated cores.
//!
//! Frames: poses are `Isometry3<f64>` from the shape frame to world; results are resolved in
//! world, lengths in \[m\]. Nothing allocates per query or per broad-phase update once warmed up.

pub mod aabb;
pub mod broad_phase;
pub mod collision_shape;
pub(crate) mod display_mesh;
pub mod error;
mod kinds;
mod mass_properties;
pub mod mesh_file;
pub mod narrow_phase;
pub mod overlap;
mod pose;
mod shape_kind;
mod shape_spec;
pub mod shapes;
pub mod smoothing;
pub mod support;

pub use aabb::{aabb_distance, aabbs_overlap, world_aabb, world_aabbs_into, Aabb};
pub use broad_phase::BroadPhase;
pub use collision_shape::CollisionShape;
pub use error::GeometryError;
pub(crate) use kinds::VolumeLaw;
pub use kinds::SHAPE_KINDS;
pub use mesh_file::{
    convex_parts, load_mesh, mesh_mass_properties, obj_vertices, repair_mesh, MeshRepair,
    TriangleMesh,
};
pub use narrow_phase::{
    contact_patch, contact_point, signed_distance, signed_distance_method, ContactPatch,
    NarrowPhaseOptions, SignedDistance,
};
pub use shape_spec::{ShapeKindSpec, ShapeParam, ShapeValue, ShapeValues};
pub use shapes::{convex_hull_from_obj, Axis, MeshCollision, Shape, ShapeKind, UnitMassProperties};
pub use smoothing::{effective_smoothing_radius, DEFAULT_SMOOTHING_RADIUS};
pub use support::CoreShape;
