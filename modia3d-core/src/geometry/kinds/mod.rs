//! Shape kinds, one file per [`Shape`] variant that states every geometry fact of it (geometry
//! stage): its row of [`SHAPE_KINDS`] (`ROW`: name, `model!` keys, value types, units,
//! stand-in) and, in `impl` [`KindGeometry`] for its `Params` (the variant's fields, borrowed),
//! loading and collision parts, the lengths and points validation checks, its exact mass
//! properties, the width its smoothing is bounded by and its core ⊕ margin, its volume-law
//! solid ([`VolumeLaw`]: none, a polytope or a frustum), its contact radius and flatness, and
//! its display mesh and primitive. No fact has a default: `ROW` is a plain struct literal and
//! [`KindGeometry`] a trait without provided methods.
//!
//! The kinds are listed once, in `shape_table!` (`shape_kind.rs`); the table generates, here,
//! [`SHAPE_KINDS`] and every dispatch from a [`Shape`] to its file as an exhaustive `match`
//! (no trait objects): the public [`Shape::spec`], [`Shape::kind`], [`Shape::load`],
//! [`Shape::collision_parts`], [`Shape::ball_diameter`], [`Shape::dimensions`],
//! [`Shape::unit_mass_properties`] and the crate's capabilities the algorithms ask
//! (`collision_shape.rs`, `smoothing.rs`, `overlap/`, the contact preprocess, validation, the
//! display exports). Adding a shape means: its file here, one line of the table, its builder
//! variant (`shapes.rs`), docs. The narrow phase's pair table (`narrow_phase/dispatch.rs`) is
//! the one table of pairs; a pair without a closed form goes to MPR.

// Without the `solver` feature (the `model!` macro's build, which asks only the rows and the
// validation facts) the contact preprocess and the display exports are not compiled.
#![cfg_attr(not(feature = "solver"), allow(dead_code))]

pub(crate) mod beam;
pub(crate) mod box_;
pub(crate) mod capsule;
pub(crate) mod cone;
pub(crate) mod convex_hull;
pub(crate) mod cylinder;
pub(crate) mod ellipsoid;
pub(crate) mod file_mesh;
pub(crate) mod mesh;
pub(crate) mod sphere;

use super::display_mesh::{Primitive, TriMesh};
use super::error::GeometryError;
use super::mass_properties::UnitMassProperties;
use super::overlap::{Frustum, Polytope};
use super::shape_kind::{shape_table, ShapeKind};
use super::shape_spec::ShapeKindSpec;
use super::shapes::{Axis, Shape};
use super::support::CoreShape;
use nalgebra::{Matrix3, Point3, Vector3};

/// The solid the volume contact law uses for a shape (`geometry/overlap/`).
pub(crate) enum VolumeLaw {
    /// None: the shape keeps a point law (sphere, capsule, ellipsoid, unloaded file mesh).
    None,
    /// A polytope; `inscribed` when it is inscribed in the shape rather than the shape itself
    /// (a beam's rounded ends are polygons): then the volume law's unsmoothed collision shape
    /// is the polytope's hull, so that its signed distance is of the same solid.
    Polytope {
        /// The polytope.
        polytope: Polytope,
        /// Whether it is inscribed in the shape.
        inscribed: bool,
    },
    /// A frustum (cylinder, cone).
    Frustum(Frustum),
}

