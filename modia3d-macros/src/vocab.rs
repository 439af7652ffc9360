//! Vocabulary of `model!`: the constructors, the keys each accepts, synonyms users guess, and
//! what kind of component a constructor makes. Plain data; the rules a *value* must satisfy
//! are the core's (`modia3d_core::scene`), not listed here, and so are the joint and shape
//! kinds: their names, keys, defaults and units are the core's tables
//! (`modia3d_core::JOINT_KINDS`, `modia3d_core::SHAPE_KINDS`).

use modia3d_core::{BlockKindSpec, JointKindSpec, ShapeKindSpec, JOINT_KINDS, SHAPE_KINDS};

/// Constructors of components that a misspelt constructor is compared with: `Object3D`, the
/// joint kinds (the core's table), then [`OTHER_COMPONENTS`]. Not the block kinds: their
/// short Modelica names (`Add`, `PI`, `Step`) are near many a sub-assembly's name (`Arm`),
/// which would then need a path; a misspelt block is an unknown type for rustc.
pub(crate) fn components() -> impl Iterator<Item = &'static str> {
    std::iter::once("Object3D")
        .chain(JOINT_KINDS.iter().map(|k| k.name))
        .chain(OTHER_COMPONENTS.iter().copied())
}

/// The row of the block kind `ctor` in the core's table; `None` for other names.
pub(crate) fn block_kind(ctor: &str) -> Option<&'static BlockKindSpec> {
    modia3d_core::block_kind(ctor)
}

/// Whether `ctor` is a constructor inside a block's values: a block kind (a `Sampled` block's
/// `inner`) or a variant of an enum-valued parameter (`Elastic`, `Dc`).
pub(crate) fn is_block_value(ctor: &str) -> bool {
    block_kind(ctor).is_some()
        || modia3d_core::BLOCK_KINDS.iter().any(|k| {
            k.params.iter().any(|p| match p.value {
                modia3d_core::BlockValue::Variant(vs) => vs.iter().any(|v| v.name == ctor),
                _ => false,
            })
        })
}

/// Whether `name` is a constructor of a component ([`components`] or a block kind).
pub(crate) fn is_component(name: &str) -> bool {
    components().any(|c| c == name) || block_kind(name).is_some()
}

/// Constructors of components other than objects and joints.
pub(crate) const OTHER_COMPONENTS: &[&str] = &[
    "SpringDamper",
    "JointSpringDamper",
    "ObjectForce",
    "Bushing",
    "WorldForce",
    "WorldTorque",
    "SolidMaterial",
    "ContactPair",
    "JointForce",
    "JointAcceleration",
    "ObjectWrench",
    "ActionAttach",
    "ActionRelease",
    "ActionDelete",
];

/// Constructors that appear only inside values, besides the shapes ([`is_nested`]).
pub(crate) const NESTED: &[&str] = &[
    "Scene",
    "Solid",
    "Visual",
    "MassProperties",
    "MassPropertiesFromShapeAndMass",
    "Var",
];

/// Whether `name` is a constructor that appears only inside values: [`NESTED`] or a shape.
pub(crate) fn is_nested(name: &str) -> bool {
    NESTED.contains(&name) || shape_kind(name).is_some()
}

/// Constructors of `feature = …`.
pub(crate) const FEATURES: &[&str] = &["Scene", "Solid", "Visual"];

/// The row of the shape constructor `ctor` in the core's table; `None` for other names (and
/// for variants that are no `model!` constructor, such as a loaded `Mesh`).
pub(crate) fn shape_kind(ctor: &str) -> Option<&'static ShapeKindSpec> {
    SHAPE_KINDS
        .iter()
        .find(|k| k.name == ctor && k.stand_in.is_some())
}

/// Constructors of `shape = …`: the core's table's, in its order.
pub(crate) fn shapes() -> Vec<&'static str> {
    SHAPE_KINDS
        .iter()
        .filter(|k| k.stand_in.is_some())
        .map(|k| k.name)
        .collect()
}

