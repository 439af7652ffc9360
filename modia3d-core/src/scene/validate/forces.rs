//! Validation of force elements and inputs: references resolved (joints with a scalar
//! coordinate where one is needed), values in range, names unique.

use super::{
    did_you_mean, Checker, Names, SceneError, ValidForce, ValidInput, ValidInputKind, ValidJoint,
};
use crate::scene::desc::{ForceElement, InputKind, SceneDesc};
use crate::scene::{Law, VectorLaw};

/// Every force element resolved and checked.
pub(super) fn forces(
    c: &mut Checker,
    desc: &SceneDesc,
    names: &Names,
    joints: &[ValidJoint],
) -> Vec<ValidForce> {
    let mut forces = vec![];
    for f in &desc.forces {
        match f {
            ForceElement::SpringDamper {
                name,
                obj1,
                obj2,
                stiffness,
                damping,
                length0,
            } => {
                let (spring, damper) = (Law::Linear(*stiffness), Law::Linear(*damping));
                if let Some(f) =
                    point_to_point(c, names, name, obj1, obj2, *length0, &spring, &damper)
                {
                    forces.push(f);
                }
            }
            ForceElement::SpringDamperPtP {
                name,
                obj1,
                obj2,
                length0,
                spring,
                damper,
            } => {
                if let Some(f) =
                    point_to_point(c, names, name, obj1, obj2, *length0, spring, damper)
                {
                    forces.push(f);
                }
            }
            ForceElement::Bushing(b) => {
                let what = |w: &str| format!("bushing `{}`: {w}", b.name);
                c.finite(|| what("nominal force [N]"), b.nominal_force.as_slice());
                c.finite(|| what("nominal torque [N·m]"), b.nominal_torque.as_slice());
                let laws = [
                    ("stiffness [N/m]", &b.spring),
                    ("damping [N·s/m]", &b.damper),
                    ("rotational stiffness [N·m/rad]", &b.rot_spring),
                    ("rotational damping [N·m·s/rad]", &b.rot_damper),
                ];
                for (label, laws) in laws {
                    for (axis, law) in ["x", "y", "z"].iter().zip(laws) {
                        linear_coefficient(c, || what(&format!("{label} along {axis}")), law);
                    }
                }
                let a = names.resolve(c, format!("bushing `{}`'s obj1", b.name), &b.obj1);
                let o = names.resolve(c, format!("bushing `{}`'s obj2", b.name), &b.obj2);
                if let (Some(obj1), Some(obj2)) = (a, o) {
                    forces.push(ValidForce::Bushing {
                        obj1,
                        obj2,
                        spec: b.clone(),
                    });
                }
            }
            ForceElement::WorldForce {
                name,
                object,
                force: value,
                resolved_in,
            }
            | ForceElement::WorldTorque {
                name,
                object,
                torque: value,
                resolved_in,
            } => {
                let torque = matches!(f, ForceElement::WorldTorque { .. });
                let kind = if torque { "WorldTorque" } else { "WorldForce" };
                if let VectorLaw::Constant(v) = value {
                    let unit = if torque { "[N·m]" } else { "[N]" };
                    c.finite(
                        || format!("{kind} on `{object}`: value {unit}"),
                        v.as_slice(),
                    );
                }
                let o = names.resolve(c, format!("{kind} on `{object}`"), object);
                // `Some(None)`: resolved in world; `None`: an unknown object (reported).
                let r = match resolved_in {
                    None => Some(None),
                    Some(r) => names
                        .resolve(c, format!("{kind} on `{object}`'s resolved_in"), r)
                        .map(Some),
                };
                if let (Some(object), Some(resolved_in)) = (o, r) {
                    forces.push(ValidForce::WorldVector {
                        name: name.clone(),
                        object,
                        value: value.clone(),
                        resolved_in,
                        torque,
                    });
                }
            }
            ForceElement::JointSpringDamper {
                joint,
                coordinate,
                stiffness,
                damping,
                offset,
            } => {
                let what = |w: &str| format!("spring-damper on joint `{joint}`: {w}");
                c.non_negative(|| what("stiffness"), *stiffness);
                c.non_negative(|| what("damping"), *damping);
                c.finite(|| what("offset"), &[*offset]);
                let referrer = format!("spring-damper on joint `{joint}`");
                if let Some((valid, coordinate)) =
                    joint_coordinate(c, desc, names, joints, &referrer, joint, coordinate)
                {
                    forces.push(ValidForce::JointSpringDamper {
                        joint: valid,
                        coordinate,
                        stiffness: *stiffness,
                        damping: *damping,
                        offset: *offset,
                    });
                }
            }
            ForceElement::ObjectForce { object, law } => {
                if let Some(o) = names.resolve(c, "object force".into(), object) {
                    forces.push(ValidForce::ObjectForce {
                        object: o,
                        law: law.clone(),
                    });
                }
            }
        }
    }

    forces
}

