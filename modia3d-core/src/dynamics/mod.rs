//! Dynamics stage: the compiled plan (immutable), the workspace (mutable scratch), and the O(n)
//! recursive algorithms that make up the multibody residual: forward kinematics, applied
//! forces, recursive Newton–Euler inverse dynamics. Touches scene data (read-only) and its own
//! workspace.

pub mod forces;
pub mod kinematics;
pub mod loops;
pub mod mass_matrix;
pub mod plan;
pub mod rnea;
pub mod spatial;

pub use plan::{InputTarget, JointCoord, ObjectPlan, Plan};

use spatial::{Force, Motion, Transform};

/// Mutable per-body scratch of the recursive algorithms; allocated once per plan, so the
/// residual allocates nothing.
#[derive(Clone, Debug)]
pub struct Workspace {
    /// Body frame placed in its parent body's frame (world for root bodies).
    pub x: Vec<Transform>,
    /// Body frame placed in world.
    pub world: Vec<Transform>,
    /// Spatial velocity of the body, resolved in the body frame.
    pub vel: Vec<Motion>,
    /// Joint velocity `S q̇`, resolved in the body frame.
    pub vj: Vec<Motion>,
    /// Spatial acceleration, resolved in the body frame.
    pub acc: Vec<Motion>,
    /// Spatial force transmitted by the body's joint, resolved in the body frame.
    pub f: Vec<Force>,
    /// External force on the body about its origin, resolved in the body frame.
    pub f_ext: Vec<Force>,
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
    pub fn new(plan: &Plan) -> Self {
        let nb = plan.bodies.len();
        Workspace {
            x: vec![Transform::default(); nb],
            world: vec![Transform::default(); nb],
            vel: vec![Motion::zero(); nb],
            vj: vec![Motion::zero(); nb],
            acc: vec![Motion::zero(); nb],
            f: vec![Force::default(); nb],
            f_ext: vec![Force::default(); nb],
            tau_applied: vec![0.0; plan.nv],
            inputs: vec![0.0; plan.n_inputs],
            fault: None,
        }
    }
}
