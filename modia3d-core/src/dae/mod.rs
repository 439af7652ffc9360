//! DAE stage: the residual `F(t, y, y') = 0` of a plan, with `y = [q; v]`:
//! `q̇ − q̇(q, v) = 0` (kinematics) and `M(q) v̇ + C(q, v) − τ_applied − τ_contact = 0`
//! (dynamics, by inverse dynamics, so no mass matrix is formed), and the two zero-crossing
//! functions of the contact set (none without collision pairs). The residual is a short list of
//! stage calls and allocates nothing.

use crate::contact::{
    ContactError, ContactPlan, ContactState, LimitPlan, LimitState, Mode, RestingPair, StepGuard,
};
use crate::dynamics::components::{ComponentState, Point};
use crate::dynamics::forces::UserFault;
use crate::dynamics::loops::LoopWork;
use crate::dynamics::{forces, kinematics, rnea, BodyId, Plan, Workspace};
use crate::solver::{BlockStructure, DaeSystem, ResidualError};
use std::sync::Arc;

#[cfg(test)]
pub(crate) mod alloc_tests;
mod hinge_jacobian;
mod increment_caps;
mod jacobian;

/// The tightest relative tolerance the error test asks of a body in a volume-law contact
/// (`rtol / κ ≥` this): the overlap's depth is a difference of coordinates of the scene's
/// size, so a face's force carries a rounding noise of `k·ε·|r|` (a 0.1 m wooden cube 1 m from
/// the origin: 1.3e9 N/m × 2e-16 m = 3e-7 N), and tighter weights only chase it. Measured on a
/// cube sliding down an incline 1 m from the origin: rtol 1e-8 took 287 steps untightened and
/// reached 1,000,000 steps tightened to 4.6e-11; tightened to 1e-9 it took 72,829; rtol 1e-6
/// tightened to 1e-8 took 287 (docs/contact-model.md §3.2).
pub(crate) const VOLUME_CONTACT_RTOL_FLOOR: f64 = 1e-8;

/// The share of the tightening factor κ a body in a volume-law contact gets (below the floor
/// of [`VOLUME_CONTACT_RTOL_FLOOR`]). κ was calibrated on a steel ball's Hertz impacts; on a
/// 0.1 m wooden cube dropped flat from 5 cm, the rebound speed against an rtol 1e-10 run was
/// within 0.01–0.18·rtol at the full κ and within 0.06–0.27·rtol at 0.3·κ over rtol
/// 1e-3…1e-6, both inside the 3·rtol of `tests/contact_times.rs` (κ/100: up to 24·rtol), and
/// `falling_boxes` took 14,684 steps instead of 17,410.
pub(crate) const VOLUME_TIGHTENING_SHARE: f64 = 0.3;

/// The tightest relative tolerance the contact tightening asks of a body in a point-law
/// contact whose narrow phase is iterative for some poses (MPR: the pairs that are not
/// [`crate::geometry::narrow_phase::exact`]), as [`VOLUME_CONTACT_RTOL_FLOOR`] for the volume
/// law: MPR's normal jitters by 1e-6–1e-5 rad between poses 1e-9 m apart, so the force's
/// direction carries that noise, and a tightening to `rtol/κ` far below it (3e-12 at rtol
/// 1e-9, κ = 316) only chases it: the steps collapse to 1e-10 s. The floor only lowers the
/// tightening (the factor stays ≥ 1: never looser than the asked rtol), so it acts below
/// rtol ≈ 1e-6 (κ = 100 there). Measured on the 10,000-scene batch's budget runs whose
/// diagnosis was the narrow phase's noise (BENCHMARKS.md, "Random scenes"): 7 of 14 then
/// finish within 20 s, 5 of them at rtol ≤ 4e-9 in 0.6–5 s; a floor of 1e-7 rescued two more
/// but coarsens the contact times of these pairs at rtol 1e-6 tenfold, and loosening below
/// the asked rtol (a factor < 1) rescued none of seven more runs at rtol ≤ 1.6e-8. Sphere
/// pairs with a closed form keep the full tightening, bit for bit.
pub(crate) const ITERATIVE_CONTACT_RTOL_FLOOR: f64 = 1e-8;

/// The multibody DAE of a plan and its contact plan, with its scratch workspace and contact set.
#[derive(Clone, Debug)]
pub(crate) struct MultibodyDae {
    plan: Arc<Plan>,
    /// The collision pipeline, `None` without candidate pairs.
    contact_plan: Option<Arc<ContactPlan>>,
    ws: Workspace,
    /// Scratch of the loop constraints (empty without cut joints).
    lw: LoopWork,
    contact: Option<ContactState>,
    /// The largest step that keeps every passage through a contact visible (tunnelling;
    /// `contact/step_guard.rs`), built with the DAE from its contact plan; `None` without one.
    step_guard: Option<StepGuard>,
    /// The joint limits, `None` without any (then nothing of them runs).
    limits: Option<Box<Limits>>,
    /// Scratch of [`Self::limit_forces`].
    limit_out: Vec<f64>,
    /// The components' scratch and discrete states, `None` without components (then nothing
    /// of them runs).
    comps: Option<Box<ComponentState>>,
    /// Scratch of the components' analytic state columns (`jacobian.rs`,
    /// `component_columns`): the flange forces' derivatives along one state (len nv, empty
    /// without components), the row operation's passed forces (len bodies) and the joint rows'
    /// change (len nv).
    comp_dtau: Vec<f64>,
    comp_pass: Vec<crate::spatial::Force>,
    comp_rows: Vec<f64>,
    /// First error of the contact stage inside a root evaluation (IDA's root callback cannot
    /// fail); reported by the driver.
    root_error: Option<ContactError>,
    /// Jacobian blocks: one per independent joint tree (bodies whose chain reaches the world
    /// through different root joints), with the couplings of the force elements; `None` only
    /// for a scene without moving bodies. A single tree is one block: the same residual
    /// evaluations and LU as IDA's dense Jacobian, but the difference-quotient increments of
    /// `solver/ida/linear.rs`, which see contacts at nanometre penetration.
    blocks: Option<TreeBlocks>,
    /// Scratch of [`DaeSystem::error_weight_factors`]: blocks with a body in contact (the
    /// largest mark of its contacts, the one that tightens least: 1 in a point-law contact
    /// with a closed form, 2 in one with an iterative narrow phase, 3 in a volume-law contact).
    ewt_marked: Vec<u8>,
    /// The factors of the last [`DaeSystem::error_weight_factors`] that formed them, with the
    /// marks and the tightening they came from: the contact set changes only at events, so
    /// most steps copy them.
    ewt_factors: Vec<f64>,
    ewt_factors_marked: Vec<u8>,
    ewt_factors_kappa: f64,
    /// The largest tightening of a block in a volume-law contact: `rtol / 1e-8`, at least 1
    /// ([`VOLUME_CONTACT_RTOL_FLOOR`]; infinite until [`MultibodyDae::set_tolerance`]).
    volume_tightening_cap: f64,
    /// The largest tightening of a block in a point-law contact with an iterative narrow
    /// phase: `rtol / 1e-8`, at least 1 ([`ITERATIVE_CONTACT_RTOL_FLOOR`]).
    iterative_tightening_cap: f64,
    /// Factor of the error weights of the bodies in contact (1 = off; see
    /// [`crate::SimOptions::contact_tightening`]).
    contact_tightening: f64,
    /// Trees whose Jacobian columns the DAE computes itself (`dae/jacobian.rs`), as last
    /// reported by `jacobian_structure`.
    analytic: Vec<bool>,
    /// Free bodies and hinge trees get the DAE's own columns (default; off with
    /// `SimOptions::analytic_jacobian`, set before the solver is created: every block by
    /// difference quotients, as before `dae/jacobian.rs`, for comparisons).
    analytic_enabled: bool,
    /// The body each position coordinate places (the body of its joint), for
    /// [`DaeSystem::quotient_residual`].
    body_of_q: Vec<BodyId>,
    /// The body each velocity coordinate moves (the body of its joint).
    body_of_v: Vec<BodyId>,
    /// Per body: whether the current quotient residual's perturbation moves it (its joint's
    /// position or an ancestor's was perturbed).
    moved: Vec<bool>,
    /// Per body: whether the perturbation changes its placement or velocity (`moved`, or its
    /// joint's velocity or an ancestor's was perturbed).
    touched: Vec<bool>,
    /// Per body: whether its rows can change (its tree is touched, or coupled to a touched
    /// tree by a force element or a pair in the contact set); per tree in `live_tree`.
    live: Vec<bool>,
    live_tree: Vec<bool>,
    /// Per tree: whether one of its bodies is touched.
    touched_tree: Vec<bool>,
    /// Placements and velocities, and the residual, at the point of the last
    /// [`DaeSystem::begin_quotients`].
    base_states: kinematics::BodyStates,
    base_res: Vec<f64>,
    /// Whether the DAE holds a [`DaeSystem::begin_quotients`] for the current contact set
    /// (cleared when an event may change the set).
    quotient_base: bool,
    /// `∂F/∂y'` ([`DaeSystem::yp_jacobian`]): a workspace of its own (the mass matrix's
    /// inverse dynamics must not disturb the residual's), the velocity indices of each tree,
    /// zero velocities, a unit acceleration per tree and one column of `M`.
    mass: MassColumns,
    /// The hinge trees and the scratch of their exact columns (`dae/hinge_jacobian.rs`).
    hinge: hinge_jacobian::HingeTrees,
}

