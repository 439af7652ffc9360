//! Joint kinds, each in one file: its coordinates (`nq`, `nv`), the names and units of its
//! signals with their state offsets, its scalar coordinates (what spring-dampers and inputs
//! act on), its initial state from the validated kind and — with the `solver` feature — its
//! dynamics: the joint transform `X_J(q)`, the joint velocity `S(q) v` and the bias
//! `c_J = Ṡ q̇` (both resolved in the child frame), the projection `Sᵀ f` and the kinematic
//! residual `q̇ − q̇(q, v)`.
//!
//! Stage: shared by validation (solver-free facts: coordinate names, units, reversibility) and
//! the plan and residual (dynamics). This module compiles without the `solver` feature so that
//! validation — which the `model!` macro runs at compile time without SUNDIALS — asks the same
//! kind the dynamics asks; the dynamics functions are gated behind `solver` because they use
//! the spatial algebra of `spatial.rs`. Touches only the slices of `q`, `v` it is given.
//!
//! The rest of the crate asks a [`JointCoord`] (a small enum whose methods dispatch to the
//! per-kind files; no trait objects in the hot path). Each kind's file also validates the
//! builder's parameters (`validate`, solver-free, with the scene's `Checker`) and lists the
//! directions it locks when it is cut to close a loop (`locked_rows`). Adding a kind means:
//! its file here and its variants and dispatch lines below ([`ValidJointKind`], [`JointCoord`],
//! [`validate_kind`], [`locked_rows`]), its builder variant (`scene/desc.rs`), the macro's
//! vocabulary, docs.

#![cfg_attr(not(feature = "solver"), allow(dead_code))]

pub(crate) mod cylindrical;
pub(crate) mod free;
pub(crate) mod planar;
pub(crate) mod prismatic;
pub(crate) mod revolute;
#[cfg(feature = "solver")]
pub(crate) mod rows;
pub(crate) mod spherical;
pub(crate) mod universal;

#[cfg(feature = "solver")]
use crate::joints::rows::Row;
use crate::scene::validate::error::Checker;
#[cfg(feature = "solver")]
use crate::spatial::{Force, Motion, Transform};
use crate::{FreeRotation, JointKind};
use nalgebra::UnitQuaternion;
use nalgebra::Vector3;

/// A resolved joint kind with unit axes and a unit quaternion.
#[derive(Clone, Debug, PartialEq)]
pub enum ValidJointKind {
    /// Rigid.
    Fix,
    /// Revolute about a unit axis resolved in obj1; initial angle \[rad\] and rate [rad/s].
    Revolute {
        /// Unit axis.
        axis: Vector3<f64>,
        /// Initial angle \[rad\].
        phi: f64,
        /// Initial angular velocity [rad/s].
        w: f64,
    },
    /// Prismatic along a unit axis resolved in obj1; initial position \[m\] and velocity [m/s].
    Prismatic {
        /// Unit axis.
        axis: Vector3<f64>,
        /// Initial position \[m\].
        s: f64,
        /// Initial velocity [m/s].
        v: f64,
    },
    /// Free motion.
    FreeMotion {
        /// Initial position, resolved in obj1 \[m\].
        r: Vector3<f64>,
        /// Initial orientation relative to obj1.
        rot: UnitQuaternion<f64>,
        /// Initial `der(r)`, resolved in obj1 [m/s].
        v: Vector3<f64>,
        /// Initial angular velocity, resolved in obj2 [rad/s].
        w: Vector3<f64>,
    },
    /// Ball joint.
    Spherical {
        /// Initial orientation relative to obj1.
        rot: UnitQuaternion<f64>,
        /// Initial angular velocity, resolved in obj2 [rad/s].
        w: Vector3<f64>,
    },
    /// Cardan joint with unit, exactly perpendicular axes.
    Universal {
        /// First axis (fixed in obj1), unit.
        axis1: Vector3<f64>,
        /// Second axis (fixed in obj2), unit, perpendicular to `axis1`.
        axis2: Vector3<f64>,
        /// Initial angles \[rad\].
        phi1: f64,
        /// See `phi1`.
        phi2: f64,
        /// Initial rates [rad/s].
        w1: f64,
        /// See `w1`.
        w2: f64,
    },
    /// Rotation about and translation along a unit axis.
    Cylindrical {
        /// Unit axis.
        axis: Vector3<f64>,
        /// Initial angle \[rad\].
        phi: f64,
        /// Initial position \[m\].
        s: f64,
        /// Initial angular velocity [rad/s].
        w: f64,
        /// Initial velocity [m/s].
        v: f64,
    },
    /// Planar motion normal to a unit normal.
    Planar {
        /// Unit normal.
        normal: Vector3<f64>,
        /// Initial positions \[m\] (resolved in obj1) and angle \[rad\].
        x: f64,
        /// See `x`.
        y: f64,
        /// See `x`.
        phi: f64,
        /// Initial rates [m/s], [rad/s].
        vx: f64,
        /// See `vx`.
        vy: f64,
        /// See `vx`.
        w: f64,
    },
}

