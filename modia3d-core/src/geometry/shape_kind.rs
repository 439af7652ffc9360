//! The kinds of shapes, listed once (geometry vocabulary, imports nothing): the table
//! `shape_table!` names each kind with the builder's [`Shape`](super::Shape) variants of the
//! kind and each variant's row of solver-free facts (`geometry/shape_spec.rs`). It generates
//! [`ShapeKind`] here and, in `shape_spec.rs`, [`SHAPE_KINDS`](super::SHAPE_KINDS) and the
//! dispatch from a `Shape` to its kind and row (exhaustive `match`es). A new shape is a line
//! here, its row and its builder variant; the algorithms that must decide for it (mass
//! properties, core and smoothing, display, contact radius, volume-law solid, validation) are
//! exhaustive `match`es in their files; the narrow phase's pair tables give a pair without a
//! closed form to MPR.
//!
//! (The table is a macro that hands the list to another macro, so that [`ShapeKind`] lives in
//! this leaf: `error.rs` names it, and the rows, which build `Shape`s, sit above `error.rs`.)

/// Calls the macro `$then!` with the shape kinds, once: `Kind => Variant(ROW) | …,` where
/// `Variant` is a [`Shape`](super::Shape) variant of the kind and `ROW` its row in
/// `shape_spec.rs`, in the builder's order.
macro_rules! shape_table {
    ($then:ident) => {
        $then! {
            Sphere => Sphere(SPHERE),
            Box => Box(BOX),
            Cylinder => Cylinder(CYLINDER),
            Capsule => Capsule(CAPSULE),
            Cone => Cone(CONE),
            Beam => Beam(BEAM),
            Ellipsoid => Ellipsoid(ELLIPSOID),
            ConvexHull => ConvexHull(CONVEX_HULL),
            Mesh => FileMesh(FILE_MESH) | Mesh(MESH),
        }
    };
}
pub(crate) use shape_table;

/// Generates [`ShapeKind`] from the table.
macro_rules! kind_enum {
    ($($kind:ident => $($variant:ident($row:ident))|+,)*) => {
        /// The kind of a shape, for messages and dispatch tables.
        #[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
        pub enum ShapeKind {
            $(
                $(#[doc = concat!("[`Shape::", stringify!($variant), "`](super::Shape::", stringify!($variant), ")")])+
                $kind,
            )*
        }
    };
}

shape_table!(kind_enum);
