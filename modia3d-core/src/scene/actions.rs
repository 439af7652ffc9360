//! Description stage: scheduled changes of the structure (Modia3D's model actions), plain data
//! referring to objects by name. An [`Action`] at time `at` attaches a free object rigidly to
//! another (gripping, within `gap`), releases an attached object into free motion, or deletes an
//! object. The driver (`simulation/segments.rs`) carries them out between IDA segments; the same
//! changes are available step-wise as `Simulation::attach`, `release` and `delete`.

use super::desc::SceneDesc;

/// What an action does (after Modia3D's `ActionAttach`, `ActionRelease`, `ActionDelete`).
#[derive(Clone, Debug, PartialEq)]
pub enum ActionKind {
    /// Fix `object` (now moved by a FreeMotion joint) rigidly to `to` at their current relative
    /// pose; allowed only while the two are at most `gap` apart (see
    /// `Simulation::attach_within`). The velocities jump as in a perfectly plastic impact:
    /// momentum is conserved.
    Attach {
        /// The free object (obj2 of a FreeMotion joint), e.g. the workpiece.
        object: String,
        /// The object it is fixed to, e.g. the gripper.
        to: String,
        /// Largest distance between the two for which the attach happens \[m\] (≥ 0).
        gap: f64,
    },
    /// Give `object` (attached by an earlier `Attach`, or rigidly parented) a FreeMotion joint
    /// relative to the world at its current absolute pose and velocity.
    Release {
        /// The object to release.
        object: String,
    },
    /// Remove `object`, the objects rigidly attached to it as children, their joints, force
    /// elements and inputs.
    Delete {
        /// The object to delete.
        object: String,
    },
}

/// A scheduled structure change: `kind` at time `at`.
#[derive(Clone, Debug, PartialEq)]
pub struct Action {
    /// Name (for the event log).
    pub name: String,
    /// When it happens \[s\] (finite, ≥ 0). Actions at the same time run in declaration order.
    pub at: f64,
    /// What it does.
    pub kind: ActionKind,
}

impl Action {
    /// Attach `object` to `to` at `at` \[s\] if they are at most `gap` \[m\] apart.
    pub fn attach(name: &str, at: f64, object: &str, to: &str, gap: f64) -> Self {
        Action {
            name: name.into(),
            at,
            kind: ActionKind::Attach {
                object: object.into(),
                to: to.into(),
                gap,
            },
        }
    }
    /// Release `object` into free motion at `at` \[s\].
    pub fn release(name: &str, at: f64, object: &str) -> Self {
        Action {
            name: name.into(),
            at,
            kind: ActionKind::Release {
                object: object.into(),
            },
        }
    }
    /// Delete `object` at `at` \[s\].
    pub fn delete(name: &str, at: f64, object: &str) -> Self {
        Action {
            name: name.into(),
            at,
            kind: ActionKind::Delete {
                object: object.into(),
            },
        }
    }
    /// The object the action moves or removes.
    pub fn object(&self) -> &str {
        match &self.kind {
            ActionKind::Attach { object, .. }
            | ActionKind::Release { object }
            | ActionKind::Delete { object } => object,
        }
    }
    /// A short description for the event log, e.g. ``attach `box` to `gripper` ``.
    pub fn describe(&self) -> String {
        match &self.kind {
            ActionKind::Attach { object, to, .. } => format!("attach `{object}` to `{to}`"),
            ActionKind::Release { object } => format!("release `{object}`"),
            ActionKind::Delete { object } => format!("delete `{object}`"),
        }
    }
}

impl SceneDesc {
    /// Schedules a structure change (see [`Action`]).
    pub fn add_action(&mut self, action: Action) -> &mut Self {
        self.actions.push(action);
        self
    }
}