/// The joint limits of a plan (`contact/limits.rs`): their stops and contact state.
#[derive(Clone, Debug)]
pub(crate) struct Limits {
    /// The stops (immutable).
    pub plan: LimitPlan,
    /// Which are in contact, their damping and last forces.
    pub state: LimitState,
}

/// Scratch of [`DaeSystem::yp_jacobian`] (allocated with the DAE).
#[derive(Clone, Debug)]
struct MassColumns {
    ws: Workspace,
    groups: Vec<Vec<usize>>,
    /// For each group: the joint if the tree is one body alone on a free joint (a root body
    /// carrying nothing, [`lone_free_joints`]), whose columns `Sᵀ I S e_k` are formed
    /// directly instead of by Newton–Euler passes over the whole scene.
    lone_free: Vec<Option<usize>>,
    zero_v: Vec<f64>,
    e: Vec<f64>,
    col: Vec<f64>,
}

/// The static part of the Jacobian's block structure (one block per joint tree).
#[derive(Clone, Debug)]
struct TreeBlocks {
    /// Block of each body.
    of_body: Vec<usize>,
    /// Number of joint trees (the blocks `0..n_trees`; the components' states, if any, are
    /// block `n_trees`, coupled to the trees whose coordinates they read or drive).
    n_trees: usize,
    /// Block of each unknown of `y = [q; v]` and the couplings by force elements.
    fixed: BlockStructure,
    /// The trees that are one free body (`dae/jacobian.rs`): their columns can be computed
    /// analytically.
    free: Vec<Option<jacobian::FreeBody>>,
    /// The free bodies' own force elements (`FreeBody::forces` ranges index it).
    own_forces: Vec<usize>,
}

impl TreeBlocks {
    /// One block per root body (a body whose parent is the world); `None` without any.
    fn new(plan: &Plan) -> Option<TreeBlocks> {
        let (of_body, n_blocks) = plan.trees();
        if n_blocks == 0 {
            return None;
        }
        let m = plan.loops.m();
        let mut block_of = vec![0; plan.nq + plan.nv + 2 * m];
        for j in &plan.joints {
            let blk = of_body[j.body.index()];
            block_of[j.q_offset..j.q_offset + j.coord.nq()].fill(blk);
            let v0 = plan.nq + j.v_offset;
            block_of[v0..v0 + j.coord.nv()].fill(blk);
        }
        let mut couplings = vec![];
        // A loop's rows (λ and μ) belong to the tree of obj2 (else obj1) and couple both trees.
        let base = plan.nq + plan.nv;
        for (i, &(c, _)) in plan.loops.kept.iter().enumerate() {
            let cut = &plan.loops.cuts[c];
            let tree = |b: Option<crate::dynamics::ids::BodyId>| b.map(|b| of_body[b.index()]);
            let (b1, b2) = (tree(cut.body1), tree(cut.body2));
            let own = b2.or(b1).unwrap_or(0);
            block_of[base + i] = own;
            block_of[base + m + i] = own;
            if let (Some(x), Some(y)) = (b1, b2) {
                if x != y {
                    couplings.push((x, y));
                }
            }
        }
        for f in &plan.scene.forces {
            if let Some((obj1, obj2)) = f.coupled_objects() {
                if let (Some(a), Some(b)) = (plan.objects[obj1].body, plan.objects[obj2].body) {
                    if of_body[a.index()] != of_body[b.index()] {
                        couplings.push((of_body[a.index()], of_body[b.index()]));
                    }
                }
            }
        }
        let (free, own_forces) = jacobian::free_bodies(plan, &of_body, n_blocks);
        let n_trees = n_blocks;
        let mut n_blocks = n_blocks;
        let cp = &plan.components;
        if cp.nx > 0 {
            block_of.resize(block_of.len() + cp.nx, n_trees);
            n_blocks += 1;
        }
        if !cp.comps.is_empty() {
            let mut tree_of_v = vec![0; plan.nv];
            for j in &plan.joints {
                tree_of_v[j.v_offset..j.v_offset + j.coord.nv()].fill(of_body[j.body.index()]);
            }
            // Trees tied through the components' signals: each pair of them, and each with the
            // components' states.
            let trees: Vec<usize> = cp.v_touched.iter().map(|&v| tree_of_v[v]).collect();
            for &a in &trees {
                if cp.nx > 0 {
                    couplings.push((a, n_trees));
                }
                for &b in &trees {
                    if a != b {
                        couplings.push((a, b));
                    }
                }
            }
        }
        Some(TreeBlocks {
            of_body,
            n_trees,
            fixed: BlockStructure {
                block_of,
                n_blocks,
                couplings,
                analytic: vec![],
            },
            free,
            own_forces,
        })
    }
}

