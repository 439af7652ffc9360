//! Free motion: six degrees of freedom of obj2 relative to obj1. Positions `r` (3, resolved in
//! obj1, \[m\]) and a quaternion `(w, x, y, z)` (4); velocities `ω` then `v` of obj2's origin
//! relative to obj1, resolved in one of two frames (the flag `in_obj1` of
//! [`Coord`], chosen by the plan, `dynamics/plan.rs`):
//!
//! - **in obj1** (`v = ṙ`): `S(q) = diag(Rᵀ, Rᵀ)` (R: obj2 → obj1, from the quaternion),
//!   `c_J = Ṡ v = (0, −ω₂ × v₂)` with the child-frame `ω₂ = Rᵀ ω`, `v₂ = Rᵀ v`, `Sᵀ f = (R n,
//!   R f)`: the dynamic rows are the Newton–Euler equations resolved in obj1; the quaternion
//!   rate is `½ (0, ω) ⊗ q`. For a body alone in its joint tree (obj1 fixed to the world, no
//!   body carried) whose centre of mass is its origin and whose collision shapes are spheres
//!   about it, or cylinders about it under the volume law (`ContactProfile::Volume`, the
//!   default): a ball rolling at speed `v` turns its own frame at `v/r`, so in the child
//!   frame its velocity components oscillate at that rate (tens of rad/s for a billiard ball)
//!   while in obj1 they are constant, and IDA's error test bounds the local error of each
//!   component: billiards16 at rtol 1e-5 took 13,045 steps in the child frame and 8,846 in
//!   obj1, with a 3× smaller error against a converged run (BENCHMARKS.md, "Free-motion
//!   velocities resolved in obj1"). A wooden cylinder rolling on its side down a 20° incline
//!   took 255 steps at rtol 1e-2 in the child frame (43 Newton failures, its acceleration
//!   2.5e-3 off) and 131 in obj1 (4 failures, 7.6e-6 off; BENCHMARKS.md, "Face contacts").
//! - **in obj2** (the child frame): `S` the identity, `c_J = 0`, `ṙ = R v`, the quaternion
//!   rate `½ q ⊗ (0, ω)`. For every other free joint: a body whose origin is off its centre
//!   of mass circles its centre when it spins, so its origin's velocity turns in obj1 but not
//!   in its own frame; a joint on a moving body sees its relative motion turn with obj1; and
//!   the root of a tree is pushed around by the bodies it carries. Resolved in obj1 these made
//!   the first 1,000 random scenes 40 % slower in sum (some scenes 10–60×). And bodies of
//!   other shapes pressed hard into a contact (an ellipsoid, a cone) failed Newton's method far
//!   more often with their velocities in obj1 and the DAE's own Jacobian columns (not with the
//!   solver's difference quotients); the cause is not found (both columns match central
//!   differences, `dae/jacobian.rs` tests), so they keep the child frame. Cylinders are among
//!   them under the point laws of the other profiles, where they rock on single points: in
//!   obj1 a 0.65 g steel cylinder thrown spinning onto a steel table (`tests/regressions.rs`,
//!   the paper's law) ended in ~20 s instead of ~7.5 s and `falling_boxes` under the paper's
//!   law took 17,557 steps instead of 15,859. Under the volume law they roll on their line
//!   contact and gain (above).
//!
//! The builder's `v` is `der(r)` in obj1 and its `w` is resolved in obj2 (as in Modia3D); the
//! `v` and `w` signals are those, whatever the frame of the states. The quaternion rate
//! carries a norm-restoring term.

use super::{Checker, Facts, InitialParam, JointKindSpec, ParamValue, SignalSpec, Source};
#[cfg(feature = "solver")]
use super::{KindDynamics, Row};
use crate::scene::SceneError;
#[cfg(feature = "solver")]
use crate::spatial::{quat_rate, quat_to_matrix, Force, Motion, Transform};
#[cfg(feature = "solver")]
use nalgebra::Matrix3;
use nalgebra::{UnitQuaternion, Vector3};

/// A validated FreeMotion joint.
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct Valid {
    /// Initial position, resolved in obj1 \[m\].
    pub r: Vector3<f64>,
    /// Initial orientation relative to obj1.
    pub rot: UnitQuaternion<f64>,
    /// Initial `der(r)`, resolved in obj1 [m/s].
    pub v: Vector3<f64>,
    /// Initial angular velocity, resolved in obj2 [rad/s].
    pub w: Vector3<f64>,
}

