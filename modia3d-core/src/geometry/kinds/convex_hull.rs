//! Convex hull: the convex hull of `points` given in the shape frame. Smoothed (bounded by its
//! inner width, `smoothing::hull_inner_width`): its core is the hull with every face moved
//! inwards; its volume-law solid is itself, a polytope; it counts as flat for the contact
//! radius (the radius of a ball of its volume). Validation checks its points finite and
//! spanning a volume.

use super::{KindGeometry, VolumeLaw};
use crate::geometry::display_mesh::{hull_mesh, Primitive, TriMesh};
use crate::geometry::error::GeometryError;
use crate::geometry::overlap::Polytope;
use crate::geometry::shape_kind::ShapeKind;
use crate::geometry::shape_spec::{param, tetrahedron, ShapeKindSpec, ShapeValue};
use crate::geometry::shapes::Shape;
use crate::geometry::smoothing::{hull_inner_width, shrink_convex_hull};
use crate::geometry::support::CoreShape;
use crate::geometry::UnitMassProperties;
use nalgebra::{Matrix3, Point3};

/// The row of [`SHAPE_KINDS`](crate::geometry::SHAPE_KINDS).
pub(crate) const ROW: ShapeKindSpec = ShapeKindSpec {
    name: "ConvexHull",
    kind: ShapeKind::ConvexHull,
    params: &[param("points", ShapeValue::Vertices, "m")],
    stand_in: Some(|v| tetrahedron(v.stand_in())),
};

/// The fields of a [`Shape::ConvexHull`].
pub(crate) struct Params<'a> {
    /// Points whose convex hull is the solid \[m\].
    pub points: &'a Vec<Point3<f64>>,
}

impl<'a> KindGeometry<'a> for Params<'a> {
    fn load(&self) -> Result<Option<Shape>, GeometryError> {
        Ok(None)
    }
    fn collision_parts(&self) -> Option<Vec<Shape>> {
        None
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
    fn hull_points(&self) -> Option<&'a [Point3<f64>]> {
        Some(self.points)
    }
    fn unit_mass_properties(&self) -> Option<UnitMassProperties> {
        hull_mass_properties(self.points)
    }
    fn smoothed_width(&self) -> Result<Option<f64>, GeometryError> {
        hull_inner_width(self.points).map(Some)
    }
    fn core(&self, r: f64) -> Result<(CoreShape, f64), GeometryError> {
        Ok((
            CoreShape::Hull {
                vertices: shrink_convex_hull(self.points, r)?,
            },
            r,
        ))
    }
    fn volume_solid(&self) -> Result<VolumeLaw, GeometryError> {
        Polytope::from_points(self.points).map(|polytope| VolumeLaw::Polytope {
            polytope,
            inscribed: false,
        })
    }
    fn contact_radius(&self) -> (f64, bool) {
        super::volume_radius(self.unit_mass_properties())
    }
    fn display_mesh(&self) -> TriMesh {
        hull_mesh(self.points)
    }
    fn display_primitive(&self) -> Option<Primitive> {
        None
    }
}

/// The exact mass properties of the convex hull of `points`; `None` for a degenerate hull.
fn hull_mass_properties(points: &[Point3<f64>]) -> Option<UnitMassProperties> {
    let poly = parry3d_f64::shape::ConvexPolyhedron::from_convex_hull(points)?;
    let mp = parry3d_f64::shape::Shape::mass_properties(&poly, 1.0);
    if mp.mass().is_nan() || mp.mass() <= 0.0 {
        return None;
    }
    let rot = mp.principal_inertia_local_frame.to_rotation_matrix();
    let inertia =
        rot.matrix() * Matrix3::from_diagonal(&mp.principal_inertia()) * rot.matrix().transpose();
    Some(UnitMassProperties {
        volume: mp.mass(),
        com: mp.local_com.coords,
        inertia,
    })
}
