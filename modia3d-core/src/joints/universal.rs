//! Universal (Cardan, Hooke) joint: rotation `phi1` about `axis1`, fixed in obj1, then `phi2`
//! about `axis2`, fixed in obj2; the axes are perpendicular (they cross at the joint centre, the
//! common origin). `R = Rot(axis1, phi1) · Rot(axis2, phi2)`. Positions `phi1`, `phi2` \[rad\],
//! velocities `w1`, `w2` [rad/s]. Resolved in obj2, `ω = Rot(axis2, phi2)ᵀ axis1 · w1 +
//! axis2 · w2`: `S` depends on `phi2`, so `c_J = w1 w2 (Rot(axis2, phi2)ᵀ axis1) × axis2`.

use super::{AxisParam, Checker, Facts, InitialParam, JointCoordinate, JointKindSpec, SignalSpec};
#[cfg(feature = "solver")]
use super::{KindDynamics, Row};
use super::{ParamValue, Source};
use crate::scene::SceneError;
#[cfg(feature = "solver")]
use crate::spatial::{axis_angle, Force, Motion, Transform};
use nalgebra::Vector3;

/// A validated Universal joint: unit, exactly perpendicular axes.
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct Valid {
    /// First axis (fixed in obj1), unit.
    pub axis1: Vector3<f64>,
    /// Second axis (fixed in obj2), unit, perpendicular to `axis1`.
    pub axis2: Vector3<f64>,
    /// Initial angles \[rad\].
    pub phi1: f64,
    /// See `phi1`.
    pub phi2: f64,
    /// Initial rates [rad/s].
    pub w1: f64,
    /// See `w1`.
    pub w2: f64,
}

/// A Universal joint in the tree: unit, perpendicular axes resolved in the joint frame.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct Coord {
    /// First axis, fixed in obj1.
    pub axis1: Vector3<f64>,
    /// Second axis, fixed in obj2.
    pub axis2: Vector3<f64>,
}

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
/// one fixed in the child); `S` depends on `phi2`.
pub(crate) const FACTS: Facts = Facts {
    spec: JointKindSpec {
        name: "Universal",
        axes: &[
            AxisParam {
                key: "axis1",
                default: None,
            },
            AxisParam {
                key: "axis2",
                default: None,
            },
        ],
        initial: &[
            InitialParam {
                key: "phi1",
                value: ParamValue::Number,
                unit: "rad",
            },
            InitialParam {
                key: "phi2",
                value: ParamValue::Number,
                unit: "rad",
            },
            InitialParam {
                key: "w1",
                value: ParamValue::Number,
                unit: "rad/s",
            },
            InitialParam {
                key: "w2",
                value: ParamValue::Number,
                unit: "rad/s",
            },
        ],
        coordinates: &[
            JointCoordinate {
                name: "phi1",
                unit: "rad",
                q: 0,
                v: 0,
                limit_keys: super::spec::limit_keys!("phi1"),
            },
            JointCoordinate {
                name: "phi2",
                unit: "rad",
                q: 1,
                v: 1,
                limit_keys: super::spec::limit_keys!("phi2"),
            },
        ],
        at_rest,
    },
    nq: 2,
    nv: 2,
    signals: SIGNALS,
    turning: &[(0, 1.0), (1, 1.0)],
    shifting: &[],
    reversed: Some(|joint, obj1, obj2| SceneError::ReversedJoint {
        joint,
        kind: "Universal",
        obj1,
        obj2,
    }),
    rigid: false,
    connects: true,
    modia3d_can_collide: false,
    hinge: false,
};

/// At rest with the axes given; an axis not given is a stand-in perpendicular to the other
/// (both not given: z and x).
fn at_rest(axis: &super::spec::AxisOf<'_>) -> crate::JointKind {
    let across = |a: Vector3<f64>| {
        a.cross(&Vector3::x())
            .try_normalize(0.0)
            .unwrap_or_else(|| a.cross(&Vector3::y()))
    };
    let (axis1, axis2) = match (axis("axis1"), axis("axis2")) {
        (Some(a1), Some(a2)) => (a1, a2),
        (Some(a1), None) => (a1, across(a1)),
        (None, Some(a2)) => (across(a2), a2),
        (None, None) => (Vector3::z(), Vector3::x()),
    };
    crate::JointKind::Universal {
        axis1,
        axis2,
        phi1: 0.0,
        phi2: 0.0,
        w1: 0.0,
        w2: 0.0,
    }
}

