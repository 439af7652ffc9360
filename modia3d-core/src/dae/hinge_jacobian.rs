//! DAE stage: exact Jacobian columns of **hinge trees** — joint trees of Revolute, Prismatic
//! and Cylindrical joints (robot arms, pendulum chains, linkages without loops) — instead of the
//! solver's difference quotients, which cost one residual evaluation per unknown of the tree
//! (a 20-link chain: 40 per Jacobian, 80 % of all residual evaluations of its run).
//!
//! A column of the iteration matrix `J = ∂F/∂y + c_j ∂F/∂y'` is the directional derivative
//! of the residual along `(δy, δy') = (e_k, c_j e_k)`, and here it is a tangent (forward-mode)
//! pass of the residual's own recursions at the Jacobian's point:
//!
//! - position rows `q̇ − v`: `c_j` in a position's column, `−1` in its velocity's;
//! - velocity rows, the row-operated Newton–Euler residual of `dynamics/rnea.rs`
//!   (`R_i = Sᵢᵀ fᵢ − τ_applied,i`, each body passing `fᵢ − Sᵢ Rᵢ` to its parent), with
//!   `Sᵢ` constant in the child frame for these kinds (`(a, 0)`, `(0, a)`, both for a
//!   cylindrical joint, whose turn and shift about the same axis commute) and the joint
//!   transform's derivative `∂(Xᵢ m)/∂qᵢ꜀ = −Sᵢ꜀ ×ₘ (Xᵢ m)` for each coordinate `c` (for
//!   `Xᵢ = X_J(qᵢ) X_tree`, Featherstone §2.9); written below for one coordinate:
//!   - forward, parents first: `δvᵢ = Xᵢ δv_p − δqᵢ Sᵢ ×ₘ (Xᵢ v_p) + Sᵢ δq̇ᵢ`,
//!     `δaᵢ = Xᵢ δa_p − δqᵢ Sᵢ ×ₘ (Xᵢ a_p) + Sᵢ δv̇ᵢ + δvᵢ ×ₘ (Sᵢ q̇ᵢ) + vᵢ ×ₘ (Sᵢ δq̇ᵢ)`
//!     (the world's `a = −g` is constant), `δfᵢ = Iᵢ δaᵢ + δvᵢ ×f Iᵢ vᵢ + vᵢ ×f Iᵢ δvᵢ`;
//!   - backward, children first: `δRᵢ = Sᵢᵀ δfᵢ + kᵢ δqᵢ + dᵢ δq̇ᵢ` (the joint
//!     spring-dampers on the coordinate, `τ = −k (q − q₀) − d q̇`; a `JointForce` input does not
//!     depend on the state) and the parent gets `Xᵢᵀ (δfᵢ − Sᵢ δRᵢ + δqᵢ Sᵢ ×f fᵢ)` — the
//!     derivative of `Xᵢᵀ` applied to the passed force `fᵢ − Sᵢ Rᵢ`, whose `Sᵢ Rᵢ` part drops
//!     out because `Sᵢ꜀ ×f Sᵢ = 0` for these kinds (the columns are `(a, 0)` and `(0, a)` of one
//!     axis `a`).
//!
//! The tangent of a column is zero outside the subtree of its joint in the forward pass and
//! outside the subtree and its ancestors in the backward pass, so a column costs those
//! bodies only. Exact up to rounding (`tests` against central differences of the residual).
//!
//! Contacts: the pairs of the contact set between the tree and fixed shapes, or between two
//! of its own bodies, add the derivatives of their wrenches to `δfᵢ` (`− δf_ext`), each by a
//! pair-local quotient along the column's tangent: the pair's bodies the column moves placed
//! at `x ± inc·(δθ, δx)` (the placement tangent, propagated as `δv` is without the velocity
//! terms) with velocities `v ± inc·δv`, the pair's narrow phase (position columns) and force
//! law evaluated again — the increment `inc` of the column's unknown with the caps of
//! `dae/increment_caps.rs`, central where `h·y'` = 0, as the free bodies' pair-local quotients
//! of `dae/jacobian.rs`. A pair apart within the set's hysteresis adds nothing.
//!
//! A tree qualifies when nothing else acts on its bodies: no force element but joint
//! spring-dampers on its joints, no point gravity, no input but joint forces, no prescribed
//! motion and no loop (each would add terms this pass does not have); and, per Jacobian, no
//! pair of the contact set ties it to another moving tree, and none of its pairs' narrow
//! phases has stopped at its iteration limit (`MultibodyDae::jacobian_structure`): such a tree
//! keeps the solver's quotients. Allocation-free after warm-up.

use super::jacobian::{bias_force_derivative, central_back, own_body};
use super::MultibodyDae;
use crate::contact::{ContactError, ContactPlan, ContactState, Mode};
use crate::dynamics::plan::JointPlan;
use crate::dynamics::BodyId;
use crate::dynamics::{forces, kinematics, rnea, InputTarget, Plan, Workspace};
use crate::scene::ValidForce;
use crate::solver::{capped_increment, JacobianArgs, JacobianSink, ResidualError};
use crate::spatial::{axis_angle, Force, Motion, Transform};
use nalgebra::Vector3;

