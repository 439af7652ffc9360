//! Check stage, components that connect: joints, force elements, inputs, contact pairs.

use super::{compact, lit_bool, lit_f64, lit_int, lit_str, lit_vec3, Args, Checker};
use crate::ast::Ctor;
use crate::ir::{
    ActionIr, ContactPairIr, ForceIr, InputIr, Item, JointAxis, JointIr, JointKindIr, LimitIr,
    MaterialName, SpringDamperIr,
};
use crate::names::{did_you_mean, hint};
use crate::vocab::{
    joint_keys, joint_kind, world_vector_keys, Kind, BUSHING_KEYS, BUSHING_LAWS, LIMIT_SUFFIXES,
    PAIR_KEYS, SPRING_DAMPER_KEYS,
};
use modia3d_core::JointKindSpec;
use proc_macro2::Ident;
use quote::ToTokens;
use syn::spanned::Spanned;
use syn::Expr;

impl Checker {
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

    /// A joint axis `key`: absent (the default Modia axis, if any), a literal ±1..3, an `i64`
    /// expression or a `[x, y, z]` vector; an out-of-range literal is an error on its token.
    fn joint_axis(
        &mut self,
        key: &str,
        e: Option<&Expr>,
        default: Option<i64>,
    ) -> Option<JointAxis> {
        match e {
            None => default.map(|d| JointAxis::Index(None, d)),
            Some(Expr::Array(arr)) => {
                let e = Expr::Array(arr.clone());
                Some(JointAxis::Vector(arr.clone(), lit_vec3(&e)))
            }
            Some(e) => match lit_int(e) {
                Some(i) if (1..=3).contains(&i.abs()) => Some(JointAxis::Index(Some(e.clone()), i)),
                Some(i) => {
                    self.err(
                        e.span(),
                        format!("`{key}` must be ±1, ±2 or ±3 (±x, ±y, ±z), found `{i}`"),
                    );
                    None
                }
                None => Some(JointAxis::Expr(e.clone())),
            },
        }
    }

    /// A joint of any kind of the core's table: its objects, its axes (a required one missing
    /// is an error), the `Var(init)` of its initial values, `can_collide`, `cut`.
    pub(super) fn joint(&mut self, name: &Ident, ctor: &Ctor) -> Option<Item> {
        // `Kind::Joint` comes from the table, so the row exists.
        let spec = joint_kind(&ctor.name().to_string())?;
        let mut keys = joint_keys(spec);
        // A limit key of a coordinate the kind does not have: one error that says which it has
        // (the key is then taken as known, so `args` does not report it a second time).
        let names: Vec<String> = ctor.args.iter().map(|a| a.key.to_string()).collect();
        for (arg, k) in ctor.args.iter().zip(&names) {
            let Some((coord, _)) = LIMIT_SUFFIXES
                .iter()
                .find_map(|s| k.strip_suffix(s).map(|c| (c, s)))
            else {
                continue;
            };
            if keys.contains(&k.as_str()) {
                continue;
            }
            let have = spec
                .coordinates
                .iter()
                .map(|c| format!("`{}`", c.name))
                .collect::<Vec<_>>()
                .join(", ");
            let msg = if have.is_empty() {
                format!(
                    "a {} joint has no scalar coordinate to limit (`{k}`); limit a Revolute, Prismatic, Cylindrical, Universal or Planar joint",
                    spec.name
                )
            } else {
                format!(
                    "a {} joint has no coordinate `{coord}` (`{k}`): its coordinates are {have} (hint: `{}_limits = [lower, upper]`)",
                    spec.name, spec.coordinates[0].name
                )
            };
            self.err(arg.key.span(), msg);
        }
        keys.extend(
            names
                .iter()
                .filter(|k| LIMIT_SUFFIXES.iter().any(|s| k.ends_with(s)))
                .map(String::as_str),
        );
        let a = self.args(ctor, &keys);
        let (o1, o2) = (
            self.required_object(&a, "obj1"),
            self.required_object(&a, "obj2"),
        );
        let can_collide = a.get("can_collide").map(|c| (c.clone(), lit_bool(c)));
        let cut = a.get("cut").map(|c| (c.clone(), lit_bool(c)));
        let mut axes = vec![];
        let mut ok = true;
        for axis in spec.axes {
            let (key, default) = (axis.key, axis.default);
            let e = match default {
                None => self.required(&a, key),
                Some(_) => a.get(key),
            };
            if default.is_none() && e.is_none() {
                ok = false;
                continue;
            }
            match self.joint_axis(key, e, default) {
                Some(ax) => axes.push((key, ax)),
                None => ok = false,
            }
        }
        let inits = spec
            .initial
            .iter()
            .filter_map(|p| {
                let e = a.get(p.key)?;
                Some((p.key, self.var(p.key, e)?))
            })
            .collect();
        let limits = self.joint_limits(spec, &a);
        let kind = ok.then_some(JointKindIr { spec, axes, inits });
        Some(Item::Joint(JointIr {
            name: name.clone(),
            obj1: o1?,
            obj2: o2?,
            kind: kind?,
            can_collide,
            cut,
            limits,
        }))
    }

