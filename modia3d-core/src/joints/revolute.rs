//! Revolute joint: rotation of obj2 relative to obj1 about a unit axis fixed in both;
//! position `phi` [rad], velocity `w` [rad/s] (`phi̇ = w`). `S = (axis, 0)` is constant.

use super::{Coordinate, KindInfo, SignalSpec, Source};
#[cfg(feature = "solver")]
use crate::dynamics::spatial::{axis_angle, Force, Motion, Transform};
#[cfg(feature = "solver")]
use nalgebra::Vector3;

/// Signals: `phi` [rad], `w` [rad/s].
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
