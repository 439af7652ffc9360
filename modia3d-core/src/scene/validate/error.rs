//! Validation errors: [`SceneError`] (one thing wrong, naming its culprit and what to do),
//! [`SceneErrors`] (all of them, from one round) and the did-you-mean hint.

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
    /// An object, a joint or a named force element share a name: they form one namespace
    /// (signals are `<object or joint>.<quantity>`; in `model!` all are Rust identifiers).
    #[error("{first} `{name}` and {second} `{name}` share a name: objects, joints and force elements form one namespace (signals are `<name>.<quantity>`); rename one of them")]
    NameClash {
        /// The shared name.
        name: String,
        /// What the first one is: "object", "joint" or "force element".
        first: &'static str,
        /// What the second one is.
        second: &'static str,
    },
    /// Two options of a scene that replace each other were both set.
    #[error("scene `{scene}` sets both `{first}` and `{second}`: `{second}` replaces `{first}`; keep one of them")]
    ConflictingOptions {
        /// The scene object.
        scene: String,
        /// The option it replaces.
        first: &'static str,
        /// The option that replaces it.
        second: &'static str,
    },
    /// A body's centre of mass sits at the centre of a point gravity field at the initial
    /// state, where the field `−μ r/|r|³` is undefined.
    #[error("body of object `{object}` has its centre of mass at the centre of the point gravity field ({distance:e} m away): the field is undefined there; move the body or the centre")]
    AtGravityCentre {
        /// An object of the body (its first).
        object: String,
        /// Its distance from the centre \[m\].
        distance: f64,
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
    #[error("object `{object}` has two parents: it is obj2 of joints {}, and they do not close a loop; an object can be moved by one joint only, unless its joints are part of a closed loop", list(.joints))]
    TwoParents {
        /// The object.
        object: String,
        /// The joints that move it.
        joints: Vec<String>,
    },
    /// An attach action that names one object twice.
    #[error("action `{action}` attaches `{object}` to itself: `object` and `to` must differ")]
    AttachToItself {
        /// The action.
        action: String,
        /// The object named twice.
        object: String,
    },
    /// A joint that joins an object to itself.
    #[error("joint `{joint}` joins `{object}` to itself: obj1 and obj2 must differ")]
    IdenticalJointEnds {
        /// The joint.
        joint: String,
        /// The object named twice.
        object: String,
    },
    /// A rigid loop: parent links and Fix joints only, or a moving joint whose two ends belong
    /// to one rigid part (it could never move). Closed chains with moving joints are allowed.
    #[error("rigid kinematic loop through {}: these objects are already rigidly connected (parent links and Fix joints), so the loop cannot move; remove a joint or parent link of the loop", list(.objects))]
    KinematicLoop {
        /// The objects (or joints) on the loop.
        objects: Vec<String>,
    },
    /// A closed loop whose constraints cannot be satisfied near the given initial coordinates
    /// (link lengths or axes that do not fit together).
    #[error("kinematic loop closed by joint `{cut}` (through {}) cannot close: after assembly its constraint residual is {residual:.3e} (metres or radians, largest component); {}", list(.joints), match .reach { Some(r) => r.to_string(), None => "check the lengths, axes and initial coordinates of the loop's bodies".into() })]
    ImpossibleLoop {
        /// The cut joint that closes the loop.
        cut: String,
        /// The joints of the loop.
        joints: Vec<String>,
        /// Largest remaining constraint residual, \[m\] for translations, \[rad\]-like for rotations.
        residual: f64,
        /// A link longer than all the others together, when the loop's joints keep their
        /// frames' origins together: the loop can never close.
        reach: Option<Box<LoopReach>>,
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
    /// A mesh shape that cannot be used: its file is missing or malformed, or the mesh bounds no
    /// solid (not closed, no volume).
    #[error("object `{object}`: {error}")]
    Mesh {
        /// The object whose shape it is.
        object: String,
        /// What is wrong with the mesh (file, line or facet, edge).
        error: crate::geometry::GeometryError,
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
    /// A joint that cannot be traversed from obj2 to obj1 (Spherical, Universal, Planar: its
    /// coordinates are defined from obj1's side) whose obj1 lies on the far side of the world.
    #[error("{kind} joint `{joint}`: obj1 `{obj1}` must lie on the world side of obj2 `{obj2}`; swap obj1 and obj2 (and, for a Universal joint, axis1 and axis2)")]
    ReversedJoint {
        /// The joint.
        joint: String,
        /// Its kind.
        kind: &'static str,
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
    /// Two solids that can collide start deeper inside each other than the contact law can
    /// push apart (found when the model is built, with the narrow phase at the initial state).
    #[error("objects `{object1}` and `{object2}` start {depth:.3e} m inside each other{}, deeper than {limit:.3e} m (half the extent of the thinner one): the contact force would throw them apart or stall the solver; {}", if *.coincident { " (their centres coincide)" } else { "" }, match .size_slip { Some(s) => format!("likely cause: {s}"), None => "move one of them out of the other, or turn collision off for one of them (`Solid::collision(false)`)".into() })]
    InitialPenetration {
        /// The first object of the pair.
        object1: String,
        /// The second object.
        object2: String,
        /// Initial penetration depth \[m\] (minus the signed distance).
        depth: f64,
        /// The deepest admissible initial penetration \[m\].
        limit: f64,
        /// The two shapes' centres coincide.
        coincident: bool,
        /// One of the two is far larger than the scene's other collision solids (the unit
        /// check of sizes, also a `SimWarning::ScaleOutlier` of every run): the likely cause.
        size_slip: Option<Box<SizeSlip>>,
    },
    /// A joint spring-damper or joint input on a joint without a scalar coordinate.
    #[error("joint spring-damper or input on `{joint}`: a {kind} joint has no scalar coordinate; use a joint with one (Revolute, Prismatic, Cylindrical, Universal, Planar)")]
    NoScalarCoordinate {
        /// The joint.
        joint: String,
        /// Its kind.
        kind: &'static str,
    },
    /// A joint limit on a joint without a scalar coordinate.
    #[error("joint `{joint}` has a limit, but a {kind} joint has no scalar coordinate; limit a joint with one (Revolute, Prismatic, Cylindrical, Universal, Planar)")]
    LimitWithoutCoordinate {
        /// The joint.
        joint: String,
        /// Its kind.
        kind: &'static str,
    },
    /// A joint limit whose lower bound is not below its upper one.
    #[error("joint `{joint}`: the limits of `{coordinate}` are lower {lower} ≥ upper {upper} [{unit}]; the lower bound must be below the upper one: swap them or widen the range")]
    LimitRange {
        /// The joint.
        joint: String,
        /// The coordinate.
        coordinate: &'static str,
        /// Lower bound.
        lower: f64,
        /// Upper bound.
        upper: f64,
        /// Unit of both (`"rad"` or `"m"`).
        unit: &'static str,
    },
    /// A joint whose initial coordinate lies outside its limits.
    #[error("joint `{joint}`: initial `{coordinate}` = {value} {unit} lies outside its limits [{lower}, {upper}] {unit}; start it between the stops (or on one) or move the stops")]
    LimitOutside {
        /// The joint.
        joint: String,
        /// The coordinate.
        coordinate: &'static str,
        /// Its initial value.
        value: f64,
        /// Lower bound (`−inf`: none).
        lower: f64,
        /// Upper bound (`inf`: none).
        upper: f64,
        /// Unit (`"rad"` or `"m"`).
        unit: &'static str,
    },
    /// Limits on a joint that closes a kinematic loop (a cut joint: its coordinates are no
    /// states, so no stop can act on them).
    #[error("joint `{joint}` has limits but closes a kinematic loop (it is the loop's cut joint, whose coordinates are no states of the model), so its stops cannot act; mark another joint of the loop `cut = true` (`Joint::cut(true)`) so this one stays in the tree, or put the limits on another joint of the loop")]
    LimitOnCutJoint {
        /// The joint.
        joint: String,
    },
    /// Two limits on one coordinate of a joint.
    #[error("joint `{joint}` has two limits on `{coordinate}`; give one limit per coordinate with both bounds (`JointLimit::range`)")]
    LimitTwice {
        /// The joint.
        joint: String,
        /// The coordinate.
        coordinate: &'static str,
    },
    /// A joint spring-damper or joint input that names no coordinate of a joint with several.
    #[error("{referrer}: a {kind} joint has the coordinates {coordinates}; name one (`coordinate = \"…\"`)")]
    AmbiguousCoordinate {
        /// The spring-damper or input, in words.
        referrer: String,
        /// The joint's kind.
        kind: &'static str,
        /// Its coordinates, listed.
        coordinates: String,
    },
    /// A component whose parameters are invalid ([`crate::scene::Component::check`]).
    #[error("component `{component}` ({kind}): {reason}")]
    ComponentParameter {
        /// The component.
        component: String,
        /// Its kind (`"PI"`).
        kind: &'static str,
        /// What is wrong and what to do.
        reason: String,
    },
    /// A component input wired to a signal that does not exist.
    #[error("component `{component}`'s input `{port}` reads unknown signal `{path}`{}; a signal is `time`, a component's output or state (`pi.y`, `pi.x`) or a joint coordinate's position or velocity (`rev.phi`, `rev.w`)", hint_text(.hint))]
    UnknownSignal {
        /// The component.
        component: String,
        /// Its input port.
        port: String,
        /// The path read.
        path: String,
        /// A close existing signal, if any.
        hint: Option<String>,
    },
    /// A component input wired that the component does not have, or wired twice.
    #[error("component `{component}` ({kind}) has no input `{port}` or wires it twice; its inputs are {ports}")]
    UnknownPort {
        /// The component.
        component: String,
        /// Its kind.
        kind: &'static str,
        /// The port named.
        port: String,
        /// Its ports, listed.
        ports: String,
    },
    /// A component input left unwired.
    #[error("component `{component}` ({kind}): input `{port}` is not wired; give it a source (a signal path, an expression or a constant)")]
    UnwiredInput {
        /// The component.
        component: String,
        /// Its kind.
        kind: &'static str,
        /// The port.
        port: String,
    },
    /// Components that read each other's outputs at the same instant with no state between.
    #[error("algebraic loop through components {}: each reads the next one's output at the same instant and no state lies between; put a state in the loop (a FirstOrder filter, an Integrator) or sample one of them (`Sampled`)", list(.cycle))]
    AlgebraicLoop {
        /// The components on the loop, in order.
        cycle: Vec<String>,
    },
    /// A component's flange or input on a cut joint of a kinematic loop.
    #[error("component `{component}` uses joint `{joint}`, which closes a kinematic loop (its coordinates are no states of the model); mark another joint of the loop `cut = true` so this one stays in the tree")]
    ComponentOnCutJoint {
        /// The component.
        component: String,
        /// The joint.
        joint: String,
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
///
/// `Debug` (what `fn main() -> Result<(), Box<dyn Error>>` prints for `build()?`) is the
/// message, each error with its hint, then the variants, e.g.
/// `(SceneError::UnknownParent; the errors are in e.0)`, not a nested struct dump.
#[derive(thiserror::Error, Clone, PartialEq)]
pub struct SceneErrors(pub Vec<SceneError>);

impl fmt::Debug for SceneErrors {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        // The variant's name is the derived `Debug` of `SceneError` up to its fields.
        let variants = self
            .0
            .iter()
            .map(|e| {
                let d = format!("{e:?}");
                let name = d.split([' ', '{', '(']).next().unwrap_or_default();
                format!("SceneError::{name}")
            })
            .collect::<Vec<_>>()
            .join(", ");
        write!(f, "{self}\n  ({variants}; the errors are in e.0)")
    }
}

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

/// Collects the errors of one validation round.
pub(crate) struct Checker {
    /// Every error found so far, in the order found.
    pub(crate) errors: Vec<SceneError>,
}

impl Checker {
    pub(crate) fn value(
        &mut self,
        what: impl FnOnce() -> String,
        v: f64,
        ok: bool,
        expected: &'static str,
    ) {
        if !ok || !v.is_finite() {
            self.errors.push(SceneError::InvalidValue {
                what: what(),
                value: v,
                expected,
            });
        }
    }
    pub(crate) fn finite(&mut self, what: impl Fn() -> String, vals: &[f64]) {
        for &v in vals {
            self.value(&what, v, true, "finite");
        }
    }
    pub(crate) fn positive(&mut self, what: impl FnOnce() -> String, v: f64) {
        self.value(what, v, v > 0.0, "finite and > 0");
    }
    pub(crate) fn non_negative(&mut self, what: impl FnOnce() -> String, v: f64) {
        self.value(what, v, v >= 0.0, "finite and ≥ 0");
    }
}

/// A collision solid far larger than the scene's others: a suspected length in the wrong unit
/// (the unit check of sizes; see [`SceneError::InitialPenetration`]).
#[derive(Clone, Debug, PartialEq)]
pub struct SizeSlip {
    /// The object.
    pub object: String,
    /// Its largest extent \[m\].
    pub size: f64,
    /// The median of the largest extents of the scene's other collision solids \[m\].
    pub median: f64,
}

impl std::fmt::Display for SizeSlip {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(
            f,
            "`{}` is {:.3e} m across, {:.0} times the median {:.3e} m of the scene's other \
             collision solids: a length in the wrong unit? (a diameter of 100 meant as 100 mm \
             is 0.1 m; check the shape's dimensions and, for a mesh, its scale)",
            self.object,
            self.size,
            self.size / self.median,
            self.median
        )
    }
}

/// A link of a closed loop too long for the others to reach round (see
/// [`SceneError::ImpossibleLoop`]): in a loop of joints that keep their frames' origins
/// together (revolute, spherical, universal, fixed) the joints' points form a polygon whose
/// sides are the links, and no side of a closed polygon is longer than the others together.
#[derive(Clone, Debug, PartialEq)]
pub struct LoopReach {
    /// The object of the link's first joint frame.
    pub from: String,
    /// The object of its second joint frame (on the same rigid part).
    pub to: String,
    /// The link's length: the distance between the two frames' origins \[m\].
    pub length: f64,
    /// The lengths of the loop's other links added up \[m\].
    pub others: f64,
}

impl std::fmt::Display for LoopReach {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(
            f,
            "the links are too short to reach: the link from `{}` to `{}` is {:.4e} m between \
             its joints, longer than the {:.4e} m of all the other links together, so no \
             joint angles close the loop; lengthen the other links or shorten that one",
            self.from, self.to, self.length, self.others
        )
    }
}
