//! Validation stage: `SceneDesc` → `ValidScene`. Resolves names to indices, checks values,
//! the topology (one scene at the root; in `topology.rs`: no parent cycles, no kinematic loops,
//! every part connected to the world, the spanning joint tree) and the contact-pair materials
//! (`contact_rules.rs`), and collects *all* errors in one round, each naming its culprit.
//! Touches only the scene description; the dynamics plan is compiled from the result.

use super::desc::{
    Feature, ForceElement, FreeRotation, InputKind, JointKind, MassSpec, MaterialRef, SceneDesc,
    SceneOptions,
};
use super::materials::{
    builtin_contact_pair, builtin_solid_material, ContactPairMaterial, SolidMaterial,
};
use crate::geometry::Shape;
use nalgebra::{Isometry3, Matrix3, Rotation3, Translation3, UnitQuaternion, Vector3};
use std::collections::HashMap;
use std::fmt;

/// One thing wrong with a scene. Every message names the culprit and says what to do.
#[derive(thiserror::Error, Debug, Clone, PartialEq)]
pub enum SceneError {
    /// Two objects or two joints share a name.
    #[error("duplicate {kind} name `{name}`: names must be unique; rename one of them")]
    DuplicateName {
        /// "object", "joint" or "material".
        kind: &'static str,
        /// The repeated name.
        name: String,
    },
    /// No object has the `Scene` feature.
    #[error("the scene has no `Scene` object: add exactly one root object with feature `Scene` (the world)")]
    NoScene,
    /// More than one object has the `Scene` feature.
    #[error("several `Scene` objects ({}): keep exactly one", list(.objects))]
    SeveralScenes {
        /// Their names.
        objects: Vec<String>,
    },
    /// The `Scene` object has a parent.
    #[error("the `Scene` object `{object}` has a parent: the scene is the world frame and must be the root; remove its parent")]
    SceneNotRoot {
        /// Its name.
        object: String,
    },
    /// A reference to an object or joint that does not exist.
    #[error("{referrer} names unknown {kind} `{name}`{}", hint_text(.hint))]
    Unknown {
        /// Who refers, e.g. "object `arm`'s parent" or "joint `rev`'s obj1".
        referrer: String,
        /// "object", "joint" or "material".
        kind: &'static str,
        /// The unknown name.
        name: String,
        /// A close existing name, if any.
        hint: Option<String>,
    },
    /// Objects whose parents form a cycle.
    #[error("parent cycle through {}: a parent chain must end at a root; break the cycle", list(.objects))]
    ParentCycle {
        /// The objects on the cycle.
        objects: Vec<String>,
    },
    /// An object moved by more than one joint.
    #[error("object `{object}` has two parents: it is obj2 of joints {}; an object can be moved by one joint only", list(.joints))]
    TwoParents {
        /// The object.
        object: String,
        /// The joints that move it.
        joints: Vec<String>,
    },
    /// A joint that joins an object to itself.
    #[error("joint `{joint}` joins `{object}` to itself: obj1 and obj2 must differ")]
    IdenticalJointEnds {
        /// The joint.
        joint: String,
        /// The object named twice.
        object: String,
    },
    /// A closed kinematic chain.
    #[error("kinematic loop through {}: closed chains are not supported yet; remove a joint or parent link of the loop", list(.objects))]
    KinematicLoop {
        /// The objects (or joints) on the loop.
        objects: Vec<String>,
    },
    /// Objects that are neither attached nor jointed to the world.
    #[error("object `{object}` is not connected to the world: give it a parent or connect it with a joint (a FreeMotion for a free body)")]
    NotConnected {
        /// An object of the unconnected part.
        object: String,
    },
    /// A number that is NaN, infinite or out of its range.
    #[error("{what} is {value}, but it must be {expected}")]
    InvalidValue {
        /// Which value, e.g. "object `ball`: Sphere diameter".
        what: String,
        /// The value given.
        value: f64,
        /// The admissible range in words.
        expected: &'static str,
    },
    /// A solid whose mass cannot be determined.
    #[error("solid `{object}` has no mass: {reason}")]
    NoMassSource {
        /// The object.
        object: String,
        /// What is missing and how to fix it.
        reason: &'static str,
    },
    /// A body that can move but has no mass or a singular inertia.
    #[error("the body moved by joint `{joint}` (objects {}) {problem}: give it a solid with mass and inertia, or fix it rigidly", list(.objects))]
    SingularMass {
        /// The joint whose coordinate has no inertia.
        joint: String,
        /// The objects of that body.
        objects: Vec<String>,
        /// What is singular.
        problem: &'static str,
    },
    /// A FreeMotion whose obj1 lies on the far side of the world.
    #[error("FreeMotion `{joint}`: obj1 `{obj1}` must lie on the world side of obj2 `{obj2}`; swap obj1 and obj2")]
    ReversedFreeMotion {
        /// The joint.
        joint: String,
        /// Its obj1.
        obj1: String,
        /// Its obj2.
        obj2: String,
    },
    /// A collision-enabled solid without a shape.
    #[error("solid `{object}` takes part in collisions but has no shape: give it a shape or set `collision` to false")]
    CollisionWithoutShape {
        /// The object.
        object: String,
    },
    /// A collision-enabled solid without a material giving Young's modulus and Poisson's ratio.
    #[error("solid `{object}` takes part in collisions but has no material: set `material` (its name is then the contact material) or a `contact_material` that names a solid material")]
    CollisionWithoutMaterial {
        /// The object.
        object: String,
    },
    /// Two contact materials that can meet have no contact-pair material.
    #[error("no contact-pair material for `{material1}` and `{material2}` (objects `{object1}` and `{object2}` can collide): add one with `SceneDesc::add_contact_pair(\"{material1}\", \"{material2}\", ContactPairMaterial::new(cor, mu_k, mu_r))` or in a material file")]
    MissingContactPair {
        /// Contact material of the first object.
        material1: String,
        /// Contact material of the second object.
        material2: String,
        /// The first object of a pair that needs it.
        object1: String,
        /// The second object.
        object2: String,
    },
    /// A joint spring-damper on a joint without a scalar coordinate.
    #[error("joint spring-damper on `{joint}`: a {kind} joint has no scalar coordinate; use a Revolute or Prismatic joint")]
    NoScalarCoordinate {
        /// The joint.
        joint: String,
        /// Its kind.
        kind: &'static str,
    },
}

