//! Spherical joint (ball joint): rotation of obj2 relative to obj1 about their common origin.
//! Position: a unit quaternion `(w, x, y, z)` (4; no singular angles), whose norm is kept as
//! for FreeMotion; velocity: the angular velocity `ω` of obj2 relative to obj1, resolved in
//! obj2 (3, [rad/s]), so `S = (I, 0)` in the child frame and `c_J = 0`.

use super::{Checker, KindInfo, SignalSpec, Source, ValidJointKind};
#[cfg(feature = "solver")]
use crate::joints::rows::Row;
#[cfg(feature = "solver")]
use crate::spatial::{quat_to_matrix, Force, Motion, Transform};
#[cfg(feature = "solver")]
use nalgebra::{UnitQuaternion, Vector3};

/// Number of positions.
pub(crate) const NQ: usize = 4;
/// Number of velocities.
pub(crate) const NV: usize = 3;

/// Signals: `q` (quaternion of obj2 relative to obj1), `w` [rad/s] (resolved in obj2).
pub(crate) const SIGNALS: &[SignalSpec] = &[
    SignalSpec {
        name: "q",
        unit: "1",
        dim: 4,
        source: Source::Q(0),
    },
    SignalSpec {
        name: "w",
        unit: "rad/s",
        dim: 3,
        source: Source::V(0),
    },
];

/// No scalar coordinates; not reversible (obj1 must lie on the world side).
pub(crate) const INFO: KindInfo = KindInfo {
    coordinates: &[],
    reversible: false,
};

/// Initial quaternion and angular velocity (resolved in obj2).
#[cfg(feature = "solver")]
pub(crate) fn initial(
    rot: &UnitQuaternion<f64>,
    w: &Vector3<f64>,
    q0: &mut Vec<f64>,
    v0: &mut Vec<f64>,
) {
    q0.extend_from_slice(&[rot.w, rot.i, rot.j, rot.k]);
    v0.extend_from_slice(w.as_slice());
}

/// `X_J`: rotation by the quaternion.
#[cfg(feature = "solver")]
#[inline]
pub(crate) fn transform(q: &[f64]) -> Transform {
    Transform {
        rot: quat_to_matrix(q),
        pos: Vector3::zeros(),
    }
}

/// `S v = (ω, 0)`.
#[cfg(feature = "solver")]
#[inline]
pub(crate) fn motion(v: &[f64]) -> Motion {
    Motion {
        w: Vector3::new(v[0], v[1], v[2]),
        v: Vector3::zeros(),
    }
}

/// `Sᵀ f`: the moment about the joint centre, resolved in obj2.
#[cfg(feature = "solver")]
#[inline]
pub(crate) fn project(f: &Force, tau: &mut [f64]) {
    tau[..3].copy_from_slice(f.n.as_slice());
}

/// `q̇ − q̇(q, ω)` with the norm-restoring term of FreeMotion.
#[cfg(feature = "solver")]
#[inline]
pub(crate) fn position_residual(q: &[f64], v: &[f64], qd: &[f64], res: &mut [f64]) {
    super::free::quaternion_residual(q, &Vector3::new(v[0], v[1], v[2]), qd, res);
}

/// Validation of the builder's parameters (solver-free): a unit initial rotation, finite
/// angular velocity.
pub(crate) fn validate(
    c: &mut Checker,
    joint: &str,
    rot: &crate::FreeRotation,
    w: &nalgebra::Vector3<f64>,
) -> ValidJointKind {
    c.finite(
        || format!("joint `{joint}`: initial w [rad/s]"),
        w.as_slice(),
    );
    ValidJointKind::Spherical {
        rot: super::unit_rotation(c, joint, rot),
        w: *w,
    }
}

/// The rows a cut Spherical locks: the three translations.
#[cfg(feature = "solver")]
pub(crate) fn locked_rows() -> Vec<Row> {
    Row::translations(&[
        nalgebra::Vector3::x(),
        nalgebra::Vector3::y(),
        nalgebra::Vector3::z(),
    ])
}
