//! Cone: a (truncated) cone along `axis`, its base circle (diameter `diameter`) in the plane
//! `axis = 0`, its top circle (diameter `top_diameter`, 0 for a pointed cone) at
//! `axis = length`. Smoothed: its core is the cone shrunk by the smoothing radius (the top
//! diameter is not counted in the bound); its volume-law solid is a frustum.

use super::{KindGeometry, VolumeLaw};
use crate::geometry::display_mesh::{lathe, Primitive, TriMesh};
use crate::geometry::error::GeometryError;
use crate::geometry::overlap::Frustum;
use crate::geometry::shape_kind::ShapeKind;
use crate::geometry::shape_spec::{param, ShapeKindSpec, ShapeParam, ShapeValue, AXIS};
use crate::geometry::shapes::{Axis, Shape};
use crate::geometry::support::CoreShape;
use crate::geometry::UnitMassProperties;
use nalgebra::{Point3, Vector3};
use std::f64::consts::PI;

/// The row of [`SHAPE_KINDS`](crate::geometry::SHAPE_KINDS).
pub(crate) const ROW: ShapeKindSpec = ShapeKindSpec {
    name: "Cone",
    kind: ShapeKind::Cone,
    params: &[
        AXIS,
        param("diameter", ShapeValue::Length, "m"),
        param("length", ShapeValue::Length, "m"),
        ShapeParam {
            required: false,
            ..param("top_diameter", ShapeValue::Length, "m")
        },
    ],
    stand_in: Some(|v| Shape::Cone {
        axis: v.axis("axis"),
        diameter: v.length("diameter"),
        length: v.length("length"),
        top_diameter: v.length("top_diameter"),
    }),
};

/// The fields of a [`Shape::Cone`].
pub(crate) struct Params<'a> {
    /// Axis of the cone.
    pub axis: &'a Axis,
    /// Diameter of the base \[m\].
    pub diameter: &'a f64,
    /// Height \[m\].
    pub length: &'a f64,
    /// Diameter of the top (0 for a pointed cone) \[m\].
    pub top_diameter: &'a f64,
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
    /// The top diameter, which may be 0, is a non-negative length.
    fn dimensions(&self) -> Vec<(&'static str, f64)> {
        vec![("diameter", *self.diameter), ("length", *self.length)]
    }
    fn non_negative_lengths(&self) -> Vec<(&'static str, f64)> {
        vec![("top_diameter", *self.top_diameter)]
    }
    fn hull_points(&self) -> Option<&'a [Point3<f64>]> {
        None
    }
    fn unit_mass_properties(&self) -> Option<UnitMassProperties> {
        // Frustum r(z) = a + b z, 0 ≤ z ≤ h: integrate z^m r^n exactly.
        let (a, h) = (0.5 * self.diameter, *self.length);
        let b = (0.5 * self.top_diameter - a) / h;
        let v = PI * poly_moment(a, b, h, 0, 2);
        let zc = PI * poly_moment(a, b, h, 1, 2) / v;
        let axial = 0.5 * PI * poly_moment(a, b, h, 0, 4);
        // About the base plane: ∫ (r⁴/4 + r² z²) π dz, then shift to the centroid.
        let trans_base = PI * (0.25 * poly_moment(a, b, h, 0, 4) + poly_moment(a, b, h, 2, 2));
        let mut com = Vector3::zeros();
        com[self.axis.index()] = zc;
        Some(UnitMassProperties {
            volume: v,
            com,
            inertia: super::axisymmetric(*self.axis, axial, trans_base - v * zc * zc),
        })
    }
    fn smoothed_width(&self) -> Result<Option<f64>, GeometryError> {
        Ok(Some(self.diameter.min(*self.length)))
    }
    fn core(&self, r: f64) -> Result<(CoreShape, f64), GeometryError> {
        Ok((
            shrunk_cone(
                *self.axis,
                *self.diameter,
                *self.length,
                *self.top_diameter,
                r,
            ),
            r,
        ))
    }
    /// A frustum: base at `z0 = 0` with radius `diameter/2`, top at `z1 = length` with radius
    /// `top_diameter/2`.
    fn volume_solid(&self) -> Result<VolumeLaw, GeometryError> {
        Ok(VolumeLaw::Frustum(Frustum {
            axis: *self.axis,
            z0: 0.0,
            z1: *self.length,
            r0: 0.5 * self.diameter,
            r1: 0.5 * self.top_diameter,
        }))
    }
    fn contact_radius(&self) -> (f64, bool) {
        (0.25 * (self.diameter + self.top_diameter), false)
    }
    fn display_mesh(&self) -> TriMesh {
        let one = Vector3::new(1.0, 1.0, 1.0);
        let (diameter, length, top_diameter) = (self.diameter, self.length, self.top_diameter);
        lathe(
            *self.axis,
            &[
                (0.0, 0.0),
                (diameter / 2.0, 0.0),
                (top_diameter / 2.0, *length),
                (0.0, *length),
            ],
            one,
        )
    }
    fn display_primitive(&self) -> Option<Primitive> {
        Some(Primitive::Frustum {
            axis: *self.axis,
            top: self.top_diameter / 2.0,
            bottom: self.diameter / 2.0,
            length: *self.length,
            lift: self.length / 2.0,
        })
    }
}

/// ∫₀ʰ zᵐ (a + b z)ⁿ dz, exactly, by the binomial expansion.
fn poly_moment(a: f64, b: f64, h: f64, m: i32, n: i32) -> f64 {
    let mut sum = 0.0;
    let mut binom = 1.0;
    for k in 0..=n {
        // term C(n,k) a^(n-k) b^k ∫ z^(m+k) dz
        let p = m + k + 1;
        sum += binom * a.powi(n - k) * b.powi(k) * h.powi(p) / f64::from(p);
        binom = binom * f64::from(n - k) / f64::from(k + 1);
    }
    sum
}

/// The core of a cone (or frustum) `diameter`, `length`, `top_diameter` shrunk by `r`: the base
/// plane moves up by `r`, the top plane down by `r`, the lateral line inwards by `r` (its
/// horizontal shift is `r·L/h` with `L` the slant length). If the shrunk lateral surface reaches
/// the axis below the shrunk top plane, the core is pointed there; then the rounded tip of the
/// outer shape lies `r(L/a − 1)` below the original apex (unavoidable when rounding a tip).
fn shrunk_cone(axis: Axis, diameter: f64, length: f64, top_diameter: f64, r: f64) -> CoreShape {
    let (a, b, h) = (0.5 * diameter, 0.5 * top_diameter, length);
    let slant = (h * h + (a - b) * (a - b)).sqrt();
    let radius_at = |z: f64| a + (b - a) * z / h - r * slant / h;
    let z0 = r;
    let mut z1 = h - r;
    let mut r1 = radius_at(z1);
    if r1 < 0.0 {
        // b < a here: solve radius_at(z) = 0.
        z1 = (r * slant - a * h) / (b - a);
        r1 = 0.0;
    }
    CoreShape::Frustum {
        axis,
        z0,
        z1,
        r0: radius_at(z0).max(0.0),
        r1,
    }
}
