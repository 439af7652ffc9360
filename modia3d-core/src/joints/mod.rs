//! Joint kinds, each in one file that states every fact of its kind (`FACTS`: name, parameters,
//! `nq`, `nv`, signals, reversal, capabilities; its validated data `Valid`
//! and its tree data `Coord`; `validate`; and — with the `solver` feature — [`KindDynamics`]:
//! initial state, locked rows, the joint transform `X_J(q)`, the joint velocity `S(q) v` and
//! the bias `c_J = Ṡ q̇` (both resolved in the child frame), the projection `Sᵀ f` and the
//! kinematic residual `q̇ − q̇(q, v)`). No fact has a default: `Facts` is a plain struct
//! literal and [`KindDynamics`] a trait without provided methods.
//!
//! The kinds are listed once, in the table `kinds!` at the end of this file; it generates
//! [`ValidJointKind`], [`JointCoord`], [`JOINT_KINDS`] (the solver-free rows `model!` reads,
//! [`spec`]) and every dispatch over kinds as an exhaustive `match` (no trait objects on the
//! hot path), including the builder's [`JointKind::name`] and validation's
//! [`validate_kind`]. Code elsewhere asks a kind's capabilities (`is_rigid`, `has_bias`,
//! `is_hinge`, `free_velocities`, …), never its name. Adding a kind means: its file here,
//! one line of the table, its builder variant (`scene/desc.rs`), docs.
//!
//! Stage: shared by validation (solver-free facts) and the plan and residual (dynamics). This
//! module compiles without the `solver` feature so that validation — which the `model!` macro
//! runs at compile time without SUNDIALS — asks the same kind the dynamics asks; the dynamics
//! are gated behind `solver` because they use the spatial algebra of `spatial.rs`. Touches
//! only the slices of `q`, `v` it is given.

#![cfg_attr(not(feature = "solver"), allow(dead_code))]

pub(crate) mod cylindrical;
pub(crate) mod fix;
pub(crate) mod free;
pub(crate) mod planar;
pub(crate) mod prismatic;
pub(crate) mod revolute;
#[cfg(feature = "solver")]
pub(crate) mod rows;
pub(crate) mod spec;
pub(crate) mod spherical;
pub(crate) mod universal;

pub use spec::{
    AxisOf, AxisParam, InitialParam, JointCoordinate, JointKindSpec, LimitKeys, ParamValue,
};

#[cfg(feature = "solver")]
use crate::joints::rows::Row;
use crate::scene::validate::error::Checker;
use crate::scene::SceneError;
#[cfg(feature = "solver")]
use crate::spatial::{Force, Motion, Transform};
use crate::{FreeRotation, JointKind};
use nalgebra::UnitQuaternion;
use nalgebra::Vector3;

/// The solver-free facts of one joint kind, stated by its file (`<kind>::FACTS`); a struct
/// literal, so a kind states every one.
#[derive(Clone, Copy)]
pub(crate) struct Facts {
    /// Name and parameters, as the builder and `model!` see them.
    pub spec: JointKindSpec,
    /// Number of positions.
    pub nq: usize,
    /// Number of velocities.
    pub nv: usize,
    /// Signals (`"<joint>.<name>"`), in state order.
    pub signals: &'static [SignalSpec],
    /// Positions that turn the child body, with the turn per unit \[rad\] (a quaternion's
    /// component turns it by up to 2 rad per unit, an angle by 1).
    pub turning: &'static [(usize, f64)],
    /// Positions that shift the child body (translations).
    pub shifting: &'static [usize],
    /// `None` when the spanning tree may traverse the joint from obj2 to obj1 (its
    /// coordinates keep their meaning with the axis negated); else the error of such a
    /// joint, from its name, obj1 and obj2 (obj1 must lie on the world side).
    pub reversed: Option<fn(String, String, String) -> SceneError>,
    /// obj2 is fixed to obj1: the two are one rigid body, the joint has no coordinates and is
    /// never in the tree.
    pub rigid: bool,
    /// A mechanical connection: the solids of its two bodies do not collide unless
    /// `can_collide` (FreeMotion is none: it never prevents a collision).
    pub connects: bool,
    /// The default of `can_collide` with `SceneOptions::modia3d_conventions` (Modia3D lets
    /// the solids of Revolute and Prismatic joints collide).
    pub modia3d_can_collide: bool,
    /// A hinge of `dae/hinge_jacobian.rs`: `q̇ = v`, `S` constant in the child frame with
    /// columns `(a, 0)` or `(0, a)` of one axis `a`, and `X_J(q)` their exponential.
    pub hinge: bool,
}

