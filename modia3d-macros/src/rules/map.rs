//! Scene rules, mapping: each error of the core's `scene_errors` on the probe scene → an
//! error on the user's token, in the slot where the old per-key checks stood; errors about
//! stand-ins, about names (the macro's own checks) and follow-ups are dropped.

use super::{is_stand_in, Probe};
use crate::check::{compact, Errors};
use crate::ir::{
    ActionIr, FeatureIr, ForceIr, InputIr, Ir, Item, JointIr, MaterialName, ObjectIr, Parent,
    SolidIr,
};
use crate::names::NameRef;
use modia3d_core::scene::{builtin_solid_names, SceneError};
use modia3d_core::JOINT_KINDS;
use proc_macro2::{Ident, Span};
use std::collections::HashMap;

/// Maps the core's errors to the user's tokens.
pub(super) struct Mapper<'a> {
    pub(super) ir: &'a Ir,
    pub(super) probe: &'a Probe<'a>,
    pub(super) assembly: bool,
    pub(super) macro_errors: bool,
    pub(super) used: Vec<bool>,
    /// How many errors of a kind were mapped per name (`NoScalarCoordinate`, duplicate drives).
    pub(super) consumed: HashMap<(u8, String), usize>,
}

/// The first name in backticks of a core message part (`object `ball`: …` → `ball`).
fn first_name(what: &str) -> Option<&str> {
    let start = what.find('`')? + 1;
    let len = what[start..].find('`')?;
    Some(&what[start..start + len])
}

