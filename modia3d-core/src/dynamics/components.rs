//! The components' stage of the residual (docs/drive-trains.md): their outputs in an order
//! without algebraic loops, their states' rows `ẋ − f = 0`, their flange forces added to the
//! joints' generalised forces, their zero crossings (one root function, the smallest of
//! them) and their discrete states, changed at events only. The plan is immutable; the
//! scratch is sized when it is built, so an evaluation allocates nothing.

use super::forces::{panic_text, FaultKind, UserFault};
use super::ids::JointId;
use super::plan::JointPlan;
use crate::scene::validate::components::{SigRef, ValidComponents, ValidSrc};
use crate::scene::{Component, ComponentIo, FlangeMotion, OutputSpec, SrcFn, StateSpec};
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
        for (ci, c) in vc.list.iter().enumerate() {
            let (x0, y0, d0, z0, u0, f0) = offs[ci];
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
        (p.nx, p.ny, p.nd, p.nz, p.nu, p.nfl, p.n_dep) = (nx, ny, nd, nz, nu, nfl, n_dep);
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
