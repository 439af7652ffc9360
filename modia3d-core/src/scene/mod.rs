//! Scene stage: the description (builder API), the material palette and validation.
//! Touches only plain data; nothing here knows about dynamics or the solver.

mod actions;
mod block_table;
pub mod blocks;
mod components;
mod contact_rules;
mod desc;
mod force_laws;
mod materials;
mod topology;
pub(crate) mod validate;

pub use actions::{Action, ActionKind};
pub use block_table::{
    block_kind, BlockKindSpec, BlockOutput, BlockParam, BlockValue, BlockVariant, BlockVariants,
    BLOCK_KINDS,
};
pub use components::{
    Component, ComponentDecl, ComponentIo, ComponentJacobian, FlangeMotion, FlangeSpec, OutputSpec,
    PortSpec, Src, SrcFn, StateSpec,
};
#[cfg(feature = "solver")]
pub(crate) use contact_rules::{colliding_objects, CollisionFilter};
pub use desc::*;
pub use force_laws::{
    Bushing, ForceFn, ForceLaw, GravityField, Law, ObjectMotion, ScalarLaw, VectorLaw, VectorLawFn,
    Wrench,
};
pub use materials::{
    average_pair, builtin_contact_pair, builtin_material_color, builtin_palette,
    builtin_solid_material, builtin_solid_names, BuiltinPair, BuiltinPalette, BuiltinSolid,
    ContactPairEntry, ContactPairMaterial, MaterialFileError, MaterialPalette, SolidMaterial,
    PALETTE_JSON,
};
/// Closest candidate to a misspelt name (shared with the `model!` macro's messages).
#[doc(hidden)]
pub use validate::did_you_mean;
pub use validate::{LoopReach, SceneError, SceneErrors, SizeSlip};
#[cfg(feature = "solver")]
pub(crate) use validate::{ValidForce, ValidInputKind, ValidJointKind, ValidScene};
