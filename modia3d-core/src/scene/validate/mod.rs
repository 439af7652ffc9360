//! Validation stage: `SceneDesc` → `ValidScene`. Resolves names to indices, checks values,
//! the topology (one scene at the root; in `topology.rs`: no parent cycles, no rigid loops,
//! every part connected to the world, the spanning joint tree and the cut joints that close
//! kinematic loops) and the contact-pair materials
//! (`contact_rules.rs`), and collects *all* errors in one round, each naming its culprit.
//! Touches only the scene description; the dynamics plan is compiled from the result.
//!
//! One file per component: `objects.rs` (the world and its options, materials, objects,
//! solids), `joints.rs`, `forces.rs` (force elements and inputs), `options.rs` (option and
//! contact-pair material ranges), `error.rs`; the topology is `../topology.rs`.
//!
//! Built without the `solver` feature (the `model!` macro's build of the core) a scene is only
//! checked, never compiled, so the validated data is not read there.
#![cfg_attr(not(feature = "solver"), allow(dead_code))]

mod actions;
pub(crate) mod components;
pub(crate) mod error;
mod forces;
mod joints;
mod objects;
mod options;

/// The resolved joint kinds are defined with the kinds themselves (`joints/mod.rs`).
pub(crate) use crate::joints::ValidJointKind;
pub(crate) use error::Checker;
pub use error::{did_you_mean, LoopReach, SceneError, SceneErrors, SizeSlip};

use super::desc::{ForceElement, SceneDesc};
use super::materials::{average_pair, builtin_contact_pair, ContactPairMaterial, SolidMaterial};
use crate::geometry::Shape;
use crate::scene::desc::SceneOptions;
use nalgebra::{Isometry3, Matrix3, Vector3};
use std::collections::HashMap;

/// Mass properties of a solid, resolved in its object's frame.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct MassProps {
    /// Mass \[kg\].
    pub mass: f64,
    /// Centre of mass, resolved in the object frame \[m\].
    pub com: Vector3<f64>,
    /// Inertia about the centre of mass, resolved in the object frame [kg·m²].
    pub inertia: Matrix3<f64>,
}

/// A resolved solid.
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct ValidSolid {
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
    /// Smoothing radius \[m\], if set.
    pub smoothing_radius: Option<f64>,
    /// Layer depth of the volume law \[m\], if set.
    pub layer_depth: Option<f64>,
    /// Material whose Young's modulus and Poisson's ratio the contact law uses (collision
    /// solids only): the solid material, else the solid material named by the contact material.
    pub contact_elasticity: Option<SolidMaterial>,
    /// What was repaired in the solid's mesh for its mass properties (merged vertices, closed
    /// holes, the volume change), if anything; `shape` is the repaired mesh.
    pub mesh_repair: Option<crate::geometry::MeshRepair>,
}

/// A resolved object.
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct ValidObject {
    /// Name.
    pub name: String,
    /// Index of the parent object.
    pub parent: Option<usize>,
    /// Pose relative to the parent (or to world for a root) \[m\].
    pub pose: Isometry3<f64>,
    /// Solid data, if a solid.
    pub solid: Option<ValidSolid>,
    /// Visual-only shape.
    pub visual: Option<Shape>,
}

/// A resolved joint.
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct ValidJoint {
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
    /// Whether the user prefers this joint to be cut if it closes a loop.
    pub cut: bool,
    /// Its stops, checked (one per limited coordinate).
    pub limits: Vec<ValidLimit>,
}

/// A checked stop on a scalar coordinate of a joint ([`crate::JointLimit`]).
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct ValidLimit {
    /// Index of the coordinate among the kind's scalar coordinates
    /// (`JointKindSpec::coordinates`).
    pub coordinate: usize,
    /// Lower bound \[rad or m\] (`−∞`: none).
    pub lower: f64,
    /// Upper bound \[rad or m\] (`+∞`: none).
    pub upper: f64,
    /// Stiffness \[N·m/rad or N/m\]; `None`: the default (docs/joint-limits.md).
    pub stiffness: Option<f64>,
    /// Coefficient of restitution \[-\].
    pub cor: f64,
}

