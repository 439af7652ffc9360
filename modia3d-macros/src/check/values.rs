//! Check stage, values of objects: `feature` (`Scene`, `Solid`, `Visual`), shapes, mass
//! properties, solid and contact materials.

use super::{lit_bool, lit_int, lit_matrix, lit_str, Checker};
use crate::ast::Ctor;
use crate::ir::{
    AxisIr, FeatureIr, Item, MassIr, MaterialName, Num, ObjectIr, Parent, Profile, SceneIr,
    ShapeArg, ShapeIr, SolidIr,
};
use crate::names::{did_you_mean, hint};
use crate::vocab::{
    shape_kind, shapes, Kind, FEATURES, PROFILES, SCENE_KEYS, SCENE_NUMBERS, SOLID_KEYS,
};
use modia3d_core::ShapeValue;
use proc_macro2::{Ident, Span};
use syn::spanned::Spanned;
use syn::Expr;

impl Checker {
    pub(super) fn object(&mut self, name: &Ident, ctor: &Ctor) -> Option<Item> {
        let a = self.args(ctor, &["parent", "translation", "rotation", "feature"]);
        let mut parent = Parent::None;
        if let Some(p) = a.get("parent") {
            if let Some(r) = self.reference(p, Kind::Object, "parent") {
                if r.local && *name == r.path {
                    self.err(r.span, format!("object `{name}` is its own parent"));
                } else {
                    parent = Parent::Ref(r);
                }
            }
        }
        let mut scene = false;
        let mut feature = None;
        if let Some(f) = a.get("feature") {
            match self.nested(f, FEATURES, "feature") {
                Err(expr) => feature = Some(FeatureIr::Expr(expr.clone())),
                Ok(None) => {}
                Ok(Some(fc)) => {
                    scene = fc.name() == "Scene";
                    feature = self.feature(&fc, a.key("parent").map(|k| k.span()));
                }
            }
        }
        Some(Item::Object(ObjectIr {
            name: name.clone(),
            parent,
            translation: a.get("translation").cloned(),
            rotation: a.get("rotation").cloned(),
            feature,
            scene,
        }))
    }

    fn feature(&mut self, fc: &Ctor, parent_key: Option<Span>) -> Option<FeatureIr> {
        match fc.name().to_string().as_str() {
            "Scene" => {
                let a = self.args(fc, SCENE_KEYS);
                self.scene_spans.push((fc.span(), parent_key));
                Some(FeatureIr::Scene(self.scene_options(&a)))
            }
            "Visual" => {
                let a = self.args(fc, &["shape"]);
                let s = self.required(&a, "shape")?;
                Some(FeatureIr::Visual(self.shape(s)?))
            }
            _ => Some(FeatureIr::Solid(self.solid(fc)?)),
        }
    }

    fn solid(&mut self, fc: &Ctor) -> Option<SolidIr> {
        let a = self.args(fc, SOLID_KEYS);
        // An unusable `mass_properties` (reported) still counts as a mass source.
        let stand_in = |m: &Expr| {
            MassIr::Mass(Num {
                key: "mass",
                expr: m.clone(),
                parts: vec![None],
            })
        };
        let mass = a.get("mass_properties").map(|m| {
            match self.nested(
                m,
                &["MassProperties", "MassPropertiesFromShapeAndMass"],
                "mass properties",
            ) {
                Err(e) => {
                    self.err_spanned(
                        e,
                        "expected `MassProperties(mass = …)`, `MassProperties(mass = …, com = …, inertia = …)` or `MassPropertiesFromShapeAndMass(mass = …)`",
                    );
                    stand_in(m)
                }
                Ok(None) => stand_in(m),
                Ok(Some(mc)) => self.mass_properties(&mc).unwrap_or_else(|| stand_in(m)),
            }
        });
        let explicit_mass = matches!(mass, Some(MassIr::Explicit { .. }));
        let shape = match a.get("shape") {
            Some(s) => Some(self.shape(s)?),
            None if explicit_mass => None,
            None => {
                self.required(&a, "shape");
                return None;
            }
        };
        let mut material = None;
        if let Some(m) = a.get("solid_material") {
            let slot = self.errors.slot();
            // A wrong reference (reported) still counts as a material.
            let name = self
                .solid_material(m)
                .unwrap_or_else(|| MaterialName::Expr(m.clone()));
            material = Some((name, m.span(), slot));
        }
        let mass_slot = self.errors.slot();
        let collision = a.get("collision").map(|c| {
            let key = a.key("collision").expect("present").span();
            (c.clone(), lit_bool(c), key, self.errors.slot())
        });
        let contact_material = a
            .get("contact_material")
            .map(|c| (self.contact_material(c), c.span()));
        let smoothing_radius = self.num(&a, "smoothing_radius", false);
        let layer_depth = self.num(&a, "layer_depth", false);
        Some(SolidIr {
            shape,
            mass,
            material,
            collision,
            contact_material,
            smoothing_radius,
            layer_depth,
            span: a.span,
            mass_slot,
        })
    }

