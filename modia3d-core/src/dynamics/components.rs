//! The components' stage of the residual (docs/drive-trains.md): their outputs in an order
//! without algebraic loops, their states' rows `ẋ − f = 0`, their flange forces added to the
//! joints' generalised forces, their zero crossings (one root function, the smallest of
//! them) and their discrete states, changed at events only. The plan is immutable; the
//! scratch is sized when it is built, so an evaluation allocates nothing.

use super::forces::{panic_text, FaultKind, UserFault};
use super::ids::JointId;
use super::plan::JointPlan;
use crate::scene::validate::components::{SigRef, ValidComponents, ValidSrc};
use crate::scene::{
    Component, ComponentIo, ComponentJacobian, FlangeMotion, OutputSpec, SrcFn, StateSpec,
};
use std::ops::Range;
use std::panic::{catch_unwind, AssertUnwindSafe};
use std::sync::Arc;

/// A signal with plan indices.
#[derive(Clone, Copy, Debug, PartialEq)]
enum PlanRef {
    Time,
    /// Index into the outputs `y`.
    Out(usize),
    /// Index into the continuous states `x`.
    X(usize),
    /// Index into the discrete states `d`.
    D(usize),
    /// Index into `q`.
    Q(usize),
    /// Index into `v`.
    V(usize),
    /// Index into `v̇`.
    A(usize),
}

#[derive(Clone)]
enum PlanSrc {
    Const(f64),
    Ref(PlanRef),
    /// The dependencies, the function, and the offset of their values in the scratch.
    Expr(Vec<PlanRef>, Arc<SrcFn>, usize),
}

impl std::fmt::Debug for PlanSrc {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            PlanSrc::Const(v) => write!(f, "Const({v})"),
            PlanSrc::Ref(r) => write!(f, "Ref({r:?})"),
            PlanSrc::Expr(d, _, o) => write!(f, "Expr({d:?}, at {o})"),
        }
    }
}

/// One component with its slices of the shared vectors.
#[derive(Clone, Debug)]
pub(crate) struct CompPlan {
    pub name: String,
    pub component: Arc<dyn Component>,
    pub x: Range<usize>,
    pub y: Range<usize>,
    pub d: Range<usize>,
    pub z: Range<usize>,
    u: Range<usize>,
    fl: Range<usize>,
    inputs: Vec<PlanSrc>,
    /// Per flange: position and velocity index (into `q`, `v`).
    flanges: Vec<(usize, usize)>,
    /// Whether an output has feedthrough (evaluated again once its inputs are known).
    feedthrough: bool,
    /// Whether an output has none (evaluated before the inputs are known).
    stateful_outputs: bool,
    pub outputs: Vec<OutputSpec>,
    pub states: Vec<StateSpec>,
    pub discrete: Vec<StateSpec>,
    /// Offsets of its partial derivatives in [`JacobianScratch`]: `∂ẋ/∂x`, `∂ẋ/∂u`, `∂y/∂x`,
    /// `∂y/∂u`, `∂F/∂x`, `∂F/∂u` (row-major, its own sizes).
    jac: [usize; 6],
}

/// The components of a plan (empty without any).
#[derive(Clone, Debug, Default)]
pub(crate) struct ComponentPlan {
    pub comps: Vec<CompPlan>,
    order: Vec<usize>,
    pub nx: usize,
    pub ny: usize,
    pub nd: usize,
    pub nz: usize,
    nu: usize,
    nfl: usize,
    n_dep: usize,
    /// Number of velocity coordinates of the plan.
    nv: usize,
    /// Initial continuous and discrete states.
    pub x0: Vec<f64>,
    pub d0: Vec<f64>,
    /// Nominal sizes of the continuous states.
    pub x_nominal: Vec<f64>,
    /// Velocity indices the components read or drive (their trees are coupled to them).
    pub v_touched: Vec<usize>,
    /// Velocity indices of the coordinates flanges drive, sorted, each once (the flange
    /// forces recorded for the joint loads).
    pub flange_v: Vec<usize>,
    /// Whether a component reads an acceleration (a `der(…)` signal or its flanges'): the
    /// consistent derivatives then iterate on them.
    pub reads_acceleration: bool,
    /// Whether every component gives its partial derivatives
    /// ([`Component::provides_jacobian`]) or has none (no states and no inputs): the states'
    /// columns are then formed by [`ComponentState::state_columns`].
    pub all_jacobians: bool,
    /// Sizes of the six partial-derivative arrays of all components together.
    jac_len: [usize; 6],
}