/// A FreeMotion joint in the tree: positions `r` (3, \[m\], resolved in obj1) and a
/// quaternion `(w, x, y, z)` (4); velocities `ω` then `v` of obj2's origin relative to obj1
/// ([rad/s], [m/s]), both resolved in obj1 (then `v = ṙ`) or both in obj2 (the module docs
/// say which the plan picks and why).
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct Coord {
    /// The velocities are resolved in obj1 (else in obj2).
    pub in_obj1: bool,
}

/// Rate [1/s] at which a joint quaternion is pulled back to unit norm; the exact kinematics
/// preserve the norm, so this only damps the integration error.
#[cfg(feature = "solver")]
pub(crate) const QUATERNION_NORM_RATE: f64 = 1.0;

/// Signals: `r` \[m\] (in obj1), `q` (quaternion), `w` [rad/s] (in obj2), `v` = `der(r)`
/// [m/s] (in obj1); `w` and `v` derived from the states (their frame is the plan's choice).
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
        source: Source::Derived,
    },
    SignalSpec {
        name: "v",
        unit: "m/s",
        dim: 3,
        source: Source::Derived,
    },
];

/// No scalar coordinates (the angular velocity is no rate of the quaternion); not reversible
/// (obj1 must lie on the world side); no mechanical connection (it never prevents a
/// collision).
pub(crate) const FACTS: Facts = Facts {
    spec: JointKindSpec {
        name: "FreeMotion",
        axes: &[],
        initial: &[
            InitialParam {
                key: "r",
                value: ParamValue::Vector,
                unit: "m",
            },
            InitialParam {
                key: "rot",
                value: ParamValue::Orientation,
                unit: "1",
            },
            InitialParam {
                key: "v",
                value: ParamValue::Vector,
                unit: "m/s",
            },
            InitialParam {
                key: "w",
                value: ParamValue::Vector,
                unit: "rad/s",
            },
        ],
        coordinates: &[],
        at_rest: |_| crate::JointKind::free(),
    },
    nq: 7,
    nv: 6,
    signals: SIGNALS,
    turning: &[(3, 2.0), (4, 2.0), (5, 2.0), (6, 2.0)],
    shifting: &[0, 1, 2],
    reversed: Some(|joint, obj1, obj2| SceneError::ReversedFreeMotion { joint, obj1, obj2 }),
    rigid: false,
    connects: false,
    modia3d_can_collide: false,
    hinge: false,
};

/// Validation of the builder's parameters (solver-free): finite initial values, a unit
/// initial rotation.
pub(crate) fn validate(
    c: &mut Checker,
    joint: &str,
    r: &Vector3<f64>,
    rot: &crate::FreeRotation,
    v: &Vector3<f64>,
    w: &Vector3<f64>,
) -> Valid {
    c.finite(
        || format!("joint `{joint}`: initial r [m], v [m/s], w [rad/s]"),
        &[r.as_slice(), v.as_slice(), w.as_slice()].concat(),
    );
    Valid {
        r: *r,
        rot: super::unit_rotation(c, joint, rot),
        v: *v,
        w: *w,
    }
}

