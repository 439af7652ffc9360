//! Cylindrical joint: rotation `phi` \[rad\] about and translation `s` \[m\] along one unit axis
//! fixed in both objects; velocities `w` [rad/s], `v` [m/s] (`phi̇ = w`, `ṡ = v`).
//! `S = [(axis, 0), (0, axis)]` is constant (the axis is invariant under the rotation).

use super::{Checker, Coordinate, KindInfo, SignalSpec, Source, ValidJointKind};
#[cfg(feature = "solver")]
use crate::joints::rows::Row;
#[cfg(feature = "solver")]
use crate::spatial::{axis_angle, Force, Motion, Transform};
#[cfg(feature = "solver")]
use nalgebra::Vector3;

/// Signals: `phi` \[rad\], `s` \[m\], `w` [rad/s], `v` [m/s].
pub(crate) const SIGNALS: &[SignalSpec] = &[
    SignalSpec {
        name: "phi",
        unit: "rad",
        dim: 1,
        source: Source::Q(0),
    },
    SignalSpec {
        name: "s",
        unit: "m",
        dim: 1,
        source: Source::Q(1),
    },
    SignalSpec {
        name: "w",
        unit: "rad/s",
        dim: 1,
        source: Source::V(0),
    },
    SignalSpec {
        name: "v",
        unit: "m/s",
        dim: 1,
        source: Source::V(1),
    },
];

/// Two scalar coordinates; reversible (the axis is negated).
pub(crate) const INFO: KindInfo = KindInfo {
    coordinates: &[
        Coordinate {
            name: "phi",
            unit: "rad",
            q: 0,
            v: 0,
        },
        Coordinate {
            name: "s",
            unit: "m",
            q: 1,
            v: 1,
        },
    ],
    reversible: true,
};

/// `X_J`: rotation by `phi` about and translation by `s` along `axis`.
#[cfg(feature = "solver")]
#[inline]
pub(crate) fn transform(axis: &Vector3<f64>, q: &[f64]) -> Transform {
    Transform {
        rot: axis_angle(axis, q[0]),
        pos: axis * q[1],
    }
}

/// `S v = (axis w, axis v)`.
#[cfg(feature = "solver")]
#[inline]
pub(crate) fn motion(axis: &Vector3<f64>, v: &[f64]) -> Motion {
    Motion {
        w: axis * v[0],
        v: axis * v[1],
    }
}

/// `Sᵀ f`: torque about and force along the axis.
#[cfg(feature = "solver")]
#[inline]
pub(crate) fn project(axis: &Vector3<f64>, f: &Force, tau: &mut [f64]) {
    tau[0] = axis.dot(&f.n);
    tau[1] = axis.dot(&f.f);
}

/// Validation of the builder's parameters (solver-free): unit axis, finite initial values.
pub(crate) fn validate(
    c: &mut Checker,
    joint: &str,
    axis: &nalgebra::Vector3<f64>,
    [phi, s, w, v]: [f64; 4],
) -> ValidJointKind {
    c.finite(
        || format!("joint `{joint}`: initial phi [rad], s [m], w [rad/s], v [m/s]"),
        &[phi, s, w, v],
    );
    ValidJointKind::Cylindrical {
        axis: super::unit_axis(c, joint, axis),
        phi,
        s,
        w,
        v,
    }
}

/// The rows a cut Cylindrical locks: the two translations across its axis and the two
/// alignments of the axis.
#[cfg(feature = "solver")]
pub(crate) fn locked_rows(axis: &nalgebra::Vector3<f64>) -> Vec<Row> {
    let (u, w) = crate::joints::rows::perpendiculars(axis);
    let mut r = Row::translations(&[u, w]);
    r.extend(Row::alignments(axis));
    r
}
