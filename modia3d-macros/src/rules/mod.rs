//! The core's scene rules on the literal part of a block. The IR is turned into a
//! `modia3d_core::SceneDesc` — literal values as written, neutral stand-ins for everything known
//! only at run time (expressions, parameters, parts of sub-assemblies) — and checked by the
//! same code `SceneDesc::build` runs (`SceneDesc::scene_errors`: validation, topology, contact
//! pairs). Each error is mapped back to the user's token; errors about stand-ins are dropped,
//! since the block alone cannot decide them (`build()` does).

mod map;

use crate::ast::ModelDef;
use crate::check::Errors;
use crate::ir::{
    shape_arg, ActionIr, AxisIr, FeatureIr, ForceIr, InputIr, Ir, Item, JointAxis, JointKindIr,
    LitNum, MassIr, MaterialIr, MaterialName, Num, Parent, SceneIr, ShapeArg, ShapeIr, SolidIr,
};
use crate::names::NameRef;
use crate::vocab::Kind;
use modia3d_core::scene::{
    Action, ContactPairMaterial, Feature, ForceElement, ForceFn, Input, Joint, JointKind, MassSpec,
    Object3D, SceneDesc, SceneOptions, Solid, SolidMaterial, Wrench,
};
use modia3d_core::scene::{Bushing, Law, VectorLaw};
use modia3d_core::{Axis, Shape, ShapeValues};
use nalgebra::{Matrix3, Vector3};
use std::collections::{HashMap, HashSet};

/// The value of every number known only at run time: inside every range the core checks
/// (positive, non-negative, [0, 1], (0, 1), (0, 1]). Should a rule ever exclude it, its error
/// has no literal culprit and is dropped like any other error about a stand-in.
const STAND_IN: f64 = 0.5;
/// The name of a material known only at run time (names with a dot are parts of
/// sub-assemblies; both are stand-ins).
const STAND_IN_MATERIAL: &str = "__modia3d_stand_in";

/// An input with its coordinate name, if given (literal, or a stand-in).
fn coordinate(i: Input, c: &Option<(syn::Expr, Option<String>)>) -> Input {
    match c {
        Some(c) => i.coordinate(&stand_in_coordinate(c)),
        None => i,
    }
}

/// A coordinate's literal name, or a stand-in (errors about it are dropped).
fn stand_in_coordinate((_, lit): &(syn::Expr, Option<String>)) -> String {
    lit.clone().unwrap_or_else(|| STAND_IN_MATERIAL.to_string())
}

/// A literal axis, else `None` (known only at run time).
fn literal_axis(a: &JointAxis) -> Option<Vector3<f64>> {
    match a {
        JointAxis::Index(_, i) => JointKind::axis_from_index(*i),
        JointAxis::Vector(_, Some(v)) => Some(Vector3::from(*v)),
        _ => None,
    }
}

/// The kind at rest with its literal axes (the row's `at_rest`: an axis known only at run time
/// is a stand-in the rules accept). Initial values do not take part in the scene rules beyond
/// being finite: zeros.
fn joint_at_rest(k: &JointKindIr) -> JointKind {
    let axis = |key: &str| {
        k.axes
            .iter()
            .find(|(a, _)| *a == key)
            .and_then(|(_, a)| literal_axis(a))
    };
    (k.spec.at_rest)(&axis)
}

pub(crate) fn is_stand_in(name: &str) -> bool {
    name.contains('.') || name.starts_with("__modia3d")
}

/// Runs the core's scene rules on the block and adds their errors, mapped to spans.
pub(crate) fn check(def: &ModelDef, ir: &Ir, errors: &mut Errors) {
    let mut p = Probe::default();
    p.build(ir);
    let macro_errors = errors.any();
    let m = map::Mapper {
        ir,
        probe: &p,
        assembly: def.assembly.is_some(),
        macro_errors,
        used: vec![false; p.nums.len()],
        consumed: HashMap::new(),
    };
    m.map_all(p.desc.scene_errors(), errors);
}