/// `axis1` resolved in the child frame at `phi2`: the first column of `S`'s angular part.
#[cfg(feature = "solver")]
#[inline]
fn axis1_in_child(axis1: &Vector3<f64>, axis2: &Vector3<f64>, phi2: f64) -> Vector3<f64> {
    axis_angle(axis2, phi2).tr_mul(axis1)
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
    axis1: &Vector3<f64>,
    axis2: &Vector3<f64>,
    phi1: &f64,
    phi2: &f64,
    w1: &f64,
    w2: &f64,
) -> Valid {
    let [phi1, phi2, w1, w2] = [*phi1, *phi2, *w1, *w2];
    c.finite(
        || format!("joint `{joint}`: initial phi1, phi2 [rad], w1, w2 [rad/s]"),
        &[phi1, phi2, w1, w2],
    );
    let a1 = super::unit_axis(c, joint, axis1);
    let a2 = super::unit_axis(c, joint, axis2);
    let cos = a1.dot(&a2);
    if cos.is_finite() && cos.abs() > PERPENDICULAR_TOLERANCE {
        c.errors.push(SceneError::InvalidValue {
            what: format!("joint `{joint}`: cosine of the angle between axis1 and axis2"),
            value: cos,
            expected: "0 within 1e-6 (a universal joint's axes are perpendicular)",
        });
    }
    Valid {
        axis1: a1,
        // Exactly perpendicular from here on (the joint is dropped if the check failed).
        axis2: (a2 - a1 * cos).normalize(),
        phi1,
        phi2,
        w1,
        w2,
    }
}

#[cfg(feature = "solver")]
impl KindDynamics for Coord {
    type Valid = Valid;
    /// Never flipped (not reversible).
    fn new(k: &Valid, _: bool, q0: &mut Vec<f64>, v0: &mut Vec<f64>) -> Coord {
        q0.extend_from_slice(&[k.phi1, k.phi2]);
        v0.extend_from_slice(&[k.w1, k.w2]);
        Coord {
            axis1: k.axis1,
            axis2: k.axis2,
        }
    }
    /// The three translations and `axis2` kept perpendicular to `axis1`.
    fn locked_rows(k: &Valid) -> Vec<Row> {
        let mut r = Row::translations(&[Vector3::x(), Vector3::y(), Vector3::z()]);
        r.push(Row::Align {
            u: k.axis1,
            a: k.axis2,
        });
        r
    }
    fn drawn_axis(_: &Valid) -> Option<(&'static str, Vector3<f64>)> {
        None
    }
    #[inline]
    fn has_bias(&self) -> bool {
        true
    }
    #[inline]
    fn free_velocities(&self) -> Option<bool> {
        None
    }
    fn resolve_in_obj1(&mut self, _: &[f64], _: &mut [f64]) -> bool {
        false
    }
    /// `X_J`: `Rot(axis1, phi1) · Rot(axis2, phi2)`.
    #[inline(always)]
    fn transform(&self, q: &[f64]) -> Transform {
        Transform {
            rot: axis_angle(&self.axis1, q[0]) * axis_angle(&self.axis2, q[1]),
            pos: Vector3::zeros(),
        }
    }
    /// `S(q) v`.
    #[inline(always)]
    fn motion(&self, q: &[f64], v: &[f64]) -> Motion {
        Motion {
            w: axis1_in_child(&self.axis1, &self.axis2, q[1]) * v[0] + self.axis2 * v[1],
            v: Vector3::zeros(),
        }
    }
    #[inline(always)]
    fn motion_at(&self, _: &Transform, q: &[f64], v: &[f64]) -> Motion {
        self.motion(q, v)
    }
    /// `c_J = Ṡ(q) v`: only the first column turns, at `w2` about `axis2`.
    #[inline]
    fn bias(&self, q: &[f64], v: &[f64], _: &Motion) -> Motion {
        Motion {
            w: axis1_in_child(&self.axis1, &self.axis2, q[1]).cross(&self.axis2) * (v[0] * v[1]),
            v: Vector3::zeros(),
        }
    }
    /// `Sᵀ f`: the moments about the two axes.
    #[inline]
    fn project(&self, q: &[f64], f: &Force, tau: &mut [f64]) {
        tau[0] = axis1_in_child(&self.axis1, &self.axis2, q[1]).dot(&f.n);
        tau[1] = self.axis2.dot(&f.n);
    }
    #[inline(always)]
    fn project_at(&self, _: &Transform, q: &[f64], f: &Force, tau: &mut [f64]) {
        self.project(q, f, tau);
    }
    /// `(phi̇1, phi̇2) − (w1, w2)`.
    #[inline]
    fn position_residual(&self, _: &[f64], v: &[f64], qd: &[f64], res: &mut [f64]) {
        super::scalar_position_residual(v, qd, res);
    }
    fn derived_signal(&self, _: &str, _: &[f64], _: &[f64], _: &mut Vec<f64>) -> Option<()> {
        None
    }
}