/// A resolved force element.
#[derive(Clone, Debug)]
pub(crate) enum ValidForce {
    /// Spring-damper between two object origins.
    SpringDamper {
        /// Name (signals).
        name: String,
        /// Object indices.
        obj1: usize,
        /// Object indices.
        obj2: usize,
        /// Tension \[N\] from the elongation \[m\].
        spring: crate::scene::Law,
        /// Tension \[N\] from the rate of the length [m/s].
        damper: crate::scene::Law,
        /// \[m\]
        length0: f64,
    },
    /// Spring-damper on a joint coordinate.
    JointSpringDamper {
        /// Joint index.
        joint: usize,
        /// Index of the coordinate among the kind's scalar coordinates
        /// (`JointKindSpec::coordinates`).
        coordinate: usize,
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
        law: crate::scene::ForceFn,
    },
    /// A bushing: the builder's description with its ends resolved.
    Bushing {
        /// Object indices.
        obj1: usize,
        /// Object indices.
        obj2: usize,
        /// Laws, nominal values and the formulation (its names are the builder's).
        spec: Box<crate::scene::Bushing>,
    },
    /// `WorldForce` (`torque = false`) or `WorldTorque` (`torque = true`).
    WorldVector {
        /// Name.
        name: String,
        /// Object acted on.
        object: usize,
        /// The value, resolved in world or `resolved_in`.
        value: crate::scene::VectorLaw,
        /// Object whose axes resolve the value; `None`: world.
        resolved_in: Option<usize>,
        /// A torque [N·m] instead of a force \[N\].
        torque: bool,
    },
}

impl ValidForce {
    /// The two objects whose motions this element's force depends on and acts on, when they
    /// may differ (spring-dampers, bushings, vectors resolved in another object).
    pub(crate) fn coupled_objects(&self) -> Option<(usize, usize)> {
        match self {
            ValidForce::SpringDamper { obj1, obj2, .. }
            | ValidForce::Bushing { obj1, obj2, .. } => Some((*obj1, *obj2)),
            ValidForce::WorldVector {
                object,
                resolved_in: Some(r),
                ..
            } => Some((*object, *r)),
            _ => None,
        }
    }
    /// The element's name for signals and messages, if it has one.
    pub(crate) fn name(&self) -> Option<&str> {
        match self {
            ValidForce::SpringDamper { name, .. } => Some(name),
            ValidForce::Bushing { spec, .. } => Some(&spec.name),
            ValidForce::WorldVector { name, .. } => Some(name),
            _ => None,
        }
    }
}

/// A checked scene: names resolved, values in range, topology a tree rooted at the world.
#[derive(Clone, Debug)]
pub(crate) struct ValidScene {
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
    /// Components with their inputs resolved and their order of evaluation.
    pub components: components::ValidComponents,
    /// Rigid clusters and the spanning joint tree (`scene/topology.rs`).
    pub topology: super::topology::Topology,
}

/// A resolved input.
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct ValidInput {
    /// Name.
    pub name: String,
    /// What it drives, with indices into `ValidScene::joints` / `objects`.
    pub kind: ValidInputKind,
}

/// What a resolved input drives.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) enum ValidInputKind {
    /// Generalised force on a scalar coordinate of a joint (index into `ValidScene::joints`,
    /// index of the coordinate among the kind's scalar coordinates).
    JointForce(usize, usize),
    /// Prescribed acceleration of a scalar coordinate of a joint (as `JointForce`).
    JointAcceleration(usize, usize),
    /// World force and torque on an object (index into `ValidScene::objects`).
    ObjectWrench(usize),
}

impl ValidScene {
    /// The contact-pair material of contact materials `a` and `b` (either order): the last
    /// user definition, else the built-in palette.
    /// With `SceneOptions::average_missing_pairs`, a pair defined in neither is the mean of
    /// the two self-pairs ([`averaged_contact_pair`](Self::averaged_contact_pair)).
    pub(crate) fn contact_pair(&self, a: &str, b: &str) -> Option<ContactPairMaterial> {
        self.defined_contact_pair(a, b)
            .or_else(|| self.averaged_contact_pair(a, b))
    }

    /// The pair as defined by the scene or the built-in palette, without averaging.
    fn defined_contact_pair(&self, a: &str, b: &str) -> Option<ContactPairMaterial> {
        self.contact_pairs
            .iter()
            .rev()
            .find(|(x, y, _)| (x == a && y == b) || (x == b && y == a))
            .map(|(_, _, m)| *m)
            .or_else(|| builtin_contact_pair(a, b))
    }

    /// The mean of the self-pairs `a|a` and `b|b` when `a|b` is not defined, both self-pairs
    /// are and `SceneOptions::average_missing_pairs` is on; `None` otherwise.
    pub(crate) fn averaged_contact_pair(&self, a: &str, b: &str) -> Option<ContactPairMaterial> {
        if !self.options.average_missing_pairs || self.defined_contact_pair(a, b).is_some() {
            return None;
        }
        let (p, q) = (
            self.defined_contact_pair(a, a)?,
            self.defined_contact_pair(b, b)?,
        );
        Some(average_pair(&p, &q))
    }
}

/// Object and joint names of the description, for resolving references.
pub(super) struct Names<'a> {
    desc: &'a SceneDesc,
    obj_index: HashMap<&'a str, usize>,
    /// Index of each joint name in `SceneDesc::joints`.
    pub(super) joint_index: HashMap<&'a str, usize>,
}