fn list(names: &[String]) -> String {
    names
        .iter()
        .map(|n| format!("`{n}`"))
        .collect::<Vec<_>>()
        .join(", ")
}

fn hint_text(h: &Option<String>) -> String {
    match h {
        Some(s) => format!(" (hint: did you mean `{s}`?)"),
        None => String::new(),
    }
}

/// All errors found in a scene, in one pass.
#[derive(thiserror::Error, Debug, Clone, PartialEq)]
pub struct SceneErrors(pub Vec<SceneError>);

impl fmt::Display for SceneErrors {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self.0.len() {
            1 => write!(f, "invalid scene: {}", self.0[0]),
            n => {
                write!(f, "invalid scene ({n} errors):")?;
                for e in &self.0 {
                    write!(f, "\n  - {e}")?;
                }
                Ok(())
            }
        }
    }
}

/// The closest name among `candidates`, if one is close enough to be a likely typo.
pub fn did_you_mean<'a>(name: &str, candidates: impl Iterator<Item = &'a str>) -> Option<String> {
    candidates
        .map(|c| (strsim::damerau_levenshtein(name, c), c))
        .filter(|(d, c)| *d <= 2.max(name.len().min(c.len()) / 3))
        .min_by_key(|(d, _)| *d)
        .map(|(_, c)| c.to_string())
}

/// Mass properties of a solid, resolved in its object's frame.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct MassProps {
    /// Mass [kg].
    pub mass: f64,
    /// Centre of mass, resolved in the object frame [m].
    pub com: Vector3<f64>,
    /// Inertia about the centre of mass, resolved in the object frame [kg·m²].
    pub inertia: Matrix3<f64>,
}

/// A resolved solid.
#[derive(Clone, Debug, PartialEq)]
pub struct ValidSolid {
    /// Geometry, if any.
    pub shape: Option<Shape>,
    /// Name of the solid material, if named.
    pub material_name: Option<String>,
    /// The solid material, if any.
    pub material: Option<SolidMaterial>,
    /// Mass properties in the object frame.
    pub mass: MassProps,
    /// Takes part in collision handling.
    pub collision: bool,
    /// Contact material name.
    pub contact_material: Option<String>,
    /// Smoothing radius [m], if set.
    pub smoothing_radius: Option<f64>,
    /// Material whose Young's modulus and Poisson's ratio the contact law uses (collision
    /// solids only): the solid material, else the solid material named by the contact material.
    pub contact_elasticity: Option<SolidMaterial>,
}

/// A resolved object.
#[derive(Clone, Debug, PartialEq)]
pub struct ValidObject {
    /// Name.
    pub name: String,
    /// Index of the parent object.
    pub parent: Option<usize>,
    /// Pose relative to the parent (or to world for a root) [m].
    pub pose: Isometry3<f64>,
    /// Solid data, if a solid.
    pub solid: Option<ValidSolid>,
    /// Visual-only shape.
    pub visual: Option<Shape>,
}