impl MultibodyDae {
    /// The DAE of `plan` with the collision pipeline `contact` (`None` without candidate
    /// pairs).
    pub(crate) fn new(plan: Arc<Plan>, contact: Option<Arc<ContactPlan>>) -> Self {
        let ws = Workspace::new(&plan);
        let contact_plan = contact;
        let contact = contact_plan.as_deref().map(ContactState::new);
        let step_guard = contact_plan.as_deref().map(StepGuard::new);
        let blocks = TreeBlocks::new(&plan);
        let lw = LoopWork::new(&plan);
        let mut body_of_q = Vec::with_capacity(plan.nq);
        for j in &plan.joints {
            // Joints come in the order of their coordinates (`Plan::nq` counts them so).
            debug_assert_eq!(j.q_offset, body_of_q.len());
            body_of_q.extend(std::iter::repeat_n(j.body, j.coord.nq()));
        }
        let mut body_of_v = vec![BodyId(0); plan.nv];
        for j in &plan.joints {
            body_of_v[j.v_offset..j.v_offset + j.coord.nv()].fill(j.body);
        }
        let nb = plan.bodies.len();
        let groups = plan.velocity_groups();
        let n_trees = blocks.as_ref().map_or(0, |b| b.n_trees);
        let limits = LimitPlan::compile(&plan).map(|lp| {
            Box::new(Limits {
                state: LimitState::new(&lp),
                plan: lp,
            })
        });
        let mut hinge: hinge_jacobian::HingeTrees =
            blocks.as_ref().map_or_else(Default::default, |b| {
                hinge_jacobian::HingeTrees::new(&plan, &b.of_body, n_trees)
            });
        if limits.is_some() {
            hinge.limit_kd = vec![(0.0, 0.0); plan.nv];
        }
        let (comp_nv, comp_nb) = if plan.components.comps.is_empty() {
            (0, 0)
        } else {
            (plan.nv, plan.bodies.len())
        };
        let comps = (!plan.components.comps.is_empty())
            .then(|| Box::new(ComponentState::new(&plan.components)));
        MultibodyDae {
            body_of_q,
            body_of_v,
            moved: vec![false; nb],
            touched: vec![false; nb],
            live: vec![false; nb],
            live_tree: vec![false; n_trees],
            touched_tree: vec![false; n_trees],
            base_states: kinematics::BodyStates::new(&plan),
            base_res: vec![0.0; (plan.nq + plan.nv + 2 * plan.loops.m()).max(1)],
            quotient_base: false,
            mass: MassColumns {
                ws: Workspace::new(&plan),
                lone_free: lone_free_joints(&plan, &groups),
                groups,
                zero_v: vec![0.0; plan.nv],
                e: vec![0.0; plan.nv],
                col: vec![0.0; plan.nv],
            },
            hinge,
            plan,
            contact_plan,
            step_guard,
            ws,
            lw,
            contact,
            limits,
            limit_out: vec![],
            comp_dtau: vec![0.0; comp_nv],
            comp_pass: vec![crate::spatial::Force::default(); comp_nb],
            comp_rows: vec![0.0; comp_nv],
            comps,
            root_error: None,
            ewt_marked: Vec::with_capacity(blocks.as_ref().map_or(0, |b| b.fixed.n_blocks)),
            ewt_factors: Vec::with_capacity(blocks.as_ref().map_or(0, |b| b.fixed.block_of.len())),
            ewt_factors_marked: Vec::with_capacity(blocks.as_ref().map_or(0, |b| b.fixed.n_blocks)),
            ewt_factors_kappa: f64::NAN,
            volume_tightening_cap: f64::INFINITY,
            iterative_tightening_cap: f64::INFINITY,
            contact_tightening: 1.0,
            blocks,
            analytic: vec![],
            analytic_enabled: true,
        }
    }
    /// Tightens the error test of the bodies in contact (in the contact set) by `factor`
    /// (≥ 1; 1 = off): see [`crate::SimOptions::contact_tightening`]. Whether the error
    /// weights are tightened at all is fixed when the solver is created (a factor > 1 then);
    /// a later change sets the factor of the following steps' weights (the driver relaxes it
    /// after a repeated error-test failure: `Simulation::relax_contact_tightening`).
    /// Sets the run's relative tolerance `rtol`, which bounds the tightening of the bodies in a
    /// volume-law contact (see [`VOLUME_CONTACT_RTOL_FLOOR`]).
    pub(crate) fn set_tolerance(&mut self, rtol: f64) {
        self.volume_tightening_cap = (rtol / VOLUME_CONTACT_RTOL_FLOOR).max(1.0);
        self.iterative_tightening_cap = (rtol / ITERATIVE_CONTACT_RTOL_FLOOR).max(1.0);
    }
    /// Computes the Jacobian columns of free bodies and hinge trees itself (`on`, the default)
    /// or leaves every block to the solver's coloured difference quotients: see
    /// [`crate::SimOptions::analytic_jacobian`]. Set before the solver is created.
    pub(crate) fn set_analytic_jacobian(&mut self, on: bool) {
        self.analytic_enabled = on;
    }
    pub(crate) fn set_contact_tightening(&mut self, factor: f64) {
        self.contact_tightening = factor.max(1.0);
    }
    /// The tightening factor of the error test of the bodies in contact [-] (1 = off).
    pub(crate) fn contact_tightening(&self) -> f64 {
        self.contact_tightening
    }
    /// The plan.
    pub(crate) fn plan(&self) -> &Plan {
        &self.plan
    }
    /// The largest step \[s\] after which no collision shape can have passed through another
    /// unseen, at the body velocities and accelerations of the last evaluation
    /// (`contact/step_guard.rs`); `None` without candidate pairs or when nothing that can
    /// collide moves.
    pub(crate) fn max_safe_step(&self) -> Option<f64> {
        self.guard_limit().map(|(h, _)| h)
    }
    /// [`Self::max_safe_step`] with the body that sets it (`StepGuard::limit`).
    pub(crate) fn guard_limit(&self) -> Option<(f64, BodyId)> {
        let (b, h) = self
            .step_guard
            .as_ref()?
            .limit(&self.ws, &self.plan.gravity)?;
        Some((h, b))
    }
    /// Speed of the origin [m/s] and angular speed [rad/s] of every body at the last
    /// evaluation, in body order (for diagnoses).
    pub(crate) fn body_speeds(&self) -> impl Iterator<Item = (f64, f64)> + '_ {
        self.ws.vel.iter().map(|m| (m.v.norm(), m.w.norm()))
    }
    /// Sets input values (len `Plan::n_inputs`).
    pub(crate) fn inputs_mut(&mut self) -> &mut [f64] {
        &mut self.ws.inputs
    }
    /// The compiled contact pipeline, if the scene has collision pairs.
    pub(crate) fn contact_plan(&self) -> Option<&ContactPlan> {
        self.contact_plan.as_deref()
    }
    /// The workspace (body poses and velocities of the last residual evaluation).
    pub(crate) fn workspace(&self) -> &Workspace {
        &self.ws
    }
    /// The contact set, if the scene has collision pairs.
    pub(crate) fn contact(&self) -> Option<&ContactState> {
        self.contact.as_ref()
    }
    /// Number of root functions (2 with collision pairs, else 0).
    pub(crate) fn num_roots_public(&self) -> usize {
        self.num_roots()
    }
    /// Names (`"a|b"`) of the pairs that started and ended at the last event.
    /// Stops of joint limits (`"<joint>.<coordinate>.lower"`, `".upper"`) follow the pairs.
    pub(crate) fn event_pairs(&self) -> (Vec<String>, Vec<String>) {
        let (mut started, mut ended) = match (self.contact.as_ref(), self.contact_plan.as_deref()) {
            (Some(cs), Some(cp)) => {
                let names = |v: &[u32]| -> Vec<String> {
                    v.iter()
                        .filter_map(|&p| cp.pair_by_id(p as usize))
                        .map(|pp| cp.pair_name(&self.plan.scene, &pp))
                        .collect()
                };
                (names(&cs.started), names(&cs.ended))
            }
            _ => (vec![], vec![]),
        };
        if let Some(l) = &self.limits {
            let name = |&s: &u32| l.plan.stops[s as usize].name.clone();
            started.extend(l.state.started.iter().map(name));
            ended.extend(l.state.ended.iter().map(name));
        }
        (started, ended)
    }
    /// The generalised force of each limited coordinate \[N·m or N\] at `y` (the stops of
    /// the current set), `None` without limits. For output points, not the hot path.
    pub(crate) fn limit_forces(&mut self, y: &[f64]) -> Option<&[f64]> {
        let l = self.limits.as_deref_mut()?;
        let (q, v) = y.split_at(self.plan.nq);
        l.state.evaluate(&l.plan, q, v);
        l.state.forces(&l.plan, &mut self.limit_out);
        Some(&self.limit_out)
    }
    /// The joint limits' stops and state, if the scene has limits.
    pub(crate) fn limits(&self) -> Option<(&LimitPlan, &LimitState)> {
        self.limits.as_deref().map(|l| (&l.plan, &l.state))
    }
    /// Number of the contact and limit root functions (2 with collision pairs or limits, else
    /// 0); the components' one, if any, follows them.
    fn contact_roots(&self) -> usize {
        if self.contact.is_some() || self.limits.is_some() {
            2
        } else {
            0
        }
    }
    /// The directions of the root functions IDA watches: `z_1` rising (a contact ends),
    /// `z_2` falling (one starts), the components' smallest crossing falling; `None` without
    /// root functions.
    pub(crate) fn root_directions(&self) -> Option<Vec<i32>> {
        let mut d = if self.contact_roots() == 2 {
            vec![1, -1]
        } else {
            vec![]
        };
        if self.plan.components.nz > 0 {
            d.push(-1);
        }
        (!d.is_empty()).then_some(d)
    }
    /// The components' point of `y` at time `t` \[s\] with accelerations `a`.
    fn component_point<'a>(plan: &'a Plan, t: f64, y: &'a [f64], a: &'a [f64]) -> Point<'a> {
        let (nq, nv, xo) = (plan.nq, plan.nv, plan.x_offset());
        Point {
            t,
            q: &y[..nq],
            v: &y[nq..nq + nv],
            a,
            x: y.get(xo..xo + plan.components.nx).unwrap_or(&[]),
        }
    }
    /// The accelerations at `(t, y)` when a component reads them (consistent derivatives,
    /// for events and output points), else none. A failure leaves them out (the residual
    /// reports it).
    fn accelerations_if_read(&mut self, t: f64, y: &[f64]) -> Vec<f64> {
        if !self.plan.components.reads_acceleration {
            return vec![];
        }
        let (nq, nv) = (self.plan.nq, self.plan.nv);
        let mut y = y.to_vec();
        self.consistent_derivative(t, &mut y)
            .map(|yp| yp[nq..nq + nv].to_vec())
            .unwrap_or_default()
    }
    /// A component event at `(t, y)` (a time event, a zero crossing, the start): the
    /// components set their discrete states. Returns whether any changed.
    pub(crate) fn component_event(&mut self, t: f64, y: &[f64]) -> Result<bool, UserFault> {
        if self.comps.is_none() {
            return Ok(false);
        }
        let a = self.accelerations_if_read(t, y);
        let Some(cs) = self.comps.as_deref_mut() else {
            return Ok(false);
        };
        self.quotient_base = false;
        let at = Self::component_point(&self.plan, t, y, &a);
        cs.event(&self.plan.components, &at)
    }
    /// The first time event of a component strictly after `t` \[s\].
    pub(crate) fn next_time_event(&self, t: f64) -> Option<f64> {
        let cs = self.comps.as_deref()?;
        cs.next_time_event(&self.plan.components, t)
    }
    /// The components at `(t, y)` for an output point, one evaluation: their continuous
    /// states, outputs and discrete states appended to `values`, and their flange forces on
    /// the coordinates of `ComponentPlan::flange_v`, in that order, to `flanges` (for the
    /// joint loads). NaN where a component fails (the next residual reports it). Nothing
    /// without components.
    pub(crate) fn component_record(
        &mut self,
        t: f64,
        y: &[f64],
        values: &mut Vec<f64>,
        flanges: &mut Vec<f64>,
    ) {
        if self.comps.is_none() {
            return;
        }
        let a = self.accelerations_if_read(t, y);
        let Some(cs) = self.comps.as_deref_mut() else {
            return;
        };
        let plan = &*self.plan;
        let at = Self::component_point(plan, t, y, &a);
        let mut tau = vec![0.0; plan.nv];
        let ok = cs.evaluate(&plan.components, &at, &mut tau).is_ok();
        values.extend_from_slice(at.x);
        let nan = |v: f64| if ok { v } else { f64::NAN };
        values.extend(cs.y.iter().map(|&v| nan(v)));
        values.extend_from_slice(&cs.d);
        flanges.extend(plan.components.flange_v.iter().map(|&v| nan(tau[v])));
    }
    /// The components' discrete states.
    pub(crate) fn component_discrete_mut(&mut self) -> Option<&mut [f64]> {
        self.comps.as_deref_mut().map(|c| &mut c.d[..])
    }
    /// Takes the first contact error met while evaluating root functions.
    pub(crate) fn take_root_error(&mut self) -> Option<ContactError> {
        self.root_error.take()
    }

    /// Event mode (docs/contact-model.md §4) at time `t` \[s\] and state `y`: recomputes every `z_AB`, rebuilds
    /// the contact set and stores `δ̇⁻` of new contacts. Returns whether the set changed. Does
    /// nothing without collision pairs.
    /// The stops of joint limits are decided in the same event.
    pub(crate) fn handle_event(&mut self, t: f64, y: &[f64]) -> Result<bool, ContactError> {
        let plan = &*self.plan;
        let (q, v) = y.split_at(plan.nq);
        let mut stops = false;
        if let Some(l) = self.limits.as_deref_mut() {
            stops = l.state.event(&l.plan, q, v);
            self.quotient_base = false;
        }
        let (Some(cs), Some(cp)) = (self.contact.as_mut(), self.contact_plan.as_deref()) else {
            return Ok(stops);
        };
        kinematics::position_velocity(plan, &mut self.ws, q, v);
        self.quotient_base = false;
        cs.evaluate(plan, cp, &mut self.ws, Mode::Event, t)?;
        Ok(stops || !cs.started.is_empty() || !cs.ended.is_empty())
    }

    /// Continuous mode at `(t, y)`: updates the geometry and forces of the pairs in the set
    /// (for output points). Does nothing without collision pairs.
    pub(crate) fn update_contacts(&mut self, t: f64, y: &[f64]) -> Result<(), ContactError> {
        let plan = &*self.plan;
        if let Some(l) = self.limits.as_deref_mut() {
            let (q, v) = y.split_at(plan.nq);
            l.state.evaluate(&l.plan, &q[..plan.nq], &v[..plan.nv]);
        }
        let (Some(cs), Some(cp)) = (self.contact.as_mut(), self.contact_plan.as_deref()) else {
            return Ok(());
        };
        let (q, v) = y.split_at(plan.nq);
        kinematics::position_velocity(plan, &mut self.ws, q, v);
        cs.evaluate(plan, cp, &mut self.ws, Mode::Continuous, t)
    }

    /// Derivative `y'` consistent with `y` at time `t` \[s\], contact forces of the current set
    /// included; an error if the mass matrix is singular there, the narrow phase fails or a
    /// user force law panics or returns a non-finite wrench. With closed loops `y` is first
    /// projected onto the constraints (positions and velocities, `loops::project`) and its
    /// multipliers are set (`λ` consistent, `μ = 0`).
    pub(crate) fn consistent_derivative(
        &mut self,
        t: f64,
        y: &mut [f64],
    ) -> Result<Vec<f64>, DerivativeError> {
        let (nq, nv, m) = (self.plan.nq, self.plan.nv, self.plan.loops.m());
        let xo = self.plan.x_offset();
        let nx = self.plan.components.nx;
        let x: Vec<f64> = y.get(xo..xo + nx).unwrap_or(&[]).to_vec();
        if nq + nv == 0 {
            let mut yp = vec![0.0; self.len()];
            if let Some(cs) = self.comps.as_deref_mut() {
                let at = Point {
                    t,
                    q: &[],
                    v: &[],
                    a: &[],
                    x: &x,
                };
                cs.evaluate(&self.plan.components, &at, &mut [])
                    .map_err(DerivativeError::User)?;
                yp[xo..xo + cs.xdot.len()].copy_from_slice(&cs.xdot);
            }
            return Ok(yp);
        }
        let (q, rest) = y.split_at_mut(nq);
        let (v, mult) = rest.split_at_mut(nv);
        if !self.plan.loops.is_empty() {
            crate::dynamics::loops::project(&self.plan, &mut self.ws, q, v)
                .map_err(DerivativeError::Loop)?;
        }
        let mut yp = vec![0.0; self.len()];
        kinematics::position_derivative(&self.plan, q, v, &mut yp[..nq]);
        // With components that read accelerations: fixed-point iteration on them (their
        // forces then depend on what they read; an inertia is better a geared one).
        let reads = self.plan.components.reads_acceleration;
        let mut a_guess: Vec<f64> = if reads { vec![0.0; nv] } else { vec![] };
        let mut iterations = 0;
        let vd = loop {
            let contact = &mut self.contact;
            let contact_plan = self.contact_plan.as_deref();
            let limits = &mut self.limits;
            let comps = &mut self.comps;
            let (qc, vc) = (&*q, &*v);
            let mut failed = None;
            let mut comp_fault = None;
            let a_read = &a_guess;
            let vd = crate::dynamics::mass_matrix::consistent_accelerations_with(
                &self.plan,
                &mut self.ws,
                t,
                q,
                v,
                &mut |plan, ws| {
                    if let (Some(cs), Some(cp)) = (contact.as_mut(), contact_plan) {
                        if let Err(e) = cs.evaluate(plan, cp, ws, Mode::Continuous, t) {
                            failed.get_or_insert(e);
                        }
                    }
                    if let Some(l) = limits.as_deref_mut() {
                        l.state.apply(&l.plan, qc, vc, &mut ws.tau_applied);
                    }
                    if let Some(cs) = comps.as_deref_mut() {
                        let at = Point {
                            t,
                            q: qc,
                            v: &vc[..plan.nv],
                            a: a_read,
                            x: &x,
                        };
                        if let Err(f) = cs.evaluate(&plan.components, &at, &mut ws.tau_applied) {
                            comp_fault.get_or_insert(f);
                        }
                    }
                },
            );
            if let Some(f) = comp_fault {
                return Err(DerivativeError::User(f));
            }
            if let Some(fault) = self.ws.fault.take() {
                return Err(DerivativeError::User(fault));
            }
            if let Some(e) = failed {
                return Err(DerivativeError::Contact(e));
            }
            if !reads {
                break vd;
            }
            let Some((vd_new, _)) = vd.as_ref() else {
                break vd;
            };
            let change = vd_new
                .iter()
                .zip(&a_guess)
                .fold(0.0f64, |m, (a, b)| m.max((a - b).abs()));
            let scale = vd_new.iter().fold(1.0f64, |m, a| m.max(a.abs()));
            a_guess.clone_from(vd_new);
            iterations += 1;
            if change <= 1e-12 * scale {
                break vd;
            }
            if iterations >= MAX_ACCELERATION_ITERATIONS {
                return Err(DerivativeError::AccelerationLoop);
            }
        };
        let (vd, lambda) = vd.ok_or(DerivativeError::Singular)?;
        yp[nq..nq + nv].copy_from_slice(&vd);
        if m > 0 {
            mult[..m].copy_from_slice(&lambda);
            mult[m..2 * m].fill(0.0);
        }
        if let Some(cs) = self.comps.as_deref() {
            yp[xo..xo + cs.xdot.len()].copy_from_slice(&cs.xdot);
        }
        Ok(yp)
    }

    /// The pairs of the contact set under the volume law at rest along their normal (see
    /// [`ContactState::resting_volume_pairs`]); empty without collision pairs.
    pub(crate) fn resting_volume_pairs(&self, speed: f64) -> Vec<RestingPair> {
        match (self.contact.as_ref(), self.contact_plan.as_deref()) {
            (Some(cs), Some(cp)) => cs.resting_volume_pairs(cp, speed),
            _ => vec![],
        }
    }

    /// For each pair of `pairs`: the normal component \[m/s²\] of the acceleration of its
    /// body b relative to its body a at the pair's contact point (> 0 separating), from the
    /// joint accelerations `vd` at positions `q`: `J(q)·v̇`, without the terms in the products
    /// of velocities (zero for bodies at rest). The point and normal are those of the pair's
    /// response when it carries a force (the overlap's centroid and normal), else the pair's
    /// own (its touch). Uses the workspace's velocities as scratch: the next evaluation sets
    /// them again.
    pub(crate) fn normal_accelerations(
        &mut self,
        q: &[f64],
        vd: &[f64],
        pairs: &[RestingPair],
        out: &mut Vec<f64>,
    ) {
        out.clear();
        kinematics::position_velocity(&self.plan, &mut self.ws, q, vd);
        let Some(cs) = self.contact.as_ref() else {
            return;
        };
        for rp in pairs {
            let (_, ps) = cs.active_pair(rp.k);
            let r = &ps.response;
            let (point, normal) = if r.f_n > 0.0 {
                (r.point, r.normal)
            } else {
                (rp.point, rp.normal)
            };
            let (a1, _) = kinematics::point_velocity(&self.ws, rp.bodies[0], &point);
            let (a2, _) = kinematics::point_velocity(&self.ws, rp.bodies[1], &point);
            out.push((a2 - a1).dot(&normal));
        }
    }

    /// Takes the first failure of a user force law since the last call (see
    /// [`Workspace::fault`]).
    pub(crate) fn take_user_fault(&mut self) -> Option<UserFault> {
        self.ws.fault.take()
    }
}

