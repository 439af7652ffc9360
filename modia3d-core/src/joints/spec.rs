//! The joint kinds as the builder and `model!` see them (solver-free vocabulary, exported as
//! [`crate::JOINT_KINDS`]): each kind's name, the parameters of its [`JointKind`] variant with
//! their defaults and units, its scalar coordinates, and the kind at rest. Each kind's file states its row
//! (`joints/<kind>.rs`, the `spec` of its `FACTS`); `joints/mod.rs` gathers the rows in the
//! order of its table. The `model!` macro reads these rows instead of keeping a vocabulary of
//! joints of its own.

use crate::scene::JointKind;
use nalgebra::Vector3;

/// One joint kind: its name (the [`JointKind`] variant's and the `model!` constructor's), its
/// parameters (the variant's fields: axes first, then initial values, each in the variant's
/// order) and the kind at rest.
#[derive(Clone, Copy)]
pub struct JointKindSpec {
    /// The variant's and the constructor's name, e.g. `"Revolute"`.
    pub name: &'static str,
    /// The axis parameters (unit-free directions, resolved as the variant's docs say).
    pub axes: &'static [AxisParam],
    /// The initial values, in the variant's field order.
    pub initial: &'static [InitialParam],
    /// The scalar coordinates (what `JointSpringDamper`, `JointForce` and
    /// `JointAcceleration` act on; empty for kinds whose rotation is a quaternion).
    pub coordinates: &'static [JointCoordinate],
    /// The kind at rest (every initial value its default) with the axes that `axis(key)`
    /// gives; an axis it does not give (known only at run time) is replaced by one that the
    /// scene's rules accept (`model!` checks the literal part of a block with it).
    pub at_rest: fn(axis: &AxisOf<'_>) -> JointKind,
}

/// The axes `model!` knows of a joint, by key (`None`: known only at run time); see
/// [`JointKindSpec::at_rest`].
pub type AxisOf<'a> = dyn Fn(&str) -> Option<Vector3<f64>> + 'a;

impl std::fmt::Debug for JointKindSpec {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("JointKindSpec")
            .field("name", &self.name)
            .field("axes", &self.axes)
            .field("initial", &self.initial)
            .field("coordinates", &self.coordinates)
            .finish_non_exhaustive()
    }
}

impl JointKindSpec {
    /// The parameter keys in the variant's field order: the axes, then the initial values.
    pub fn keys(&self) -> impl Iterator<Item = &'static str> {
        let (axes, initial) = (self.axes, self.initial);
        axes.iter()
            .map(|a| a.key)
            .chain(initial.iter().map(|p| p.key))
    }

    /// The signal names of each scalar coordinate: its position and its velocity (`("phi",
    /// "w")`, `("s", "v")`), in the order of `coordinates`. The rows list the initial values
    /// of scalar coordinates as the positions, then the velocities in `v` order (the joints'
    /// unit test checks this against each kind's signals).
    pub fn coordinate_signals(&self) -> impl Iterator<Item = (&'static str, &'static str)> {
        let (initial, n) = (self.initial, self.coordinates.len());
        self.coordinates.iter().map(move |c| {
            let vel = initial.get(n + c.v).map_or("", |p| p.key);
            (c.name, vel)
        })
    }
}

/// An axis parameter of a joint kind.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct AxisParam {
    /// The key (the variant's field), e.g. `"axis"`.
    pub key: &'static str,
    /// The default Modia axis (±1, ±2, ±3 for ±x, ±y, ±z); `None`: required.
    pub default: Option<i64>,
}

/// An initial-value parameter of a joint kind.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct InitialParam {
    /// The key (the variant's field), e.g. `"phi"`.
    pub key: &'static str,
    /// What it takes; its default (at rest) is zero or the identity rotation.
    pub value: ParamValue,
    /// Its unit, e.g. `"rad"`, `"m/s"` (`"1"` for a rotation).
    pub unit: &'static str,
}

/// The type of a joint parameter's value.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ParamValue {
    /// An `f64`; default 0.
    Number,
    /// A 3-vector (`Vector3<f64>`); default zero.
    Vector,
    /// An orientation ([`crate::FreeRotation`]); default the identity. (Not named
    /// `Rotation`: a second public item of that name makes rustc print the crate's
    /// `Rotation` with its full path in `model!`'s type errors.)
    Orientation,
}

/// A scalar coordinate of a joint: a position `q[q]` whose rate is the velocity `v[v]`
/// (`q̇ = v`), which spring-dampers and joint inputs act on.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct JointCoordinate {
    /// Name of the position, e.g. `"phi1"`.
    pub name: &'static str,
    /// Unit of the position (`"rad"` or `"m"`); the velocity's is this per second.
    pub unit: &'static str,
    /// Offset of the position in the joint's `q`.
    pub q: usize,
    /// Offset of the velocity in the joint's `v`.
    pub v: usize,
    /// The `model!` keys of a limit on it ([`crate::JointLimit`]).
    pub limit_keys: LimitKeys,
}

/// The `model!` keys of a joint limit on one scalar coordinate `c` (`limit_keys!("c")` states
/// them): `c_limits = [lower, upper]`, `c_limit_stiffness`, `c_limit_cor`.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct LimitKeys {
    /// `"<c>_limits"`: `[lower, upper]` \[rad or m\] (`f64::INFINITY`: no upper bound).
    pub range: &'static str,
    /// `"<c>_limit_stiffness"` \[N·m/rad or N/m\].
    pub stiffness: &'static str,
    /// `"<c>_limit_cor"` \[-\].
    pub cor: &'static str,
}

/// The [`LimitKeys`] of coordinate `$c` (a string literal).
macro_rules! limit_keys {
    ($c:literal) => {
        $crate::joints::spec::LimitKeys {
            range: concat!($c, "_limits"),
            stiffness: concat!($c, "_limit_stiffness"),
            cor: concat!($c, "_limit_cor"),
        }
    };
}
pub(crate) use limit_keys;
