//! DAE stage: the residual `F(t, y, y') = 0` of a plan, with `y = [q; v]`:
//! `q̇ − q̇(q, v) = 0` (kinematics) and `M(q) v̇ + C(q, v) − τ_applied = 0` (dynamics, by
//! inverse dynamics, so no mass matrix is formed). The residual is a short list of stage calls
//! and allocates nothing.

use crate::dynamics::{forces, kinematics, rnea, Plan, Workspace};
use crate::solver::{DaeSystem, ResidualError};
use std::sync::Arc;

/// The multibody DAE of a plan, with its scratch workspace.
#[derive(Clone, Debug)]
pub struct MultibodyDae {
    plan: Arc<Plan>,
    ws: Workspace,
}

impl MultibodyDae {
    /// The DAE of `plan`.
    pub fn new(plan: Arc<Plan>) -> Self {
        let ws = Workspace::new(&plan);
        MultibodyDae { plan, ws }
    }
    /// The plan.
    pub fn plan(&self) -> &Plan {
        &self.plan
    }
    /// The workspace (after the last evaluation).
    pub fn workspace_mut(&mut self) -> &mut Workspace {
        &mut self.ws
    }
    /// Derivative `y'` consistent with `y` at time `t` [s]; `None` if the mass matrix is
    /// singular there.
    pub fn consistent_derivative(&mut self, t: f64, y: &[f64]) -> Option<Vec<f64>> {
        let (nq, nv) = (self.plan.nq, self.plan.nv);
        let (q, v) = y.split_at(nq);
        let mut yp = vec![0.0; nq + nv];
        kinematics::position_derivative(&self.plan, q, v, &mut yp[..nq]);
        let vd = crate::dynamics::mass_matrix::consistent_accelerations(
            &self.plan,
            &mut self.ws,
            t,
            q,
            v,
        )?;
        yp[nq..].copy_from_slice(&vd);
        Some(yp)
    }
}

impl DaeSystem for MultibodyDae {
    fn len(&self) -> usize {
        self.plan.nq + self.plan.nv
    }

    fn residual(
        &mut self,
        t: f64,
        y: &[f64],
        yp: &[f64],
        res: &mut [f64],
    ) -> Result<(), ResidualError> {
        let plan = &*self.plan;
        let nq = plan.nq;
        let (q, v) = y.split_at(nq);
        let (qd, vd) = yp.split_at(nq);
        let (res_q, res_v) = res.split_at_mut(nq);
        kinematics::position_velocity(plan, &mut self.ws, q, v);
        forces::applied_forces(plan, &mut self.ws, t, q, v);
        kinematics::position_residual(plan, q, v, qd, res_q);
        rnea::inverse_dynamics(plan, &mut self.ws, vd, &plan.gravity, res_v);
        for (r, tau) in res_v.iter_mut().zip(&self.ws.tau_applied) {
            *r -= tau;
        }
        Ok(())
    }
}
