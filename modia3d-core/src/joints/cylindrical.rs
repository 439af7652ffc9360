//! Cylindrical joint: rotation `phi` \[rad\] about and translation `s` \[m\] along one unit axis
//! fixed in both objects; velocities `w` [rad/s], `v` [m/s] (`phi̇ = w`, `ṡ = v`).
//! `S = [(axis, 0), (0, axis)]` is constant (the axis is invariant under the rotation).

use super::{AxisParam, Checker, Facts, InitialParam, JointCoordinate, JointKindSpec, SignalSpec};
#[cfg(feature = "solver")]
use super::{KindDynamics, Row};
use super::{ParamValue, Source};
#[cfg(feature = "solver")]
use crate::spatial::{axis_angle, Force, Motion, Transform};
use nalgebra::Vector3;

/// A validated Cylindrical joint.
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct Valid {
    /// Unit axis, resolved in obj1.
    pub axis: Vector3<f64>,
    /// Initial angle \[rad\].
    pub phi: f64,
    /// Initial position \[m\].
    pub s: f64,
    /// Initial angular velocity [rad/s].
    pub w: f64,
    /// Initial velocity [m/s].
    pub v: f64,
}

/// A Cylindrical joint in the tree.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct Coord {
    /// Unit axis (already negated when traversed from obj2 to obj1).
    pub axis: Vector3<f64>,
}

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

/// Two scalar coordinates, `phi` and `s`; reversible (the axis is negated); a hinge (its turn
/// and shift about the same axis commute).
pub(crate) const FACTS: Facts = Facts {
    spec: JointKindSpec {
        name: "Cylindrical",
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
                key: "s",
                value: ParamValue::Number,
                unit: "m",
            },
            InitialParam {
                key: "w",
                value: ParamValue::Number,
                unit: "rad/s",
            },
            InitialParam {
                key: "v",
                value: ParamValue::Number,
                unit: "m/s",
            },
        ],
        coordinates: &[
            JointCoordinate {
                name: "phi",
                unit: "rad",
                q: 0,
                v: 0,
                limit_keys: super::spec::limit_keys!("phi"),
            },
            JointCoordinate {
                name: "s",
                unit: "m",
                q: 1,
                v: 1,
                limit_keys: super::spec::limit_keys!("s"),
            },
        ],
        at_rest: |axis| crate::JointKind::Cylindrical {
            axis: axis("axis").unwrap_or_else(Vector3::z),
            phi: 0.0,
            s: 0.0,
            w: 0.0,
            v: 0.0,
        },
    },
    nq: 2,
    nv: 2,
    signals: SIGNALS,
    turning: &[(0, 1.0)],
    shifting: &[1],
    reversed: None,
    rigid: false,
    connects: true,
    modia3d_can_collide: false,
    hinge: true,
};

/// Validation of the builder's parameters (solver-free): unit axis, finite initial values.
pub(crate) fn validate(
    c: &mut Checker,
    joint: &str,
    axis: &Vector3<f64>,
    phi: &f64,
    s: &f64,
    w: &f64,
    v: &f64,
) -> Valid {
    let [phi, s, w, v] = [*phi, *s, *w, *v];
    c.finite(
        || format!("joint `{joint}`: initial phi [rad], s [m], w [rad/s], v [m/s]"),
        &[phi, s, w, v],
    );
    Valid {
        axis: super::unit_axis(c, joint, axis),
        phi,
        s,
        w,
        v,
    }
}

#[cfg(feature = "solver")]
impl KindDynamics for Coord {
    type Valid = Valid;
    fn new(k: &Valid, flipped: bool, q0: &mut Vec<f64>, v0: &mut Vec<f64>) -> Coord {
        q0.extend_from_slice(&[k.phi, k.s]);
        v0.extend_from_slice(&[k.w, k.v]);
        Coord {
            axis: if flipped { -k.axis } else { k.axis },
        }
    }
    /// The two translations across its axis and the two alignments of the axis.
    fn locked_rows(k: &Valid) -> Vec<Row> {
        let (u, w) = crate::joints::rows::perpendiculars(&k.axis);
        let mut r = Row::translations(&[u, w]);
        r.extend(Row::alignments(&k.axis));
        r
    }
    fn drawn_axis(_: &Valid) -> Option<(&'static str, Vector3<f64>)> {
        None
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
    /// `X_J`: rotation by `phi` about and translation by `s` along `axis`.
    #[inline(always)]
    fn transform(&self, q: &[f64]) -> Transform {
        Transform {
            rot: axis_angle(&self.axis, q[0]),
            pos: self.axis * q[1],
        }
    }
    /// `S v = (axis w, axis v)`.
    #[inline(always)]
    fn motion(&self, _: &[f64], v: &[f64]) -> Motion {
        Motion {
            w: self.axis * v[0],
            v: self.axis * v[1],
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
    /// `Sᵀ f`: torque about and force along the axis.
    #[inline]
    fn project(&self, _: &[f64], f: &Force, tau: &mut [f64]) {
        tau[0] = self.axis.dot(&f.n);
        tau[1] = self.axis.dot(&f.f);
    }
    #[inline(always)]
    fn project_at(&self, _: &Transform, q: &[f64], f: &Force, tau: &mut [f64]) {
        self.project(q, f, tau);
    }
    /// `(phi̇, ṡ) − (w, v)`.
    #[inline]
    fn position_residual(&self, _: &[f64], v: &[f64], qd: &[f64], res: &mut [f64]) {
        super::scalar_position_residual(v, qd, res);
    }
    fn derived_signal(&self, _: &str, _: &[f64], _: &[f64], _: &mut Vec<f64>) -> Option<()> {
        None
    }
}