/// A resolved joint kind with unit axes and a unit quaternion.
#[derive(Clone, Debug, PartialEq)]
pub enum ValidJointKind {
    /// Rigid.
    Fix,
    /// Revolute about a unit axis resolved in obj1; initial angle [rad] and rate [rad/s].
    Revolute {
        /// Unit axis.
        axis: Vector3<f64>,
        /// Initial angle [rad].
        phi: f64,
        /// Initial angular velocity [rad/s].
        w: f64,
    },
    /// Prismatic along a unit axis resolved in obj1; initial position [m] and velocity [m/s].
    Prismatic {
        /// Unit axis.
        axis: Vector3<f64>,
        /// Initial position [m].
        s: f64,
        /// Initial velocity [m/s].
        v: f64,
    },
    /// Free motion.
    FreeMotion {
        /// Initial position, resolved in obj1 [m].
        r: Vector3<f64>,
        /// Initial orientation relative to obj1.
        rot: UnitQuaternion<f64>,
        /// Initial `der(r)`, resolved in obj1 [m/s].
        v: Vector3<f64>,
        /// Initial angular velocity, resolved in obj2 [rad/s].
        w: Vector3<f64>,
    },
}

/// A resolved joint.
#[derive(Clone, Debug, PartialEq)]
pub struct ValidJoint {
    /// Name.
    pub name: String,
    /// Index of obj1.
    pub obj1: usize,
    /// Index of obj2.
    pub obj2: usize,
    /// Kind.
    pub kind: ValidJointKind,
    /// Whether the joined bodies may collide.
    pub can_collide: bool,
}

/// A resolved force element.
#[derive(Clone, Debug)]
pub enum ValidForce {
    /// Spring-damper between two object origins.
    SpringDamper {
        /// Object indices.
        obj1: usize,
        /// Object indices.
        obj2: usize,
        /// [N/m]
        stiffness: f64,
        /// [N·s/m]
        damping: f64,
        /// [m]
        length0: f64,
    },
    /// Spring-damper on a joint coordinate.
    JointSpringDamper {
        /// Joint index.
        joint: usize,
        /// Stiffness.
        stiffness: f64,
        /// Damping.
        damping: f64,
        /// Offset.
        offset: f64,
    },
    /// User force law on an object.
    ObjectForce {
        /// Object index.
        object: usize,
        /// The law.
        law: super::desc::ForceFn,
    },
}

/// A checked scene: names resolved, values in range, topology a tree rooted at the world.
#[derive(Clone, Debug)]
pub struct ValidScene {
    /// Objects, in declaration order.
    pub objects: Vec<ValidObject>,
    /// Joints, in declaration order (Fix joints included).
    pub joints: Vec<ValidJoint>,
    /// Force elements.
    pub forces: Vec<ValidForce>,
    /// Index of the `Scene` object (the world).
    pub world: usize,
    /// Scene options.
    pub options: SceneOptions,
    /// User-defined contact-pair materials, checked (override the built-in ones).
    pub contact_pairs: Vec<(String, String, ContactPairMaterial)>,
    /// Inputs with resolved joint/object indices.
    pub inputs: Vec<ValidInput>,
    /// Rigid clusters and the spanning joint tree (`scene/topology.rs`).
    pub topology: super::topology::Topology,
}

/// A resolved input.
#[derive(Clone, Debug, PartialEq)]
pub struct ValidInput {
    /// Name.
    pub name: String,
    /// What it drives, with indices into `ValidScene::joints` / `objects`.
    pub kind: ValidInputKind,
}

/// What a resolved input drives.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum ValidInputKind {
    /// Generalised force on a scalar joint (index into `ValidScene::joints`).
    JointForce(usize),
    /// Prescribed acceleration of a scalar joint (index into `ValidScene::joints`).
    JointAcceleration(usize),
    /// World force and torque on an object (index into `ValidScene::objects`).
    ObjectWrench(usize),
}

impl ValidScene {
    /// The contact-pair material of contact materials `a` and `b` (either order): the last
    /// user definition, else the built-in palette.
    pub fn contact_pair(&self, a: &str, b: &str) -> Option<ContactPairMaterial> {
        self.contact_pairs
            .iter()
            .rev()
            .find(|(x, y, _)| (x == a && y == b) || (x == b && y == a))
            .map(|(_, _, m)| *m)
            .or_else(|| builtin_contact_pair(a, b))
    }
}

