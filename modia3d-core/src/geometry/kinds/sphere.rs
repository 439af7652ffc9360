//! Sphere: a ball of diameter `diameter`, centred at the origin. Smooth (no smoothing): its core
//! is its centre, its margin its radius (what makes MPR exact for it); it has no volume-law
//! solid (a sphere pair keeps the paper's point law).

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
    name: "Sphere",
    kind: ShapeKind::Sphere,
    params: &[param("diameter", ShapeValue::Length, "m")],
    stand_in: Some(|v| Shape::Sphere {
        diameter: v.length("diameter"),
    }),
};

/// The fields of a [`Shape::Sphere`].
pub(crate) struct Params<'a> {
    /// Diameter \[m\].
    pub diameter: &'a f64,
}

impl<'a> KindGeometry<'a> for Params<'a> {
    fn load(&self) -> Result<Option<Shape>, GeometryError> {
        Ok(None)
    }
    fn collision_parts(&self) -> Option<Vec<Shape>> {
        None
    }
    fn ball_diameter(&self) -> Option<f64> {
        Some(*self.diameter)
    }
    fn dimensions(&self) -> Vec<(&'static str, f64)> {
        vec![("diameter", *self.diameter)]
    }
    fn non_negative_lengths(&self) -> Vec<(&'static str, f64)> {
        vec![]
    }
    fn hull_points(&self) -> Option<&'a [Point3<f64>]> {
        None
    }
    fn unit_mass_properties(&self) -> Option<UnitMassProperties> {
        let r = 0.5 * self.diameter;
        let v = 4.0 / 3.0 * PI * r.powi(3);
        Some(UnitMassProperties {
            volume: v,
            com: Vector3::zeros(),
            inertia: Matrix3::identity() * (0.4 * v * r * r),
        })
    }
    fn smoothed_width(&self) -> Result<Option<f64>, GeometryError> {
        Ok(None)
    }
    fn core(&self, _r: f64) -> Result<(CoreShape, f64), GeometryError> {
        Ok((
            CoreShape::Point {
                centre: Point3::origin(),
            },
            0.5 * self.diameter,
        ))
    }
    fn volume_solid(&self) -> Result<VolumeLaw, GeometryError> {
        Ok(VolumeLaw::None)
    }
    fn contact_radius(&self) -> (f64, bool) {
        (0.5 * self.diameter, false)
    }
    fn display_mesh(&self) -> TriMesh {
        let one = Vector3::new(1.0, 1.0, 1.0);
        lathe(Axis::Y, &arc(self.diameter / 2.0, 0.0, 0.0, PI, RINGS), one)
    }
    fn display_primitive(&self) -> Option<Primitive> {
        Some(Primitive::Ball {
            radius: self.diameter / 2.0,
            scaling: None,
        })
    }
}
