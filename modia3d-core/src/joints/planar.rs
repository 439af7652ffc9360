//! Planar joint: obj2 moves in the plane through obj1's origin normal to the unit `normal`
//! (fixed in both). Positions `x`, `y` \[m\]: obj2's origin at `x e1 + y e2`, **resolved in
//! obj1** (the plane axes `e1`, `e2` are fixed in obj1, see [`plane_axes`]), and the rotation
//! `phi` \[rad\] about `normal`; velocities `vx = ẋ`, `vy = ẏ` [m/s] (also in obj1) and `w = phi̇`
//! [rad/s]. Resolved in obj2 the translation columns of `S` turn with `phi`:
//! `S v = (normal w, Rᵀ (e1 vx + e2 vy))`, `c_J = (0, −w · normal × Rᵀ (e1 vx + e2 vy))`.

use super::{AxisParam, Checker, Facts, InitialParam, JointCoordinate, JointKindSpec, SignalSpec};
#[cfg(feature = "solver")]
use super::{KindDynamics, Row};
use super::{ParamValue, Source};
use crate::scene::SceneError;
#[cfg(feature = "solver")]
use crate::spatial::{axis_angle, Force, Motion, Transform};
use nalgebra::Vector3;

/// A validated Planar joint.
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct Valid {
    /// Unit normal, resolved in obj1.
    pub normal: Vector3<f64>,
    /// Initial positions \[m\] (resolved in obj1) and angle \[rad\].
    pub x: f64,
    /// See `x`.
    pub y: f64,
    /// See `x`.
    pub phi: f64,
    /// Initial rates [m/s], [rad/s].
    pub vx: f64,
    /// See `vx`.
    pub vy: f64,
    /// See `vx`.
    pub w: f64,
}

/// A Planar joint in the tree: translations `x`, `y` along `e1`, `e2` (resolved in obj1) and
/// rotation `phi` about `normal`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct Coord {
    /// Unit normal of the plane.
    pub normal: Vector3<f64>,
    /// First in-plane axis.
    pub e1: Vector3<f64>,
    /// Second in-plane axis, `normal × e1`.
    pub e2: Vector3<f64>,
}

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

/// Three scalar coordinates; not reversible (the translations are resolved in obj1); `S`
/// depends on `phi`.
pub(crate) const FACTS: Facts = Facts {
    spec: JointKindSpec {
        name: "Planar",
        axes: &[AxisParam {
            key: "normal",
            default: Some(3),
        }],
        initial: &[
            InitialParam {
                key: "x",
                value: ParamValue::Number,
                unit: "m",
            },
            InitialParam {
                key: "y",
                value: ParamValue::Number,
                unit: "m",
            },
            InitialParam {
                key: "phi",
                value: ParamValue::Number,
                unit: "rad",
            },
            InitialParam {
                key: "vx",
                value: ParamValue::Number,
                unit: "m/s",
            },
            InitialParam {
                key: "vy",
                value: ParamValue::Number,
                unit: "m/s",
            },
            InitialParam {
                key: "w",
                value: ParamValue::Number,
                unit: "rad/s",
            },
        ],
        coordinates: &[
            JointCoordinate {
                name: "x",
                unit: "m",
                q: 0,
                v: 0,
                limit_keys: super::spec::limit_keys!("x"),
            },
            JointCoordinate {
                name: "y",
                unit: "m",
                q: 1,
                v: 1,
                limit_keys: super::spec::limit_keys!("y"),
            },
            JointCoordinate {
                name: "phi",
                unit: "rad",
                q: 2,
                v: 2,
                limit_keys: super::spec::limit_keys!("phi"),
            },
        ],
        at_rest: |axis| crate::JointKind::Planar {
            normal: axis("normal").unwrap_or_else(Vector3::z),
            x: 0.0,
            y: 0.0,
            phi: 0.0,
            vx: 0.0,
            vy: 0.0,
            w: 0.0,
        },
    },
    nq: 3,
    nv: 3,
    signals: SIGNALS,
    turning: &[(2, 1.0)],
    shifting: &[0, 1],
    reversed: Some(|joint, obj1, obj2| SceneError::ReversedJoint {
        joint,
        kind: "Planar",
        obj1,
        obj2,
    }),
    rigid: false,
    connects: true,
    modia3d_can_collide: false,
    hinge: false,
};

