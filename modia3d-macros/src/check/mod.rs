//! Check stage: interprets the syntax tree against the vocabulary (`vocab.rs`) and lowers it to
//! the IR (`ir.rs`): unknown or duplicate names, constructors and keys, missing keys,
//! references of the wrong kind, misplaced `Scene`s — everything that needs the user's
//! tokens. The rules of a valid *scene* (value ranges, materials, topology, contact pairs) are
//! the core's: `rules.rs` runs them on the literal part of the IR. All errors of a block are
//! collected in one pass, each on the smallest offending token, and sorted into source order
//! of discovery by their slot.
//!
//! What the macro cannot see (objects inside another `model!`'s expansion, types of values) is
//! left to rustc through spanned code (`ir::PathCheck`, `expand/`).

mod blocks;
mod joints;
mod values;

use crate::ast::{push, Arg, Ctor, ModelDef};
use crate::ir::{Ir, Item, LitNum, MaterialIr, Num, Parent, PathCheck, PathWant};
use crate::names::{did_you_mean, hint, path_segments, NameRef};
use crate::vocab::{components, is_nested, nested_hint, Kind, SYNONYMS};
use proc_macro2::{Ident, Span};
use quote::ToTokens;
use std::collections::{HashMap, HashSet};
use syn::spanned::Spanned;
use syn::{Expr, Lit};

/// Errors of a block, each with its slot (the order in which they are reported).
pub(crate) struct Errors {
    list: Vec<(u32, syn::Error)>,
    next: u32,
}

impl Errors {
    fn new() -> Self {
        Errors {
            list: vec![],
            next: 0,
        }
    }
    /// A fresh slot: errors found later about this place sort here.
    pub(crate) fn slot(&mut self) -> u32 {
        self.next += 1;
        self.next
    }
    /// Adds an error in the next slot.
    pub(crate) fn push(&mut self, e: syn::Error) {
        let s = self.slot();
        self.list.push((s, e));
    }
    /// Adds an error in a given slot.
    pub(crate) fn push_at(&mut self, slot: u32, e: syn::Error) {
        self.list.push((slot, e));
    }
    /// Whether any error was found.
    pub(crate) fn any(&self) -> bool {
        !self.list.is_empty()
    }
    /// All errors combined in slot order, or `None`.
    pub(crate) fn combined(mut self) -> Option<syn::Error> {
        self.list.sort_by_key(|(s, _)| *s);
        let mut acc = None;
        for (_, e) in self.list {
            push(&mut acc, e);
        }
        acc
    }
}

/// The parameters whose type is `ty` (its last path segment: `SignalRef`,
/// `modia3d::SignalRef`).
fn typed_params(def: &ModelDef, ty: &str) -> HashSet<String> {
    def.params
        .iter()
        .filter(|p| {
            matches!(&p.ty, syn::Type::Path(t)
                if t.path.segments.last().is_some_and(|s| s.ident == ty))
        })
        .map(|p| p.name.to_string())
        .collect()
}

/// Checks a block and lowers it; the errors found (not yet those of the core's scene rules).
pub(crate) fn check(def: &ModelDef) -> (Ir, Errors) {
    let mut c = Checker {
        errors: Errors::new(),
        kinds: HashMap::new(),
        assembly_types: HashMap::new(),
        ctors: HashMap::new(),
        signal_params: typed_params(def, "SignalRef"),
        joint_params: typed_params(def, "JointRef"),
        feedthrough_reads: vec![],
        block_ports: HashMap::new(),
        params: def.params.iter().map(|p| p.name.to_string()).collect(),
        path_checks: vec![],
        scene_spans: vec![],
    };
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
    let mut lowered = vec![];
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
            c.kinds.insert(name.clone(), k);
            c.ctors.insert(name.clone(), comp.ctor.name().to_string());
            if let Some(spec) = crate::vocab::block_kind(&comp.ctor.name().to_string()) {
                c.block_ports
                    .insert(name.clone(), blocks::block_ports(spec, &comp.ctor));
            }
            if k == Kind::Assembly {
                c.assembly_types.insert(name, comp.ctor.path.clone());
            }
            kinds.push((comp.name.clone(), k));
            lowered.push(comp);
        }
    }
    // Pass 2: lower each component.
    let mut items: Vec<Item> = lowered
        .into_iter()
        .filter_map(|comp| {
            let kind = c.kinds[&comp.name.to_string()];
            c.component(&comp.name, kind, &comp.ctor)
        })
        .collect();
    // Pass 3: algebraic loops among the blocks; where the `Scene` may be.
    c.algebraic_loops();
    c.scenes(def);
    crate::names::attach_roots(&mut items);
    let has_scene = !c.scene_spans.is_empty();
    let ir = Ir {
        items,
        kinds,
        path_checks: c.path_checks,
        has_scene,
    };
    (ir, c.errors)
}

