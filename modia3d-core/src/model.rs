//! Model stage: compiles a validated scene, in one place, into the two immutable plans a run
//! shares — the multibody [`Plan`] (dynamics) and, beside it, the collision pipeline's
//! [`ContactPlan`] (`None` without candidate pairs). Neither plan refers to the other: the DAE
//! stage takes both. A model is data: its runners ([`Model::simulate`], [`Model::simulation`])
//! are the driver's (`simulation.rs`) and its signal names the result store's
//! (`results/mod.rs`), so this file imports nothing above the plans.
// No panic on user input: indexing goes through `get` and iterators (issue 15's audit).
#![deny(clippy::indexing_slicing)]

use crate::contact::ContactPlan;
use crate::dynamics::Plan;
use crate::scene::{SceneDesc, SceneErrors, ValidScene};
use std::sync::Arc;

/// A compiled, runnable model. Cheap to clone; runs share the immutable plans. `Debug` prints
/// a summary (bodies, joints, state length, collision pairs), not the plans.
#[derive(Clone)]
pub struct Model {
    /// The multibody plan: bodies, joint tree, state layout, mass properties.
    pub(crate) plan: Arc<Plan>,
    /// The collision pipeline; `None` when the scene has no candidate pair (then no collision
    /// code runs and there are no root functions).
    pub(crate) contact: Option<Arc<ContactPlan>>,
    /// The description it was built from (the structure changes of a segmented run edit a
    /// copy and build again; `simulation/segments.rs`).
    pub(crate) desc: Arc<SceneDesc>,
}

impl std::fmt::Debug for Model {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Model")
            .field("bodies", &self.plan.bodies.len())
            .field("joints", &self.joint_names())
            .field("state_len", &self.state_len())
            .field(
                "collision_shapes",
                &self.contact.as_ref().map(|c| c.shapes.len()),
            )
            .finish_non_exhaustive()
    }
}

/// A candidate collision pair and its constants (fixed when the model is built; the damping
/// factor is fixed when a contact starts), see `docs/contact-model.md` §3.
#[derive(Clone, Debug, PartialEq)]
pub struct ContactPairInfo {
    /// `"<object a>|<object b>"`, the owner part of its signals (normal from a to b).
    pub name: String,
    /// Coefficient of restitution [-].
    pub cor: f64,
    /// Sliding friction coefficient [-].
    pub mu_k: f64,
    /// Rolling resistance coefficient [-].
    pub mu_r: f64,
    /// Regularisation velocity [m/s] of the `cor` blend (and of a point law's friction).
    pub v_min: f64,
    /// Regularisation velocity of sliding and spin friction [m/s]: `v_min` for a point law;
    /// for the volume law the pair material's `v_min`, else `SceneOptions::v_min_volume`,
    /// raised for a light body under a heavy scene (up to 10×; docs/contact-model.md §3.2,
    /// "Friction's regularisation").
    pub v_slip: f64,
    /// Regularisation angular velocity [rad/s].
    pub w_min: f64,
    /// Combined elastic modulus `c_res = 1 / (1/c_1 + 1/c_2)` [N/m²].
    pub c_res: f64,
    /// Geometry coefficient `μ_geo` \[m\] (1 for the linear law).
    pub mu_geo: f64,
    /// Geometry coefficient `c_geo` [m^(1/2)] (1 for the linear law).
    pub c_geo: f64,
    /// Exponent of the penetration `n_geo` [-]: 3/2 (Hertz) or 1 (point laws only).
    pub n_geo: f64,
    /// `Some(κ)` for a pair with the volume law (docs/contact-model.md §3.2): its stiffness per
    /// unit overlap volume `κ = κ_a κ_b/(κ_a + κ_b)` \[N/m³\] (before `k_red`); `None` for a
    /// point law (then `c_res`, `μ_geo`, `c_geo`, `n_geo` define it).
    pub volume_stiffness: Option<f64>,
}

/// A moving body of a model: objects rigidly attached to each other, moved by one joint.
#[derive(Clone, Debug, PartialEq)]
pub struct BodyInfo {
    /// The joint that moves it.
    pub joint: String,
    /// Its objects, in declaration order.
    pub objects: Vec<String>,
    /// Combined mass \[kg\].
    pub mass: f64,
}

/// A closed kinematic loop of a model: its cut joint and how its constraints were assembled
/// (see `dynamics/loops.rs`).
#[derive(Clone, Debug, PartialEq)]
pub struct LoopInfo {
    /// The cut joint (kept out of the joint tree, enforced by constraints); its constraint
    /// force and torque are the signals `<cut>.f` \[N\] and `<cut>.t` [N·m].
    pub cut: String,
    /// The joints of the loop, the cut joint first.
    pub joints: Vec<String>,
    /// Number of constraint rows kept (independent) for this cut joint.
    pub rows: usize,
    /// Rows dropped as redundant, `"<cut>.<row>"` (`x`, `y`, `z`: translations along obj1's
    /// axes; `rot_x`…: rotations; `align0`…: axis alignments).
    pub dropped: Vec<String>,
}

