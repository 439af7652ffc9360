//! Revolute joint: rotation of obj2 relative to obj1 about a unit axis fixed in both;
//! position `phi` \[rad\], velocity `w` [rad/s] (`phi̇ = w`). `S = (axis, 0)` is constant.

use super::{AxisParam, Checker, Facts, InitialParam, JointCoordinate, JointKindSpec, SignalSpec};
#[cfg(feature = "solver")]
use super::{KindDynamics, Row};
use super::{ParamValue, Source};
#[cfg(feature = "solver")]
use crate::spatial::{axis_angle, Force, Motion, Transform};
use nalgebra::Vector3;

/// A validated Revolute joint.
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct Valid {
    /// Unit axis, resolved in obj1.
    pub axis: Vector3<f64>,
    /// Initial angle \[rad\].
    pub phi: f64,
    /// Initial angular velocity [rad/s].
    pub w: f64,
}

/// A Revolute joint in the tree.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct Coord {
    /// Unit axis (already negated when the joint is traversed from obj2 to obj1).
    pub axis: Vector3<f64>,
}

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

/// One scalar coordinate, `phi`; reversible (the axis is negated); a hinge.
pub(crate) const FACTS: Facts = Facts {
    spec: JointKindSpec {
        name: "Revolute",
        axes: &[AxisParam {
            key: "axis",
            default: Some(3),
        }],
        initial: &[
            InitialParam {
                key: "phi",
                value: ParamValue::Number,
                unit: "rad",
            },
            InitialParam {
                key: "w",
                value: ParamValue::Number,
                unit: "rad/s",
            },
        ],
        coordinates: &[JointCoordinate {
            name: "phi",
            unit: "rad",
            q: 0,
            v: 0,
            limit_keys: super::spec::limit_keys!("phi"),
        }],
        at_rest: |axis| crate::JointKind::Revolute {
            axis: axis("axis").unwrap_or_else(Vector3::z),
            phi: 0.0,
            w: 0.0,
        },
    },
    nq: 1,
    nv: 1,
    signals: SIGNALS,
    turning: &[(0, 1.0)],
    shifting: &[],
    reversed: None,
    rigid: false,
    connects: true,
    modia3d_can_collide: true,
    hinge: true,
};

/// Validation of the builder's parameters (solver-free): unit axis, finite initial values.
pub(crate) fn validate(
    c: &mut Checker,
    joint: &str,
    axis: &Vector3<f64>,
    phi: &f64,
    w: &f64,
) -> Valid {
    let (phi, w) = (*phi, *w);
    c.finite(
        || format!("joint `{joint}`: initial phi [rad], w [rad/s]"),
        &[phi, w],
    );
    Valid {
        axis: super::unit_axis(c, joint, axis),
        phi,
        w,
    }
}

#[cfg(feature = "solver")]
impl KindDynamics for Coord {
    type Valid = Valid;
    fn new(k: &Valid, flipped: bool, q0: &mut Vec<f64>, v0: &mut Vec<f64>) -> Coord {
        q0.push(k.phi);
        v0.push(k.w);
        Coord {
            axis: if flipped { -k.axis } else { k.axis },
        }
    }
    /// The three translations and the two alignments of its axis.
    fn locked_rows(k: &Valid) -> Vec<Row> {
        let mut r = Row::translations(&[Vector3::x(), Vector3::y(), Vector3::z()]);
        r.extend(Row::alignments(&k.axis));
        r
    }
    fn drawn_axis(k: &Valid) -> Option<(&'static str, Vector3<f64>)> {
        Some(("revolute", k.axis))
    }
    #[inline]
    fn has_bias(&self) -> bool {
        false
    }
    #[inline]
    fn free_velocities(&self) -> Option<bool> {
        None
    }
    fn resolve_in_obj1(&mut self, _: &[f64], _: &mut [f64]) -> bool {
        false
    }
    /// `X_J`: rotation by `q[0]` about `axis`.
    #[inline(always)]
    fn transform(&self, q: &[f64]) -> Transform {
        Transform {
            rot: axis_angle(&self.axis, q[0]),
            pos: Vector3::zeros(),
        }
    }
    /// `S v`.
    #[inline(always)]
    fn motion(&self, _: &[f64], v: &[f64]) -> Motion {
        Motion {
            w: self.axis * v[0],
            v: Vector3::zeros(),
        }
    }
    #[inline(always)]
    fn motion_at(&self, _: &Transform, q: &[f64], v: &[f64]) -> Motion {
        self.motion(q, v)
    }
    /// Zero: `S` is constant.
    #[inline]
    fn bias(&self, _: &[f64], _: &[f64], _: &Motion) -> Motion {
        Motion::zero()
    }
    /// `Sᵀ f`: the torque about the axis.
    #[inline]
    fn project(&self, _: &[f64], f: &Force, tau: &mut [f64]) {
        tau[0] = self.axis.dot(&f.n);
    }
    #[inline(always)]
    fn project_at(&self, _: &Transform, q: &[f64], f: &Force, tau: &mut [f64]) {
        self.project(q, f, tau);
    }
    /// `phi̇ − w`.
    #[inline]
    fn position_residual(&self, _: &[f64], v: &[f64], qd: &[f64], res: &mut [f64]) {
        super::scalar_position_residual(v, qd, res);
    }
    fn derived_signal(&self, _: &str, _: &[f64], _: &[f64], _: &mut Vec<f64>) -> Option<()> {
        None
    }
}