/// The dynamics of one joint kind, implemented by its tree data `<kind>::Coord` in its file
/// (no provided methods: each kind states each one).
#[cfg(feature = "solver")]
pub(crate) trait KindDynamics: Sized {
    /// The kind's validated data.
    type Valid;
    /// The tree coordinates of a validated joint (axes negated when `flipped`: the tree runs
    /// from obj2 to obj1), with its initial positions and velocities appended to `q0`, `v0`.
    fn new(valid: &Self::Valid, flipped: bool, q0: &mut Vec<f64>, v0: &mut Vec<f64>) -> Self;
    /// The rows a joint of the kind locks when it is cut to close a loop.
    fn locked_rows(valid: &Self::Valid) -> Vec<Row>;
    /// The axis the HTML viewer draws, with its label (`"revolute"`, `"prismatic"`).
    fn drawn_axis(valid: &Self::Valid) -> Option<(&'static str, Vector3<f64>)>;
    /// Whether `S` depends on `q` (then the bias `c_J = Ṡ q̇` is not zero).
    fn has_bias(&self) -> bool;
    /// `Some(in_obj1)` for a joint that leaves all six degrees of freedom free (positions `r`
    /// (3) then a quaternion (4); velocities `ω` then `v` (3 + 3), resolved in obj1 when
    /// `in_obj1`, else in obj2), `None` otherwise.
    fn free_velocities(&self) -> Option<bool>;
    /// Resolves the joint's velocities in obj1 where the kind can (a free joint: `joints/free.rs`
    /// says when it pays), turning its initial velocities `v` at positions `q`; `false` if it
    /// cannot.
    fn resolve_in_obj1(&mut self, q: &[f64], v: &mut [f64]) -> bool;
    /// The joint transform `X_J(q)`: the child (joint) frame placed in the joint's
    /// parent-side frame.
    fn transform(&self, q: &[f64]) -> Transform;
    /// The joint velocity `S(q) v`, resolved in the child frame.
    fn motion(&self, q: &[f64], v: &[f64]) -> Motion;
    /// [`Self::motion`] with `xj = X_J(q)` at hand.
    fn motion_at(&self, xj: &Transform, q: &[f64], v: &[f64]) -> Motion;
    /// The bias `c_J = Ṡ(q) v`; `s_v` is [`Self::motion`].
    fn bias(&self, q: &[f64], v: &[f64], s_v: &Motion) -> Motion;
    /// The generalised forces `Sᵀ f` into `tau`.
    fn project(&self, q: &[f64], f: &Force, tau: &mut [f64]);
    /// [`Self::project`] with `xj = X_J(q)` at hand.
    fn project_at(&self, xj: &Transform, q: &[f64], f: &Force, tau: &mut [f64]);
    /// The kinematic residual `q̇ − q̇(q, v)` into `res`.
    fn position_residual(&self, q: &[f64], v: &[f64], qd: &[f64], res: &mut [f64]);
    /// The values of a derived signal `name` appended to `out`; `None` if the kind has none.
    fn derived_signal(&self, name: &str, q: &[f64], v: &[f64], out: &mut Vec<f64>) -> Option<()>;
}

/// `q̇ − v`: the kinematic residual of a kind whose positions are all scalar coordinates.
#[cfg(feature = "solver")]
#[inline]
pub(crate) fn scalar_position_residual(v: &[f64], qd: &[f64], res: &mut [f64]) {
    for k in 0..res.len() {
        res[k] = qd[k] - v[k];
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

/// Largest admissible `|‖q‖ − 1|` of an initial quaternion (round-off of a normalised
/// quaternion is ~1e-16; a user's rounded literal digits stay well inside).
const UNIT_QUATERNION_TOLERANCE: f64 = 1e-6;

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

/// A builder field read as a number ([`JointKind::initial_number`]): `f64`s are, axes and
/// rotations are not.
trait Number {
    fn number(&self) -> Option<f64>;
}
impl Number for f64 {
    fn number(&self) -> Option<f64> {
        Some(*self)
    }
}
impl Number for Vector3<f64> {
    fn number(&self) -> Option<f64> {
        None
    }
}
impl Number for FreeRotation {
    fn number(&self) -> Option<f64> {
        None
    }
}

/// Generates, from the table of kinds (`Variant { builder fields } => file`), the enums over
/// kinds and every dispatch: each a `match` with one arm per kind, no wildcard.
macro_rules! kinds {
    ($($name:ident { $($field:ident),* } => $file:ident,)*) => {
        /// The solver-free rows of the joint kinds (name, parameter keys, defaults, units), in
        /// the order of the table in `joints/mod.rs`; the `model!` macro reads them.
        pub const JOINT_KINDS: &[JointKindSpec] = &[$($file::FACTS.spec,)*];

        /// The builder fields of each kind's variant, as the table names them (the test that
        /// they are the rows' keys is in this module's tests).
        #[cfg(test)]
        const BUILDER_FIELDS: &[(&str, &[&str])] =
            &[$((stringify!($name), &[$(stringify!($field)),*]),)*];

        /// A validated joint kind (unit axes, a unit quaternion): each kind's `Valid`.
        #[derive(Clone, Debug, PartialEq)]
        pub(crate) enum ValidJointKind {
            $(
                #[doc = concat!("`", stringify!($name), "` (`joints/", stringify!($file), ".rs`).")]
                $name($file::Valid),
            )*
        }

        /// Coordinates of a joint in the tree, with its axes resolved in the joint frame (which
        /// coincides with obj1's frame at zero coordinates and is the child body's frame): each
        /// kind's `Coord` (a Fix joint's is uninhabited: it is never in the tree).
        #[derive(Clone, Copy, Debug, PartialEq)]
        pub(crate) enum JointCoord {
            $(
                #[doc = concat!("`", stringify!($name), "` (`joints/", stringify!($file), ".rs`).")]
                $name($file::Coord),
            )*
        }

        impl JointKind {
            /// A short name for messages (the kind's name in `model!`).
            pub fn name(&self) -> &'static str {
                self.facts().spec.name
            }
            /// The kind's solver-free facts.
            pub(crate) fn facts(&self) -> &'static Facts {
                match self {
                    $(JointKind::$name { .. } => &$file::FACTS,)*
                }
            }
            /// The value of the number parameter `key` (a scalar coordinate's initial value:
            /// the variant's field of that name); `None` for another key.
            pub(crate) fn initial_number(&self, key: &str) -> Option<f64> {
                match self {
                    $(JointKind::$name { $($field),* } => {
                        $(if stringify!($field) == key {
                            return Number::number($field);
                        })*
                        None
                    })*
                }
            }
        }

        /// The validated kind of joint `joint`'s builder kind `k` (each kind's `validate`), or
        /// `None` when a check failed (the errors are in `c`).
        pub(crate) fn validate_kind(
            c: &mut Checker,
            joint: &str,
            k: &JointKind,
        ) -> Option<ValidJointKind> {
            let before = c.errors.len();
            let kind = match k {
                $(JointKind::$name { $($field),* } => {
                    ValidJointKind::$name($file::validate(c, joint, $($field),*))
                })*
            };
            (c.errors.len() == before).then_some(kind)
        }

        impl ValidJointKind {
            /// The kind's solver-free facts.
            pub(crate) fn facts(&self) -> &'static Facts {
                match self {
                    $(ValidJointKind::$name(_) => &$file::FACTS,)*
                }
            }
            /// The rows a joint of this kind locks when it is cut to close a loop.
            #[cfg(feature = "solver")]
            pub(crate) fn locked_rows(&self) -> Vec<Row> {
                match self {
                    $(ValidJointKind::$name(k) => {
                        <$file::Coord as KindDynamics>::locked_rows(k)
                    })*
                }
            }
            /// The axis the HTML viewer draws (resolved in obj1), with its label.
            #[cfg(feature = "solver")]
            pub(crate) fn drawn_axis(&self) -> Option<(&'static str, Vector3<f64>)> {
                match self {
                    $(ValidJointKind::$name(k) => {
                        <$file::Coord as KindDynamics>::drawn_axis(k)
                    })*
                }
            }
        }

        impl JointCoord {
            /// The kind's solver-free facts.
            #[inline]
            pub(crate) fn facts(&self) -> &'static Facts {
                match self {
                    $(JointCoord::$name(_) => &$file::FACTS,)*
                }
            }
        }

