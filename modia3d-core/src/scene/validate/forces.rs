//! Validation of force elements and inputs: references resolved (joints with a scalar
//! coordinate where one is needed), values in range, names unique.

use super::{
    did_you_mean, Checker, Names, SceneError, ValidForce, ValidInput, ValidInputKind, ValidJoint,
};
use crate::scene::desc::{ForceElement, InputKind, SceneDesc};

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
                let what = |w: &str| format!("spring-damper `{name}`: {w}");
                c.non_negative(|| what("stiffness [N/m]"), *stiffness);
                c.non_negative(|| what("damping [N·s/m]"), *damping);
                c.non_negative(|| what("unstretched length [m]"), *length0);
                let a = names.resolve(c, format!("spring-damper `{name}`'s obj1"), obj1);
                let b = names.resolve(c, format!("spring-damper `{name}`'s obj2"), obj2);
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

/// The validated joint and the index of its scalar coordinate `coordinate` (`None`: its only
/// one) that a spring-damper or input (`referrer`) acts on; errors for an unknown joint, a kind
/// without scalar coordinates, an unknown coordinate name, or no name where several exist.
fn joint_coordinate(
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
    let kind = desc.joints[ji].kind.name();
    let coords = crate::joints::info(kind).map_or(&[][..], |i| i.coordinates);
    if coords.is_empty() {
        c.errors.push(SceneError::NoScalarCoordinate {
            joint: joint.to_string(),
            kind,
        });
        return None;
    }
    let k = match coordinate {
        None if coords.len() == 1 => 0,
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
            return None;
        }
        Some(name) => match coords.iter().position(|c| c.name == name) {
            Some(k) => k,
            None => {
                c.errors.push(SceneError::Unknown {
                    referrer: format!("{referrer} (a {kind} joint)"),
                    kind: "joint coordinate",
                    name: name.clone(),
                    hint: did_you_mean(name, coords.iter().map(|c| c.name)),
                });
                return None;
            }
        },
    };
    // A joint with an invalid value was dropped (its error is reported).
    let valid = joints.iter().position(|vj| vj.name == joint)?;
    Some((valid, k))
}