/// Why [`MultibodyDae::consistent_derivative`] found no derivative.
#[derive(Clone, Debug, PartialEq)]
pub(crate) enum DerivativeError {
    /// The mass matrix of the free coordinates is singular.
    Singular,
    /// The collision stage failed.
    Contact(ContactError),
    /// A user force law failed.
    User(UserFault),
    /// A kinematic loop does not close at the current state.
    Loop(crate::dynamics::loops::LoopFailure),
    /// Components' forces depend on the accelerations they read so strongly that the
    /// fixed-point iteration for consistent accelerations does not converge.
    AccelerationLoop,
}

/// Iterations of the fixed point on the accelerations components read (each halves the
/// error of a coupling whose force changes by half the inertia it acts on).
const MAX_ACCELERATION_ITERATIONS: usize = 60;

impl DaeSystem for MultibodyDae {
    /// `nq + nv`, or 1 for a scene without unknowns (every body fixed): IDA needs n ≥ 1, so
    /// such a scene integrates one dummy state with `ẏ = 0` and its signals stay constant.
    fn len(&self) -> usize {
        (self.plan.x_offset() + self.plan.components.nx).max(1)
    }

    fn residual(
        &mut self,
        t: f64,
        y: &[f64],
        yp: &[f64],
        res: &mut [f64],
    ) -> Result<(), ResidualError> {
        self.residual_with(t, y, yp, res, false)
    }