    fn mass_properties(&mut self, mc: &Ctor) -> Option<MassIr> {
        if mc.name() == "MassPropertiesFromShapeAndMass" {
            let ma = self.args(mc, &["mass"]);
            return self.num(&ma, "mass", true).map(MassIr::Scaled);
        }
        let ma = self.args(mc, &["mass", "com", "inertia"]);
        let mass = self.num(&ma, "mass", true);
        let com = ma.get("com");
        let inertia = ma.get("inertia");
        match (mass, com, inertia) {
            (Some(m), None, None) => Some(MassIr::Mass(m)),
            (Some(mass), com, Some(i)) => Some(MassIr::Explicit {
                mass,
                com: com.cloned(),
                inertia: i.clone(),
                inertia_lit: lit_matrix(i),
            }),
            (Some(_), Some(_), None) => {
                self.err(
                    ma.span,
                    "missing key `inertia` in `MassProperties(…)`: `com` needs an explicit `inertia` (hint: add `inertia = [[…], […], […]]`)",
                );
                None
            }
            (None, ..) => None,
        }
    }

    /// `solid_material = "Steel" | wood | "wood" | <expr>`. Literal names the block does not
    /// define are the core's to resolve (`rules.rs`).
    fn solid_material(&mut self, m: &Expr) -> Option<MaterialName> {
        if let Some(name) = lit_str(m) {
            if self.kind(&name) == Some(Kind::Material) {
                return Some(MaterialName::Local(name));
            }
            return Some(MaterialName::Named(name, m.clone()));
        }
        if let Expr::Path(p) = m {
            if let Some(id) = p.path.get_ident() {
                let n = id.to_string();
                match self.kind(&n) {
                    Some(Kind::Material) => return Some(MaterialName::Local(n)),
                    Some(k) => {
                        self.err(
                            id.span(),
                            format!("`{n}` is {}, not a solid material", k.article()),
                        );
                        return None;
                    }
                    None if !self.is_param(&n) => {
                        let locals = self.names_of(Kind::Material);
                        if let Some(h) = did_you_mean(&n, locals.into_iter()) {
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
        Some(MaterialName::Expr(m.clone()))
    }

    /// `contact_material = "…"` (a name, not a block material) or a `&str` expression.
    fn contact_material(&mut self, c: &Expr) -> MaterialName {
        match lit_str(c) {
            Some(n) => MaterialName::Named(n, c.clone()),
            None => MaterialName::Expr(c.clone()),
        }
    }

    /// `Scene(…)` → the options given; the others come from `SceneOptions::default()`.
    fn scene_options(&mut self, a: &super::Args) -> SceneIr {
        let gravity = a.get("gravity").cloned();
        let gravity_field = a.get("gravity_field").cloned();
        if let (Some(_), Some(k)) = (&gravity, a.key("gravity_field")) {
            self.err(
                k.span(),
                "`gravity_field` replaces `gravity`: give one of them (hint: `gravity_field = GravityField::Uniform(…)` is `gravity = …`)",
            );
        }
        let contact_detection = a.get("contact_detection").map(|c| (c.clone(), lit_bool(c)));
        let exact_restitution = a.get("exact_restitution").cloned();
        let average_missing_pairs = a
            .get("average_missing_pairs")
            .map(|c| (c.clone(), lit_bool(c)));
        let modia3d_conventions = a
            .get("modia3d_conventions")
            .map(|c| (c.clone(), lit_bool(c)));
        let mut numbers = vec![];
        for key in SCENE_NUMBERS {
            if let Some(n) = self.num(a, key, false) {
                numbers.push(n);
            }
        }
        let mpr_max_iterations = self.num(a, "mpr_max_iterations", false);
        let mut profile = None;
        if let Some(p) = a.get("profile") {
            match p {
                Expr::Path(ep) if ep.path.get_ident().is_some() => {
                    let id = ep.path.get_ident().expect("checked");
                    let n = id.to_string();
                    if PROFILES.contains(&n.as_str()) {
                        profile = Some(Profile::Variant(id.clone()));
                    } else if self.is_param(&n) {
                        profile = Some(Profile::Expr(p.clone()));
                    } else {
                        let h = did_you_mean(&n, PROFILES.iter().copied())
                            .map(|h| format!("did you mean `{h}`?"))
                            .unwrap_or_else(|| "`Volume`, `Paper2019` or `Modia3DLater`".into());
                        self.err(
                            id.span(),
                            format!("unknown contact profile `{n}` (hint: {h})"),
                        );
                    }
                }
                _ => profile = Some(Profile::Expr(p.clone())),
            }
        }
        SceneIr {
            gravity,
            gravity_field,
            contact_detection,
            exact_restitution,
            average_missing_pairs,
            modia3d_conventions,
            numbers,
            mpr_max_iterations,
            profile,
        }
    }

    /// A shape: an expression, or a constructor of the core's table with its row's keys (a
    /// required one missing is an error), each read as its value type asks.
    pub(super) fn shape(&mut self, e: &Expr) -> Option<ShapeIr> {
        let sc = match self.nested(e, &shapes(), "shape") {
            Err(expr) => return Some(ShapeIr::Expr(expr.clone())),
            Ok(None) => return None,
            Ok(Some(c)) => c,
        };
        // `nested` returns only constructors of the table.
        let spec = shape_kind(&sc.name().to_string())?;
        let a = self.args(&sc, &spec.keys().collect::<Vec<_>>());
        let mut args = vec![];
        let mut ok = true;
        for p in spec.params {
            let arg = match p.value {
                ShapeValue::AxisIndex => self.shape_axis(a.get(p.key)).map(ShapeArg::Axis),
                ShapeValue::Length | ShapeValue::Lengths | ShapeValue::Factors => {
                    self.num(&a, p.key, p.required).map(ShapeArg::Num)
                }
                ShapeValue::Vertices | ShapeValue::File | ShapeValue::Decomposition => {
                    let e = match p.required {
                        true => self.required(&a, p.key),
                        false => a.get(p.key),
                    };
                    e.cloned().map(ShapeArg::Expr)
                }
                // Not a `model!` value (`shape_kind` gives no row with one).
                ShapeValue::LoadedMesh => None,
            };
            match arg {
                Some(arg) => args.push((p.key, arg)),
                None => ok &= !p.required && p.value != ShapeValue::AxisIndex,
            }
        }
        ok.then_some(ShapeIr::Call { spec, args })
    }

    /// A shape's axis: literal 1..3 (default 3, z) or an expression of type `Axis`.
    fn shape_axis(&mut self, e: Option<&Expr>) -> Option<AxisIr> {
        let Some(e) = e else {
            return Some(AxisIr::Index(3));
        };
        match lit_int(e) {
            Some(i @ 1..=3) => Some(AxisIr::Index(i as u8)),
            Some(i) => {
                self.err(
                    e.span(),
                    format!("`axis` of a shape must be 1, 2 or 3 (x, y, z), found `{i}`"),
                );
                None
            }
            None => Some(AxisIr::Expr(e.clone())),
        }
    }
}