impl ComponentPlan {
    /// The components of `vc` with the joints' coordinates placed by `tree_joint_of` (index in
    /// `ValidScene::joints` → tree joint) and `joints`; also the reflected inertia per velocity
    /// coordinate (empty if none).
    pub(crate) fn compile(
        vc: &ValidComponents,
        tree_joint_of: &[Option<JointId>],
        joints: &[JointPlan],
        nv: usize,
    ) -> (ComponentPlan, Vec<f64>) {
        let mut p = ComponentPlan::default();
        let mut armature = vec![0.0; nv];
        let coord = |j: usize, k: usize| -> Option<(usize, usize)> {
            let jp = &joints[tree_joint_of.get(j).copied().flatten()?.index()];
            let c = jp.coord.coordinates().get(k)?;
            Some((jp.q_offset + c.q, jp.v_offset + c.v))
        };
        // Offsets first (signals refer across components).
        let mut offs = vec![];
        let (mut nx, mut ny, mut nd, mut nz, mut nu, mut nfl) = (0, 0, 0, 0, 0, 0);
        for c in &vc.list {
            let o = (nx, ny, nd, nz, nu, nfl);
            nx += c.states.len();
            ny += c.outputs.len();
            nd += c.discrete.len();
            nz += c.n_crossings;
            nu += c.inputs.len();
            nfl += c.flanges.len();
            offs.push(o);
        }
        let mut n_dep = 0;
        let mut touched = vec![];
        let resolve = |r: &SigRef, touched: &mut Vec<usize>| -> PlanRef {
            match *r {
                SigRef::Time => PlanRef::Time,
                SigRef::Output(c, k) => PlanRef::Out(offs[c].1 + k),
                SigRef::State(c, k) => PlanRef::X(offs[c].0 + k),
                SigRef::Discrete(c, k) => PlanRef::D(offs[c].2 + k),
                SigRef::JointPos(j, k) => match coord(j, k) {
                    Some((qi, vi)) => {
                        touched.push(vi);
                        PlanRef::Q(qi)
                    }
                    None => PlanRef::Time, // validated: tree joints only
                },
                SigRef::JointVel(j, k) => match coord(j, k) {
                    Some((_, vi)) => {
                        touched.push(vi);
                        PlanRef::V(vi)
                    }
                    None => PlanRef::Time,
                },
                SigRef::JointAcc(j, k) => match coord(j, k) {
                    Some((_, vi)) => {
                        touched.push(vi);
                        PlanRef::A(vi)
                    }
                    None => PlanRef::Time,
                },
            }
        };
        let mut jac_len = [0usize; 6];
        for (ci, c) in vc.list.iter().enumerate() {
            let (x0, y0, d0, z0, u0, f0) = offs[ci];
            let (cx, cy, cu) = (c.states.len(), c.outputs.len(), c.inputs.len());
            let cf = c.flanges.len();
            let jac = jac_len;
            for (len, add) in
                jac_len
                    .iter_mut()
                    .zip([cx * cx, cx * cu, cy * cx, cy * cu, cf * cx, cf * cu])
            {
                *len += add;
            }
            let mut inputs = vec![];
            for s in &c.inputs {
                inputs.push(match s {
                    ValidSrc::Const(v) => PlanSrc::Const(*v),
                    ValidSrc::Ref(r) => PlanSrc::Ref(resolve(r, &mut touched)),
                    ValidSrc::Expr(deps, f) => {
                        let d: Vec<PlanRef> =
                            deps.iter().map(|r| resolve(r, &mut touched)).collect();
                        let at = n_dep;
                        n_dep += d.len();
                        PlanSrc::Expr(d, f.clone(), at)
                    }
                });
            }
            let mut flanges = vec![];
            for &(j, k, inertia) in &c.flanges {
                if let Some((qi, vi)) = coord(j, k) {
                    flanges.push((qi, vi));
                    armature[vi] += inertia;
                    touched.push(vi);
                }
            }
            p.x0.extend(c.states.iter().map(|s| s.start));
            p.x_nominal.extend(c.states.iter().map(|s| s.nominal));
            p.d0.extend(c.discrete.iter().map(|s| s.start));
            p.comps.push(CompPlan {
                name: c.name.clone(),
                component: c.component.clone(),
                x: x0..x0 + c.states.len(),
                y: y0..y0 + c.outputs.len(),
                d: d0..d0 + c.discrete.len(),
                z: z0..z0 + c.n_crossings,
                u: u0..u0 + c.inputs.len(),
                fl: f0..f0 + flanges.len(),
                inputs,
                flanges,
                feedthrough: c.outputs.iter().any(|o| o.feedthrough),
                stateful_outputs: c.outputs.iter().any(|o| !o.feedthrough),
                outputs: c.outputs.clone(),
                states: c.states.clone(),
                discrete: c.discrete.clone(),
                jac,
            });
        }
        touched.sort_unstable();
        touched.dedup();
        p.reads_acceleration = vc.list.iter().any(|c| {
            c.component.reads_flange_acceleration()
                || c.inputs.iter().any(|s| match s {
                    ValidSrc::Const(_) => false,
                    ValidSrc::Ref(r) => matches!(r, SigRef::JointAcc(..)),
                    ValidSrc::Expr(d, _) => d.iter().any(|r| matches!(r, SigRef::JointAcc(..))),
                })
        });
        p.order.clone_from(&vc.order);
        // A component without states and inputs (a source) has no partial derivatives to give.
        p.all_jacobians = vc.list.iter().all(|c| {
            (c.states.is_empty() && c.inputs.is_empty()) || c.component.provides_jacobian()
        });
        p.jac_len = jac_len;
        (p.nx, p.ny, p.nd, p.nz, p.nu, p.nfl, p.n_dep) = (nx, ny, nd, nz, nu, nfl, n_dep);
        p.nv = nv;
        p.v_touched = touched;
        p.flange_v = p.flange_coordinates().map(|(_, v)| v).collect();
        p.flange_v.sort_unstable();
        p.flange_v.dedup();
        if armature.iter().all(|&a| a == 0.0) {
            armature.clear();
        }
        (p, armature)
    }