impl SceneDesc {
    /// Validates and compiles the scene into a runnable model.
    pub fn build(&self) -> Result<Model, SceneErrors> {
        let mut model = Model::compile(self.validated()?)?;
        model.desc = Arc::new(self.clone());
        Ok(model)
    }
}

impl Model {
    /// Compiles both plans of a validated scene. The mass-matrix positivity check and the
    /// initial penetrations come last: they need the compiled plans and the initial state (see
    /// `mass_matrix::check_inertia` for why they are not validation checks; `contact/initial.rs`).
    pub(crate) fn compile(valid: ValidScene) -> Result<Model, SceneErrors> {
        Model::finish(Plan::compile(valid), true)
    }

    /// The rest of [`Model::compile`] on a laid-out plan whose `q0`, `v0` the caller may have
    /// set (a segment's start, `simulation/segments.rs`); `penetration`: run the
    /// initial-penetration check (a user-input check, skipped at a segment's start).
    pub(crate) fn finish(mut plan: Plan, penetration: bool) -> Result<Model, SceneErrors> {
        // Closed loops: redundant rows dropped, q0 and v0 projected onto the constraints.
        crate::dynamics::loops::assemble_initial(&mut plan).map_err(|e| SceneErrors(vec![e]))?;
        let contact =
            ContactPlan::compile(&plan.scene, &plan.objects, &plan.bodies).map_err(SceneErrors)?;
        crate::dynamics::mass_matrix::check_inertia(&plan)?;
        crate::dynamics::forces::check_gravity_centre(&plan)?;
        if let Some(cp) = contact.as_ref().filter(|_| penetration) {
            let deep = crate::contact::initial_penetrations(&plan, cp);
            if !deep.is_empty() {
                return Err(SceneErrors(deep));
            }
        }
        Ok(Model {
            plan: Arc::new(plan),
            contact: contact.map(Arc::new),
            desc: Arc::default(),
        })
    }

    /// The candidate collision pairs (after the preprocessing rules, `docs/contact-model.md`
    /// §2.1) with their constants, in the order of their signals; empty without collisions.
    pub fn contact_pairs(&self) -> Vec<ContactPairInfo> {
        let Some(cp) = self.contact.as_deref() else {
            return vec![];
        };
        cp.candidate_pairs()
            .map(|pp| ContactPairInfo {
                name: cp.pair_name(&self.plan.scene, &pp),
                cor: pp.cor,
                mu_k: pp.mu_k,
                mu_r: pp.mu_r,
                v_min: pp.v_min,
                v_slip: pp.v_slip,
                w_min: pp.w_min,
                c_res: pp.c_res,
                mu_geo: pp.mu_geo,
                c_geo: pp.c_geo,
                n_geo: pp.n_geo,
                volume_stiffness: (pp.law != crate::contact::PairLaw::Point).then_some(pp.kappa),
            })
            .collect()
    }

    /// Names of the joints that carry states (Fix joints are merged away), parents first.
    pub fn joint_names(&self) -> Vec<&str> {
        self.plan.joints.iter().map(|j| j.name.as_str()).collect()
    }

    /// The moving bodies, parents first: the objects rigidly attached to each other that one
    /// joint moves, with their combined mass \[kg\].
    pub fn bodies(&self) -> Vec<BodyInfo> {
        self.plan
            .bodies
            .iter()
            .map(|b| BodyInfo {
                joint: self
                    .plan
                    .joints
                    .get(b.joint)
                    .map(|j| j.name.clone())
                    .unwrap_or_default(),
                objects: b
                    .objects
                    .iter()
                    .filter_map(|&o| self.plan.objects.get(o))
                    .map(|o| o.name.clone())
                    .collect(),
                mass: b.inertia.mass,
            })
            .collect()
    }

    /// The closed kinematic loops, one per cut joint; empty for a tree.
    pub fn loops(&self) -> Vec<LoopInfo> {
        let lp = &self.plan.loops;
        lp.cuts
            .iter()
            .enumerate()
            .map(|(c, cut)| LoopInfo {
                cut: cut.name.clone(),
                joints: cut.loop_joints.clone(),
                rows: lp.kept.iter().filter(|k| k.0 == c).count(),
                dropped: lp
                    .dropped
                    .iter()
                    .filter(|d| {
                        d.strip_prefix(cut.name.as_str())
                            .is_some_and(|r| r.starts_with('.'))
                    })
                    .cloned()
                    .collect(),
            })
            .collect()
    }

    /// The coordinates treated as independent when the loops were closed at the initial state
    /// (`"joint.phi"`, `"joint.s"`, `"free.w[0]"`…): the build kept them at the given values and
    /// moved the others onto the constraints. Empty without loops.
    pub fn independent_coordinates(&self) -> Vec<String> {
        crate::dynamics::loops::independent_names(&self.plan, &self.plan.loops.independent)
    }

    /// Number of unknowns `y = [q; v]` of the DAE (without the loop multipliers).
    pub fn state_len(&self) -> usize {
        self.plan.nq + self.plan.nv
    }

    /// Names of the declared inputs.
    pub fn input_names(&self) -> Vec<&str> {
        self.plan.inputs.iter().map(|i| i.name.as_str()).collect()
    }
}