impl ValidJointKind {
    /// The kind's name, as [`crate::JointKind::name`].
    pub fn name(&self) -> &'static str {
        match self {
            ValidJointKind::Fix => "Fix",
            ValidJointKind::Revolute { .. } => "Revolute",
            ValidJointKind::Prismatic { .. } => "Prismatic",
            ValidJointKind::FreeMotion { .. } => "FreeMotion",
            ValidJointKind::Spherical { .. } => "Spherical",
            ValidJointKind::Universal { .. } => "Universal",
            ValidJointKind::Cylindrical { .. } => "Cylindrical",
            ValidJointKind::Planar { .. } => "Planar",
        }
    }
}

/// Largest admissible `|‖q‖ − 1|` of an initial quaternion (round-off of a normalised
/// quaternion is ~1e-16; a user's rounded literal digits stay well inside).
const UNIT_QUATERNION_TOLERANCE: f64 = 1e-6;

/// The validated kind of joint `joint`'s builder kind `k` (each kind's `validate`), or `None`
/// when a check failed (the errors are in `c`).
pub(crate) fn validate_kind(c: &mut Checker, joint: &str, k: &JointKind) -> Option<ValidJointKind> {
    let before = c.errors.len();
    let kind = match k {
        JointKind::Fix => ValidJointKind::Fix,
        JointKind::Revolute { axis, phi, w } => revolute::validate(c, joint, axis, *phi, *w),
        JointKind::Prismatic { axis, s, v } => prismatic::validate(c, joint, axis, *s, *v),
        JointKind::FreeMotion { r, rot, v, w } => free::validate(c, joint, r, rot, v, w),
        JointKind::Spherical { rot, w } => spherical::validate(c, joint, rot, w),
        JointKind::Universal {
            axis1,
            axis2,
            phi1,
            phi2,
            w1,
            w2,
        } => universal::validate(c, joint, axis1, axis2, *phi1, *phi2, *w1, *w2),
        JointKind::Cylindrical { axis, phi, s, w, v } => {
            cylindrical::validate(c, joint, axis, [*phi, *s, *w, *v])
        }
        JointKind::Planar {
            normal,
            x,
            y,
            phi,
            vx,
            vy,
            w,
        } => planar::validate(c, joint, normal, [*x, *y, *phi, *vx, *vy, *w]),
    };
    (c.errors.len() == before).then_some(kind)
}

/// `axis` normalised; a zero (or non-finite) length is an error naming the joint.
pub(crate) fn unit_axis(c: &mut Checker, joint: &str, axis: &Vector3<f64>) -> Vector3<f64> {
    let n = axis.norm();
    c.value(
        || format!("joint `{joint}`: axis length"),
        n,
        n > 0.0,
        "non-zero (an axis ±1, ±2, ±3 or a direction vector)",
    );
    axis / n
}