    /// The `(q, v)` indices of every coordinate a flange drives (repeats possible).
    pub(crate) fn flange_coordinates(&self) -> impl Iterator<Item = (usize, usize)> + '_ {
        self.comps.iter().flat_map(|c| c.flanges.iter().copied())
    }

    /// `<component>.<state>` of every continuous state, in state order.
    pub(crate) fn state_names(&self) -> impl Iterator<Item = String> + '_ {
        self.comps.iter().flat_map(|c| {
            c.states
                .iter()
                .map(move |s| format!("{}.{}", c.name, s.name))
        })
    }
}

/// The mutable scratch and discrete states of the components.
#[derive(Clone, Debug)]
pub(crate) struct ComponentState {
    /// Outputs of the last evaluation.
    pub y: Vec<f64>,
    /// Discrete states.
    pub d: Vec<f64>,
    /// Crossing functions of the last [`ComponentState::crossings`].
    pub z: Vec<f64>,
    u: Vec<f64>,
    fl: Vec<FlangeMotion>,
    ff: Vec<f64>,
    dep: Vec<f64>,
    /// Scratch of the derivatives `ẋ = f`.
    pub xdot: Vec<f64>,
    d_new: Vec<f64>,
    /// The analytic states' columns' scratch (empty unless every component gives its
    /// partial derivatives).
    jac: JacobianScratch,
}

/// Scratch of [`ComponentState::state_columns`], sized with the plan.
#[derive(Clone, Debug, Default)]
struct JacobianScratch {
    /// The components' partial derivatives (see `CompPlan::jac`).
    parts: [Vec<f64>; 6],
    /// `∂(expression)/∂(dependency)` of every expression input, at the dependencies' offsets.
    dexpr: Vec<f64>,
    /// Directional derivatives of the outputs and inputs along one state.
    dy: Vec<f64>,
    du: Vec<f64>,
    /// Flange forces of an evaluation (len nv; discarded).
    tau: Vec<f64>,
}

/// The values a component evaluation reads.
#[derive(Clone, Copy)]
pub(crate) struct Point<'a> {
    pub t: f64,
    pub q: &'a [f64],
    pub v: &'a [f64],
    /// The accelerations `v̇` (empty where no component reads them: read as 0).
    pub a: &'a [f64],
    pub x: &'a [f64],
}

