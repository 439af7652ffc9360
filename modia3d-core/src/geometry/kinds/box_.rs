//! Box: edge lengths `lengths` along x, y, z, centred at the origin. Smoothed: its core is the
//! box shrunk by the smoothing radius; its volume-law solid is itself, a polytope; it counts as
//! flat for the contact radius.

use super::{KindGeometry, VolumeLaw};
use crate::geometry::display_mesh::{Primitive, TriMesh};
use crate::geometry::error::GeometryError;
use crate::geometry::overlap::Polytope;
use crate::geometry::shape_kind::ShapeKind;
use crate::geometry::shape_spec::{param, ShapeKindSpec, ShapeValue};
use crate::geometry::shapes::Shape;
use crate::geometry::support::CoreShape;
use crate::geometry::UnitMassProperties;
use nalgebra::{Matrix3, Point3, Vector3};

/// The row of [`SHAPE_KINDS`](crate::geometry::SHAPE_KINDS).
pub(crate) const ROW: ShapeKindSpec = ShapeKindSpec {
    name: "Box",
    kind: ShapeKind::Box,
    params: &[param("lengths", ShapeValue::Lengths, "m")],
    stand_in: Some(|v| Shape::Box {
        lengths: v.vector("lengths"),
    }),
};

/// The fields of a [`Shape::Box`].
pub(crate) struct Params<'a> {
    /// Edge lengths along x, y, z \[m\].
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
        let l = self.lengths;
        let v = l.x * l.y * l.z;
        let s = l.component_mul(l);
        Some(UnitMassProperties {
            volume: v,
            com: Vector3::zeros(),
            inertia: Matrix3::from_diagonal(
                &(Vector3::new(s.y + s.z, s.x + s.z, s.x + s.y) * (v / 12.0)),
            ),
        })
    }
    fn smoothed_width(&self) -> Result<Option<f64>, GeometryError> {
        Ok(Some(self.lengths.min()))
    }
    fn core(&self, r: f64) -> Result<(CoreShape, f64), GeometryError> {
        Ok((
            CoreShape::Box {
                half_extents: 0.5 * self.lengths - Vector3::repeat(r),
            },
            r,
        ))
    }
    fn volume_solid(&self) -> Result<VolumeLaw, GeometryError> {
        for &l in self.lengths.iter() {
            if !(l.is_finite() && l > 0.0) {
                return Err(GeometryError::InvalidDimension {
                    name: "lengths",
                    value: l,
                });
            }
        }
        Ok(VolumeLaw::Polytope {
            polytope: Polytope::from_box(self.lengths / 2.0),
            inscribed: false,
        })
    }
    fn contact_radius(&self) -> (f64, bool) {
        (0.5 * self.lengths.min(), true)
    }
    fn display_mesh(&self) -> TriMesh {
        let h = self.lengths / 2.0;
        let c = |i: usize| {
            Vector3::new(
                if i & 1 == 0 { -h.x } else { h.x },
                if i & 2 == 0 { -h.y } else { h.y },
                if i & 4 == 0 { -h.z } else { h.z },
            )
        };
        let mut m = TriMesh::default();
        let centre = Vector3::zeros();
        // Faces as corner-index quads (bit 0 = x, bit 1 = y, bit 2 = z).
        for q in [
            [0, 2, 6, 4],
            [1, 3, 7, 5],
            [0, 1, 5, 4],
            [2, 3, 7, 6],
            [0, 1, 3, 2],
            [4, 5, 7, 6],
        ] {
            m.push(c(q[0]), c(q[1]), c(q[2]), &centre);
            m.push(c(q[0]), c(q[2]), c(q[3]), &centre);
        }
        m
    }
    fn display_primitive(&self) -> Option<Primitive> {
        Some(Primitive::Box {
            lengths: *self.lengths,
        })
    }
}