/// The geometry facts of one shape variant, implemented by its `Params` in its file (no
/// provided methods: each kind states each one). `'a` is the lifetime of the shape's fields.
pub(crate) trait KindGeometry<'a> {
    /// `Some` shape read from a file (a [`Shape::FileMesh`] into a [`Shape::Mesh`]); `None`:
    /// the shape is loaded already.
    fn load(&self) -> Result<Option<Shape>, GeometryError>;
    /// `Some` shapes of the collision shapes the shape becomes when it is not itself one (a
    /// mesh: the convex hulls of its parts; an unloaded file mesh: none); `None`: itself.
    fn collision_parts(&self) -> Option<Vec<Shape>>;
    /// The diameter of a ball \[m\] (the contact laws of the paper's sphere pairs apply to
    /// it); `None` for every other shape.
    fn ball_diameter(&self) -> Option<f64>;
    /// Every length parameter that must be finite and > 0, with its name.
    fn dimensions(&self) -> Vec<(&'static str, f64)>;
    /// Every length parameter that must be finite and ≥ 0 (a cone's top diameter), with its
    /// name.
    fn non_negative_lengths(&self) -> Vec<(&'static str, f64)>;
    /// The points the solid is the convex hull of, when the user gives them (validation
    /// checks them finite and spanning a volume); `None` for every other shape.
    fn hull_points(&self) -> Option<&'a [Point3<f64>]>;
    /// Exact volume, centre of mass and unit-density inertia; `None` when there are none (a
    /// degenerate hull, an open mesh, an unloaded file mesh).
    fn unit_mass_properties(&self) -> Option<UnitMassProperties>;
    /// The dimension a smoothing radius is bounded by (a tenth of it, see
    /// [`effective_smoothing_radius`](super::effective_smoothing_radius)) \[m\]; `None` for
    /// a shape that is smooth already.
    fn smoothed_width(&self) -> Result<Option<f64>, GeometryError>;
    /// The core and the margin of `core ⊕ ball(margin)` with the effective smoothing radius
    /// `r` \[m\].
    fn core(&self, r: f64) -> Result<(CoreShape, f64), GeometryError>;
    /// The volume law's solid of the shape.
    fn volume_solid(&self) -> Result<VolumeLaw, GeometryError>;
    /// Contact radius \[m\] in the later Modia3D profile and whether the shape counts as flat.
    fn contact_radius(&self) -> (f64, bool);
    /// The display mesh in the shape frame (`display_mesh.rs`).
    fn display_mesh(&self) -> TriMesh;
    /// The primitive an export with geometries of its own draws the shape as (three.js);
    /// `None`: its display mesh.
    fn display_primitive(&self) -> Option<Primitive>;
}

/// The inertia of an axisymmetric solid of unit density, `axial` about `axis` and `transverse`
/// about the other two axes, as a diagonal matrix.
fn axisymmetric(axis: Axis, axial: f64, transverse: f64) -> Matrix3<f64> {
    let mut d = Vector3::repeat(transverse);
    d[axis.index()] = axial;
    Matrix3::from_diagonal(&d)
}

/// The components of `v` along x, y, z with their names (`dimensions` of a vector).
fn components(names: [&'static str; 3], v: &Vector3<f64>) -> Vec<(&'static str, f64)> {
    let [x, y, z] = names;
    vec![(x, v.x), (y, v.y), (z, v.z)]
}

/// The contact radius of a solid without a radius of its own (a hull or mesh), from its unit
/// mass properties: half the cube root of its volume (1 without one); flat (its flat faces are
/// what it usually rests on).
fn volume_radius(props: Option<UnitMassProperties>) -> (f64, bool) {
    let w = props.map(|u| u.volume.cbrt()).unwrap_or(1.0);
    (0.5 * w, true)
}

/// Generates [`SHAPE_KINDS`] and the dispatch from a [`Shape`] to its file.
macro_rules! dispatch {
    ($($kind:ident => $($variant:ident { $($field:ident),* } in $file:ident)|+,)*) => {
        /// The solver-free rows of the shape kinds, one per [`Shape`] variant (name,
        /// parameters with their `model!` keys, value types and units), in the builder's
        /// order; the `model!` macro reads them.
        pub const SHAPE_KINDS: &[ShapeKindSpec] = &[$($($file::ROW,)+)*];

        /// `$shape.$method $args` of the shape's `Params` (an exhaustive `match`).
        macro_rules! each_kind {
            ($shape:expr, $method:ident $args:tt) => {
                match $shape {
                    $($(Shape::$variant { $($field),* } => {
                        $file::Params { $($field),* }.$method $args
                    })+)*
                }
            };
        }

        impl Shape {
            /// The row of this shape's variant in [`SHAPE_KINDS`].
            pub fn spec(&self) -> &'static ShapeKindSpec {
                match self {
                    $($(Shape::$variant { .. } => &$file::ROW,)+)*
                }
            }
        }
    };
}

shape_table!(dispatch);

impl Shape {
    /// The kind of this shape.
    pub fn kind(&self) -> ShapeKind {
        self.spec().kind
    }

    /// This shape with a [`Shape::FileMesh`] read into a [`Shape::Mesh`]; other shapes
    /// unchanged. Only reading and parsing can fail here; whether the mesh bounds a solid
    /// (needed for mass properties, not for a visual) is
    /// [`mesh_mass_properties`](super::mesh_mass_properties)' check.
    pub fn load(&self) -> Result<Shape, GeometryError> {
        Ok(each_kind!(self, load())?.unwrap_or_else(|| self.clone()))
    }

    /// The shapes of the collision shapes this shape becomes: itself, or for a mesh the
    /// convex hulls of its parts ([`MeshCollision`](super::MeshCollision)). Empty for an
    /// unloaded file mesh.
    pub fn collision_parts(&self) -> Vec<Shape> {
        each_kind!(self, collision_parts()).unwrap_or_else(|| vec![self.clone()])
    }

    /// The diameter of a ball \[m\] (a sphere: the contact laws of the paper's sphere pairs
    /// apply to it); `None` for every other shape.
    pub fn ball_diameter(&self) -> Option<f64> {
        each_kind!(self, ball_diameter())
    }

    /// Every length parameter that must be finite and > 0, with its name, for validation. A
    /// cone's top diameter, which may be 0, is not among them: the validators check it
    /// themselves (`≥ 0`).
    pub fn dimensions(&self) -> Vec<(&'static str, f64)> {
        each_kind!(self, dimensions())
    }

    /// Every length parameter that must be finite and ≥ 0, with its name (a cone's top
    /// diameter).
    pub(crate) fn non_negative_lengths(&self) -> Vec<(&'static str, f64)> {
        each_kind!(self, non_negative_lengths())
    }

    /// The points the solid is the convex hull of, when the user gives them (a
    /// [`Shape::ConvexHull`]'s); `None` for every other shape.
    pub(crate) fn hull_points(&self) -> Option<&[Point3<f64>]> {
        each_kind!(self, hull_points())
    }

    /// Exact volume, centre of mass and unit-density inertia. `None` for a degenerate convex
    /// hull (fewer than 4 points not in a plane), a mesh that is not closed (see
    /// [`mesh_mass_properties`](super::mesh_mass_properties) for the reason) and a
    /// [`Shape::FileMesh`] not yet loaded.
    pub fn unit_mass_properties(&self) -> Option<UnitMassProperties> {
        each_kind!(self, unit_mass_properties())
    }

    /// The dimension a smoothing radius is bounded by \[m\]; `None` for a shape that is
    /// smooth already (sphere, capsule, ellipsoid).
    pub(crate) fn smoothed_width(&self) -> Result<Option<f64>, GeometryError> {
        each_kind!(self, smoothed_width())
    }

    /// The core and the margin of `core ⊕ ball(margin)` with the effective smoothing radius
    /// `r` \[m\].
    pub(crate) fn core(&self, r: f64) -> Result<(CoreShape, f64), GeometryError> {
        each_kind!(self, core(r))
    }

    /// The volume law's solid of the shape.
    pub(crate) fn volume_solid(&self) -> Result<VolumeLaw, GeometryError> {
        each_kind!(self, volume_solid())
    }

    /// Contact radius \[m\] in the later Modia3D profile and whether the shape counts as flat.
    pub(crate) fn contact_radius(&self) -> (f64, bool) {
        each_kind!(self, contact_radius())
    }

    /// The display mesh of the shape, in its shape frame (empty for an unloaded file mesh).
    pub(crate) fn display_mesh(&self) -> TriMesh {
        each_kind!(self, display_mesh())
    }

    /// The primitive an export with geometries of its own draws the shape as (three.js);
    /// `None`: its display mesh.
    pub(crate) fn display_primitive(&self) -> Option<Primitive> {
        each_kind!(self, display_primitive())
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::shape_kind::shape_table;

    /// Each row's kind is the one the table names, and every kind has a row.
    #[test]
    fn rows_name_their_kinds() {
        macro_rules! kinds {
            ($($kind:ident => $($variant:ident { $($field:ident),* } in $file:ident)|+,)*) => {
                &[$($((ShapeKind::$kind, stringify!($variant), &$file::ROW),)+)*]
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
