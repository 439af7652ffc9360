//! Validation of joints: ends resolved and distinct, kinds with unit axes (a universal joint's
//! perpendicular), finite initial values and unit quaternions. The per-kind parameter checks
//! live here, not in `joints/`, because they produce the scene's typed errors with the
//! scene's `Checker` in the same round as every other check (this stage compiles with and
//! without the `solver` feature; `joints/` supplies the solver-free facts of a kind). Topology (loops, two parents, connectivity) is `topology.rs`.

use super::{Checker, Names, SceneError, ValidJoint, ValidJointKind};
use crate::scene::desc::{FreeRotation, JointKind, SceneDesc};
use nalgebra::{Rotation3, UnitQuaternion, Vector3};

/// Largest admissible `|‖q‖ − 1|` of a FreeMotion's initial quaternion (round-off of a
/// normalised quaternion is ~1e-16; a user's rounded literal digits stay well inside).
const UNIT_QUATERNION_TOLERANCE: f64 = 1e-6;

/// Largest admissible `|cos|` of the angle between a universal joint's axes (as the quaternion
/// norm: rounded literal digits pass, a wrong axis does not).
const PERPENDICULAR_TOLERANCE: f64 = 1e-6;

/// Every joint resolved and checked, in declaration order; a joint with an error is left out
/// and its resolved ends marked in `suspect` (they may now look unconnected).
pub(super) fn joints(
    c: &mut Checker,
    desc: &SceneDesc,
    names: &Names,
    suspect: &mut [bool],
) -> Vec<ValidJoint> {
    let mut joints = Vec::with_capacity(desc.joints.len());
    for j in &desc.joints {
        let o1 = names.resolve(c, format!("joint `{}`'s obj1", j.name), &j.obj1);
        let o2 = names.resolve(c, format!("joint `{}`'s obj2", j.name), &j.obj2);
        let kind = check_joint_kind(c, &j.name, &j.kind);
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
            cut: j.cut,
        });
    }

    joints
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
            ValidJointKind::FreeMotion {
                r: *r,
                rot: rotation(c, joint, rot),
                v: *v,
                w: *w,
            }
        }
        JointKind::Spherical { rot, w } => {
            c.finite(
                || format!("joint `{joint}`: initial w [rad/s]"),
                w.as_slice(),
            );
            ValidJointKind::Spherical {
                rot: rotation(c, joint, rot),
                w: *w,
            }
        }
        JointKind::Universal {
            axis1,
            axis2,
            phi1,
            phi2,
            w1,
            w2,
        } => {
            c.finite(
                || format!("joint `{joint}`: initial phi1, phi2 [rad], w1, w2 [rad/s]"),
                &[*phi1, *phi2, *w1, *w2],
            );
            let (a1, a2) = (axis_of(c, axis1), axis_of(c, axis2));
            let cos = a1.dot(&a2);
            if cos.is_finite() && cos.abs() > PERPENDICULAR_TOLERANCE {
                c.errors.push(SceneError::InvalidValue {
                    what: format!("joint `{joint}`: cosine of the angle between axis1 and axis2"),
                    value: cos,
                    expected: "0 within 1e-6 (a universal joint's axes are perpendicular)",
                });
            }
            ValidJointKind::Universal {
                axis1: a1,
                // Exactly perpendicular from here on (the joint is dropped if the check failed).
                axis2: (a2 - a1 * cos).normalize(),
                phi1: *phi1,
                phi2: *phi2,
                w1: *w1,
                w2: *w2,
            }
        }
        JointKind::Cylindrical { axis, phi, s, w, v } => {
            c.finite(
                || format!("joint `{joint}`: initial phi [rad], s [m], w [rad/s], v [m/s]"),
                &[*phi, *s, *w, *v],
            );
            ValidJointKind::Cylindrical {
                axis: axis_of(c, axis),
                phi: *phi,
                s: *s,
                w: *w,
                v: *v,
            }
        }
        JointKind::Planar {
            normal,
            x,
            y,
            phi,
            vx,
            vy,
            w,
        } => {
            c.finite(
                || format!("joint `{joint}`: initial x, y [m], phi [rad], vx, vy [m/s], w [rad/s]"),
                &[*x, *y, *phi, *vx, *vy, *w],
            );
            ValidJointKind::Planar {
                normal: axis_of(c, normal),
                x: *x,
                y: *y,
                phi: *phi,
                vx: *vx,
                vy: *vy,
                w: *w,
            }
        }
    };
    (c.errors.len() == before).then_some(kind)
}

/// The unit quaternion of an initial rotation (FreeMotion, Spherical): Cardan angles finite, a
/// given quaternion finite and of unit norm.
fn rotation(c: &mut Checker, joint: &str, rot: &FreeRotation) -> UnitQuaternion<f64> {
    match rot {
        FreeRotation::Cardan(a) => {
            c.finite(
                || format!("joint `{joint}`: initial Cardan angles [rad]"),
                a,
            );
            UnitQuaternion::from_rotation_matrix(&Rotation3::from_matrix_unchecked(
                crate::scene::desc::cardan_to_matrix(*a),
            ))
        }
        FreeRotation::Quaternion(q) => {
            c.finite(
                || format!("joint `{joint}`: initial quaternion"),
                q.coords.as_slice(),
            );
            // A `UnitQuaternion` made with `new_unchecked` may be anything: a zero
            // (or far from unit) quaternion is no rotation, and the solver would
            // fail on it later without naming the joint.
            let n = q.coords.norm();
            if n.is_finite() && (n - 1.0).abs() > UNIT_QUATERNION_TOLERANCE {
                c.errors.push(SceneError::InvalidValue {
                    what: format!("joint `{joint}`: norm of the initial quaternion"),
                    value: n,
                    expected: "1 within 1e-6 (a unit quaternion: build it with UnitQuaternion::from_quaternion or new_normalize, not new_unchecked)",
                });
            }
            // Exactly unit from here on (the joint is dropped if the check failed).
            UnitQuaternion::new_normalize(q.into_inner())
        }
    }
}