    fn begin_quotients(&mut self, t: f64, y: &[f64], yp: &[f64]) -> Result<bool, ResidualError> {
        self.quotient_base = false;
        // With components every quotient evaluates the whole residual: their signals tie
        // trees together in ways the live-tree bookkeeping below does not follow.
        if self.blocks.is_none() || self.comps.is_some() {
            return Ok(false);
        }
        let mut base = std::mem::take(&mut self.base_res);
        let outcome = self.residual_with(t, y, yp, &mut base, false);
        self.base_res = base;
        outcome?;
        self.base_states.save(&self.ws);
        if let Some(cs) = self.contact.as_mut() {
            cs.begin_quotients();
        }
        self.quotient_base = true;
        Ok(true)
    }

    fn quotient_residual(
        &mut self,
        t: f64,
        y: &[f64],
        yp: &[f64],
        res: &mut [f64],
        changed: &[usize],
    ) -> Result<(), ResidualError> {
        let Some(tb) = self.blocks.as_ref().filter(|_| self.quotient_base) else {
            return self.residual_with(t, y, yp, res, false);
        };
        // The bodies the perturbation moves (their joint's positions changed) and touches
        // (positions or velocities), with their descendants (bodies come parents first).
        let plan = &*self.plan;
        let nq = plan.nq;
        self.moved.fill(false);
        self.touched.fill(false);
        for &j in changed {
            if let Some(&b) = self.body_of_q.get(j) {
                self.moved[b.index()] = true;
                self.touched[b.index()] = true;
            } else if let Some(&b) = j.checked_sub(nq).and_then(|k| self.body_of_v.get(k)) {
                self.touched[b.index()] = true;
            }
        }
        for (b, body) in plan.bodies.iter().enumerate() {
            if let Some(p) = body.parent {
                self.moved[b] |= self.moved[p.index()];
                self.touched[b] |= self.touched[p.index()];
            }
        }
        // The trees whose rows can change: the touched ones and those a force element or a
        // pair in the contact set couples to them (the rows the quotients read are those of
        // the perturbed trees and of their neighbours in `jacobian_structure`). With loops,
        // every tree (a loop's rows depend on both ends).
        self.touched_tree.fill(false);
        for (b, &t) in self.touched.iter().enumerate() {
            if t {
                self.touched_tree[tb.of_body[b]] = true;
            }
        }
        self.live_tree.copy_from_slice(&self.touched_tree);
        if plan.loops.m() > 0 {
            self.live_tree.fill(true);
        }
        let (touched, live) = (&self.touched_tree, &mut self.live_tree);
        let mut couple = |a: usize, b: usize| {
            live[b] |= touched[a];
            live[a] |= touched[b];
        };
        for &(a, b) in &tb.fixed.couplings {
            couple(a, b);
        }
        if let (Some(cs), Some(cp)) = (self.contact.as_ref(), self.contact_plan.as_deref()) {
            for (_, pp, _) in cs.active_pairs() {
                if let (Some(a), Some(b)) = (cp.shapes[pp.a].body, cp.shapes[pp.b].body) {
                    couple(tb.of_body[a.index()], tb.of_body[b.index()]);
                }
            }
        }
        for (l, &t) in self.live.iter_mut().zip(&tb.of_body) {
            *l = self.live_tree[t];
        }
        self.residual_with(t, y, yp, res, true)
    }