impl ComponentState {
    pub(crate) fn new(p: &ComponentPlan) -> Self {
        ComponentState {
            y: vec![0.0; p.ny],
            d: p.d0.clone(),
            z: vec![0.0; p.nz],
            u: vec![0.0; p.nu],
            fl: vec![FlangeMotion::default(); p.nfl],
            ff: vec![0.0; p.nfl],
            dep: vec![0.0; p.n_dep],
            xdot: vec![0.0; p.nx],
            d_new: p.d0.clone(),
            jac: if p.all_jacobians && p.nx > 0 {
                JacobianScratch {
                    parts: p.jac_len.map(|n| vec![0.0; n]),
                    dexpr: vec![0.0; p.n_dep],
                    dy: vec![0.0; p.ny],
                    du: vec![0.0; p.nu],
                    tau: vec![0.0; p.nv],
                }
            } else {
                JacobianScratch::default()
            },
        }
    }

    fn value(&self, r: PlanRef, at: &Point<'_>) -> f64 {
        match r {
            PlanRef::Time => at.t,
            PlanRef::Out(i) => self.y[i],
            PlanRef::X(i) => at.x[i],
            PlanRef::D(i) => self.d[i],
            PlanRef::Q(i) => at.q[i],
            PlanRef::V(i) => at.v[i],
            PlanRef::A(i) => at.a.get(i).copied().unwrap_or(0.0),
        }
    }

    /// Fills the inputs and flange motions of component `c`; a panic of an expression is a
    /// fault.
    fn gather(&mut self, c: &CompPlan, at: &Point<'_>) -> Result<(), UserFault> {
        for (k, s) in c.inputs.iter().enumerate() {
            let v = match s {
                PlanSrc::Const(v) => *v,
                PlanSrc::Ref(r) => self.value(*r, at),
                PlanSrc::Expr(deps, f, o) => {
                    for (i, &r) in deps.iter().enumerate() {
                        self.dep[o + i] = self.value(r, at);
                    }
                    let vals = &self.dep[*o..o + deps.len()];
                    let t = at.t;
                    guarded(c, at.t, || f(t, vals))?
                }
            };
            self.u[c.u.start + k] = v;
        }
        for (k, &(qi, vi)) in c.flanges.iter().enumerate() {
            self.fl[c.fl.start + k] = FlangeMotion {
                position: at.q[qi],
                velocity: at.v[vi],
                acceleration: at.a.get(vi).copied().unwrap_or(0.0),
            };
        }
        Ok(())
    }

    /// Every output at `at`: those without feedthrough first, then, in the plan's order, the
    /// components with feedthrough once their inputs are known.
    pub(crate) fn outputs(&mut self, p: &ComponentPlan, at: &Point<'_>) -> Result<(), UserFault> {
        self.u.fill(0.0);
        for c in p.comps.iter().filter(|c| c.stateful_outputs) {
            for (k, &(qi, vi)) in c.flanges.iter().enumerate() {
                self.fl[c.fl.start + k] = FlangeMotion {
                    position: at.q[qi],
                    velocity: at.v[vi],
                    acceleration: at.a.get(vi).copied().unwrap_or(0.0),
                };
            }
            self.call_outputs(c, at)?;
        }
        for &i in &p.order {
            let c = &p.comps[i];
            if c.feedthrough {
                self.gather(c, at)?;
                self.call_outputs(c, at)?;
            }
        }
        for c in &p.comps {
            if let Some(k) = self.y[c.y.clone()].iter().position(|v| !v.is_finite()) {
                let (name, v) = (&c.outputs[k].name, self.y[c.y.start + k]);
                return Err(fault(
                    c,
                    at.t,
                    FaultKind::Undefined(format!("its output `{name}` is {v}")),
                ));
            }
        }
        Ok(())
    }

    fn call_outputs(&mut self, c: &CompPlan, at: &Point<'_>) -> Result<(), UserFault> {
        let io = io(c, at, (&self.d, &self.u, &self.fl));
        let y = &mut self.y[c.y.clone()];
        guarded(c, at.t, || c.component.outputs_at(&io, y))
    }

