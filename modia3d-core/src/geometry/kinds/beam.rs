//! Beam (Modia3D's `Beam`): a box with two half-cylinder ends, centred at the origin: `length`
//! (the box part only; the total length is `length + width`) along `axis`, `width` (= the
//! diameter of the ends) along the next axis cyclically and `thickness` along the one after
//! (see `geometry::shapes`). Smoothed (the length is not counted in the bound: the straight part
//! is not shrunk); its volume-law solid is the polytope with the rounded ends as inscribed
//! polygons, so its volume law's unsmoothed collision shape is that polytope's hull; it counts
//! as flat for the contact radius.

use super::{KindGeometry, VolumeLaw};
use crate::geometry::display_mesh::{hull_mesh, Primitive, TriMesh, SEGMENTS};
use crate::geometry::error::GeometryError;
use crate::geometry::overlap::polytope::beam_points;
use crate::geometry::overlap::Polytope;
use crate::geometry::shape_kind::ShapeKind;
use crate::geometry::shape_spec::{param, ShapeKindSpec, ShapeValue, AXIS};
use crate::geometry::shapes::{Axis, Shape};
use crate::geometry::support::CoreShape;
use crate::geometry::UnitMassProperties;
use nalgebra::{Matrix3, Point3, Vector3};
use std::f64::consts::PI;

/// The row of [`SHAPE_KINDS`](crate::geometry::SHAPE_KINDS).
pub(crate) const ROW: ShapeKindSpec = ShapeKindSpec {
    name: "Beam",
    kind: ShapeKind::Beam,
    params: &[
        AXIS,
        param("length", ShapeValue::Length, "m"),
        param("width", ShapeValue::Length, "m"),
        param("thickness", ShapeValue::Length, "m"),
    ],
    stand_in: Some(|v| Shape::Beam {
        axis: v.axis("axis"),
        length: v.length("length"),
        width: v.length("width"),
        thickness: v.length("thickness"),
    }),
};

/// The fields of a [`Shape::Beam`].
pub(crate) struct Params<'a> {
    /// Longitudinal axis.
    pub axis: &'a Axis,
    /// Length of the box part along `axis` \[m\].
    pub length: &'a f64,
    /// Width = diameter of the half-cylinder ends \[m\].
    pub width: &'a f64,
    /// Thickness, along the ends' cylinder axes \[m\].
    pub thickness: &'a f64,
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
        vec![
            ("length", *self.length),
            ("width", *self.width),
            ("thickness", *self.thickness),
        ]
    }
    fn non_negative_lengths(&self) -> Vec<(&'static str, f64)> {
        vec![]
    }
    fn hull_points(&self) -> Option<&'a [Point3<f64>]> {
        None
    }
    fn unit_mass_properties(&self) -> Option<UnitMassProperties> {
        Some(mass_properties(
            *self.axis,
            *self.length,
            *self.width,
            *self.thickness,
        ))
    }
    fn smoothed_width(&self) -> Result<Option<f64>, GeometryError> {
        Ok(Some(self.width.min(*self.thickness)))
    }
    fn core(&self, r: f64) -> Result<(CoreShape, f64), GeometryError> {
        Ok((
            CoreShape::Beam {
                axis: *self.axis,
                half_length: 0.5 * self.length,
                half_thickness: 0.5 * self.thickness - r,
                radius: 0.5 * self.width - r,
            },
            r,
        ))
    }
    /// The polytope with the rounded ends as inscribed polygons (`beam_points`).
    fn volume_solid(&self) -> Result<VolumeLaw, GeometryError> {
        for (name, value) in self.dimensions() {
            if !(value.is_finite() && value > 0.0) {
                return Err(GeometryError::InvalidDimension { name, value });
            }
        }
        Polytope::from_points(&beam_points(
            *self.axis,
            *self.length,
            *self.width,
            *self.thickness,
        ))
        .map(|polytope| VolumeLaw::Polytope {
            polytope,
            inscribed: true,
        })
    }
    /// Its flat faces are what it usually rests on.
    fn contact_radius(&self) -> (f64, bool) {
        (0.5 * self.width.min(*self.thickness), true)
    }
    fn display_mesh(&self) -> TriMesh {
        hull_mesh(&display_points(
            *self.axis,
            *self.length,
            *self.width,
            *self.thickness,
        ))
    }
    fn display_primitive(&self) -> Option<Primitive> {
        None
    }
}

/// Exact mass properties of a beam of unit density: box `l × w × t` plus two half-cylinders
/// (radius `w/2`, height `t`) whose flat faces are the box's end faces. With `u`, `v`, `s` the
/// length, width and thickness coordinates, the second moments `∫u²`, `∫v²`, `∫s²` are summed
/// over the parts; a half-disk of radius `r` (area `A = πr²/2`) with its flat side on
/// `u = l/2` has `∫u² dA = A (l²/4 + l·4r/(3π) + r²/4)` and `∫v² dA = A r²/4`. All products of
/// inertia vanish (the beam is symmetric in every coordinate plane).
fn mass_properties(axis: Axis, l: f64, w: f64, t: f64) -> UnitMassProperties {
    let r = 0.5 * w;
    let v_box = l * w * t;
    let v_ends = PI * r * r * t; // both half-cylinders
    let s_u = v_box * l * l / 12.0
        + v_ends * (0.25 * l * l + 0.25 * r * r)
        + 4.0 / 3.0 * l * r.powi(3) * t;
    let s_v = v_box * w * w / 12.0 + v_ends * 0.25 * r * r;
    let s_s = (v_box + v_ends) * t * t / 12.0;
    let (kw, kt) = axis.beam_directions();
    let mut d = Vector3::zeros();
    d[axis.index()] = s_v + s_s;
    d[kw] = s_u + s_s;
    d[kt] = s_u + s_v;
    UnitMassProperties {
        volume: v_box + v_ends,
        com: Vector3::zeros(),
        inertia: Matrix3::from_diagonal(&d),
    }
}

/// Points whose convex hull is a beam with each half-disk end drawn as `SEGMENTS / 2`
/// chords (vertices on the circle).
fn display_points(axis: Axis, length: f64, width: f64, thickness: f64) -> Vec<Point3<f64>> {
    let (k, (kw, kt)) = (axis.index(), axis.beam_directions());
    let (r, n) = (width / 2.0, SEGMENTS / 2);
    let mut pts = Vec::with_capacity(4 * (n + 1));
    for end in [-1.0, 1.0] {
        for i in 0..=n {
            let phi = std::f64::consts::PI * (i as f64 / n as f64 - 0.5);
            for s in [-1.0, 1.0] {
                let mut p = Point3::origin();
                p[k] = end * (length / 2.0 + r * phi.cos());
                p[kw] = r * phi.sin();
                p[kt] = s * thickness / 2.0;
                pts.push(p);
            }
        }
    }
    pts
}
