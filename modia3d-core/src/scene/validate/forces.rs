//! Validation of force elements and inputs: references resolved (joints with a scalar
//! coordinate where one is needed), values in range, names unique.

use super::{
    did_you_mean, Checker, Names, SceneError, ValidForce, ValidInput, ValidInputKind, ValidJoint,
};
use crate::scene::desc::{ForceElement, InputKind, JointKind, SceneDesc};

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
                stiffness,
                damping,
                offset,
            } => {
                let what = |w: &str| format!("spring-damper on joint `{joint}`: {w}");
                c.non_negative(|| what("stiffness"), *stiffness);
                c.non_negative(|| what("damping"), *damping);
                c.finite(|| what("offset"), &[*offset]);
                match names.joint_index.get(joint.as_str()) {
                    None => c.errors.push(SceneError::Unknown {
                        referrer: "joint spring-damper".into(),
                        kind: "joint",
                        name: joint.clone(),
                        hint: did_you_mean(joint, desc.joints.iter().map(|j| j.name.as_str())),
                    }),
                    Some(&ji) => {
                        let k = &desc.joints[ji].kind;
                        if !matches!(k, JointKind::Revolute { .. } | JointKind::Prismatic { .. }) {
                            c.errors.push(SceneError::NoScalarCoordinate {
                                joint: joint.clone(),
                                kind: k.name(),
                            });
                        } else if let Some(valid) = joints.iter().position(|vj| vj.name == *joint) {
                            forces.push(ValidForce::JointSpringDamper {
                                joint: valid,
                                coordinate: 0,
                                stiffness: *stiffness,
                                damping: *damping,
                                offset: *offset,
                            });
                        }
                    }
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
        let joint = |c: &mut Checker, jn: &str| -> Option<usize> {
            let Some(&ji) = names.joint_index.get(jn) else {
                c.errors.push(SceneError::Unknown {
                    referrer: format!("input `{}`", inp.name),
                    kind: "joint",
                    name: jn.to_string(),
                    hint: did_you_mean(jn, desc.joints.iter().map(|j| j.name.as_str())),
                });
                return None;
            };
            let k = &desc.joints[ji].kind;
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
            InputKind::JointForce { joint: jn } => joint(c, jn).map(ValidInputKind::JointForce),
            InputKind::JointAcceleration { joint: jn } => {
                let j = joint(c, jn);
                if j.is_some() && !driven.insert(jn.as_str()) {
                    c.errors.push(SceneError::DuplicateName {
                        kind: "prescribed-acceleration joint",
                        name: jn.clone(),
                    });
                }
                j.map(ValidInputKind::JointAcceleration)
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