/// The scene description of the literal part, and where its literal numbers came from.
#[derive(Default)]
pub(crate) struct Probe<'a> {
    pub(crate) desc: SceneDesc,
    /// (owner as the core names it, key, literal).
    pub(crate) nums: Vec<(String, &'static str, &'a LitNum)>,
    /// A `ContactPair` of the block names a material known only at run time.
    pub(crate) pairs_unsure: bool,
    /// The block has sub-assemblies (they may add anything).
    pub(crate) has_assemblies: bool,
    /// Some value of the block is known only at run time (a stand-in stands for it).
    pub(crate) run_time_values: bool,
}

impl<'a> Probe<'a> {
    fn scalar(&mut self, owner: &str, n: &'a Num) -> f64 {
        match n.parts.as_slice() {
            [Some(l)] => {
                self.nums.push((owner.to_string(), n.key, l));
                l.value
            }
            _ => {
                self.run_time_values = true;
                STAND_IN
            }
        }
    }

    fn vec3(&mut self, owner: &str, n: &'a Num) -> Vector3<f64> {
        let mut v = Vector3::repeat(STAND_IN);
        self.run_time_values |= n.parts.len() != 3 || n.parts.iter().any(|p| p.is_none());
        if n.parts.len() == 3 {
            for (i, part) in n.parts.iter().enumerate() {
                if let Some(l) = part {
                    self.nums.push((owner.to_string(), n.key, l));
                    v[i] = l.value;
                }
            }
        }
        v
    }

    fn material(&mut self, m: &MaterialName) -> String {
        match m {
            MaterialName::Local(n) | MaterialName::Named(n, _) => n.clone(),
            MaterialName::Expr(_) => {
                self.run_time_values = true;
                STAND_IN_MATERIAL.to_string()
            }
        }
    }

    fn build(&mut self, ir: &'a Ir) {
        let neutral = SolidMaterial {
            density: STAND_IN,
            young_modulus: STAND_IN,
            poisson_ratio: STAND_IN,
        };
        self.desc.add_solid_material(STAND_IN_MATERIAL, neutral);
        // Block materials whose definition has errors (reported) still exist.
        for (n, k) in &ir.kinds {
            let defined = ir
                .items
                .iter()
                .any(|it| matches!(it, Item::Material(MaterialIr { name, .. }) if name == n));
            if *k == Kind::Material && !defined {
                self.desc.add_solid_material(&n.to_string(), neutral);
            }
        }
        let mut outside: Vec<&str> = vec![];
        for it in &ir.items {
            self.item(it, &mut outside);
        }
        let mut seen = HashSet::new();
        for path in outside {
            if seen.insert(path) {
                self.desc.add(Object3D::new(path));
            }
        }
    }

