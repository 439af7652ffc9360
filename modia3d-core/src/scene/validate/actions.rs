//! Validation of scheduled actions: object names resolved (with hints), times and gaps in
//! range, an object not attached to itself. Whether an action can be carried out (the object
//! free, within the gap) depends on the state at its time and is checked then
//! (`simulation/segments.rs`).

use super::{Checker, Names};
use crate::scene::actions::ActionKind;
use crate::scene::desc::SceneDesc;

/// Checks every action of `desc`.
pub(super) fn actions(c: &mut Checker, desc: &SceneDesc, names: &Names) {
    for a in &desc.actions {
        let who = || format!("action `{}`", a.name);
        c.value(
            || format!("{}: time [s]", who()),
            a.at,
            a.at >= 0.0,
            "finite and ≥ 0",
        );
        names.resolve(c, format!("{}'s object", who()), a.object());
        if let ActionKind::Attach { object, to, gap } = &a.kind {
            c.value(
                || format!("{}: gap [m]", who()),
                *gap,
                *gap >= 0.0,
                "finite and ≥ 0",
            );
            names.resolve(c, format!("{}'s `to`", who()), to);
            if object == to {
                c.errors.push(super::SceneError::AttachToItself {
                    action: a.name.clone(),
                    object: object.clone(),
                });
            }
        }
    }
}