/// Keys of `Scene(…)`: the fields of `SceneOptions` (`profile` is `contact_profile`).
pub(crate) const SCENE_KEYS: &[&str] = &[
    "gravity",
    "gravity_field",
    "contact_detection",
    "exact_restitution",
    "average_missing_pairs",
    "modia3d_conventions",
    "k_red",
    "d_max",
    "cor_min",
    "v_min",
    "v_min_volume",
    "w_min",
    "hysteresis",
    "mpr_tolerance",
    "mpr_max_iterations",
    "smoothing_radius",
    "profile",
];

/// The numeric fields of `SceneOptions` that `Scene(…)` sets directly (`f64`).
pub(crate) const SCENE_NUMBERS: &[&str] = &[
    "k_red",
    "d_max",
    "cor_min",
    "v_min",
    "v_min_volume",
    "w_min",
    "hysteresis",
    "mpr_tolerance",
    "smoothing_radius",
];

/// The variants of `ContactProfile`.
pub(crate) const PROFILES: &[&str] = &["Volume", "Paper2019", "Modia3DLater"];

/// Keys of `SpringDamper(…)`: `spring_law`/`damper_law` (a number or a closure of the
/// elongation / its rate) replace `stiffness`/`damping`.
pub(crate) const SPRING_DAMPER_KEYS: &[&str] = &[
    "obj1",
    "obj2",
    "stiffness",
    "damping",
    "length0",
    "spring_law",
    "damper_law",
];

/// Keys of `Bushing(…)` (Modia3D's, in snake case; each law a 3-array of numbers or closures).
pub(crate) const BUSHING_KEYS: &[&str] = &[
    "obj1",
    "obj2",
    "nominal_force",
    "spring_law",
    "damper_law",
    "nominal_torque",
    "rot_spring_law",
    "rot_damper_law",
    "large_angles",
];

/// The law keys of `Bushing(…)`.
pub(crate) const BUSHING_LAWS: &[&str] = &[
    "spring_law",
    "damper_law",
    "rot_spring_law",
    "rot_damper_law",
];

/// Keys of `WorldForce(…)` and `WorldTorque(…)` (the value key is `force` or `torque`).
pub(crate) fn world_vector_keys(ctor: &str) -> &'static [&'static str] {
    match ctor {
        "WorldTorque" => &["object", "torque", "resolved_in"],
        _ => &["object", "force", "resolved_in"],
    }
}

/// Keys of `Solid(…)`.
pub(crate) const SOLID_KEYS: &[&str] = &[
    "shape",
    "solid_material",
    "mass_properties",
    "collision",
    "contact_material",
    "smoothing_radius",
    "layer_depth",
];

/// Keys of `ContactPair(…)`.
pub(crate) const PAIR_KEYS: &[&str] = &[
    "material1",
    "material2",
    "cor",
    "mu_k",
    "mu_r",
    "v_min",
    "w_min",
];

/// The row of the joint kind `ctor` in the core's table; `None` for other names.
pub(crate) fn joint_kind(ctor: &str) -> Option<&'static JointKindSpec> {
    JOINT_KINDS.iter().find(|k| k.name == ctor)
}

/// Keys of a joint constructor: the objects, the kind's parameters (the core's table), then
/// `can_collide`, `cut` and the limit keys of each scalar coordinate (`phi_limits`,
/// `phi_limit_stiffness`, `phi_limit_cor`; the table's `LimitKeys`).
pub(crate) fn joint_keys(kind: &JointKindSpec) -> Vec<&'static str> {
    ["obj1", "obj2"]
        .into_iter()
        .chain(kind.keys())
        .chain(["can_collide", "cut"])
        .chain(
            kind.coordinates
                .iter()
                .flat_map(|c| [c.limit_keys.range, c.limit_keys.stiffness, c.limit_keys.cor]),
        )
        .collect()
}

