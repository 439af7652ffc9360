//! Prismatic joint: translation of obj2 relative to obj1 along a unit axis fixed in both;
//! position `s` \[m\], velocity `v` [m/s] (`ṡ = v`). `S = (0, axis)` is constant.

use super::{Checker, Coordinate, KindInfo, SignalSpec, Source, ValidJointKind};
#[cfg(feature = "solver")]
use crate::joints::rows::Row;
#[cfg(feature = "solver")]
use crate::spatial::{Force, Motion, Transform};
#[cfg(feature = "solver")]
use nalgebra::{Matrix3, Vector3};

/// Signals: `s` \[m\], `v` [m/s].
pub(crate) const SIGNALS: &[SignalSpec] = &[
    SignalSpec {
        name: "s",
        unit: "m",
        dim: 1,
        source: Source::Q(0),
    },
    SignalSpec {
        name: "v",
        unit: "m/s",
        dim: 1,
        source: Source::V(0),
    },
];

/// One scalar coordinate; reversible (the axis is negated).
pub(crate) const INFO: KindInfo = KindInfo {
    coordinates: &[Coordinate {
        name: "s",
        unit: "m",
        q: 0,
        v: 0,
    }],
    reversible: true,
};

/// `X_J`: translation by `q[0]` along `axis`.
#[cfg(feature = "solver")]
#[inline]
pub(crate) fn transform(axis: &Vector3<f64>, q: &[f64]) -> Transform {
    Transform {
        rot: Matrix3::identity(),
        pos: axis * q[0],
    }
}

/// `S v`.
#[cfg(feature = "solver")]
#[inline]
pub(crate) fn motion(axis: &Vector3<f64>, v: &[f64]) -> Motion {
    Motion {
        w: Vector3::zeros(),
        v: axis * v[0],
    }
}

/// `Sᵀ f`: the force along the axis.
#[cfg(feature = "solver")]
#[inline]
pub(crate) fn project(axis: &Vector3<f64>, f: &Force, tau: &mut [f64]) {
    tau[0] = axis.dot(&f.f);
}

/// Validation of the builder's parameters (solver-free): unit axis, finite initial values.
pub(crate) fn validate(
    c: &mut Checker,
    joint: &str,
    axis: &nalgebra::Vector3<f64>,
    s: f64,
    v: f64,
) -> ValidJointKind {
    c.finite(
        || format!("joint `{joint}`: initial s [m], v [m/s]"),
        &[s, v],
    );
    ValidJointKind::Prismatic {
        axis: super::unit_axis(c, joint, axis),
        s,
        v,
    }
}

/// The rows a cut Prismatic locks: the two translations across its axis and the three
/// rotations.
#[cfg(feature = "solver")]
pub(crate) fn locked_rows(axis: &nalgebra::Vector3<f64>) -> Vec<Row> {
    let (u, w) = crate::joints::rows::perpendiculars(axis);
    let mut r = Row::translations(&[u, w]);
    r.extend(Row::rotations());
    r
}
