//! Scene stage: the description (builder API), the material palette and validation.
//! Touches only plain data; nothing here knows about dynamics or the solver.

pub mod contact_rules;
pub mod desc;
pub mod materials;
pub mod topology;
pub mod validate;

pub use contact_rules::{colliding_objects, missing_contact_pairs, CollisionFilter};
pub use desc::*;
pub use materials::{
    builtin_contact_pair, builtin_solid_material, ContactPairEntry, ContactPairMaterial,
    MaterialFileError, MaterialPalette, SolidMaterial, CONTACT_PAIR_MATERIALS, SOLID_MATERIALS,
};
pub use topology::{Topology, TreeEdge};
pub use validate::{
    did_you_mean, MassProps, SceneError, SceneErrors, ValidForce, ValidInput, ValidInputKind,
    ValidJoint, ValidJointKind, ValidObject, ValidScene, ValidSolid,
};