    fn num_roots(&self) -> usize {
        self.contact_roots() + usize::from(self.plan.components.nz > 0)
    }

    /// The stops of joint limits are folded into the same two functions (`z_1` the largest
    /// over pairs and stops in contact, `z_2` the smallest over the others).
    fn roots(&mut self, t: f64, y: &[f64], yp: &[f64], g: &mut [f64]) {
        let plan = &*self.plan;
        // The components' zero crossings: one function, the smallest of them, after the
        // contacts' two.
        let base = self.contact_roots();
        if let Some(cs) = self.comps.as_deref_mut().filter(|_| plan.components.nz > 0) {
            let a = yp.get(plan.nq..plan.nq + plan.nv).unwrap_or(&[]);
            let at = Self::component_point(plan, t, y, a);
            g[base] = match cs.min_crossing(&plan.components, &at) {
                Ok(z) => z,
                Err(f) => {
                    self.ws.fault.get_or_insert(f);
                    1.0
                }
            };
        }
        let (q, v) = y.split_at(plan.nq);
        let stops = self.limits.as_deref().map(|l| l.state.roots(&l.plan, q));
        let (Some(cs), Some(cp)) = (self.contact.as_mut(), self.contact_plan.as_deref()) else {
            if let Some((z1, z2)) = stops {
                g[0] = z1;
                g[1] = z2;
            }
            return;
        };
        kinematics::position_velocity(plan, &mut self.ws, q, v);
        if let Err(e) = cs.evaluate(plan, cp, &mut self.ws, Mode::ZeroCrossing, t) {
            self.root_error.get_or_insert(e);
        }
        let (z1, z2) = cs.roots(cp);
        g[0] = z1;
        g[1] = z2;
        if let Some((s1, s2)) = stops {
            // A negative constant stands for "no pair in contact": a stop in contact decides.
            g[0] = if cs.n_in_contact() == 0 {
                s1
            } else {
                z1.max(s1)
            };
            g[1] = z2.min(s2);
        }
    }

    /// One block per independent joint tree, coupled by spring-dampers between trees and by
    /// the pairs in the contact set (continuous mode computes forces for those only, and the
    /// set changes only at events, after which IDA forms a new Jacobian).
    fn jacobian_structure(&mut self, s: &mut BlockStructure) -> bool {
        let Some(tb) = &self.blocks else {
            return false;
        };
        s.block_of.clone_from(&tb.fixed.block_of);
        s.n_blocks = tb.fixed.n_blocks;
        s.couplings.clone_from(&tb.fixed.couplings);
        // A free body's columns are analytic unless a contact ties it to a tree that is not a
        // free body (whose rows the pair-local quotients cannot fill).
        s.analytic.clear();
        s.analytic.extend(tb.free.iter().map(Option::is_some));
        // So are a hinge tree's (`dae/hinge_jacobian.rs`) while no pair of the set touches it.
        for (a, &h) in s.analytic.iter_mut().zip(&self.hinge.is_hinge) {
            *a |= h;
        }
        if let (Some(cs), Some(cp)) = (self.contact.as_ref(), self.contact_plan.as_deref()) {
            for (_, pp, _) in cs.active_pairs() {
                let (a, b) = (cp.shapes[pp.a].body, cp.shapes[pp.b].body);
                let tree = |x: Option<crate::dynamics::BodyId>| x.map(|x| tb.of_body[x.index()]);
                let (ta, tb_) = (tree(a), tree(b));
                // A hinge tree keeps its exact columns against fixed shapes and itself (its
                // pair-local quotients, `dae/hinge_jacobian.rs`), not against another tree.
                for (this, other) in [(ta, tb_), (tb_, ta)] {
                    if let (Some(this), Some(other)) = (this, other) {
                        if self.hinge.is_hinge[this] && other != this {
                            s.analytic[this] = false;
                        }
                    }
                }
                for (this, other) in [(ta, tb_), (tb_, ta)] {
                    if let (Some(this), Some(other)) = (this, other) {
                        if tb.free[other].is_none() {
                            s.analytic[this] = false;
                        }
                    }
                }
                // A pair whose narrow phase stopped at its iteration limit is rough at the
                // increment's scale: its bodies keep the quotients of the full residual (as
                // before dae/jacobian.rs, where a run with a one-iteration MPR ends at its work
                // budget; with pair-local quotients it failed to converge, tests/contact_mpr_options.rs).
                if cs.hit_iteration_limit(pp.a, pp.b) {
                    for t in [ta, tb_].into_iter().flatten() {
                        s.analytic[t] = false;
                    }
                }
                if let (Some(ba), Some(bb)) = (ta, tb_) {
                    if ba != bb {
                        s.couplings.push((ba, bb));
                    }
                }
            }
        }
        if !self.plan.components.comps.is_empty() {
            // Trees whose coordinates components read or drive get quotient columns (the
            // analytic ones do not see the components' rows), as does the components' block.
            for &v in &self.plan.components.v_touched {
                s.analytic[tb.of_body[self.body_of_v[v].index()]] = false;
            }
            s.analytic.resize(s.n_blocks, false);
            // The components' states: from their partial derivatives when all give them.
            let cp = &self.plan.components;
            if cp.nx > 0 && cp.all_jacobians {
                if let Some(a) = s.analytic.get_mut(tb.n_trees) {
                    *a = true;
                }
            }
        }
        if !self.analytic_enabled {
            s.analytic.fill(false);
        }
        self.analytic.clone_from(&s.analytic);
        true
    }