    /// The limits of a joint of kind `spec`: per scalar coordinate `c`, `c_limits = [lower,
    /// upper]` (an array of two; literal bounds must have `lower < upper`) with its optional
    /// `c_limit_stiffness` and `c_limit_cor` (which need `c_limits`).
    fn joint_limits(&mut self, spec: &JointKindSpec, a: &Args) -> Vec<LimitIr> {
        let mut out = vec![];
        for c in spec.coordinates {
            let keys = c.limit_keys;
            let (stiffness, cor) = (a.get(keys.stiffness), a.get(keys.cor));
            let Some(range) = a.get(keys.range) else {
                for k in [keys.stiffness, keys.cor] {
                    if let Some(key) = a.key(k) {
                        self.err(
                            key.span(),
                            format!(
                                "`{k}` needs `{}` (hint: `{} = [lower, upper]`)",
                                keys.range, keys.range
                            ),
                        );
                    }
                }
                continue;
            };
            let Expr::Array(arr) = range else {
                self.err(
                    range.span(),
                    format!(
                        "`{}` takes `[lower, upper]` [{}] (use `f64::INFINITY` for no upper bound)",
                        keys.range, c.unit
                    ),
                );
                continue;
            };
            let [lower, upper] = [arr.elems.first(), arr.elems.get(1)];
            let (Some(lower), Some(upper), 2) = (lower, upper, arr.elems.len()) else {
                self.err(
                    range.span(),
                    format!(
                        "`{}` takes two bounds `[lower, upper]` [{}], found {}",
                        keys.range,
                        c.unit,
                        arr.elems.len()
                    ),
                );
                continue;
            };
            if let (Some(lo), Some(hi)) = (lit_f64(lower), lit_f64(upper)) {
                if lo >= hi {
                    self.err(
                        range.span(),
                        format!("`{}`: the lower bound {lo} must be below the upper bound {hi} [{}]; swap them or widen the range", keys.range, c.unit),
                    );
                    continue;
                }
            }
            out.push(LimitIr {
                coordinate: c.name,
                lower: lower.clone(),
                upper: upper.clone(),
                stiffness: stiffness.cloned(),
                cor: cor.cloned(),
            });
        }
        out
    }