#[cfg(feature = "solver")]
impl KindDynamics for Coord {
    type Valid = Valid;
    /// Initial `q` (`r`, quaternion) and `v` (`ω`, the origin's velocity, both resolved in
    /// obj2: the child frame; the plan turns them into obj1 where it resolves the joint there,
    /// [`KindDynamics::resolve_in_obj1`]) from the validated values: `v` is `der(r)` resolved
    /// in obj1, `w` is resolved in obj2. Never flipped: validation rejects a reversed
    /// FreeMotion.
    fn new(k: &Valid, _: bool, q0: &mut Vec<f64>, v0: &mut Vec<f64>) -> Coord {
        let rot = &k.rot;
        q0.extend_from_slice(k.r.as_slice());
        q0.extend_from_slice(&[rot.w, rot.i, rot.j, rot.k]);
        v0.extend_from_slice(k.w.as_slice());
        v0.extend_from_slice((rot.inverse() * k.v).as_slice());
        Coord { in_obj1: false }
    }
    /// Nothing.
    fn locked_rows(_: &Valid) -> Vec<Row> {
        vec![]
    }
    fn drawn_axis(_: &Valid) -> Option<(&'static str, Vector3<f64>)> {
        None
    }
    /// In obj1, `S(q) = diag(Rᵀ, Rᵀ)` depends on `q`; in the child frame it is the identity.
    #[inline]
    fn has_bias(&self) -> bool {
        self.in_obj1
    }
    #[inline]
    fn free_velocities(&self) -> Option<bool> {
        Some(self.in_obj1)
    }
    /// Resolves the velocities in obj1 ([`velocities_to_obj1`]).
    fn resolve_in_obj1(&mut self, q: &[f64], v: &mut [f64]) -> bool {
        self.in_obj1 = true;
        velocities_to_obj1(q, v);
        true
    }
    /// `X_J`: rotation by the quaternion `q[3..7]`, translation `q[0..3]`.
    #[inline(always)]
    fn transform(&self, q: &[f64]) -> Transform {
        Transform {
            rot: quat_to_matrix(&q[3..7]),
            pos: Vector3::new(q[0], q[1], q[2]),
        }
    }
    /// `S(q) v`, the joint velocity in the child frame: `(Rᵀ ω, Rᵀ v)` `in_obj1`, else
    /// `(ω, v)`.
    #[inline(always)]
    fn motion(&self, q: &[f64], v: &[f64]) -> Motion {
        if self.in_obj1 {
            motion_with(&quat_to_matrix(&q[3..7]), v)
        } else {
            Motion {
                w: Vector3::new(v[0], v[1], v[2]),
                v: Vector3::new(v[3], v[4], v[5]),
            }
        }
    }
    /// In obj1, the velocities turned with `xj.rot` instead of forming the rotation from the
    /// quaternion a second time.
    #[inline(always)]
    fn motion_at(&self, xj: &Transform, q: &[f64], v: &[f64]) -> Motion {
        if self.in_obj1 {
            motion_with(&xj.rot, v)
        } else {
            self.motion(q, v)
        }
    }
    /// `c_J = Ṡ v`: `(0, −ω₂ × v₂)` `in_obj1` with `(ω₂, v₂) = (Rᵀ ω, Rᵀ v)` the joint
    /// velocity `s_v` (`d(Rᵀ)/dt = −[ω₂]× Rᵀ`, and its angular part `−ω₂ × ω₂` vanishes);
    /// zero in the child frame.
    #[inline]
    fn bias(&self, _: &[f64], _: &[f64], s_v: &Motion) -> Motion {
        if !self.in_obj1 {
            return Motion::zero();
        }
        Motion {
            w: Vector3::zeros(),
            v: -s_v.w.cross(&s_v.v),
        }
    }
    /// `Sᵀ f`: the child-frame wrench resolved in obj1 `(R n, R f)` `in_obj1`, else `(n, f)`.
    #[inline]
    fn project(&self, q: &[f64], f: &Force, tau: &mut [f64]) {
        if self.in_obj1 {
            project_with(&quat_to_matrix(&q[3..7]), f, tau);
        } else {
            tau[..3].copy_from_slice(f.n.as_slice());
            tau[3..6].copy_from_slice(f.f.as_slice());
        }
    }
    /// In obj1, the wrench turned with `xj.rot`.
    #[inline(always)]
    fn project_at(&self, xj: &Transform, q: &[f64], f: &Force, tau: &mut [f64]) {
        if self.in_obj1 {
            project_with(&xj.rot, f, tau);
        } else {
            self.project(q, f, tau);
        }
    }
    /// `q̇ − q̇(q, v)`: `in_obj1`, `ṙ = v` and the quaternion rate `½ (0, ω) ⊗ q`; in the
    /// child frame `ṙ = R v` and `½ q ⊗ (0, ω)`; both with the norm-restoring term of
    /// [`quaternion_residual`].
    #[inline]
    fn position_residual(&self, q: &[f64], v: &[f64], qd: &[f64], res: &mut [f64]) {
        let (quat, w) = (&q[3..7], Vector3::new(v[0], v[1], v[2]));
        let (rd, rate) = if self.in_obj1 {
            (Vector3::new(v[3], v[4], v[5]), quat_rate_obj1(quat, &w))
        } else {
            let rot = quat_to_matrix(quat);
            (rot * Vector3::new(v[3], v[4], v[5]), quat_rate(quat, &w))
        };
        for k in 0..3 {
            res[k] = qd[k] - rd[k];
        }
        rate_residual(quat, &rate, &qd[3..7], &mut res[3..7]);
    }
    /// `w` (resolved in obj2) and `v` (`der(r)`, resolved in obj1), whatever the frame of
    /// the states.
    fn derived_signal(&self, name: &str, q: &[f64], v: &[f64], out: &mut Vec<f64>) -> Option<()> {
        match name {
            "w" => w_in_obj2(self, q, v, out),
            "v" => velocity_in_obj1(self.in_obj1, q, v, out),
            _ => return None,
        }
        Some(())
    }
}

