//! Check stage: interprets the syntax tree against the vocabulary of the core builder API
//! (constructors, keys, references) and checks the structure of the model — names, parent
//! cycles, joints, kinematic loops, scenes, literal values, materials. All errors of a block are
//! collected in one pass and combined; each sits on the smallest offending token.
//!
//! What the macro cannot see (objects inside another `model!`'s expansion, types of values) is
//! left to rustc through spanned code (see `path_check` and `expand.rs`).
//!
//! Contact materials: every colliding solid records its contact material (literal or not) in
//! `Checker::colliders`; after the topology pass, `Checker::missing_pairs` reports two literal
//! materials that can meet without a pair entry (built in, [`BUILTIN_CONTACT_PAIRS`], or a
//! `ContactPair(…)` of the block) — only where the block tells for sure (see there).

use crate::ast::{push, Arg, Component, Ctor, ModelDef};
use crate::expand::scoped;
use proc_macro2::{Ident, Span, TokenStream};
use quote::{format_ident, quote, quote_spanned, ToTokens};
use std::collections::{HashMap, HashSet};
use syn::spanned::Spanned;
use syn::{Expr, Lit};

/// Names of the built-in solid materials (`modia3d_core::scene::SOLID_MATERIALS`; a facade
/// test keeps the two lists equal through `__solid_material_names!`).
pub const BUILTIN_SOLID_MATERIALS: &[&str] = &[
    "Steel",
    "Aluminium",
    "DryWood",
    "BilliardBall",
    "BilliardTable",
    "BilliardCushion",
    "BilliardCue",
];

/// The built-in contact-pair materials by name (`modia3d_core::scene::CONTACT_PAIR_MATERIALS`;
/// a facade test keeps the two lists equal through `__contact_pair_names!`).
pub const BUILTIN_CONTACT_PAIRS: &[(&str, &str)] = &[
    ("Steel", "Steel"),
    ("DryWood", "DryWood"),
    ("BilliardBall", "BilliardBall"),
    ("BilliardBall", "BilliardTable"),
    ("BilliardBall", "BilliardCushion"),
    ("BilliardBall", "BilliardCue"),
    ("BilliardTable", "BilliardCue"),
    ("BilliardCue", "BilliardCue"),
];

/// Keys of `Scene(…)`: the fields of `SceneOptions` (`profile` is `contact_profile`).
const SCENE_KEYS: &[&str] = &[
    "gravity",
    "contact_detection",
    "k_red",
    "d_max",
    "cor_min",
    "v_min",
    "w_min",
    "hysteresis",
    "mpr_tolerance",
    "mpr_max_iterations",
    "smoothing_radius",
    "profile",
];

/// The variants of `ContactProfile`.
const PROFILES: &[&str] = &["Paper2019", "Modia3DLater"];

/// Constructors of components.
const COMPONENTS: &[&str] = &[
    "Object3D",
    "Fix",
    "Revolute",
    "Prismatic",
    "FreeMotion",
    "SpringDamper",
    "JointSpringDamper",
    "ObjectForce",
    "SolidMaterial",
    "ContactPair",
    "JointForce",
    "JointAcceleration",
    "ObjectWrench",
];
/// Constructors that appear only inside values.
const NESTED: &[&str] = &[
    "Scene",
    "Solid",
    "Visual",
    "MassProperties",
    "Var",
    "Sphere",
    "Box",
    "Cylinder",
    "Capsule",
    "Cone",
    "Ellipsoid",
    "ConvexHull",
];
const FEATURES: &[&str] = &["Scene", "Solid", "Visual"];
const SHAPES: &[&str] = &[
    "Sphere",
    "Box",
    "Cylinder",
    "Capsule",
    "Cone",
    "Ellipsoid",
    "ConvexHull",
];
/// Keys that are easy to guess wrong, with the key meant.
const SYNONYMS: &[(&str, &str)] = &[
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
];

/// What a component is.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Kind {
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
    /// A sub-assembly (another `model!` type).
    Assembly,
}

/// A reference to an object or joint of this block or of a sub-assembly, as a dotted path.
#[derive(Clone, Debug)]
pub struct NameRef {
    /// `body` or `arm1.tip`.
    pub path: String,
    /// The user's tokens.
    pub span: Span,
    /// Whether it names a component of this block (no dots).
    pub local: bool,
}

/// Where an object's or sub-assembly's parent comes from.
#[derive(Clone, Debug)]
pub enum Parent {
    /// A root (the scene, or a body moved by a joint).
    None,
    /// `parent = …`.
    Ref(NameRef),
    /// A root-level part of an assembly: takes the `parent` handed to `add_to`, if any.
    Attach,
}

/// One component, lowered to builder fragments.
pub enum Item {
    /// `scene.add_solid_material(name, value)`.
    Material {
        /// Component name.
        name: Ident,
        /// A `SolidMaterial` expression.
        value: TokenStream,
    },
    /// `scene.add(Object3D::new(name)…)`.
    Object {
        /// Component name.
        name: Ident,
        /// Its parent.
        parent: Parent,
        /// Builder calls after `Object3D::new(…)`, e.g. `.translation(…)`.
        calls: Vec<TokenStream>,
        /// Whether it is the scene (the world).
        scene: bool,
    },
    /// `scene.add_input(value)`.
    Input {
        /// An `Input` expression.
        value: TokenStream,
    },
    /// `scene.add_contact_pair(material1, material2, value)`.
    ContactPair {
        /// The first contact material's name (a `&str` expression).
        material1: TokenStream,
        /// The second one.
        material2: TokenStream,
        /// A `ContactPairMaterial` expression.
        value: TokenStream,
    },
    /// `scene.add_joint(Joint::new(name, obj1, obj2, kind)…)`.
    Joint {
        /// Component name.
        name: Ident,
        /// The world-side object.
        obj1: NameRef,
        /// The moved object.
        obj2: NameRef,
        /// A `JointKind` expression.
        kind: TokenStream,
        /// Builder calls after `Joint::new(…)`.
        calls: Vec<TokenStream>,
        /// What the joint means for contacts: `Some(true)` if it merges or excludes its two
        /// bodies (Fix; Revolute/Prismatic with `can_collide = false`), `Some(false)` if not,
        /// `None` if unknown at compile time (a non-literal `can_collide`).
        rigid: bool,
        /// See `rigid`: whether it excludes the pair of its bodies from collisions.
        excludes: Option<bool>,
    },
    /// `scene.add_force(value)`.
    Force {
        /// A `ForceElement` expression.
        value: TokenStream,
    },
    /// `Type { params… }.add_to(scene, prefix.name., parent)`.
    Assembly {
        /// Component name.
        name: Ident,
        /// The assembly's type.
        ty: syn::Path,
        /// Its parent.
        parent: Parent,
        /// Parameter values.
        fields: Vec<(Ident, Expr)>,
    },
}

/// The checked model.
pub struct Ir {
    /// Components in declaration order.
    pub items: Vec<Item>,
    /// Kind of every component, in declaration order.
    pub kinds: Vec<(Ident, Kind)>,
    /// Statements that make rustc check paths into sub-assemblies on the user's tokens.
    pub path_checks: Vec<TokenStream>,
    /// Whether the block has a `Scene` object (then it is a model with `build()`).
    pub has_scene: bool,
}

/// A colliding solid, for the contact-pair check.
struct Collider {
    /// The object (a component of this block).
    object: String,
    /// Its contact material's name (with this block's materials at the top level), if literal.
    material: Option<String>,
    /// How the material is written in a `ContactPair(…)`: `"Steel"` or `wood`.
    written: String,
    /// The material's token (explicit `contact_material`, else `solid_material`).
    span: Span,
}