impl<'a> Mapper<'a> {
    fn object(&self, name: &str) -> Option<&'a Item> {
        self.ir
            .items
            .iter()
            .find(|it| matches!(it, Item::Object(ObjectIr { name: n, .. }) if n == name))
    }

    fn solid(&self, name: &str) -> Option<&'a SolidIr> {
        match self.object(name)? {
            Item::Object(ObjectIr {
                feature: Some(FeatureIr::Solid(s)),
                ..
            }) => Some(s),
            _ => None,
        }
    }

    fn joint(&self, name: &str) -> Option<(&'a NameRef, &'a NameRef)> {
        self.ir.items.iter().find_map(|it| match it {
            Item::Joint(JointIr {
                name: n,
                obj1,
                obj2,
                ..
            }) if n == name => Some((obj1, obj2)),
            _ => None,
        })
    }

    /// The span of a component's name.
    fn component(&self, name: &str) -> Option<&'a Ident> {
        self.ir
            .kinds
            .iter()
            .find(|(n, _)| n == name)
            .map(|(n, _)| n)
    }

    pub(super) fn map_all(mut self, found: Vec<SceneError>, errors: &mut Errors) {
        let (unconnected, found): (Vec<_>, Vec<_>) = found
            .into_iter()
            .partition(|e| matches!(e, SceneError::NotConnected { .. }));
        for e in found {
            if let Some((slot, err)) = self.map(&e, errors) {
                errors.push_at(slot, err);
            }
        }
        // A part not connected to the world is reported only for a block the macro sees
        // whole (no values known only at run time) and that has no other error: so it never
        // hides rustc's type errors, nor adds to a block's real mistakes; `build()` reports
        // the rest.
        if errors.any() || self.probe.run_time_values {
            return;
        }
        for e in unconnected {
            if let Some((slot, err)) = self.map(&e, errors) {
                errors.push_at(slot, err);
            }
        }
    }

    /// The error for one core error and its slot, or `None` if it concerns a stand-in, a
    /// rule the macro states itself (names, the `Scene`), or a follow-up.
    fn map(&mut self, e: &SceneError, errors: &mut Errors) -> Option<(u32, syn::Error)> {
        use SceneError as E;
        let new = |span: Span, msg: String| syn::Error::new(span, msg);
        match e {
            E::InvalidValue {
                what,
                value,
                expected,
            } => {
                let owner = first_name(what)?;
                if is_stand_in(owner) {
                    return None;
                }
                let hit = self
                    .probe
                    .nums
                    .iter()
                    .enumerate()
                    .position(|(i, (o, _, l))| {
                        !self.used[i] && o == owner && l.value.to_bits() == value.to_bits()
                    });
                if let Some(i) = hit {
                    self.used[i] = true;
                    let (_, key, l) = &self.probe.nums[i];
                    // A literal is finite: the range is the part of the rule that can fail.
                    let range = expected.trim_start_matches("finite and ");
                    let msg = format!("`{key}` must be {range}, found `{}`", compact(&l.expr));
                    return Some((l.slot, syn::Error::new_spanned(&l.expr, msg)));
                }
                let id = self.component(owner)?;
                Some((errors.slot(), new(id.span(), e.to_string())))
            }
            E::Unknown {
                referrer,
                kind: "solid material",
                name,
                hint,
            } => {
                let s = self.solid(first_name(referrer)?)?;
                // With Modia3D conventions a contact material names the solid material of the
                // contact stiffness: reported on the contact material's token.
                let by_contact = referrer.contains("contact material");
                let (span, slot) = if by_contact {
                    (&s.contact_material.as_ref()?.1, &s.mass_slot)
                } else {
                    let (_, span, slot) = s.material.as_ref()?;
                    (span, slot)
                };
                let what = if by_contact {
                    "with Modia3D conventions the contact material names the solid material of the contact stiffness; "
                } else {
                    ""
                };
                let h = match hint {
                    Some(h) => format!("did you mean `{h}`?"),
                    None => format!(
                        "the built-in ones are {}; or define it in the block: `{} = SolidMaterial(…)`",
                        builtin_solid_names()
                            .map(|n| format!("`{n}`"))
                            .collect::<Vec<_>>()
                            .join(", "),
                        name.to_lowercase().replace(|c: char| !c.is_alphanumeric(), "_"),
                    ),
                };
                Some((
                    *slot,
                    new(
                        *span,
                        format!("unknown solid material `{name}` ({what}hint: {h})"),
                    ),
                ))
            }
            E::NoMassSource { object, .. } => {
                let s = self.solid(object)?;
                if s.material.is_some() {
                    return None; // the material's name is unknown: reported on its token
                }
                Some((
                    s.mass_slot,
                    new(
                        s.span,
                        "`Solid(…)` has no mass: add `solid_material = \"…\"` (mass from density) or `mass_properties = MassProperties(mass = …)`".into(),
                    ),
                ))
            }
            E::CollisionWithoutMaterial { object } | E::CollisionWithoutShape { object } => {
                let (_, _, key, slot) = self.solid(object)?.collision.as_ref()?;
                let msg = if matches!(e, E::CollisionWithoutShape { .. }) {
                    "`collision = true` needs a shape (hint: add `shape = …`)"
                } else {
                    "`collision = true` needs a material (hint: add `solid_material = \"…\"` or `contact_material = \"…\"`)"
                };
                Some((*slot, new(*key, msg.into())))
            }
            _ => self.map_structure(e, errors),
        }
    }

    /// [`Mapper::map`] for topology, contact pairs and joint drives.
    fn map_structure(&mut self, e: &SceneError, errors: &mut Errors) -> Option<(u32, syn::Error)> {
        use SceneError as E;
        let new = |span: Span, msg: String| syn::Error::new(span, msg);
        match e {
            E::ParentCycle { objects } => {
                if objects.iter().any(|o| is_stand_in(o)) {
                    return None;
                }
                let last = objects.last()?;
                let Some(Item::Object(ObjectIr {
                    parent: Parent::Ref(r),
                    ..
                })) = self.object(last)
                else {
                    return None;
                };
                let list = objects
                    .iter()
                    .map(|n| format!("`{n}`"))
                    .collect::<Vec<_>>()
                    .join(" → ");
                Some((
                    errors.slot(),
                    new(
                        r.span,
                        format!(
                            "parent cycle: {list} → `{}` (hint: a parent chain must end at a root; remove one `parent`)",
                            objects[0]
                        ),
                    ),
                ))
            }
            E::TwoParents { object, joints } => {
                let first = joints.first()?;
                let mut out: Option<syn::Error> = None;
                for j in &joints[1..] {
                    let (_, o2) = self.joint(j)?;
                    crate::ast::push(
                        &mut out,
                        new(
                            o2.span,
                            format!(
                                "object `{object}` has two parents: it is already obj2 of joint `{first}` (hint: an object is moved by one joint only, unless the joints close a loop; swap obj1 and obj2, or join another object)"
                            ),
                        ),
                    );
                }
                Some((errors.slot(), out?))
            }
            E::IdenticalJointEnds { joint, object } => {
                let (_, o2) = self.joint(joint)?;
                Some((
                    errors.slot(),
                    new(
                        o2.span,
                        format!("joint `{joint}` joins `{object}` to itself (hint: obj1 and obj2 must differ)"),
                    ),
                ))
            }
            E::AttachToItself { action, object } => {
                let (to, slot) = self.ir.items.iter().find_map(|it| match it {
                    Item::Action {
                        name,
                        action: ActionIr::Attach { to, .. },
                        slot,
                        ..
                    } if name == action => Some((to, *slot)),
                    _ => None,
                })?;
                Some((
                    slot,
                    new(
                        to.span,
                        format!("action `{action}` attaches `{object}` to itself (hint: `object` and `to` must differ)"),
                    ),
                ))
            }
            E::KinematicLoop { objects } => {
                if objects.iter().any(|o| is_stand_in(o)) {
                    return None;
                }
                self.kinematic_loop(objects, errors)
            }
            E::ReversedFreeMotion { joint, obj1, obj2 } => {
                if is_stand_in(obj1) || is_stand_in(obj2) {
                    return None;
                }
                let (o1, _) = self.joint(joint)?;
                Some((
                    errors.slot(),
                    new(
                        o1.span,
                        format!("FreeMotion `{joint}`: obj1 `{obj1}` must lie on the world side of obj2 `{obj2}` (hint: swap obj1 and obj2)"),
                    ),
                ))
            }
            E::NotConnected { object } => {
                if self.assembly
                    || self.probe.has_assemblies
                    || self.macro_errors
                    || is_stand_in(object)
                {
                    return None;
                }
                let id = self.component(object)?;
                Some((
                    errors.slot(),
                    new(
                        id.span(),
                        format!("object `{object}` is not connected to the world (hint: give it a `parent`, or connect it with a joint: a `FreeMotion` for a free body)"),
                    ),
                ))
            }
            E::MissingContactPair {
                material1,
                material2,
                object1,
                object2,
            } => {
                if self.assembly
                    || self.macro_errors
                    || self.probe.has_assemblies
                    || self.probe.pairs_unsure
                    || [material1, material2, object1, object2]
                        .iter()
                        .any(|n| is_stand_in(n))
                {
                    return None;
                }
                let (w1, _) = self.written(object1)?;
                let (w2, span) = self.written(object2)?;
                let ident = |s: &str| {
                    s.to_lowercase()
                        .replace(|c: char| !c.is_alphanumeric(), "_")
                };
                let pname = format!("{}_{}", ident(material1), ident(material2));
                Some((
                    errors.slot(),
                    new(
                        span,
                        format!(
                            "no contact-pair material for `{material1}` and `{material2}`: solids `{object1}` and `{object2}` can collide (hint: add `{pname} = ContactPair(material1 = {w1}, material2 = {w2}, cor = …, mu_k = …, mu_r = …)`)"
                        ),
                    ),
                ))
            }
            _ => self.map_drives(e),
        }
    }

    /// [`Mapper::map`] for joint drives and joint spring-dampers.
    fn map_drives(&mut self, e: &SceneError) -> Option<(u32, syn::Error)> {
        use SceneError as E;
        let new = |span: Span, msg: String| syn::Error::new(span, msg);
        match e {
            E::NoScalarCoordinate { joint, kind } => {
                if is_stand_in(joint) {
                    return None;
                }
                let (ctor, r, slot) = self.nth_driver(0, joint, |it| match it {
                    Item::Force {
                        force: ForceIr::JointSpringDamper { joint, .. },
                        slot,
                        ..
                    } => Some(("JointSpringDamper", joint, *slot)),
                    Item::Input {
                        input: InputIr::JointForce(j, _),
                        slot,
                        ..
                    } => Some(("JointForce", j, *slot)),
                    Item::Input {
                        input: InputIr::JointAcceleration(j, _),
                        slot,
                        ..
                    } => Some(("JointAcceleration", j, *slot)),
                    _ => None,
                })?;
                // The kinds with scalar coordinates, from the core's table.
                let kinds = JOINT_KINDS
                    .iter()
                    .filter(|k| !k.coordinates.is_empty())
                    .map(|k| k.name)
                    .collect::<Vec<_>>()
                    .join(", ");
                Some((
                    slot,
                    new(
                        r.span,
                        format!("`{ctor}` needs a joint with a scalar coordinate ({kinds}), but `{joint}` is a {kind} (hint: its rotation is a quaternion, with no single coordinate to drive)"),
                    ),
                ))
            }
            E::DuplicateName {
                kind: "prescribed-acceleration joint",
                name,
            } => {
                let drives = |it: &'a Item| match it {
                    Item::Input {
                        name,
                        input: InputIr::JointAcceleration(j, _),
                        slot,
                    } => Some((name, j, *slot)),
                    _ => None,
                };
                let first = self
                    .ir
                    .items
                    .iter()
                    .filter_map(drives)
                    .find(|(_, j, _)| j.path == *name)?
                    .0;
                // The core reports the second, third, … drive of the joint.
                let (_, r, slot) = self.nth_driver(1, name, |it| {
                    drives(it).map(|(_, j, s)| ("JointAcceleration", j, s))
                })?;
                Some((
                    slot,
                    new(
                        r.span,
                        format!("joint `{name}` already has a prescribed acceleration: input `{first}` (hint: one `JointAcceleration` per joint)"),
                    ),
                ))
            }
            E::AmbiguousCoordinate {
                referrer,
                kind,
                coordinates,
            } => {
                let (r, _, slot) = self.coordinate_user(referrer, None)?;
                Some((
                    slot,
                    new(
                        r.span,
                        format!("`{}` is a {kind} joint with the coordinates {coordinates} (hint: name one: `coordinate = \"…\"`)", r.path),
                    ),
                ))
            }
            E::Unknown {
                referrer,
                kind: "joint coordinate",
                name,
                hint,
            } => {
                if is_stand_in(name) {
                    return None;
                }
                let (r, span, slot) = self.coordinate_user(referrer, Some(name))?;
                let h = hint
                    .as_ref()
                    .map(|h| format!(" (hint: did you mean `{h}`?)"))
                    .unwrap_or_default();
                Some((
                    slot,
                    new(
                        span,
                        format!("joint `{}` has no coordinate `{name}`{h}", r.path),
                    ),
                ))
            }
            // Names, references and the `Scene` are the macro's own checks (`check/`);
            // the plan's checks (mass matrix, FreeMotion direction) are not scene rules.
            _ => None,
        }
    }

    /// The next not yet mapped item (after skipping `skip`) that drives or springs `joint`, in
    /// the order the core checks them (force elements, then inputs).
    fn nth_driver(
        &mut self,
        skip: usize,
        joint: &str,
        f: impl Fn(&'a Item) -> Option<(&'static str, &'a NameRef, u32)>,
    ) -> Option<(&'static str, &'a NameRef, u32)> {
        let key = (skip as u8, joint.to_string());
        let n = self.consumed.entry(key).or_insert(0);
        let forces = self
            .ir
            .items
            .iter()
            .filter(|it| matches!(it, Item::Force { .. }));
        let inputs = self
            .ir
            .items
            .iter()
            .filter(|it| matches!(it, Item::Input { .. }));
        let hit = forces
            .chain(inputs)
            .filter_map(f)
            .filter(|(_, r, _)| r.path == joint)
            .nth(*n + skip);
        *n += 1;
        hit
    }

    /// The spring-damper (`spring-damper on joint `j``) or input (`input `name``) the core
    /// names in `referrer` whose literal coordinate is `coordinate` (`None`: not given): its
    /// joint reference, the span of its coordinate (else of the joint) and its error slot.
    fn coordinate_user(
        &self,
        referrer: &str,
        coordinate: Option<&str>,
    ) -> Option<(&'a NameRef, Span, u32)> {
        let who = first_name(referrer)?;
        if is_stand_in(who) {
            return None;
        }
        let spring = referrer.starts_with("spring-damper");
        let fits = |c: &'a Option<(syn::Expr, Option<String>)>| match (c, coordinate) {
            (None, None) => Some(None),
            (Some((e, Some(lit))), Some(want)) if lit == want => Some(Some(e)),
            _ => None,
        };
        let found = self.ir.items.iter().find_map(|it| match it {
            Item::Force {
                force:
                    ForceIr::JointSpringDamper {
                        joint, coordinate, ..
                    },
                slot,
                ..
            } if spring && joint.path == who => fits(coordinate).map(|e| (joint, e, *slot)),
            Item::Input {
                name,
                input: InputIr::JointForce(j, c) | InputIr::JointAcceleration(j, c),
                slot,
            } if !spring && *name == who => fits(c).map(|e| (j, e, *slot)),
            _ => None,
        })?;
        let (r, e, slot) = found;
        let span = e.map_or(r.span, syn::spanned::Spanned::span);
        Some((r, span, slot))
    }

    /// How a colliding solid's contact material is written in a `ContactPair(…)`, and its
    /// token.
    fn written(&self, object: &str) -> Option<(String, Span)> {
        let s = self.solid(object)?;
        if let Some((m, span)) = &s.contact_material {
            let MaterialName::Named(n, _) = m else {
                return None;
            };
            return Some((format!("{n:?}"), *span));
        }
        let (m, span, _) = s.material.as_ref()?;
        match m {
            MaterialName::Local(n) => Some((n.clone(), *span)),
            MaterialName::Named(n, _) => Some((format!("{n:?}"), *span)),
            MaterialName::Expr(_) => None,
        }
    }

    /// A loop closed by the joint between its first two objects (the core names them first).
    fn kinematic_loop(&self, objects: &[String], errors: &mut Errors) -> Option<(u32, syn::Error)> {
        let (a, b) = (objects.first()?, objects.get(1)?);
        let closing = self.ir.items.iter().rev().find_map(|it| match it {
            Item::Joint(JointIr {
                name, obj1, obj2, ..
            }) if (obj1.path == *a && obj2.path == *b) || (obj1.path == *b && obj2.path == *a) => {
                Some((name, obj1, obj2))
            }
            _ => None,
        });
        let (name, obj1, obj2) = closing?;
        Some((
            errors.slot(),
            syn::Error::new(
                obj2.span,
                format!(
                    "rigid kinematic loop: joint `{name}` joins `{}` and `{}`, which are already rigidly connected by `parent` links and Fix joints, so it can never move (hint: remove this joint or a `parent` of the loop; closed chains of moving joints are fine)",
                    obj1.path, obj2.path
                ),
            ),
        ))
    }
}
