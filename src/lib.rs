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
//!     .add(Object3D::new("pivot").parent("bob").translation([0.0, 1.0, 0.0]))
//!     .add_joint(Joint::new("rev", "world", "pivot", JointKind::revolute(1)).init_position(0.5));
//! let model = scene.build()?;
//! let result = model.simulate(&SimOptions::new(1.0).tolerance(1e-8))?;
//! assert!(result.signal("rev.phi")?.last()[0] < 0.5);
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
//! assert!(result.signal("rev.phi")?.last()[0] < 0.5);
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```
#![warn(missing_docs)]

pub use modia3d_core as core;
pub use modia3d_macros::model;

/// Support items for the code `model!` generates; not part of the API.
#[doc(hidden)]
pub mod __private {
    pub use modia3d_macros::__solid_material_names;
    pub use nalgebra;
    /// The type of a hidden item that names an object of a `model!` type.
    pub struct ObjectPath;
    /// The type of a hidden item that names a joint of a `model!` type.
    pub struct JointPath;
    /// The type of a hidden item that names a force element or material of a `model!` type.
    pub struct OtherPath;
}

/// Everything a model needs: builder types, shapes, options, results, nalgebra's vectors.
pub mod prelude {
    pub use modia3d_core::{
        Axis, Event, Feature, ForceElement, ForceFn, FreeRotation, Joint, JointKind, MassSpec,
        MaterialRef, Model, Object3D, ObjectMotion, ResultError, Rotation, SceneDesc, SceneError,
        SceneErrors, SceneOptions, Shape, Signal, SimError, SimErrorKind, SimOptions, SimStats,
        SimulationResult, Solid, SolidMaterial, Wrench,
    };
    pub use modia3d_macros::model;
    pub use nalgebra::{Matrix3, Point3, UnitQuaternion, Vector3};
}