/// The unit quaternion of an initial rotation (FreeMotion, Spherical): Cardan angles finite, a
/// given quaternion finite and of unit norm.
pub(crate) fn unit_rotation(
    c: &mut Checker,
    joint: &str,
    rot: &FreeRotation,
) -> UnitQuaternion<f64> {
    match rot {
        FreeRotation::Cardan(a) => {
            c.finite(
                || format!("joint `{joint}`: initial Cardan angles [rad]"),
                a,
            );
            UnitQuaternion::from_rotation_matrix(&nalgebra::Rotation3::from_matrix_unchecked(
                crate::scene::cardan_to_matrix(*a),
            ))
        }
        FreeRotation::Quaternion(q) => {
            c.finite(
                || format!("joint `{joint}`: initial quaternion"),
                q.coords.as_slice(),
            );
            // A `UnitQuaternion` made with `new_unchecked` may be anything: a zero
            // (or far from unit) quaternion is no rotation, and the solver would
            // fail on it later without naming the joint.
            let n = q.coords.norm();
            if n.is_finite() && (n - 1.0).abs() > UNIT_QUATERNION_TOLERANCE {
                c.errors.push(crate::scene::SceneError::InvalidValue {
                    what: format!("joint `{joint}`: norm of the initial quaternion"),
                    value: n,
                    expected: "1 within 1e-6 (a unit quaternion: build it with UnitQuaternion::from_quaternion or new_normalize, not new_unchecked)",
                });
            }
            // Exactly unit from here on (the joint is dropped if the check failed).
            UnitQuaternion::new_normalize(q.into_inner())
        }
    }
}

/// The rows a joint of `kind` locks when it is cut to close a loop (each kind's
/// `locked_rows`; a Fix locks all six).
#[cfg(feature = "solver")]
pub(crate) fn locked_rows(kind: &ValidJointKind) -> Vec<Row> {
    match kind {
        ValidJointKind::Fix => {
            let mut r = Row::translations(&[Vector3::x(), Vector3::y(), Vector3::z()]);
            r.extend(Row::rotations());
            r
        }
        ValidJointKind::Revolute { axis, .. } => revolute::locked_rows(axis),
        ValidJointKind::Prismatic { axis, .. } => prismatic::locked_rows(axis),
        ValidJointKind::FreeMotion { .. } => free::locked_rows(),
        ValidJointKind::Spherical { .. } => spherical::locked_rows(),
        ValidJointKind::Universal { axis1, axis2, .. } => universal::locked_rows(axis1, axis2),
        ValidJointKind::Cylindrical { axis, .. } => cylindrical::locked_rows(axis),
        ValidJointKind::Planar { normal, .. } => planar::locked_rows(normal),
    }
}

/// Where a signal of a joint comes from.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Source {
    /// Positions `q[offset..offset + dim]` of the joint.
    Q(usize),
    /// Velocities `v[offset..offset + dim]` of the joint.
    V(usize),
    /// Computed from the joint's `q` and `v` by [`JointCoord::derived_signal`].
    Derived,
}

/// A signal of a joint: `"<joint>.<name>"`, `dim` values, unit.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) struct SignalSpec {
    /// The quantity's name, e.g. `"phi"`.
    pub name: &'static str,
    /// Unit, e.g. `"rad"`.
    pub unit: &'static str,
    /// Number of values.
    pub dim: usize,
    /// Where the values come from.
    pub source: Source,
}

/// A scalar coordinate of a joint: a position `q[q]` whose rate is the velocity `v[v]`
/// (`q̇ = v`), which spring-dampers and joint inputs act on.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) struct Coordinate {
    /// Name of the position, e.g. `"phi1"`.
    pub name: &'static str,
    /// Unit of the position (`"rad"` or `"m"`); the velocity's is this per second.
    pub unit: &'static str,
    /// Offset of the position in the joint's `q`.
    pub q: usize,
    /// Offset of the velocity in the joint's `v`.
    pub v: usize,
}

