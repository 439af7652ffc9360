//! modia3d-core: scenes, multibody dynamics, contacts and the IDA solver wrapper.
//!
//! Cargo feature `solver` (default) builds every stage; without it only the solver-free stages
//! compile — [`scene`] (description, materials, validation) and [`geometry`] — so the `model!`
//! macro can run the same scene checks at compile time without building SUNDIALS.
#![warn(missing_docs)]
// Only the solver stage's FFI module `solver::ida` (solver/ida.rs with its children ida/callbacks.rs
// and ida/linear.rs) may use `unsafe`; `mod ida` opts back in explicitly.
#![deny(unsafe_code)]

#[cfg(feature = "solver")]
pub mod contact;
#[cfg(feature = "solver")]
pub mod dae;
#[cfg(feature = "solver")]
pub mod dynamics;
pub mod geometry;
#[cfg(feature = "solver")]
pub mod model;
#[cfg(feature = "solver")]
pub mod results;
pub mod scene;
#[cfg(feature = "solver")]
pub mod simulation;
#[cfg(feature = "solver")]
pub mod solver;

pub use geometry::{Axis, Shape};
#[cfg(feature = "solver")]
pub use model::Model;
#[cfg(feature = "solver")]
pub use results::{Event, ResultError, Signal, SimStats, SimulationResult};
pub use scene::{
    ContactPairMaterial, ContactProfile, Feature, ForceElement, ForceFn, FreeRotation, Input,
    InputKind, Joint, JointKind, MassSpec, MaterialPalette, MaterialRef, Object3D, ObjectMotion,
    Rotation, SceneDesc, SceneError, SceneErrors, SceneOptions, Solid, SolidMaterial, Wrench,
};
#[cfg(feature = "solver")]
pub use simulation::{InputError, SimError, SimErrorKind, SimOptions, Simulation};
