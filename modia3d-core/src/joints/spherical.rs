//! Spherical joint (ball joint): rotation of obj2 relative to obj1 about their common origin.
//! Position: a unit quaternion `(w, x, y, z)` (4; no singular angles), whose norm is kept as
//! for FreeMotion; velocity: the angular velocity `ω` of obj2 relative to obj1, resolved in
//! obj2 (3, [rad/s]), so `S = (I, 0)` in the child frame and `c_J = 0`.

use super::{Checker, Facts, InitialParam, JointKindSpec, ParamValue, SignalSpec, Source};
#[cfg(feature = "solver")]
use super::{KindDynamics, Row};
use crate::scene::SceneError;
#[cfg(feature = "solver")]
use crate::spatial::{quat_to_matrix, Force, Motion, Transform};
use nalgebra::{UnitQuaternion, Vector3};

/// A validated Spherical joint.
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct Valid {
    /// Initial orientation relative to obj1.
    pub rot: UnitQuaternion<f64>,
    /// Initial angular velocity, resolved in obj2 [rad/s].
    pub w: Vector3<f64>,
}

/// A Spherical joint in the tree: a quaternion (4) and `ω` resolved in obj2 (3, [rad/s]).
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct Coord;

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

/// No scalar coordinates (the angular velocity is no rate of the quaternion); not reversible
/// (obj1 must lie on the world side); the quaternion's components turn the child.
pub(crate) const FACTS: Facts = Facts {
    spec: JointKindSpec {
        name: "Spherical",
        axes: &[],
        initial: &[
            InitialParam {
                key: "rot",
                value: ParamValue::Orientation,
                unit: "1",
            },
            InitialParam {
                key: "w",
                value: ParamValue::Vector,
                unit: "rad/s",
            },
        ],
        coordinates: &[],
        at_rest: |_| crate::JointKind::spherical(),
    },
    nq: 4,
    nv: 3,
    signals: SIGNALS,
    turning: &[(0, 2.0), (1, 2.0), (2, 2.0), (3, 2.0)],
    shifting: &[],
    reversed: Some(|joint, obj1, obj2| SceneError::ReversedJoint {
        joint,
        kind: "Spherical",
        obj1,
        obj2,
    }),
    rigid: false,
    connects: true,
    modia3d_can_collide: false,
    hinge: false,
};

/// Validation of the builder's parameters (solver-free): a unit initial rotation, finite
/// angular velocity.
pub(crate) fn validate(
    c: &mut Checker,
    joint: &str,
    rot: &crate::FreeRotation,
    w: &Vector3<f64>,
) -> Valid {
    c.finite(
        || format!("joint `{joint}`: initial w [rad/s]"),
        w.as_slice(),
    );
    Valid {
        rot: super::unit_rotation(c, joint, rot),
        w: *w,
    }
}

#[cfg(feature = "solver")]
impl KindDynamics for Coord {
    type Valid = Valid;
    /// Initial quaternion and angular velocity (resolved in obj2); never flipped (not
    /// reversible).
    fn new(k: &Valid, _: bool, q0: &mut Vec<f64>, v0: &mut Vec<f64>) -> Coord {
        let rot = &k.rot;
        q0.extend_from_slice(&[rot.w, rot.i, rot.j, rot.k]);
        v0.extend_from_slice(k.w.as_slice());
        Coord
    }
    /// The three translations.
    fn locked_rows(_: &Valid) -> Vec<Row> {
        Row::translations(&[Vector3::x(), Vector3::y(), Vector3::z()])
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
    /// `X_J`: rotation by the quaternion.
    #[inline(always)]
    fn transform(&self, q: &[f64]) -> Transform {
        Transform {
            rot: quat_to_matrix(q),
            pos: Vector3::zeros(),
        }
    }
    /// `S v = (ω, 0)`.
    #[inline(always)]
    fn motion(&self, _: &[f64], v: &[f64]) -> Motion {
        Motion {
            w: Vector3::new(v[0], v[1], v[2]),
            v: Vector3::zeros(),
        }
    }
    #[inline(always)]
    fn motion_at(&self, _: &Transform, q: &[f64], v: &[f64]) -> Motion {
        self.motion(q, v)
    }
    /// Zero: `S = (I, 0)` is constant.
    #[inline]
    fn bias(&self, _: &[f64], _: &[f64], _: &Motion) -> Motion {
        Motion::zero()
    }
    /// `Sᵀ f`: the moment about the joint centre, resolved in obj2.
    #[inline]
    fn project(&self, _: &[f64], f: &Force, tau: &mut [f64]) {
        tau[..3].copy_from_slice(f.n.as_slice());
    }
    #[inline(always)]
    fn project_at(&self, _: &Transform, q: &[f64], f: &Force, tau: &mut [f64]) {
        self.project(q, f, tau);
    }
    /// `q̇ − q̇(q, ω)` with the norm-restoring term of FreeMotion.
    #[inline]
    fn position_residual(&self, q: &[f64], v: &[f64], qd: &[f64], res: &mut [f64]) {
        super::free::quaternion_residual(q, &Vector3::new(v[0], v[1], v[2]), qd, res);
    }
    fn derived_signal(&self, _: &str, _: &[f64], _: &[f64], _: &mut Vec<f64>) -> Option<()> {
        None
    }
}
