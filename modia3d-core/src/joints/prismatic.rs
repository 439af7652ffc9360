//! Prismatic joint: translation of obj2 relative to obj1 along a unit axis fixed in both;
//! position `s` \[m\], velocity `v` [m/s] (`ṡ = v`). `S = (0, axis)` is constant.

use super::{AxisParam, Checker, Facts, InitialParam, JointCoordinate, JointKindSpec, SignalSpec};
#[cfg(feature = "solver")]
use super::{KindDynamics, Row};
use super::{ParamValue, Source};
#[cfg(feature = "solver")]
use crate::spatial::{Force, Motion, Transform};
#[cfg(feature = "solver")]
use nalgebra::Matrix3;
use nalgebra::Vector3;

/// A validated Prismatic joint.
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct Valid {
    /// Unit axis, resolved in obj1.
    pub axis: Vector3<f64>,
    /// Initial position \[m\].
    pub s: f64,
    /// Initial velocity [m/s].
    pub v: f64,
}

/// A Prismatic joint in the tree.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct Coord {
    /// Unit axis (already negated when traversed from obj2 to obj1).
    pub axis: Vector3<f64>,
}

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

/// One scalar coordinate, `s`; reversible (the axis is negated); a hinge.
pub(crate) const FACTS: Facts = Facts {
    spec: JointKindSpec {
        name: "Prismatic",
        axes: &[AxisParam {
            key: "axis",
            default: Some(3),
        }],
        initial: &[
            InitialParam {
                key: "s",
                value: ParamValue::Number,
                unit: "m",
            },
            InitialParam {
                key: "v",
                value: ParamValue::Number,
                unit: "m/s",
            },
        ],
        coordinates: &[JointCoordinate {
            name: "s",
            unit: "m",
            q: 0,
            v: 0,
            limit_keys: super::spec::limit_keys!("s"),
        }],
        at_rest: |axis| crate::JointKind::Prismatic {
            axis: axis("axis").unwrap_or_else(Vector3::z),
            s: 0.0,
            v: 0.0,
        },
    },
    nq: 1,
    nv: 1,
    signals: SIGNALS,
    turning: &[],
    shifting: &[0],
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
    s: &f64,
    v: &f64,
) -> Valid {
    let (s, v) = (*s, *v);
    c.finite(
        || format!("joint `{joint}`: initial s [m], v [m/s]"),
        &[s, v],
    );
    Valid {
        axis: super::unit_axis(c, joint, axis),
        s,
        v,
    }
}

#[cfg(feature = "solver")]
impl KindDynamics for Coord {
    type Valid = Valid;
    fn new(k: &Valid, flipped: bool, q0: &mut Vec<f64>, v0: &mut Vec<f64>) -> Coord {
        q0.push(k.s);
        v0.push(k.v);
        Coord {
            axis: if flipped { -k.axis } else { k.axis },
        }
    }
    /// The two translations across its axis and the three rotations.
    fn locked_rows(k: &Valid) -> Vec<Row> {
        let (u, w) = crate::joints::rows::perpendiculars(&k.axis);
        let mut r = Row::translations(&[u, w]);
        r.extend(Row::rotations());
        r
    }
    fn drawn_axis(k: &Valid) -> Option<(&'static str, Vector3<f64>)> {
        Some(("prismatic", k.axis))
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
    /// `X_J`: translation by `q[0]` along `axis`.
    #[inline(always)]
    fn transform(&self, q: &[f64]) -> Transform {
        Transform {
            rot: Matrix3::identity(),
            pos: self.axis * q[0],
        }
    }
    /// `S v`.
    #[inline(always)]
    fn motion(&self, _: &[f64], v: &[f64]) -> Motion {
        Motion {
            w: Vector3::zeros(),
            v: self.axis * v[0],
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
    /// `Sᵀ f`: the force along the axis.
    #[inline]
    fn project(&self, _: &[f64], f: &Force, tau: &mut [f64]) {
        tau[0] = self.axis.dot(&f.f);
    }
    #[inline(always)]
    fn project_at(&self, _: &Transform, q: &[f64], f: &Force, tau: &mut [f64]) {
        self.project(q, f, tau);
    }
    /// `ṡ − v`.
    #[inline]
    fn position_residual(&self, _: &[f64], v: &[f64], qd: &[f64], res: &mut [f64]) {
        super::scalar_position_residual(v, qd, res);
    }
    fn derived_signal(&self, _: &str, _: &[f64], _: &[f64], _: &mut Vec<f64>) -> Option<()> {
        None
    }
}
