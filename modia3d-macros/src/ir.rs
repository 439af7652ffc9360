//! The checked model as plain data: every component lowered to what it means (objects,
//! joints, materials, …), values kept as the user's expressions with their spans, literal
//! numbers read out. Produced by `check/`, read by `rules.rs` (the core's scene rules on the
//! literal part) and by `expand/` (code generation). No token streams here.

// A handful of nodes per block, built once at compile time: size does not matter, plain
// nesting reads better than boxes.
#![allow(clippy::large_enum_variant)]

use crate::vocab::Kind;
use modia3d_core::{BlockKindSpec, BlockVariant, JointKindSpec, ShapeKindSpec};
use proc_macro2::{Ident, Span};
use syn::Expr;

/// A reference to an object or joint of this block or of a sub-assembly, as a dotted path.
#[derive(Clone, Debug)]
pub(crate) struct NameRef {
    /// `body` or `arm1.tip`.
    pub path: String,
    /// The user's tokens.
    pub span: Span,
    /// Whether it names a component of this block (no dots).
    pub local: bool,
}

/// A literal number in the source (possibly negated), where the core's checks can see it.
#[derive(Clone, Debug)]
pub(crate) struct LitNum {
    /// Its value.
    pub value: f64,
    /// The literal's tokens (errors cover all of them).
    pub expr: Expr,
    /// Where errors about it sort among the block's errors.
    pub slot: u32,
}

/// A number-valued key (`diameter = 0.1`, `lengths = [1.0, 2.0, 3.0]`).
#[derive(Clone, Debug)]
pub(crate) struct Num {
    /// The key, as messages name it.
    pub key: &'static str,
    /// The user's expression.
    pub expr: Expr,
    /// Its literal parts: one for a scalar, one per element of an array literal; `None` where
    /// the value is only known at run time.
    pub parts: Vec<Option<LitNum>>,
}

/// A joint limit as written: `<coordinate>_limits = [lower, upper]` with its optional
/// `<coordinate>_limit_stiffness` and `<coordinate>_limit_cor`.
#[derive(Clone, Debug)]
pub(crate) struct LimitIr {
    /// The coordinate (the core's table).
    pub coordinate: &'static str,
    /// The bounds' expressions.
    pub lower: Expr,
    /// See `lower`.
    pub upper: Expr,
    /// `<coordinate>_limit_stiffness`.
    pub stiffness: Option<Expr>,
    /// `<coordinate>_limit_cor`.
    pub cor: Option<Expr>,
}

/// Where an object's or sub-assembly's parent comes from.
#[derive(Clone, Debug)]
pub(crate) enum Parent {
    /// A root (the scene, or a body moved by a joint).
    None,
    /// `parent = …`.
    Ref(NameRef),
    /// A root-level part of an assembly: takes the `parent` handed to `add_to`, if any.
    Attach,
}

/// A solid material or contact material as written.
#[derive(Clone, Debug)]
pub(crate) enum MaterialName {
    /// A material of this block (`wood` or `"wood"`).
    Local(String),
    /// A literal name that is not one of the block's (`"Steel"`): the core resolves it.
    Named(String, Expr),
    /// A `&str`/`String` expression.
    Expr(Expr),
}

/// `Scene(…)`.
#[derive(Clone, Debug)]
pub(crate) struct SceneIr {
    /// `gravity = …`.
    pub gravity: Option<Expr>,
    /// `gravity_field = …` (a `GravityField` expression).
    pub gravity_field: Option<Expr>,
    /// `contact_detection = …` and its literal value.
    pub contact_detection: Option<(Expr, Option<bool>)>,
    /// `exact_restitution = …` (`bool`; no scene rule depends on it).
    pub exact_restitution: Option<Expr>,
    /// `average_missing_pairs = …` and its literal value (a missing pair is averaged from its
    /// self-pairs instead of an error; a non-literal value is taken as `true` by the rules).
    pub average_missing_pairs: Option<(Expr, Option<bool>)>,
    /// `modia3d_conventions = …` and its literal value (a non-literal value is taken as
    /// `false` by the rules; `build()` decides at run time).
    pub modia3d_conventions: Option<(Expr, Option<bool>)>,
    /// The `f64` options that were given.
    pub numbers: Vec<Num>,
    /// `mpr_max_iterations = …` (`u32`).
    pub mpr_max_iterations: Option<Num>,
    /// `profile = …`.
    pub profile: Option<Profile>,
}