/// The limit suffixes of joint keys (`<coordinate>_limits`, …), for the message on a limit key
/// whose coordinate the joint does not have.
pub(crate) const LIMIT_SUFFIXES: &[&str] = &["_limits", "_limit_stiffness", "_limit_cor"];

/// Keys that are easy to guess wrong, with the key meant.
pub(crate) const SYNONYMS: &[(&str, &str)] = &[
    ("radius", "diameter"),
    ("size", "lengths"),
    ("dimensions", "lengths"),
    ("material", "solid_material"),
    ("density", "solid_material"),
    ("angle", "phi"),
    ("position", "translation"),
    ("mass_properties", "mass"),
    ("k", "stiffness"),
    ("d", "damping"),
    ("contact_profile", "profile"),
    ("mu", "mu_k"),
    ("e", "cor"),
    ("spring_force_law", "spring_law"),
    ("damper_force_law", "damper_law"),
    ("rot_spring_force_law", "rot_spring_law"),
    ("rot_damper_force_law", "rot_damper_law"),
    ("stiffness", "spring_law"),
    ("damping", "damper_law"),
    ("rot_stiffness", "rot_spring_law"),
    ("rot_damping", "rot_damper_law"),
    ("large_angle", "large_angles"),
    ("obj", "object"),
    ("frame", "resolved_in"),
    ("frame_coord", "resolved_in"),
    ("force", "torque"),
    ("torque", "force"),
    // A `Drive`'s input: `tau` for a torque source, `v` for a DC motor.
    ("tau", "v"),
    ("v", "tau"),
];

/// What a component is.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Kind {
    /// An `Object3D`.
    Object,
    /// A joint.
    Joint,
    /// A force element.
    Force,
    /// A solid material defined in the block.
    Material,
    /// A contact-pair material defined in the block.
    ContactPair,
    /// An input (set between simulation steps).
    Input,
    /// A scheduled structure change (attach, release, delete).
    Action,
    /// A block with ports and states in the DAE (`PI`, `Ramp`, `Drive`; the core's
    /// `BLOCK_KINDS`).
    Block,
    /// A sub-assembly (another `model!` type).
    Assembly,
}

impl Kind {
    /// The kind a built-in component constructor makes; `None` for other names.
    pub(crate) fn of_builtin(ctor: &str) -> Option<Kind> {
        Some(match ctor {
            "Object3D" => Kind::Object,
            k if joint_kind(k).is_some() => Kind::Joint,
            "SpringDamper" | "JointSpringDamper" | "ObjectForce" | "Bushing" | "WorldForce"
            | "WorldTorque" => Kind::Force,
            "SolidMaterial" => Kind::Material,
            "ContactPair" => Kind::ContactPair,
            "JointForce" | "JointAcceleration" | "ObjectWrench" => Kind::Input,
            "ActionAttach" | "ActionRelease" | "ActionDelete" => Kind::Action,
            k if block_kind(k).is_some() => Kind::Block,
            _ => return None,
        })
    }

    /// "an object", "a joint", … for messages.
    pub(crate) fn article(self) -> &'static str {
        match self {
            Kind::Object => "an object",
            Kind::Joint => "a joint",
            Kind::Force => "a force element",
            Kind::Material => "a solid material",
            Kind::ContactPair => "a contact-pair material",
            Kind::Input => "an input",
            Kind::Action => "an action",
            Kind::Block => "a block",
            Kind::Assembly => "a sub-assembly",
        }
    }
}

/// How to write a nested constructor that was used as a component.
pub(crate) fn nested_hint(n: &str) -> String {
    match n {
        "Scene" | "Solid" | "Visual" => format!("`Object3D(feature = {n}(…))`"),
        "Var" => "`phi = Var(init = …)` inside a joint".into(),
        "MassProperties" | "MassPropertiesFromShapeAndMass" => {
            format!("`Solid(mass_properties = {n}(…))`")
        }
        // The shapes (the rest of `is_nested`).
        _ => format!("`Object3D(feature = Solid(shape = {n}(…)))`"),
    }
}