    pub(super) fn force(&mut self, name: &Ident, ctor: &Ctor) -> Option<Item> {
        let force = match ctor.name().to_string().as_str() {
            "SpringDamper" => {
                let a = self.args(ctor, SPRING_DAMPER_KEYS);
                let (o1, o2) = (
                    self.required_object(&a, "obj1"),
                    self.required_object(&a, "obj2"),
                );
                // A law replaces its linear coefficient: one of the two, the coefficient
                // required without a law.
                let pair = |c: &mut Self, coef: &'static str, law: &'static str, req: bool| {
                    if let (Some(_), Some(k)) = (a.get(coef), a.key(law)) {
                        c.err(
                            k.span(),
                            format!("`{law}` replaces `{coef}`: give one of them (hint: `{law} = 100.0` is `{coef} = 100.0`)"),
                        );
                    }
                    let l = a.get(law).map(|e| c.num_of(law, e));
                    let n = c.num(&a, coef, req && l.is_none());
                    (n, l)
                };
                let (stiffness, spring_law) = pair(self, "stiffness", "spring_law", true);
                let (damping, damper_law) = pair(self, "damping", "damper_law", false);
                let length0 = self.num(&a, "length0", false);
                if stiffness.is_none() && spring_law.is_none() {
                    return None;
                }
                ForceIr::SpringDamper(SpringDamperIr {
                    obj1: o1?,
                    obj2: o2?,
                    stiffness,
                    damping,
                    length0,
                    spring_law,
                    damper_law,
                })
            }
            "Bushing" => {
                let a = self.args(ctor, BUSHING_KEYS);
                let (o1, o2) = (
                    self.required_object(&a, "obj1"),
                    self.required_object(&a, "obj2"),
                );
                let nominal = ["nominal_force", "nominal_torque"].map(|k| self.num(&a, k, false));
                let laws = [0, 1, 2, 3].map(|i| {
                    let key = BUSHING_LAWS[i];
                    let n = a.get(key).map(|e| self.num_of(key, e));
                    if let Some(e) = a.get(key).filter(|e| !matches!(e, Expr::Array(_))) {
                        if matches!(e, Expr::Closure(_) | Expr::Lit(_)) {
                            self.err_spanned(
                                e,
                                format!("`{key}` takes one law per axis: `[x, y, z]`, each a number or a closure (hint: `[{e}, 0.0, 0.0]`)", e = compact(e)),
                            );
                            return None;
                        }
                    }
                    n
                });
                ForceIr::Bushing {
                    obj1: o1?,
                    obj2: o2?,
                    nominal,
                    laws,
                    large_angles: a.get("large_angles").cloned(),
                }
            }
            "WorldForce" | "WorldTorque" => {
                let cname = ctor.name().to_string();
                let keys = world_vector_keys(&cname);
                let a = self.args(ctor, keys);
                let o = self
                    .required(&a, "object")
                    .and_then(|e| self.reference(e, Kind::Object, "object"));
                let value = self.required(&a, keys[1]).cloned();
                let r = a
                    .get("resolved_in")
                    .map(|e| self.reference(e, Kind::Object, "object"));
                ForceIr::WorldVector {
                    object: o?,
                    value: value?,
                    resolved_in: match r {
                        Some(r) => Some(r?),
                        None => None,
                    },
                    torque: cname == "WorldTorque",
                }
            }
            "JointSpringDamper" => {
                let a = self.args(
                    ctor,
                    &["joint", "coordinate", "stiffness", "damping", "offset"],
                );
                let joint = self
                    .required(&a, "joint")
                    .and_then(|e| self.reference(e, Kind::Joint, "joint"));
                let stiffness = self.num(&a, "stiffness", true);
                let damping = self.num(&a, "damping", false);
                ForceIr::JointSpringDamper {
                    joint: joint?,
                    coordinate: a.get("coordinate").map(|e| (e.clone(), lit_str(e))),
                    stiffness: stiffness?,
                    damping,
                    offset: a.get("offset").cloned(),
                }
            }
            _ => {
                let a = self.args(ctor, &["object", "law"]);
                let o = self
                    .required(&a, "object")
                    .and_then(|e| self.reference(e, Kind::Object, "object"));
                let law = self.required(&a, "law");
                ForceIr::ObjectForce {
                    object: o?,
                    law: law?.clone(),
                }
            }
        };
        Some(Item::Force {
            name: name.clone(),
            force,
            slot: self.errors.slot(),
        })
    }

    /// `JointForce(joint)`, `JointAcceleration(joint)`, `ObjectWrench(object)`.
    pub(super) fn input(&mut self, name: &Ident, ctor: &Ctor) -> Option<Item> {
        let cname = ctor.name().to_string();
        let input = if cname == "ObjectWrench" {
            let a = self.args(ctor, &["object"]);
            let o = self
                .required(&a, "object")
                .and_then(|e| self.reference(e, Kind::Object, "object"))?;
            InputIr::ObjectWrench(o)
        } else {
            let a = self.args(ctor, &["joint", "coordinate"]);
            let e = self.required(&a, "joint")?;
            let j = self.reference(e, Kind::Joint, "joint")?;
            let coordinate = a.get("coordinate").map(|e| (e.clone(), lit_str(e)));
            if cname == "JointForce" {
                InputIr::JointForce(j, coordinate)
            } else {
                InputIr::JointAcceleration(j, coordinate)
            }
        };
        Some(Item::Input {
            name: name.clone(),
            input,
            slot: self.errors.slot(),
        })
    }

