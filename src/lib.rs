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
#![warn(missing_docs)]

pub use modia3d_core as core;

pub mod demo;

/// Everything a model needs: builder types, shapes, options, results, nalgebra's vectors.
pub mod prelude {
    pub use modia3d_core::{
        Axis, ContactPairMaterial, ContactProfile, Event, Feature, ForceElement, ForceFn,
        FreeRotation, Joint, JointKind, MassSpec, MaterialPalette, MaterialRef, Model, Object3D,
        ObjectMotion, ResultError, Rotation, SceneDesc, SceneError, SceneErrors, SceneOptions,
        Shape, Signal, SimError, SimErrorKind, SimOptions, SimStats, SimulationResult, Solid,
        SolidMaterial, Wrench,
    };
    pub use nalgebra::{Matrix3, Point3, UnitQuaternion, Vector3};
}