/// Checks a model; all errors combined.
pub fn check(def: &ModelDef) -> Result<Ir, syn::Error> {
    let mut c = Checker {
        errors: None,
        kinds: HashMap::new(),
        assembly_types: HashMap::new(),
        params: def.params.iter().map(|p| p.name.to_string()).collect(),
        path_checks: vec![],
        scene_spans: vec![],
        colliders: vec![],
        current_object: None,
        pairs: vec![],
        pairs_unsure: false,
        contact_detection: Some(true),
        joint_types: HashMap::new(),
        driven: HashMap::new(),
    };
    // Parameters: names unique and not reserved.
    let mut seen = HashSet::new();
    for p in &def.params {
        if !seen.insert(p.name.to_string()) {
            c.err(p.name.span(), format!("duplicate parameter `{}`", p.name));
        }
        if p.name == "parent" {
            c.err(
                p.name.span(),
                "parameter name `parent` is reserved: it attaches a sub-assembly (hint: rename it)",
            );
        }
    }
    // Pass 1: names and kinds.
    let mut kinds = vec![];
    for comp in &def.components {
        let kind = c.kind_of(&comp.ctor);
        let name = comp.name.to_string();
        if c.kinds.contains_key(&name) {
            c.err(
                comp.name.span(),
                format!(
                    "duplicate name `{name}` (hint: component names must be unique; rename one)"
                ),
            );
            continue;
        }
        if let Some(k) = kind {
            if k == Kind::Joint {
                c.joint_types
                    .insert(name.clone(), comp.ctor.name().to_string());
            }
            c.kinds.insert(name.clone(), k);
            if k == Kind::Assembly {
                c.assembly_types.insert(name, comp.ctor.path.clone());
            }
            kinds.push((comp.name.clone(), k));
        }
    }
    // Pass 2: lower each component.
    let items: Vec<Item> = def
        .components
        .iter()
        .filter_map(|comp| c.component(comp))
        .collect();
    // Pass 3: structure.
    c.scenes(def);
    let items = c.topology(items);
    let has_scene = !c.scene_spans.is_empty();
    if has_scene && c.errors.is_none() {
        c.missing_pairs(&items);
    }
    match c.errors {
        Some(e) => Err(e),
        None => Ok(Ir {
            items,
            kinds,
            path_checks: c.path_checks,
            has_scene,
        }),
    }
}

struct Checker {
    errors: Option<syn::Error>,
    kinds: HashMap<String, Kind>,
    assembly_types: HashMap<String, syn::Path>,
    params: HashSet<String>,
    path_checks: Vec<TokenStream>,
    /// Spans of the `Scene` constructors, and the span of the scene object's `parent` key.
    scene_spans: Vec<(Span, Option<Span>)>,
    /// Colliding solids of this block.
    colliders: Vec<Collider>,
    /// The object being lowered (for `colliders`).
    current_object: Option<String>,
    /// Contact-pair materials of the block with literal names.
    pairs: Vec<(String, String)>,
    /// Whether a `ContactPair` of the block has a non-literal material name.
    pairs_unsure: bool,
    /// The scene's `contact_detection`, `None` if not literal.
    contact_detection: Option<bool>,
    /// Constructor of every joint of the block (`Revolute`, …).
    joint_types: HashMap<String, String>,
    /// Joints of the block with a prescribed acceleration, and the input doing it.
    driven: HashMap<String, String>,
}

/// The arguments of one constructor, with the keys it accepts.
struct Args<'a> {
    ctor: String,
    span: Span,
    args: Vec<&'a Arg>,
    /// Keys suggested for unknown keys: not reported again as missing.
    suggested: Vec<String>,
}

impl<'a> Args<'a> {
    fn get(&self, key: &str) -> Option<&'a Expr> {
        self.args.iter().find(|a| a.key == key).map(|a| &a.value)
    }
    fn key(&self, key: &str) -> Option<&'a Ident> {
        self.args.iter().find(|a| a.key == key).map(|a| &a.key)
    }
}

/// The closest candidate if it is a likely typo (the same rule as the core's `did_you_mean`).
pub fn did_you_mean<'a>(
    name: &str,
    candidates: impl IntoIterator<Item = &'a str>,
) -> Option<String> {
    candidates
        .into_iter()
        .filter(|c| *c != name)
        .map(|c| (strsim::damerau_levenshtein(name, c), c))
        .filter(|(d, c)| *d <= 2.max(name.len().min(c.len()) / 3))
        .min_by_key(|(d, _)| *d)
        .map(|(_, c)| c.to_string())
}

fn hint(h: Option<String>) -> String {
    h.map(|h| format!(" (hint: did you mean `{h}`?)"))
        .unwrap_or_default()
}

/// A literal number, possibly negated.
fn lit_f64(e: &Expr) -> Option<f64> {
    match e {
        Expr::Lit(l) => match &l.lit {
            Lit::Float(f) => f.base10_parse().ok(),
            Lit::Int(i) => i.base10_parse::<f64>().ok(),
            _ => None,
        },
        Expr::Unary(u) if matches!(u.op, syn::UnOp::Neg(_)) => lit_f64(&u.expr).map(|v| -v),
        Expr::Paren(p) => lit_f64(&p.expr),
        _ => None,
    }
}

/// A literal integer, possibly negated.
fn lit_int(e: &Expr) -> Option<i64> {
    match e {
        Expr::Lit(l) => match &l.lit {
            Lit::Int(i) => i.base10_parse().ok(),
            _ => None,
        },
        Expr::Unary(u) if matches!(u.op, syn::UnOp::Neg(_)) => lit_int(&u.expr).map(|v| -v),
        _ => None,
    }
}

fn lit_bool(e: &Expr) -> Option<bool> {
    match e {
        Expr::Lit(l) => match &l.lit {
            Lit::Bool(b) => Some(b.value),
            _ => None,
        },
        _ => None,
    }
}

fn lit_str(e: &Expr) -> Option<String> {
    match e {
        Expr::Lit(l) => match &l.lit {
            Lit::Str(s) => Some(s.value()),
            _ => None,
        },
        _ => None,
    }
}

/// Range rules for literal numbers.
#[derive(Clone, Copy)]
enum Range {
    Positive,
    NonNegative,
    /// Coefficients of restitution of contact pairs.
    UnitInterval,
    OpenUnitInterval,
    /// `cor_min`: (0, 1].
    PositiveUnit,
}

impl Range {
    fn ok(self, v: f64) -> bool {
        match self {
            Range::Positive => v > 0.0,
            Range::NonNegative => v >= 0.0,
            Range::UnitInterval => (0.0..=1.0).contains(&v),
            Range::OpenUnitInterval => v > 0.0 && v < 1.0,
            Range::PositiveUnit => v > 0.0 && v <= 1.0,
        }
    }
    fn text(self) -> &'static str {
        match self {
            Range::Positive => "must be positive",
            Range::NonNegative => "must not be negative",
            Range::UnitInterval => "must be in [0, 1]",
            Range::OpenUnitInterval => "must be in (0, 1)",
            Range::PositiveUnit => "must be in (0, 1]",
        }
    }
}

impl Checker {
    fn err(&mut self, span: Span, msg: impl std::fmt::Display) {
        push(&mut self.errors, syn::Error::new(span, msg));
    }

    /// An error covering all of `tokens` (on stable, `span()` of a multi-token expression is
    /// only its first token).
    fn err_spanned(&mut self, tokens: impl ToTokens, msg: impl std::fmt::Display) {
        push(&mut self.errors, syn::Error::new_spanned(tokens, msg));
    }

    /// The kind a component constructor makes, or `None` (error reported) if unknown.
    fn kind_of(&mut self, ctor: &Ctor) -> Option<Kind> {
        if !ctor.is_single() {
            return Some(Kind::Assembly);
        }
        let n = ctor.name().to_string();
        match n.as_str() {
            "Object3D" => Some(Kind::Object),
            "Fix" | "Revolute" | "Prismatic" | "FreeMotion" => Some(Kind::Joint),
            "SpringDamper" | "JointSpringDamper" | "ObjectForce" => Some(Kind::Force),
            "SolidMaterial" => Some(Kind::Material),
            "ContactPair" => Some(Kind::ContactPair),
            "JointForce" | "JointAcceleration" | "ObjectWrench" => Some(Kind::Input),
            _ if NESTED.contains(&n.as_str()) => {
                let hint = match n.as_str() {
                    "Scene" | "Solid" | "Visual" => format!("`Object3D(feature = {n}(…))`"),
                    "Var" => "`phi = Var(init = …)` inside a joint".into(),
                    "MassProperties" => "`Solid(mass_properties = MassProperties(…))`".into(),
                    _ => format!("`Object3D(feature = Solid(shape = {n}(…)))`"),
                };
                self.err(
                    ctor.span(),
                    format!("`{n}` is not a component on its own (hint: write {hint})"),
                );
                None
            }
            _ => match did_you_mean(&n, COMPONENTS.iter().copied()) {
                Some(h) => {
                    self.err(
                        ctor.span(),
                        format!(
                            "unknown constructor `{n}` (hint: did you mean `{h}`? a sub-assembly \
                             type this close to a built-in must be written as a path, \
                             e.g. `self::{n}`)"
                        ),
                    );
                    None
                }
                None => Some(Kind::Assembly),
            },
        }
    }

