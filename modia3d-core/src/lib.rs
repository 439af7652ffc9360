//! modia3d-core: scenes, multibody dynamics, contacts and the IDA solver wrapper.
#![warn(missing_docs)]
// Only the solver stage's FFI module (solver/ida.rs) may use `unsafe`; it opts back in explicitly.
#![deny(unsafe_code)]

pub mod contact;
pub mod dae;
pub mod dynamics;
pub mod geometry;
pub mod results;
pub mod scene;
pub mod simulation;
pub mod solver;

pub use geometry::{Axis, Shape};
pub use results::{Event, ResultError, Signal, SimStats, SimulationResult};
pub use scene::{
    ContactPairMaterial, ContactProfile, Feature, ForceElement, ForceFn, FreeRotation, Input,
    InputKind, Joint, JointKind, MassSpec, MaterialPalette, MaterialRef, Object3D, ObjectMotion,
    Rotation, SceneDesc, SceneError, SceneErrors, SceneOptions, Solid, SolidMaterial, Wrench,
};
pub use simulation::{InputError, Model, SimError, SimErrorKind, SimOptions, Simulation};