struct Checker {
    errors: Vec<SceneError>,
}

impl Checker {
    fn value(&mut self, what: impl FnOnce() -> String, v: f64, ok: bool, expected: &'static str) {
        if !ok || !v.is_finite() {
            self.errors.push(SceneError::InvalidValue {
                what: what(),
                value: v,
                expected,
            });
        }
    }
    fn finite(&mut self, what: impl Fn() -> String, vals: &[f64]) {
        for &v in vals {
            self.value(&what, v, true, "finite");
        }
    }
    fn positive(&mut self, what: impl FnOnce() -> String, v: f64) {
        self.value(what, v, v > 0.0, "finite and > 0");
    }
    fn non_negative(&mut self, what: impl FnOnce() -> String, v: f64) {
        self.value(what, v, v >= 0.0, "finite and ≥ 0");
    }
}

fn rotation_is_proper(m: &Matrix3<f64>) -> bool {
    (m.transpose() * m - Matrix3::identity()).norm() < 1e-9 && (m.determinant() - 1.0).abs() < 1e-9
}

impl SceneDesc {
    /// Checks the scene and resolves names; returns every error found.
    pub fn validate(&self) -> Result<ValidScene, SceneErrors> {
        let mut c = Checker { errors: vec![] };

        // --- names
        let mut obj_index: HashMap<&str, usize> = HashMap::new();
        for (i, o) in self.objects.iter().enumerate() {
            if obj_index.insert(o.name.as_str(), i).is_some() {
                c.errors.push(SceneError::DuplicateName {
                    kind: "object",
                    name: o.name.clone(),
                });
            }
        }
        let mut joint_index: HashMap<&str, usize> = HashMap::new();
        for (i, j) in self.joints.iter().enumerate() {
            if joint_index.insert(j.name.as_str(), i).is_some() {
                c.errors.push(SceneError::DuplicateName {
                    kind: "joint",
                    name: j.name.clone(),
                });
            }
        }
        let obj_names = || self.objects.iter().map(|o| o.name.as_str());
        let resolve = |c: &mut Checker, referrer: String, name: &str| -> Option<usize> {
            let r = obj_index.get(name).copied();
            if r.is_none() {
                c.errors.push(SceneError::Unknown {
                    referrer,
                    kind: "object",
                    name: name.to_string(),
                    hint: did_you_mean(name, obj_names()),
                });
            }
            r
        };

        // --- materials
        let mut materials: HashMap<&str, SolidMaterial> = HashMap::new();
        for (name, m) in &self.solid_materials {
            let what = |f: &str| format!("solid material `{name}`: {f}");
            c.positive(|| what("density [kg/m³]"), m.density);
            c.positive(|| what("Young's modulus [N/m²]"), m.young_modulus);
            c.value(
                || what("Poisson's ratio"),
                m.poisson_ratio,
                m.poisson_ratio > 0.0 && m.poisson_ratio < 1.0,
                "in (0, 1)",
            );
            materials.insert(name.as_str(), *m);
        }
        let lookup_material = |name: &str| {
            materials
                .get(name)
                .copied()
                .or_else(|| builtin_solid_material(name))
        };

        // --- scene object
        let scenes: Vec<usize> = self
            .objects
            .iter()
            .enumerate()
            .filter(|(_, o)| matches!(o.feature, Feature::Scene(_)))
            .map(|(i, _)| i)
            .collect();
        let world = match scenes.len() {
            0 => {
                c.errors.push(SceneError::NoScene);
                None
            }
            1 => Some(scenes[0]),
            _ => {
                c.errors.push(SceneError::SeveralScenes {
                    objects: scenes
                        .iter()
                        .map(|&i| self.objects[i].name.clone())
                        .collect(),
                });
                None
            }
        };
        let mut options = SceneOptions::default();
        if let Some(w) = world {
            let o = &self.objects[w];
            if o.parent.is_some() {
                c.errors.push(SceneError::SceneNotRoot {
                    object: o.name.clone(),
                });
            }
            if let Feature::Scene(opts) = &o.feature {
                c.finite(
                    || format!("scene `{}`: gravity [m/s²]", o.name),
                    opts.gravity.as_slice(),
                );
                check_options(&mut c, &o.name, opts);
                options = opts.clone();
            }
        }

        // --- objects
        let mut objects = Vec::with_capacity(self.objects.len());
        // Objects whose links were dropped because of an error already reported.
        let mut suspect = Vec::with_capacity(self.objects.len());
        for o in &self.objects {
            let parent = o
                .parent
                .as_ref()
                .and_then(|p| resolve(&mut c, format!("object `{}`'s parent", o.name), p));
            // An unknown parent: the object may now look unconnected.
            suspect.push(o.parent.is_some() && parent.is_none());
            c.finite(
                || format!("object `{}`: translation [m]", o.name),
                o.translation.as_slice(),
            );
            let rv = o.rotation.values();
            c.finite(|| format!("object `{}`: rotation", o.name), &rv);
            let rm = o.rotation.to_matrix();
            if rv.iter().all(|v| v.is_finite()) && !rotation_is_proper(&rm) {
                c.errors.push(SceneError::InvalidValue {
                    what: format!("object `{}`: rotation matrix determinant", o.name),
                    value: rm.determinant(),
                    expected: "1 with orthonormal columns (a proper rotation)",
                });
            }
            let pose = Isometry3::from_parts(
                Translation3::from(o.translation),
                UnitQuaternion::from_rotation_matrix(&Rotation3::from_matrix_unchecked(rm)),
            );
            let mut solid = None;
            let mut visual = None;
            match &o.feature {
                Feature::Solid(s) => {
                    if let Some(shape) = &s.shape {
                        check_shape(&mut c, &o.name, shape);
                    }
                    let (material_name, material) = match &s.material {
                        None => (None, None),
                        Some(MaterialRef::Name(n)) => match lookup_material(n) {
                            Some(m) => (Some(n.clone()), Some(m)),
                            None => {
                                c.errors.push(SceneError::Unknown {
                                    referrer: format!("solid `{}`", o.name),
                                    kind: "solid material",
                                    name: n.clone(),
                                    hint: did_you_mean(
                                        n,
                                        materials.keys().copied().chain(
                                            super::materials::SOLID_MATERIALS
                                                .iter()
                                                .map(|(n, _)| *n),
                                        ),
                                    ),
                                });
                                (Some(n.clone()), None)
                            }
                        },
                        Some(MaterialRef::Value(m)) => {
                            let what = |f: &str| format!("solid `{}`: material {f}", o.name);
                            c.positive(|| what("density [kg/m³]"), m.density);
                            c.positive(|| what("Young's modulus [N/m²]"), m.young_modulus);
                            c.value(
                                || what("Poisson's ratio"),
                                m.poisson_ratio,
                                m.poisson_ratio > 0.0 && m.poisson_ratio < 1.0,
                                "in (0, 1)",
                            );
                            (None, Some(*m))
                        }
                    };
                    if let Some(r) = s.smoothing_radius {
                        c.non_negative(|| format!("solid `{}`: smoothing radius [m]", o.name), r);
                    }
                    let mass = solid_mass(&mut c, &o.name, s, material.as_ref());
                    let contact_material = s.contact_material.clone().or(material_name.clone());
                    let mut contact_elasticity = None;
                    if s.collision {
                        if s.shape.is_none() {
                            c.errors.push(SceneError::CollisionWithoutShape {
                                object: o.name.clone(),
                            });
                        }
                        contact_elasticity = material
                            .or_else(|| s.contact_material.as_deref().and_then(lookup_material));
                        if contact_elasticity.is_none() || contact_material.is_none() {
                            c.errors.push(SceneError::CollisionWithoutMaterial {
                                object: o.name.clone(),
                            });
                        }
                    }
                    solid = Some(ValidSolid {
                        shape: s.shape.clone(),
                        material_name,
                        material,
                        mass,
                        collision: s.collision,
                        contact_material,
                        smoothing_radius: s.smoothing_radius,
                        contact_elasticity,
                    });
                }
                Feature::Visual(shape) => {
                    check_shape(&mut c, &o.name, shape);
                    visual = Some(shape.clone());
                }
                Feature::None | Feature::Scene(_) => {}
            }
            objects.push(ValidObject {
                name: o.name.clone(),
                parent,
                pose,
                solid,
                visual,
            });
        }

        // --- joints
        let mut joints = Vec::with_capacity(self.joints.len());
        for j in &self.joints {
            let o1 = resolve(&mut c, format!("joint `{}`'s obj1", j.name), &j.obj1);
            let o2 = resolve(&mut c, format!("joint `{}`'s obj2", j.name), &j.obj2);
            let kind = check_joint_kind(&mut c, &j.name, &j.kind);
            let (Some(o1), Some(o2), Some(kind)) = (o1, o2, kind) else {
                // Dropped: its resolved ends may now look unconnected.
                for o in [o1, o2].into_iter().flatten() {
                    suspect[o] = true;
                }
                continue;
            };
            if o1 == o2 {
                c.errors.push(SceneError::IdenticalJointEnds {
                    joint: j.name.clone(),
                    object: j.obj1.clone(),
                });
                suspect[o1] = true;
                continue;
            }
            joints.push(ValidJoint {
                name: j.name.clone(),
                obj1: o1,
                obj2: o2,
                kind,
                can_collide: j.can_collide,
            });
        }

        // --- topology: cycles, two parents, clusters, the joint tree, loops, connectivity
        let topology = super::topology::check_topology(
            &mut objects,
            &joints,
            world,
            &mut suspect,
            &mut c.errors,
        );

        // --- force elements
        let mut forces = vec![];
        for f in &self.forces {
            match f {
                ForceElement::SpringDamper {
                    name,
                    obj1,
                    obj2,
                    stiffness,
                    damping,
                    length0,
                } => {
                    let what = |w: &str| format!("spring-damper `{name}`: {w}");
                    c.non_negative(|| what("stiffness [N/m]"), *stiffness);
                    c.non_negative(|| what("damping [N·s/m]"), *damping);
                    c.non_negative(|| what("unstretched length [m]"), *length0);
                    let a = resolve(&mut c, format!("spring-damper `{name}`'s obj1"), obj1);
                    let b = resolve(&mut c, format!("spring-damper `{name}`'s obj2"), obj2);
                    if let (Some(obj1), Some(obj2)) = (a, b) {
                        forces.push(ValidForce::SpringDamper {
                            obj1,
                            obj2,
                            stiffness: *stiffness,
                            damping: *damping,
                            length0: *length0,
                        });
                    }
                }
                ForceElement::JointSpringDamper {
                    joint,
                    stiffness,
                    damping,
                    offset,
                } => {
                    let what = |w: &str| format!("spring-damper on joint `{joint}`: {w}");
                    c.non_negative(|| what("stiffness"), *stiffness);
                    c.non_negative(|| what("damping"), *damping);
                    c.finite(|| what("offset"), &[*offset]);
                    match joint_index.get(joint.as_str()) {
                        None => c.errors.push(SceneError::Unknown {
                            referrer: "joint spring-damper".into(),
                            kind: "joint",
                            name: joint.clone(),
                            hint: did_you_mean(joint, self.joints.iter().map(|j| j.name.as_str())),
                        }),
                        Some(&ji) => {
                            let k = &self.joints[ji].kind;
                            if !matches!(
                                k,
                                JointKind::Revolute { .. } | JointKind::Prismatic { .. }
                            ) {
                                c.errors.push(SceneError::NoScalarCoordinate {
                                    joint: joint.clone(),
                                    kind: k.name(),
                                });
                            } else if let Some(valid) =
                                joints.iter().position(|vj| vj.name == *joint)
                            {
                                forces.push(ValidForce::JointSpringDamper {
                                    joint: valid,
                                    stiffness: *stiffness,
                                    damping: *damping,
                                    offset: *offset,
                                });
                            }
                        }
                    }
                }
                ForceElement::ObjectForce { object, law } => {
                    if let Some(o) = resolve(&mut c, "object force".into(), object) {
                        forces.push(ValidForce::ObjectForce {
                            object: o,
                            law: law.clone(),
                        });
                    }
                }
            }
        }

        // --- inputs
        let mut inputs = vec![];
        let mut input_names = std::collections::HashSet::new();
        let mut driven = std::collections::HashSet::new();
        for inp in &self.inputs {
            if !input_names.insert(inp.name.as_str()) {
                c.errors.push(SceneError::DuplicateName {
                    kind: "input",
                    name: inp.name.clone(),
                });
            }
            let joint = |c: &mut Checker, jn: &str| -> Option<usize> {
                let Some(&ji) = joint_index.get(jn) else {
                    c.errors.push(SceneError::Unknown {
                        referrer: format!("input `{}`", inp.name),
                        kind: "joint",
                        name: jn.to_string(),
                        hint: did_you_mean(jn, self.joints.iter().map(|j| j.name.as_str())),
                    });
                    return None;
                };
                let k = &self.joints[ji].kind;
                if !matches!(k, JointKind::Revolute { .. } | JointKind::Prismatic { .. }) {
                    c.errors.push(SceneError::NoScalarCoordinate {
                        joint: jn.to_string(),
                        kind: k.name(),
                    });
                    return None;
                }
                joints.iter().position(|vj| vj.name == jn)
            };
            let kind = match &inp.kind {
                InputKind::JointForce { joint: jn } => {
                    joint(&mut c, jn).map(ValidInputKind::JointForce)
                }
                InputKind::JointAcceleration { joint: jn } => {
                    let j = joint(&mut c, jn);
                    if j.is_some() && !driven.insert(jn.as_str()) {
                        c.errors.push(SceneError::DuplicateName {
                            kind: "prescribed-acceleration joint",
                            name: jn.clone(),
                        });
                    }
                    j.map(ValidInputKind::JointAcceleration)
                }
                InputKind::ObjectWrench { object } => {
                    resolve(&mut c, format!("input `{}`", inp.name), object)
                        .map(ValidInputKind::ObjectWrench)
                }
            };
            if let Some(kind) = kind {
                inputs.push(ValidInput {
                    name: inp.name.clone(),
                    kind,
                });
            }
        }

        // --- contact-pair materials
        for (a, b, m) in &self.contact_pairs {
            let what = |f: &str| format!("contact pair material `{a}`–`{b}`: {f}");
            c.value(
                || what("cor"),
                m.cor,
                (0.0..=1.0).contains(&m.cor),
                "in [0, 1]",
            );
            c.non_negative(|| what("mu_k"), m.mu_k);
            c.non_negative(|| what("mu_r"), m.mu_r);
            if let Some(v) = m.v_min {
                c.positive(|| what("v_min [m/s]"), v);
            }
            if let Some(w) = m.w_min {
                c.positive(|| what("w_min [rad/s]"), w);
            }
        }

        let valid = ValidScene {
            contact_pairs: self.contact_pairs.clone(),
            inputs,
            objects,
            joints,
            forces,
            world: world.unwrap_or(0),
            options,
            topology,
        };
        // --- contact pairs that can meet but have no material (the same rule as the contact
        // preprocessing's candidate pairs)
        c.errors
            .extend(super::contact_rules::missing_contact_pairs(&valid));
        if !c.errors.is_empty() {
            return Err(SceneErrors(c.errors));
        }
        Ok(valid)
    }
}