/// The hinge trees of a plan and the scratch of their tangent passes.
#[derive(Clone, Debug, Default)]
pub(super) struct HingeTrees {
    /// Per joint tree: whether it is a hinge tree (see the module header).
    pub is_hinge: Vec<bool>,
    /// Tree of each body.
    tree_of: Vec<usize>,
    /// Bodies of each hinge tree, parents first (empty for the other trees).
    bodies: Vec<Vec<usize>>,
    /// Per body: whether it belongs to a hinge tree (the `live` flags of the base pass).
    live: Vec<bool>,
    /// Per velocity index: the summed stiffness and damping of the joint spring-dampers on
    /// that coordinate ([N/m or N·m/rad], [N·s/m or N·m·s/rad]).
    stiffness: Vec<f64>,
    damping: Vec<f64>,
    /// Per velocity index: the derivatives `(∂/∂q, ∂/∂q̇)` of the joint limits' rows at the
    /// Jacobian's point (`LimitState::row_derivatives`); empty without limits.
    pub limit_kd: Vec<(f64, f64)>,
    /// Per body: whether the current column's tangent reaches it in the forward pass, then
    /// in the backward pass whether it carries a force tangent.
    reached: Vec<bool>,
    /// Tangents per body: velocity, acceleration, force (resolved in the body frame).
    dvel: Vec<Motion>,
    dacc: Vec<Motion>,
    df: Vec<Force>,
    /// The base pass's dynamics rows (only the hinge trees' entries are written).
    tau: Vec<f64>,
    /// Per hinge tree: its velocity rows as runs of consecutive indices `(first, length)`
    /// (a chain's are one run), so that a column is written a run at a time.
    runs: Vec<Vec<(usize, usize)>>,
    /// The velocity rows of the current column (by velocity index).
    column: Vec<f64>,
    /// Per body: the placement tangent of the current column (`(δθ, δx)` resolved in the
    /// body, as a velocity is: `δR = R [δθ]×`, `δp = R δx`).
    dpose: Vec<Motion>,
    /// The increment caps of the hinge trees' positions in contact (`caps_of`), per unknown.
    caps: Vec<f64>,
    /// Per pair of the contact set: its narrow phase at the Jacobian's point, if it touches
    /// a hinge tree with exact columns and its shapes overlap.
    geo: Vec<Option<crate::contact::PairGeometry>>,
}

impl HingeTrees {
    /// The hinge trees of `plan`, whose bodies lie in the trees `of_body` (the trees that
    /// are one free body are not hinge trees: they have a path of their own).
    pub(super) fn new(plan: &Plan, of_body: &[usize], n_trees: usize) -> HingeTrees {
        let nb = plan.bodies.len();
        let mut ok = vec![plan.point_gravity.is_none(); n_trees];
        let mut disqualify = |b: Option<crate::dynamics::BodyId>| {
            if let Some(b) = b {
                ok[of_body[b.index()]] = false;
            }
        };
        let (mut stiffness, mut damping) = (vec![0.0; plan.nv], vec![0.0; plan.nv]);
        for f in &plan.scene.forces {
            if let ValidForce::JointSpringDamper {
                joint,
                coordinate,
                stiffness: k,
                damping: d,
                ..
            } = f
            {
                if let Some(tj) = plan.tree_joint_of.get(*joint).copied().flatten() {
                    let j = &plan.joints[tj];
                    let vi = j.v_offset + j.coord.coordinates()[*coordinate].v;
                    stiffness[vi] += k;
                    damping[vi] += d;
                }
                continue;
            }
            match own_body(plan, f) {
                Ok(b) => disqualify(Some(b)),
                Err(bodies) => bodies.into_iter().for_each(&mut disqualify),
            }
        }
        for inp in &plan.inputs {
            match inp.target {
                InputTarget::JointForce { .. } => {}
                InputTarget::JointAcceleration { joint, .. } => {
                    disqualify(Some(plan.joints[joint].body))
                }
                InputTarget::ObjectWrench { object } => disqualify(plan.objects[object].body),
            }
        }
        for cut in &plan.loops.cuts {
            disqualify(cut.body1);
            disqualify(cut.body2);
        }
        for (i, body) in plan.bodies.iter().enumerate() {
            let j = &plan.joints[body.joint];
            let prescribed = plan.prescribed[j.v_offset..j.v_offset + j.coord.nv()]
                .iter()
                .any(Option::is_some);
            if prescribed || !j.coord.is_hinge() {
                ok[of_body[i]] = false;
            }
        }
        let mut bodies = vec![vec![]; n_trees];
        let mut live = vec![false; nb];
        for i in 0..nb {
            if ok[of_body[i]] {
                bodies[of_body[i]].push(i);
                live[i] = true;
            }
        }
        let mut runs = vec![vec![]; n_trees];
        for (t, group) in plan.velocity_groups().into_iter().enumerate() {
            if !ok[t] {
                continue;
            }
            let r: &mut Vec<(usize, usize)> = &mut runs[t];
            for v in group {
                match r.last_mut() {
                    Some((first, len)) if *first + *len == v => *len += 1,
                    _ => r.push((v, 1)),
                }
            }
        }
        HingeTrees {
            is_hinge: ok,
            tree_of: of_body.to_vec(),
            bodies,
            live,
            stiffness,
            damping,
            limit_kd: vec![],
            reached: vec![false; nb],
            dvel: vec![Motion::zero(); nb],
            dacc: vec![Motion::zero(); nb],
            df: vec![Force::default(); nb],
            tau: vec![0.0; plan.nv],
            runs,
            column: vec![0.0; plan.nv],
            dpose: vec![Motion::zero(); nb],
            caps: vec![f64::INFINITY; plan.nq + plan.nv + 2 * plan.loops.m()],
            geo: vec![],
        }
    }
}

impl HingeTrees {
    /// Starts the column of body `k = bodies[t][pos]`: marks k's subtree as reached by the
    /// forward tangent (bodies come parents first, so the subtree follows k) and clears the
    /// force tangents of the other bodies of the tree.
    fn mark_subtree(&mut self, plan: &Plan, t: usize, pos: usize) {
        let k = self.bodies[t][pos];
        for idx in 0..self.bodies[t].len() {
            let i = self.bodies[t][idx];
            let reached = idx >= pos
                && (i == k
                    || plan.bodies[i]
                        .parent
                        .is_some_and(|p| self.reached[p.index()]));
            self.reached[i] = reached;
            if !reached {
                self.df[i] = Force::default();
            }
        }
    }

