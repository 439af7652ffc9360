//! Geometry stage: shapes, mass properties, (later) support maps, bounding boxes, broad and
//! narrow phase. Touches nothing outside itself.

pub mod shapes;

pub use shapes::{Axis, Shape, ShapeKind, UnitMassProperties};