    /// The outputs, then every derivative into `xdot` and the flange forces added to `tau`
    /// (len nv).
    pub(crate) fn evaluate(
        &mut self,
        p: &ComponentPlan,
        at: &Point<'_>,
        tau: &mut [f64],
    ) -> Result<(), UserFault> {
        self.outputs(p, at)?;
        for c in &p.comps {
            if !c.feedthrough {
                self.gather(c, at)?;
            }
            let io = io(c, at, (&self.d, &self.u, &self.fl));
            let xdot = &mut self.xdot[c.x.clone()];
            let ff = &mut self.ff[c.fl.clone()];
            ff.fill(0.0);
            guarded(c, at.t, || c.component.derivatives(&io, xdot, ff))?;
            if let Some(k) = xdot.iter().position(|v| !v.is_finite()) {
                let (name, v) = (&c.states[k].name, xdot[k]);
                return Err(fault(
                    c,
                    at.t,
                    FaultKind::Undefined(format!("the derivative of its state `{name}` is {v}")),
                ));
            }
            for (k, &(_, vi)) in c.flanges.iter().enumerate() {
                let f = self.ff[c.fl.start + k];
                if !f.is_finite() {
                    return Err(fault(
                        c,
                        at.t,
                        FaultKind::Undefined(format!("its flange force is {f}")),
                    ));
                }
                tau[vi] += f;
            }
        }
        Ok(())
    }

    /// The smallest crossing function of all components at `at` (`+∞` without any), after
    /// [`Self::outputs`].
    pub(crate) fn min_crossing(
        &mut self,
        p: &ComponentPlan,
        at: &Point<'_>,
    ) -> Result<f64, UserFault> {
        self.outputs(p, at)?;
        let mut m = f64::INFINITY;
        for c in p.comps.iter().filter(|c| !c.z.is_empty()) {
            self.gather(c, at)?;
            let io = io(c, at, (&self.d, &self.u, &self.fl));
            let z = &mut self.z[c.z.clone()];
            guarded(c, at.t, || c.component.crossings(&io, z))?;
            for &v in z.iter() {
                m = m.min(if v.is_nan() { -1.0 } else { v });
            }
        }
        Ok(m)
    }

    /// An event at `at`: every component sets its new discrete states from the signals with
    /// the old ones, repeated until none changes (at most 20 rounds: a limiter's new mode may
    /// change another's input). Returns whether any changed.
    pub(crate) fn event(&mut self, p: &ComponentPlan, at: &Point<'_>) -> Result<bool, UserFault> {
        let mut changed = false;
        for _ in 0..20 {
            self.outputs(p, at)?;
            self.d_new.clone_from(&self.d);
            for c in &p.comps {
                self.gather(c, at)?;
                let io = io(c, at, (&self.d, &self.u, &self.fl));
                let dn = &mut self.d_new[c.d.clone()];
                guarded(c, at.t, || c.component.event(&io, dn))?;
            }
            if self.d_new == self.d {
                return Ok(changed);
            }
            if let Some(i) = self.d_new.iter().position(|v| !v.is_finite()) {
                let c = p
                    .comps
                    .iter()
                    .find(|c| c.d.contains(&i))
                    .unwrap_or(&p.comps[0]);
                return Err(fault(
                    c,
                    at.t,
                    FaultKind::Undefined(format!(
                        "its discrete state `{}` became {}",
                        c.discrete[i - c.d.start].name,
                        self.d_new[i]
                    )),
                ));
            }
            std::mem::swap(&mut self.d, &mut self.d_new);
            changed = true;
        }
        Ok(changed)
    }

    /// The first time event of any component strictly after `t` \[s\].
    pub(crate) fn next_time_event(&self, p: &ComponentPlan, t: f64) -> Option<f64> {
        p.comps
            .iter()
            .filter_map(|c| {
                catch_unwind(AssertUnwindSafe(|| {
                    c.component.next_time_event(t, &self.d[c.d.clone()])
                }))
                .ok()
                .flatten()
            })
            .filter(|s| s.is_finite() && *s > t)
            .min_by(f64::total_cmp)
    }
}