/// The plane's axes `(e1, e2)`, resolved in obj1, of a unit `normal`: `e1` is the coordinate
/// axis that follows `normal`'s largest component cyclically (x → y → z → x), made
/// perpendicular to `normal`; `e2 = normal × e1`. So a normal `z` gives `(x, y)`, `x` gives
/// `(y, z)` and `y` gives `(z, x)`.
pub(crate) fn plane_axes(normal: &Vector3<f64>) -> (Vector3<f64>, Vector3<f64>) {
    let k = normal.iamax();
    let a = Vector3::ith((k + 1) % 3, 1.0);
    let e1 = (a - normal * normal.dot(&a)).normalize();
    (e1, normal.cross(&e1))
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

/// Validation of the builder's parameters (solver-free): unit normal, finite initial values.
#[allow(clippy::too_many_arguments)]
pub(crate) fn validate(
    c: &mut Checker,
    joint: &str,
    normal: &Vector3<f64>,
    x: &f64,
    y: &f64,
    phi: &f64,
    vx: &f64,
    vy: &f64,
    w: &f64,
) -> Valid {
    let [x, y, phi, vx, vy, w] = [*x, *y, *phi, *vx, *vy, *w];
    c.finite(
        || format!("joint `{joint}`: initial x, y [m], phi [rad], vx, vy [m/s], w [rad/s]"),
        &[x, y, phi, vx, vy, w],
    );
    Valid {
        normal: super::unit_axis(c, joint, normal),
        x,
        y,
        phi,
        vx,
        vy,
        w,
    }
}

#[cfg(feature = "solver")]
impl KindDynamics for Coord {
    type Valid = Valid;
    /// Never flipped (not reversible).
    fn new(k: &Valid, _: bool, q0: &mut Vec<f64>, v0: &mut Vec<f64>) -> Coord {
        q0.extend_from_slice(&[k.x, k.y, k.phi]);
        v0.extend_from_slice(&[k.vx, k.vy, k.w]);
        let (e1, e2) = plane_axes(&k.normal);
        Coord {
            normal: k.normal,
            e1,
            e2,
        }
    }
    /// The translation along its normal and the two alignments of the normal.
    fn locked_rows(k: &Valid) -> Vec<Row> {
        let mut r = Row::translations(&[k.normal]);
        r.extend(Row::alignments(&k.normal));
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
    /// `X_J`: rotation by `phi` about `normal`, translation `x e1 + y e2`.
    #[inline(always)]
    fn transform(&self, q: &[f64]) -> Transform {
        Transform {
            rot: axis_angle(&self.normal, q[2]),
            pos: self.e1 * q[0] + self.e2 * q[1],
        }
    }
    /// `S(q) v`.
    #[inline(always)]
    fn motion(&self, q: &[f64], v: &[f64]) -> Motion {
        Motion {
            w: self.normal * v[2],
            v: planar_velocity(&self.normal, &self.e1, &self.e2, q, v),
        }
    }
    #[inline(always)]
    fn motion_at(&self, _: &Transform, q: &[f64], v: &[f64]) -> Motion {
        self.motion(q, v)
    }
    /// `c_J = Ṡ(q) v`: the translation columns turn at `w` about `normal`.
    #[inline]
    fn bias(&self, q: &[f64], v: &[f64], _: &Motion) -> Motion {
        let n = &self.normal;
        Motion {
            w: Vector3::zeros(),
            v: -n.cross(&planar_velocity(n, &self.e1, &self.e2, q, v)) * v[2],
        }
    }
    /// `Sᵀ f`: the force along `e1`, `e2` and the torque about `normal`.
    #[inline]
    fn project(&self, q: &[f64], f: &Force, tau: &mut [f64]) {
        let r = axis_angle(&self.normal, q[2]);
        tau[0] = (r.tr_mul(&self.e1)).dot(&f.f);
        tau[1] = (r.tr_mul(&self.e2)).dot(&f.f);
        tau[2] = self.normal.dot(&f.n);
    }
    #[inline(always)]
    fn project_at(&self, _: &Transform, q: &[f64], f: &Force, tau: &mut [f64]) {
        self.project(q, f, tau);
    }
    /// `(ẋ, ẏ, phi̇) − (vx, vy, w)`.
    #[inline]
    fn position_residual(&self, _: &[f64], v: &[f64], qd: &[f64], res: &mut [f64]) {
        super::scalar_position_residual(v, qd, res);
    }
    fn derived_signal(&self, _: &str, _: &[f64], _: &[f64], _: &mut Vec<f64>) -> Option<()> {
        None
    }
}
