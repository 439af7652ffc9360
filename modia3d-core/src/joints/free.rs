//! Free motion: six degrees of freedom of obj2 relative to obj1. Positions `r` (3, resolved in
//! obj1, \[m\]) and a quaternion `(w, x, y, z)` (4); velocities `ω` then `v` of obj2's origin
//! relative to obj1, both resolved in obj2 ([rad/s], [m/s]), so `S` is the identity in the
//! child frame and `c_J = 0`. The quaternion rate carries a norm-restoring term.

use super::{Checker, KindInfo, SignalSpec, Source, ValidJointKind};
#[cfg(feature = "solver")]
use crate::dynamics::loops::Row;
#[cfg(feature = "solver")]
use crate::dynamics::spatial::{quat_rate, quat_to_matrix, Force, Motion, Transform};
#[cfg(feature = "solver")]
use nalgebra::{UnitQuaternion, Vector3};

/// Number of positions.
pub(crate) const NQ: usize = 7;
/// Number of velocities.
pub(crate) const NV: usize = 6;

/// Rate [1/s] at which a joint quaternion is pulled back to unit norm; the exact kinematics
/// preserve the norm, so this only damps the integration error.
#[cfg(feature = "solver")]
pub(crate) const QUATERNION_NORM_RATE: f64 = 1.0;

/// Signals: `r` \[m\] (in obj1), `q` (quaternion), `w` [rad/s] (in obj2), `v` = `der(r)`
/// [m/s] (in obj1, derived).
pub(crate) const SIGNALS: &[SignalSpec] = &[
    SignalSpec {
        name: "r",
        unit: "m",
        dim: 3,
        source: Source::Q(0),
    },
    SignalSpec {
        name: "q",
        unit: "1",
        dim: 4,
        source: Source::Q(3),
    },
    SignalSpec {
        name: "w",
        unit: "rad/s",
        dim: 3,
        source: Source::V(0),
    },
    SignalSpec {
        name: "v",
        unit: "m/s",
        dim: 3,
        source: Source::Derived,
    },
];

/// No scalar coordinates (the velocities are resolved in obj2, not rates of `r`); not
/// reversible (obj1 must lie on the world side).
pub(crate) const INFO: KindInfo = KindInfo {
    coordinates: &[],
    reversible: false,
};

/// Initial `q` (`r`, quaternion) and `v` (`ω`, body-frame velocity) from the validated values:
/// `v_obj1` is `der(r)` resolved in obj1, `w` is resolved in obj2.
#[cfg(feature = "solver")]
pub(crate) fn initial(
    r: &Vector3<f64>,
    rot: &UnitQuaternion<f64>,
    v_obj1: &Vector3<f64>,
    w: &Vector3<f64>,
    q0: &mut Vec<f64>,
    v0: &mut Vec<f64>,
) {
    q0.extend_from_slice(r.as_slice());
    q0.extend_from_slice(&[rot.w, rot.i, rot.j, rot.k]);
    v0.extend_from_slice(w.as_slice());
    v0.extend_from_slice((rot.inverse() * v_obj1).as_slice());
}

/// `X_J`: rotation by the quaternion `q[3..7]`, translation `q[0..3]`.
#[cfg(feature = "solver")]
#[inline]
pub(crate) fn transform(q: &[f64]) -> Transform {
    Transform {
        rot: quat_to_matrix(&q[3..7]),
        pos: Vector3::new(q[0], q[1], q[2]),
    }
}

/// `S v = (ω, v)`.
#[cfg(feature = "solver")]
#[inline]
pub(crate) fn motion(v: &[f64]) -> Motion {
    Motion {
        w: Vector3::new(v[0], v[1], v[2]),
        v: Vector3::new(v[3], v[4], v[5]),
    }
}

/// `Sᵀ f = (n, f)`.
#[cfg(feature = "solver")]
#[inline]
pub(crate) fn project(f: &Force, tau: &mut [f64]) {
    for k in 0..3 {
        tau[k] = f.n[k];
        tau[3 + k] = f.f[k];
    }
}

/// `q̇ − q̇(q, v)`: `ṙ = R v` and the quaternion rate of `ω` with the norm-restoring term.
#[cfg(feature = "solver")]
#[inline]
pub(crate) fn position_residual(q: &[f64], v: &[f64], qd: &[f64], res: &mut [f64]) {
    let rot = quat_to_matrix(&q[3..7]);
    let lin = Vector3::new(v[3], v[4], v[5]);
    let rd = rot * lin;
    for k in 0..3 {
        res[k] = qd[k] - rd[k];
    }
    quaternion_residual(
        &q[3..7],
        &Vector3::new(v[0], v[1], v[2]),
        &qd[3..7],
        &mut res[3..7],
    );
}

/// Residual of a joint quaternion `quat` rotating at `w` (resolved in the child frame):
/// `q̇ − (½ q ⊗ ω − k (‖q‖² − 1) q)`, whose last term pulls the norm back to 1 at the rate
/// [`QUATERNION_NORM_RATE`].
#[cfg(feature = "solver")]
#[inline]
pub(crate) fn quaternion_residual(quat: &[f64], w: &Vector3<f64>, qd: &[f64], res: &mut [f64]) {
    let qr = quat_rate(quat, w);
    let n2 = quat.iter().map(|x| x * x).sum::<f64>();
    let pull = QUATERNION_NORM_RATE * (n2 - 1.0);
    for k in 0..4 {
        res[k] = qd[k] - (qr[k] - pull * quat[k]);
    }
}

/// `der(r)` resolved in obj1 [m/s]: the child-frame velocity rotated by the quaternion.
#[cfg(feature = "solver")]
pub(crate) fn velocity_in_obj1(q: &[f64], v: &[f64], out: &mut Vec<f64>) {
    let rot = quat_to_matrix(&q[3..7]);
    let v_body = Vector3::new(v[3], v[4], v[5]);
    out.extend_from_slice((rot * v_body).as_slice());
}

/// Validation of the builder's parameters (solver-free): finite initial values, a unit
/// initial rotation.
pub(crate) fn validate(
    c: &mut Checker,
    joint: &str,
    r: &nalgebra::Vector3<f64>,
    rot: &crate::FreeRotation,
    v: &nalgebra::Vector3<f64>,
    w: &nalgebra::Vector3<f64>,
) -> ValidJointKind {
    c.finite(
        || format!("joint `{joint}`: initial r [m], v [m/s], w [rad/s]"),
        &[r.as_slice(), v.as_slice(), w.as_slice()].concat(),
    );
    ValidJointKind::FreeMotion {
        r: *r,
        rot: super::unit_rotation(c, joint, rot),
        v: *v,
        w: *w,
    }
}

/// A cut FreeMotion locks nothing.
#[cfg(feature = "solver")]
pub(crate) fn locked_rows() -> Vec<Row> {
    vec![]
}
