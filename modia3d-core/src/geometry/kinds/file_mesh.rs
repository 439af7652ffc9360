//! File mesh (Modia3D's `FileMesh`): a triangle mesh in an OBJ or STL file, its frame the
//! file's, scaled by `scale`. Loaded by `SceneDesc::build` (or [`Shape::load`]) into a
//! [`Shape::Mesh`] (`kinds/mesh.rs`), which states its other facts; unloaded it has no mass
//! properties, no collision shape and an empty display mesh. `model!` stands in a tetrahedron
//! for it (the file is read at run time).

use super::{KindGeometry, VolumeLaw};
use crate::geometry::display_mesh::{Primitive, TriMesh};
use crate::geometry::error::GeometryError;
use crate::geometry::mesh_file::{load_mesh, MeshCollision};
use crate::geometry::shape_kind::ShapeKind;
use crate::geometry::shape_spec::{param, tetrahedron, ShapeKindSpec, ShapeParam, ShapeValue};
use crate::geometry::shapes::Shape;
use crate::geometry::support::CoreShape;
use crate::geometry::UnitMassProperties;
use nalgebra::{Point3, Vector3};
use std::path::PathBuf;
use std::sync::Arc;

/// The row of [`SHAPE_KINDS`](crate::geometry::SHAPE_KINDS).
pub(crate) const ROW: ShapeKindSpec = ShapeKindSpec {
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

/// The fields of a [`Shape::FileMesh`].
pub(crate) struct Params<'a> {
    /// The file, `.obj` or `.stl`.
    pub path: &'a PathBuf,
    /// Factors applied to the file's x, y, z coordinates (each > 0).
    pub scale: &'a Vector3<f64>,
    /// Convex hull or convex decomposition for collision.
    pub collision: &'a MeshCollision,
}

impl Params<'_> {
    /// The error of a use that needs the mesh read.
    fn not_loaded(&self) -> GeometryError {
        GeometryError::MeshNotLoaded(self.path.display().to_string())
    }
}

impl<'a> KindGeometry<'a> for Params<'a> {
    fn load(&self) -> Result<Option<Shape>, GeometryError> {
        let mesh = load_mesh(self.path, *self.scale)?;
        Ok(Some(Shape::Mesh {
            mesh: Arc::new(mesh),
            collision: *self.collision,
        }))
    }
    fn collision_parts(&self) -> Option<Vec<Shape>> {
        Some(vec![])
    }
    fn ball_diameter(&self) -> Option<f64> {
        None
    }
    fn dimensions(&self) -> Vec<(&'static str, f64)> {
        super::components(["scale[0]", "scale[1]", "scale[2]"], self.scale)
    }
    fn non_negative_lengths(&self) -> Vec<(&'static str, f64)> {
        vec![]
    }
    fn hull_points(&self) -> Option<&'a [Point3<f64>]> {
        None
    }
    fn unit_mass_properties(&self) -> Option<UnitMassProperties> {
        None
    }
    fn smoothed_width(&self) -> Result<Option<f64>, GeometryError> {
        Err(self.not_loaded())
    }
    fn core(&self, _r: f64) -> Result<(CoreShape, f64), GeometryError> {
        Err(self.not_loaded())
    }
    /// Loaded first.
    fn volume_solid(&self) -> Result<VolumeLaw, GeometryError> {
        Ok(VolumeLaw::None)
    }
    fn contact_radius(&self) -> (f64, bool) {
        super::volume_radius(self.unit_mass_properties())
    }
    /// Loaded by `SceneDesc::build`; a result never holds an unloaded one.
    fn display_mesh(&self) -> TriMesh {
        TriMesh::default()
    }
    fn display_primitive(&self) -> Option<Primitive> {
        None
    }
}