/// A point-to-point spring-damper (`SpringDamper`, `SpringDamperPtP`) checked and resolved.
#[allow(clippy::too_many_arguments)]
fn point_to_point(
    c: &mut Checker,
    names: &Names,
    name: &str,
    obj1: &str,
    obj2: &str,
    length0: f64,
    spring: &Law,
    damper: &Law,
) -> Option<ValidForce> {
    let what = |w: &str| format!("spring-damper `{name}`: {w}");
    linear_coefficient(c, || what("stiffness [N/m]"), spring);
    linear_coefficient(c, || what("damping [N·s/m]"), damper);
    c.non_negative(|| what("unstretched length [m]"), length0);
    let a = names.resolve(c, format!("spring-damper `{name}`'s obj1"), obj1);
    let b = names.resolve(c, format!("spring-damper `{name}`'s obj2"), obj2);
    Some(ValidForce::SpringDamper {
        name: name.to_string(),
        obj1: a?,
        obj2: b?,
        spring: spring.clone(),
        damper: damper.clone(),
        length0,
    })
}

/// A linear law's coefficient must be finite and ≥ 0 (a closure is the user's).
fn linear_coefficient(c: &mut Checker, what: impl FnOnce() -> String, law: &Law) {
    if let Law::Linear(k) = law {
        c.non_negative(what, *k);
    }
}

/// Every input resolved and checked; a joint has at most one prescribed acceleration.
pub(super) fn inputs(
    c: &mut Checker,
    desc: &SceneDesc,
    names: &Names,
    joints: &[ValidJoint],
) -> Vec<ValidInput> {
    let mut inputs = vec![];
    let mut input_names = std::collections::HashSet::new();
    let mut driven = std::collections::HashSet::new();
    for inp in &desc.inputs {
        if !input_names.insert(inp.name.as_str()) {
            c.errors.push(SceneError::DuplicateName {
                kind: "input",
                name: inp.name.clone(),
            });
        }
        let referrer = format!("input `{}`", inp.name);
        let joint = |c: &mut Checker, jn: &str, co: &Option<String>| {
            joint_coordinate(c, desc, names, joints, &referrer, jn, co)
        };
        let kind = match &inp.kind {
            InputKind::JointForce {
                joint: jn,
                coordinate,
            } => joint(c, jn, coordinate).map(|(j, k)| ValidInputKind::JointForce(j, k)),
            InputKind::JointAcceleration {
                joint: jn,
                coordinate,
            } => {
                let j = joint(c, jn, coordinate);
                if let Some((_, k)) = j {
                    if !driven.insert((jn.as_str(), k)) {
                        c.errors.push(SceneError::DuplicateName {
                            kind: "prescribed-acceleration joint",
                            name: jn.clone(),
                        });
                    }
                }
                j.map(|(j, k)| ValidInputKind::JointAcceleration(j, k))
            }
            InputKind::ObjectWrench { object } => names
                .resolve(c, format!("input `{}`", inp.name), object)
                .map(ValidInputKind::ObjectWrench),
        };
        if let Some(kind) = kind {
            inputs.push(ValidInput {
                name: inp.name.clone(),
                kind,
            });
        }
    }

    inputs
}

/// The index of the scalar coordinate `coordinate` (`None`: the only one) of a joint of the
/// kind `facts` with scalar coordinates, that `referrer` (a spring-damper, input or limit, in
/// words) names; errors for an unknown name, or no name where several exist.
pub(super) fn coordinate_index(
    c: &mut Checker,
    referrer: &str,
    facts: &crate::joints::Facts,
    coordinate: &Option<String>,
) -> Option<usize> {
    let (kind, coords) = (facts.spec.name, facts.spec.coordinates);
    match coordinate {
        None if coords.len() == 1 => Some(0),
        None => {
            c.errors.push(SceneError::AmbiguousCoordinate {
                referrer: referrer.to_string(),
                kind,
                coordinates: coords
                    .iter()
                    .map(|c| format!("`{}`", c.name))
                    .collect::<Vec<_>>()
                    .join(", "),
            });
            None
        }
        Some(name) => {
            let k = coords.iter().position(|c| c.name == name);
            if k.is_none() {
                c.errors.push(SceneError::Unknown {
                    referrer: format!("{referrer} (a {kind} joint)"),
                    kind: "joint coordinate",
                    name: name.clone(),
                    hint: did_you_mean(name, coords.iter().map(|c| c.name)),
                });
            }
            k
        }
    }
}

/// The validated joint and the index of its scalar coordinate `coordinate` (`None`: its only
/// one) that a spring-damper or input (`referrer`) acts on; errors for an unknown joint, a kind
/// without scalar coordinates, an unknown coordinate name, or no name where several exist.
pub(super) fn joint_coordinate(
    c: &mut Checker,
    desc: &SceneDesc,
    names: &Names,
    joints: &[ValidJoint],
    referrer: &str,
    joint: &str,
    coordinate: &Option<String>,
) -> Option<(usize, usize)> {
    let Some(&ji) = names.joint_index.get(joint) else {
        c.errors.push(SceneError::Unknown {
            referrer: referrer.to_string(),
            kind: "joint",
            name: joint.to_string(),
            hint: did_you_mean(joint, desc.joints.iter().map(|j| j.name.as_str())),
        });
        return None;
    };
    let facts = desc.joints[ji].kind.facts();
    let (kind, coords) = (facts.spec.name, facts.spec.coordinates);
    if coords.is_empty() {
        c.errors.push(SceneError::NoScalarCoordinate {
            joint: joint.to_string(),
            kind,
        });
        return None;
    }
    let k = coordinate_index(c, referrer, facts, coordinate)?;
    // A joint with an invalid value was dropped (its error is reported).
    let valid = joints.iter().position(|vj| vj.name == joint)?;
    Some((valid, k))
}