impl ComponentState {
    /// The iteration matrix's columns of the components' states when every component gives
    /// its partial derivatives ([`ComponentPlan::all_jacobians`]): at `at`, for each state
    /// `x_j`, the directional derivative of every signal along it by the chain rule in the
    /// outputs' evaluation order (outputs without feedthrough first, then the plan's order),
    /// then `emit(StateRow(i), j, value)` for the components' rows (`c_j·δ_ij − ∂ẋ_i/∂x_j`;
    /// rows numbered from 0 over the states), `emit(Force(v), j, value)` for the derivative of
    /// the generalised force on velocity coordinate `v` (several may name the same `v`: they
    /// add), and `emit(Done, j, 0)` when column `j` is complete.
    /// Joint positions, velocities and accelerations do not depend on `x`, so they contribute
    /// nothing here. An expression input's partial derivatives are central differences of its
    /// function alone (step `6e-6·max(|value|, 1)`, relative error ~1e-10).
    pub(crate) fn state_columns(
        &mut self,
        p: &ComponentPlan,
        at: &Point<'_>,
        c_j: f64,
        mut emit: impl FnMut(ColumnRow, usize, f64),
    ) -> Result<(), UserFault> {
        let mut tau = std::mem::take(&mut self.jac.tau);
        tau.fill(0.0);
        let evaluated = self.evaluate(p, at, &mut tau);
        self.jac.tau = tau;
        evaluated?;
        // Every component's partial derivatives at `at`, with the inputs, flange motions and
        // expression dependencies the evaluation gathered (every component's, once).
        for c in &p.comps {
            let io = io(c, at, (&self.d, &self.u, &self.fl));
            let [fx, fu, yx, yu, tx, tu] = &mut self.jac.parts;
            let (cx, cy, cu, cf) = (c.x.len(), c.y.len(), c.u.len(), c.fl.len());
            let o = c.jac;
            let mut jac = ComponentJacobian {
                nx: cx,
                nu: cu,
                f_x: &mut fx[o[0]..o[0] + cx * cx],
                f_u: &mut fu[o[1]..o[1] + cx * cu],
                y_x: &mut yx[o[2]..o[2] + cy * cx],
                y_u: &mut yu[o[3]..o[3] + cy * cu],
                t_x: &mut tx[o[4]..o[4] + cf * cx],
                t_u: &mut tu[o[5]..o[5] + cf * cu],
            };
            for m in [
                &mut *jac.f_x,
                &mut *jac.f_u,
                &mut *jac.y_x,
                &mut *jac.y_u,
                &mut *jac.t_x,
                &mut *jac.t_u,
            ] {
                m.fill(0.0);
            }
            guarded(c, at.t, || c.component.jacobian(&io, &mut jac))?;
            let bad = [&jac.f_x, &jac.f_u, &jac.y_x, &jac.y_u, &jac.t_x, &jac.t_u]
                .iter()
                .any(|m| m.iter().any(|v| !v.is_finite()));
            if bad {
                return Err(fault(
                    c,
                    at.t,
                    FaultKind::Undefined(
                        "a partial derivative of its Jacobian is not finite".into(),
                    ),
                ));
            }
            // The expressions' partial derivatives.
            for s in &c.inputs {
                if let PlanSrc::Expr(deps, f, o) = s {
                    for i in 0..deps.len() {
                        let v0 = self.dep[o + i];
                        let h = 6e-6 * v0.abs().max(1.0);
                        let t = at.t;
                        self.dep[o + i] = v0 + h;
                        let plus = guarded(c, t, || f(t, &self.dep[*o..o + deps.len()]))?;
                        self.dep[o + i] = v0 - h;
                        let minus = guarded(c, t, || f(t, &self.dep[*o..o + deps.len()]))?;
                        self.dep[o + i] = v0;
                        self.jac.dexpr[o + i] = (plus - minus) / (2.0 * h);
                    }
                }
            }
        }
        let parts = &self.jac.parts;
        for owner in &p.comps {
            for lj in 0..owner.x.len() {
                let j = owner.x.start + lj;
                self.jac.dy.fill(0.0);
                // Outputs without feedthrough depend on the owner's states only.
                let cx = owner.x.len();
                for (k, spec) in owner.outputs.iter().enumerate() {
                    if !spec.feedthrough {
                        self.jac.dy[owner.y.start + k] = parts[2][owner.jac[2] + k * cx + lj];
                    }
                }
                // Outputs with feedthrough, in evaluation order.
                for &i in &p.order {
                    let c = &p.comps[i];
                    if !c.feedthrough {
                        continue;
                    }
                    directional_inputs(c, j, &self.jac.dexpr, &self.jac.dy, &mut self.jac.du);
                    let (cx, cu) = (c.x.len(), c.u.len());
                    for (k, spec) in c.outputs.iter().enumerate() {
                        if !spec.feedthrough {
                            continue;
                        }
                        let mut d = if c.x.contains(&j) {
                            parts[2][c.jac[2] + k * cx + (j - c.x.start)]
                        } else {
                            0.0
                        };
                        for m in 0..cu {
                            d += parts[3][c.jac[3] + k * cu + m] * self.jac.du[c.u.start + m];
                        }
                        self.jac.dy[c.y.start + k] = d;
                    }
                }
                // Every component's rows and flange forces.
                for c in &p.comps {
                    directional_inputs(c, j, &self.jac.dexpr, &self.jac.dy, &mut self.jac.du);
                    let (cx, cu) = (c.x.len(), c.u.len());
                    let own = c.x.contains(&j).then(|| j - c.x.start);
                    for i in 0..cx {
                        let mut d = own.map_or(0.0, |l| parts[0][c.jac[0] + i * cx + l]);
                        for m in 0..cu {
                            d += parts[1][c.jac[1] + i * cu + m] * self.jac.du[c.u.start + m];
                        }
                        let diag = if own == Some(i) { c_j } else { 0.0 };
                        emit(ColumnRow::State(c.x.start + i), j, diag - d);
                    }
                    for (k, &(_, vi)) in c.flanges.iter().enumerate() {
                        let mut d = own.map_or(0.0, |l| parts[4][c.jac[4] + k * cx + l]);
                        for m in 0..cu {
                            d += parts[5][c.jac[5] + k * cu + m] * self.jac.du[c.u.start + m];
                        }
                        if d != 0.0 {
                            emit(ColumnRow::Force(vi), j, d);
                        }
                    }
                }
                emit(ColumnRow::Done, j, 0.0);
            }
        }
        Ok(())
    }
}