/// `profile = …`.
#[derive(Clone, Debug)]
pub(crate) enum Profile {
    /// A `ContactProfile` variant.
    Variant(Ident),
    /// An expression of type `ContactProfile`.
    Expr(Expr),
}

/// `mass_properties = …`.
#[derive(Clone, Debug)]
pub(crate) enum MassIr {
    /// `MassProperties(mass = …)`: a mass without inertia (`MassSpec::Mass`: inertia from the
    /// shape, or a point mass with Modia3D conventions).
    Mass(Num),
    /// `MassPropertiesFromShapeAndMass(mass = …)`: inertia from the shape.
    Scaled(Num),
    /// `MassProperties(mass = …, com = …, inertia = …)`.
    Explicit {
        /// Mass.
        mass: Num,
        /// Centre of mass (default zero).
        com: Option<Expr>,
        /// Inertia, and its value if every element is literal.
        inertia: Expr,
        /// See `inertia`.
        inertia_lit: Option<[[f64; 3]; 3]>,
    },
}

/// `Solid(…)`.
#[derive(Clone, Debug)]
pub(crate) struct SolidIr {
    /// The shape (`None` with explicit mass properties only).
    pub shape: Option<ShapeIr>,
    /// `mass_properties`.
    pub mass: Option<MassIr>,
    /// `solid_material`, its token and the error slot of its name.
    pub material: Option<(MaterialName, Span, u32)>,
    /// `collision = …`, its literal value, the key's span and the error slot.
    pub collision: Option<(Expr, Option<bool>, Span, u32)>,
    /// `contact_material = …` and its token.
    pub contact_material: Option<(MaterialName, Span)>,
    /// `smoothing_radius`.
    pub smoothing_radius: Option<Num>,
    /// `layer_depth` (the volume contact law's elastic layer, m).
    pub layer_depth: Option<Num>,
    /// The `Solid` constructor's span and the error slot of "no mass".
    pub span: Span,
    /// See `span`.
    pub mass_slot: u32,
}

/// `shape = …`.
#[derive(Clone, Debug)]
pub(crate) enum ShapeIr {
    /// An expression of type `Shape`.
    Expr(Expr),
    /// A constructor of the core's table (`modia3d_core::SHAPE_KINDS`) with the arguments
    /// given, by key, in the row's order.
    Call {
        /// The constructor's row.
        spec: &'static ShapeKindSpec,
        /// The arguments given (an axis is always there: given or its default).
        args: Vec<(&'static str, ShapeArg)>,
    },
}

/// The argument `key` of a shape constructor's `args`, if given.
pub(crate) fn shape_arg<'a>(
    args: &'a [(&'static str, ShapeArg)],
    key: &str,
) -> Option<&'a ShapeArg> {
    args.iter().find(|(k, _)| *k == key).map(|(_, a)| a)
}

/// An argument of a shape constructor, by the value type of its parameter.
#[derive(Clone, Debug)]
pub(crate) enum ShapeArg {
    /// A length, lengths or factors.
    Num(Num),
    /// An axis.
    Axis(AxisIr),
    /// Points, a path or the flag `convex_decomposition`: the user's expression.
    Expr(Expr),
}

/// A shape's axis.
#[derive(Clone, Debug)]
pub(crate) enum AxisIr {
    /// 1, 2 or 3 (default 3).
    Index(u8),
    /// An expression of type `Axis`.
    Expr(Expr),
}

/// `feature = …`.
#[derive(Clone, Debug)]
pub(crate) enum FeatureIr {
    /// An expression of type `Feature`.
    Expr(Expr),
    /// `Scene(…)`.
    Scene(SceneIr),
    /// `Visual(shape)`.
    Visual(ShapeIr),
    /// `Solid(…)`.
    Solid(SolidIr),
}