/// Solver-free facts of a kind, by its name ([`crate::JointKind::name`]).
#[derive(Clone, Copy, Debug)]
pub(crate) struct KindInfo {
    /// Scalar coordinates (empty for kinds whose rotation is a quaternion).
    pub coordinates: &'static [Coordinate],
    /// Whether the spanning tree may traverse it from obj2 to obj1 (the coordinates keep
    /// their meaning with the axis negated); otherwise obj1 must lie on the world side.
    pub reversible: bool,
}

/// The facts of the kind named `name`; `None` for `Fix` (no coordinates).
pub(crate) fn info(name: &str) -> Option<&'static KindInfo> {
    Some(match name {
        "Revolute" => &revolute::INFO,
        "Prismatic" => &prismatic::INFO,
        "FreeMotion" => &free::INFO,
        "Spherical" => &spherical::INFO,
        "Universal" => &universal::INFO,
        "Cylindrical" => &cylindrical::INFO,
        "Planar" => &planar::INFO,
        _ => return None,
    })
}

/// Coordinates of a joint in the tree, with its axes resolved in the joint frame (which
/// coincides with obj1's frame at zero coordinates and is the child body's frame).
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum JointCoord {
    /// Rotation about a unit axis resolved in the joint frame (= child body frame axis);
    /// one position `phi` \[rad\], one velocity `w` [rad/s].
    Revolute {
        /// Unit axis (already negated when the joint is traversed from obj2 to obj1).
        axis: Vector3<f64>,
    },
    /// Translation along a unit axis resolved in the joint frame;
    /// one position `s` \[m\], one velocity `v` [m/s].
    Prismatic {
        /// Unit axis (already negated when traversed from obj2 to obj1).
        axis: Vector3<f64>,
    },
    /// Six degrees of freedom: positions `r` (3, \[m\], resolved in obj1) and a quaternion
    /// `(w, x, y, z)` (4); velocities `ω` then `v` of obj2's origin relative to obj1 ([rad/s],
    /// [m/s]), both resolved in obj1 (then `v = ṙ`) or both in obj2 (`joints/free.rs` says
    /// which the plan picks and why).
    Free {
        /// The velocities are resolved in obj1 (else in obj2).
        in_obj1: bool,
    },
    /// Ball joint: a quaternion (4) and `ω` resolved in obj2 (3, [rad/s]).
    Spherical,
    /// Cardan joint: `phi1` about `axis1` (fixed in obj1), then `phi2` about `axis2` (fixed in
    /// obj2); unit, perpendicular axes resolved in the joint frame.
    Universal {
        /// First axis, fixed in obj1.
        axis1: Vector3<f64>,
        /// Second axis, fixed in obj2.
        axis2: Vector3<f64>,
    },
    /// Rotation `phi` about and translation `s` along one unit axis.
    Cylindrical {
        /// Unit axis (already negated when traversed from obj2 to obj1).
        axis: Vector3<f64>,
    },
    /// Translations `x`, `y` along `e1`, `e2` (resolved in obj1) and rotation `phi` about
    /// `normal`.
    Planar {
        /// Unit normal of the plane.
        normal: Vector3<f64>,
        /// First in-plane axis.
        e1: Vector3<f64>,
        /// Second in-plane axis, `normal × e1`.
        e2: Vector3<f64>,
    },
}