        #[cfg(feature = "solver")]
        impl JointCoord {
            /// The tree coordinates of a validated kind (axes negated when `flipped`: the tree
            /// runs from obj2 to obj1), with its initial positions and velocities appended to
            /// `q0`, `v0`.
            // A Fix joint's arm: `fix::Coord::new` never returns (its joints are merged).
            #[allow(unreachable_code)]
            pub(crate) fn new(
                kind: &ValidJointKind,
                flipped: bool,
                q0: &mut Vec<f64>,
                v0: &mut Vec<f64>,
            ) -> JointCoord {
                match kind {
                    $(ValidJointKind::$name(k) => {
                        JointCoord::$name(KindDynamics::new(k, flipped, q0, v0))
                    })*
                }
            }
            /// Whether `S` depends on `q` (then the bias `c_J = Ṡ q̇` is not zero).
            #[inline]
            pub(crate) fn has_bias(&self) -> bool {
                match self {
                    $(JointCoord::$name(c) => c.has_bias(),)*
                }
            }
            /// `Some(in_obj1)` for a joint that leaves all six degrees of freedom free
            /// (`KindDynamics::free_velocities`), `None` otherwise.
            #[inline]
            pub(crate) fn free_velocities(&self) -> Option<bool> {
                match self {
                    $(JointCoord::$name(c) => c.free_velocities(),)*
                }
            }
            /// Resolves the joint's velocities in obj1 where the kind can, turning its
            /// initial velocities `v` at positions `q`; `false` if it cannot.
            pub(crate) fn resolve_in_obj1(&mut self, q: &[f64], v: &mut [f64]) -> bool {
                match self {
                    $(JointCoord::$name(c) => c.resolve_in_obj1(q, v),)*
                }
            }
            /// The joint transform `X_J(q)`: the child (joint) frame placed in the joint's
            /// parent-side frame; `q` is the joint's positions. Always inlined: with a second
            /// caller (the results' chain kinematics) the compiler stopped inlining it into the
            /// hot path's `position_velocity`, +8 % instructions per call there.
            #[inline(always)]
            pub(crate) fn transform(&self, q: &[f64]) -> Transform {
                match self {
                    $(JointCoord::$name(c) => c.transform(q),)*
                }
            }
            /// The joint velocity `S(q) v`, resolved in the child frame; `v` is the joint's
            /// velocities (or accelerations: `S(q) v̇`). Always inlined, as
            /// [`Self::transform`].
            #[inline(always)]
            pub(crate) fn motion(&self, q: &[f64], v: &[f64]) -> Motion {
                match self {
                    $(JointCoord::$name(c) => c.motion(q, v),)*
                }
            }
            /// [`Self::motion`] with the joint transform `xj = X_J(q)` ([`Self::transform`]) at
            /// hand: a free joint resolved in obj1 turns its velocities with `xj.rot` instead of
            /// forming the rotation from the quaternion a second time (the kinematics' hot
            /// path).
            #[inline(always)]
            pub(crate) fn motion_at(&self, xj: &Transform, q: &[f64], v: &[f64]) -> Motion {
                match self {
                    $(JointCoord::$name(c) => c.motion_at(xj, q, v),)*
                }
            }
            /// The bias `c_J = Ṡ(q) v` (the apparent derivative in the child frame), zero for
            /// kinds whose `S` is constant ([`Self::has_bias`]). `s_v` is the joint velocity
            /// `S(q) v` ([`Self::motion`]), which the free joint's bias is formed from.
            #[inline]
            pub(crate) fn bias(&self, q: &[f64], v: &[f64], s_v: &Motion) -> Motion {
                match self {
                    $(JointCoord::$name(c) => c.bias(q, v, s_v),)*
                }
            }
            /// [`Self::project`] with the joint transform `xj = X_J(q)` at hand (as
            /// [`Self::motion_at`]).
            #[inline(always)]
            pub(crate) fn project_at(&self, xj: &Transform, q: &[f64], f: &Force, tau: &mut [f64]) {
                match self {
                    $(JointCoord::$name(c) => c.project_at(xj, q, f, tau),)*
                }
            }
            /// The generalised forces `Sᵀ f` of a spatial force `f` transmitted by the joint
            /// (resolved in the child frame) into `tau` (the joint's `nv` entries).
            #[inline]
            pub(crate) fn project(&self, q: &[f64], f: &Force, tau: &mut [f64]) {
                match self {
                    $(JointCoord::$name(c) => c.project(q, f, tau),)*
                }
            }
            /// The kinematic residual `q̇ − q̇(q, v)` of the joint into `res` (its `nq`
            /// entries).
            #[inline]
            pub(crate) fn position_residual(&self, q: &[f64], v: &[f64], qd: &[f64], res: &mut [f64]) {
                match self {
                    $(JointCoord::$name(c) => c.position_residual(q, v, qd, res),)*
                }
            }
            /// The values of a [`Source::Derived`] signal `name` at the joint's `q`, `v`
            /// appended to `out`; `None` if the kind has no such signal.
            pub(crate) fn derived_signal(
                &self,
                name: &str,
                q: &[f64],
                v: &[f64],
                out: &mut Vec<f64>,
            ) -> Option<()> {
                match self {
                    $(JointCoord::$name(c) => c.derived_signal(name, q, v, out),)*
                }
            }
        }
    };
}