    fn has_error_weight_factors(&self) -> bool {
        self.blocks.is_some() && self.contact.is_some() && self.contact_tightening > 1.0
    }

    fn error_weight_factors(&mut self, _y: &[f64], f: &mut [f64]) -> bool {
        let (Some(tb), Some(cs), Some(cp)) = (
            &self.blocks,
            self.contact.as_ref(),
            self.contact_plan.as_deref(),
        ) else {
            return false;
        };
        let kappa = self.contact_tightening;
        let marked = &mut self.ewt_marked;
        marked.clear();
        marked.resize(tb.fixed.n_blocks, 0);
        let mut any = false;
        for (_, pp, _) in cs.active_pairs() {
            let mark = match pp.law {
                crate::contact::PairLaw::Point
                    if crate::geometry::narrow_phase::exact(
                        cp.shapes[pp.a].shape.kind(),
                        cp.shapes[pp.b].shape.kind(),
                    ) =>
                {
                    1
                }
                crate::contact::PairLaw::Point => 2,
                _ => 3,
            };
            for s in [pp.a, pp.b] {
                if let Some(b) = cp.shapes[s].body {
                    let m = &mut marked[tb.of_body[b.index()]];
                    *m = (*m).max(mark);
                    any = true;
                }
            }
        }
        if !any {
            return false;
        }
        let m = f.len().min(tb.fixed.block_of.len());
        if kappa != self.ewt_factors_kappa
            || *marked != self.ewt_factors_marked
            || self.ewt_factors.len() != m
        {
            self.ewt_factors.clear();
            self.ewt_factors
                .extend(tb.fixed.block_of[..m].iter().map(|&blk| {
                    match marked[blk] {
                        0 => 1.0,
                        1 => kappa,
                        2 => kappa.min(self.iterative_tightening_cap).max(1.0),
                        _ => (VOLUME_TIGHTENING_SHARE * kappa)
                            .min(self.volume_tightening_cap)
                            .max(1.0),
                    }
                }));
            self.ewt_factors_marked.clone_from(marked);
            self.ewt_factors_kappa = kappa;
        }
        f[..m].copy_from_slice(&self.ewt_factors);
        true
    }

    fn jacobian(
        &mut self,
        args: &crate::solver::JacobianArgs<'_>,
        out: &mut dyn crate::solver::JacobianSink,
    ) -> Result<(), ResidualError> {
        self.analytic_jacobian(args, out)
    }

    fn increment_caps(&mut self, args: &crate::solver::JacobianArgs<'_>, caps: &mut [f64]) -> bool {
        self.position_caps(args, caps)
    }

    /// `∂F/∂y'`: the identity in the position rows (`q̇ − q̇(q, v)` for every joint kind),
    /// in the velocity rows the derivative of `rnea::residual_dynamics` (a row operation on
    /// `M(q) v̇ + C(q, v) − τ`, linear in `v̇`; no applied force, contact or constraint wrench
    /// depends on `v̇`), a unit row for a prescribed coordinate (`v̇ − a`) and nothing for the
    /// loop multipliers. The velocity rows column by column: the same recursion with zero
    /// velocity, gravity, applied and external forces in a workspace of its own, one unit
    /// acceleration per tree at a time (as `mass_matrix::tree_mass_matrices` forms `M`).
    /// Allocation-free.
    fn yp_jacobian(
        &mut self,
        args: &crate::solver::JacobianArgs<'_>,
        out: &mut dyn crate::solver::JacobianSink,
    ) -> Result<bool, ResidualError> {
        let plan = &*self.plan;
        let (nq, nv) = (plan.nq, plan.nv);
        // With components every matrix is formed anew (their rows and the geared inertias
        // are not in the columns below).
        if nq + nv == 0 || self.comps.is_some() {
            return Ok(false);
        }
        let q = &args.y[..nq];
        for i in 0..nq {
            out.add(i, i, &[1.0]);
        }
        let mc = &mut self.mass;
        kinematics::position_velocity(plan, &mut mc.ws, q, &mc.zero_v);
        // The hinge trees' columns by their own pass (`dae/hinge_jacobian.rs`), those of a
        // body alone on a free joint directly, the other trees' by Newton–Euler passes with
        // unit accelerations.
        self.hinge.mass_columns(plan, &mc.ws, out);
        for (g, &j) in mc.groups.iter().zip(&mc.lone_free) {
            if let Some(j) = j {
                free_mass_columns(plan, &mc.ws, q, j, nq + g[0], out);
            }
        }
        let hinge = &self.hinge.is_hinge;
        let lone = &mc.lone_free;
        let others = || {
            mc.groups
                .iter()
                .enumerate()
                .filter(|&(t, _)| !hinge.get(t).copied().unwrap_or(false) && lone[t].is_none())
                .map(|(_, g)| g)
        };
        mc.ws.f_ext.fill(crate::spatial::Force::default());
        let width = others().map(Vec::len).max().unwrap_or(0);
        let prescribed = |k: usize| plan.prescribed.get(k).is_some_and(Option::is_some);
        for c in 0..width {
            mc.e.fill(0.0);
            for g in others().filter(|g| c < g.len()) {
                mc.e[g[c]] = 1.0;
            }
            rnea::residual_dynamics(
                plan,
                &mut mc.ws,
                (q, &mc.e),
                &nalgebra::Vector3::zeros(),
                &mut mc.col,
                None,
            );
            for g in others().filter(|g| c < g.len()) {
                let j = g[c];
                for &i in g.iter().filter(|&&i| !prescribed(i)) {
                    out.add(nq + i, nq + j, &[mc.col[i]]);
                }
            }
        }
        for k in (0..nv).filter(|&k| prescribed(k)) {
            out.add(nq + k, nq + k, &[1.0]);
        }
        Ok(true)
    }
}

/// For each velocity group of `plan` (a joint tree): the joint, if the tree is one root body
/// on a free joint that carries no other body (its six velocities consecutive).
fn lone_free_joints(plan: &Plan, groups: &[Vec<usize>]) -> Vec<Option<usize>> {
    let mut carries = vec![false; plan.bodies.len()];
    for b in &plan.bodies {
        if let Some(p) = b.parent {
            carries[p.index()] = true;
        }
    }
    // The joint whose velocities start at each offset.
    let mut joint_at = vec![None; plan.nv];
    for (k, j) in plan.joints.iter().enumerate() {
        if j.coord.nv() > 0 {
            joint_at[j.v_offset] = Some(k);
        }
    }
    groups
        .iter()
        .map(|g| {
            let k = joint_at[*g.first()?]?;
            let j = &plan.joints[k];
            let lone = j.coord.free_velocities().is_some()
                && plan.bodies[j.body].parent.is_none()
                && !carries[j.body.index()]
                && g.len() == 6
                && g.iter().enumerate().all(|(i, &v)| v == j.v_offset + i)
                && g.iter().all(|&v| plan.prescribed[v].is_none());
            lone.then_some(k)
        })
        .collect()
}

