//! Expand stage, components: each IR item → the builder calls that add it to the scene
//! (`scene.add(Object3D::new(…)…)`, `scene.add_joint(…)`, …), with the user's expressions
//! spliced in on their own spans so rustc reports type errors there.

use super::{local, paths_module_at, prefix, scoped};
use crate::ir::{
    shape_arg, wire_locals, ActionIr, AxisIr, BlockIr, ContactPairIr, Dep, FeatureIr, ForceIr,
    InputIr, Item, JointArg, JointAxis, JointIr, JointKindIr, MassIr, MaterialIr, MaterialName,
    Num, ObjectIr, Parent, PathCheck, PathWant, Profile, SceneIr, ShapeArg, ShapeIr, SolidIr,
    SpringDamperIr, WireIr,
};
use modia3d_core::{BlockValue, ParamValue, ShapeValue};
use proc_macro2::Ident;
use proc_macro2::TokenStream;
use quote::{format_ident, quote, quote_spanned};
use syn::Expr;

/// The statement that adds one component to the scene (`params`: the model's parameters,
/// which a block's input closures clone).
pub(super) fn item(it: &Item, params: &[&Ident]) -> TokenStream {
    let scene = local("scene");
    let attach = local("parent");
    let obj = local("object");
    let p = local("p");
    let core = quote!(::modia3d::core);
    match it {
        Item::Material(MaterialIr {
            name,
            density,
            young_modulus,
            poisson_ratio,
        }) => {
            let n = scoped(&name.to_string());
            let (d, e, nu) = (&density.expr, &young_modulus.expr, &poisson_ratio.expr);
            quote! {
                #scene.add_solid_material(#n, ::modia3d::core::SolidMaterial {
                    density: #d,
                    young_modulus: #e,
                    poisson_ratio: #nu,
                });
            }
        }
        Item::Object(ObjectIr {
            name,
            parent,
            translation,
            rotation,
            feature,
            ..
        }) => {
            let n = scoped(&name.to_string());
            let t = translation.as_ref().map(|t| quote!(.translation(#t)));
            let r = rotation
                .as_ref()
                .map(|r| quote!(.rotation(::modia3d::__private::rotation(#r))));
            let f = feature.as_ref().map(|f| {
                let f = self::feature(f);
                quote!(.feature(#f))
            });
            let base = quote!(#core::Object3D::new(#n) #t #r #f);
            match parent {
                Parent::None => quote!(#scene.add(#base);),
                Parent::Ref(r) => {
                    let p = scoped(&r.path);
                    quote!(#scene.add(#base.parent(#p));)
                }
                Parent::Attach => quote! {
                    let #obj = #base;
                    #scene.add(match #attach {
                        ::core::option::Option::Some(#p) => #obj.parent(#p),
                        ::core::option::Option::None => #obj,
                    });
                },
            }
        }
        Item::Input { name, input, .. } => {
            let n = scoped(&name.to_string());
            let i = quote!(::modia3d::core::Input);
            let v = match input {
                InputIr::ObjectWrench(o) => {
                    let o = scoped(&o.path);
                    quote!(#i::object_wrench(#n, #o))
                }
                InputIr::JointForce(j, c) | InputIr::JointAcceleration(j, c) => {
                    let j = scoped(&j.path);
                    let f = if matches!(input, InputIr::JointForce(..)) {
                        quote!(joint_force)
                    } else {
                        quote!(joint_acceleration)
                    };
                    let c = c.as_ref().map(|(e, _)| quote!(.coordinate(#e)));
                    quote!(#i::#f(#n, #j) #c)
                }
            };
            quote!(#scene.add_input(#v);)
        }
        Item::Action {
            name, at, action, ..
        } => {
            let n = scoped(&name.to_string());
            let a = quote!(#core::Action);
            let at = &at.expr;
            let v = match action {
                ActionIr::Attach { object, to, gap } => {
                    let (o, to, gap) = (scoped(&object.path), scoped(&to.path), &gap.expr);
                    quote!(#a::attach(#n, #at, #o, #to, #gap))
                }
                ActionIr::Release(o) => {
                    let o = scoped(&o.path);
                    quote!(#a::release(#n, #at, #o))
                }
                ActionIr::Delete(o) => {
                    let o = scoped(&o.path);
                    quote!(#a::delete(#n, #at, #o))
                }
            };
            quote!(#scene.add_action(#v);)
        }
        Item::ContactPair(ContactPairIr {
            material1,
            material2,
            cor,
            mu_k,
            mu_r,
            v_min,
            w_min,
            ..
        }) => {
            let (m1, m2) = (pair_material(material1), pair_material(material2));
            let (cor, mu_k, mu_r) = (&cor.expr, &mu_k.expr, &mu_r.expr);
            let private = quote!(::modia3d::__private);
            let v = v_min.as_ref().map(|v| {
                let v = &v.expr;
                quote!(__modia3d_pair.v_min = #private::optional_f64(#v);)
            });
            let w = w_min.as_ref().map(|w| {
                let w = &w.expr;
                quote!(__modia3d_pair.w_min = #private::optional_f64(#w);)
            });
            quote! {
                #scene.add_contact_pair(#m1, #m2, {
                    #[allow(unused_mut)]
                    let mut __modia3d_pair = ::modia3d::core::ContactPairMaterial::new(#cor, #mu_k, #mu_r);
                    #v
                    #w
                    __modia3d_pair
                });
            }
        }
        Item::Joint(JointIr {
            name,
            obj1,
            obj2,
            kind,
            can_collide,
            cut,
            limits,
        }) => {
            let (n, o1, o2) = (
                scoped(&name.to_string()),
                scoped(&obj1.path),
                scoped(&obj2.path),
            );
            let kind = joint_kind(kind);
            let c = can_collide.as_ref().map(|(c, _)| quote!(.can_collide(#c)));
            let cut = cut.as_ref().map(|(c, _)| quote!(.cut(#c)));
            let limits = limits.iter().map(|l| {
                let (coord, lo, hi) = (l.coordinate, &l.lower, &l.upper);
                let k = l.stiffness.as_ref().map(|k| quote!(.stiffness(#k)));
                let e = l.cor.as_ref().map(|e| quote!(.cor(#e)));
                quote!(.limit(#core::JointLimit::range(#lo, #hi).on(#coord) #k #e))
            });
            quote!(#scene.add_joint(#core::Joint::new(#n, #o1, #o2, #kind) #c #cut #(#limits)*);)
        }
        Item::Force { name, force, .. } => {
            let v = self::force(&name.to_string(), force);
            quote!(#scene.add_force(#v);)
        }
        Item::Assembly {
            name,
            ty,
            parent,
            fields,
            paths,
        } => assembly(name, ty, parent, fields, paths),
        Item::Block(b) => block(b, params),
    }
}

/// `scene.add_component(ComponentDecl::new(name, blocks::Kind { … }).input(port, src)…);`
fn block(b: &BlockIr, params: &[&Ident]) -> TokenStream {
    let scene = local("scene");
    let core = quote!(::modia3d::core);
    let n = scoped(&b.name.to_string());
    let value = block_value(b);
    let inputs = b.inputs.iter().map(|(port, w)| {
        let src = wire(w, params);
        quote!(.input(#port, #src))
    });
    quote! {
        #scene.add_component(#core::ComponentDecl::new(#n, #value) #(#inputs)*);
    }
}

/// The block's struct literal, `blocks::Kind { field: value, …, ..Default::default() }`.
fn block_value(b: &BlockIr) -> TokenStream {
    let core = quote!(::modia3d::core);
    let spec = b.spec;
    let given = |key: &str| b.params.iter().find(|(k, _)| *k == key).map(|(_, e)| e);
    let private = quote!(::modia3d::__private);
    let mut fields = vec![];
    for p in spec.params {
        let field = format_ident!("{}", p.key);
        let value = match (p.value, given(p.key)) {
            (BlockValue::Number, Some(e)) => quote!(#e),
            (BlockValue::Numbers, Some(e)) => quote!(#private::numbers(#e)),
            (BlockValue::Rows, Some(e)) => quote!(#private::rows(#e)),
            (BlockValue::Pairs, Some(e)) => quote!(#private::pairs(#e)),
            (BlockValue::Joint, _) => {
                let j = match &b.joint {
                    Some(JointArg::Ref(j)) => scoped(&j.path),
                    Some(JointArg::Param(p)) => quote!(::modia3d::JointRef::path(&#p)),
                    None => quote!(::core::unreachable!()),
                };
                quote!(::std::string::ToString::to_string(#j))
            }
            (BlockValue::Coordinate, _) => match &b.coordinate {
                Some(c) => {
                    quote!(::core::option::Option::Some(::std::string::ToString::to_string(#c)))
                }
                None => quote!(::core::option::Option::None),
            },
            // The variant chosen or the row's default (the first), of the field's type, named
            // as the key (`gear` → `Gear::Elastic { c, d }`).
            (BlockValue::Variant(vs), _) => {
                let ty = format_ident!("{}", to_camel(p.key));
                match b.variants.iter().find(|v| v.key == p.key) {
                    Some(v) => {
                        let id = format_ident!("{}", v.variant.name);
                        let fs = v.fields.iter().map(|(f, e)| {
                            let f = format_ident!("{}", f);
                            quote!(#f: #e)
                        });
                        if v.fields.is_empty() {
                            quote!(#core::blocks::#ty::#id)
                        } else {
                            quote!(#core::blocks::#ty::#id { #(#fs),* })
                        }
                    }
                    None => {
                        let id = format_ident!("{}", vs[0].name);
                        quote!(#core::blocks::#ty::#id)
                    }
                }
            }
            // A `Sampled` block's inner block (the check stage requires it).
            (BlockValue::Block, _) => match &b.inner {
                Some(inner) => {
                    let v = block_value(inner);
                    quote!(::std::sync::Arc::new(#v))
                }
                None => quote!(::core::unreachable!()),
            },
            // Not given: the negation of another key (`uMin = -uMax`) when that one is given,
            // else the struct's default.
            (_, None) => match p.default.and_then(|d| d.strip_prefix('-')).and_then(given) {
                Some(other) => quote!(-(#other)),
                None if spec.has_default => continue,
                None => quote!(::core::default::Default::default()),
            },
        };
        fields.push(quote!(#field: #value));
    }
    let ty = format_ident!("{}", spec.name);
    let rest = spec
        .has_default
        .then(|| quote!(..::core::default::Default::default()));
    quote!(#core::blocks::#ty { #(#fields,)* #rest })
}

/// `gear` → `Gear`.
fn to_camel(key: &str) -> String {
    let mut c = key.chars();
    c.next()
        .map(|f| f.to_uppercase().chain(c).collect())
        .unwrap_or_default()
}

/// A signal's full name as a `&str`: a path with this block's prefix (`time` without), a
/// `SignalRef` parameter's, or `der(<prefix><path>)`.
fn dep(d: &Dep) -> TokenStream {
    match d {
        Dep::Path(p) if p == "time" => quote!("time"),
        Dep::Path(p) => {
            let p = scoped(p);
            quote!(::std::string::String::as_str(#p))
        }
        Dep::Param(id) => quote!(::modia3d::SignalRef::path(&#id)),
        Dep::Der(path) => {
            let p = prefix();
            quote!(::std::string::String::as_str(
                &::std::format!("der({}{})", #p, #path)
            ))
        }
    }
}

/// An input's `Src`: a constant, a signal by its full name, or a closure of time and the
/// signals' values (the parameters it reads cloned into it).
fn wire(w: &WireIr, params: &[&Ident]) -> TokenStream {
    let src = quote!(::modia3d::core::Src);
    match w {
        WireIr::Const(e) => quote!(#src::Const(#e)),
        WireIr::Signal(d) => {
            let p = dep(d);
            quote!(#src::signal(#p))
        }
        WireIr::Expr { deps, expr } => {
            let (t, v) = wire_locals();
            let deps = deps.iter().map(dep);
            quote! {
                #src::expr(&[#(#deps),*], {
                    #(let #params = ::core::clone::Clone::clone(&#params);)*
                    move |#t: f64, #v: &[f64]| -> f64 { #expr }
                })
            }
        }
    }
}

fn assembly(
    name: &proc_macro2::Ident,
    ty: &syn::Path,
    parent: &Parent,
    fields: &[(proc_macro2::Ident, syn::Expr)],
    paths: &[(proc_macro2::Ident, String)],
) -> TokenStream {
    let scene = local("scene");
    let attach = local("parent");
    let prefix = prefix();
    let tyname = ty.segments.last().expect("path").ident.to_string();
    let msg = format!(
        "`{tyname}` has a `Scene` object, so it is a model and cannot be a sub-assembly \
         (hint: declare it as `assembly {tyname}` without a `Scene`)"
    );
    let span = ty.segments.last().expect("path").ident.span();
    let assert = quote_spanned! {span=>
        const _: () = ::core::assert!(<#ty>::__MODIA3D_IS_ASSEMBLY, #msg);
    };
    let n = format!("{name}.");
    let p = quote!(&::std::format!("{}{}", #prefix, #n));
    let parent = match parent {
        Parent::Ref(r) => {
            let s = scoped(&r.path);
            quote!(::core::option::Option::Some(::core::convert::AsRef::<str>::as_ref(#s)))
        }
        Parent::Attach => quote!(#attach),
        Parent::None => quote!(::core::option::Option::None),
    };
    let ks = fields.iter().map(|(k, _)| k);
    let vs = fields.iter().map(|(_, v)| v);
    // A signal or joint of this block: its full name, as the parameter's `SignalRef` or
    // `JointRef`.
    let pks = paths.iter().map(|(k, _)| k);
    let pvs = paths.iter().map(|(k, path)| {
        let full = dep(&Dep::Path(path.clone()));
        quote_spanned!(k.span()=> ::modia3d::__private::FromPath::from_path(#full))
    });
    quote! {
        #assert
        #ty {
            #(#ks: #vs,)*
            #(#pks: #pvs,)*
            ..::core::default::Default::default()
        }
        .add_to(#scene, #p, #parent);
    }
}

/// `let _: ObjectPath = __modia3d_Arm::tip;` — rustc checks the path on the user's tokens;
/// a velocity read by `der(…)` by the kind its signal's type alias names
/// (`velocity::<__modia3d_Arm::rev::w>()`).
pub(super) fn path_check(c: &PathCheck) -> TokenStream {
    let rest = &c.rest;
    let module = paths_module_at(&c.ty, rest[0].span());
    if c.want == PathWant::Velocity {
        let last_span = rest.last().expect("non-empty").span();
        let check = quote_spanned!(last_span=> ::modia3d::__private::velocity);
        return quote! {
            #check::<#module #(:: #rest)*>();
        };
    }
    let marker = match c.want {
        PathWant::Joint => quote!(JointPath),
        PathWant::Object => quote!(ObjectPath),
        PathWant::Signal | PathWant::Velocity => quote!(SignalPath),
    };
    let last_span = rest.last().expect("non-empty").span();
    let marker = quote_spanned!(last_span=> ::modia3d::__private::#marker);
    quote! {
        let _: #marker = #module #(:: #rest)*;
    }
}

fn pair_material(m: &MaterialName) -> TokenStream {
    match m {
        MaterialName::Local(n) => scoped(n),
        MaterialName::Named(_, e) => quote!(#e),
        MaterialName::Expr(e) => quote!(&(#e)),
    }
}

fn feature(f: &FeatureIr) -> TokenStream {
    match f {
        FeatureIr::Expr(e) => quote!(#e),
        FeatureIr::Scene(s) => scene_options(s),
        FeatureIr::Visual(s) => {
            let s = shape(s);
            quote!(::modia3d::core::Feature::Visual(#s))
        }
        FeatureIr::Solid(s) => {
            let s = solid(s);
            quote!(::modia3d::core::Feature::Solid(#s))
        }
    }
}

fn num_or(n: &Option<Num>, default: TokenStream) -> TokenStream {
    match n {
        Some(n) => {
            let e = &n.expr;
            quote!(#e)
        }
        None => default,
    }
}

fn solid(s: &SolidIr) -> TokenStream {
    let mut calls = vec![];
    match &s.mass {
        None => {}
        Some(MassIr::Mass(m)) => {
            let m = &m.expr;
            calls.push(quote!(.given_mass(#m)));
        }
        Some(MassIr::Scaled(m)) => {
            let m = &m.expr;
            calls.push(quote!(.mass(#m)));
        }
        Some(MassIr::Explicit {
            mass, com, inertia, ..
        }) => {
            let m = &mass.expr;
            let com = com
                .as_ref()
                .map(|c| quote!(#c))
                .unwrap_or_else(|| quote!([0.0, 0.0, 0.0]));
            calls.push(quote! {
                .mass_properties(
                    #m,
                    ::modia3d::__private::vector3(#com),
                    ::modia3d::__private::matrix3(#inertia),
                )
            });
        }
    }
    if let Some((m, span, _)) = &s.material {
        calls.push(match m {
            MaterialName::Local(n) => {
                let n = scoped(n);
                quote_spanned!(*span=> .material(#n))
            }
            MaterialName::Named(_, e) => quote!(.material(#e)),
            MaterialName::Expr(e) => quote!(.material(&(#e))),
        });
    }
    if let Some((c, ..)) = &s.collision {
        calls.push(quote!(.collision(#c)));
    }
    if let Some((m, _)) = &s.contact_material {
        let e = match m {
            MaterialName::Named(_, e) | MaterialName::Expr(e) => e,
            MaterialName::Local(n) => unreachable!("contact materials are names: {n}"),
        };
        calls.push(quote!(.contact_material(&(#e))));
    }
    if let Some(r) = &s.smoothing_radius {
        let r = &r.expr;
        calls.push(quote!(.smoothing_radius(#r)));
    }
    if let Some(h) = &s.layer_depth {
        let h = &h.expr;
        calls.push(quote!(.layer_depth(#h)));
    }
    let base = match &s.shape {
        Some(sh) => {
            let sh = shape(sh);
            quote!(::modia3d::core::Solid::new(#sh))
        }
        None => quote!(<::modia3d::core::Solid as ::core::default::Default>::default()),
    };
    quote!(#base #(#calls)*)
}

/// A shape's `Shape` expression: the row's variant with every field, each as given (or its
/// value type's default).
fn shape(s: &ShapeIr) -> TokenStream {
    let (spec, args) = match s {
        ShapeIr::Expr(e) => return quote!(#e),
        ShapeIr::Call { spec, args } => (spec, args),
    };
    let v3 = quote!(::modia3d::__private::vector3);
    let fields = spec.params.iter().map(|p| {
        let field = format_ident!("{}", p.field);
        let arg = shape_arg(args, p.key);
        let value = match (p.value, arg) {
            (ShapeValue::Length, Some(ShapeArg::Num(n))) => {
                let e = &n.expr;
                quote!(#e)
            }
            (ShapeValue::Lengths | ShapeValue::Factors, Some(ShapeArg::Num(n))) => {
                let e = &n.expr;
                quote!(#v3(#e))
            }
            (ShapeValue::AxisIndex, Some(ShapeArg::Axis(a))) => shape_axis(a),
            (ShapeValue::Vertices, Some(ShapeArg::Expr(p))) => {
                quote!(::modia3d::__private::points(#p))
            }
            // Spanned on the user's path so a type error points at it.
            (ShapeValue::File, Some(ShapeArg::Expr(path))) => {
                quote_spanned!(syn::spanned::Spanned::span(path)=> ::std::path::PathBuf::from(#path))
            }
            (ShapeValue::Decomposition, arg) => {
                let mc = quote!(::modia3d::core::MeshCollision);
                match arg {
                    Some(ShapeArg::Expr(e)) => {
                        quote!(if #e { #mc::ConvexDecomposition } else { #mc::ConvexHull })
                    }
                    _ => quote!(#mc::ConvexHull),
                }
            }
            // Not given: the value type's default (a required one is always given).
            (ShapeValue::Length, _) => quote!(0.0),
            (ShapeValue::Factors, _) => quote!(#v3([1.0, 1.0, 1.0])),
            (ShapeValue::AxisIndex, _) => quote!(::modia3d::core::Axis::Z),
            (
                ShapeValue::Lengths
                | ShapeValue::Vertices
                | ShapeValue::File
                | ShapeValue::LoadedMesh,
                _,
            ) => quote!(::core::default::Default::default()),
        };
        quote!(#field: #value)
    });
    let id = format_ident!("{}", spec.name);
    quote!(::modia3d::core::Shape::#id { #(#fields),* })
}

/// A shape's axis as an `Axis` expression.
fn shape_axis(axis: &AxisIr) -> TokenStream {
    let ax = quote!(::modia3d::core::Axis);
    match axis {
        AxisIr::Index(1) => quote!(#ax::X),
        AxisIr::Index(2) => quote!(#ax::Y),
        AxisIr::Index(_) => quote!(#ax::Z),
        AxisIr::Expr(e) => quote!(#e),
    }
}

/// A scalar force law: a closure becomes `Law::new`, anything else `Law::from` (a number, the
/// linear coefficient, or a `Law`).
/// A closure is made `move` (it outlives `build()`; the parameters it reads are copied in).
/// Spanned on the user's value, so rustc reports a wrong type there.
fn scalar_law(e: &Expr) -> TokenStream {
    let span = syn::spanned::Spanned::span(e);
    match e {
        Expr::Closure(c) => {
            let c = moved(c);
            quote_spanned!(span=> ::modia3d::core::Law::new(#c))
        }
        _ => quote_spanned!(span=> ::modia3d::core::Law::from(#e)),
    }
}

/// The closure with `move` added.
fn moved(c: &syn::ExprClosure) -> syn::ExprClosure {
    let mut c = c.clone();
    c.capture.get_or_insert_with(Default::default);
    c
}

/// `Scene(…)` → `Feature::Scene(SceneOptions { …, ..Default::default() })`.
fn scene_options(s: &SceneIr) -> TokenStream {
    let mut fields = vec![];
    if let Some(g) = &s.gravity {
        fields.push(quote!(gravity: ::modia3d::__private::vector3(#g)));
    }
    if let Some(g) = &s.gravity_field {
        let span = syn::spanned::Spanned::span(g);
        fields.push(quote_spanned!(span=> gravity_field: ::modia3d::__private::gravity_field(#g)));
    }
    if let Some((c, _)) = &s.contact_detection {
        fields.push(quote!(contact_detection: #c));
    }
    if let Some(e) = &s.exact_restitution {
        fields.push(quote!(exact_restitution: #e));
    }
    if let Some((e, _)) = &s.modia3d_conventions {
        fields.push(quote!(modia3d_conventions: #e));
    }
    if let Some((e, _)) = &s.average_missing_pairs {
        fields.push(quote!(average_missing_pairs: #e));
    }
    for n in &s.numbers {
        let (k, v) = (format_ident!("{}", n.key), &n.expr);
        fields.push(quote!(#k: #v));
    }
    if let Some(n) = &s.mpr_max_iterations {
        let v = &n.expr;
        fields.push(quote!(mpr_max_iterations: #v));
    }
    match &s.profile {
        Some(Profile::Variant(id)) => {
            fields.push(quote!(contact_profile: ::modia3d::core::ContactProfile::#id))
        }
        Some(Profile::Expr(p)) => fields.push(quote!(contact_profile: #p)),
        None => {}
    }
    quote! {
        ::modia3d::core::Feature::Scene(::modia3d::core::SceneOptions {
            #(#fields,)*
            ..::core::default::Default::default()
        })
    }
}

/// A joint's `JointKind` expression: the row's variant with every field, each axis as given
/// (or its default) and each initial value as given (or at rest: zero, the identity rotation).
fn joint_kind(k: &JointKindIr) -> TokenStream {
    let jk = quote!(::modia3d::core::JointKind);
    let v3 = quote!(::modia3d::__private::vector3);
    let mut fields = vec![];
    for axis in k.spec.axes {
        let field = format_ident!("{}", axis.key);
        let value = match k
            .axes
            .iter()
            .find(|(key, _)| *key == axis.key)
            .map(|(_, a)| a)
        {
            Some(JointAxis::Vector(arr, _)) => quote!(#v3(#arr)),
            Some(JointAxis::Index(Some(e), _) | JointAxis::Expr(e)) => {
                quote!(#jk::axis_from_index(#e).unwrap_or_default())
            }
            Some(JointAxis::Index(None, d)) => {
                quote!(#jk::axis_from_index(#d).unwrap_or_default())
            }
            None => quote!(::core::default::Default::default()),
        };
        fields.push(quote!(#field: #value));
    }
    for p in k.spec.initial {
        let field = format_ident!("{}", p.key);
        let init = k
            .inits
            .iter()
            .find(|(key, _)| *key == p.key)
            .map(|(_, e)| e);
        let value = match (init, p.value) {
            (Some(e), ParamValue::Orientation) => quote!(::modia3d::__private::free_rotation(#e)),
            (None, ParamValue::Orientation) => {
                quote!(::modia3d::__private::free_rotation([0.0, 0.0, 0.0]))
            }
            (Some(e), ParamValue::Vector) => quote!(#v3(#e)),
            (None, ParamValue::Vector) => quote!(#v3([0.0, 0.0, 0.0])),
            (Some(e), ParamValue::Number) => quote!(#e),
            (None, ParamValue::Number) => quote!(0.0),
        };
        fields.push(quote!(#field: #value));
    }
    let ctor = format_ident!("{}", k.spec.name);
    quote!(#jk::#ctor { #(#fields),* })
}

fn force(name: &str, f: &ForceIr) -> TokenStream {
    let fe = quote!(::modia3d::core::ForceElement);
    let to_string = quote!(::std::string::ToString::to_string);
    match f {
        ForceIr::SpringDamper(SpringDamperIr {
            obj1,
            obj2,
            stiffness,
            damping,
            length0,
            spring_law,
            damper_law,
        }) => {
            let (n, o1, o2) = (scoped(name), scoped(&obj1.path), scoped(&obj2.path));
            let l = num_or(length0, quote!(0.0));
            if spring_law.is_none() && damper_law.is_none() {
                let c = num_or(stiffness, quote!(0.0));
                let d = num_or(damping, quote!(0.0));
                return quote! {
                    #fe::SpringDamper {
                        name: #to_string(#n),
                        obj1: #to_string(#o1),
                        obj2: #to_string(#o2),
                        stiffness: #c,
                        damping: #d,
                        length0: #l,
                    }
                };
            }
            let law_or = |law: &Option<Num>, coef: &Option<Num>| match (law, coef) {
                (Some(law), _) => scalar_law(&law.expr),
                (None, Some(c)) => {
                    let c = &c.expr;
                    quote!(::modia3d::core::Law::Linear(#c))
                }
                (None, None) => quote!(::modia3d::core::Law::Linear(0.0)),
            };
            let (c, d) = (law_or(spring_law, stiffness), law_or(damper_law, damping));
            quote! {
                #fe::SpringDamperPtP {
                    name: #to_string(#n),
                    obj1: #to_string(#o1),
                    obj2: #to_string(#o2),
                    length0: #l,
                    spring: #c,
                    damper: #d,
                }
            }
        }
        ForceIr::Bushing {
            obj1,
            obj2,
            nominal,
            laws,
            large_angles,
        } => {
            let (n, o1, o2) = (scoped(name), scoped(&obj1.path), scoped(&obj2.path));
            let [nf, nt] = nominal.each_ref().map(|v| match v {
                Some(v) => {
                    let v = &v.expr;
                    quote!(::modia3d::__private::vector3(#v))
                }
                None => quote!(::modia3d::__private::nalgebra::Vector3::zeros()),
            });
            let [k, d, rk, rd] = laws.each_ref().map(|l| match l {
                None => quote!(::core::default::Default::default()),
                Some(l) => match &l.expr {
                    Expr::Array(arr) if arr.elems.len() == 3 => {
                        let els = arr.elems.iter().map(scalar_law);
                        quote!([#(#els),*])
                    }
                    e => quote!(::modia3d::__private::laws(#e)),
                },
            });
            let la = large_angles
                .as_ref()
                .map_or_else(|| quote!(false), |e| quote!(#e));
            quote! {
                #fe::from(::modia3d::core::Bushing {
                    name: #to_string(#n),
                    obj1: #to_string(#o1),
                    obj2: #to_string(#o2),
                    nominal_force: #nf,
                    spring: #k,
                    damper: #d,
                    nominal_torque: #nt,
                    rot_spring: #rk,
                    rot_damper: #rd,
                    large_angles: #la,
                })
            }
        }
        ForceIr::WorldVector {
            object,
            value,
            resolved_in,
            torque,
        } => {
            let (n, o) = (scoped(name), scoped(&object.path));
            let r = match resolved_in {
                Some(r) => {
                    let r = scoped(&r.path);
                    quote!(::core::option::Option::Some(#to_string(#r)))
                }
                None => quote!(::core::option::Option::None),
            };
            let span = syn::spanned::Spanned::span(value);
            let v = match value {
                Expr::Closure(c) => {
                    let c = moved(c);
                    quote_spanned!(span=> ::modia3d::core::VectorLaw::new(#c))
                }
                _ => quote_spanned!(span=> ::modia3d::core::VectorLaw::from(#value)),
            };
            if *torque {
                quote!(#fe::WorldTorque { name: #to_string(#n), object: #to_string(#o), torque: #v, resolved_in: #r })
            } else {
                quote!(#fe::WorldForce { name: #to_string(#n), object: #to_string(#o), force: #v, resolved_in: #r })
            }
        }
        ForceIr::JointSpringDamper {
            joint,
            coordinate,
            stiffness,
            damping,
            offset,
        } => {
            let j = scoped(&joint.path);
            let co = match coordinate {
                Some((e, _)) => quote!(::core::option::Option::Some(#to_string(#e))),
                None => quote!(::core::option::Option::None),
            };
            let c = &stiffness.expr;
            let d = num_or(damping, quote!(0.0));
            let off = offset
                .as_ref()
                .map(|o| quote!(#o))
                .unwrap_or_else(|| quote!(0.0));
            quote! {
                #fe::JointSpringDamper {
                    joint: #to_string(#j),
                    coordinate: #co,
                    stiffness: #c,
                    damping: #d,
                    offset: #off,
                }
            }
        }
        ForceIr::ObjectForce { object, law } => {
            let o = scoped(&object.path);
            quote! {
                #fe::ObjectForce {
                    object: #to_string(#o),
                    law: ::modia3d::core::ForceFn::new(#law),
                }
            }
        }
    }
}
