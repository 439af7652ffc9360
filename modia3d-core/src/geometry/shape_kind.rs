//! The kinds of shapes, listed once (geometry vocabulary, imports nothing): the table
//! `shape_table!` names each kind with the builder's [`Shape`](super::Shape) variants of the
//! kind, each with all its fields and its file in `geometry/kinds/`, which states every
//! geometry fact of the variant (its row of [`SHAPE_KINDS`](super::SHAPE_KINDS), validation's
//! lengths, mass properties, smoothing bound and core, volume-law solid, contact radius,
//! display mesh, loading). It generates [`ShapeKind`] here and, in `kinds/mod.rs`,
//! [`SHAPE_KINDS`](super::SHAPE_KINDS) and every dispatch from a `Shape` to its file
//! (exhaustive `match`es, no trait objects). A new shape is its file in `kinds/`, a line
//! here, its builder variant (`shapes.rs`) and docs; the narrow phase's pair table
//! (`narrow_phase/dispatch.rs`) gives a pair without a closed form to MPR.
//!
//! (The table is a macro that hands the list to another macro, so that [`ShapeKind`] lives in
//! this leaf: `error.rs` names it, and the kinds' files, which build `Shape`s and return
//! errors, sit above `error.rs`.)

/// Calls the macro `$then!` with the shape kinds, once: `Kind => Variant { fields } in file |
/// …,` where `Variant` is a [`Shape`](super::Shape) variant of the kind with all its fields and
/// `file` the module of `geometry/kinds/` that states its facts, in the builder's order.
macro_rules! shape_table {
    ($then:ident) => {
        $then! {
            Sphere => Sphere { diameter } in sphere,
            Box => Box { lengths } in box_,
            Cylinder => Cylinder { axis, diameter, length } in cylinder,
            Capsule => Capsule { axis, diameter, length } in capsule,
            Cone => Cone { axis, diameter, length, top_diameter } in cone,
            Beam => Beam { axis, length, width, thickness } in beam,
            Ellipsoid => Ellipsoid { lengths } in ellipsoid,
            ConvexHull => ConvexHull { points } in convex_hull,
            Mesh => FileMesh { path, scale, collision } in file_mesh
                | Mesh { mesh, collision } in mesh,
        }
    };
}
pub(crate) use shape_table;

/// Generates [`ShapeKind`] from the table.
macro_rules! kind_enum {
    ($($kind:ident => $($variant:ident { $($field:ident),* } in $file:ident)|+,)*) => {
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