/// The child-frame velocities `v` (`ω`, `v`) of a joint at positions `q` resolved in obj1
/// instead (`R ω`, `R v`), in place.
#[cfg(feature = "solver")]
pub(crate) fn velocities_to_obj1(q: &[f64], v: &mut [f64]) {
    let rot = quat_to_matrix(&q[3..7]);
    for h in [0, 3] {
        let x = rot * Vector3::new(v[h], v[h + 1], v[h + 2]);
        v[h..h + 3].copy_from_slice(x.as_slice());
    }
}

/// [`Coord::motion`](KindDynamics::motion) `in_obj1` with the rotation `rot = R(q)` given: `(Rᵀ ω, Rᵀ v)`.
#[cfg(feature = "solver")]
#[inline]
pub(crate) fn motion_with(rot: &Matrix3<f64>, v: &[f64]) -> Motion {
    Motion {
        w: rot.tr_mul(&Vector3::new(v[0], v[1], v[2])),
        v: rot.tr_mul(&Vector3::new(v[3], v[4], v[5])),
    }
}

/// [`Coord::project`](KindDynamics::project) `in_obj1` with the rotation `rot = R(q)` given: `(R n, R f)`.
#[cfg(feature = "solver")]
#[inline]
pub(crate) fn project_with(rot: &Matrix3<f64>, f: &Force, tau: &mut [f64]) {
    tau[..3].copy_from_slice((rot * f.n).as_slice());
    tau[3..6].copy_from_slice((rot * f.f).as_slice());
}

/// `½ (0, ω) ⊗ q`: the rate of the quaternion `q` of a frame turning at `ω` resolved in the
/// parent frame (obj1) [1/s].
#[cfg(feature = "solver")]
#[inline]
pub(crate) fn quat_rate_obj1(q: &[f64], w: &Vector3<f64>) -> [f64; 4] {
    [
        0.5 * (-w.x * q[1] - w.y * q[2] - w.z * q[3]),
        0.5 * (w.x * q[0] + w.y * q[3] - w.z * q[2]),
        0.5 * (w.y * q[0] + w.z * q[1] - w.x * q[3]),
        0.5 * (w.z * q[0] + w.x * q[2] - w.y * q[1]),
    ]
}

/// The `w` signal, `ω` resolved in obj2 [rad/s] (`Rᵀ ω` `in_obj1`).
#[cfg(feature = "solver")]
fn w_in_obj2(c: &Coord, q: &[f64], v: &[f64], out: &mut Vec<f64>) {
    out.extend_from_slice(c.motion(q, v).w.as_slice());
}

/// The `v` signal, `der(r)` resolved in obj1 [m/s] (`R v` in the child frame).
#[cfg(feature = "solver")]
fn velocity_in_obj1(in_obj1: bool, q: &[f64], v: &[f64], out: &mut Vec<f64>) {
    let lin = Vector3::new(v[3], v[4], v[5]);
    let x = if in_obj1 {
        lin
    } else {
        quat_to_matrix(&q[3..7]) * lin
    };
    out.extend_from_slice(x.as_slice());
}

/// Residual of a joint quaternion `quat` rotating at `w` (resolved in the child frame):
/// `q̇ − (½ q ⊗ ω − k (‖q‖² − 1) q)`, whose last term pulls the norm back to 1 at the rate
/// [`QUATERNION_NORM_RATE`].
#[cfg(feature = "solver")]
#[inline]
pub(crate) fn quaternion_residual(quat: &[f64], w: &Vector3<f64>, qd: &[f64], res: &mut [f64]) {
    rate_residual(quat, &quat_rate(quat, w), qd, res);
}

/// `q̇ − (rate − k (‖q‖² − 1) q)` for a quaternion `quat` whose exact rate is `rate`.
#[cfg(feature = "solver")]
#[inline]
fn rate_residual(quat: &[f64], rate: &[f64; 4], qd: &[f64], res: &mut [f64]) {
    let n2 = quat.iter().map(|x| x * x).sum::<f64>();
    let pull = QUATERNION_NORM_RATE * (n2 - 1.0);
    for k in 0..4 {
        res[k] = qd[k] - (rate[k] - pull * quat[k]);
    }
}