    /// `ActionAttach(object, to, at, gap)`, `ActionRelease(object, at)`,
    /// `ActionDelete(object, at)`: the objects must be objects of the block (or parts of its
    /// sub-assemblies); the core checks `at` and `gap`.
    pub(super) fn action(&mut self, name: &Ident, ctor: &Ctor) -> Option<Item> {
        let attach = ctor.name() == "ActionAttach";
        let keys: &[&str] = if attach {
            &["object", "to", "at", "gap"]
        } else {
            &["object", "at"]
        };
        let a = self.args(ctor, keys);
        let object = self
            .required(&a, "object")
            .and_then(|e| self.reference(e, Kind::Object, "object"));
        let at = self.num(&a, "at", true);
        let action = if attach {
            let to = self
                .required(&a, "to")
                .and_then(|e| self.reference(e, Kind::Object, "object"));
            let gap = self.num(&a, "gap", true);
            ActionIr::Attach {
                object: object?,
                to: to?,
                gap: gap?,
            }
        } else if ctor.name() == "ActionRelease" {
            ActionIr::Release(object?)
        } else {
            ActionIr::Delete(object?)
        };
        Some(Item::Action {
            name: name.clone(),
            at: at?,
            action,
            slot: self.errors.slot(),
        })
    }

    /// A material name in `ContactPair(…)`: `"Steel"`, `"wood"` or `wood` (a material of this
    /// block), or a `&str`/`String` expression.
    fn pair_material(&mut self, e: &Expr) -> Option<MaterialName> {
        if let Some(name) = lit_str(e) {
            if self.kind(&name) == Some(Kind::Material) {
                return Some(MaterialName::Local(name));
            }
            return Some(MaterialName::Named(name, e.clone()));
        }
        if let Expr::Path(p) = e {
            if let Some(id) = p.path.get_ident() {
                let n = id.to_string();
                match self.kind(&n) {
                    Some(Kind::Material) => return Some(MaterialName::Local(n)),
                    Some(k) => {
                        self.err(
                            id.span(),
                            format!(
                                "`{n}` is {}, not a material (hint: a contact material is a string like `\"Steel\"` or a `SolidMaterial` of this block)",
                                k.article()
                            ),
                        );
                        return None;
                    }
                    None if !self.is_param(&n) => {
                        let h = match did_you_mean(&n, self.names_of(Kind::Material).into_iter()) {
                            Some(h) => hint(Some(h)),
                            None => format!(" (hint: write a name as a string, `\"{n}\"`, or define `{n} = SolidMaterial(…)`)"),
                        };
                        self.err(id.span(), format!("unknown material `{n}`{h}"));
                        return None;
                    }
                    None => {}
                }
            }
        }
        Some(MaterialName::Expr(e.clone()))
    }

    /// `ContactPair(material1, material2, cor, mu_k, mu_r, v_min, w_min)`.
    pub(super) fn contact_pair(&mut self, _name: &Ident, ctor: &Ctor) -> Option<Item> {
        let a = self.args(ctor, PAIR_KEYS);
        // A wrong name (reported) still leaves a pair whose numbers the core checks.
        let material = |c: &mut Self, key: &str| {
            let e = c.required(&a, key)?;
            Some(
                c.pair_material(e)
                    .unwrap_or_else(|| MaterialName::Expr(e.clone())),
            )
        };
        let m1 = material(self, "material1");
        let m2 = material(self, "material2");
        let cor = self.num(&a, "cor", true);
        let mu_k = self.num(&a, "mu_k", true);
        let mu_r = self.num(&a, "mu_r", true);
        let v_min = self.num(&a, "v_min", false);
        let w_min = self.num(&a, "w_min", false);
        Some(Item::ContactPair(ContactPairIr {
            material1: m1?,
            material2: m2?,
            cor: cor?,
            mu_k: mu_k?,
            mu_r: mu_r?,
            v_min,
            w_min,
        }))
    }
}