/// A joint's kind: its row of the core's table (`modia3d_core::JOINT_KINDS`), the axes and the
/// `Var(init)` of the initial values that were given, by key.
#[derive(Clone, Debug)]
pub(crate) struct JointKindIr {
    /// The kind's row.
    pub spec: &'static JointKindSpec,
    /// Axis keys with their axes (absent keys with a default have it).
    pub axes: Vec<(&'static str, JointAxis)>,
    /// Initial-value keys with their `Var(init)`.
    pub inits: Vec<(&'static str, Expr)>,
}

/// A joint's axis.
#[derive(Clone, Debug)]
pub(crate) enum JointAxis {
    /// Default (3) or a literal ±1..3.
    Index(Option<Expr>, i64),
    /// An `i64` expression.
    Expr(Expr),
    /// `[x, y, z]`, with the value if literal.
    Vector(syn::ExprArray, Option<[f64; 3]>),
}

/// `SpringDamper(…)` ([`ForceIr::SpringDamper`]).
#[derive(Clone, Debug)]
pub(crate) struct SpringDamperIr {
    /// Ends.
    pub obj1: NameRef,
    /// Ends.
    pub obj2: NameRef,
    /// `stiffness`, or `spring_law` (then `stiffness` is `None`).
    pub stiffness: Option<Num>,
    /// `damping`.
    pub damping: Option<Num>,
    /// `length0`.
    pub length0: Option<Num>,
    /// `spring_law = <number or closure>` (a `SpringDamperPtP`).
    pub spring_law: Option<Num>,
    /// `damper_law = <number or closure>`.
    pub damper_law: Option<Num>,
}

/// A force element.
#[derive(Clone, Debug)]
pub(crate) enum ForceIr {
    /// `SpringDamper`.
    SpringDamper(SpringDamperIr),
    /// `Bushing`.
    Bushing {
        /// Ends.
        obj1: NameRef,
        /// Ends.
        obj2: NameRef,
        /// `nominal_force`, `nominal_torque`: 3-vectors.
        nominal: [Option<Num>; 2],
        /// `spring_law`, `damper_law`, `rot_spring_law`, `rot_damper_law` (`vocab::BUSHING_LAWS`):
        /// 3-arrays of numbers or closures.
        laws: [Option<Num>; 4],
        /// `large_angles`.
        large_angles: Option<Expr>,
    },
    /// `WorldForce` (`torque = false`) or `WorldTorque`.
    WorldVector {
        /// The object acted on.
        object: NameRef,
        /// The value: a 3-vector or a closure `|t, motion| …`.
        value: Expr,
        /// `resolved_in`.
        resolved_in: Option<NameRef>,
        /// `WorldTorque`.
        torque: bool,
    },
    /// `JointSpringDamper`.
    JointSpringDamper {
        /// The joint.
        joint: NameRef,
        /// `coordinate = "…"`: the expression and its literal value.
        coordinate: Option<(Expr, Option<String>)>,
        /// `stiffness`.
        stiffness: Num,
        /// `damping`.
        damping: Option<Num>,
        /// `offset`.
        offset: Option<Expr>,
    },
    /// `ObjectForce`.
    ObjectForce {
        /// The object.
        object: NameRef,
        /// The closure.
        law: Expr,
    },
}

/// An input.
#[derive(Clone, Debug)]
pub(crate) enum InputIr {
    /// `JointForce(joint, coordinate)`: the coordinate's expression and literal value.
    JointForce(NameRef, Option<(Expr, Option<String>)>),
    /// `JointAcceleration(joint, coordinate)`.
    JointAcceleration(NameRef, Option<(Expr, Option<String>)>),
    /// `ObjectWrench(object)`.
    ObjectWrench(NameRef),
}

/// A scheduled structure change (`ActionAttach`, `ActionRelease`, `ActionDelete`).
#[derive(Clone, Debug)]
pub(crate) enum ActionIr {
    /// `ActionAttach(object, to, gap)`.
    Attach {
        /// The free object.
        object: NameRef,
        /// The object it is fixed to.
        to: NameRef,
        /// The gap \[m\].
        gap: Num,
    },
    /// `ActionRelease(object)`.
    Release(NameRef),
    /// `ActionDelete(object)`.
    Delete(NameRef),
}

/// `SolidMaterial(density, young_modulus, poisson_ratio)` ([`Item::Material`]).
#[derive(Clone, Debug)]
pub(crate) struct MaterialIr {
    /// Component name.
    pub name: Ident,
    /// The three numbers.
    pub density: Num,
    /// See `density`.
    pub young_modulus: Num,
    /// See `density`.
    pub poisson_ratio: Num,
}

/// `Object3D(…)` ([`Item::Object`]).
#[derive(Clone, Debug)]
pub(crate) struct ObjectIr {
    /// Component name.
    pub name: Ident,
    /// Its parent.
    pub parent: Parent,
    /// `translation`.
    pub translation: Option<Expr>,
    /// `rotation`.
    pub rotation: Option<Expr>,
    /// `feature`.
    pub feature: Option<FeatureIr>,
    /// Whether it is the scene (the world).
    pub scene: bool,
}

/// A joint ([`Item::Joint`]).
#[derive(Clone, Debug)]
pub(crate) struct JointIr {
    /// Component name.
    pub name: Ident,
    /// The world-side object.
    pub obj1: NameRef,
    /// The moved object.
    pub obj2: NameRef,
    /// Kind and initial values.
    pub kind: JointKindIr,
    /// `can_collide = …` and its literal value.
    pub can_collide: Option<(Expr, Option<bool>)>,
    /// `cut = …` (prefer this joint as the one that closes its loop) and its literal value.
    pub cut: Option<(Expr, Option<bool>)>,
    /// Its limits (`<coordinate>_limits = [lower, upper]`, …), one per coordinate.
    pub limits: Vec<LimitIr>,
}

/// `ContactPair(…)` ([`Item::ContactPair`]).
#[derive(Clone, Debug)]
pub(crate) struct ContactPairIr {
    /// The two contact materials.
    pub material1: MaterialName,
    /// See `material1`.
    pub material2: MaterialName,
    /// Coefficients.
    pub cor: Num,
    /// See `cor`.
    pub mu_k: Num,
    /// See `cor`.
    pub mu_r: Num,
    /// Optional regularisation velocities (`f64` or `Option<f64>`).
    pub v_min: Option<Num>,
    /// See `v_min`.
    pub w_min: Option<Num>,
}

/// A signal a block's input reads.
#[derive(Clone, Debug, PartialEq)]
pub(crate) enum Dep {
    /// By path, relative to the block's prefix (`ramp.y`, `arm.rev.phi`), or `time`
    /// (absolute).
    Path(String),
    /// A parameter of type `SignalRef`: the outer model's signal handed to this assembly
    /// (absolute).
    Param(Ident),
    /// `der(slide.v)`: the acceleration of a joint coordinate, by its velocity's path relative
    /// to the block's prefix (the signal `der(<prefix><path>)`).
    Der(String),
}

/// Where a block's input port reads its value from.
#[derive(Clone, Debug)]
pub(crate) enum WireIr {
    /// An expression of parameters only: `Src::Const`.
    Const(Expr),
    /// One signal: `Src::signal`.
    Signal(Dep),
    /// An expression over `time` and the signals `deps` (in order of first use): `expr` is
    /// the user's with each signal replaced by the closure's values `v[i]` and `time` by its
    /// time argument (both locals of [`wire_locals`]).
    Expr {
        /// The signals read.
        deps: Vec<Dep>,
        /// The rewritten expression.
        expr: Expr,
    },
}

/// The closure arguments of a [`WireIr::Expr`]: time \[s\] and the values of its signals
/// (mixed-site hygiene: the user's expression cannot name them).
pub(crate) fn wire_locals() -> (Ident, Ident) {
    (
        Ident::new("__modia3d_time", Span::mixed_site()),
        Ident::new("__modia3d_values", Span::mixed_site()),
    )
}

/// What a block offers and takes, for the variants chosen (a `Drive` with a DC motor takes
/// `v`, not `tau`): from the core's example block of the kind.
#[derive(Clone, Debug, Default)]
pub(crate) struct BlockPorts {
    /// Input ports, in order.
    pub inputs: Vec<String>,
    /// Outputs with their feedthrough flags.
    pub outputs: Vec<(String, bool)>,
    /// Continuous, then discrete states.
    pub states: Vec<String>,
    /// A variant key's value is no variant (an error): the ports are not known, and keys
    /// that are no parameter are not checked against them (no follow-up errors).
    pub uncertain: bool,
}

impl BlockPorts {
    /// Every signal: outputs, then states (a state named as an output is listed once).
    pub(crate) fn signals(&self) -> Vec<&str> {
        let mut v: Vec<&str> = self.outputs.iter().map(|(n, _)| n.as_str()).collect();
        for s in &self.states {
            if !v.contains(&s.as_str()) {
                v.push(s);
            }
        }
        v
    }
}

/// A variant chosen for an enum-valued parameter (`gear = Elastic(c = …, d = …)`).
#[derive(Clone, Debug)]
pub(crate) struct VariantIr {
    /// The parameter (`gear`).
    pub key: &'static str,
    /// The variant (the core's table).
    pub variant: &'static BlockVariant,
    /// Its fields' values, in the table's order.
    pub fields: Vec<(&'static str, Expr)>,
}

/// A block's joint.
#[derive(Clone, Debug)]
pub(crate) enum JointArg {
    /// A joint of this block or of a sub-assembly.
    Ref(NameRef),
    /// A parameter of type `JointRef` (absolute).
    Param(Ident),
}

/// A block (`name = PI(k = …, u = …)`, [`Item::Block`]).
#[derive(Clone, Debug)]
pub(crate) struct BlockIr {
    /// Component name.
    pub name: Ident,
    /// The kind's row of the core's table.
    pub spec: &'static BlockKindSpec,
    /// The parameters given (numbers and lists), by key in the row's order.
    pub params: Vec<(&'static str, Expr)>,
    /// A `Drive`'s joint: of this block, or a parameter of type `JointRef` (the outer
    /// model's joint handed to this assembly).
    pub joint: Option<JointArg>,
    /// A `Drive`'s `coordinate = "…"`.
    pub coordinate: Option<Expr>,
    /// The variants chosen for enum-valued parameters (others take the row's default).
    pub variants: Vec<VariantIr>,
    /// A `Sampled` block's inner block (its parameters only; its inputs are the outer's).
    pub inner: Option<Box<BlockIr>>,
    /// Its ports and signals with these variants.
    pub ports: BlockPorts,
    /// Each input port's source, in the ports' order.
    pub inputs: Vec<(String, WireIr)>,
}

/// One component. The variants that both consumers of the IR (the rules' scene of literal
/// values, `rules/`, and the expansion's builder calls, `expand/`) read field by field are
/// named structs, so each reads the fields it needs by name.
#[derive(Clone, Debug)]
pub(crate) enum Item {
    /// `SolidMaterial(density, young_modulus, poisson_ratio)`.
    Material(MaterialIr),
    /// `Object3D(…)`.
    Object(ObjectIr),
    /// A joint.
    Joint(JointIr),
    /// A force element.
    Force {
        /// Component name.
        name: Ident,
        /// What it is.
        force: ForceIr,
        /// Where errors about it sort.
        slot: u32,
    },
    /// An input.
    Input {
        /// Component name.
        name: Ident,
        /// What it drives.
        input: InputIr,
        /// Where errors about it sort.
        slot: u32,
    },
    /// An action at time `at`.
    Action {
        /// Component name.
        name: Ident,
        /// Its time \[s\].
        at: Num,
        /// What it does.
        action: ActionIr,
        /// Where errors about it sort.
        slot: u32,
    },
    /// `ContactPair(…)`.
    ContactPair(ContactPairIr),
    /// A block with ports and states.
    Block(BlockIr),
    /// A sub-assembly: `Type { params… }.add_to(scene, prefix.name., parent)`.
    Assembly {
        /// Component name.
        name: Ident,
        /// The assembly's type.
        ty: syn::Path,
        /// Its parent.
        parent: Parent,
        /// Parameter values.
        fields: Vec<(Ident, Expr)>,
        /// Parameters given a signal or joint of this block by path (`reference = ramp.y`,
        /// `joint = rev`): a `SignalRef` or `JointRef` of the path with this block's prefix.
        paths: Vec<(Ident, String)>,
    },
}

/// A reference into a sub-assembly for rustc to check: `arm1.tip` → `__modia3d_Arm::tip`.
#[derive(Clone, Debug)]
pub(crate) struct PathCheck {
    /// The sub-assembly's type.
    pub ty: syn::Path,
    /// The path inside it.
    pub rest: Vec<Ident>,
    /// What it must name.
    pub want: PathWant,
}

/// What a [`PathCheck`]'s path must name.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum PathWant {
    /// An object.
    Object,
    /// A joint.
    Joint,
    /// A signal a block reads (`pi.y`, `rev.phi`).
    Signal,
    /// A joint coordinate's velocity, read by `der(…)` (`rev.w`).
    Velocity,
}

/// The checked model.
#[derive(Clone, Debug)]
pub(crate) struct Ir {
    /// Components in declaration order.
    pub items: Vec<Item>,
    /// Kind of every component, in declaration order.
    pub kinds: Vec<(Ident, Kind)>,
    /// References into sub-assemblies.
    pub path_checks: Vec<PathCheck>,
    /// Whether the block has a `Scene` object (then it is a model with `build()`).
    pub has_scene: bool,
}