/// The velocity rows' columns of `∂F/∂y'` for joint `j`, a root body alone on a free joint:
/// `Sᵀ I S e_k` for `k = 0..6` (`I` the body's spatial inertia about its origin; `S` the
/// identity in the child frame, `diag(Rᵀ, Rᵀ)` in obj1), written at rows and columns
/// `v0..v0 + 6`. The operations a Newton–Euler pass with a unit acceleration does for this
/// body, without the terms that are zero at zero velocity and gravity. `ws` holds the joint
/// transform at the Jacobian's `q`.
fn free_mass_columns(
    plan: &Plan,
    ws: &Workspace,
    q: &[f64],
    j: usize,
    v0: usize,
    out: &mut dyn crate::solver::JacobianSink,
) {
    let jp = &plan.joints[j];
    let (b, qj) = (jp.body, &q[jp.q_offset..jp.q_offset + jp.coord.nq()]);
    let (xj, inertia) = (&ws.xj[b], &plan.bodies[b].inertia);
    let mut col = [0.0; 6];
    for k in 0..6 {
        let mut e = [0.0; 6];
        e[k] = 1.0;
        let f = inertia.mul_motion(&jp.coord.motion_at(xj, qj, &e));
        jp.coord.project_at(xj, qj, &f, &mut col);
        out.add(v0, v0 + k, &col);
    }
}

/// `Err` (fatal) if a force law failed in the last `forces::applied_forces` of `ws`; the
/// driver takes the fault (with the element's name) when IDA stops.
fn fault_check(ws: &Workspace) -> Result<(), ResidualError> {
    match &ws.fault {
        Some(f) => Err(ResidualError::Fatal(format!(
            "{} failed at t = {} s",
            f.element_name(),
            f.t
        ))),
        None => Ok(()),
    }
}

impl MultibodyDae {
    /// [`DaeSystem::residual`]; with `quotient`, a quotient residual after
    /// [`DaeSystem::quotient_residual`] has flagged the bodies: only the touched bodies are
    /// placed (the others restored from the Jacobian's point), the contact stage reuses the
    /// geometry of the pairs of bodies not moved, the dynamics rows are computed for the live
    /// trees and taken from the Jacobian's point for the others.
    fn residual_with(
        &mut self,
        t: f64,
        y: &[f64],
        yp: &[f64],
        res: &mut [f64],
        quotient: bool,
    ) -> Result<(), ResidualError> {
        let plan = &*self.plan;
        let nq = plan.nq;
        // The components' rows `ẋ − f = 0` after the multibody ones (`dynamics/components.rs`).
        let xo = plan.x_offset();
        let (y, x) = y.split_at(xo.min(y.len()));
        let (yp, xd) = yp.split_at(xo.min(yp.len()));
        let (res, res_x) = res.split_at_mut(xo.min(res.len()));
        if nq + plan.nv == 0 {
            if let Some(cs) = self.comps.as_deref_mut() {
                let at = Point {
                    t,
                    q: &[],
                    v: &[],
                    a: &[],
                    x,
                };
                if let Err(f) = cs.evaluate(&plan.components, &at, &mut []) {
                    self.ws.fault.get_or_insert(f);
                }
                fault_check(&self.ws)?;
                for ((r, d), f) in res_x.iter_mut().zip(xd).zip(&cs.xdot) {
                    *r = d - f;
                }
            }
            if plan.components.nx == 0 {
                // The dummy state of a scene without unknowns (see `len`).
                res_x[0] = xd[0];
            }
            return Ok(());
        }
        let (nv, m) = (plan.nv, plan.loops.m());
        let (q, rest) = y.split_at(nq);
        let (v, mult) = rest.split_at(nv);
        let (qd, rest) = yp.split_at(nq);
        let vd = &rest[..nv];
        let (res_q, rest) = res.split_at_mut(nq);
        let (res_v, res_c) = rest.split_at_mut(nv);
        if quotient {
            kinematics::touched_position_velocity(
                plan,
                &mut self.ws,
                &self.base_states,
                &self.touched,
                q,
                v,
            );
        } else {
            kinematics::position_velocity(plan, &mut self.ws, q, v);
        }
        forces::applied_forces(plan, &mut self.ws, t, q, v);
        if let Some(cs) = self.comps.as_deref_mut() {
            let at = Point { t, q, v, a: vd, x };
            if let Err(f) = cs.evaluate(&plan.components, &at, &mut self.ws.tau_applied) {
                self.ws.fault.get_or_insert(f);
            }
            for ((r, d), f) in res_x.iter_mut().zip(xd).zip(&cs.xdot) {
                *r = d - f;
            }
        }
        fault_check(&self.ws)?;
        if let (Some(cs), Some(cp)) = (self.contact.as_mut(), self.contact_plan.as_deref()) {
            if quotient {
                cs.evaluate_moved(plan, cp, &mut self.ws, t, &self.moved)
            } else {
                cs.evaluate(plan, cp, &mut self.ws, Mode::Continuous, t)
            }
            .map_err(|e| ResidualError::Fatal(e.to_string()))?;
        }
        if let Some(l) = self.limits.as_deref_mut() {
            l.state.apply(&l.plan, q, v, &mut self.ws.tau_applied);
        }
        if m > 0 {
            // Stabilised index 2 (dynamics/loops.rs): kinematics at v + Gᵀμ, constraint
            // wrenches of λ as external forces, then g(q) = 0 and G v = 0.
            let (lambda, mu) = mult.split_at(m);
            self.lw.evaluate(plan, &self.ws);
            self.lw.stabilised_velocity(plan, &self.ws, q, v, mu);
            self.lw.apply_forces(plan, &mut self.ws, lambda);
            kinematics::position_residual(plan, q, &self.lw.w, qd, res_q);
            let (res_g, res_gv) = res_c.split_at_mut(m);
            res_g.copy_from_slice(&self.lw.g);
            res_gv.copy_from_slice(&self.lw.gv);
        } else {
            kinematics::position_residual(plan, q, v, qd, res_q);
        }
        let live = quotient.then_some(&self.live[..]);
        rnea::residual_dynamics(plan, &mut self.ws, (q, vd), &plan.gravity, res_v, live);
        for (r, tau) in res_v.iter_mut().zip(&self.ws.tau_applied) {
            *r -= tau;
        }
        // Prescribed motion: the acceleration row becomes v̇ − a_input = 0.
        for (k, p) in plan.prescribed.iter().enumerate() {
            if let Some(i) = p {
                res_v[k] = vd[k] - self.ws.inputs[*i];
            }
        }
        if quotient {
            // The rows of the trees the perturbation leaves alone: those of the Jacobian's
            // point (the same bits: their inputs are the same).
            for j in &plan.joints {
                if !self.live[j.body.index()] {
                    let (v0, n) = (nq + j.v_offset, j.coord.nv());
                    res_v[j.v_offset..j.v_offset + n].copy_from_slice(&self.base_res[v0..v0 + n]);
                }
            }
        }
        Ok(())
    }
}