impl JointCoord {
    /// The kind's name, as [`crate::JointKind::name`].
    pub fn name(&self) -> &'static str {
        match self {
            JointCoord::Revolute { .. } => "Revolute",
            JointCoord::Prismatic { .. } => "Prismatic",
            JointCoord::Free { .. } => "FreeMotion",
            JointCoord::Spherical => "Spherical",
            JointCoord::Universal { .. } => "Universal",
            JointCoord::Cylindrical { .. } => "Cylindrical",
            JointCoord::Planar { .. } => "Planar",
        }
    }
    /// Number of position coordinates.
    pub fn nq(&self) -> usize {
        match self {
            JointCoord::Revolute { .. } | JointCoord::Prismatic { .. } => 1,
            JointCoord::Free { .. } => free::NQ,
            JointCoord::Spherical => spherical::NQ,
            JointCoord::Universal { .. } | JointCoord::Cylindrical { .. } => 2,
            JointCoord::Planar { .. } => 3,
        }
    }
    /// Number of velocity coordinates.
    pub fn nv(&self) -> usize {
        match self {
            JointCoord::Revolute { .. } | JointCoord::Prismatic { .. } => 1,
            JointCoord::Free { .. } => free::NV,
            JointCoord::Spherical => spherical::NV,
            JointCoord::Universal { .. } | JointCoord::Cylindrical { .. } => 2,
            JointCoord::Planar { .. } => 3,
        }
    }
    /// Its signals (`"<joint>.<name>"`), in state order.
    pub(crate) fn signals(&self) -> &'static [SignalSpec] {
        match self {
            JointCoord::Revolute { .. } => revolute::SIGNALS,
            JointCoord::Prismatic { .. } => prismatic::SIGNALS,
            JointCoord::Free { .. } => free::SIGNALS,
            JointCoord::Spherical => spherical::SIGNALS,
            JointCoord::Universal { .. } => universal::SIGNALS,
            JointCoord::Cylindrical { .. } => cylindrical::SIGNALS,
            JointCoord::Planar { .. } => planar::SIGNALS,
        }
    }
    /// Its scalar coordinates.
    pub(crate) fn coordinates(&self) -> &'static [Coordinate] {
        info(self.name()).map_or(&[], |i| i.coordinates)
    }
    /// Calls `f(i, rad_per_unit)` for every position `q[i]` of the joint that turns its child
    /// body: the quaternion's components of FreeMotion and Spherical joints (a change `δq`
    /// turns by up to `2 δq` rad) and the angles of the others (`"rad"` coordinates, 1 rad per
    /// unit). Translations are not passed.
    pub(crate) fn for_each_turning_position(&self, mut f: impl FnMut(usize, f64)) {
        match self {
            JointCoord::Free { .. } => (3..7).for_each(|i| f(i, 2.0)),
            JointCoord::Spherical => (0..4).for_each(|i| f(i, 2.0)),
            _ => {
                for c in self.coordinates().iter().filter(|c| c.unit == "rad") {
                    f(c.q, 1.0);
                }
            }
        }
    }
    /// Calls `f(i)` for every position `q[i]` of the joint that shifts its child body: the
    /// translation of a FreeMotion joint and the `"m"` coordinates of the others.
    pub(crate) fn for_each_shifting_position(&self, mut f: impl FnMut(usize)) {
        match self {
            JointCoord::Free { .. } => (0..3).for_each(&mut f),
            JointCoord::Spherical => {}
            _ => {
                for c in self.coordinates().iter().filter(|c| c.unit == "m") {
                    f(c.q);
                }
            }
        }
    }
    /// Whether `S` depends on `q` (then the bias `c_J = Ṡ q̇` is not zero).
    #[inline]
    pub fn has_bias(&self) -> bool {
        matches!(
            self,
            JointCoord::Universal { .. }
                | JointCoord::Planar { .. }
                | JointCoord::Free { in_obj1: true }
        )
    }
}