impl<'a> Names<'a> {
    /// The name indices; duplicate object and joint names are errors.
    fn new(c: &mut Checker, desc: &'a SceneDesc) -> Self {
        let mut obj_index: HashMap<&str, usize> = HashMap::new();
        for (i, o) in desc.objects.iter().enumerate() {
            if obj_index.insert(o.name.as_str(), i).is_some() {
                c.errors.push(SceneError::DuplicateName {
                    kind: "object",
                    name: o.name.clone(),
                });
            }
        }
        let mut joint_index: HashMap<&str, usize> = HashMap::new();
        for (i, j) in desc.joints.iter().enumerate() {
            if joint_index.insert(j.name.as_str(), i).is_some() {
                c.errors.push(SceneError::DuplicateName {
                    kind: "joint",
                    name: j.name.clone(),
                });
            }
        }
        // One namespace: a joint (or spring-damper) named like an object would make its
        // signals `<name>.<quantity>` ambiguous.
        let spring_names = desc.forces.iter().filter_map(|f| match f {
            ForceElement::SpringDamper { name, .. }
            | ForceElement::SpringDamperPtP { name, .. } => Some(name.as_str()),
            ForceElement::Bushing(b) => Some(b.name.as_str()),
            ForceElement::WorldForce { name, .. } | ForceElement::WorldTorque { name, .. } => {
                Some(name.as_str())
            }
            _ => None,
        });
        let mut seen: HashMap<&str, &'static str> =
            obj_index.keys().map(|&n| (n, "object")).collect();
        let joint_names = desc.joints.iter().map(|j| (j.name.as_str(), "joint"));
        for (name, kind) in joint_names.chain(spring_names.map(|n| (n, "force element"))) {
            match seen.get(name) {
                Some(&first) if first != kind => c.errors.push(SceneError::NameClash {
                    name: name.to_string(),
                    first,
                    second: kind,
                }),
                // Two joints of one name are reported above; two spring-dampers here.
                Some(_) if kind == "force element" => c.errors.push(SceneError::DuplicateName {
                    kind: "force element",
                    name: name.to_string(),
                }),
                Some(_) => {}
                None => {
                    seen.insert(name, kind);
                }
            }
        }
        Names {
            desc,
            obj_index,
            joint_index,
        }
    }

    /// The object called `name`; else an error naming `referrer`, with a hint.
    pub(super) fn resolve(&self, c: &mut Checker, referrer: String, name: &str) -> Option<usize> {
        let r = self.obj_index.get(name).copied();
        if r.is_none() {
            c.errors.push(SceneError::Unknown {
                referrer,
                kind: "object",
                name: name.to_string(),
                hint: did_you_mean(name, self.desc.objects.iter().map(|o| o.name.as_str())),
            });
        }
        r
    }
}

impl SceneDesc {
    /// Checks the scene: every error found, in one round (what [`SceneDesc::build`] reports
    /// before it compiles anything).
    pub fn validate(&self) -> Result<(), SceneErrors> {
        self.validated().map(|_| ())
    }

    /// [`Self::validate`], keeping the checked scene with its names resolved (the input of
    /// the plans).
    pub(crate) fn validated(&self) -> Result<ValidScene, SceneErrors> {
        let c = &mut Checker { errors: vec![] };
        let names = Names::new(c, self);
        let materials = objects::solid_materials(c, self);
        let (world, options) = objects::world(c, self);
        let (mut objects, mut suspect) = objects::objects(c, self, &names, &materials, &options);
        let joints = joints::joints(c, self, &names, &mut suspect, &options);
        // Cycles, two parents, clusters, the joint tree, loops, connectivity.
        let topology = super::topology::check_topology(
            &mut objects,
            &joints,
            world,
            &mut suspect,
            &mut c.errors,
        );
        // A cut joint's coordinates are no states: its stops could not act.
        for cut in &topology.cuts {
            if let Some(j) = joints.get(cut.joint).filter(|j| !j.limits.is_empty()) {
                c.errors.push(SceneError::LimitOnCutJoint {
                    joint: j.name.clone(),
                });
            }
        }
        let forces = forces::forces(c, self, &names, &joints);
        let inputs = forces::inputs(c, self, &names, &joints);
        let cut_joints: Vec<usize> = topology.cuts.iter().map(|cut| cut.joint).collect();
        let components = components::components(c, self, &names, &joints, &cut_joints);
        options::contact_pair_materials(c, self);
        actions::actions(c, self, &names);
        let valid = ValidScene {
            contact_pairs: self.contact_pairs.clone(),
            inputs,
            components,
            objects,
            joints,
            forces,
            world: world.unwrap_or(0),
            options,
            topology,
        };
        // Contact pairs that can meet but have no material (the same rule as the contact
        // preprocessing's candidate pairs).
        c.errors
            .extend(super::contact_rules::missing_contact_pairs(&valid));
        if !c.errors.is_empty() {
            return Err(SceneErrors(std::mem::take(&mut c.errors)));
        }
        Ok(valid)
    }
}
