//! Ellipsoid: full axis lengths `lengths` along x, y, z, centred at the origin. Smooth (no
//! smoothing): its core is itself, with margin 0; it has no volume-law solid (it keeps a point
//! law).

use super::{KindGeometry, VolumeLaw};
use crate::geometry::display_mesh::{arc, lathe, Primitive, TriMesh, RINGS};
use crate::geometry::error::GeometryError;
use crate::geometry::shape_kind::ShapeKind;
use crate::geometry::shape_spec::{param, ShapeKindSpec, ShapeValue};
use crate::geometry::shapes::{Axis, Shape};
use crate::geometry::support::CoreShape;
use crate::geometry::UnitMassProperties;
use nalgebra::{Matrix3, Point3, Vector3};
use std::f64::consts::PI;

/// The row of [`SHAPE_KINDS`](crate::geometry::SHAPE_KINDS).
pub(crate) const ROW: ShapeKindSpec = ShapeKindSpec {
    name: "Ellipsoid",
    kind: ShapeKind::Ellipsoid,
    params: &[param("lengths", ShapeValue::Lengths, "m")],
    stand_in: Some(|v| Shape::Ellipsoid {
        lengths: v.vector("lengths"),
    }),
};

/// The fields of a [`Shape::Ellipsoid`].
pub(crate) struct Params<'a> {
    /// Full lengths of the three axes (twice the semi-axes) \[m\].
    pub lengths: &'a Vector3<f64>,
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
        super::components(["lengths[0]", "lengths[1]", "lengths[2]"], self.lengths)
    }
    fn non_negative_lengths(&self) -> Vec<(&'static str, f64)> {
        vec![]
    }
    fn hull_points(&self) -> Option<&'a [Point3<f64>]> {
        None
    }
    fn unit_mass_properties(&self) -> Option<UnitMassProperties> {
        let a = self.lengths * 0.5;
        let v = 4.0 / 3.0 * PI * a.x * a.y * a.z;
        let s = a.component_mul(&a);
        Some(UnitMassProperties {
            volume: v,
            com: Vector3::zeros(),
            inertia: Matrix3::from_diagonal(
                &(Vector3::new(s.y + s.z, s.x + s.z, s.x + s.y) * (v / 5.0)),
            ),
        })
    }
    fn smoothed_width(&self) -> Result<Option<f64>, GeometryError> {
        Ok(None)
    }
    fn core(&self, _r: f64) -> Result<(CoreShape, f64), GeometryError> {
        Ok((
            CoreShape::Ellipsoid {
                semi_axes: 0.5 * self.lengths,
            },
            0.0,
        ))
    }
    fn volume_solid(&self) -> Result<VolumeLaw, GeometryError> {
        Ok(VolumeLaw::None)
    }
    fn contact_radius(&self) -> (f64, bool) {
        (0.5 * self.lengths.min(), false)
    }
    fn display_mesh(&self) -> TriMesh {
        lathe(Axis::Y, &arc(1.0, 0.0, 0.0, PI, RINGS), self.lengths / 2.0)
    }
    fn display_primitive(&self) -> Option<Primitive> {
        Some(Primitive::Ball {
            radius: 0.5,
            scaling: Some(*self.lengths),
        })
    }
}