#[cfg(feature = "solver")]
impl JointCoord {
    /// The tree coordinates of a validated kind (axes negated when `flipped`: the tree runs
    /// from obj2 to obj1), with its initial positions and velocities appended to `q0`, `v0`.
    pub(crate) fn new(
        kind: &ValidJointKind,
        flipped: bool,
        q0: &mut Vec<f64>,
        v0: &mut Vec<f64>,
    ) -> JointCoord {
        let orient = |a: &Vector3<f64>| if flipped { -a } else { *a };
        match kind {
            ValidJointKind::Revolute { axis, phi, w } => {
                q0.push(*phi);
                v0.push(*w);
                JointCoord::Revolute { axis: orient(axis) }
            }
            ValidJointKind::Prismatic { axis, s, v } => {
                q0.push(*s);
                v0.push(*v);
                JointCoord::Prismatic { axis: orient(axis) }
            }
            // Never flipped: validation rejects a reversed FreeMotion.
            ValidJointKind::FreeMotion { r, rot, v, w } => {
                free::initial(r, rot, v, w, q0, v0);
                JointCoord::Free { in_obj1: false }
            }
            // Never flipped (not reversible), as FreeMotion.
            ValidJointKind::Spherical { rot, w } => {
                spherical::initial(rot, w, q0, v0);
                JointCoord::Spherical
            }
            ValidJointKind::Universal {
                axis1,
                axis2,
                phi1,
                phi2,
                w1,
                w2,
            } => {
                q0.extend_from_slice(&[*phi1, *phi2]);
                v0.extend_from_slice(&[*w1, *w2]);
                JointCoord::Universal {
                    axis1: *axis1,
                    axis2: *axis2,
                }
            }
            ValidJointKind::Cylindrical { axis, phi, s, w, v } => {
                q0.extend_from_slice(&[*phi, *s]);
                v0.extend_from_slice(&[*w, *v]);
                JointCoord::Cylindrical { axis: orient(axis) }
            }
            ValidJointKind::Planar {
                normal,
                x,
                y,
                phi,
                vx,
                vy,
                w,
            } => {
                q0.extend_from_slice(&[*x, *y, *phi]);
                v0.extend_from_slice(&[*vx, *vy, *w]);
                let (e1, e2) = planar::plane_axes(normal);
                JointCoord::Planar {
                    normal: *normal,
                    e1,
                    e2,
                }
            }
            ValidJointKind::Fix => unreachable!("fix joints are merged"),
        }
    }

    /// The joint transform `X_J(q)`: the child (joint) frame placed in the joint's parent-side
    /// frame; `q` is the joint's positions. Always inlined: with a second caller (the results'
    /// chain kinematics) the compiler stopped inlining it into the hot path's
    /// `position_velocity`, +8 % instructions per call there.
    #[inline(always)]
    pub fn transform(&self, q: &[f64]) -> Transform {
        match self {
            JointCoord::Revolute { axis } => revolute::transform(axis, q),
            JointCoord::Prismatic { axis } => prismatic::transform(axis, q),
            JointCoord::Free { .. } => free::transform(q),
            JointCoord::Spherical => spherical::transform(q),
            JointCoord::Universal { axis1, axis2 } => universal::transform(axis1, axis2, q),
            JointCoord::Cylindrical { axis } => cylindrical::transform(axis, q),
            JointCoord::Planar { normal, e1, e2 } => planar::transform(normal, e1, e2, q),
        }
    }

    /// The joint velocity `S(q) v`, resolved in the child frame; `v` is the joint's
    /// velocities (or accelerations: `S(q) v̇`). Always inlined, as [`Self::transform`].
    #[inline(always)]
    pub fn motion(&self, q: &[f64], v: &[f64]) -> Motion {
        match self {
            JointCoord::Revolute { axis } => revolute::motion(axis, v),
            JointCoord::Prismatic { axis } => prismatic::motion(axis, v),
            JointCoord::Free { in_obj1 } => free::motion(*in_obj1, q, v),
            JointCoord::Spherical => spherical::motion(v),
            JointCoord::Universal { axis1, axis2 } => universal::motion(axis1, axis2, q, v),
            JointCoord::Cylindrical { axis } => cylindrical::motion(axis, v),
            JointCoord::Planar { normal, e1, e2 } => planar::motion(normal, e1, e2, q, v),
        }
    }

