//! Check stage, blocks (`ramp = Ramp(height = 2.95, duration = 1.18)`, `pi = PI(k = k2, u =
//! …)`, `drive = Drive(joint = rev, …, tau = pi.y)`): keys against the core's table of block
//! kinds (`modia3d_core::BLOCK_KINDS`), a `Drive`'s joint and coordinate, and each input's
//! expression: the signal paths it reads (`ramp.y`, `rev.w`, `arm.pi.y`) resolved against the
//! block's blocks and joints (paths into sub-assemblies by rustc, as other references), and
//! the accelerations it reads (`der(rev.w)`: only of a joint coordinate's velocity), then
//! rewritten for a closure `|time, values| …`. Finally the algebraic loops: cycles of blocks
//! each reading another's output with direct feedthrough (an acceleration is none).

use super::{lit_str, Args, Checker};
use crate::ast::Ctor;
use crate::ir::{
    wire_locals, BlockIr, BlockPorts, Dep, Item, JointArg, PathCheck, PathWant, VariantIr, WireIr,
};
use crate::names::{did_you_mean, hint, path_segments, NameRef};
use crate::vocab::{block_kind, joint_kind, Kind};
use modia3d_core::{BlockKindSpec, BlockValue, BlockVariant};
use proc_macro2::{Ident, Span};
use std::collections::HashMap;
use syn::spanned::Spanned;
use syn::visit_mut::VisitMut;
use syn::Expr;

/// A same-instant read of a feedthrough output by a block that has one: an edge of the graph
/// whose cycles are algebraic loops.
#[derive(Clone, Debug)]
pub(crate) struct FeedthroughRead {
    /// The block whose output is read.
    from: String,
    /// The reading block.
    to: String,
    /// The path's tokens.
    span: Span,
}

/// Collects the signal paths and `der(…)` reads of an input expression and rewrites them to
/// `values[i]`, and `time` to the closure's time argument.
struct Rewriter<'a> {
    /// Whether a name starts a signal path (a component of the block, or an unknown name that
    /// is no parameter: reported as an unknown signal).
    is_root: &'a dyn Fn(&str) -> bool,
    /// Whether a name is a component of the block (a component used as a value is an error).
    is_component: &'a dyn Fn(&str) -> bool,
    /// Whether `time` is a parameter (then it is the parameter).
    time_is_param: bool,
    /// Parameters of type `SignalRef`: signals of the outer model.
    signal_params: &'a std::collections::HashSet<String>,
    /// Every occurrence of a path: its segments and its tokens.
    found: Vec<(Vec<Ident>, Expr)>,
    /// The distinct signals, in order of first use.
    paths: Vec<Dep>,
    /// Whether `time` was read.
    time: bool,
    /// Components used alone (`u = ramp`).
    lone: Vec<Ident>,
    /// Whether `der(…)` is the derivative (not when `der` is a parameter).
    der_is_call: bool,
    /// Every `der(path)`: the path's segments and tokens.
    ders: Vec<(Vec<Ident>, Expr)>,
    /// Calls of `der` whose argument is no path (`der(2.0 * rev.w)`, `der()`).
    bad_ders: Vec<Expr>,
}

/// `der(…)` in an input expression, unless `der` is a parameter of the block.
fn der_call(e: &Expr, der_is_call: bool) -> Option<&syn::ExprCall> {
    match e {
        Expr::Call(c) if der_is_call => match &*c.func {
            Expr::Path(p) if p.qself.is_none() && p.path.is_ident("der") => Some(c),
            _ => None,
        },
        _ => None,
    }
}

impl Rewriter<'_> {
    /// The index of signal `d` among the closure's values (added at first use).
    fn index(&mut self, d: Dep) -> syn::Index {
        let i = match self.paths.iter().position(|p| *p == d) {
            Some(i) => i,
            None => {
                self.paths.push(d);
                self.paths.len() - 1
            }
        };
        syn::Index::from(i)
    }
}