// The joint kinds, once: `Variant { fields of the builder's variant } => file`.
kinds! {
    Fix {} => fix,
    Revolute { axis, phi, w } => revolute,
    Prismatic { axis, s, v } => prismatic,
    FreeMotion { r, rot, v, w } => free,
    Spherical { rot, w } => spherical,
    Universal { axis1, axis2, phi1, phi2, w1, w2 } => universal,
    Cylindrical { axis, phi, s, w, v } => cylindrical,
    Planar { normal, x, y, phi, vx, vy, w } => planar,
}

impl ValidJointKind {
    /// Whether obj2 is fixed to obj1 (one rigid body; never in the tree).
    pub(crate) fn is_rigid(&self) -> bool {
        self.facts().rigid
    }
    /// Whether the joint is a mechanical connection (see `Facts::connects`).
    pub(crate) fn connects(&self) -> bool {
        self.facts().connects
    }
}

impl JointCoord {
    /// Number of position coordinates.
    #[inline]
    pub(crate) fn nq(&self) -> usize {
        self.facts().nq
    }
    /// Number of velocity coordinates.
    #[inline]
    pub(crate) fn nv(&self) -> usize {
        self.facts().nv
    }
    /// Its signals (`"<joint>.<name>"`), in state order.
    pub(crate) fn signals(&self) -> &'static [SignalSpec] {
        self.facts().signals
    }
    /// Its scalar coordinates.
    pub(crate) fn coordinates(&self) -> &'static [JointCoordinate] {
        self.facts().spec.coordinates
    }
    /// Whether it is a hinge of `dae/hinge_jacobian.rs` (`Facts::hinge`).
    pub(crate) fn is_hinge(&self) -> bool {
        self.facts().hinge
    }
    /// Calls `f(i, rad_per_unit)` for every position `q[i]` of the joint that turns its child
    /// body: the quaternion's components of FreeMotion and Spherical joints (a change `δq`
    /// turns by up to `2 δq` rad) and the angles of the others (1 rad per unit). Translations
    /// are not passed.
    pub(crate) fn for_each_turning_position(&self, mut f: impl FnMut(usize, f64)) {
        for &(i, rad_per_unit) in self.facts().turning {
            f(i, rad_per_unit);
        }
    }
    /// Calls `f(i)` for every position `q[i]` of the joint that shifts its child body.
    pub(crate) fn for_each_shifting_position(&self, mut f: impl FnMut(usize)) {
        for &i in self.facts().shifting {
            f(i);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Each row's keys are its builder variant's fields, in order; its signals, coordinates
    /// and turning/shifting positions agree with `nq`, `nv`.
    #[test]
    fn rows_agree_with_their_builder_variants_and_states() {
        assert_eq!(JOINT_KINDS.len(), BUILDER_FIELDS.len());
        for (spec, (name, fields)) in JOINT_KINDS.iter().zip(BUILDER_FIELDS) {
            assert_eq!(spec.name, *name);
            assert_eq!(spec.keys().collect::<Vec<_>>(), *fields, "{name}");
        }
        let all = [
            &fix::FACTS,
            &revolute::FACTS,
            &prismatic::FACTS,
            &free::FACTS,
            &spherical::FACTS,
            &universal::FACTS,
            &cylindrical::FACTS,
            &planar::FACTS,
        ];
        assert_eq!(all.len(), JOINT_KINDS.len());
        for f in all {
            let name = f.spec.name;
            let (mut nq, mut nv) = (0, 0);
            for s in f.signals {
                match s.source {
                    Source::Q(o) => nq = nq.max(o + s.dim),
                    Source::V(o) => nv = nv.max(o + s.dim),
                    Source::Derived => {}
                }
            }
            assert_eq!(nq, f.nq, "{name}: positions of the signals");
            assert!(nv <= f.nv, "{name}: velocities of the signals");
            for c in f.spec.coordinates {
                assert!(c.q < f.nq && c.v < f.nv, "{name}: coordinate {}", c.name);
                assert_eq!(c.limit_keys.range, format!("{}_limits", c.name), "{name}");
                let turns = f.turning.iter().any(|&(i, r)| i == c.q && r == 1.0);
                let shifts = f.shifting.contains(&c.q);
                assert_eq!(turns, c.unit == "rad", "{name}: {}", c.name);
                assert_eq!(shifts, c.unit == "m", "{name}: {}", c.name);
            }
            // `JointKindSpec::coordinate_signals` (what `model!` resolves `rev.w` with) names
            // each coordinate's position and velocity signals.
            for ((p, v), c) in f.spec.coordinate_signals().zip(f.spec.coordinates) {
                let q = f
                    .signals
                    .iter()
                    .find(|s| s.dim == 1 && s.source == Source::Q(c.q));
                let w = f
                    .signals
                    .iter()
                    .find(|s| s.dim == 1 && s.source == Source::V(c.v));
                assert_eq!(q.map(|s| s.name), Some(p), "{name}: position of {}", c.name);
                assert_eq!(w.map(|s| s.name), Some(v), "{name}: velocity of {}", c.name);
            }
            assert!(f.turning.iter().all(|&(i, _)| i < f.nq), "{name}");
            assert!(f.shifting.iter().all(|&i| i < f.nq), "{name}");
        }
    }
}
