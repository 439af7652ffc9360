//! Mesh: a closed triangle mesh in the shape frame (what a file mesh becomes when loaded).
//! Mass properties come from the closed mesh; for collision it is the convex hull of its
//! vertices or the convex hulls of its parts (`collision`, `Shape::collision_parts`); as one
//! collision shape, smoothing and volume-law solid it is the convex hull of its vertices; it
//! counts as flat for the contact radius (the radius of a ball of its volume); its display
//! mesh keeps its triangles' orientation (it need not be convex).

use super::{KindGeometry, VolumeLaw};
use crate::geometry::display_mesh::{Primitive, TriMesh};
use crate::geometry::error::GeometryError;
use crate::geometry::mesh_file::{convex_parts, mesh_mass_properties, MeshCollision, TriangleMesh};
use crate::geometry::overlap::Polytope;
use crate::geometry::shape_kind::ShapeKind;
use crate::geometry::shape_spec::{param, ShapeKindSpec, ShapeValue};
use crate::geometry::shapes::Shape;
use crate::geometry::smoothing::{hull_inner_width, shrink_convex_hull};
use crate::geometry::support::CoreShape;
use crate::geometry::UnitMassProperties;
use nalgebra::Point3;
use std::sync::Arc;

/// The row of [`SHAPE_KINDS`](crate::geometry::SHAPE_KINDS).
pub(crate) const ROW: ShapeKindSpec = ShapeKindSpec {
    name: "Mesh",
    kind: ShapeKind::Mesh,
    params: &[
        param("mesh", ShapeValue::LoadedMesh, "m"),
        param("collision", ShapeValue::Decomposition, "1"),
    ],
    stand_in: None,
};

/// The fields of a [`Shape::Mesh`].
pub(crate) struct Params<'a> {
    /// The mesh, in the shape frame \[m\].
    pub mesh: &'a Arc<TriangleMesh>,
    /// Convex hull or convex decomposition for collision.
    pub collision: &'a MeshCollision,
}

impl<'a> KindGeometry<'a> for Params<'a> {
    fn load(&self) -> Result<Option<Shape>, GeometryError> {
        Ok(None)
    }
    fn collision_parts(&self) -> Option<Vec<Shape>> {
        Some(
            convex_parts(self.mesh, *self.collision)
                .into_iter()
                .map(|points| Shape::ConvexHull { points })
                .collect(),
        )
    }
    fn ball_diameter(&self) -> Option<f64> {
        None
    }
    fn dimensions(&self) -> Vec<(&'static str, f64)> {
        vec![]
    }
    fn non_negative_lengths(&self) -> Vec<(&'static str, f64)> {
        vec![]
    }
    /// Checked when it is read and repaired (validation's `load_shape`, `solid_mesh`).
    fn hull_points(&self) -> Option<&'a [Point3<f64>]> {
        None
    }
    fn unit_mass_properties(&self) -> Option<UnitMassProperties> {
        mesh_mass_properties(self.mesh).ok()
    }
    fn smoothed_width(&self) -> Result<Option<f64>, GeometryError> {
        hull_inner_width(&self.mesh.vertices).map(Some)
    }
    /// As one shape, its convex hull (`Shape::collision_parts` splits it).
    fn core(&self, r: f64) -> Result<(CoreShape, f64), GeometryError> {
        Ok((
            CoreShape::Hull {
                vertices: shrink_convex_hull(&self.mesh.vertices, r)?,
            },
            r,
        ))
    }
    /// The convex hull of its vertices.
    fn volume_solid(&self) -> Result<VolumeLaw, GeometryError> {
        Polytope::from_points(&self.mesh.vertices).map(|polytope| VolumeLaw::Polytope {
            polytope,
            inscribed: false,
        })
    }
    fn contact_radius(&self) -> (f64, bool) {
        super::volume_radius(self.unit_mass_properties())
    }
    /// Keeps its own (outward) orientation: it need not be convex.
    fn display_mesh(&self) -> TriMesh {
        let mesh = self.mesh;
        let mut m = TriMesh::default();
        for t in &mesh.triangles {
            let [a, b, c] = t.map(|i| mesh.vertices[i as usize].coords);
            let centre = (a + b + c) / 3.0 - (b - a).cross(&(c - a));
            m.push(a, b, c, &centre);
        }
        m
    }
    fn display_primitive(&self) -> Option<Primitive> {
        None
    }
}
