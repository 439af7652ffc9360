//! Scene stage: the description (builder API), the material palette and validation.
//! Touches only plain data; nothing here knows about dynamics or the solver.

mod contact_rules;
mod desc;
mod materials;
mod topology;
mod validate;

#[cfg(feature = "solver")]
pub(crate) use contact_rules::{colliding_objects, CollisionFilter};
pub use desc::*;
pub use materials::{
    builtin_contact_pair, builtin_solid_material, ContactPairEntry, ContactPairMaterial,
    MaterialFileError, MaterialPalette, SolidMaterial, CONTACT_PAIR_MATERIALS, SOLID_MATERIALS,
};
/// Closest candidate to a misspelt name (shared with the `model!` macro's messages).
#[doc(hidden)]
pub use validate::did_you_mean;
pub use validate::{SceneError, SceneErrors};
#[cfg(feature = "solver")]
pub(crate) use validate::{ValidForce, ValidInputKind, ValidJointKind, ValidScene};