    /// The backward pass of a column of tree `t` whose forward force tangents are in `df`,
    /// its velocity rows written into `out` at column `col`: `δRᵢ = Sᵢᵀ δfᵢ (+ kₖ δq + dₖ δq̇
    /// at k)`, each body passing `Xᵢᵀ (δfᵢ − Sᵢ δRᵢ (+ δq Sₖ ×f fₖ at k))` to its parent, over
    /// the bodies that carry a tangent (`reached` then marks them). `(dq, dv)`: the column's
    /// change of k's coordinate `c`; `f_k` (`ws.f`) is read only when `dq ≠ 0`.
    #[allow(clippy::too_many_arguments)] // one pass, its column's parameters
    fn backward(
        &mut self,
        plan: &Plan,
        ws: &Workspace,
        (t, k, c): (usize, usize, usize),
        (dq, dv): (f64, f64),
        col: usize,
        out: &mut dyn JacobianSink,
    ) {
        for &(first, len) in &self.runs[t] {
            self.column[first..first + len].fill(0.0);
        }
        for idx in (0..self.bodies[t].len()).rev() {
            let i = self.bodies[t][idx];
            if !self.reached[i] {
                continue;
            }
            let b = &plan.bodies[i];
            let j = &plan.joints[b.joint];
            let (vi, nv) = (j.v_offset, j.coord.nv());
            let df = self.df[i];
            // S is constant for these kinds: `motion` and `project` do not read q.
            let mut dr = [0.0; 2];
            j.coord.project(&ZERO[..j.coord.nq()], &df, &mut dr[..nv]);
            if i == k {
                dr[c] += self.stiffness[vi + c] * dq + self.damping[vi + c] * dv;
                if let Some(&(kq, kv)) = self.limit_kd.get(vi + c) {
                    dr[c] += kq * dq + kv * dv;
                }
            }
            self.column[vi..vi + nv].copy_from_slice(&dr[..nv]);
            if let Some(p) = b.parent {
                let s = j.coord.motion(&ZERO[..j.coord.nq()], &dr[..nv]);
                let mut pass = Force {
                    n: df.n - s.w,
                    f: df.f - s.v,
                };
                if i == k && dq != 0.0 {
                    pass = pass + scaled(&unit(j, c), dq).cross_force(&ws.f[i]);
                }
                let fp = ws.x[i].force_to_parent(&pass);
                self.df[p.index()] = self.df[p.index()] + fp;
                self.reached[p.index()] = true;
            }
        }
        let nq = plan.nq;
        for &(first, len) in &self.runs[t] {
            out.add(nq + first, col, &self.column[first..first + len]);
        }
    }

    /// The hinge tree with exact columns in this Jacobian (`analytic`) that a pair of the
    /// contact set with bodies `bodies` touches, if any (its other shape is fixed or on the
    /// same tree: `MultibodyDae::jacobian_structure` keeps no other pair's tree exact).
    fn pair_tree(
        &self,
        bodies: (Option<BodyId>, Option<BodyId>),
        analytic: &[bool],
    ) -> Option<usize> {
        [bodies.0, bodies.1].into_iter().flatten().find_map(|b| {
            let t = self.tree_of[b.index()];
            (self.is_hinge[t] && analytic.get(t).copied().unwrap_or(false)).then_some(t)
        })
    }

    /// Adds to the force tangents `df` the derivatives of the contact wrenches on tree `t`'s
    /// bodies along the current column (placement tangents `dpose`, velocity tangents `dvel`
    /// of the bodies it reaches), pair by pair: a pair-local quotient — the reached bodies
    /// of the pair placed at `x ± inc·δx`, the pair's narrow phase (position columns only)
    /// and force law evaluated again — with the increment of the column's unknown `col`
    /// (`JacobianArgs::increment`, capped by `caps` for positions; central where `h·y'` = 0),
    /// as the free bodies' pair-local quotients (`dae/jacobian.rs`). The bodies that get a
    /// wrench tangent are marked `reached` for the backward pass. `ws` is left as it was.
    fn contact_tangents(
        &mut self,
        plan: &Plan,
        (cs, cp): (&ContactState, &ContactPlan),
        ws: &mut Workspace,
        args: &JacobianArgs<'_>,
        (t, col): (usize, usize),
    ) -> Result<(), ContactError> {
        let position = col < plan.nq;
        let mut inc = args.increment(col);
        if position {
            inc = capped_increment(inc, self.caps[col], args.y[col]);
        }
        let back = central_back(args, col, inc);
        for k2 in 0..cs.n_in_contact() {
            let Some(geo0) = self.geo.get(k2).copied().flatten() else {
                continue;
            };
            let (ba, bb) = cs.active_bodies(cp, k2);
            let moved = |b: Option<BodyId>| {
                b.is_some_and(|b| self.tree_of[b.index()] == t && self.reached[b.index()])
            };
            if !(moved(ba) || moved(bb)) {
                continue;
            }
            let mut eval = |step: f64| {
                let saved = [ba, bb].map(|b| b.map(|b| (ws.world[b], ws.vel[b])));
                for b in [ba, bb].into_iter().flatten() {
                    if moved(Some(b)) {
                        let (dp, dv) = (self.dpose[b.index()], self.dvel[b.index()]);
                        if position {
                            ws.world[b] = turned(&ws.world[b], &dp, step);
                        }
                        ws.vel[b] = ws.vel[b] + scaled(&dv, step);
                    }
                }
                let wrenches = if position {
                    cs.pair_geometry(plan, cp, ws, k2, args.t)
                        .map(|g| cs.pair_wrenches(cp, ws, k2, &g))
                } else {
                    Ok(cs.pair_wrenches(cp, ws, k2, &geo0))
                };
                for (b, s) in [ba, bb].into_iter().zip(saved) {
                    if let (Some(b), Some(s)) = (b, s) {
                        (ws.world[b], ws.vel[b]) = s;
                    }
                }
                wrenches
            };
            let plus = eval(inc)?;
            let (minus, inv) = match back {
                Some(back) => (eval(back)?, 1.0 / (inc - back)),
                None => (cs.pair_wrenches(cp, ws, k2, &geo0), 1.0 / inc),
            };
            for (b, f, f0) in [(ba, plus.0, minus.0), (bb, plus.1, minus.1)] {
                let (Some(b), Some(f), Some(f0)) = (b, f, f0) else {
                    continue;
                };
                if self.tree_of[b.index()] != t {
                    continue;
                }
                // The residual has `− f_ext`.
                let d = f - f0;
                self.df[b.index()] = self.df[b.index()]
                    - Force {
                        n: d.n * inv,
                        f: d.f * inv,
                    };
                self.reached[b.index()] = true;
            }
        }
        Ok(())
    }

