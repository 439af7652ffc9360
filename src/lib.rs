//! modia3d: 3D multibody models written as Rust, simulated with SUNDIALS IDA (variable step,
//! error control) and, for collisions, compliant contacts located by zero crossings.
//!
//! The crate is a facade: [`core`] holds the scene builder, dynamics, solver and results;
//! the `model!` macro comes from `modia3d-macros`. Most programs need only the [`prelude`].
//!
//! ```
//! use modia3d::prelude::*;
//! let mut scene = SceneDesc::new();
//! scene
//!     .add(Object3D::new("world").scene(SceneOptions::default()))
//!     .add(Object3D::new("bob").solid(Solid::new(Shape::Sphere { diameter: 0.1 }).mass(1.0)))
//!     .add(Object3D::new("pivot").parent("bob").translation([0.0, 0.0, 1.0]))
//!     .add_joint(Joint::new("rev", "world", "pivot", JointKind::revolute(1)).init_position(0.5));
//! let model = scene.build()?;
//! let result = model.simulate(&SimOptions::new(1.0).tolerance(1e-8))?;
//! // Energy is conserved: the swing never exceeds its initial amplitude.
//! assert!(result.signal("rev.phi")?.values().iter().all(|p| p.abs() <= 0.5 + 1e-6));
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```
//!
//! The same model written with [`model!`], checked at compile time:
//!
//! ```
//! use modia3d::prelude::*;
//!
//! model! {
//!     /// A ball on a massless rod of length `l`, released at `phi0`.
//!     pub Pendulum(l: f64 = 1.0, phi0: f64 = 0.5) {
//!         world = Object3D(feature = Scene()),
//!         bob   = Object3D(feature = Solid(shape = Sphere(diameter = 0.1),
//!                                          mass_properties = MassProperties(mass = 1.0))),
//!         pivot = Object3D(parent = bob, translation = [0.0, 0.0, l]),
//!         rev   = Revolute(obj1 = world, obj2 = pivot, axis = 1, phi = Var(init = phi0)),
//!     }
//! }
//!
//! let model = Pendulum { l: 1.0, ..Default::default() }.build()?;
//! let result = model.simulate(&SimOptions::new(1.0).tolerance(1e-8))?;
//! assert!(result.signal("rev.phi")?.last().ok_or("no output point")?[0] < 0.5);
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```
#![warn(missing_docs)]
#![warn(unreachable_pub)]

pub use modia3d_core as core;
pub use modia3d_macros::model;

/// A signal of the outer model handed to a `model!` sub-assembly as a parameter, so that its
/// blocks read it: `pub assembly Servo(reference: SignalRef = SignalRef::time()) { pi = PI(…,
/// u = reference - drive.motor_phi / 156.0) }`, used as `axis1 = Servo(reference = ramp.y)`
/// (the outer `model!` resolves `ramp.y` and names it with its prefix).
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct SignalRef(String);

impl SignalRef {
    /// The signal named `path` in the built scene (`"ramp.y"`, `"arm1.rev.phi"`).
    pub fn new(path: &str) -> Self {
        SignalRef(path.to_string())
    }
    /// Time \[s\].
    pub fn time() -> Self {
        SignalRef::new("time")
    }
    /// The signal's name in the built scene.
    pub fn path(&self) -> &str {
        &self.0
    }
}

impl Default for SignalRef {
    /// Time (a parameter needs a default; give the signal when using the assembly).
    fn default() -> Self {
        SignalRef::time()
    }
}

/// A joint of the outer model handed to a `model!` sub-assembly as a parameter, so that its
/// `Drive` acts on it: `pub assembly Servo(joint: JointRef = JointRef::default()) { drive =
/// Drive(joint = joint, …) }`, used as `axis1 = Servo(joint = shoulder)`.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct JointRef(String);

impl JointRef {
    /// The joint named `path` in the built scene (`"rev"`, `"arm1.shoulder"`).
    pub fn new(path: &str) -> Self {
        JointRef(path.to_string())
    }
    /// The joint's name in the built scene (empty by default: `build()` then reports an
    /// unknown joint).
    pub fn path(&self) -> &str {
        &self.0
    }
}

/// Support items for the code `model!` generates; not part of the API.
#[doc(hidden)]
pub mod __private {
    pub use nalgebra;
    /// The type of a hidden item that names an object of a `model!` type.
    pub struct ObjectPath;
    /// The type of a hidden item that names a joint of a `model!` type.
    pub struct JointPath;
    /// The type of a hidden item that names a force element or material of a `model!` type.
    pub struct OtherPath;
    /// The type of a hidden item that names a signal a block of a `model!` type reads
    /// (`pi.y`, `rev.w`).
    pub struct SignalPath;
    /// What a signal of a `model!` type is, as a type alias of the signal's name beside its
    /// constant: a joint coordinate's velocity (`rev.w`, whose derivative `der(…)` reads) …
    pub struct VelocitySignal;
    /// … or any other signal (a position, a block's output or state).
    pub struct OtherSignal;

    /// A signal `der(…)` takes: a joint coordinate's velocity.
    #[diagnostic::on_unimplemented(
        message = "`der(…)` reads the acceleration of a joint coordinate's velocity: this signal is no velocity",
        label = "not a joint coordinate's velocity",
        note = "a joint's velocities are its coordinates' rates (`w` of a revolute joint, `v` of a prismatic one): `der(arm.rev.w)`"
    )]
    pub trait Velocity {}
    impl Velocity for VelocitySignal {}

    /// Compiles when `T`, the kind of a signal of a sub-assembly that `der(…)` reads, is a
    /// velocity.
    pub fn velocity<T: Velocity>() {}

    /// What a sub-assembly's parameter given a path of the outer model (`reference = ramp.y`,
    /// `joint = rev`) is: a `SignalRef` or a `JointRef`, whichever the parameter is.
    #[diagnostic::on_unimplemented(
        message = "a signal or joint of this model is given to a parameter of type `{Self}`",
        label = "a path of this model",
        note = "a sub-assembly takes a signal as a `SignalRef` parameter and a joint as a `JointRef` parameter"
    )]
    pub trait FromPath {
        /// The reference to the signal or joint named `path` in the built scene.
        fn from_path(path: &str) -> Self;
    }
    impl FromPath for crate::SignalRef {
        fn from_path(path: &str) -> Self {
            crate::SignalRef::new(path)
        }
    }
    impl FromPath for crate::JointRef {
        fn from_path(path: &str) -> Self {
            crate::JointRef::new(path)
        }
    }

    /// A block's list of numbers (`v_max = [1.0, 2.0]`) from an array, a `Vec` or any iterable.
    pub fn numbers(v: impl IntoIterator<Item = f64>) -> Vec<f64> {
        v.into_iter().collect()
    }
    /// A block's rows of numbers (`positions = [[0.0], [1.0]]`) from arrays, `Vec`s or any
    /// iterables.
    pub fn rows<R: IntoIterator<Item = f64>>(v: impl IntoIterator<Item = R>) -> Vec<Vec<f64>> {
        v.into_iter().map(|r| r.into_iter().collect()).collect()
    }
    /// A block's `(time, value)` rows (`table = [(0.0, 1.0), (1.0, 2.0)]`).
    pub fn pairs(v: impl IntoIterator<Item = (f64, f64)>) -> Vec<(f64, f64)> {
        v.into_iter().collect()
    }

    /// What `model!` accepts where the builder wants a `Vector3<f64>`.
    #[diagnostic::on_unimplemented(
        message = "expected `[f64; 3]` or `Vector3<f64>`, found `{Self}`",
        label = "expected a 3-vector"
    )]
    pub trait IntoVector3 {
        /// The vector.
        fn into_vector3(self) -> nalgebra::Vector3<f64>;
    }
    impl IntoVector3 for [f64; 3] {
        fn into_vector3(self) -> nalgebra::Vector3<f64> {
            nalgebra::Vector3::from(self)
        }
    }
    impl IntoVector3 for nalgebra::Vector3<f64> {
        fn into_vector3(self) -> nalgebra::Vector3<f64> {
            self
        }
    }
    /// A `Vector3<f64>` from `[f64; 3]` or `Vector3<f64>`.
    pub fn vector3(v: impl IntoVector3) -> nalgebra::Vector3<f64> {
        v.into_vector3()
    }

    /// `Scene(gravity_field = …)`: the field, set.
    pub fn gravity_field(g: modia3d_core::GravityField) -> Option<modia3d_core::GravityField> {
        Some(g)
    }

    /// Three force laws from an array of numbers (linear coefficients) or `Law`s: a
    /// `Bushing`'s law key given as an expression rather than an array literal.
    pub fn laws<T: Into<modia3d_core::Law>>(a: [T; 3]) -> [modia3d_core::Law; 3] {
        a.map(Into::into)
    }

    /// What `model!` accepts for a contact pair's `v_min` / `w_min`: `f64` or `Option<f64>`.
    #[diagnostic::on_unimplemented(
        message = "expected `f64` or `Option<f64>`, found `{Self}`",
        label = "expected a number"
    )]
    pub trait IntoOptionalF64 {
        /// The value.
        fn into_optional_f64(self) -> Option<f64>;
    }
    impl IntoOptionalF64 for f64 {
        fn into_optional_f64(self) -> Option<f64> {
            Some(self)
        }
    }
    impl IntoOptionalF64 for Option<f64> {
        fn into_optional_f64(self) -> Option<f64> {
            self
        }
    }
    /// `Some(v)` from `f64`, or the `Option<f64>` itself.
    pub fn optional_f64(v: impl IntoOptionalF64) -> Option<f64> {
        v.into_optional_f64()
    }

    /// What `model!` accepts where the builder wants a `Matrix3<f64>`: rows `[[f64; 3]; 3]` or
    /// a `Matrix3<f64>`.
    #[diagnostic::on_unimplemented(
        message = "expected rows `[[f64; 3]; 3]` or `Matrix3<f64>`, found `{Self}`",
        label = "expected a 3×3 matrix"
    )]
    pub trait IntoMatrix3 {
        /// The matrix.
        fn into_matrix3(self) -> nalgebra::Matrix3<f64>;
    }
    impl IntoMatrix3 for [[f64; 3]; 3] {
        fn into_matrix3(self) -> nalgebra::Matrix3<f64> {
            nalgebra::Matrix3::from_fn(|i, j| self[i][j])
        }
    }
    impl IntoMatrix3 for nalgebra::Matrix3<f64> {
        fn into_matrix3(self) -> nalgebra::Matrix3<f64> {
            self
        }
    }
    /// A `Matrix3<f64>` from rows `[[f64; 3]; 3]` or a `Matrix3<f64>`.
    pub fn matrix3(m: impl IntoMatrix3) -> nalgebra::Matrix3<f64> {
        m.into_matrix3()
    }

    /// What `model!` accepts for `rotation`: Cardan angles `[f64; 3]`, a rotation matrix
    /// `Matrix3<f64>` (columns: the frame's axes in the parent), or a `Rotation`.
    #[diagnostic::on_unimplemented(
        message = "expected Cardan angles `[f64; 3]`, a `Matrix3<f64>` or a `Rotation`, found `{Self}`",
        label = "expected a rotation"
    )]
    pub trait IntoRotation {
        /// The rotation.
        fn into_rotation(self) -> modia3d_core::Rotation;
    }
    impl IntoRotation for [f64; 3] {
        fn into_rotation(self) -> modia3d_core::Rotation {
            modia3d_core::Rotation::Cardan(self)
        }
    }
    impl IntoRotation for nalgebra::Matrix3<f64> {
        fn into_rotation(self) -> modia3d_core::Rotation {
            modia3d_core::Rotation::Matrix(self)
        }
    }
    impl IntoRotation for modia3d_core::Rotation {
        fn into_rotation(self) -> modia3d_core::Rotation {
            self
        }
    }
    /// A `Rotation` from Cardan angles, a matrix or a `Rotation`.
    pub fn rotation(r: impl IntoRotation) -> modia3d_core::Rotation {
        r.into_rotation()
    }

    /// What `model!` accepts for a FreeMotion's `rot`: Cardan angles `[f64; 3]`, a
    /// `UnitQuaternion<f64>`, or a `FreeRotation`.
    #[diagnostic::on_unimplemented(
        message = "expected Cardan angles `[f64; 3]`, a `UnitQuaternion<f64>` or a `FreeRotation`, found `{Self}`",
        label = "expected an orientation"
    )]
    pub trait IntoFreeRotation {
        /// The orientation.
        fn into_free_rotation(self) -> modia3d_core::FreeRotation;
    }
    impl IntoFreeRotation for [f64; 3] {
        fn into_free_rotation(self) -> modia3d_core::FreeRotation {
            modia3d_core::FreeRotation::Cardan(self)
        }
    }
    impl IntoFreeRotation for nalgebra::UnitQuaternion<f64> {
        fn into_free_rotation(self) -> modia3d_core::FreeRotation {
            modia3d_core::FreeRotation::Quaternion(self)
        }
    }
    impl IntoFreeRotation for modia3d_core::FreeRotation {
        fn into_free_rotation(self) -> modia3d_core::FreeRotation {
            self
        }
    }
    /// The points of a convex hull from anything iterable over `[f64; 3]` or `Point3<f64>`.
    pub fn points<P: Into<nalgebra::Point3<f64>>>(
        points: impl IntoIterator<Item = P>,
    ) -> Vec<nalgebra::Point3<f64>> {
        points.into_iter().map(Into::into).collect()
    }

    /// A `FreeRotation` from Cardan angles, a quaternion or a `FreeRotation`.
    pub fn free_rotation(r: impl IntoFreeRotation) -> modia3d_core::FreeRotation {
        r.into_free_rotation()
    }
}