    /// Checks the keys of `ctor` against `allowed`: unknown keys (with hints) and duplicates.
    fn args<'a>(&mut self, ctor: &'a Ctor, allowed: &[&str]) -> Args<'a> {
        let cname = ctor.name().to_string();
        let mut seen: HashMap<String, Span> = HashMap::new();
        let mut args = vec![];
        let mut suggested = vec![];
        for a in &ctor.args {
            let k = a.key.to_string();
            if !allowed.contains(&k.as_str()) {
                if k == "can_collide" {
                    self.err(
                        a.key.span(),
                        format!(
                            "`can_collide` is a key of joints, not of `{cname}(…)` (hint: put it \
                             on the joint between the two bodies)"
                        ),
                    );
                } else {
                    let h = SYNONYMS
                        .iter()
                        .find(|(s, t)| *s == k && allowed.contains(t))
                        .map(|(_, t)| t.to_string())
                        .or_else(|| did_you_mean(&k, allowed.iter().copied()));
                    let keys = allowed
                        .iter()
                        .map(|k| format!("`{k}`"))
                        .collect::<Vec<_>>()
                        .join(", ");
                    suggested.extend(h.clone());
                    let h = match h {
                        Some(h) => format!(" (hint: did you mean `{h}`?)"),
                        None if allowed.is_empty() => format!(" (hint: `{cname}` takes no keys)"),
                        None => format!(" (hint: `{cname}` takes {keys})"),
                    };
                    self.err(
                        a.key.span(),
                        format!("unknown key `{k}` in `{cname}(…)`{h}"),
                    );
                }
                continue;
            }
            if seen.insert(k.clone(), a.key.span()).is_some() {
                self.err(a.key.span(), format!("duplicate key `{k}` in `{cname}(…)`"));
                continue;
            }
            args.push(a);
        }
        Args {
            ctor: cname,
            span: ctor.span(),
            args,
            suggested,
        }
    }

    fn required<'a>(&mut self, a: &Args<'a>, key: &str) -> Option<&'a Expr> {
        let v = a.get(key);
        if v.is_none() && !a.suggested.iter().any(|s| s == key) {
            self.err(
                a.span,
                format!(
                    "missing key `{key}` in `{}(…)` (hint: add `{key} = …`)",
                    a.ctor
                ),
            );
        }
        v
    }

    /// Checks a literal number (or the literal elements of an array) against `range`.
    fn range(&mut self, key: &str, e: &Expr, range: Range) {
        if let Expr::Array(arr) = e {
            for el in &arr.elems {
                self.range(key, el, range);
            }
            return;
        }
        if let Some(v) = lit_f64(e) {
            if !range.ok(v) {
                self.err_spanned(
                    e,
                    format!(
                        "`{key}` {}, found `{}`",
                        range.text(),
                        e.to_token_stream().to_string().replace(' ', "")
                    ),
                );
            }
        }
    }

    /// A number key: its expression, range-checked if literal.
    fn num<'a>(
        &mut self,
        a: &Args<'a>,
        key: &str,
        range: Option<Range>,
        required: bool,
    ) -> Option<&'a Expr> {
        let v = if required {
            self.required(a, key)
        } else {
            a.get(key)
        };
        if let (Some(v), Some(r)) = (v, range) {
            self.range(key, v, r);
        }
        v
    }

    /// A nested constructor among `allowed`, or `Err(expr)` when the value is a plain
    /// expression. Reports unknown constructors.
    fn nested<'a>(
        &mut self,
        e: &'a Expr,
        allowed: &[&str],
        what: &str,
    ) -> Result<Option<Ctor>, &'a Expr> {
        // A call whose arguments are not all `key = value` and that is not one of `allowed`
        // is a plain expression (`Feature::Visual(shape)`), not a constructor.
        if let Expr::Call(call) = e {
            let known = matches!(&*call.func, Expr::Path(p)
                if p.path.get_ident().is_some_and(|id| allowed.contains(&id.to_string().as_str())));
            if !known && !call.args.iter().all(|a| matches!(a, Expr::Assign(_))) {
                return Err(e);
            }
        }
        match Ctor::from_expr(e) {
            Err(err) => {
                push(&mut self.errors, err);
                Ok(None)
            }
            Ok(None) => Err(e),
            Ok(Some(c)) => {
                let n = c.name().to_string();
                if c.is_single() && allowed.contains(&n.as_str()) {
                    return Ok(Some(c));
                }
                // A lower-case single identifier is a variable, not a constructor.
                let first = n.chars().next().unwrap_or('a');
                if c.is_single() && c.args.is_empty() && !first.is_uppercase() {
                    return Err(e);
                }
                if !c.is_single() && c.args.is_empty() {
                    return Err(e);
                }
                let h = did_you_mean(&n, allowed.iter().copied());
                let list = allowed
                    .iter()
                    .map(|k| format!("`{k}`"))
                    .collect::<Vec<_>>()
                    .join(", ");
                let h = match h {
                    Some(h) => format!(" (hint: did you mean `{h}`?)"),
                    None => format!(" (hint: expected one of {list})"),
                };
                self.err(c.span(), format!("unknown {what} `{n}`{h}"));
                Ok(None)
            }
        }
    }

    /// Lowers one component.
    fn component(&mut self, comp: &Component) -> Option<Item> {
        let kind = *self.kinds.get(&comp.name.to_string())?;
        let ctor = &comp.ctor;
        match kind {
            Kind::Object => self.object(comp),
            Kind::Joint => self.joint(comp),
            Kind::Force => self.force(comp),
            Kind::Material => {
                let a = self.args(ctor, &["density", "young_modulus", "poisson_ratio"]);
                let d = self.num(&a, "density", Some(Range::Positive), true);
                let e = self.num(&a, "young_modulus", Some(Range::Positive), true);
                let p = self.num(&a, "poisson_ratio", Some(Range::OpenUnitInterval), true);
                let (d, e, p) = (d?, e?, p?);
                Some(Item::Material {
                    name: comp.name.clone(),
                    value: quote! {
                        ::modia3d::core::SolidMaterial {
                            density: #d,
                            young_modulus: #e,
                            poisson_ratio: #p,
                        }
                    },
                })
            }
            Kind::ContactPair => self.contact_pair(ctor),
            Kind::Input => self.input(comp),
            Kind::Assembly => {
                let mut parent = Parent::Attach;
                let mut fields = vec![];
                let mut seen = HashSet::new();
                for a in &ctor.args {
                    if !seen.insert(a.key.to_string()) {
                        self.err(
                            a.key.span(),
                            format!("duplicate key `{}` in `{}(…)`", a.key, ctor.name()),
                        );
                        continue;
                    }
                    if a.key == "parent" {
                        if let Some(r) = self.reference(&a.value, Kind::Object, "parent") {
                            parent = Parent::Ref(r);
                        }
                    } else if a.key == "can_collide" {
                        self.err(
                            a.key.span(),
                            format!(
                                "`can_collide` is a key of joints, not of the sub-assembly `{}`",
                                comp.name
                            ),
                        );
                    } else {
                        fields.push((a.key.clone(), a.value.clone()));
                    }
                }
                Some(Item::Assembly {
                    name: comp.name.clone(),
                    ty: ctor.path.clone(),
                    parent,
                    fields,
                })
            }
        }
    }

    fn object(&mut self, comp: &Component) -> Option<Item> {
        let a = self.args(
            &comp.ctor,
            &["parent", "translation", "rotation", "feature"],
        );
        let mut calls = vec![];
        let mut scene = false;
        let mut parent = Parent::None;
        if let Some(p) = a.get("parent") {
            if let Some(r) = self.reference(p, Kind::Object, "parent") {
                if r.local && comp.name == r.path {
                    self.err(r.span, format!("object `{}` is its own parent", comp.name));
                } else {
                    parent = Parent::Ref(r);
                }
            }
        }
        if let Some(t) = a.get("translation") {
            calls.push(quote!(.translation(#t)));
        }
        if let Some(r) = a.get("rotation") {
            calls.push(quote!(.rotation(::modia3d::__private::rotation(#r))));
        }
        self.current_object = Some(comp.name.to_string());
        if let Some(f) = a.get("feature") {
            match self.nested(f, FEATURES, "feature") {
                Err(expr) => calls.push(quote!(.feature(#expr))),
                Ok(None) => {}
                Ok(Some(fc)) => {
                    scene = fc.name() == "Scene";
                    if let Some(feat) = self.feature(&fc, a.key("parent").map(|k| k.span())) {
                        calls.push(quote!(.feature(#feat)));
                    }
                }
            }
        }
        Some(Item::Object {
            name: comp.name.clone(),
            parent,
            calls,
            scene,
        })
    }

    fn feature(&mut self, fc: &Ctor, parent_key: Option<Span>) -> Option<TokenStream> {
        match fc.name().to_string().as_str() {
            "Scene" => {
                let a = self.args(fc, SCENE_KEYS);
                self.scene_spans.push((fc.span(), parent_key));
                Some(self.scene_options(&a))
            }
            "Visual" => {
                let a = self.args(fc, &["shape"]);
                let s = self.required(&a, "shape")?;
                let s = self.shape(s)?;
                Some(quote!(::modia3d::core::Feature::Visual(#s)))
            }
            _ => {
                let s = self.solid(fc)?;
                Some(quote!(::modia3d::core::Feature::Solid(#s)))
            }
        }
    }

    fn solid(&mut self, fc: &Ctor) -> Option<TokenStream> {
        let a = self.args(
            fc,
            &[
                "shape",
                "solid_material",
                "mass_properties",
                "collision",
                "contact_material",
                "smoothing_radius",
            ],
        );
        let mut calls = vec![];
        let mut explicit_mass = false;
        let mut has_mass = false;
        if let Some(m) = a.get("mass_properties") {
            has_mass = true;
            match self.nested(m, &["MassProperties"], "mass properties") {
                Err(e) => {
                    self.err_spanned(
                        e,
                        "expected `MassProperties(mass = …)` or `MassProperties(mass = …, com = …, inertia = …)`",
                    );
                }
                Ok(None) => {}
                Ok(Some(mc)) => {
                    let ma = self.args(&mc, &["mass", "com", "inertia"]);
                    let mass = self.num(&ma, "mass", Some(Range::Positive), true);
                    let com = ma.get("com");
                    let inertia = ma.get("inertia");
                    match (mass, com, inertia) {
                        (Some(m), None, None) => calls.push(quote!(.mass(#m))),
                        (Some(m), com, Some(i)) => {
                            explicit_mass = true;
                            let com = com
                                .map(|c| quote!(#c))
                                .unwrap_or_else(|| quote!([0.0, 0.0, 0.0]));
                            calls.push(quote! {
                                .mass_properties(
                                    #m,
                                    ::modia3d::__private::vector3(#com),
                                    ::modia3d::__private::matrix3(#i),
                                )
                            });
                        }
                        (Some(_), Some(_), None) => {
                            self.err(
                                ma.span,
                                "missing key `inertia` in `MassProperties(…)`: `com` needs an explicit `inertia` (hint: add `inertia = [[…], […], […]]`)",
                            );
                        }
                        (None, ..) => {}
                    }
                }
            }
        }
        let shape = match a.get("shape") {
            Some(s) => Some(self.shape(s)?),
            None if explicit_mass => None,
            None => {
                self.required(&a, "shape");
                return None;
            }
        };
        let mut has_material = false;
        if let Some(m) = a.get("solid_material") {
            has_material = true;
            if let Some(call) = self.material(m) {
                calls.push(call);
            }
        }
        if !has_mass && !has_material && a.get("shape").is_some() {
            self.err(
                a.span,
                "`Solid(…)` has no mass: add `solid_material = \"…\"` (mass from density) or `mass_properties = MassProperties(mass = …)`",
            );
        }
        if let Some(c) = a.get("collision") {
            calls.push(quote!(.collision(#c)));
            let on = lit_bool(c) == Some(true);
            let cm = a.get("contact_material");
            if on && !has_material && cm.is_none() {
                let key = a.key("collision").expect("present");
                self.err(
                    key.span(),
                    "`collision = true` needs a material (hint: add `solid_material = \"…\"` or `contact_material = \"…\"`)",
                );
            }
            if on {
                if let Some(obj) = self.current_object.clone() {
                    let m = cm.or_else(|| a.get("solid_material"));
                    if let Some(m) = m {
                        let (material, written) = self.literal_contact_material(m, cm.is_some());
                        self.colliders.push(Collider {
                            object: obj,
                            material,
                            written,
                            span: m.span(),
                        });
                    }
                }
            }
        }
        if let Some(c) = a.get("contact_material") {
            calls.push(quote!(.contact_material(&(#c))));
        }
        if let Some(r) = self.num(&a, "smoothing_radius", Some(Range::NonNegative), false) {
            calls.push(quote!(.smoothing_radius(#r)));
        }
        let base = match shape {
            Some(s) => quote!(::modia3d::core::Solid::new(#s)),
            None => quote!(<::modia3d::core::Solid as ::core::default::Default>::default()),
        };
        Some(quote!(#base #(#calls)*))
    }

    /// `solid_material = "Steel" | wood | <expr>` → a builder call.
    fn material(&mut self, m: &Expr) -> Option<TokenStream> {
        let locals: Vec<String> = self
            .kinds
            .iter()
            .filter(|(_, k)| **k == Kind::Material)
            .map(|(n, _)| n.clone())
            .collect();
        if let Some(name) = lit_str(m) {
            if locals.contains(&name) {
                let n = scoped(&name);
                return Some(quote_spanned!(m.span()=> .material(#n)));
            }
            if BUILTIN_SOLID_MATERIALS.contains(&name.as_str()) {
                return Some(quote!(.material(#m)));
            }
            let h = did_you_mean(
                &name,
                BUILTIN_SOLID_MATERIALS
                    .iter()
                    .copied()
                    .chain(locals.iter().map(|s| s.as_str())),
            );
            let msg = match h {
                Some(h) => format!("unknown solid material `{name}` (hint: did you mean `{h}`?)"),
                None => format!(
                    "unknown solid material `{name}` (hint: the built-in ones are {}; or define it in the block: `{} = SolidMaterial(…)`)",
                    BUILTIN_SOLID_MATERIALS
                        .iter()
                        .map(|n| format!("`{n}`"))
                        .collect::<Vec<_>>()
                        .join(", "),
                    name.to_lowercase().replace(|c: char| !c.is_alphanumeric(), "_"),
                ),
            };
            self.err(m.span(), msg);
            return None;
        }
        if let Expr::Path(p) = m {
            if let Some(id) = p.path.get_ident() {
                let n = id.to_string();
                match self.kinds.get(&n) {
                    Some(Kind::Material) => {
                        let s = scoped(&n);
                        return Some(quote!(.material(#s)));
                    }
                    Some(k) => {
                        self.err(
                            id.span(),
                            format!("`{n}` is {}, not a solid material", article(*k)),
                        );
                        return None;
                    }
                    None if !self.params.contains(&n) => {
                        if let Some(h) = did_you_mean(&n, locals.iter().map(|s| s.as_str())) {
                            self.err(
                                id.span(),
                                format!("unknown solid material `{n}`{}", hint(Some(h))),
                            );
                            return None;
                        }
                    }
                    None => {}
                }
            }
        }
        Some(quote!(.material(&(#m))))
    }

    /// `JointForce(joint)`, `JointAcceleration(joint)`, `ObjectWrench(object)` → `Input`.
    fn input(&mut self, comp: &Component) -> Option<Item> {
        let ctor = &comp.ctor;
        let cname = ctor.name().to_string();
        let n = scoped(&comp.name.to_string());
        let input = quote!(::modia3d::core::Input);
        if cname == "ObjectWrench" {
            let a = self.args(ctor, &["object"]);
            let o = self
                .required(&a, "object")
                .and_then(|e| self.reference(e, Kind::Object, "object"))?;
            let o = scoped(&o.path);
            return Some(Item::Input {
                value: quote!(#input::object_wrench(#n, #o)),
            });
        }
        let a = self.args(ctor, &["joint"]);
        let e = self.required(&a, "joint")?;
        let j = self.reference(e, Kind::Joint, "joint")?;
        if j.local {
            let ty = self.joint_types.get(&j.path).cloned().unwrap_or_default();
            if ty != "Revolute" && ty != "Prismatic" {
                self.err(
                    j.span,
                    format!(
                        "`{cname}` needs a Revolute or Prismatic joint, but `{}` is a {ty} (hint: it has no single coordinate to drive)",
                        j.path
                    ),
                );
                return None;
            }
            if cname == "JointAcceleration" {
                if let Some(first) = self.driven.get(&j.path) {
                    self.err(
                        j.span,
                        format!(
                            "joint `{}` already has a prescribed acceleration: input `{first}` (hint: one `JointAcceleration` per joint)",
                            j.path
                        ),
                    );
                    return None;
                }
                self.driven.insert(j.path.clone(), comp.name.to_string());
            }
        }
        let j = scoped(&j.path);
        let f = if cname == "JointForce" {
            quote!(joint_force)
        } else {
            quote!(joint_acceleration)
        };
        Some(Item::Input {
            value: quote!(#input::#f(#n, #j)),
        })
    }

    /// `Scene(…)` → `Feature::Scene(SceneOptions { …, ..Default::default() })`, literal values
    /// range-checked as `SceneDesc::validate` does.
    fn scene_options(&mut self, a: &Args) -> TokenStream {
        let pos = Some(Range::Positive);
        let mut fields = vec![];
        if let Some(g) = a.get("gravity") {
            fields.push(quote!(gravity: ::modia3d::__private::vector3(#g)));
        }
        self.contact_detection = Some(true);
        if let Some(c) = a.get("contact_detection") {
            self.contact_detection = lit_bool(c);
            fields.push(quote!(contact_detection: #c));
        }
        let ranged: [(&str, Option<Range>); 8] = [
            ("k_red", pos),
            ("d_max", pos),
            ("cor_min", Some(Range::PositiveUnit)),
            ("v_min", pos),
            ("w_min", pos),
            ("hysteresis", pos),
            ("mpr_tolerance", pos),
            ("smoothing_radius", Some(Range::NonNegative)),
        ];
        for (key, range) in ranged {
            if let Some(v) = self.num(a, key, range, false) {
                let k = format_ident!("{}", key);
                fields.push(quote!(#k: #v));
            }
        }
        if let Some(v) = a.get("mpr_max_iterations") {
            if lit_int(v).is_some_and(|i| i <= 0) {
                self.err_spanned(
                    v,
                    format!(
                        "`mpr_max_iterations` must be positive, found `{}`",
                        v.to_token_stream().to_string().replace(' ', "")
                    ),
                );
            }
            fields.push(quote!(mpr_max_iterations: #v));
        }
        if let Some(p) = a.get("profile") {
            let cp = quote!(::modia3d::core::ContactProfile);
            match p {
                Expr::Path(ep) if ep.path.get_ident().is_some() => {
                    let id = ep.path.get_ident().expect("checked");
                    let n = id.to_string();
                    if PROFILES.contains(&n.as_str()) {
                        fields.push(quote!(contact_profile: #cp::#id));
                    } else if self.params.contains(&n) {
                        fields.push(quote!(contact_profile: #p));
                    } else {
                        let h = did_you_mean(&n, PROFILES.iter().copied())
                            .map(|h| format!("did you mean `{h}`?"))
                            .unwrap_or_else(|| "`Paper2019` or `Modia3DLater`".into());
                        self.err(
                            id.span(),
                            format!("unknown contact profile `{n}` (hint: {h})"),
                        );
                    }
                }
                _ => fields.push(quote!(contact_profile: #p)),
            }
        }
        quote! {
            ::modia3d::core::Feature::Scene(::modia3d::core::SceneOptions {
                #(#fields,)*
                ..::core::default::Default::default()
            })
        }
    }

    /// A material name in `ContactPair(…)`: `"Steel"`, `"wood"` or `wood` (a material of this
    /// block), or a `&str`/`String` expression. Returns the builder argument and the literal
    /// name (`None` if not literal).
    fn pair_material(&mut self, e: &Expr) -> Option<(TokenStream, Option<String>)> {
        let is_local = |c: &Self, n: &str| c.kinds.get(n) == Some(&Kind::Material);
        if let Some(name) = lit_str(e) {
            if is_local(self, &name) {
                return Some((scoped(&name), Some(name)));
            }
            return Some((quote!(#e), Some(name)));
        }
        if let Expr::Path(p) = e {
            if let Some(id) = p.path.get_ident() {
                let n = id.to_string();
                match self.kinds.get(&n) {
                    Some(Kind::Material) => return Some((scoped(&n), Some(n))),
                    Some(k) => {
                        self.err(
                            id.span(),
                            format!(
                                "`{n}` is {}, not a material (hint: a contact material is a string like `\"Steel\"` or a `SolidMaterial` of this block)",
                                article(*k)
                            ),
                        );
                        return None;
                    }
                    None if !self.params.contains(&n) => {
                        let locals: Vec<&str> = self
                            .kinds
                            .iter()
                            .filter(|(_, k)| **k == Kind::Material)
                            .map(|(n, _)| n.as_str())
                            .collect();
                        self.err(
                            id.span(),
                            format!(
                                "unknown material `{n}`{}",
                                match did_you_mean(&n, locals) {
                                    Some(h) => hint(Some(h)),
                                    None => format!(" (hint: write a name as a string, `\"{n}\"`, or define `{n} = SolidMaterial(…)`)"),
                                }
                            ),
                        );
                        return None;
                    }
                    None => {}
                }
            }
        }
        self.pairs_unsure = true;
        Some((quote!(&(#e)), None))
    }

    /// `ContactPair(material1, material2, cor, mu_k, mu_r, v_min, w_min)`.
    fn contact_pair(&mut self, ctor: &Ctor) -> Option<Item> {
        let a = self.args(
            ctor,
            &[
                "material1",
                "material2",
                "cor",
                "mu_k",
                "mu_r",
                "v_min",
                "w_min",
            ],
        );
        let m1 = self
            .required(&a, "material1")
            .and_then(|e| self.pair_material(e));
        let m2 = self
            .required(&a, "material2")
            .and_then(|e| self.pair_material(e));
        let nn = Some(Range::NonNegative);
        let cor = self.num(&a, "cor", Some(Range::UnitInterval), true);
        let mu_k = self.num(&a, "mu_k", nn, true);
        let mu_r = self.num(&a, "mu_r", nn, true);
        let v_min = self.num(&a, "v_min", Some(Range::Positive), false);
        let w_min = self.num(&a, "w_min", Some(Range::Positive), false);
        let ((m1, n1), (m2, n2), cor, mu_k, mu_r) = (m1?, m2?, cor?, mu_k?, mu_r?);
        if let (Some(n1), Some(n2)) = (n1, n2) {
            self.pairs.push((n1, n2));
        }
        let private = quote!(::modia3d::__private);
        let v = v_min.map(|v| quote!(__modia3d_pair.v_min = #private::optional_f64(#v);));
        let w = w_min.map(|w| quote!(__modia3d_pair.w_min = #private::optional_f64(#w);));
        Some(Item::ContactPair {
            material1: m1,
            material2: m2,
            value: quote! {{
                #[allow(unused_mut)]
                let mut __modia3d_pair = ::modia3d::core::ContactPairMaterial::new(#cor, #mu_k, #mu_r);
                #v
                #w
                __modia3d_pair
            }},
        })
    }

    /// The contact material of a colliding solid as the core will name it (at the top level),
    /// if it is literal, and how to write it in a `ContactPair(…)`.
    fn literal_contact_material(&self, m: &Expr, explicit: bool) -> (Option<String>, String) {
        if let Some(name) = lit_str(m) {
            let written = if !explicit && self.kinds.get(&name) == Some(&Kind::Material) {
                name.clone()
            } else {
                format!("{name:?}")
            };
            return (Some(name), written);
        }
        if let Expr::Path(p) = m {
            if let Some(id) = p.path.get_ident() {
                let n = id.to_string();
                if !explicit && self.kinds.get(&n) == Some(&Kind::Material) {
                    return (Some(n.clone()), n);
                }
            }
        }
        (None, String::new())
    }

    /// Two literal contact materials that can meet without a pair entry. Only where the block
    /// tells for sure: a model (an assembly's outer model may add pairs), without sub-assemblies
    /// (they may add pairs), with literal `contact_detection` on and literal pair names; solids
    /// on one rigid body (parents, Fix) never meet, nor do the bodies of a Revolute/Prismatic
    /// without `can_collide` (a non-literal `can_collide` counts as excluding). The core reports
    /// the rest when the scene is built.
    fn missing_pairs(&mut self, items: &[Item]) {
        if self.pairs_unsure
            || self.contact_detection != Some(true)
            || items.iter().any(|it| matches!(it, Item::Assembly { .. }))
        {
            return;
        }
        let mut uf = UnionFind::default();
        for it in items {
            match it {
                Item::Object {
                    name,
                    parent: Parent::Ref(p),
                    ..
                } => uf.union(&name.to_string(), &p.path),
                Item::Joint {
                    obj1, obj2, rigid, ..
                } if *rigid => uf.union(&obj1.path, &obj2.path),
                _ => {}
            }
        }
        let mut excluded: HashSet<(String, String)> = HashSet::new();
        for it in items {
            if let Item::Joint {
                obj1,
                obj2,
                excludes,
                ..
            } = it
            {
                if *excludes != Some(false) {
                    let (a, b) = (uf.find(&obj1.path), uf.find(&obj2.path));
                    excluded.insert((a.clone(), b.clone()));
                    excluded.insert((b, a));
                }
            }
        }
        let has_pair = |x: &str, y: &str, pairs: &[(String, String)]| {
            let same = |a: &str, b: &str| (a == x && b == y) || (a == y && b == x);
            BUILTIN_CONTACT_PAIRS.iter().any(|(a, b)| same(a, b))
                || pairs.iter().any(|(a, b)| same(a, b))
        };
        let mut reported: HashSet<(String, String)> = HashSet::new();
        let mut errors = vec![];
        for (j, cj) in self.colliders.iter().enumerate() {
            let Some(mj) = &cj.material else { continue };
            for ci in &self.colliders[..j] {
                let Some(mi) = &ci.material else { continue };
                let (gi, gj) = (uf.find(&ci.object), uf.find(&cj.object));
                if gi == gj || excluded.contains(&(gi, gj)) || has_pair(mi, mj, &self.pairs) {
                    continue;
                }
                let key = if mi <= mj {
                    (mi.clone(), mj.clone())
                } else {
                    (mj.clone(), mi.clone())
                };
                if !reported.insert(key) {
                    continue;
                }
                let ident = |s: &str| {
                    s.to_lowercase()
                        .replace(|c: char| !c.is_alphanumeric(), "_")
                };
                let pname = format!("{}_{}", ident(mi), ident(mj));
                errors.push((
                    cj.span,
                    format!(
                        "no contact-pair material for `{mi}` and `{mj}`: solids `{}` and `{}` can collide (hint: add `{pname} = ContactPair(material1 = {}, material2 = {}, cor = …, mu_k = …, mu_r = …)`)",
                        ci.object, cj.object, ci.written, cj.written
                    ),
                ));
            }
        }
        for (span, msg) in errors {
            self.err(span, msg);
        }
    }

    fn shape(&mut self, e: &Expr) -> Option<TokenStream> {
        let sc = match self.nested(e, SHAPES, "shape") {
            Err(expr) => return Some(quote!(#expr)),
            Ok(None) => return None,
            Ok(Some(c)) => c,
        };
        let name = sc.name().to_string();
        let pos = Some(Range::Positive);
        let shape = quote!(::modia3d::core::Shape);
        let v3 = quote!(::modia3d::__private::vector3);
        match name.as_str() {
            "Sphere" => {
                let a = self.args(&sc, &["diameter"]);
                let d = self.num(&a, "diameter", pos, true)?;
                Some(quote!(#shape::Sphere { diameter: #d }))
            }
            "Box" | "Ellipsoid" => {
                let a = self.args(&sc, &["lengths"]);
                let l = self.num(&a, "lengths", pos, true)?;
                let id = format_ident!("{}", name);
                Some(quote!(#shape::#id { lengths: #v3(#l) }))
            }
            "Cylinder" | "Capsule" | "Cone" => {
                let keys: &[&str] = if name == "Cone" {
                    &["axis", "diameter", "length", "top_diameter"]
                } else {
                    &["axis", "diameter", "length"]
                };
                let a = self.args(&sc, keys);
                let axis = self.shape_axis(a.get("axis"));
                let d = self.num(&a, "diameter", pos, true);
                let l = self.num(&a, "length", pos, true);
                let top = if name == "Cone" {
                    let t = self.num(&a, "top_diameter", Some(Range::NonNegative), false);
                    let t = t.map(|t| quote!(#t)).unwrap_or_else(|| quote!(0.0));
                    quote!(top_diameter: #t,)
                } else {
                    quote!()
                };
                let (axis, d, l) = (axis?, d?, l?);
                let id = format_ident!("{}", name);
                Some(quote!(#shape::#id { axis: #axis, diameter: #d, length: #l, #top }))
            }
            _ => {
                let a = self.args(&sc, &["points"]);
                let p = self.required(&a, "points")?;
                Some(quote!(#shape::ConvexHull { points: ::modia3d::__private::points(#p) }))
            }
        }
    }

    /// A shape's axis: literal 1..3 (default 3, z) or an expression of type `Axis`.
    fn shape_axis(&mut self, e: Option<&Expr>) -> Option<TokenStream> {
        let axis = quote!(::modia3d::core::Axis);
        let Some(e) = e else {
            return Some(quote!(#axis::Z));
        };
        match lit_int(e) {
            Some(1) => Some(quote!(#axis::X)),
            Some(2) => Some(quote!(#axis::Y)),
            Some(3) => Some(quote!(#axis::Z)),
            Some(i) => {
                self.err(
                    e.span(),
                    format!("`axis` of a shape must be 1, 2 or 3 (x, y, z), found `{i}`"),
                );
                None
            }
            None => Some(quote!(#e)),
        }
    }

    /// `Var(init = …)` → the initial value.
    fn var(&mut self, key: &str, e: &Expr) -> Option<Expr> {
        match self.nested(e, &["Var"], "initial value") {
            Err(e) => {
                self.err(
                    e.span(),
                    format!(
                        "expected `Var(init = …)` for `{key}` (hint: `{key} = Var(init = {})`)",
                        e.to_token_stream().to_string().replace(" . ", ".")
                    ),
                );
                None
            }
            Ok(None) => None,
            Ok(Some(vc)) => {
                let a = self.args(&vc, &["init"]);
                self.required(&a, "init").cloned()
            }
        }
    }

    fn joint(&mut self, comp: &Component) -> Option<Item> {
        let ctor = &comp.ctor;
        let kind_name = ctor.name().to_string();
        let keys: &[&str] = match kind_name.as_str() {
            "Fix" => &["obj1", "obj2", "can_collide"],
            "Revolute" => &["obj1", "obj2", "axis", "phi", "w", "can_collide"],
            "Prismatic" => &["obj1", "obj2", "axis", "s", "v", "can_collide"],
            _ => &["obj1", "obj2", "r", "rot", "v", "w", "can_collide"],
        };
        let a = self.args(ctor, keys);
        let o1 = self
            .required(&a, "obj1")
            .and_then(|e| self.reference(e, Kind::Object, "object"));
        let o2 = self
            .required(&a, "obj2")
            .and_then(|e| self.reference(e, Kind::Object, "object"));
        let mut calls = vec![];
        let can_collide = match a.get("can_collide") {
            Some(c) => {
                calls.push(quote!(.can_collide(#c)));
                lit_bool(c)
            }
            None => Some(false),
        };
        // As the core's contact preprocessing: Fix merges the bodies, Revolute and Prismatic
        // exclude their pair unless `can_collide`, FreeMotion never excludes.
        let rigid = kind_name == "Fix";
        let excludes = match kind_name.as_str() {
            "Revolute" | "Prismatic" => can_collide.map(|c| !c),
            _ => Some(false),
        };
        let jk = quote!(::modia3d::core::JointKind);
        let v3 = quote!(::modia3d::__private::vector3);
        let kind = match kind_name.as_str() {
            "Fix" => Some(quote!(#jk::Fix)),
            "Revolute" | "Prismatic" => {
                let (pos, vel) = if kind_name == "Revolute" {
                    ("phi", "w")
                } else {
                    ("s", "v")
                };
                let axis = match a.get("axis") {
                    None => Some(quote!(3)),
                    Some(e) => match lit_int(e) {
                        Some(i) if (1..=3).contains(&i.abs()) => Some(quote!(#e)),
                        Some(i) => {
                            self.err(
                                e.span(),
                                format!("`axis` must be ±1, ±2 or ±3 (±x, ±y, ±z), found `{i}`"),
                            );
                            None
                        }
                        None => Some(quote!(#e)),
                    },
                };
                if let Some(p) = a.get(pos) {
                    if let Some(init) = self.var(pos, p) {
                        calls.push(quote!(.init_position(#init)));
                    }
                }
                if let Some(v) = a.get(vel) {
                    if let Some(init) = self.var(vel, v) {
                        calls.push(quote!(.init_velocity(#init)));
                    }
                }
                let ctor_fn = format_ident!("{}", kind_name.to_lowercase());
                match a.get("axis") {
                    // A vector axis: the variant itself, at rest at 0 like the constructors.
                    Some(Expr::Array(arr)) => Some(if kind_name == "Revolute" {
                        quote!(#jk::Revolute { axis: #v3(#arr), phi: 0.0, w: 0.0 })
                    } else {
                        quote!(#jk::Prismatic { axis: #v3(#arr), s: 0.0, v: 0.0 })
                    }),
                    _ => axis.map(|ax| quote!(#jk::#ctor_fn(#ax))),
                }
            }
            _ => {
                let mut field = |k: &str, default: TokenStream| -> TokenStream {
                    match a.get(k).and_then(|e| self.var(k, e)) {
                        Some(init) => quote!(#init),
                        None => default,
                    }
                };
                let zero = quote!([0.0, 0.0, 0.0]);
                let r = field("r", zero.clone());
                let rot = field("rot", zero.clone());
                let v = field("v", zero.clone());
                let w = field("w", zero);
                Some(quote! {
                    #jk::FreeMotion {
                        r: #v3(#r),
                        rot: ::modia3d::__private::free_rotation(#rot),
                        v: #v3(#v),
                        w: #v3(#w),
                    }
                })
            }
        };
        Some(Item::Joint {
            name: comp.name.clone(),
            obj1: o1?,
            obj2: o2?,
            kind: kind?,
            calls,
            rigid,
            excludes,
        })
    }

    fn force(&mut self, comp: &Component) -> Option<Item> {
        let ctor = &comp.ctor;
        let fe = quote!(::modia3d::core::ForceElement);
        let nn = Some(Range::NonNegative);
        match ctor.name().to_string().as_str() {
            "SpringDamper" => {
                let a = self.args(ctor, &["obj1", "obj2", "stiffness", "damping", "length0"]);
                let o1 = self
                    .required(&a, "obj1")
                    .and_then(|e| self.reference(e, Kind::Object, "object"));
                let o2 = self
                    .required(&a, "obj2")
                    .and_then(|e| self.reference(e, Kind::Object, "object"));
                let c = self.num(&a, "stiffness", nn, true);
                let d = self.num(&a, "damping", nn, false);
                let l = self.num(&a, "length0", nn, false);
                let (o1, o2, c) = (o1?, o2?, c?);
                let d = d.map(|d| quote!(#d)).unwrap_or_else(|| quote!(0.0));
                let l = l.map(|l| quote!(#l)).unwrap_or_else(|| quote!(0.0));
                let (name, o1, o2) = (
                    scoped(&comp.name.to_string()),
                    scoped(&o1.path),
                    scoped(&o2.path),
                );
                Some(Item::Force {
                    value: quote! {
                        #fe::SpringDamper {
                            name: ::std::string::ToString::to_string(#name),
                            obj1: ::std::string::ToString::to_string(#o1),
                            obj2: ::std::string::ToString::to_string(#o2),
                            stiffness: #c,
                            damping: #d,
                            length0: #l,
                        }
                    },
                })
            }
            "JointSpringDamper" => {
                let a = self.args(ctor, &["joint", "stiffness", "damping", "offset"]);
                let j = self
                    .required(&a, "joint")
                    .and_then(|e| self.reference(e, Kind::Joint, "joint"));
                let c = self.num(&a, "stiffness", nn, true);
                let d = self.num(&a, "damping", nn, false);
                let (j, c) = (j?, c?);
                let d = d.map(|d| quote!(#d)).unwrap_or_else(|| quote!(0.0));
                let off = a
                    .get("offset")
                    .map(|o| quote!(#o))
                    .unwrap_or_else(|| quote!(0.0));
                let j = scoped(&j.path);
                Some(Item::Force {
                    value: quote! {
                        #fe::JointSpringDamper {
                            joint: ::std::string::ToString::to_string(#j),
                            stiffness: #c,
                            damping: #d,
                            offset: #off,
                        }
                    },
                })
            }
            _ => {
                let a = self.args(ctor, &["object", "law"]);
                let o = self
                    .required(&a, "object")
                    .and_then(|e| self.reference(e, Kind::Object, "object"));
                let law = self.required(&a, "law");
                let (o, law) = (o?, law?);
                let o = scoped(&o.path);
                Some(Item::Force {
                    value: quote! {
                        #fe::ObjectForce {
                            object: ::std::string::ToString::to_string(#o),
                            law: ::modia3d::core::ForceFn::new(#law),
                        }
                    },
                })
            }
        }
    }

    /// Resolves `name` or `assembly.path.to.part`; paths into sub-assemblies are checked by
    /// rustc through `path_checks`.
    fn reference(&mut self, e: &Expr, want: Kind, role: &str) -> Option<NameRef> {
        let mut segs = vec![];
        if !path_segments(e, &mut segs) {
            let what = if want == Kind::Joint {
                "the name of a joint, like `rev` or `arm1.rev`"
            } else {
                "the name of an object, like `body` or `arm1.tip`"
            };
            self.err_spanned(e, format!("expected {what}"));
            return None;
        }
        let first = &segs[0];
        let fname = first.to_string();
        let wanted = |k: Kind| k == want || k == Kind::Assembly;
        let Some(&kind) = self.kinds.get(&fname) else {
            let cands: Vec<&str> = self
                .kinds
                .iter()
                .filter(|(_, k)| wanted(**k))
                .map(|(n, _)| n.as_str())
                .collect();
            let h = did_you_mean(&fname, cands);
            self.err(first.span(), format!("unknown {role} `{fname}`{}", hint(h)));
            return None;
        };
        if segs.len() == 1 {
            if kind == Kind::Assembly {
                self.err(
                    first.span(),
                    format!(
                        "`{fname}` is a sub-assembly, not {} (hint: name one of its parts, like `{fname}.<name>`)",
                        article(want)
                    ),
                );
                return None;
            }
            if kind != want {
                self.err(
                    first.span(),
                    format!("`{fname}` is {}, not {}", article(kind), article(want)),
                );
                return None;
            }
        } else {
            if kind != Kind::Assembly {
                self.err(
                    segs[1].span(),
                    format!(
                        "`{fname}` is {}, not a sub-assembly: only parts of sub-assemblies are reached by paths",
                        article(kind)
                    ),
                );
                return None;
            }
            let ty = self.assembly_types[&fname].clone();
            let rest = &segs[1..];
            let module = crate::expand::paths_module_at(&ty, rest[0].span());
            let marker = if want == Kind::Joint {
                quote!(JointPath)
            } else {
                quote!(ObjectPath)
            };
            let last_span = rest.last().expect("non-empty").span();
            let marker = quote_spanned!(last_span=> ::modia3d::__private::#marker);
            self.path_checks.push(quote! {
                let _: #marker = #module #(:: #rest)*;
            });
        }
        Some(NameRef {
            path: segs
                .iter()
                .map(|s| s.to_string())
                .collect::<Vec<_>>()
                .join("."),
            span: e.span(),
            local: segs.len() == 1,
        })
    }

    /// Missing, duplicate and misplaced `Scene`s.
    fn scenes(&mut self, def: &ModelDef) {
        let spans = self.scene_spans.clone();
        if let Some(kw) = &def.assembly {
            for (s, _) in &spans {
                self.err(
                    *s,
                    format!(
                        "assembly `{}` must not have a `Scene`: the outer model has the world (hint: remove this object, or drop `{kw}` to make `{}` a model)",
                        def.name, def.name
                    ),
                );
            }
            return;
        }
        if spans.is_empty() {
            self.err(
                def.name.span(),
                format!(
                    "model `{}` has no `Scene` object (hint: add `world = Object3D(feature = Scene())`, or write `assembly {}` for a sub-assembly)",
                    def.name, def.name
                ),
            );
        }
        for (s, _) in spans.iter().skip(1) {
            self.err(
                *s,
                "duplicate `Scene`: a model has exactly one `Scene` object (the world)",
            );
        }
        for (_, p) in &spans {
            if let Some(p) = p {
                self.err(
                    *p,
                    "the `Scene` object must not have a `parent`: it is the world frame, the root (hint: remove `parent`)",
                );
            }
        }
    }

    /// Parent cycles, joints moving one object twice, identical joint ends, kinematic loops;
    /// then the attach rule for assemblies.
    fn topology(&mut self, mut items: Vec<Item>) -> Vec<Item> {
        // Local parent links.
        let mut parent_of: HashMap<String, NameRef> = HashMap::new();
        for it in &items {
            let (name, parent) = match it {
                Item::Object { name, parent, .. } | Item::Assembly { name, parent, .. } => {
                    (name, parent)
                }
                _ => continue,
            };
            if let Parent::Ref(r) = parent {
                parent_of.insert(name.to_string(), r.clone());
            }
        }
        let mut in_cycle: HashSet<String> = HashSet::new();
        let names: Vec<String> = items
            .iter()
            .filter_map(|it| match it {
                Item::Object { name, .. } | Item::Assembly { name, .. } => Some(name.to_string()),
                _ => None,
            })
            .collect();
        for start in &names {
            if in_cycle.contains(start) {
                continue;
            }
            let mut chain = vec![start.clone()];
            let mut cur = start.clone();
            while let Some(p) = parent_of.get(&cur).filter(|p| p.local) {
                if p.path == *start {
                    let list = chain
                        .iter()
                        .map(|n| format!("`{n}`"))
                        .collect::<Vec<_>>()
                        .join(" → ");
                    let span = parent_of[&chain[chain.len() - 1]].span;
                    self.err(
                        span,
                        format!("parent cycle: {list} → `{start}` (hint: a parent chain must end at a root; remove one `parent`)"),
                    );
                    in_cycle.extend(chain.iter().cloned());
                    break;
                }
                if chain.contains(&p.path) {
                    break; // a cycle not through `start`; reported from its own members
                }
                chain.push(p.path.clone());
                cur = p.path.clone();
            }
        }
        // Rigid groups by parent links.
        let mut uf = UnionFind::default();
        for (child, p) in &parent_of {
            if !in_cycle.contains(child) {
                uf.union(child, &p.path);
            }
        }
        let rigid = uf.clone();
        // Joints.
        let mut moved_by: HashMap<String, String> = HashMap::new();
        for it in &items {
            let Item::Joint {
                name, obj1, obj2, ..
            } = it
            else {
                continue;
            };
            if obj1.path == obj2.path {
                self.err(
                    obj2.span,
                    format!(
                        "joint `{name}` joins `{}` to itself (hint: obj1 and obj2 must differ)",
                        obj2.path
                    ),
                );
                continue;
            }
            if let Some(first) = moved_by.get(&obj2.path) {
                self.err(
                    obj2.span,
                    format!(
                        "object `{}` has two parents: it is already obj2 of joint `{first}` (hint: an object is moved by one joint only; swap obj1 and obj2, or join another object)",
                        obj2.path
                    ),
                );
                continue;
            }
            moved_by.insert(obj2.path.clone(), name.to_string());
            if uf.find(&obj1.path) == uf.find(&obj2.path) {
                self.err(
                    obj2.span,
                    format!(
                        "kinematic loop: joint `{name}` joins `{}` and `{}`, which are already connected (hint: closed chains are not supported; remove this joint or a `parent` of the loop)",
                        obj1.path, obj2.path
                    ),
                );
                continue;
            }
            uf.union(&obj1.path, &obj2.path);
        }
        // Attach rule: parts without `parent` whose rigid group no local joint moves.
        let mut rigid = rigid;
        let moved_groups: HashSet<String> = moved_by
            .keys()
            .filter(|p| !p.contains('.'))
            .map(|p| rigid.find(p))
            .collect();
        for it in &mut items {
            match it {
                Item::Object {
                    name,
                    parent,
                    scene,
                    ..
                } if matches!(parent, Parent::None)
                    && !*scene
                    && !moved_groups.contains(&rigid.find(&name.to_string())) =>
                {
                    *parent = Parent::Attach;
                }
                Item::Assembly { name, parent, .. } => {
                    // A sub-assembly that a joint of this block moves is not root-level.
                    let inside = format!("{name}.");
                    if matches!(parent, Parent::Attach)
                        && moved_by.keys().any(|p| p.starts_with(&inside))
                    {
                        *parent = Parent::None;
                    }
                }
                _ => {}
            }
        }
        items
    }
}

fn article(k: Kind) -> &'static str {
    match k {
        Kind::Object => "an object",
        Kind::Joint => "a joint",
        Kind::Force => "a force element",
        Kind::Material => "a solid material",
        Kind::ContactPair => "a contact-pair material",
        Kind::Input => "an input",
        Kind::Assembly => "a sub-assembly",
    }
}

/// `a` or `a.b.c` → identifiers; false for anything else.
fn path_segments(e: &Expr, out: &mut Vec<Ident>) -> bool {
    match e {
        Expr::Path(p) if p.qself.is_none() => match p.path.get_ident() {
            Some(id) => {
                out.push(id.clone());
                true
            }
            None => false,
        },
        Expr::Field(f) => {
            if !path_segments(&f.base, out) {
                return false;
            }
            match &f.member {
                syn::Member::Named(id) => {
                    out.push(id.clone());
                    true
                }
                syn::Member::Unnamed(_) => false,
            }
        }
        _ => false,
    }
}

#[derive(Default, Clone)]
struct UnionFind {
    parent: HashMap<String, String>,
}

impl UnionFind {
    fn find(&mut self, x: &str) -> String {
        let p = self.parent.get(x).cloned();
        match p {
            None => x.to_string(),
            Some(p) if p == x => p,
            Some(p) => {
                let r = self.find(&p);
                self.parent.insert(x.to_string(), r.clone());
                r
            }
        }
    }
    fn union(&mut self, a: &str, b: &str) {
        let (ra, rb) = (self.find(a), self.find(b));
        if ra != rb {
            self.parent.insert(ra, rb);
        }
    }
}
