//! Capsule: a cylinder with hemispherical caps along `axis`, centred at the origin; `length` is
//! the cylindrical part's (the total length is `length + diameter`). Smooth (no smoothing): its
//! core is its axis segment, its margin its radius (what makes MPR exact for it); it has no
//! volume-law solid (it keeps a point law).

use super::{KindGeometry, VolumeLaw};
use crate::geometry::display_mesh::{arc, lathe, Primitive, TriMesh, RINGS};
use crate::geometry::error::GeometryError;
use crate::geometry::shape_kind::ShapeKind;
use crate::geometry::shape_spec::{ShapeKindSpec, AXIS_DIAMETER_LENGTH};
use crate::geometry::shapes::{Axis, Shape};
use crate::geometry::support::CoreShape;
use crate::geometry::UnitMassProperties;
use nalgebra::{Point3, Vector3};
use std::f64::consts::{FRAC_PI_2, PI};

/// The row of [`SHAPE_KINDS`](crate::geometry::SHAPE_KINDS).
pub(crate) const ROW: ShapeKindSpec = ShapeKindSpec {
    name: "Capsule",
    kind: ShapeKind::Capsule,
    params: AXIS_DIAMETER_LENGTH,
    stand_in: Some(|v| Shape::Capsule {
        axis: v.axis("axis"),
        diameter: v.length("diameter"),
        length: v.length("length"),
    }),
};

/// The fields of a [`Shape::Capsule`].
pub(crate) struct Params<'a> {
    /// Axis of the capsule.
    pub axis: &'a Axis,
    /// Diameter of the cylinder and caps \[m\].
    pub diameter: &'a f64,
    /// Length of the cylindrical part, without the caps \[m\].
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
        let r = 0.5 * self.diameter;
        let l = *self.length;
        let vc = PI * r * r * l; // cylinder
                                 // One hemisphere: centroid 3r/8 from its flat face, transverse inertia about its
                                 // centroid 83/320 m r², axial 2/5 m r².
        let vh = 2.0 / 3.0 * PI * r.powi(3);
        let d = 0.5 * l + 3.0 * r / 8.0;
        let axial = 0.5 * vc * r * r + 2.0 * 0.4 * vh * r * r;
        let transverse =
            vc * (3.0 * r * r + l * l) / 12.0 + 2.0 * (83.0 / 320.0 * vh * r * r + vh * d * d);
        Some(UnitMassProperties {
            volume: vc + 2.0 * vh,
            com: Vector3::zeros(),
            inertia: super::axisymmetric(*self.axis, axial, transverse),
        })
    }
    fn smoothed_width(&self) -> Result<Option<f64>, GeometryError> {
        Ok(None)
    }
    fn core(&self, _r: f64) -> Result<(CoreShape, f64), GeometryError> {
        Ok((
            CoreShape::Segment {
                axis: *self.axis,
                half_length: 0.5 * self.length,
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
        let (r, h) = (self.diameter / 2.0, self.length / 2.0);
        let mut p = arc(r, -h, 0.0, FRAC_PI_2, RINGS / 2);
        p.extend(arc(r, h, FRAC_PI_2, PI, RINGS / 2));
        lathe(*self.axis, &p, one)
    }
    fn display_primitive(&self) -> Option<Primitive> {
        Some(Primitive::Capsule {
            axis: *self.axis,
            radius: self.diameter / 2.0,
            length: *self.length,
        })
    }
}