fn check_options(c: &mut Checker, scene: &str, o: &SceneOptions) {
    let what = |f: &str| format!("scene `{scene}`: {f}");
    c.positive(|| what("k_red"), o.k_red);
    c.positive(|| what("d_max [s/m]"), o.d_max);
    c.value(
        || what("cor_min"),
        o.cor_min,
        o.cor_min > 0.0 && o.cor_min <= 1.0,
        "in (0, 1]",
    );
    c.positive(|| what("v_min [m/s]"), o.v_min);
    c.positive(|| what("w_min [rad/s]"), o.w_min);
    c.positive(|| what("hysteresis [m]"), o.hysteresis);
    c.positive(|| what("MPR tolerance"), o.mpr_tolerance);
    c.value(
        || what("MPR iteration limit"),
        o.mpr_max_iterations as f64,
        o.mpr_max_iterations > 0,
        "> 0",
    );
    c.non_negative(|| what("smoothing radius [m]"), o.smoothing_radius);
}

fn check_shape(c: &mut Checker, object: &str, shape: &Shape) {
    let kind = shape.kind();
    for (name, v) in shape.dimensions() {
        c.positive(|| format!("object `{object}`: {kind:?} {name} [m]"), v);
    }
    if let Shape::Cone { top_diameter, .. } = shape {
        c.non_negative(
            || format!("object `{object}`: Cone top_diameter [m]"),
            *top_diameter,
        );
    }
    if let Shape::ConvexHull { points } = shape {
        let flat: Vec<f64> = points
            .iter()
            .flat_map(|p| p.coords.iter().copied())
            .collect();
        c.finite(
            || format!("object `{object}`: ConvexHull points [m]"),
            &flat,
        );
        if flat.iter().all(|v| v.is_finite()) && shape.unit_mass_properties().is_none() {
            c.errors.push(SceneError::InvalidValue {
                what: format!("object `{object}`: ConvexHull volume [m³]"),
                value: 0.0,
                expected: "> 0 (at least 4 points not in one plane)",
            });
        }
    }
}

