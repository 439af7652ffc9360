//! Planar joint: obj2 moves in the plane through obj1's origin normal to the unit `normal`
//! (fixed in both). Positions `x`, `y` \[m\]: obj2's origin at `x e1 + y e2`, **resolved in
//! obj1** (the plane axes `e1`, `e2` are fixed in obj1, see [`plane_axes`]), and the rotation
//! `phi` \[rad\] about `normal`; velocities `vx = ẋ`, `vy = ẏ` [m/s] (also in obj1) and `w = phi̇`
//! [rad/s]. Resolved in obj2 the translation columns of `S` turn with `phi`:
//! `S v = (normal w, Rᵀ (e1 vx + e2 vy))`, `c_J = (0, −w · normal × Rᵀ (e1 vx + e2 vy))`.

use super::{Checker, Coordinate, KindInfo, SignalSpec, Source, ValidJointKind};
#[cfg(feature = "solver")]
use crate::joints::rows::Row;
#[cfg(feature = "solver")]
use crate::spatial::{axis_angle, Force, Motion, Transform};
use nalgebra::Vector3;

/// Signals: `x`, `y` \[m\], `phi` \[rad\], `vx`, `vy` [m/s], `w` [rad/s].
pub(crate) const SIGNALS: &[SignalSpec] = &[
    SignalSpec {
        name: "x",
        unit: "m",
        dim: 1,
        source: Source::Q(0),
    },
    SignalSpec {
        name: "y",
        unit: "m",
        dim: 1,
        source: Source::Q(1),
    },
    SignalSpec {
        name: "phi",
        unit: "rad",
        dim: 1,
        source: Source::Q(2),
    },
    SignalSpec {
        name: "vx",
        unit: "m/s",
        dim: 1,
        source: Source::V(0),
    },
    SignalSpec {
        name: "vy",
        unit: "m/s",
        dim: 1,
        source: Source::V(1),
    },
    SignalSpec {
        name: "w",
        unit: "rad/s",
        dim: 1,
        source: Source::V(2),
    },
];

/// Three scalar coordinates; not reversible (the translations are resolved in obj1).
pub(crate) const INFO: KindInfo = KindInfo {
    coordinates: &[
        Coordinate {
            name: "x",
            unit: "m",
            q: 0,
            v: 0,
        },
        Coordinate {
            name: "y",
            unit: "m",
            q: 1,
            v: 1,
        },
        Coordinate {
            name: "phi",
            unit: "rad",
            q: 2,
            v: 2,
        },
    ],
    reversible: false,
};

/// The plane's axes `(e1, e2)`, resolved in obj1, of a unit `normal`: `e1` is the coordinate
/// axis that follows `normal`'s largest component cyclically (x → y → z → x), made
/// perpendicular to `normal`; `e2 = normal × e1`. So a normal `z` gives `(x, y)`, `x` gives
/// `(y, z)` and `y` gives `(z, x)`.
pub fn plane_axes(normal: &Vector3<f64>) -> (Vector3<f64>, Vector3<f64>) {
    let k = normal.iamax();
    let a = Vector3::ith((k + 1) % 3, 1.0);
    let e1 = (a - normal * normal.dot(&a)).normalize();
    (e1, normal.cross(&e1))
}

/// `X_J`: rotation by `phi` about `normal`, translation `x e1 + y e2`.
#[cfg(feature = "solver")]
#[inline]
pub(crate) fn transform(
    n: &Vector3<f64>,
    e1: &Vector3<f64>,
    e2: &Vector3<f64>,
    q: &[f64],
) -> Transform {
    Transform {
        rot: axis_angle(n, q[2]),
        pos: e1 * q[0] + e2 * q[1],
    }
}

/// The in-plane velocity `e1 vx + e2 vy` resolved in the child frame.
#[cfg(feature = "solver")]
#[inline]
fn planar_velocity(
    n: &Vector3<f64>,
    e1: &Vector3<f64>,
    e2: &Vector3<f64>,
    q: &[f64],
    v: &[f64],
) -> Vector3<f64> {
    axis_angle(n, q[2]).tr_mul(&(e1 * v[0] + e2 * v[1]))
}

/// `S(q) v`.
#[cfg(feature = "solver")]
#[inline]
pub(crate) fn motion(
    n: &Vector3<f64>,
    e1: &Vector3<f64>,
    e2: &Vector3<f64>,
    q: &[f64],
    v: &[f64],
) -> Motion {
    Motion {
        w: n * v[2],
        v: planar_velocity(n, e1, e2, q, v),
    }
}

/// `c_J = Ṡ(q) v`: the translation columns turn at `w` about `normal`.
#[cfg(feature = "solver")]
#[inline]
pub(crate) fn bias(
    n: &Vector3<f64>,
    e1: &Vector3<f64>,
    e2: &Vector3<f64>,
    q: &[f64],
    v: &[f64],
) -> Motion {
    Motion {
        w: Vector3::zeros(),
        v: -n.cross(&planar_velocity(n, e1, e2, q, v)) * v[2],
    }
}

/// `Sᵀ f`: the force along `e1`, `e2` and the torque about `normal`.
#[cfg(feature = "solver")]
#[inline]
pub(crate) fn project(
    n: &Vector3<f64>,
    e1: &Vector3<f64>,
    e2: &Vector3<f64>,
    q: &[f64],
    f: &Force,
    tau: &mut [f64],
) {
    let r = axis_angle(n, q[2]);
    tau[0] = (r.tr_mul(e1)).dot(&f.f);
    tau[1] = (r.tr_mul(e2)).dot(&f.f);
    tau[2] = n.dot(&f.n);
}

/// Validation of the builder's parameters (solver-free): unit normal, finite initial values.
pub(crate) fn validate(
    c: &mut Checker,
    joint: &str,
    normal: &nalgebra::Vector3<f64>,
    [x, y, phi, vx, vy, w]: [f64; 6],
) -> ValidJointKind {
    c.finite(
        || format!("joint `{joint}`: initial x, y [m], phi [rad], vx, vy [m/s], w [rad/s]"),
        &[x, y, phi, vx, vy, w],
    );
    ValidJointKind::Planar {
        normal: super::unit_axis(c, joint, normal),
        x,
        y,
        phi,
        vx,
        vy,
        w,
    }
}

/// The rows a cut Planar locks: the translation along its normal and the two alignments of
/// the normal.
#[cfg(feature = "solver")]
pub(crate) fn locked_rows(normal: &nalgebra::Vector3<f64>) -> Vec<Row> {
    let mut r = Row::translations(&[*normal]);
    r.extend(Row::alignments(normal));
    r
}
