//! The shape kinds as the builder and `model!` see them (solver-free vocabulary, exported as
//! [`crate::SHAPE_KINDS`]): one row per [`Shape`] variant with its name, its parameters (the
//! variant's fields, with the `model!` key, value type and unit of each) and the shape `model!`
//! checks a literal constructor with. The rows are listed here in the order of the table in
//! `shape_kind.rs`, which also generates [`Shape::kind`] and [`Shape::spec`]. The `model!`
//! macro reads these rows instead of keeping a vocabulary of shapes of its own.

use super::shape_kind::{shape_table, ShapeKind};
use super::shapes::{Axis, Shape};
use nalgebra::{Point3, Vector3};

/// One shape kind as a [`Shape`] variant: its name (the variant's and the `model!`
/// constructor's), its [`ShapeKind`], its parameters in the variant's field order, and how
/// `model!` builds it from the values it knows.
#[derive(Clone, Copy)]
pub struct ShapeKindSpec {
    /// The variant's and the constructor's name, e.g. `"Cylinder"`.
    pub name: &'static str,
    /// The kind (the narrow phase's and messages' name of the shape).
    pub kind: ShapeKind,
    /// The parameters, in the variant's field order.
    pub params: &'static [ShapeParam],
    /// The shape with the values `model!` knows at compile time (a value known only at run
    /// time, points and files are stand-ins the scene's rules accept); `None`: the variant is
    /// not a `model!` constructor (a loaded [`Shape::Mesh`]).
    pub stand_in: Option<fn(&mut dyn ShapeValues) -> Shape>,
}

impl std::fmt::Debug for ShapeKindSpec {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("ShapeKindSpec")
            .field("name", &self.name)
            .field("kind", &self.kind)
            .field("params", &self.params)
            .finish_non_exhaustive()
    }
}

impl ShapeKindSpec {
    /// The `model!` keys in the variant's field order.
    pub fn keys(&self) -> impl Iterator<Item = &'static str> {
        self.params.iter().map(|p| p.key)
    }
    /// The variant's fields in their order.
    pub fn fields(&self) -> impl Iterator<Item = &'static str> {
        self.params.iter().map(|p| p.field)
    }
}

/// A parameter of a shape kind.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct ShapeParam {
    /// The `model!` key, e.g. `"diameter"`.
    pub key: &'static str,
    /// The variant's field (the key but for a file mesh's `convex_decomposition`, which
    /// sets `collision`).
    pub field: &'static str,
    /// What it takes.
    pub value: ShapeValue,
    /// Its unit, e.g. `"m"` (`"1"` when it has none).
    pub unit: &'static str,
    /// Whether it must be given; else its default is the one of its [`ShapeValue`].
    pub required: bool,
}

/// The type of a shape parameter's value. (No variant is named after a type of the crate —
/// `Axis`, `Path`, `MeshCollision`: a second public item of a type's name makes rustc print
/// that type with its full path in `model!`'s type errors.)
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ShapeValue {
    /// A length (`f64`) \[m\]; default 0.
    Length,
    /// Three lengths along x, y, z (`Vector3<f64>`, `[f64; 3]` in `model!`) \[m\].
    Lengths,
    /// Three factors along x, y, z (`Vector3<f64>`, `[f64; 3]` in `model!`); default ones.
    Factors,
    /// A frame [`Axis`] (1, 2 or 3 in `model!`); default z.
    AxisIndex,
    /// Points in the shape frame (`Vec<Point3<f64>>`) \[m\].
    Vertices,
    /// A file (`PathBuf`; anything `PathBuf::from` takes in `model!`).
    File,
    /// A [`MeshCollision`](super::MeshCollision) (`model!`: a `bool`, true for a convex
    /// decomposition); default the convex hull.
    Decomposition,
    /// A loaded triangle mesh (not a `model!` value).
    LoadedMesh,
}

