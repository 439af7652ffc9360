//! Model stage: compiles a validated scene, in one place, into the two immutable plans a run
//! shares — the multibody [`Plan`] (dynamics) and, beside it, the collision pipeline's
//! [`ContactPlan`] (`None` without candidate pairs) — and is the entry point of a run
//! ([`Model::simulate`], [`Model::simulation`]). Neither plan refers to the other: the DAE
//! stage takes both.

use crate::contact::ContactPlan;
use crate::dynamics::Plan;
use crate::results::SimulationResult;
use crate::scene::{SceneDesc, SceneErrors, ValidScene};
use crate::simulation::{SimError, SimOptions, Simulation};
use std::sync::Arc;

/// A compiled, runnable model. Cheap to clone; runs share the immutable plans.
#[derive(Clone, Debug)]
pub struct Model {
    /// The multibody plan: bodies, joint tree, state layout, mass properties.
    pub(crate) plan: Arc<Plan>,
    /// The collision pipeline; `None` when the scene has no candidate pair (then no collision
    /// code runs and there are no root functions).
    pub(crate) contact: Option<Arc<ContactPlan>>,
}

impl SceneDesc {
    /// Validates and compiles the scene into a runnable model.
    pub fn build(&self) -> Result<Model, SceneErrors> {
        Model::compile(self.validate()?)
    }
}

impl Model {
    /// Compiles both plans of a validated scene. The mass-matrix positivity check comes last:
    /// it needs the compiled plan and an inverse-dynamics pass at the initial state (see
    /// `Plan::check_inertia` for why it is not a validation check).
    pub(crate) fn compile(valid: ValidScene) -> Result<Model, SceneErrors> {
        let plan = Plan::compile(valid);
        let contact = ContactPlan::compile(&plan.scene, &plan.objects).map_err(SceneErrors)?;
        plan.check_inertia()?;
        Ok(Model {
            plan: Arc::new(plan),
            contact: contact.map(Arc::new),
        })
    }

    /// The compiled plan.
    pub fn plan(&self) -> &Plan {
        &self.plan
    }

    /// The compiled collision pipeline, `None` without candidate pairs.
    pub fn contact_plan(&self) -> Option<&ContactPlan> {
        self.contact.as_deref()
    }

    /// Runs the model with error control from `opts.start_time` to `opts.stop_time`.
    pub fn simulate(&self, opts: &SimOptions) -> Result<SimulationResult, SimError> {
        crate::simulation::run(self, opts)
    }

    /// A step-wise simulation of this model (see [`Simulation`]); the plans are shared, not
    /// recompiled.
    pub fn simulation(&self, opts: &SimOptions) -> Result<Simulation, SimError> {
        Simulation::new(self, opts)
    }
}