extern crate self as modia3d;

pub mod demo;

/// Everything a model needs: builder types, shapes, options, results, nalgebra's vectors.
pub mod prelude {
    pub use crate::{JointRef, SignalRef};
    pub use modia3d_core::{blocks, Component, ComponentDecl, ComponentIo, ComponentJacobian, Src};
    pub use modia3d_core::{
        linspace, ColumnInfo, Distribution, ParamPoints, Params, RunError, Sweep, SweepError,
        SweepRegistry, SweepRow, SweepSpec, SweepTable,
    };
    pub use modia3d_core::{
        Action, ActionError, ActionKind, Axis, BodyInfo, ContactPairInfo, ContactPairMaterial,
        ContactPhase, ContactProfile, Event, Feature, ForceElement, ForceFn, FreeRotation, Input,
        InputError, InputKind, Joint, JointKind, JointLimit, JointLoadPeak, LoopInfo, MassSpec,
        MaterialPalette, MaterialRef, MeshCollision, Model, Object3D, ObjectMotion, PlotFormat,
        PlotOptions, ResultError, Rotation, SceneDesc, SceneError, SceneErrors, SceneOptions,
        Shape, Signal, SimError, SimErrorKind, SimOptions, SimStats, SimWarning, Simulation,
        SimulationResult, Solid, SolidMaterial, Wrench,
    };
    pub use modia3d_core::{Bushing, GravityField, Law, VectorLaw};
    pub use modia3d_macros::model;
    pub use nalgebra::{Matrix3, Point3, UnitQuaternion, Vector3};
}

/// The README's code blocks, compiled and run as doctests so the README stays true.
#[doc = include_str!("../README.md")]
#[cfg(doctest)]
pub struct ReadmeDoctests;