/// A row of [`ComponentState::state_columns`]' entries.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum ColumnRow {
    /// The row of continuous state `i` (over all components' states).
    State(usize),
    /// The generalised force on velocity coordinate `v`.
    Force(usize),
    /// The column is complete.
    Done,
}

/// The directional derivatives `du` of component `c`'s inputs along state `j`, from those of
/// the outputs `dy` and the expressions' partial derivatives `dexpr`.
fn directional_inputs(c: &CompPlan, j: usize, dexpr: &[f64], dy: &[f64], du: &mut [f64]) {
    let along = |r: PlanRef| match r {
        PlanRef::Out(i) => dy[i],
        PlanRef::X(i) if i == j => 1.0,
        _ => 0.0,
    };
    for (k, s) in c.inputs.iter().enumerate() {
        du[c.u.start + k] = match s {
            PlanSrc::Const(_) => 0.0,
            PlanSrc::Ref(r) => along(*r),
            PlanSrc::Expr(deps, _, o) => deps
                .iter()
                .enumerate()
                .map(|(i, &r)| dexpr[o + i] * along(r))
                .sum(),
        };
    }
}

/// What component `c` sees at `at`, from the slices of the shared vectors.
fn io<'a>(
    c: &CompPlan,
    at: &Point<'a>,
    (d, u, fl): (&'a [f64], &'a [f64], &'a [FlangeMotion]),
) -> ComponentIo<'a> {
    ComponentIo {
        t: at.t,
        x: &at.x[c.x.clone()],
        d: &d[c.d.clone()],
        u: &u[c.u.clone()],
        flanges: &fl[c.fl.clone()],
    }
}

/// Calls `f` (a method of component `c` at time `t`), a panic being the component's fault.
fn guarded<R>(c: &CompPlan, t: f64, f: impl FnOnce() -> R) -> Result<R, UserFault> {
    catch_unwind(AssertUnwindSafe(f)).map_err(|e| fault(c, t, FaultKind::Panic(panic_text(&*e))))
}

fn fault(c: &CompPlan, t: f64, kind: FaultKind) -> UserFault {
    UserFault {
        object: c.name.clone(),
        what: c.component.kind(),
        element: None,
        t,
        kind,
    }
}