    /// [`Self::motion`] with the joint transform `xj = X_J(q)` ([`Self::transform`]) at hand:
    /// a free joint resolved in obj1 turns its velocities with `xj.rot` instead of forming the
    /// rotation from the quaternion a second time (the kinematics' hot path).
    #[inline(always)]
    pub fn motion_at(&self, xj: &Transform, q: &[f64], v: &[f64]) -> Motion {
        match self {
            JointCoord::Free { in_obj1: true } => free::motion_with(&xj.rot, v),
            _ => self.motion(q, v),
        }
    }

    /// The bias `c_J = Ṡ(q) v` (the apparent derivative in the child frame) for kinds whose
    /// `S` depends on `q` ([`Self::has_bias`]); zero for the others. `s_v` is the joint
    /// velocity `S(q) v` ([`Self::motion`]), which the free joint's bias is formed from.
    #[inline]
    pub fn bias(&self, q: &[f64], v: &[f64], s_v: &Motion) -> Motion {
        match self {
            JointCoord::Universal { axis1, axis2 } => universal::bias(axis1, axis2, q, v),
            JointCoord::Planar { normal, e1, e2 } => planar::bias(normal, e1, e2, q, v),
            JointCoord::Free { in_obj1 } => free::bias(*in_obj1, s_v),
            _ => Motion::zero(),
        }
    }

    /// [`Self::project`] with the joint transform `xj = X_J(q)` at hand (as
    /// [`Self::motion_at`]): a free joint resolved in obj1 turns the wrench with `xj.rot`.
    #[inline(always)]
    pub fn project_at(&self, xj: &Transform, q: &[f64], f: &Force, tau: &mut [f64]) {
        match self {
            JointCoord::Free { in_obj1: true } => free::project_with(&xj.rot, f, tau),
            _ => self.project(q, f, tau),
        }
    }

    /// The generalised forces `Sᵀ f` of a spatial force `f` transmitted by the joint
    /// (resolved in the child frame) into `tau` (the joint's `nv` entries).
    #[inline]
    pub fn project(&self, q: &[f64], f: &Force, tau: &mut [f64]) {
        match self {
            JointCoord::Revolute { axis } => revolute::project(axis, f, tau),
            JointCoord::Prismatic { axis } => prismatic::project(axis, f, tau),
            JointCoord::Free { in_obj1 } => free::project(*in_obj1, q, f, tau),
            JointCoord::Spherical => spherical::project(f, tau),
            JointCoord::Universal { axis1, axis2 } => universal::project(axis1, axis2, q, f, tau),
            JointCoord::Cylindrical { axis } => cylindrical::project(axis, f, tau),
            JointCoord::Planar { normal, e1, e2 } => planar::project(normal, e1, e2, q, f, tau),
        }
    }

    /// The kinematic residual `q̇ − q̇(q, v)` of the joint into `res` (its `nq` entries).
    #[inline]
    pub fn position_residual(&self, q: &[f64], v: &[f64], qd: &[f64], res: &mut [f64]) {
        match self {
            JointCoord::Free { in_obj1 } => free::position_residual(*in_obj1, q, v, qd, res),
            JointCoord::Spherical => spherical::position_residual(q, v, qd, res),
            // q̇ = v for every kind whose coordinates are all scalar.
            _ => {
                for k in 0..res.len() {
                    res[k] = qd[k] - v[k];
                }
            }
        }
    }

    /// The values of a [`Source::Derived`] signal `name` at the joint's `q`, `v` appended to
    /// `out`; `None` if the kind has no such signal.
    pub(crate) fn derived_signal(
        &self,
        name: &str,
        q: &[f64],
        v: &[f64],
        out: &mut Vec<f64>,
    ) -> Option<()> {
        match (self, name) {
            (JointCoord::Free { in_obj1 }, "w") => free::w_in_obj2(*in_obj1, q, v, out),
            (JointCoord::Free { in_obj1 }, "v") => free::velocity_in_obj1(*in_obj1, q, v, out),
            _ => return None,
        }
        Some(())
    }
}
