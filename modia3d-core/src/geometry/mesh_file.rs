//! Reading the vertices of a mesh file for a convex-hull shape (geometry stage; reads files,
//! touches nothing else).
//!
//! Only Wavefront OBJ, through the small dependency-free `tobj` crate (f64 positions). The
//! convex hull of all vertices referenced by the faces of all objects in the file is the solid
//! (vertices no face uses are dropped by `tobj`); normals and materials are ignored. STL is not
//! supported (no equally small, dependency-free crate).

use super::error::GeometryError;
use super::shapes::Shape;
use nalgebra::{Point3, Vector3};
use std::path::Path;

/// All vertex positions of the OBJ file at `path`, each multiplied component-wise by `scale`,
/// in the file's frame [m after scaling].
pub fn obj_vertices(path: &Path, scale: Vector3<f64>) -> Result<Vec<Point3<f64>>, GeometryError> {
    let err = |message: String| GeometryError::MeshFile {
        path: path.display().to_string(),
        message,
    };
    let (models, _materials) =
        tobj::load_obj(path, &tobj::LoadOptions::default()).map_err(|e| err(e.to_string()))?;
    let points: Vec<Point3<f64>> = models
        .iter()
        .flat_map(|m| m.mesh.positions.chunks_exact(3))
        .map(|p| Point3::new(p[0] * scale.x, p[1] * scale.y, p[2] * scale.z))
        .collect();
    if points.len() < 4 {
        return Err(err(format!("{} vertices, need at least 4", points.len())));
    }
    Ok(points)
}

/// The convex hull of the vertices of the OBJ file at `path` (scaled by `scale`) as a
/// [`Shape::ConvexHull`].
pub fn convex_hull_from_obj(path: &Path, scale: Vector3<f64>) -> Result<Shape, GeometryError> {
    Ok(Shape::ConvexHull {
        points: obj_vertices(path, scale)?,
    })
}
