//! Revolute joint: rotation of obj2 relative to obj1 about a unit axis fixed in both;
//! position `phi` \[rad\], velocity `w` [rad/s] (`phi̇ = w`). `S = (axis, 0)` is constant.

use super::{Checker, Coordinate, KindInfo, SignalSpec, Source, ValidJointKind};
#[cfg(feature = "solver")]
use crate::joints::rows::Row;
#[cfg(feature = "solver")]
use crate::spatial::{axis_angle, Force, Motion, Transform};
#[cfg(feature = "solver")]
use nalgebra::Vector3;

/// Signals: `phi` \[rad\], `w` [rad/s].
pub(crate) const SIGNALS: &[SignalSpec] = &[
    SignalSpec {
        name: "phi",
        unit: "rad",
        dim: 1,
        source: Source::Q(0),
    },
    SignalSpec {
        name: "w",
        unit: "rad/s",
        dim: 1,
        source: Source::V(0),
    },
];

/// One scalar coordinate; reversible (the axis is negated).
pub(crate) const INFO: KindInfo = KindInfo {
    coordinates: &[Coordinate {
        name: "phi",
        unit: "rad",
        q: 0,
        v: 0,
    }],
    reversible: true,
};

/// `X_J`: rotation by `q[0]` about `axis`.
#[cfg(feature = "solver")]
#[inline]
pub(crate) fn transform(axis: &Vector3<f64>, q: &[f64]) -> Transform {
    Transform {
        rot: axis_angle(axis, q[0]),
        pos: Vector3::zeros(),
    }
}

/// `S v`.
#[cfg(feature = "solver")]
#[inline]
pub(crate) fn motion(axis: &Vector3<f64>, v: &[f64]) -> Motion {
    Motion {
        w: axis * v[0],
        v: Vector3::zeros(),
    }
}

/// `Sᵀ f`: the torque about the axis.
#[cfg(feature = "solver")]
#[inline]
pub(crate) fn project(axis: &Vector3<f64>, f: &Force, tau: &mut [f64]) {
    tau[0] = axis.dot(&f.n);
}

/// Validation of the builder's parameters (solver-free): unit axis, finite initial values.
pub(crate) fn validate(
    c: &mut Checker,
    joint: &str,
    axis: &nalgebra::Vector3<f64>,
    phi: f64,
    w: f64,
) -> ValidJointKind {
    c.finite(
        || format!("joint `{joint}`: initial phi [rad], w [rad/s]"),
        &[phi, w],
    );
    ValidJointKind::Revolute {
        axis: super::unit_axis(c, joint, axis),
        phi,
        w,
    }
}

/// The rows a cut Revolute locks: the three translations and the two alignments of its axis.
#[cfg(feature = "solver")]
pub(crate) fn locked_rows(axis: &nalgebra::Vector3<f64>) -> Vec<Row> {
    let mut r = Row::translations(&[
        nalgebra::Vector3::x(),
        nalgebra::Vector3::y(),
        nalgebra::Vector3::z(),
    ]);
    r.extend(Row::alignments(axis));
    r
}