impl VisitMut for Rewriter<'_> {
    fn visit_expr_mut(&mut self, e: &mut Expr) {
        let (t, v) = wire_locals();
        // `der(rev.w)`: the acceleration, a signal of its own (a derivative read, no path).
        if let Some(c) = der_call(e, self.der_is_call) {
            let mut segs = vec![];
            if c.args.len() == 1 && path_segments(&c.args[0], &mut segs) {
                let path = segs
                    .iter()
                    .map(Ident::to_string)
                    .collect::<Vec<_>>()
                    .join(".");
                let arg = c.args[0].clone();
                let i = self.index(Dep::Der(path));
                self.ders.push((segs, arg));
                let span = e.span();
                *e = syn::parse_quote_spanned!(span=> #v[#i]);
            } else {
                self.bad_ders.push(e.clone());
            }
            return;
        }
        if let Expr::Field(_) = e {
            let mut segs = vec![];
            if path_segments(e, &mut segs) && (self.is_root)(&segs[0].to_string()) {
                let path = segs
                    .iter()
                    .map(Ident::to_string)
                    .collect::<Vec<_>>()
                    .join(".");
                let i = self.index(Dep::Path(path));
                self.found.push((segs, e.clone()));
                let span = e.span();
                *e = syn::parse_quote_spanned!(span=> #v[#i]);
                return;
            }
        }
        if let Expr::Path(p) = e {
            if let (None, Some(id)) = (&p.qself, p.path.get_ident()) {
                let n = id.to_string();
                if self.signal_params.contains(&n) {
                    let i = self.index(Dep::Param(id.clone()));
                    let span = id.span();
                    *e = syn::parse_quote_spanned!(span=> #v[#i]);
                    return;
                }
                if n == "time" && !self.time_is_param {
                    self.time = true;
                    let span = id.span();
                    *e = syn::parse_quote_spanned!(span=> #t);
                    return;
                }
                if (self.is_component)(&n) {
                    self.lone.push(id.clone());
                }
            }
        }
        syn::visit_mut::visit_expr_mut(self, e);
    }
}

/// The ports of a block of kind `spec` as written in `ctor`: with the variants its
/// enum-valued keys name (`gear = Elastic(…)`; an unknown one counts as the default, reported
/// when the block is lowered).
pub(super) fn block_ports(spec: &BlockKindSpec, ctor: &Ctor) -> BlockPorts {
    let uncertain = std::cell::Cell::new(false);
    let chosen = |key: &str| -> Option<&'static str> {
        let p = spec.param(key)?;
        let arg = ctor.args.iter().find(|a| a.key == key)?;
        let vs = match p.value {
            BlockValue::Variant(vs) => vs,
            // A block kind by its constructor's name (a `Sampled` block's `inner`).
            BlockValue::Block => {
                let k = match &arg.value {
                    Expr::Call(c) => match &*c.func {
                        Expr::Path(p) => {
                            p.path.get_ident().and_then(|i| block_kind(&i.to_string()))
                        }
                        _ => None,
                    },
                    _ => None,
                };
                uncertain.set(uncertain.get() || k.is_none());
                return k.map(|k| k.name);
            }
            _ => return None,
        };
        let name = match &arg.value {
            Expr::Call(c) => match &*c.func {
                Expr::Path(p) => p.path.get_ident().map(Ident::to_string),
                _ => None,
            },
            Expr::Path(p) => p.path.get_ident().map(Ident::to_string),
            _ => None,
        };
        let v = vs.iter().find(|v| Some(v.name) == name.as_deref());
        uncertain.set(uncertain.get() || v.is_none());
        v.map(|v| v.name)
    };
    let b = (spec.example)(&chosen);
    BlockPorts {
        inputs: b.inputs().into_iter().map(|p| p.name).collect(),
        outputs: b
            .outputs()
            .into_iter()
            .map(|o| (o.name, o.feedthrough))
            .collect(),
        states: b
            .states()
            .into_iter()
            .chain(b.discrete_states())
            .map(|x| x.name)
            .collect(),
        uncertain: uncertain.get(),
    }
}

impl Checker {
    /// A value parameter `p` of a block from its arguments `a` into `params`: required unless
    /// it has a default (a missing required one is reported). Whether it is all right.
    fn value_param(
        &mut self,
        a: &Args<'_>,
        p: &modia3d_core::BlockParam,
        params: &mut Vec<(&'static str, syn::Expr)>,
    ) -> bool {
        let v = match p.default {
            None => self.required(a, p.key),
            Some(_) => a.get(p.key),
        };
        match v {
            Some(v) => {
                params.push((p.key, v.clone()));
                true
            }
            None => p.default.is_some(),
        }
    }

    /// The row of the joint named `name` in this block, if it is one of its joints.
    fn local_joint(&self, name: &str) -> Option<&'static modia3d_core::JointKindSpec> {
        (self.kind(name) == Some(Kind::Joint))
            .then(|| self.ctors.get(name).and_then(|c| joint_kind(c)))
            .flatten()
    }

    /// The row of the block named `name` in this block, if it is one of its blocks.
    fn local_block(&self, name: &str) -> Option<&'static BlockKindSpec> {
        (self.kind(name) == Some(Kind::Block))
            .then(|| self.ctors.get(name).and_then(|c| block_kind(c)))
            .flatten()
    }

    /// The signals the block named `name` offers: outputs, then states.
    fn block_signals(&self, name: &str) -> Vec<String> {
        self.block_ports
            .get(name)
            .map(|p| p.signals().into_iter().map(String::from).collect())
            .unwrap_or_default()
    }

    /// Every signal path of this block's own blocks and joints, and `time` (for hints).
    fn signal_paths(&self) -> Vec<String> {
        let mut all = vec!["time".to_string()];
        let mut names: Vec<&String> = self.kinds.keys().collect();
        names.sort();
        for n in names {
            if self.local_block(n).is_some() {
                all.extend(self.block_signals(n).iter().map(|s| format!("{n}.{s}")));
            } else if let Some(spec) = self.local_joint(n) {
                for (p, v) in spec.coordinate_signals() {
                    all.push(format!("{n}.{p}"));
                    all.push(format!("{n}.{v}"));
                }
            }
        }
        all
    }

    /// Lowers a block: its parameters, a `Drive`'s joint, and each input's source.
    pub(super) fn block(&mut self, name: &Ident, ctor: &Ctor) -> Option<Item> {
        let spec = block_kind(&ctor.name().to_string())?;
        let ports = self
            .block_ports
            .get(&name.to_string())
            .cloned()
            .unwrap_or_default();
        let written: Vec<String> = ctor.args.iter().map(|a| a.key.to_string()).collect();
        let keys: Vec<&str> = spec
            .params
            .iter()
            .map(|p| p.key)
            .chain(ports.inputs.iter().map(String::as_str))
            .chain(
                written
                    .iter()
                    .map(String::as_str)
                    .filter(|_| ports.uncertain),
            )
            .collect();
        let a = self.args(ctor, &keys);
        let mut ok = true;
        let mut params = vec![];
        let mut variants = vec![];
        let mut inner = None;
        let (mut joint, mut coordinate) = (None, None);
        for p in spec.params {
            match p.value {
                BlockValue::Joint => {
                    joint = self.required(&a, p.key).and_then(|e| {
                        let param = match e {
                            Expr::Path(p) => p
                                .path
                                .get_ident()
                                .filter(|i| self.joint_params.contains(&i.to_string())),
                            _ => None,
                        };
                        match param {
                            Some(id) => Some(JointArg::Param(id.clone())),
                            None => self.reference(e, Kind::Joint, "joint").map(JointArg::Ref),
                        }
                    });
                    ok &= joint.is_some();
                }
                BlockValue::Coordinate => coordinate = a.get(p.key).cloned(),
                BlockValue::Variant(vs) => {
                    if let Some(e) = a.get(p.key) {
                        match self.variant(spec, p.key, vs, e) {
                            Some(v) => variants.push(v),
                            None => ok = false,
                        }
                    }
                }
                BlockValue::Block => match self.required(&a, p.key) {
                    Some(e) => {
                        inner = self.inner_block(spec, e).map(Box::new);
                        ok &= inner.is_some();
                    }
                    None => ok = false,
                },
                BlockValue::Number | BlockValue::Numbers | BlockValue::Rows | BlockValue::Pairs => {
                    ok &= self.value_param(&a, p, &mut params);
                }
            }
        }
        if let Some(JointArg::Ref(j)) = &joint {
            self.flange(spec, j, coordinate.as_ref(), &a);
        }
        let mut inputs = vec![];
        for port in &ports.inputs {
            let port = port.as_str();
            let Some(e) = a.get(port) else {
                if !a.suggested.iter().any(|s| s == port) && !ports.uncertain {
                    self.err(
                        a.span,
                        format!(
                            "missing input `{port}` of `{}(…)` (hint: `{port} = …`, an expression over parameters, `time` and signals such as `ramp.y` or `rev.phi`)",
                            spec.name
                        ),
                    );
                }
                ok = false;
                continue;
            };
            let reads_through = ports.outputs.iter().any(|(_, ft)| *ft);
            match self.wire(name, reads_through, e) {
                Some(w) => inputs.push((port.to_string(), w)),
                None => ok = false,
            }
        }
        ok.then(|| {
            Item::Block(BlockIr {
                name: name.clone(),
                spec,
                params,
                joint,
                coordinate,
                variants,
                inner,
                ports,
                inputs,
            })
        })
    }

    /// A sub-assembly's parameter given a path of this block: a signal (`ramp.y`, `rev.w`,
    /// `arm.pi.y`), `time`, or a joint (`rev`, `arm.rev`), for a `SignalRef` or `JointRef`
    /// parameter. `None`: not such a path (a Rust value); `Some(None)`: a wrong path (reported).
    /// Paths into sub-assemblies are left to `build()` (a signal or a joint: the parameter's
    /// type decides).
    pub(super) fn path_argument(&mut self, e: &Expr) -> Option<Option<String>> {
        let mut segs = vec![];
        if !path_segments(e, &mut segs) {
            return None;
        }
        let root = segs[0].to_string();
        if self.params.contains(&root) {
            return None;
        }
        if segs.len() == 1 && root == "time" {
            return Some(Some(root));
        }
        let kind = self.kind(&root)?;
        let path = segs
            .iter()
            .map(Ident::to_string)
            .collect::<Vec<_>>()
            .join(".");
        let ok = match (kind, segs.len()) {
            (Kind::Joint, 1) | (Kind::Assembly, 2..) => true,
            (Kind::Block | Kind::Joint, 2..) => {
                let reader = Ident::new("__modia3d_outer", Span::call_site());
                self.signal(&reader, false, &segs, e)
            }
            (Kind::Assembly, _) => {
                self.err(
                    segs[0].span(),
                    format!("`{root}` is a sub-assembly: a parameter takes one of its signals (`{root}.<block>.y`) or joints (`{root}.<joint>`)"),
                );
                false
            }
            (k, _) => {
                self.err(
                    segs[0].span(),
                    format!(
                        "`{root}` is {}: a sub-assembly's parameter takes a signal (`ramp.y`, `rev.phi`) or a joint (`rev`) of this block",
                        k.article()
                    ),
                );
                false
            }
        };
        Some(ok.then_some(path))
    }

    /// A `Sampled` block's `inner = PI(k = …, T = …)`: a block kind with continuous states
    /// and outputs only, its parameters (its inputs are the outer block's keys).
    fn inner_block(&mut self, outer: &BlockKindSpec, e: &Expr) -> Option<BlockIr> {
        let names: Vec<&str> = modia3d_core::BLOCK_KINDS.iter().map(|k| k.name).collect();
        let vc = match self.nested(e, &names, "block") {
            Ok(Some(vc)) => vc,
            Ok(None) => return None,
            Err(e) => {
                self.err_spanned(
                    e,
                    format!(
                        "`inner` of `{}(…)` takes a block, like `PI(k = …, T = …)` (its inputs are keys of `{}(…)`)",
                        outer.name, outer.name
                    ),
                );
                return None;
            }
        };
        let spec = block_kind(&vc.name().to_string())?;
        let plain = |v: BlockValue| {
            matches!(
                v,
                BlockValue::Number | BlockValue::Numbers | BlockValue::Rows | BlockValue::Pairs
            )
        };
        if !spec.params.iter().all(|p| plain(p.value)) || !spec.discrete_states.is_empty() {
            self.err(
                vc.span(),
                format!(
                    "`{}` cannot be sampled: a sampled block has continuous states and outputs only, no flange, discrete state or zero crossing (hint: sample a `PI`, `PID`, `FirstOrder` or `Gain`)",
                    spec.name
                ),
            );
            return None;
        }
        let keys: Vec<&str> = spec.params.iter().map(|p| p.key).collect();
        let a = self.args(&vc, &keys);
        let mut params = vec![];
        let mut ok = true;
        for p in spec.params {
            ok &= self.value_param(&a, p, &mut params);
        }
        ok.then(|| BlockIr {
            name: vc.name().clone(),
            spec,
            params,
            joint: None,
            coordinate: None,
            variants: vec![],
            inner: None,
            ports: BlockPorts::default(),
            inputs: vec![],
        })
    }

    /// `key = Variant(field = …, …)` or a bare `Variant` of an enum-valued parameter.
    fn variant(
        &mut self,
        spec: &BlockKindSpec,
        key: &'static str,
        vs: &'static [BlockVariant],
        e: &Expr,
    ) -> Option<VariantIr> {
        let names: Vec<&str> = vs.iter().map(|v| v.name).collect();
        let written = |v: &BlockVariant| {
            if v.fields.is_empty() {
                format!("`{}`", v.name)
            } else {
                let f: Vec<String> = v.fields.iter().map(|f| format!("{f} = …")).collect();
                format!("`{}({})`", v.name, f.join(", "))
            }
        };
        let list = vs.iter().map(written).collect::<Vec<_>>().join(" or ");
        let vc = match self.nested(e, &names, key) {
            Ok(Some(vc)) => vc,
            Ok(None) => return None,
            Err(e) => {
                self.err_spanned(e, format!("`{key}` of `{}(…)` takes {list}", spec.name));
                return None;
            }
        };
        let variant = vs.iter().find(|v| *vc.name() == v.name)?;
        let a = self.args(&vc, variant.fields);
        let mut fields = vec![];
        for f in variant.fields {
            fields.push((*f, self.required(&a, f)?.clone()));
        }
        Some(VariantIr {
            key,
            variant,
            fields,
        })
    }

    /// A flange on joint `j`'s coordinate: a joint of this block must have a scalar
    /// coordinate, the one named by a literal `coordinate`, or only one when none is named.
    fn flange(&mut self, spec: &BlockKindSpec, j: &NameRef, coordinate: Option<&Expr>, a: &Args) {
        if !j.local {
            return; // a joint of a sub-assembly: build() checks it
        }
        let Some(kind) = self.local_joint(&j.path) else {
            return;
        };
        let coords: Vec<&str> = kind.coordinates.iter().map(|c| c.name).collect();
        let list = coords
            .iter()
            .map(|c| format!("`{c}`"))
            .collect::<Vec<_>>()
            .join(", ");
        if coords.is_empty() {
            self.err(
                j.span,
                format!(
                    "`{}` is a {} joint: it has no scalar coordinate for the flange of `{}(…)` (hint: drive a Revolute, Prismatic, Cylindrical, Universal or Planar joint)",
                    j.path, kind.name, spec.name
                ),
            );
            return;
        }
        match coordinate {
            Some(e) => {
                if let Some(c) = lit_str(e) {
                    if !coords.contains(&c.as_str()) {
                        let h = did_you_mean(&c, coords.iter().copied());
                        let h = match h {
                            Some(h) => format!(" (hint: did you mean `\"{h}\"`?)"),
                            None => String::new(),
                        };
                        self.err(
                            e.span(),
                            format!(
                                "a {} joint has no coordinate `{c}`: its coordinates are {list}{h}",
                                kind.name
                            ),
                        );
                    }
                }
            }
            None if coords.len() > 1 => self.err(
                a.span,
                format!(
                    "`{}` is a {} joint with several coordinates ({list}): say which one `{}(…)` drives (hint: `coordinate = \"{}\"`)",
                    j.path, kind.name, spec.name, coords[0]
                ),
            ),
            None => {}
        }
    }

    /// The source of an input port of block `reader`: its signal paths resolved, the
    /// expression rewritten.
    fn wire(&mut self, reader: &Ident, reads_through: bool, e: &Expr) -> Option<WireIr> {
        // A lone path or `time`: a signal.
        let mut segs = vec![];
        let mut expr = e.clone();
        let kinds = &self.kinds;
        let params = &self.params;
        let is_component = |n: &str| kinds.contains_key(n) && !params.contains(n);
        let is_root = |n: &str| {
            !params.contains(n)
                && (kinds.contains_key(n) || n.chars().next().is_some_and(|c| c.is_lowercase()))
        };
        let mut rw = Rewriter {
            is_root: &is_root,
            is_component: &is_component,
            time_is_param: params.contains("time"),
            signal_params: &self.signal_params,
            found: vec![],
            paths: vec![],
            time: false,
            lone: vec![],
            der_is_call: !params.contains("der"),
            ders: vec![],
            bad_ders: vec![],
        };
        rw.visit_expr_mut(&mut expr);
        let der_is_call = rw.der_is_call;
        let (found, paths, time, lone) = (rw.found, rw.paths, rw.time, rw.lone);
        let (ders, bad_ders) = (rw.ders, rw.bad_ders);
        let mut ok = true;
        for call in bad_ders {
            self.err_spanned(
                call,
                "`der(…)` takes one path, a joint coordinate's velocity, and reads its acceleration (hint: `der(rev.w)`)",
            );
            ok = false;
        }
        // A derivative read is no feedthrough edge: accelerations come from the solver.
        for (segs, tokens) in &ders {
            ok &= self.der_signal(segs, tokens);
        }
        for id in lone {
            let n = id.to_string();
            let what = self.kind(&n).map_or("a component", |k| k.article());
            let signals: Vec<String> = match self.local_block(&n) {
                Some(_) => self.block_signals(&n),
                None => self
                    .local_joint(&n)
                    .map(|s| {
                        s.coordinate_signals()
                            .flat_map(|(p, v)| [p.to_string(), v.to_string()])
                            .collect()
                    })
                    .unwrap_or_default(),
            };
            let h = match signals.first() {
                Some(s) => format!(" (hint: `{n}.{s}`)"),
                None => String::new(),
            };
            self.err(
                id.span(),
                format!("`{n}` is {what}, not a signal: an input reads a signal by its path{h}"),
            );
            ok = false;
        }
        for (segs, tokens) in &found {
            ok &= self.signal(reader, reads_through, segs, tokens);
        }
        if !ok {
            return None;
        }
        path_segments(e, &mut segs);
        let lone_path = paths.len() == 1
            && (segs.len() > 1 && found.len() == 1
                || segs.len() == 1 && matches!(paths[0], Dep::Param(_)));
        let lone_der = paths.len() == 1 && ders.len() == 1 && der_call(e, der_is_call).is_some();
        Some(if lone_path || lone_der {
            WireIr::Signal(paths[0].clone())
        } else if paths.is_empty() && !time {
            WireIr::Const(e.clone())
        } else if matches!(e, Expr::Path(p) if p.path.is_ident("time")) && time {
            WireIr::Signal(Dep::Path("time".into()))
        } else {
            WireIr::Expr { deps: paths, expr }
        })
    }

    /// Resolves one signal path read by block `reader`; records a read of a feedthrough
    /// output for the loop check. False after an error.
    fn signal(
        &mut self,
        reader: &Ident,
        reads_through: bool,
        segs: &[Ident],
        tokens: &Expr,
    ) -> bool {
        let root = segs[0].to_string();
        let path = segs
            .iter()
            .map(Ident::to_string)
            .collect::<Vec<_>>()
            .join(".");
        let Some(kind) = self.kind(&root) else {
            let all = self.signal_paths();
            let h = did_you_mean(&path, all.iter().map(String::as_str));
            self.err_spanned(tokens, format!("unknown signal `{path}`{}", hint(h)));
            return false;
        };
        let field = &segs[1];
        let f = field.to_string();
        match kind {
            Kind::Assembly => {
                self.path_checks.push(PathCheck {
                    ty: self.assembly_types[&root].clone(),
                    rest: segs[1..].to_vec(),
                    want: PathWant::Signal,
                });
                true
            }
            Kind::Block => {
                let Some(spec) = self.local_block(&root) else {
                    return false;
                };
                let signals = self.block_signals(&root);
                let signals: Vec<&str> = signals.iter().map(String::as_str).collect();
                let numbered = |s: &str| {
                    spec.numbered_outputs
                        && spec.outputs.iter().any(|o| {
                            s.strip_prefix(o.name).is_some_and(|n| {
                                !n.is_empty() && n.bytes().all(|b| b.is_ascii_digit())
                            })
                        })
                };
                if segs.len() > 2 || !(signals.contains(&f.as_str()) || numbered(&f)) {
                    let list = signals
                        .iter()
                        .map(|s| format!("`{s}`"))
                        .collect::<Vec<_>>()
                        .join(", ");
                    let h = did_you_mean(&f, signals.iter().copied());
                    let (span, what) = if segs.len() > 2 && signals.contains(&f.as_str()) {
                        (
                            segs[2].span(),
                            format!("`{root}.{f}` is a signal, not a path"),
                        )
                    } else {
                        (
                            field.span(),
                            format!("`{root}` ({}) has no signal `{f}`", spec.name),
                        )
                    };
                    self.err(span, format!("{what}: its signals are {list}{}", hint(h)));
                    return false;
                }
                let through = self
                    .block_ports
                    .get(&root)
                    .and_then(|p| p.outputs.iter().find(|(o, _)| *o == f))
                    .is_some_and(|(_, ft)| *ft);
                if through && reads_through {
                    self.feedthrough_reads.push(FeedthroughRead {
                        from: root,
                        to: reader.to_string(),
                        span: tokens.span(),
                    });
                }
                true
            }
            Kind::Joint => {
                let Some(spec) = self.local_joint(&root) else {
                    return false;
                };
                let signals: Vec<&str> = spec
                    .coordinate_signals()
                    .flat_map(|(p, v)| [p, v])
                    .collect();
                if segs.len() == 2 && signals.contains(&f.as_str()) {
                    return true;
                }
                let msg = if signals.is_empty() {
                    format!(
                        "`{root}` is a {} joint: it has no scalar coordinate whose position or velocity a block can read",
                        spec.name
                    )
                } else {
                    let list = signals
                        .iter()
                        .map(|s| format!("`{s}`"))
                        .collect::<Vec<_>>()
                        .join(", ");
                    let h = did_you_mean(&f, signals.iter().copied());
                    format!(
                        "`{root}` ({}) has no signal `{f}` a block can read: its coordinates' signals are {list}{}",
                        spec.name,
                        hint(h)
                    )
                };
                self.err(field.span(), msg);
                false
            }
            other => {
                self.err(
                    segs[0].span(),
                    format!(
                        "`{root}` is {}: a block reads signals of blocks (`pi.y`), joints' coordinates (`rev.phi`, `rev.w`) and `time`",
                        other.article()
                    ),
                );
                false
            }
        }
    }

    /// The velocities of this block's joints' coordinates (`rev.w`), what `der(…)` takes.
    fn velocity_paths(&self) -> Vec<String> {
        let mut names: Vec<&String> = self.kinds.keys().collect();
        names.sort();
        let mut all = vec![];
        for n in names {
            if let Some(spec) = self.local_joint(n) {
                all.extend(
                    spec.coordinate_signals()
                        .filter(|(_, v)| !v.is_empty())
                        .map(|(_, v)| format!("{n}.{v}")),
                );
            }
        }
        all
    }

    /// Resolves the path of a `der(path)` read: a joint coordinate's velocity (`rev.w`), or a
    /// path into a sub-assembly (a velocity there, checked by rustc). False after an error.
    fn der_signal(&mut self, segs: &[Ident], tokens: &Expr) -> bool {
        let root = segs[0].to_string();
        let path = segs
            .iter()
            .map(Ident::to_string)
            .collect::<Vec<_>>()
            .join(".");
        let velocities = self.velocity_paths();
        let listed = |vs: &[String]| {
            vs.iter()
                .map(|s| format!("`{s}`"))
                .collect::<Vec<_>>()
                .join(", ")
        };
        // For a path that is no joint's: the velocities there are.
        let h = if velocities.is_empty() {
            String::new()
        } else {
            format!(
                " (hint: this block's joint velocities are {})",
                listed(&velocities)
            )
        };
        if self.is_param(&root) {
            self.err_spanned(
                tokens,
                format!("`{root}` is a parameter: `der(…)` reads the acceleration of a joint coordinate's velocity{h}"),
            );
            return false;
        }
        match self.kind(&root) {
            None => {
                let h = did_you_mean(&path, velocities.iter().map(String::as_str));
                self.err_spanned(
                    tokens,
                    format!("unknown joint velocity `{path}` in `der(…)`{}", hint(h)),
                );
                false
            }
            Some(Kind::Assembly) if segs.len() > 2 => {
                self.path_checks.push(PathCheck {
                    ty: self.assembly_types[&root].clone(),
                    rest: segs[1..].to_vec(),
                    want: PathWant::Velocity,
                });
                true
            }
            Some(Kind::Joint) => {
                let Some(spec) = self.local_joint(&root) else {
                    return false;
                };
                let coords: Vec<(&str, &str)> = spec.coordinate_signals().collect();
                let own: Vec<String> = coords
                    .iter()
                    .filter(|(_, v)| !v.is_empty())
                    .map(|(_, v)| format!("{root}.{v}"))
                    .collect();
                let f = segs.get(1).map(Ident::to_string);
                if segs.len() == 2 && own.contains(&path) {
                    return true;
                }
                let position = coords.iter().find(|(p, _)| Some(*p) == f.as_deref());
                let (span, msg) = match (segs.len(), position) {
                    (2, Some((p, v))) if !v.is_empty() => (
                        segs[1].span(),
                        format!(
                            "`{path}` is a position, not a velocity: `der(…)` reads the acceleration of a joint coordinate's velocity (hint: `{root}.{v}` is the velocity of `{p}`, `der({root}.{v})` its acceleration)"
                        ),
                    ),
                    _ if own.is_empty() => (
                        segs[0].span(),
                        format!(
                            "`{root}` is a {} joint: it has no scalar coordinate whose acceleration `der(…)` can read",
                            spec.name
                        ),
                    ),
                    (1, _) => (
                        segs[0].span(),
                        format!(
                            "`{root}` is a joint: `der(…)` takes one of its coordinates' velocities, {} (hint: `der({})`)",
                            listed(&own),
                            own[0]
                        ),
                    ),
                    _ => {
                        let rest: Vec<String> =
                            own.iter().map(|s| s[root.len() + 1..].to_string()).collect();
                        let h = did_you_mean(
                            &segs[1..]
                                .iter()
                                .map(Ident::to_string)
                                .collect::<Vec<_>>()
                                .join("."),
                            rest.iter().map(String::as_str),
                        );
                        (
                            segs[1].span(),
                            format!(
                                "`{root}` ({}) has no velocity `{}` whose acceleration `der(…)` can read: its coordinates' velocities are {}{}",
                                spec.name,
                                &path[root.len() + 1..],
                                listed(&rest),
                                hint(h)
                            ),
                        )
                    }
                };
                self.err(span, msg);
                false
            }
            Some(k) => {
                let what = match k {
                    Kind::Block => format!("`{root}` is a block: `der(…)` does not differentiate a block's output or state; it reads the acceleration of a joint coordinate's velocity"),
                    k => format!("`{root}` is {}: `der(…)` reads the acceleration of a joint coordinate's velocity", k.article()),
                };
                self.err_spanned(tokens, format!("{what}{h}"));
                false
            }
        }
    }

    /// Algebraic loops: a cycle of blocks, each reading another's feedthrough output (and
    /// having one itself). Each cycle is reported once, on the path that closes it.
    pub(super) fn algebraic_loops(&mut self) {
        let reads = std::mem::take(&mut self.feedthrough_reads);
        let mut succ: HashMap<&str, Vec<&FeedthroughRead>> = HashMap::new();
        for r in &reads {
            succ.entry(r.from.as_str()).or_default().push(r);
        }
        let mut nodes: Vec<&str> = succ.keys().copied().collect();
        nodes.sort_unstable();
        // Depth-first search; 0 unvisited, 1 on the stack, 2 done.
        let mut state: HashMap<&str, u8> = HashMap::new();
        let mut errors = vec![];
        for start in nodes {
            if state.get(start).copied().unwrap_or(0) != 0 {
                continue;
            }
            let mut stack: Vec<(&str, usize)> = vec![(start, 0)];
            let mut trail: Vec<&FeedthroughRead> = vec![];
            state.insert(start, 1);
            while let Some((n, i)) = stack.pop() {
                let out = succ.get(n).map_or(&[][..], Vec::as_slice);
                if i < out.len() {
                    stack.push((n, i + 1));
                    let r = out[i];
                    match state.get(r.to.as_str()).copied().unwrap_or(0) {
                        0 => {
                            state.insert(r.to.as_str(), 1);
                            trail.push(r);
                            stack.push((r.to.as_str(), 0));
                        }
                        1 => {
                            // A cycle: the trail from `r.to` back to here, closed by `r`.
                            let from = trail
                                .iter()
                                .position(|t| t.from == r.to)
                                .unwrap_or(trail.len());
                            let mut cycle: Vec<&str> =
                                trail[from..].iter().map(|t| t.from.as_str()).collect();
                            cycle.push(r.from.as_str());
                            cycle.push(r.to.as_str());
                            let shown = cycle
                                .iter()
                                .map(|c| format!("`{c}`"))
                                .collect::<Vec<_>>()
                                .join(" → ");
                            errors.push((
                                r.span,
                                format!(
                                    "algebraic loop: {shown} — each reads the other's output at the same instant (direct feedthrough) and none has a state in the loop (hint: break it with a block that has one, such as `FirstOrder`, `Integrator` or `Sampled`, or read a signal that does not depend on the input)"
                                ),
                            ));
                        }
                        _ => {}
                    }
                } else {
                    state.insert(n, 2);
                    if trail.last().is_some_and(|t| t.to == n) {
                        trail.pop();
                    }
                }
            }
        }
        for (span, msg) in errors {
            self.err(span, msg);
        }
    }
}