    /// The velocity rows of `∂F/∂y'` of every hinge tree (the row-operated mass matrix), at
    /// the placements in `ws` (from `kinematics::position_velocity`), into `out`: per unit
    /// acceleration `v̇_k` the tangent pass of the module header with `δq = δq̇ = 0` —
    /// `δaᵢ = Xᵢ δa_p (+ Sₖ at k)`, `δfᵢ = Iᵢ δaᵢ`, then [`HingeTrees::backward`] — over k's
    /// subtree and ancestors only, where a Newton–Euler pass with unit accelerations
    /// (`MultibodyDae::yp_jacobian` for the other trees) goes over every body with the
    /// velocity terms. The position rows are the caller's.
    pub(super) fn mass_columns(&mut self, plan: &Plan, ws: &Workspace, out: &mut dyn JacobianSink) {
        for t in 0..self.bodies.len() {
            for pos in 0..self.bodies[t].len() {
                let k = self.bodies[t][pos];
                let jk = &plan.joints[plan.bodies[k].joint];
                for c in 0..jk.coord.nv() {
                    self.mark_subtree(plan, t, pos);
                    for idx in pos..self.bodies[t].len() {
                        let i = self.bodies[t][idx];
                        if !self.reached[i] {
                            continue;
                        }
                        let b = &plan.bodies[i];
                        let dacc = match b.parent {
                            Some(p) if i != k => ws.x[i].motion_to_child(&self.dacc[p.index()]),
                            _ => unit(jk, c),
                        };
                        self.dacc[i] = dacc;
                        self.df[i] = b.inertia.mul_motion(&dacc);
                    }
                    let col = plan.nq + jk.v_offset + c;
                    self.backward(plan, ws, (t, k, c), (0.0, 0.0), col, out);
                }
            }
        }
    }
}

/// Zero positions, for `motion` and `project` of the kinds here (whose `S` does not depend on
/// `q`).
const ZERO: [f64; 2] = [0.0; 2];

/// The column `c` of joint `j`'s motion subspace `S` (constant for the kinds here).
#[inline]
fn unit(j: &JointPlan, c: usize) -> Motion {
    let mut e = [0.0; 2];
    e[c] = 1.0;
    j.coord.motion(&ZERO[..j.coord.nq()], &e[..j.coord.nv()])
}

/// `m·s`.
#[inline]
fn scaled(m: &Motion, s: f64) -> Motion {
    Motion {
        w: m.w * s,
        v: m.v * s,
    }
}

/// `x` (a body's placement in world) moved along the placement tangent `d` (resolved in the
/// body) by `step`: `R exp(step [δθ]×)`, `p + step R δx`.
#[inline]
fn turned(x: &Transform, d: &Motion, step: f64) -> Transform {
    let angle = d.w.norm() * step;
    let rot = if angle == 0.0 {
        x.rot
    } else {
        x.rot * axis_angle(&(d.w / d.w.norm()), angle)
    };
    Transform {
        rot,
        pos: x.pos + x.rot * (d.v * step),
    }
}

/// `a − b`.
#[inline]
fn minus(a: &Motion, b: &Motion) -> Motion {
    Motion {
        w: a.w - b.w,
        v: a.v - b.v,
    }
}

