//! Universal (Cardan, Hooke) joint: rotation `phi1` about `axis1`, fixed in obj1, then `phi2`
//! about `axis2`, fixed in obj2; the axes are perpendicular (they cross at the joint centre, the
//! common origin). `R = Rot(axis1, phi1) · Rot(axis2, phi2)`. Positions `phi1`, `phi2` \[rad\],
//! velocities `w1`, `w2` [rad/s]. Resolved in obj2, `ω = Rot(axis2, phi2)ᵀ axis1 · w1 +
//! axis2 · w2`: `S` depends on `phi2`, so `c_J = w1 w2 (Rot(axis2, phi2)ᵀ axis1) × axis2`.

use super::{Checker, Coordinate, KindInfo, SignalSpec, Source, ValidJointKind};
#[cfg(feature = "solver")]
use crate::joints::rows::Row;
#[cfg(feature = "solver")]
use crate::spatial::{axis_angle, Force, Motion, Transform};
#[cfg(feature = "solver")]
use nalgebra::Vector3;

/// Signals: `phi1`, `phi2` \[rad\], `w1`, `w2` [rad/s].
pub(crate) const SIGNALS: &[SignalSpec] = &[
    SignalSpec {
        name: "phi1",
        unit: "rad",
        dim: 1,
        source: Source::Q(0),
    },
    SignalSpec {
        name: "phi2",
        unit: "rad",
        dim: 1,
        source: Source::Q(1),
    },
    SignalSpec {
        name: "w1",
        unit: "rad/s",
        dim: 1,
        source: Source::V(0),
    },
    SignalSpec {
        name: "w2",
        unit: "rad/s",
        dim: 1,
        source: Source::V(1),
    },
];

/// Two scalar coordinates; not reversible (traversed from obj2 the first axis would be the
/// one fixed in the child).
pub(crate) const INFO: KindInfo = KindInfo {
    coordinates: &[
        Coordinate {
            name: "phi1",
            unit: "rad",
            q: 0,
            v: 0,
        },
        Coordinate {
            name: "phi2",
            unit: "rad",
            q: 1,
            v: 1,
        },
    ],
    reversible: false,
};

/// `axis1` resolved in the child frame at `phi2`: the first column of `S`'s angular part.
#[cfg(feature = "solver")]
#[inline]
fn axis1_in_child(axis1: &Vector3<f64>, axis2: &Vector3<f64>, phi2: f64) -> Vector3<f64> {
    axis_angle(axis2, phi2).tr_mul(axis1)
}

/// `X_J`: `Rot(axis1, phi1) · Rot(axis2, phi2)`.
#[cfg(feature = "solver")]
#[inline]
pub(crate) fn transform(axis1: &Vector3<f64>, axis2: &Vector3<f64>, q: &[f64]) -> Transform {
    Transform {
        rot: axis_angle(axis1, q[0]) * axis_angle(axis2, q[1]),
        pos: Vector3::zeros(),
    }
}

/// `S(q) v`.
#[cfg(feature = "solver")]
#[inline]
pub(crate) fn motion(axis1: &Vector3<f64>, axis2: &Vector3<f64>, q: &[f64], v: &[f64]) -> Motion {
    Motion {
        w: axis1_in_child(axis1, axis2, q[1]) * v[0] + axis2 * v[1],
        v: Vector3::zeros(),
    }
}

/// `c_J = Ṡ(q) v`: only the first column turns, at `w2` about `axis2`.
#[cfg(feature = "solver")]
#[inline]
pub(crate) fn bias(axis1: &Vector3<f64>, axis2: &Vector3<f64>, q: &[f64], v: &[f64]) -> Motion {
    Motion {
        w: axis1_in_child(axis1, axis2, q[1]).cross(axis2) * (v[0] * v[1]),
        v: Vector3::zeros(),
    }
}

/// `Sᵀ f`: the moments about the two axes.
#[cfg(feature = "solver")]
#[inline]
pub(crate) fn project(
    axis1: &Vector3<f64>,
    axis2: &Vector3<f64>,
    q: &[f64],
    f: &Force,
    tau: &mut [f64],
) {
    tau[0] = axis1_in_child(axis1, axis2, q[1]).dot(&f.n);
    tau[1] = axis2.dot(&f.n);
}

/// Largest admissible `|cos|` of the angle between the axes (as a quaternion's norm: rounded
/// literal digits pass, a wrong axis does not).
const PERPENDICULAR_TOLERANCE: f64 = 1e-6;

/// Validation of the builder's parameters (solver-free): unit, perpendicular axes (made
/// exactly perpendicular), finite initial values.
#[allow(clippy::too_many_arguments)]
pub(crate) fn validate(
    c: &mut Checker,
    joint: &str,
    axis1: &nalgebra::Vector3<f64>,
    axis2: &nalgebra::Vector3<f64>,
    phi1: f64,
    phi2: f64,
    w1: f64,
    w2: f64,
) -> ValidJointKind {
    c.finite(
        || format!("joint `{joint}`: initial phi1, phi2 [rad], w1, w2 [rad/s]"),
        &[phi1, phi2, w1, w2],
    );
    let a1 = super::unit_axis(c, joint, axis1);
    let a2 = super::unit_axis(c, joint, axis2);
    let cos = a1.dot(&a2);
    if cos.is_finite() && cos.abs() > PERPENDICULAR_TOLERANCE {
        c.errors.push(crate::scene::SceneError::InvalidValue {
            what: format!("joint `{joint}`: cosine of the angle between axis1 and axis2"),
            value: cos,
            expected: "0 within 1e-6 (a universal joint's axes are perpendicular)",
        });
    }
    ValidJointKind::Universal {
        axis1: a1,
        // Exactly perpendicular from here on (the joint is dropped if the check failed).
        axis2: (a2 - a1 * cos).normalize(),
        phi1,
        phi2,
        w1,
        w2,
    }
}

/// The rows a cut Universal locks: the three translations and `axis2` kept perpendicular to
/// `axis1`.
#[cfg(feature = "solver")]
pub(crate) fn locked_rows(
    axis1: &nalgebra::Vector3<f64>,
    axis2: &nalgebra::Vector3<f64>,
) -> Vec<Row> {
    let mut r = Row::translations(&[
        nalgebra::Vector3::x(),
        nalgebra::Vector3::y(),
        nalgebra::Vector3::z(),
    ]);
    r.push(Row::Align {
        u: *axis1,
        a: *axis2,
    });
    r
}