    fn item(&mut self, it: &'a Item, outside: &mut Vec<&'a str>) {
        let mut obj = |r: &'a NameRef| {
            if !r.local {
                outside.push(&r.path);
            }
            r.path.as_str()
        };
        match it {
            Item::Material(mat) => {
                let n = mat.name.to_string();
                let m = SolidMaterial {
                    density: self.scalar(&n, &mat.density),
                    young_modulus: self.scalar(&n, &mat.young_modulus),
                    poisson_ratio: self.scalar(&n, &mat.poisson_ratio),
                };
                self.desc.add_solid_material(&n, m);
            }
            Item::Object(object) => {
                let n = object.name.to_string();
                let mut o = Object3D::new(&n);
                if let Parent::Ref(r) = &object.parent {
                    o = o.parent(obj(r));
                }
                if let Some(f) = &object.feature {
                    o = o.feature(self.feature(&n, f));
                }
                self.desc.add(o);
            }
            Item::Joint(j) => {
                let kind = joint_at_rest(&j.kind);
                let (o1, o2) = (obj(&j.obj1), obj(&j.obj2));
                let cut = j.cut.as_ref().and_then(|c| c.1).unwrap_or(false);
                let mut joint = Joint::new(&j.name.to_string(), o1, o2, kind).cut(cut);
                // Not given: the scene's conventions decide (`SceneOptions::modia3d_conventions`).
                if let Some(c) = &j.can_collide {
                    joint = joint.can_collide(c.1.unwrap_or(false));
                }
                self.desc.add_joint(joint);
            }
            Item::Force { name, force, .. } => {
                let f = match force {
                    ForceIr::SpringDamper(sd) => {
                        // A law's literal number is a coefficient; a closure a stand-in.
                        let n = name.to_string();
                        let mut coef = |a: &'a Option<Num>, b: &'a Option<Num>| {
                            a.as_ref()
                                .or(b.as_ref())
                                .map_or(0.0, |x| self.scalar(&n, x))
                        };
                        let (c, d) = (
                            coef(&sd.stiffness, &sd.spring_law),
                            coef(&sd.damping, &sd.damper_law),
                        );
                        ForceElement::SpringDamper {
                            obj1: obj(&sd.obj1).to_string(),
                            obj2: obj(&sd.obj2).to_string(),
                            stiffness: c,
                            damping: d,
                            length0: sd.length0.as_ref().map_or(0.0, |l| self.scalar(&n, l)),
                            name: n,
                        }
                    }
                    ForceIr::Bushing {
                        obj1,
                        obj2,
                        nominal,
                        laws,
                        ..
                    } => {
                        let n = name.to_string();
                        let mut b = Bushing::new(&n, obj(obj1), obj(obj2));
                        let mut vec3 = |x: &'a Option<Num>| {
                            x.as_ref().map_or(Vector3::zeros(), |x| self.vec3(&n, x))
                        };
                        b.nominal_force = vec3(&nominal[0]);
                        b.nominal_torque = vec3(&nominal[1]);
                        [b.spring, b.damper, b.rot_spring, b.rot_damper] =
                            laws.each_ref().map(|l| {
                                let v = vec3(l);
                                [v.x, v.y, v.z].map(Law::Linear)
                            });
                        ForceElement::from(b)
                    }
                    ForceIr::WorldVector {
                        object,
                        resolved_in,
                        torque,
                        ..
                    } => {
                        let (object, resolved_in) = (
                            obj(object).to_string(),
                            resolved_in.as_ref().map(|r| obj(r).to_string()),
                        );
                        let value = VectorLaw::Constant(Vector3::zeros());
                        let name = name.to_string();
                        if *torque {
                            ForceElement::WorldTorque {
                                name,
                                object,
                                torque: value,
                                resolved_in,
                            }
                        } else {
                            ForceElement::WorldForce {
                                name,
                                object,
                                force: value,
                                resolved_in,
                            }
                        }
                    }
                    ForceIr::JointSpringDamper {
                        joint,
                        coordinate,
                        stiffness,
                        damping,
                        ..
                    } => ForceElement::JointSpringDamper {
                        joint: joint.path.clone(),
                        coordinate: coordinate.as_ref().map(stand_in_coordinate),
                        stiffness: self.scalar(&joint.path, stiffness),
                        damping: damping
                            .as_ref()
                            .map_or(0.0, |d| self.scalar(&joint.path, d)),
                        offset: 0.0,
                    },
                    ForceIr::ObjectForce { object, .. } => ForceElement::ObjectForce {
                        object: obj(object).to_string(),
                        law: ForceFn::new(|_, _| Wrench::default()),
                    },
                };
                self.desc.add_force(f);
            }
            Item::Input { name, input, .. } => {
                let n = name.to_string();
                self.desc.add_input(match input {
                    InputIr::JointForce(j, c) => coordinate(Input::joint_force(&n, &j.path), c),
                    InputIr::JointAcceleration(j, c) => {
                        coordinate(Input::joint_acceleration(&n, &j.path), c)
                    }
                    InputIr::ObjectWrench(o) => Input::object_wrench(&n, obj(o)),
                });
            }
            Item::Action {
                name, at, action, ..
            } => {
                let n = name.to_string();
                let at = self.scalar(&n, at);
                let a = match action {
                    ActionIr::Attach { object, to, gap } => {
                        let gap = self.scalar(&n, gap);
                        Action::attach(&n, at, obj(object), obj(to), gap)
                    }
                    ActionIr::Release(o) => Action::release(&n, at, obj(o)),
                    ActionIr::Delete(o) => Action::delete(&n, at, obj(o)),
                };
                self.desc.add_action(a);
            }
            Item::ContactPair(pair) => {
                let unsure = |m: &MaterialName| matches!(m, MaterialName::Expr(_));
                self.pairs_unsure |= unsure(&pair.material1) || unsure(&pair.material2);
                let (a, b) = (
                    self.material(&pair.material1),
                    self.material(&pair.material2),
                );
                let mut m = ContactPairMaterial::new(
                    self.scalar(&a, &pair.cor),
                    self.scalar(&a, &pair.mu_k),
                    self.scalar(&a, &pair.mu_r),
                );
                m.v_min = pair.v_min.as_ref().map(|v| self.scalar(&a, v));
                m.w_min = pair.w_min.as_ref().map(|w| self.scalar(&a, w));
                self.desc.add_contact_pair(&a, &b, m);
            }
            // Blocks are checked by the macro (`check/blocks.rs`) and by `build()`.
            Item::Block(_) => {}
            Item::Assembly { parent, .. } => {
                self.has_assemblies = true;
                if let Parent::Ref(r) = parent {
                    obj(r);
                }
            }
        }
    }

    fn feature(&mut self, owner: &str, f: &'a FeatureIr) -> Feature {
        match f {
            FeatureIr::Expr(_) => {
                self.run_time_values = true;
                Feature::None
            }
            FeatureIr::Scene(s) => Feature::Scene(self.scene(owner, s)),
            FeatureIr::Visual(s) => Feature::Visual(self.shape(owner, s)),
            FeatureIr::Solid(s) => Feature::Solid(self.solid(owner, s)),
        }
    }

    fn scene(&mut self, owner: &str, s: &'a SceneIr) -> SceneOptions {
        let mut o = SceneOptions::default();
        if let Some((_, lit)) = &s.contact_detection {
            o.contact_detection = lit.unwrap_or(false);
        }
        if let Some((_, lit)) = &s.modia3d_conventions {
            o.modia3d_conventions = lit.unwrap_or(false);
        }
        if let Some((_, lit)) = &s.average_missing_pairs {
            // A run-time value may be true: report no missing pair that averaging would fill.
            o.average_missing_pairs = lit.unwrap_or(true);
        }
        for n in &s.numbers {
            let v = self.scalar(owner, n);
            let field = match n.key {
                "k_red" => &mut o.k_red,
                "d_max" => &mut o.d_max,
                "cor_min" => &mut o.cor_min,
                "v_min" => &mut o.v_min,
                "v_min_volume" => &mut o.v_min_volume,
                "w_min" => &mut o.w_min,
                "hysteresis" => &mut o.hysteresis,
                "mpr_tolerance" => &mut o.mpr_tolerance,
                _ => &mut o.smoothing_radius,
            };
            *field = v;
        }
        if let Some(n) = &s.mpr_max_iterations {
            let v = self.scalar(owner, n);
            if v >= 0.0 && v.fract() == 0.0 && v <= u32::MAX as f64 {
                o.mpr_max_iterations = v as u32;
            }
        }
        o
    }

    /// A shape as its row builds it from the literal values (`ShapeKindSpec::stand_in`); an
    /// expression stands in as a sphere.
    fn shape(&mut self, owner: &str, s: &'a ShapeIr) -> Shape {
        match s {
            ShapeIr::Expr(_) => {
                self.run_time_values = true;
                Shape::Sphere { diameter: STAND_IN }
            }
            ShapeIr::Call { spec, args } => {
                let mut values = ShapeLiterals {
                    probe: self,
                    owner,
                    args,
                };
                // `ShapeIr::Call` holds only rows that are `model!` constructors.
                spec.stand_in
                    .map_or(Shape::Sphere { diameter: STAND_IN }, |f| f(&mut values))
            }
        }
    }

    fn solid(&mut self, owner: &str, s: &'a SolidIr) -> Solid {
        let mut solid = Solid {
            shape: s.shape.as_ref().map(|sh| self.shape(owner, sh)),
            ..Default::default()
        };
        if let Some((m, ..)) = &s.material {
            let name = self.material(m);
            solid = solid.material(&name);
        }
        solid.mass_properties = match &s.mass {
            None => MassSpec::FromShapeAndDensity,
            Some(MassIr::Mass(m)) => MassSpec::Mass(self.scalar(owner, m)),
            Some(MassIr::Scaled(m)) => MassSpec::FromShapeAndMass(self.scalar(owner, m)),
            Some(MassIr::Explicit {
                mass, inertia_lit, ..
            }) => MassSpec::Explicit {
                mass: self.scalar(owner, mass),
                com: Vector3::zeros(),
                inertia: match inertia_lit {
                    Some(rows) => Matrix3::from_fn(|i, j| rows[i][j]),
                    None => Matrix3::identity() * STAND_IN,
                },
            },
        };
        if let Some((_, lit, ..)) = &s.collision {
            solid.collision = lit.unwrap_or(false);
        }
        if let Some((m, _)) = &s.contact_material {
            let name = self.material(m);
            solid = solid.contact_material(&name);
        }
        if let Some(r) = &s.smoothing_radius {
            solid.smoothing_radius = Some(self.scalar(owner, r));
        }
        if let Some(h) = &s.layer_depth {
            solid.layer_depth = Some(self.scalar(owner, h));
        }
        solid
    }
}

