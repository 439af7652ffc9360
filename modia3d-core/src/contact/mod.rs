//! Contact stage (`docs/contact-model.md` §2–§4): the collision pairs compiled once from the
//! scene ([`ContactPlan`], immutable, in `preprocess.rs`), the contact set and per-pair state
//! ([`ContactState`], mutable, in `contact_set.rs`), the regularisations (`regularise.rs`) and
//! the elastic response (`response.rs`); the build-time check of initial penetrations
//! (`initial.rs`). Reads the dynamics workspace (poses, velocities) and
//! writes only external forces into it (`ws.f_ext`, through `add_world_wrench`).
//!
//! Evaluation modes ([`Mode`]): `Event` (rebuild the contact set, store `δ̇⁻`),
//! `ZeroCrossing` (all `z_AB`, set kept), `Continuous` (only pairs in the set, for forces).
//! A scene without candidate pairs has no `ContactPlan` at all, so none of this runs.
//! Joint limits (`limits.rs`) are stops in joint space that share the events, root functions
//! and restitution of the pairs; a scene without limits has no `LimitPlan`.

mod contact_set;
pub(crate) mod initial;
mod limits;
mod pair_jacobian;
mod preprocess;
mod regularise;
mod response;
mod restitution;
mod step_guard;

// `ContactError` is public (re-exported by lib.rs: `SimErrorKind::Contact` carries it); the
// rest of the contact stage is internal.
pub use contact_set::ContactError;
pub(crate) use contact_set::{ContactState, Mode, PairGeometry, PairState, RestingPair};
pub(crate) use initial::initial_penetrations;
pub use limits::DEFAULT_STOP_FREQUENCY;
pub(crate) use limits::{LimitPlan, LimitState};
pub(crate) use pair_jacobian::{pair_wrench_jacobian, PER_BODY};
pub(crate) use preprocess::{ContactPlan, PairLaw};
pub(crate) use regularise::CLAMP_BAND;
pub(crate) use step_guard::StepGuard;