fn solid_mass(
    c: &mut Checker,
    object: &str,
    s: &super::desc::Solid,
    material: Option<&SolidMaterial>,
) -> MassProps {
    let zero = MassProps {
        mass: 0.0,
        com: Vector3::zeros(),
        inertia: Matrix3::zeros(),
    };
    let unit = || s.shape.as_ref().and_then(|sh| sh.unit_mass_properties());
    match &s.mass_properties {
        MassSpec::FromShapeAndDensity => {
            let Some(m) = material else {
                c.errors.push(SceneError::NoMassSource {
                    object: object.into(),
                    reason:
                        "mass from density needs a solid material; set `material` or give a mass",
                });
                return zero;
            };
            if s.shape.is_none() {
                c.errors.push(SceneError::NoMassSource {
                    object: object.into(),
                    reason: "mass from density needs a shape; set `shape` or give explicit mass properties",
                });
                return zero;
            }
            match unit() {
                Some(u) => MassProps {
                    mass: m.density * u.volume,
                    com: u.com,
                    inertia: u.inertia * m.density,
                },
                None => zero, // degenerate hull: reported by check_shape
            }
        }
        MassSpec::FromShapeAndMass(mass) => {
            c.positive(|| format!("solid `{object}`: mass [kg]"), *mass);
            if s.shape.is_none() {
                c.errors.push(SceneError::NoMassSource {
                    object: object.into(),
                    reason: "inertia from mass needs a shape; set `shape` or give explicit mass properties",
                });
                return zero;
            }
            match unit() {
                Some(u) if u.volume > 0.0 && u.volume.is_finite() => MassProps {
                    mass: *mass,
                    com: u.com,
                    inertia: u.inertia * (*mass / u.volume),
                },
                _ => zero,
            }
        }
        MassSpec::Explicit { mass, com, inertia } => {
            c.positive(|| format!("solid `{object}`: mass [kg]"), *mass);
            c.finite(
                || format!("solid `{object}`: centre of mass [m]"),
                com.as_slice(),
            );
            c.finite(
                || format!("solid `{object}`: inertia [kg·m²]"),
                inertia.as_slice(),
            );
            if inertia.iter().all(|v| v.is_finite()) {
                let sym = (inertia - inertia.transpose()).norm() <= 1e-12 * inertia.norm();
                let ev = inertia.symmetric_eigenvalues();
                let (a, b, cc) = (ev[0], ev[1], ev[2]);
                let tol = 1e-12 * ev.abs().max();
                let triangle = a + b >= cc - tol && a + cc >= b - tol && b + cc >= a - tol;
                if !sym || ev.min() < -tol || !triangle {
                    c.errors.push(SceneError::InvalidValue {
                        what: format!(
                            "solid `{object}`: smallest principal inertia [kg·m²]"
                        ),
                        value: ev.min(),
                        expected: "a symmetric, positive semi-definite tensor whose principal moments satisfy the triangle inequality",
                    });
                }
            }
            MassProps {
                mass: *mass,
                com: *com,
                inertia: *inertia,
            }
        }
    }
}

