//! Cylinder: a circular cylinder along `axis`, centred at the origin. Smoothed: its core is the
//! frustum shrunk by the smoothing radius; its volume-law solid is a frustum.

use super::{KindGeometry, VolumeLaw};
use crate::geometry::display_mesh::{lathe, Primitive, TriMesh};
use crate::geometry::error::GeometryError;
use crate::geometry::overlap::Frustum;
use crate::geometry::shape_kind::ShapeKind;
use crate::geometry::shape_spec::{ShapeKindSpec, AXIS_DIAMETER_LENGTH};
use crate::geometry::shapes::{Axis, Shape};
use crate::geometry::support::CoreShape;
use crate::geometry::UnitMassProperties;
use nalgebra::{Point3, Vector3};
use std::f64::consts::PI;

/// The row of [`SHAPE_KINDS`](crate::geometry::SHAPE_KINDS).
pub(crate) const ROW: ShapeKindSpec = ShapeKindSpec {
    name: "Cylinder",
    kind: ShapeKind::Cylinder,
    params: AXIS_DIAMETER_LENGTH,
    stand_in: Some(|v| Shape::Cylinder {
        axis: v.axis("axis"),
        diameter: v.length("diameter"),
        length: v.length("length"),
    }),
};

/// The fields of a [`Shape::Cylinder`].
pub(crate) struct Params<'a> {
    /// Axis of the cylinder.
    pub axis: &'a Axis,
    /// Diameter \[m\].
    pub diameter: &'a f64,
    /// Length along the axis \[m\].
    pub length: &'a f64,
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
        vec![("diameter", *self.diameter), ("length", *self.length)]
    }
    fn non_negative_lengths(&self) -> Vec<(&'static str, f64)> {
        vec![]
    }
    fn hull_points(&self) -> Option<&'a [Point3<f64>]> {
        None
    }
    fn unit_mass_properties(&self) -> Option<UnitMassProperties> {
        let (diameter, length) = (self.diameter, self.length);
        let r = 0.5 * diameter;
        let v = PI * r * r * length;
        Some(UnitMassProperties {
            volume: v,
            com: Vector3::zeros(),
            inertia: super::axisymmetric(
                *self.axis,
                0.5 * v * r * r,
                v * (3.0 * r * r + length * length) / 12.0,
            ),
        })
    }
    fn smoothed_width(&self) -> Result<Option<f64>, GeometryError> {
        Ok(Some(self.diameter.min(*self.length)))
    }
    fn core(&self, r: f64) -> Result<(CoreShape, f64), GeometryError> {
        let (diameter, length) = (self.diameter, self.length);
        Ok((
            CoreShape::Frustum {
                axis: *self.axis,
                z0: -0.5 * length + r,
                z1: 0.5 * length - r,
                r0: 0.5 * diameter - r,
                r1: 0.5 * diameter - r,
            },
            r,
        ))
    }
    /// A frustum, centred: `z0 = −length/2`, `z1 = length/2`, `r0 = r1 = diameter/2`.
    fn volume_solid(&self) -> Result<VolumeLaw, GeometryError> {
        let (diameter, length) = (*self.diameter, *self.length);
        Ok(VolumeLaw::Frustum(Frustum {
            axis: *self.axis,
            z0: -0.5 * length,
            z1: 0.5 * length,
            r0: 0.5 * diameter,
            r1: 0.5 * diameter,
        }))
    }
    fn contact_radius(&self) -> (f64, bool) {
        (0.5 * self.diameter.min(*self.length), false)
    }
    fn display_mesh(&self) -> TriMesh {
        let one = Vector3::new(1.0, 1.0, 1.0);
        let (r, h) = (self.diameter / 2.0, self.length / 2.0);
        lathe(*self.axis, &[(0.0, -h), (r, -h), (r, h), (0.0, h)], one)
    }
    fn display_primitive(&self) -> Option<Primitive> {
        Some(Primitive::Frustum {
            axis: *self.axis,
            top: self.diameter / 2.0,
            bottom: self.diameter / 2.0,
            length: *self.length,
            lift: 0.0,
        })
    }
}