impl MultibodyDae {
    /// Writes the columns of every hinge tree that is analytic in this Jacobian
    /// (`self.analytic`) into `out` (see the module header). `Err` if a force law fails in
    /// the base pass, as the residual would.
    pub(super) fn hinge_jacobian(
        &mut self,
        args: &JacobianArgs<'_>,
        out: &mut dyn JacobianSink,
    ) -> Result<(), ResidualError> {
        let any = self
            .hinge
            .is_hinge
            .iter()
            .zip(&self.analytic)
            .any(|(&h, &a)| h && a);
        if !any {
            return Ok(());
        }
        // Contacts of the exact hinge trees (with fixed shapes or within the tree): their
        // pair-local quotients are capped as the solver's are (`dae/increment_caps.rs`).
        let contacts = match (self.contact.as_ref(), self.contact_plan.as_deref()) {
            (Some(cs), Some(cp)) => (0..cs.n_in_contact()).any(|k2| {
                self.hinge
                    .pair_tree(cs.active_bodies(cp, k2), &self.analytic)
                    .is_some()
            }),
            _ => false,
        };
        if contacts {
            let mut caps = std::mem::take(&mut self.hinge.caps);
            caps.fill(f64::INFINITY);
            self.caps_of(args, &mut caps, true);
            self.hinge.caps = caps;
        }
        let ht = &mut self.hinge;
        let plan = &*self.plan;
        let (nq, nv) = (plan.nq, plan.nv);
        let (q, v) = (&args.y[..nq], &args.y[nq..nq + nv]);
        let vd = &args.yp[nq..nq + nv];
        // The base pass at the Jacobian's point: placements, velocities, the applied joint
        // forces and contact wrenches, and the hinge trees' accelerations and forces.
        let ws = &mut self.ws;
        kinematics::position_velocity(plan, ws, q, v);
        forces::applied_forces(plan, ws, args.t, q, v);
        super::fault_check(ws)?;
        let fatal = |e: crate::contact::ContactError| ResidualError::Fatal(e.to_string());
        let (cs, cp) = (self.contact.as_mut(), self.contact_plan.as_deref());
        let pairs = match (cs, cp) {
            (Some(cs), Some(cp)) if contacts => {
                cs.evaluate(plan, cp, ws, Mode::Continuous, args.t)
                    .map_err(fatal)?;
                ht.geo.clear();
                for k2 in 0..cs.n_in_contact() {
                    let geo = match ht.pair_tree(cs.active_bodies(cp, k2), &self.analytic) {
                        Some(_) => Some(cs.pair_geometry(plan, cp, ws, k2, args.t).map_err(fatal)?),
                        None => None,
                    };
                    // Apart (within the set's hysteresis) the pair exerts no force on a whole
                    // neighbourhood of the state: no derivative.
                    ht.geo.push(geo.filter(|g| g.0.distance <= 0.0));
                }
                Some((&*cs, cp))
            }
            _ => None,
        };
        if let Some(l) = self.limits.as_deref() {
            ht.limit_kd.fill((0.0, 0.0));
            l.state.row_derivatives(&l.plan, q, v, &mut ht.limit_kd);
        }
        rnea::residual_dynamics(
            plan,
            ws,
            (q, vd),
            &plan.gravity,
            &mut ht.tau,
            Some(&ht.live),
        );
        let a_world = Motion {
            w: Vector3::zeros(),
            v: -plan.gravity,
        };
        for t in 0..ht.bodies.len() {
            if !(ht.is_hinge[t] && self.analytic.get(t).copied().unwrap_or(false)) {
                continue;
            }
            for pos in 0..ht.bodies[t].len() {
                let k = ht.bodies[t][pos];
                let jk = &plan.joints[plan.bodies[k].joint];
                for (c, velocity) in (0..jk.coord.nv()).flat_map(|c| [(c, false), (c, true)]) {
                    let s = unit(jk, c);
                    // The column of k's coordinate c: its position (δq = 1, δq̇ = c_j) or its
                    // velocity (δv = 1, δv̇ = c_j).
                    let (dq, dv, dvd) = if velocity {
                        (0.0, 1.0, args.c_j)
                    } else {
                        (1.0, 0.0, 0.0)
                    };
                    ht.mark_subtree(plan, t, pos);
                    for idx in pos..ht.bodies[t].len() {
                        let i = ht.bodies[t][idx];
                        if !ht.reached[i] {
                            continue;
                        }
                        let b = &plan.bodies[i];
                        let x = &ws.x[i];
                        let (mut dvel, mut dacc) = match b.parent {
                            Some(p) if i != k => (
                                x.motion_to_child(&ht.dvel[p.index()]),
                                x.motion_to_child(&ht.dacc[p.index()]),
                            ),
                            _ => (Motion::zero(), Motion::zero()),
                        };
                        if pairs.is_some() {
                            ht.dpose[i] = match b.parent {
                                Some(p) if i != k => x.motion_to_child(&ht.dpose[p.index()]),
                                _ => scaled(&s, dq),
                            };
                        }
                        if i == k {
                            let (vel_p, acc_p) = match b.parent {
                                Some(p) => (ws.vel[p], ws.acc[p]),
                                None => (Motion::zero(), a_world),
                            };
                            let xv = x.motion_to_child(&vel_p);
                            let xa = x.motion_to_child(&acc_p);
                            dvel =
                                minus(&(dvel + scaled(&s, dv)), &scaled(&s.cross_motion(&xv), dq));
                            dacc =
                                minus(&(dacc + scaled(&s, dvd)), &scaled(&s.cross_motion(&xa), dq))
                                    + ws.vel[i].cross_motion(&scaled(&s, dv));
                        }
                        dacc = dacc + dvel.cross_motion(&ws.vj[i]);
                        let inertia = &b.inertia;
                        ht.dvel[i] = dvel;
                        ht.dacc[i] = dacc;
                        ht.df[i] = inertia.mul_motion(&dacc)
                            + bias_force_derivative(inertia, &ws.vel[i], &dvel);
                    }
                    let col = if velocity {
                        nq + jk.v_offset + c
                    } else {
                        jk.q_offset + c
                    };
                    if let Some((cs, cp)) = pairs {
                        ht.contact_tangents(plan, (cs, cp), ws, args, (t, col))
                            .map_err(fatal)?;
                    }
                    ht.backward(plan, ws, (t, k, c), (dq, dv), col, out);
                }
                // The position rows q̇_k − v_k (scalar coordinates: q̇ = v).
                for c in 0..jk.coord.nq() {
                    let row = jk.q_offset + c;
                    out.add(row, row, &[args.c_j]);
                    out.add(row, nq + jk.v_offset + c, &[-1.0]);
                }
            }
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::super::MultibodyDae;
    use crate::solver::{BlockStructure, DaeSystem, JacobianArgs};
    use crate::{ForceElement, Joint, JointKind, Object3D, SceneDesc, SceneOptions, Shape, Solid};
    use nalgebra::Vector3;

    /// A branched hinge tree: `a` on a revolute joint about x at the world, `b` on a
    /// prismatic joint along a skew axis on `a`, and on `b` two children, `c` (revolute about
    /// a skew axis, offset from its body's centre of mass) and `d` (revolute about z); `e` on
    /// a cylindrical joint along a skew axis on `a`; joint spring-dampers on `a`'s and `c`'s
    /// coordinates. Gravity is skew too, so that no term
    /// vanishes by symmetry.
    fn branched() -> SceneDesc {
        let boxed = |l: [f64; 3], m: f64| {
            Solid::new(Shape::Box {
                lengths: Vector3::from(l),
            })
            .mass(m)
        };
        let options = SceneOptions {
            gravity: Vector3::new(0.3, -1.1, -9.81),
            ..SceneOptions::default()
        };
        let skew = Vector3::new(0.0, 1.0, 1.0).normalize();
        let skew2 = Vector3::new(1.0, -2.0, 0.5).normalize();
        let mut s = SceneDesc::new();
        s.add(Object3D::new("world").scene(options))
            .add(Object3D::new("a").solid(boxed([0.05, 0.05, 0.4], 1.2)))
            .add(
                Object3D::new("a_tip")
                    .parent("a")
                    .translation([0.0, 0.02, -0.2]),
            )
            .add(Object3D::new("b").solid(boxed([0.1, 0.2, 0.05], 0.7)))
            .add(
                Object3D::new("b_left")
                    .parent("b")
                    .translation([-0.05, 0.1, 0.0]),
            )
            .add(
                Object3D::new("b_right")
                    .parent("b")
                    .translation([0.05, -0.1, 0.01]),
            )
            .add(Object3D::new("c").solid(boxed([0.03, 0.3, 0.02], 0.4)))
            .add(
                Object3D::new("c_pin")
                    .parent("c")
                    .translation([0.01, 0.15, -0.02]),
            )
            .add(Object3D::new("d").solid(boxed([0.2, 0.02, 0.02], 0.3)))
            .add(
                Object3D::new("a_side")
                    .parent("a")
                    .translation([0.03, -0.01, 0.05]),
            )
            .add(Object3D::new("e").solid(boxed([0.02, 0.06, 0.1], 0.25)))
            .add_joint(Joint::new("ja", "world", "a", JointKind::revolute(1)))
            .add_joint(Joint::new(
                "jb",
                "a_tip",
                "b",
                JointKind::Prismatic {
                    axis: skew,
                    s: 0.0,
                    v: 0.0,
                },
            ))
            .add_joint(Joint::new(
                "jc",
                "b_left",
                "c_pin",
                JointKind::Revolute {
                    axis: skew2,
                    phi: 0.0,
                    w: 0.0,
                },
            ))
            .add_joint(Joint::new("jd", "b_right", "d", JointKind::revolute(3)))
            .add_joint(Joint::new(
                "je",
                "a_side",
                "e",
                JointKind::Cylindrical {
                    axis: Vector3::new(2.0, 1.0, -1.0).normalize(),
                    phi: 0.0,
                    s: 0.0,
                    w: 0.0,
                    v: 0.0,
                },
            ))
            .add_force(ForceElement::JointSpringDamper {
                joint: "ja".into(),
                coordinate: None,
                stiffness: 30.0,
                damping: 0.8,
                offset: 0.1,
            })
            .add_force(ForceElement::JointSpringDamper {
                joint: "jc".into(),
                coordinate: None,
                stiffness: 0.0,
                damping: 2.5,
                offset: 0.0,
            });
        s
    }

    /// Asserts that the exact columns `dae.jacobian` writes at `args` match central
    /// differences of the full residual (increment `eta·max(|y_j|, 1)`) entry by entry to
    /// `tol` of their row's largest entry plus 1e-9; returns the worst relative error.
    /// The Jacobian's point is (`y`, `yp`) with `c_j`, `h` = 1e-4 and every `zero_size`
    /// `zero`.
    fn exact_against_central(
        dae: &mut MultibodyDae,
        (y, yp): (&[f64], &[f64]),
        (c_j, zero): (f64, f64),
        (eta, tol): (f64, f64),
        what: &str,
    ) -> f64 {
        let n = y.len();
        let zero_size = vec![zero; n];
        let args = &JacobianArgs {
            t: 0.0,
            c_j,
            h: 1e-4,
            y,
            yp,
            zero_size: &zero_size,
        };
        let mut a = vec![vec![0.0; n]; n];
        dae.jacobian(args, &mut |i: usize, j: usize, d: f64| a[i][j] += d)
            .unwrap();
        let central: Vec<Vec<f64>> = (0..n)
            .map(|j| {
                super::super::jacobian::tests::central_with(
                    dae,
                    (args.y, args.yp),
                    args.c_j,
                    j,
                    eta,
                )
            })
            .collect();
        let mut worst = 0.0f64;
        for i in 0..n {
            let scale = (0..n).map(|j| central[j][i].abs()).fold(0.0, f64::max);
            for j in 0..n {
                let err = (a[i][j] - central[j][i]).abs();
                worst = worst.max(err / scale);
                assert!(
                    err <= tol * scale + 1e-9,
                    "{what}: entry ({i}, {j}): exact {:e}, central {:e}, row scale {scale:e}",
                    a[i][j],
                    central[j][i]
                );
            }
        }
        worst
    }

    /// The hinge tree's columns against central differences of the full residual at random
    /// states (angles ±1.5 rad, offsets ±0.2 m, rates ±5 per s, `y'` random, so the residual
    /// is far from zero and every term of the row-operated recursion counts), entry by entry.
    ///
    /// Tolerance `1e-6 · max_j |C_ij|` per row `i` plus 1e-9: the tangent pass is exact, so
    /// what differs is the reference's error: truncation `η²/6·|F'''|` (η = 1e-5 on O(1)
    /// coordinates: ~1e-10 relative) and rounding `ε·|F|/η` (|F| ~ 10–100 against entries of
    /// 1–1e3: ≤ 1e-9 relative). A missing or wrong term is O(1) of its row (seen: a sign
    /// error in the prismatic transform's derivative gave 0.3).
    #[test]
    fn hinge_tree_columns_match_central_differences() {
        let model = branched().build().unwrap();
        let mut dae = MultibodyDae::new(model.plan.clone(), model.contact.clone());
        let n = dae.len();
        let mut s = BlockStructure::default();
        assert!(dae.jacobian_structure(&mut s));
        assert_eq!(s.analytic, vec![true], "one tree, a hinge tree");
        let c_j = 2.5e3;
        let mut u = crate::test_rng::uniform(5);
        for trial in 0..4 {
            let plan = dae.plan().clone();
            let mut y = vec![0.0; n];
            for j in &plan.joints {
                for c in j.coord.coordinates() {
                    let range = if c.unit == "m" { 0.4 } else { 3.0 };
                    y[j.q_offset + c.q] = range * u();
                    y[plan.nq + j.v_offset + c.v] = 10.0 * u();
                }
            }
            let yp: Vec<f64> = (0..n).map(|_| 20.0 * u()).collect();
            let what = format!("trial {trial}");
            let worst =
                exact_against_central(&mut dae, (&y, &yp), (c_j, 1e-6), (1e-5, 1e-6), &what);
            eprintln!("trial {trial}: worst relative error {worst:e}");
        }
    }

    /// The same with joint limits in contact (`contact/limits.rs`): [`branched`] with stops on
    /// `ja`'s angle, `jb`'s offset and both of `je`'s coordinates, every one pressed 1e-3 into
    /// its stop at the Jacobian's point and entered at an event with random rates (so each
    /// has its damping `d` and the damping's derivative counts), the rest as in
    /// [`hinge_tree_columns_match_central_differences`]: the stops' rows are exact
    /// (`LimitState::row_derivatives`), the same tolerance holds.
    #[test]
    fn hinge_tree_columns_with_limits_match_central_differences() {
        let mut scene = branched();
        for j in &mut scene.joints {
            let l = |c: Option<&str>, k: f64| {
                let l = crate::JointLimit::range(-0.3, 0.3).stiffness(k).cor(0.6);
                match c {
                    Some(c) => l.on(c),
                    None => l,
                }
            };
            match j.name.as_str() {
                "ja" => j.limits.push(l(None, 400.0)),
                "jb" => j.limits.push(l(None, 2e3)),
                "je" => j.limits.extend([l(Some("phi"), 50.0), l(Some("s"), 900.0)]),
                _ => {}
            }
        }
        let model = scene.build().unwrap();
        let mut dae = MultibodyDae::new(model.plan.clone(), model.contact.clone());
        let n = dae.len();
        let mut s = BlockStructure::default();
        assert!(dae.jacobian_structure(&mut s));
        assert_eq!(s.analytic, vec![true]);
        let plan = dae.plan().clone();
        let mut u = crate::test_rng::uniform(11);
        for trial in 0..4 {
            let mut y = vec![0.0; n];
            for j in &plan.joints {
                for c in j.coord.coordinates() {
                    // Past the upper stop on even trials, below the lower one on odd.
                    let side = if trial % 2 == 0 { 1.0 } else { -1.0 };
                    y[j.q_offset + c.q] = side * (0.3 + 1e-3);
                    y[plan.nq + j.v_offset + c.v] = 2.0 * u();
                }
            }
            dae.handle_event(0.0, &y).unwrap();
            let yp: Vec<f64> = (0..n).map(|_| 20.0 * u()).collect();
            let what = format!("limits, trial {trial}");
            let worst =
                exact_against_central(&mut dae, (&y, &yp), (2.5e3, 1e-6), (1e-5, 1e-6), &what);
            eprintln!("{what}: worst relative error {worst:e}");
        }
    }

    /// The tangent passes allocate nothing once warmed up (the crate's test binary counts
    /// this thread's allocations): 100 Jacobians of [`branched`], and of [`pressed`] (its
    /// contacts' pair-local quotients).
    #[test]
    fn hinge_columns_do_not_allocate() {
        for scene in [branched(), pressed()] {
            hinge_jacobians_do_not_allocate(scene);
        }
    }

    fn hinge_jacobians_do_not_allocate(scene: SceneDesc) {
        let model = scene.build().unwrap();
        let mut dae = MultibodyDae::new(model.plan.clone(), model.contact.clone());
        let n = dae.len();
        let mut y = model.plan.y0();
        y.resize(n, 0.0);
        dae.handle_event(0.0, &y).unwrap();
        let mut s = BlockStructure::default();
        assert!(dae.jacobian_structure(&mut s));
        assert_eq!(s.analytic, vec![true]);
        let yp = dae.consistent_derivative(0.0, &mut y).unwrap();
        let zero_size = vec![1e-6; n];
        let args = JacobianArgs {
            t: 0.0,
            c_j: 100.0,
            h: 1e-3,
            y: &y,
            yp: &yp,
            zero_size: &zero_size,
        };
        let mut entries = 0usize;
        dae.jacobian(&args, &mut |_: usize, _: usize, _: f64| entries += 1)
            .unwrap();
        let before = crate::counting_alloc::allocs();
        for _ in 0..100 {
            dae.jacobian(&args, &mut |_: usize, _: usize, _: f64| entries += 1)
                .unwrap();
        }
        assert_eq!(crate::counting_alloc::allocs() - before, 0);
        assert!(entries >= 101 * 2 * n, "every column written: {entries}");
    }

    /// `yp_jacobian` of the branched hinge tree (its own mass-column pass) against
    /// quotients in `y'` alone with increment 1, at random states (the residual is linear in
    /// `y'`: exact up to rounding; `jacobian::tests::assert_yp_jacobian_is_exact`).
    #[test]
    fn hinge_mass_columns_are_the_derivative_in_y_prime() {
        let model = branched().build().unwrap();
        let mut dae = MultibodyDae::new(model.plan.clone(), model.contact.clone());
        let n = dae.len();
        let mut u = crate::test_rng::uniform(9);
        for trial in 0..3 {
            let y: Vec<f64> = (0..n).map(|_| 2.0 * u()).collect();
            let yp: Vec<f64> = (0..n).map(|_| 20.0 * u()).collect();
            let what = format!("trial {trial}");
            super::super::jacobian::tests::assert_yp_jacobian_is_exact(&mut dae, &y, &yp, &what);
        }
    }

    /// A hinge tree pressed into a fixed steel table (top at z = −0.45 m): `arm` on a revolute
    /// joint about x at the origin, hanging down; `slider` on a prismatic joint along the arm;
    /// at its end a steel ball (Ø 0.1 m) 1e-6 m into the table at the initial angles, and on a
    /// revolute joint about y a steel box (0.1 × 0.04 × 0.04 m) whose lower edge is 1e-6 m
    /// into the table when turned by 0.3 rad (a line contact: the box's patch).
    fn pressed() -> SceneDesc {
        let (r, pen) = (0.05, 1e-6);
        // Its edges are rounded with the default smoothing radius (1 mm): the core's edge,
        // then the radius, below its centre.
        let rs = 1e-3;
        let half = (0.05 - rs) * 0.3f64.sin() + (0.02 - rs) * 0.3f64.cos() + rs;
        let steel = |shape: Shape| Solid::new(shape).material("Steel").collision(true);
        let mut s = SceneDesc::new();
        s.add(Object3D::new("world").scene(SceneOptions::default()))
            .add(
                Object3D::new("table")
                    .parent("world")
                    .translation([0.0, 0.0, -0.5])
                    .solid(steel(Shape::Box {
                        lengths: Vector3::new(2.0, 2.0, 0.1),
                    })),
            )
            .add(
                Object3D::new("arm").solid(
                    Solid::new(Shape::Box {
                        lengths: Vector3::new(0.02, 0.02, 0.2),
                    })
                    .mass(0.5),
                ),
            )
            .add(
                Object3D::new("arm_end")
                    .parent("arm")
                    .translation([0.0, 0.0, -0.1]),
            )
            .add(Object3D::new("slider"))
            .add(
                Object3D::new("ball")
                    .parent("slider")
                    .translation([0.0, 0.0, -0.25 + r - pen - 0.1])
                    .solid(steel(Shape::Sphere { diameter: 2.0 * r })),
            )
            .add(
                // The paddle turned by 0.3 rad about y reaches `half` below its centre.
                Object3D::new("hinge").parent("slider").translation([
                    0.15,
                    0.0,
                    -0.35 - pen + half,
                ]),
            )
            .add(Object3D::new("paddle").solid(steel(Shape::Box {
                lengths: Vector3::new(0.1, 0.04, 0.04),
            })))
            .add_joint(Joint::new("rev", "world", "arm", JointKind::revolute(1)))
            .add_joint(Joint::new(
                "slide",
                "arm_end",
                "slider",
                JointKind::Prismatic {
                    axis: Vector3::z(),
                    s: 0.0,
                    v: 0.0,
                },
            ))
            .add_joint(Joint::new(
                "flap",
                "hinge",
                "paddle",
                JointKind::revolute(2),
            ));
        s
    }

    /// The columns of a hinge tree in contact with a fixed table (a ball and a box corner,
    /// friction) against central differences of the full residual, at random velocities and
    /// the pressed positions, with random `y'`. Tolerance per row `1e-3 · max_j |C_ij|`,
    /// as for the free bodies' pair-local quotients (`jacobian::tests`,
    /// `analytic_columns_match_central_differences`: the one-sided quotient's truncation
    /// `η/(4δ)` at depth δ = 1e-6 m and the box's patch); a missing contact term is O(1) of
    /// its row (the Hertz stiffness dwarfs the rest).
    #[test]
    fn hinge_tree_in_contact_matches_central_differences() {
        let model = pressed().build().unwrap();
        let mut dae = MultibodyDae::new(model.plan.clone(), model.contact.clone());
        let n = dae.len();
        let plan = dae.plan().clone();
        let flap = plan.joints.iter().find(|j| j.name == "flap").unwrap();
        let mut y0 = plan.y0();
        y0.resize(n, 0.0);
        y0[flap.q_offset] = 0.3;
        // The arm turned by 1e-5 rad about x tilts the paddle's edge: its ends 1e-6 ± 1.9e-7 m
        // deep, so the state is not on the symmetric line's kink (where a tilt either way
        // moves the centre of pressure to either end and one-sided slopes differ).
        let rev = plan.joints.iter().find(|j| j.name == "rev").unwrap();
        y0[rev.q_offset] = 1e-5;
        let mut u = crate::test_rng::uniform(13);
        for trial in 0..3 {
            let mut y = y0.clone();
            for j in &plan.joints {
                y[plan.nq + j.v_offset] = 0.5 * u();
            }
            dae.handle_event(0.0, &y).unwrap();
            let pairs = dae.contact().unwrap().n_in_contact();
            assert_eq!(pairs, 2, "the ball and the paddle touch the table");
            let mut st = BlockStructure::default();
            assert!(dae.jacobian_structure(&mut st));
            assert_eq!(
                st.analytic,
                vec![true],
                "in contact with a fixed table: exact"
            );
            let yp: Vec<f64> = (0..n).map(|_| u()).collect();
            let what = format!("trial {trial}");
            let worst =
                exact_against_central(&mut dae, (&y, &yp), (2.5e3, 1e-2), (1e-9, 1e-3), &what);
            eprintln!("trial {trial}: {pairs} pairs, worst relative error {worst:e}");
        }
    }
}
