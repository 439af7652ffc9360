//! Validation of joints: ends resolved and distinct; each kind's parameters (unit axes, finite
//! initial values, unit quaternions, …) are checked by the kind's own file in `joints/`
//! (`joints::validate_kind`), with the scene's `Checker`, in the same round as every other check. Topology (loops, two parents, connectivity) is `topology.rs`.

use super::{Checker, Names, SceneError, ValidJoint};
use crate::scene::desc::{SceneDesc, SceneOptions};

/// Every joint resolved and checked, in declaration order; a joint with an error is left out
/// and its resolved ends marked in `suspect` (they may now look unconnected).
pub(super) fn joints(
    c: &mut Checker,
    desc: &SceneDesc,
    names: &Names,
    suspect: &mut [bool],
    options: &SceneOptions,
) -> Vec<ValidJoint> {
    let mut joints = Vec::with_capacity(desc.joints.len());
    for j in &desc.joints {
        let o1 = names.resolve(c, format!("joint `{}`'s obj1", j.name), &j.obj1);
        let o2 = names.resolve(c, format!("joint `{}`'s obj2", j.name), &j.obj2);
        let kind = crate::joints::validate_kind(c, &j.name, &j.kind);
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
            can_collide: j
                .can_collide
                .unwrap_or(options.modia3d_conventions && j.kind.facts().modia3d_can_collide),
            cut: j.cut,
        });
    }

    joints
}