pub(crate) struct Checker {
    pub(crate) errors: Errors,
    kinds: HashMap<String, Kind>,
    assembly_types: HashMap<String, syn::Path>,
    /// The constructor of each component, by name (a joint's or block's kind).
    ctors: HashMap<String, String>,
    /// Parameters of type `SignalRef` (signals of an outer model a block reads) and
    /// `JointRef` (joints of an outer model a `Drive` acts on).
    signal_params: HashSet<String>,
    /// See `signal_params`.
    joint_params: HashSet<String>,
    /// Blocks' reads of other blocks' feedthrough outputs (`blocks.rs`'s loop check).
    feedthrough_reads: Vec<blocks::FeedthroughRead>,
    /// The ports and signals of each block, for its variants (`blocks::block_ports`).
    block_ports: HashMap<String, crate::ir::BlockPorts>,
    params: HashSet<String>,
    path_checks: Vec<PathCheck>,
    /// Spans of the `Scene` constructors, and the span of the scene object's `parent` key.
    scene_spans: Vec<(Span, Option<Span>)>,
}

/// The arguments of one constructor, with the keys it accepts.
pub(crate) struct Args<'a> {
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

/// `[[a, b, c], [d, e, f], [g, h, i]]` with literal numbers.
fn lit_matrix(e: &Expr) -> Option<[[f64; 3]; 3]> {
    let Expr::Array(rows) = e else { return None };
    let mut m = [[0.0; 3]; 3];
    if rows.elems.len() != 3 {
        return None;
    }
    for (i, row) in rows.elems.iter().enumerate() {
        m[i] = lit_vec3(row)?;
    }
    Some(m)
}

/// `[x, y, z]` with literal numbers.
fn lit_vec3(e: &Expr) -> Option<[f64; 3]> {
    let Expr::Array(arr) = e else { return None };
    if arr.elems.len() != 3 {
        return None;
    }
    let mut v = [0.0; 3];
    for (i, el) in arr.elems.iter().enumerate() {
        v[i] = lit_f64(el)?;
    }
    Some(v)
}

/// The tokens of an expression as the user wrote them, without spaces (`-0.1`).
pub(crate) fn compact(e: &Expr) -> String {
    e.to_token_stream().to_string().replace(' ', "")
}

impl Checker {
    fn err(&mut self, span: Span, msg: impl std::fmt::Display) {
        self.errors.push(syn::Error::new(span, msg));
    }

    /// An error covering all of `tokens` (on stable, `span()` of a multi-token expression is
    /// only its first token).
    fn err_spanned(&mut self, tokens: impl ToTokens, msg: impl std::fmt::Display) {
        self.errors.push(syn::Error::new_spanned(tokens, msg));
    }

    fn is_param(&self, n: &str) -> bool {
        self.params.contains(n)
    }

    fn kind(&self, n: &str) -> Option<Kind> {
        self.kinds.get(n).copied()
    }

    /// Names of the block's components of kind `k`.
    fn names_of(&self, k: Kind) -> Vec<&str> {
        self.kinds
            .iter()
            .filter(|(_, kk)| **kk == k)
            .map(|(n, _)| n.as_str())
            .collect()
    }