fn check_joint_kind(c: &mut Checker, joint: &str, k: &JointKind) -> Option<ValidJointKind> {
    let before = c.errors.len();
    let axis_of = |c: &mut Checker, axis: &Vector3<f64>| {
        let n = axis.norm();
        c.value(
            || format!("joint `{joint}`: axis length"),
            n,
            n > 0.0,
            "non-zero (an axis ±1, ±2, ±3 or a direction vector)",
        );
        axis / n
    };
    let kind = match k {
        JointKind::Fix => ValidJointKind::Fix,
        JointKind::Revolute { axis, phi, w } => {
            c.finite(
                || format!("joint `{joint}`: initial phi [rad], w [rad/s]"),
                &[*phi, *w],
            );
            ValidJointKind::Revolute {
                axis: axis_of(c, axis),
                phi: *phi,
                w: *w,
            }
        }
        JointKind::Prismatic { axis, s, v } => {
            c.finite(
                || format!("joint `{joint}`: initial s [m], v [m/s]"),
                &[*s, *v],
            );
            ValidJointKind::Prismatic {
                axis: axis_of(c, axis),
                s: *s,
                v: *v,
            }
        }
        JointKind::FreeMotion { r, rot, v, w } => {
            c.finite(
                || format!("joint `{joint}`: initial r [m], v [m/s], w [rad/s]"),
                &[r.as_slice(), v.as_slice(), w.as_slice()].concat(),
            );
            let q = match rot {
                FreeRotation::Cardan(a) => {
                    c.finite(
                        || format!("joint `{joint}`: initial Cardan angles [rad]"),
                        a,
                    );
                    UnitQuaternion::from_rotation_matrix(&Rotation3::from_matrix_unchecked(
                        super::desc::cardan_to_matrix(*a),
                    ))
                }
                FreeRotation::Quaternion(q) => {
                    c.finite(
                        || format!("joint `{joint}`: initial quaternion"),
                        q.coords.as_slice(),
                    );
                    *q
                }
            };
            ValidJointKind::FreeMotion {
                r: *r,
                rot: q,
                v: *v,
                w: *w,
            }
        }
    };
    (c.errors.len() == before).then_some(kind)
}
