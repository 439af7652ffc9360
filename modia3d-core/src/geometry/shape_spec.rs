//! The shape kinds as the builder and `model!` see them (solver-free vocabulary, exported as
//! [`crate::SHAPE_KINDS`]): one row per [`Shape`] variant with its name, its parameters (the
//! variant's fields, with the `model!` key, value type and unit of each) and the shape `model!`
//! checks a literal constructor with. This file has the rows' types; each row is the `ROW` of
//! its kind's file (`geometry/kinds/<kind>.rs`), and the table of `shape_kind.rs` lists them
//! into [`SHAPE_KINDS`](super::SHAPE_KINDS) (`kinds/mod.rs` also generates [`Shape::kind`] and
//! [`Shape::spec`]). The `model!` macro reads these rows instead of keeping a vocabulary of
//! shapes of its own.

use super::shape_kind::ShapeKind;
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
pub(crate) fn tetrahedron(s: f64) -> Shape {
    Shape::ConvexHull {
        points: vec![
            Point3::origin(),
            Point3::new(s, 0.0, 0.0),
            Point3::new(0.0, s, 0.0),
            Point3::new(0.0, 0.0, s),
        ],
    }
}

/// A required parameter whose field is its key.
pub(crate) const fn param(key: &'static str, value: ShapeValue, unit: &'static str) -> ShapeParam {
    ShapeParam {
        key,
        field: key,
        value,
        unit,
        required: true,
    }
}

/// The axis of a shape (optional: z).
pub(crate) const AXIS: ShapeParam = ShapeParam {
    required: false,
    ..param("axis", ShapeValue::AxisIndex, "1")
};

/// The parameters of a round shape along an axis (cylinder, capsule): axis, diameter, length.
pub(crate) const AXIS_DIAMETER_LENGTH: &[ShapeParam] = &[
    AXIS,
    param("diameter", ShapeValue::Length, "m"),
    param("length", ShapeValue::Length, "m"),
];