/// The values `model!` knows of a shape's parameters at compile time, by key: a literal, else
/// a stand-in; a parameter not given has its default ([`ShapeValue`]). See
/// [`ShapeKindSpec::stand_in`].
pub trait ShapeValues {
    /// A [`ShapeValue::Length`] \[m\].
    fn length(&mut self, key: &'static str) -> f64;
    /// A [`ShapeValue::Lengths`] or [`ShapeValue::Factors`].
    fn vector(&mut self, key: &'static str) -> Vector3<f64>;
    /// A [`ShapeValue::AxisIndex`].
    fn axis(&mut self, key: &'static str) -> Axis;
    /// The length that stands in for a value known only at run time \[m\].
    fn stand_in(&self) -> f64;
}

/// A tetrahedron of edge `s` at the origin: what points or a file stand in as.
fn tetrahedron(s: f64) -> Shape {
    Shape::ConvexHull {
        points: vec![
            Point3::origin(),
            Point3::new(s, 0.0, 0.0),
            Point3::new(0.0, s, 0.0),
            Point3::new(0.0, 0.0, s),
        ],
    }
}

const fn param(key: &'static str, value: ShapeValue, unit: &'static str) -> ShapeParam {
    ShapeParam {
        key,
        field: key,
        value,
        unit,
        required: true,
    }
}

/// The axis of a shape (optional: z).
const AXIS: ShapeParam = ShapeParam {
    required: false,
    ..param("axis", ShapeValue::AxisIndex, "1")
};

const SPHERE: ShapeKindSpec = ShapeKindSpec {
    name: "Sphere",
    kind: ShapeKind::Sphere,
    params: &[param("diameter", ShapeValue::Length, "m")],
    stand_in: Some(|v| Shape::Sphere {
        diameter: v.length("diameter"),
    }),
};

const BOX: ShapeKindSpec = ShapeKindSpec {
    name: "Box",
    kind: ShapeKind::Box,
    params: &[param("lengths", ShapeValue::Lengths, "m")],
    stand_in: Some(|v| Shape::Box {
        lengths: v.vector("lengths"),
    }),
};

const CYLINDER: ShapeKindSpec = ShapeKindSpec {
    name: "Cylinder",
    kind: ShapeKind::Cylinder,
    params: &[
        AXIS,
        param("diameter", ShapeValue::Length, "m"),
        param("length", ShapeValue::Length, "m"),
    ],
    stand_in: Some(|v| Shape::Cylinder {
        axis: v.axis("axis"),
        diameter: v.length("diameter"),
        length: v.length("length"),
    }),
};

const CAPSULE: ShapeKindSpec = ShapeKindSpec {
    name: "Capsule",
    kind: ShapeKind::Capsule,
    params: &[
        AXIS,
        param("diameter", ShapeValue::Length, "m"),
        param("length", ShapeValue::Length, "m"),
    ],
    stand_in: Some(|v| Shape::Capsule {
        axis: v.axis("axis"),
        diameter: v.length("diameter"),
        length: v.length("length"),
    }),
};

const CONE: ShapeKindSpec = ShapeKindSpec {
    name: "Cone",
    kind: ShapeKind::Cone,
    params: &[
        AXIS,
        param("diameter", ShapeValue::Length, "m"),
        param("length", ShapeValue::Length, "m"),
        ShapeParam {
            required: false,
            ..param("top_diameter", ShapeValue::Length, "m")
        },
    ],
    stand_in: Some(|v| Shape::Cone {
        axis: v.axis("axis"),
        diameter: v.length("diameter"),
        length: v.length("length"),
        top_diameter: v.length("top_diameter"),
    }),
};

const BEAM: ShapeKindSpec = ShapeKindSpec {
    name: "Beam",
    kind: ShapeKind::Beam,
    params: &[
        AXIS,
        param("length", ShapeValue::Length, "m"),
        param("width", ShapeValue::Length, "m"),
        param("thickness", ShapeValue::Length, "m"),
    ],
    stand_in: Some(|v| Shape::Beam {
        axis: v.axis("axis"),
        length: v.length("length"),
        width: v.length("width"),
        thickness: v.length("thickness"),
    }),
};

const ELLIPSOID: ShapeKindSpec = ShapeKindSpec {
    name: "Ellipsoid",
    kind: ShapeKind::Ellipsoid,
    params: &[param("lengths", ShapeValue::Lengths, "m")],
    stand_in: Some(|v| Shape::Ellipsoid {
        lengths: v.vector("lengths"),
    }),
};

const CONVEX_HULL: ShapeKindSpec = ShapeKindSpec {
    name: "ConvexHull",
    kind: ShapeKind::ConvexHull,
    params: &[param("points", ShapeValue::Vertices, "m")],
    stand_in: Some(|v| tetrahedron(v.stand_in())),
};

const FILE_MESH: ShapeKindSpec = ShapeKindSpec {
    name: "FileMesh",
    kind: ShapeKind::Mesh,
    params: &[
        param("path", ShapeValue::File, "1"),
        ShapeParam {
            required: false,
            ..param("scale", ShapeValue::Factors, "1")
        },
        ShapeParam {
            key: "convex_decomposition",
            required: false,
            ..param("collision", ShapeValue::Decomposition, "1")
        },
    ],
    // The file is read by `build()` at run time.
    stand_in: Some(|v| tetrahedron(v.stand_in())),
};

const MESH: ShapeKindSpec = ShapeKindSpec {
    name: "Mesh",
    kind: ShapeKind::Mesh,
    params: &[
        param("mesh", ShapeValue::LoadedMesh, "m"),
        param("collision", ShapeValue::Decomposition, "1"),
    ],
    stand_in: None,
};

/// Generates [`SHAPE_KINDS`] and the dispatch from a [`Shape`] to its row.
macro_rules! rows {
    ($($kind:ident => $($variant:ident($row:ident))|+,)*) => {
        /// The solver-free rows of the shape kinds, one per [`Shape`] variant (name, parameters
        /// with their `model!` keys, value types and units), in the builder's order; the
        /// `model!` macro reads them.
        pub const SHAPE_KINDS: &[ShapeKindSpec] = &[$($($row,)+)*];

        impl Shape {
            /// The row of this shape's variant in [`SHAPE_KINDS`].
            pub fn spec(&self) -> &'static ShapeKindSpec {
                match self {
                    $($(Shape::$variant { .. } => &$row,)+)*
                }
            }
            /// The kind of this shape.
            pub fn kind(&self) -> ShapeKind {
                self.spec().kind
            }
        }
    };
}

shape_table!(rows);

#[cfg(test)]
mod tests {
    use super::*;

    /// Each row's kind is the one the table names, and every kind has a row.
    #[test]
    fn rows_name_their_kinds() {
        macro_rules! kinds {
            ($($kind:ident => $($variant:ident($row:ident))|+,)*) => {
                &[$($((ShapeKind::$kind, stringify!($variant), &$row),)+)*]
            };
        }
        let table: &[(ShapeKind, &str, &ShapeKindSpec)] = shape_table!(kinds);
        assert_eq!(table.len(), SHAPE_KINDS.len());
        for (kind, variant, row) in table {
            assert_eq!(row.kind, *kind, "{variant}");
            assert_eq!(row.name, *variant);
        }
    }
}