    /// The kind a component constructor makes, or `None` (error reported) if unknown.
    fn kind_of(&mut self, ctor: &Ctor) -> Option<Kind> {
        if !ctor.is_single() {
            return Some(Kind::Assembly);
        }
        let n = ctor.name().to_string();
        if let Some(k) = Kind::of_builtin(&n) {
            return Some(k);
        }
        if is_nested(&n) {
            let h = nested_hint(&n);
            self.err(
                ctor.span(),
                format!("`{n}` is not a component on its own (hint: write {h})"),
            );
            return None;
        }
        match did_you_mean(&n, components()) {
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

    /// A required key whose value names an object (a joint's or an element's ends).
    fn required_object(&mut self, a: &Args<'_>, key: &str) -> Option<NameRef> {
        self.required(a, key)
            .and_then(|e| self.reference(e, Kind::Object, "object"))
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

    /// A number key, with its literal parts read out (their slots reserved now, so that the
    /// core's verdict on them sorts where the old per-key checks stood).
    fn num(&mut self, a: &Args, key: &'static str, required: bool) -> Option<Num> {
        let v = if required {
            self.required(a, key)
        } else {
            a.get(key)
        }?;
        Some(self.num_of(key, v))
    }

    fn num_of(&mut self, key: &'static str, e: &Expr) -> Num {
        let lit = |c: &mut Self, el: &Expr| {
            lit_f64(el).map(|value| LitNum {
                value,
                expr: el.clone(),
                slot: c.errors.slot(),
            })
        };
        let parts = match e {
            Expr::Array(arr) => arr.elems.iter().map(|el| lit(self, el)).collect(),
            _ => vec![lit(self, e)],
        };
        Num {
            key,
            expr: e.clone(),
            parts,
        }
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
                self.errors.push(err);
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
    fn component(&mut self, name: &Ident, kind: Kind, ctor: &Ctor) -> Option<Item> {
        match kind {
            Kind::Object => self.object(name, ctor),
            Kind::Joint => self.joint(name, ctor),
            Kind::Force => self.force(name, ctor),
            Kind::Material => {
                let a = self.args(ctor, &["density", "young_modulus", "poisson_ratio"]);
                let d = self.num(&a, "density", true);
                let e = self.num(&a, "young_modulus", true);
                let p = self.num(&a, "poisson_ratio", true);
                Some(Item::Material(MaterialIr {
                    name: name.clone(),
                    density: d?,
                    young_modulus: e?,
                    poisson_ratio: p?,
                }))
            }
            Kind::ContactPair => self.contact_pair(name, ctor),
            Kind::Input => self.input(name, ctor),
            Kind::Action => self.action(name, ctor),
            Kind::Block => self.block(name, ctor),
            Kind::Assembly => Some(self.assembly(name, ctor)),
        }
    }

    fn assembly(&mut self, name: &Ident, ctor: &Ctor) -> Item {
        let mut parent = Parent::Attach;
        let mut fields = vec![];
        let mut paths = vec![];
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
                    format!("`can_collide` is a key of joints, not of the sub-assembly `{name}`"),
                );
            } else if let Some(path) = self.path_argument(&a.value) {
                if let Some(path) = path {
                    paths.push((a.key.clone(), path));
                }
            } else {
                fields.push((a.key.clone(), a.value.clone()));
            }
        }
        Item::Assembly {
            name: name.clone(),
            ty: ctor.path.clone(),
            parent,
            fields,
            paths,
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
        let Some(kind) = self.kind(&fname) else {
            let cands: Vec<&str> = self
                .kinds
                .iter()
                .filter(|(_, k)| **k == want || **k == Kind::Assembly)
                .map(|(n, _)| n.as_str())
                .collect();
            let h = did_you_mean(&fname, cands.into_iter());
            self.err(first.span(), format!("unknown {role} `{fname}`{}", hint(h)));
            return None;
        };
        if segs.len() == 1 {
            if kind == Kind::Assembly {
                self.err(
                    first.span(),
                    format!(
                        "`{fname}` is a sub-assembly, not {} (hint: name one of its parts, like `{fname}.<name>`)",
                        want.article()
                    ),
                );
                return None;
            }
            if kind != want {
                self.err(
                    first.span(),
                    format!("`{fname}` is {}, not {}", kind.article(), want.article()),
                );
                return None;
            }
        } else {
            if kind != Kind::Assembly {
                self.err(
                    segs[1].span(),
                    format!(
                        "`{fname}` is {}, not a sub-assembly: only parts of sub-assemblies are reached by paths",
                        kind.article()
                    ),
                );
                return None;
            }
            self.path_checks.push(PathCheck {
                ty: self.assembly_types[&fname].clone(),
                rest: segs[1..].to_vec(),
                want: if want == Kind::Joint {
                    PathWant::Joint
                } else {
                    PathWant::Object
                },
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
}