/// The values of a shape constructor's arguments as the scene rules see them: literals
/// (recorded, so that an error on one is put on its token), stand-ins for values known only at
/// run time, the default of an argument not given.
struct ShapeLiterals<'p, 'a> {
    probe: &'p mut Probe<'a>,
    owner: &'p str,
    args: &'a [(&'static str, ShapeArg)],
}

impl ShapeValues for ShapeLiterals<'_, '_> {
    fn length(&mut self, key: &'static str) -> f64 {
        match shape_arg(self.args, key) {
            Some(ShapeArg::Num(n)) => self.probe.scalar(self.owner, n),
            Some(ShapeArg::Axis(_) | ShapeArg::Expr(_)) | None => 0.0,
        }
    }
    fn vector(&mut self, key: &'static str) -> Vector3<f64> {
        match shape_arg(self.args, key) {
            Some(ShapeArg::Num(n)) => self.probe.vec3(self.owner, n),
            Some(ShapeArg::Axis(_) | ShapeArg::Expr(_)) | None => Vector3::repeat(1.0),
        }
    }
    fn axis(&mut self, key: &'static str) -> Axis {
        match shape_arg(self.args, key) {
            Some(ShapeArg::Axis(a)) => shape_axis(a),
            Some(ShapeArg::Num(_) | ShapeArg::Expr(_)) | None => Axis::Z,
        }
    }
    fn stand_in(&self) -> f64 {
        STAND_IN
    }
}

/// A shape's literal axis (an `Axis` expression stands in as z: no rule depends on it).
fn shape_axis(axis: &AxisIr) -> Axis {
    match axis {
        AxisIr::Index(1) => Axis::X,
        AxisIr::Index(2) => Axis::Y,
        _ => Axis::Z,
    }
}
