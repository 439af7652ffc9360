//! Dynamics stage: the compiled plan (immutable), the workspace (mutable scratch), and the O(n)
//! recursive algorithms that make up the multibody residual: forward kinematics, applied
//! forces, recursive Newton–Euler inverse dynamics. Touches scene data (read-only) and its own
//! workspace.

pub(crate) mod components;
pub(crate) mod forces;
pub(crate) mod ids;
pub(crate) mod kinematics;
pub(crate) mod loads;
pub(crate) mod loops;
pub(crate) mod mass_matrix;
pub(crate) mod plan;
pub(crate) mod rnea;

pub(crate) use ids::{BodyId, IdVec, ObjectId};
pub(crate) use plan::{InputTarget, ObjectPlan, Plan};

use crate::spatial::{Force, Motion, Transform};

/// Mutable per-body scratch of the recursive algorithms; allocated once per plan, so the
/// residual allocates nothing.
#[derive(Clone, Debug)]
pub(crate) struct Workspace {
    /// Body frame placed in its parent body's frame (world for root bodies).
    pub x: IdVec<BodyId, Transform>,
    /// The joint's own transform `X_J(q)` (`x` without the joint's tree placement): the
    /// Newton–Euler pass turns a free joint's accelerations and forces with its rotation
    /// instead of forming it from the quaternion again.
    pub xj: IdVec<BodyId, Transform>,
    /// Body frame placed in world.
    pub world: IdVec<BodyId, Transform>,
    /// Spatial velocity of the body, resolved in the body frame.
    pub vel: IdVec<BodyId, Motion>,
    /// Joint velocity `S q̇`, resolved in the body frame.
    pub vj: IdVec<BodyId, Motion>,
    /// Joint bias `c_J = Ṡ q̇`, resolved in the body frame (set only for joints whose `S`
    /// depends on `q`, see `JointCoord::has_bias`).
    pub cj: IdVec<BodyId, Motion>,
    /// Spatial acceleration, resolved in the body frame.
    pub acc: IdVec<BodyId, Motion>,
    /// Spatial force transmitted by the body's joint, resolved in the body frame.
    pub f: IdVec<BodyId, Force>,
    /// External force on the body about its origin, resolved in the body frame.
    pub f_ext: IdVec<BodyId, Force>,
    /// Generalised forces from joint springs, dampers and inputs (len nv).
    pub tau_applied: Vec<f64>,
    /// Current input values (len `Plan::n_inputs`), 0 until set.
    pub inputs: Vec<f64>,
    /// The first failure of a user force law since it was last taken (a panic caught at the
    /// call, or a non-finite wrench); the law's contribution is left out meanwhile and the
    /// caller ends the run with it (see [`forces::UserFault`]).
    pub fault: Option<forces::UserFault>,
}

impl Workspace {
    /// Scratch sized for `plan`.
    pub(crate) fn new(plan: &Plan) -> Self {
        let nb = plan.bodies.len();
        Workspace {
            x: vec![Transform::default(); nb].into(),
            xj: vec![Transform::default(); nb].into(),
            world: vec![Transform::default(); nb].into(),
            vel: vec![Motion::zero(); nb].into(),
            vj: vec![Motion::zero(); nb].into(),
            cj: vec![Motion::zero(); nb].into(),
            acc: vec![Motion::zero(); nb].into(),
            f: vec![Force::default(); nb].into(),
            f_ext: vec![Force::default(); nb].into(),
            tau_applied: vec![0.0; plan.nv],
            inputs: vec![0.0; plan.n_inputs],
            fault: None,
        }
    }
}
