//! Closed kinematic loops (plan, residual and restart stages): the cut joints that
//! `scene/topology.rs` keeps out of the spanning tree become algebraic constraints on the tree's
//! coordinates. This module holds their plan ([`LoopPlan`], immutable once the model is built),
//! the per-evaluation scratch ([`LoopWork`], no allocation on the residual's path), and the
//! restart-time algorithms (assembly of consistent positions and velocities, consistent
//! accelerations and multipliers). It reads the plan and the kinematics workspace and writes
//! external wrenches (`Workspace::f_ext`); it touches nothing else.
//!
//! # Constraints
//!
//! Let obj1's frame of a cut joint be `(R1, P1)` and obj2's `(R2, P2)` in world, `R = R1ᵀ R2`
//! and `p = R1ᵀ (P2 − P1)` (obj2 relative to obj1, resolved in obj1). Each locked direction of
//! the joint is one scalar row [`Row`]:
//!
//! * `Translation { e }`: `g = e·p` (e unit, in obj1) \[m\];
//! * `Align { u, a }`: `g = u·(R a)`: obj2's axis `a` stays perpendicular to obj1's `u` \[1\];
//! * `Rotation { k }`: `g = ½ vee(R − Rᵀ)_k` (a full rotation lock, near identity) \[1\].
//!
//! A cut Revolute (axis `a`) is three translations and `Align {u, a}`, `Align {w, a}` with
//! `u, w ⊥ a`: unlike `½ vee(R − Rᵀ)` these two rows keep full rank at every angle of the
//! joint, which a crank's cut joint sweeps through. A Prismatic (axis `a`) is two
//! translations ⊥ `a` and three rotations; a Fix six rows; a FreeMotion none; a Spherical the
//! three translations; a Universal (axes `a1` in obj1, `a2` in obj2) three translations and
//! `Align {a1, a2}`; a Cylindrical (axis `a`) two translations ⊥ `a` and the two alignments of
//! `a`; a Planar (normal `n`) the translation along `n` and the two alignments of `n`. These
//! locked directions come from each kind's file in `joints/` ([`rows_of`]); the
//! motion of the tree's coordinates comes from the kinds themselves (`JointCoord::motion`).
//!
//! Every row's time derivative is *exactly* `ġ = A·(ω2 − ω1) + B·(v2(P2) − v1(P2))`, with
//! `A`, `B` world vectors of the row at the current positions (`Translation`: `A = 0`,
//! `B = R1 e`; `Align`: `A = R1 ((R a) × u)`, `B = 0`; `Rotation`: `A = R1 ½(tr R e_k − Rᵀ e_k)`,
//! `B = 0`), `ω` the bodies' angular velocities and `v1(P2)`, `v2(P2)` the velocities of both
//! bodies' material points at obj2's origin. So `G(q) v = ġ` holds to round-off, which the
//! stabilised formulation below needs, and the multiplier `λ` of a row is a force `λ B` on obj2
//! at `P2` (−`λ B` on obj1 at the same point) and a torque `λ A` (−`λ A` on obj1): the
//! constraint wrench enters the residual as external forces before inverse dynamics, so
//! `Gᵀ λ` is never formed. `G`'s columns, where needed (restarts), come from the tree: a
//! coordinate of an ancestor joint of body `b` moves `b` with the world twist of its motion
//! subspace column; coordinates shared by both ends' paths cancel.
//!
//! # Formulation: stabilised index 2 (Gear–Gupta–Leimkuhler)
//!
//! The unknowns are `y = [q; v; λ; μ]` with one `λ` and one `μ` per kept row:
//!
//! ```text
//! q̇ − q̇(q, v + Gᵀ μ) = 0        (the kinematic rows at the stabilised velocity)
//! M v̇ + C − τ − Gᵀ λ = 0
//! g(q) = 0
//! G(q) v = 0
//! ```
//!
//! `μ` is zero on the exact solution (`d/dt g = G (v + Gᵀ μ) = G Gᵀ μ` with `G v = 0`, and
//! `G Gᵀ` is regular once redundant rows are dropped) and keeps the positions on `g = 0`; `λ`
//! and `μ` are algebraic and left out of IDA's error test (`IdaOptions::differential` +
//! `suppress_algebraic_error`), as SUNDIALS' `idaSlCrank_dns` example does. Stabilising with
//! `Gᵀ μ` in velocity space (`q̇(q, ·)` maps velocities to position derivatives) instead of
//! `Bᵀ μ` with `B = ∂g/∂q` works for quaternion coordinates too and reuses the kinematic residual
//! unchanged. Why not index 1 with projection: the index-1 form (`G v̇ = −Ġ v` as the algebraic
//! equation) leaves `g` and `G v` to drift with the integration error and needs a projection
//! step after every accepted step, which IDA's one-step driver offers no hook for; the GGL form
//! holds both to the Newton tolerance at every step at the price of `2 m` extra unknowns.
//! Measured on the driven four-bar (`tests/loops.rs`): over 100 s (100 turns) at rtol = atol =
//! 1e-8 the tips' gap stays ≤ 1.5e-10 m and their relative velocity ≤ 1.9e-9 m/s with no
//! growth (mean of the last 25 s 1.5× the first's); one turn costs 350 steps at rtol 1e-8 and
//! 700 at 1e-10 (BENCHMARKS.md). No index-1 variant was built to compare against: the
//! decision rests on the drift argument above, and the measured residuals leave nothing for a
//! projection to gain.
//!
//! Three IDA settings make the index-2 form work (`simulation.rs`), each found on these
//! examples: the multipliers get an absolute tolerance of their own in the Newton test
//! (with the states' 1e-12 their round-off, which grows like the iteration matrix's condition
//! ∝ 1/h², never passes it), a stricter Newton coefficient (fewer error-test failures from
//! inexact `λ`), and a first step of 1e-6 of the run (IDA's estimate from `y'` can be 1e-17 s
//! for a mechanism starting at rest with large accelerations, where Newton cannot converge).
//!
//! # Assembly and redundant rows
//!
//! At build time ([`assemble_initial`]) the rows are ranked by pivoted Gram–Schmidt on `G` at a
//! generic position next to `q0` (so a start at a dead centre is not mistaken for redundancy):
//! rows that add less than [`RANK_TOLERANCE`] of the largest row's norm are redundant (a planar
//! four-bar of spatial revolutes has 5 rows of rank 2) and dropped, so `G` has full row rank and
//! the iteration matrix is regular; the dropped rows are named in the model's loop report and
//! must still vanish at the assembled state, else the loop cannot close. The dependent
//! coordinates are chosen by pivoted Gram–Schmidt on `G`'s columns (see [`choose_dependent`]);
//! Levenberg–Marquardt steps (Newton steps once close) move them until `g = 0`; a loop that
//! does not close to [`CLOSE_TOLERANCE`] is [`SceneError::ImpossibleLoop`]. Then `G v = 0` is solved for the
//! dependent velocities and the KKT system `[M −Gᵀ; G 0] [v̇; λ] = [τ − C; −Ġ v]` for the
//! accelerations and multipliers. Restarts (events, input changes) repeat the projection at the
//! current state with the rows kept at build time.

use super::ids::BodyId;
use super::kinematics::{position_derivative, position_velocity};
use super::{Plan, Workspace};
use crate::joints::rows::Row;
use crate::scene::{LoopReach, SceneError, ValidJointKind, ValidScene};
use crate::spatial::Transform;
use nalgebra::{DMatrix, DVector, Matrix3, Vector3};

/// Relative size below which a row (or column) of `G` counts as dependent on the rows (columns)
/// chosen before it, in the pivoted Gram–Schmidt of [`rank_rows`] and [`choose_dependent`]:
/// exact redundancy leaves round-off (~1e-16 of the row norm); a genuine constraint near a
/// singular configuration is larger than 1e-8 of the others except within ~1e-8 rad of it.
pub(crate) const RANK_TOLERANCE: f64 = 1e-8;

/// Largest constraint residual (\[m\] for translations, \[1\] for rotations) an assembled loop may
/// keep: Newton's method reaches round-off (~1e-15 for metre-sized links); 1e-9 leaves room for
/// links of kilometres and is far below any mis-fit a user would make.
pub(crate) const CLOSE_TOLERANCE: f64 = 1e-9;

/// Largest number of Newton iterations of an assembly.
const MAX_NEWTON: usize = 60;

/// A cut joint: both ends (body and placement in it) and its rows.
#[derive(Clone, Debug)]
pub(crate) struct CutPlan {
    /// The joint's name.
    pub name: String,
    /// Index in `ValidScene::joints`.
    pub scene_joint: usize,
    /// Body of obj1 (`None` = fixed to the world).
    pub body1: Option<BodyId>,
    /// obj1's frame placed in `body1`'s frame (or in world) \[m\].
    pub in_body1: Transform,
    /// Body of obj2.
    pub body2: Option<BodyId>,
    /// obj2's frame placed in `body2`'s frame (or in world) \[m\].
    pub in_body2: Transform,
    /// Every row the joint kind locks.
    pub rows: Vec<Row>,
    /// The joints of its loop (names), the cut joint first.
    pub loop_joints: Vec<String>,
    /// Why the loop can never close, when its link lengths show it ([`loop_reach`]).
    pub reach: Option<LoopReach>,
}

/// The loops of a plan: cut joints and the rows kept after redundancy removal.
#[derive(Clone, Debug, Default)]
pub(crate) struct LoopPlan {
    /// Cut joints in the order the tree search met them.
    pub cuts: Vec<CutPlan>,
    /// Kept rows as (cut, row within the cut), in order: the layout of `λ` and `μ`.
    pub kept: Vec<(usize, usize)>,
    /// Rows dropped as redundant, `"<cut joint>.<row>"` (e.g. `"loop.rot_x"`).
    pub dropped: Vec<String>,
    /// Velocity coordinates treated as independent at the initial assembly.
    pub independent: Vec<usize>,
}

impl LoopPlan {
    /// Number of kept rows `m` (the lengths of `λ` and `μ`).
    pub(crate) fn m(&self) -> usize {
        self.kept.len()
    }
    /// True without cut joints.
    pub(crate) fn is_empty(&self) -> bool {
        self.cuts.is_empty()
    }
}

/// The rows a joint kind locks when it is cut (each kind says which, in `joints/`).
pub(crate) fn rows_of(kind: &ValidJointKind) -> Vec<Row> {
    kind.locked_rows()
}

/// The cut joints of a validated scene, placed in their bodies: `in_ref` is each object's
/// placement in its cluster's reference frame and `cluster_body` the body of each cluster
/// (both from the plan's layout).
pub(crate) fn cut_plans(
    scene: &ValidScene,
    in_ref: &[Transform],
    cluster_body: &[Option<BodyId>],
) -> LoopPlan {
    let cluster = &scene.topology.cluster;
    let cuts = scene
        .topology
        .cuts
        .iter()
        .map(|c| {
            let j = &scene.joints[c.joint];
            CutPlan {
                name: j.name.clone(),
                scene_joint: c.joint,
                body1: cluster_body[cluster[j.obj1]],
                in_body1: in_ref[j.obj1],
                body2: cluster_body[cluster[j.obj2]],
                in_body2: in_ref[j.obj2],
                rows: rows_of(&j.kind),
                loop_joints: c
                    .loop_joints
                    .iter()
                    .map(|&k| scene.joints[k].name.clone())
                    .collect(),
                reach: loop_reach(scene, in_ref, &c.loop_joints),
            }
        })
        .collect();
    LoopPlan {
        cuts,
        ..LoopPlan::default()
    }
}

/// The link that is too long for the loop through the joints `loop_joints` (indices into
/// `scene.joints`) ever to close, if there is one. When every joint of the loop keeps the
/// origins of its two frames together (it locks all three translations: revolute, spherical,
/// universal, fixed), the joints' points form a closed polygon whose sides are the rigid
/// links: each side is the distance between the two joint frames' origins on one rigid part
/// (placed by `in_ref` in their cluster's frame, so no motion changes it). A closed polygon
/// needs every side no longer than the others together; a longer one is reported, with both
/// lengths. `None` when the polygon can close, and for loops with a sliding joint (their
/// lengths change) or a part the loop passes more than once (not a simple chain). Necessary,
/// not sufficient: a spatial loop can fail for its axes with every length fitting.
pub(crate) fn loop_reach(
    scene: &ValidScene,
    in_ref: &[Transform],
    loop_joints: &[usize],
) -> Option<LoopReach> {
    let cluster = &scene.topology.cluster;
    // The joints' ends on each rigid part of the loop: (object, position in its cluster).
    let mut ends: Vec<(usize, Vec<usize>)> = vec![];
    for &k in loop_joints {
        let j = scene.joints.get(k)?;
        let translations = rows_of(&j.kind)
            .iter()
            .filter(|r| matches!(r, Row::Translation { .. }))
            .count();
        if translations < 3 {
            return None;
        }
        for o in [j.obj1, j.obj2] {
            let c = *cluster.get(o)?;
            match ends.iter_mut().find(|(cl, _)| *cl == c) {
                Some((_, objs)) => objs.push(o),
                None => ends.push((c, vec![o])),
            }
        }
    }
    let mut links = vec![];
    for (_, objs) in &ends {
        let [a, b] = objs[..] else { return None };
        let length = (in_ref.get(a)?.pos - in_ref.get(b)?.pos).norm();
        links.push((a, b, length));
    }
    let total: f64 = links.iter().map(|l| l.2).sum();
    let &(a, b, length) = links.iter().max_by(|x, y| x.2.total_cmp(&y.2))?;
    let others = total - length;
    let name = |o: usize| scene.objects.get(o).map(|x| x.name.clone());
    (length > others * (1.0 + 1e-9)).then_some(())?;
    Some(LoopReach {
        from: name(a)?,
        to: name(b)?,
        length,
        others,
    })
}

/// Placement in world of a frame `x` of body `b` (`None` = the world) at the workspace state.
#[inline]
fn frame(ws: &Workspace, b: Option<BodyId>, x: &Transform) -> Transform {
    match b {
        Some(b) => ws.world[b].then(x),
        None => *x,
    }
}

/// Value `g` and world vectors `A`, `B` of one row (see the module docs), with obj1's frame
/// `f1` and obj2's `f2` in world.
#[inline]
fn row_eval(row: &Row, f1: &Transform, f2: &Transform) -> (f64, Vector3<f64>, Vector3<f64>) {
    let zero = Vector3::zeros();
    match row {
        Row::Translation { e } => {
            let p = f1.rot.tr_mul(&(f2.pos - f1.pos));
            (e.dot(&p), zero, f1.rot * e)
        }
        Row::Align { u, a } => {
            let ra = f1.rot.tr_mul(&(f2.rot * a)); // obj2's axis resolved in obj1
            (u.dot(&ra), f1.rot * ra.cross(u), zero)
        }
        Row::Rotation { k } => {
            let r: Matrix3<f64> = f1.rot.tr_mul(&f2.rot);
            let g = match k {
                0 => 0.5 * (r[(2, 1)] - r[(1, 2)]),
                1 => 0.5 * (r[(0, 2)] - r[(2, 0)]),
                _ => 0.5 * (r[(1, 0)] - r[(0, 1)]),
            };
            let ek = Vector3::ith(*k, 1.0);
            let a = 0.5 * (r.trace() * ek - r.tr_mul(&ek));
            (g, f1.rot * a, zero)
        }
    }
}

/// Angular velocity [rad/s] and velocity [m/s] of body `b`'s material point at `p` (both
/// resolved in world; zero for the world).
#[inline]
fn body_point_velocity(
    ws: &Workspace,
    b: Option<BodyId>,
    p: &Vector3<f64>,
) -> (Vector3<f64>, Vector3<f64>) {
    let (v, w) = super::kinematics::point_velocity(ws, b, p);
    (w, v)
}

/// Calls `f(k, ω_k, v_k)` for every velocity coordinate `k` of the joints from body `b` up to the
/// world, with `ω_k` [rad/s per unit] the world angular velocity and `v_k` the world velocity of
/// the body's material point at `p` that a unit velocity of `k` causes (the joint's motion
/// subspace column `S(q) e_k`, asked of its kind). `unit` is scratch of at least the largest
/// joint's `nv`, all zeros (left so). No allocation.
#[inline]
fn for_each_column(
    plan: &Plan,
    ws: &Workspace,
    q: &[f64],
    mut b: Option<BodyId>,
    p: &Vector3<f64>,
    unit: &mut [f64],
    mut f: impl FnMut(usize, Vector3<f64>, Vector3<f64>),
) {
    while let Some(bi) = b {
        let body = &plan.bodies[bi];
        let j = &plan.joints[body.joint];
        let x = &ws.world[bi];
        let qj = &q[j.q_offset..j.q_offset + j.coord.nq()];
        for k in 0..j.coord.nv() {
            unit[k] = 1.0;
            let s = j.coord.motion(qj, &unit[..j.coord.nv()]);
            unit[k] = 0.0;
            let w = x.rot * s.w;
            let v = x.rot * s.v + w.cross(&(p - x.pos));
            f(j.v_offset + k, w, v);
        }
        b = body.parent;
    }
}

/// Largest number of velocities of one joint (FreeMotion's six).
const MAX_JOINT_NV: usize = 6;

/// Scratch of the loop rows at one state: allocated once per DAE, so the residual allocates
/// nothing.
#[derive(Clone, Debug)]
pub(crate) struct LoopWork {
    /// `g` of every kept row.
    pub g: Vec<f64>,
    /// `G v` of every kept row.
    pub gv: Vec<f64>,
    /// `A` of every kept row (world, see the module docs).
    a: Vec<Vector3<f64>>,
    /// `B` of every kept row (world).
    b: Vec<Vector3<f64>>,
    /// obj2's origin in world, per cut \[m\].
    p2: Vec<Vector3<f64>>,
    /// `v + Gᵀ μ` (len nv).
    pub w: Vec<f64>,
}

impl LoopWork {
    /// Scratch for `plan`.
    pub(crate) fn new(plan: &Plan) -> Self {
        let m = plan.loops.m();
        LoopWork {
            g: vec![0.0; m],
            gv: vec![0.0; m],
            a: vec![Vector3::zeros(); m],
            b: vec![Vector3::zeros(); m],
            p2: vec![Vector3::zeros(); plan.loops.cuts.len()],
            w: vec![0.0; plan.nv],
        }
    }

    /// Evaluates every kept row at the workspace state (after
    /// [`position_velocity`]): `g`, `G v`, and the row vectors.
    pub(crate) fn evaluate(&mut self, plan: &Plan, ws: &Workspace) {
        let lp = &plan.loops;
        for (c, cut) in lp.cuts.iter().enumerate() {
            let f2 = frame(ws, cut.body2, &cut.in_body2);
            self.p2[c] = f2.pos;
        }
        let mut last = usize::MAX;
        let (mut f1, mut f2) = (Transform::default(), Transform::default());
        let (mut w1, mut v1, mut w2, mut v2) = (
            Vector3::zeros(),
            Vector3::zeros(),
            Vector3::zeros(),
            Vector3::zeros(),
        );
        for (i, &(c, r)) in lp.kept.iter().enumerate() {
            let cut = &lp.cuts[c];
            if c != last {
                f1 = frame(ws, cut.body1, &cut.in_body1);
                f2 = frame(ws, cut.body2, &cut.in_body2);
                (w1, v1) = body_point_velocity(ws, cut.body1, &f2.pos);
                (w2, v2) = body_point_velocity(ws, cut.body2, &f2.pos);
                last = c;
            }
            let (g, a, b) = row_eval(&cut.rows[r], &f1, &f2);
            self.g[i] = g;
            self.a[i] = a;
            self.b[i] = b;
            self.gv[i] = a.dot(&(w2 - w1)) + b.dot(&(v2 - v1));
        }
    }

    /// Sums `Σ x_i (A_i, B_i)` over the kept rows of cut `c` (a torque and a force in world for
    /// multipliers `x`).
    fn cut_sum(&self, lp: &LoopPlan, c: usize, x: &[f64]) -> (Vector3<f64>, Vector3<f64>) {
        let (mut t, mut f) = (Vector3::zeros(), Vector3::zeros());
        for (i, &(ci, _)) in lp.kept.iter().enumerate() {
            if ci == c {
                t += x[i] * self.a[i];
                f += x[i] * self.b[i];
            }
        }
        (t, f)
    }

    /// `self.w = v + Gᵀ μ` (after [`LoopWork::evaluate`]).
    pub(crate) fn stabilised_velocity(
        &mut self,
        plan: &Plan,
        ws: &Workspace,
        q: &[f64],
        v: &[f64],
        mu: &[f64],
    ) {
        self.w.copy_from_slice(v);
        let lp = &plan.loops;
        let mut unit = [0.0; MAX_JOINT_NV];
        for (c, cut) in lp.cuts.iter().enumerate() {
            let (t, f) = self.cut_sum(lp, c, mu);
            let p = self.p2[c];
            let w = &mut self.w;
            for_each_column(plan, ws, q, cut.body2, &p, &mut unit, |k, wk, vk| {
                w[k] += wk.dot(&t) + vk.dot(&f)
            });
            for_each_column(plan, ws, q, cut.body1, &p, &mut unit, |k, wk, vk| {
                w[k] -= wk.dot(&t) + vk.dot(&f)
            });
        }
    }

    /// Adds the constraint wrenches of multipliers `lambda` to `ws.f_ext` (after
    /// [`LoopWork::evaluate`]): on obj2 the force `Σ λ B` at its origin and the torque `Σ λ A`,
    /// the opposite on obj1 at the same point. Inverse dynamics then contains `−Gᵀ λ`.
    pub(crate) fn apply_forces(&self, plan: &Plan, ws: &mut Workspace, lambda: &[f64]) {
        let lp = &plan.loops;
        for (c, cut) in lp.cuts.iter().enumerate() {
            let (t, f) = self.cut_sum(lp, c, lambda);
            let p = self.p2[c];
            super::forces::add_world_wrench(ws, cut.body2, &p, &f, &t);
            super::forces::add_world_wrench(ws, cut.body1, &p, &-f, &-t);
        }
    }
}

/// All rows (kept or not, per `rows`) at the workspace state: values and the dense `G`.
/// Allocates; restarts only.
fn dense_rows(
    plan: &Plan,
    ws: &Workspace,
    q: &[f64],
    rows: &[(usize, usize)],
) -> (DVector<f64>, DMatrix<f64>) {
    let lp = &plan.loops;
    let mut unit = [0.0; MAX_JOINT_NV];
    let mut g = DVector::zeros(rows.len());
    let mut gm = DMatrix::zeros(rows.len(), plan.nv);
    for (i, &(c, r)) in rows.iter().enumerate() {
        let cut = &lp.cuts[c];
        let f1 = frame(ws, cut.body1, &cut.in_body1);
        let f2 = frame(ws, cut.body2, &cut.in_body2);
        let (gi, a, b) = row_eval(&cut.rows[r], &f1, &f2);
        g[i] = gi;
        for_each_column(plan, ws, q, cut.body2, &f2.pos, &mut unit, |k, wk, vk| {
            gm[(i, k)] += a.dot(&wk) + b.dot(&vk)
        });
        for_each_column(plan, ws, q, cut.body1, &f2.pos, &mut unit, |k, wk, vk| {
            gm[(i, k)] -= a.dot(&wk) + b.dot(&vk)
        });
    }
    (g, gm)
}

/// Every row of every cut, as (cut, row).
fn all_rows(lp: &LoopPlan) -> Vec<(usize, usize)> {
    lp.cuts
        .iter()
        .enumerate()
        .flat_map(|(c, cut)| (0..cut.rows.len()).map(move |r| (c, r)))
        .collect()
}

/// Pivoted Gram–Schmidt on the rows of `gm`: the rows that are independent (each adds more than
/// [`RANK_TOLERANCE`] of the largest row norm), largest remaining first, returned in ascending
/// order.
fn rank_rows(gm: &DMatrix<f64>) -> Vec<usize> {
    let mut rest: Vec<DVector<f64>> = (0..gm.nrows()).map(|i| gm.row(i).transpose()).collect();
    let scale = rest.iter().map(|r| r.norm()).fold(0.0, f64::max);
    let mut chosen = vec![];
    loop {
        let best = (0..rest.len())
            .filter(|i| !chosen.contains(i))
            .max_by(|&i, &j| rest[i].norm().total_cmp(&rest[j].norm()));
        let Some(i) = best else { break };
        let n = rest[i].norm();
        if n <= RANK_TOLERANCE * scale || n == 0.0 {
            break;
        }
        let q = &rest[i] / n;
        chosen.push(i);
        for r in rest.iter_mut() {
            let d = q.dot(r);
            *r -= d * &q;
        }
    }
    chosen.sort_unstable();
    chosen
}

/// The dependent velocity coordinates (one per row of `gm`, full row rank): pivoted Gram–Schmidt
/// on the columns. Among the columns whose remaining norm is at least a quarter of the largest,
/// the coordinate of the joint declared last is taken, so joints declared first (the drive, by
/// habit) stay independent when that costs at most a factor 4 in conditioning; prescribed
/// coordinates (acceleration inputs) are taken only when nothing else remains.
pub(crate) fn choose_dependent(plan: &Plan, gm: &DMatrix<f64>) -> Vec<usize> {
    let nv = gm.ncols();
    let mut rest: Vec<DVector<f64>> = (0..nv).map(|k| gm.column(k).into_owned()).collect();
    let scale = rest.iter().map(|r| r.norm()).fold(0.0, f64::max);
    // Declaration rank of each coordinate's joint.
    let mut declared = vec![0usize; nv];
    for j in &plan.joints {
        declared[j.v_offset..j.v_offset + j.coord.nv()].fill(j.scene_joint);
    }
    let mut dep: Vec<usize> = vec![];
    for _ in 0..gm.nrows() {
        let pick = |prescribed_ok: bool| {
            let cand: Vec<usize> = (0..nv)
                .filter(|k| !dep.contains(k))
                .filter(|&k| prescribed_ok || plan.prescribed[k].is_none())
                .filter(|&k| rest[k].norm() > RANK_TOLERANCE * scale)
                .collect();
            let best = cand.iter().map(|&k| rest[k].norm()).fold(0.0, f64::max);
            cand.into_iter()
                .filter(|&k| rest[k].norm() >= 0.25 * best)
                .max_by_key(|&k| (declared[k], k))
        };
        let Some(k) = pick(false).or_else(|| pick(true)) else {
            break;
        };
        let q = &rest[k] / rest[k].norm();
        dep.push(k);
        for r in rest.iter_mut() {
            let d = q.dot(r);
            *r -= d * &q;
        }
    }
    dep.sort_unstable();
    dep
}

/// Moves the positions `q` by the velocity-space increment `dv` (one value per velocity
/// coordinate): `q + q̇(q, dv)`, one explicit step of each kind's own kinematics. Exact for
/// scalar coordinates; for quaternions and the rotated translations of free joints it is off
/// by O(|dv|²), which keeps Newton's method quadratic (the steps vanish at the solution), and
/// the quaternion's norm is restored by the kinematic residual's norm term afterwards.
fn retract(plan: &Plan, q: &mut [f64], dv: &[f64]) {
    let mut qd = vec![0.0; plan.nq];
    position_derivative(plan, q, dv, &mut qd);
    for (x, d) in q.iter_mut().zip(&qd) {
        *x += d;
    }
}

/// Why an assembly failed: the cut joint whose loop does not close and the residual.
#[derive(Clone, Debug, PartialEq)]
pub struct LoopFailure {
    /// The cut joint.
    pub cut: String,
    /// Its loop's joints.
    pub joints: Vec<String>,
    /// Largest remaining residual of its rows (\[m\] or \[1\]).
    pub residual: f64,
    /// Why the loop can never close, when its link lengths show it.
    pub reach: Option<LoopReach>,
}

impl From<LoopFailure> for SceneError {
    fn from(f: LoopFailure) -> Self {
        SceneError::ImpossibleLoop {
            cut: f.cut,
            joints: f.joints,
            residual: f.residual,
            reach: f.reach.map(Box::new),
        }
    }
}

/// The cut with the largest residual among `rows` (values `g`), as a failure.
fn failure(lp: &LoopPlan, rows: &[(usize, usize)], g: &DVector<f64>) -> LoopFailure {
    let (i, r) = g
        .iter()
        .enumerate()
        .max_by(|a, b| a.1.abs().total_cmp(&b.1.abs()))
        .map(|(i, r)| (i, r.abs()))
        .unwrap_or((0, 0.0));
    let cut = &lp.cuts[rows.get(i).map_or(0, |r| r.0)];
    LoopFailure {
        cut: cut.name.clone(),
        joints: cut.loop_joints.clone(),
        residual: r,
        reach: cut.reach.clone(),
    }
}

/// Projects `q`, `v` onto the constraints with the kept rows: Levenberg–Marquardt steps on the
/// dependent coordinates until `g = 0` (plain Newton steps once close; the damping lets a rough
/// guess, where `G` restricted to them is nearly singular, still reach the loop), then
/// `G v = 0` for the dependent velocities. Returns the dependent velocity coordinates.
/// Allocates; initial values and restarts only.
pub(crate) fn project(
    plan: &Plan,
    ws: &mut Workspace,
    q: &mut [f64],
    v: &mut [f64],
) -> Result<Vec<usize>, LoopFailure> {
    let lp = &plan.loops;
    let zero_v = vec![0.0; plan.nv];
    position_velocity(plan, ws, q, &zero_v);
    let (mut g, mut gm) = dense_rows(plan, ws, q, &lp.kept);
    let dep = choose_dependent(plan, &gm);
    let cost = |g: &DVector<f64>| g.norm_squared();
    let mut damping = 1e-6;
    let mut it = 0;
    while !dep.is_empty() && g.amax() > 1e-14 && it < MAX_NEWTON {
        it += 1;
        let gd = gm.select_columns(&dep);
        let jtj = gd.transpose() * &gd;
        let rhs = -(gd.transpose() * &g);
        let mut accepted = false;
        for _ in 0..40 {
            let scale = jtj.diagonal().amax().max(1e-300);
            let mut a = jtj.clone();
            for i in 0..dep.len() {
                a[(i, i)] += damping * scale;
            }
            let Some(step) = a.lu().solve(&rhs) else {
                damping *= 10.0;
                continue;
            };
            let mut dv = vec![0.0; plan.nv];
            for (s, &k) in step.iter().zip(&dep) {
                dv[k] = *s;
            }
            let mut qn = q.to_vec();
            retract(plan, &mut qn, &dv);
            position_velocity(plan, ws, &qn, &zero_v);
            let (gn, gmn) = dense_rows(plan, ws, &qn, &lp.kept);
            if cost(&gn) < cost(&g) {
                q.copy_from_slice(&qn);
                (g, gm) = (gn, gmn);
                damping = (damping * 0.1).max(1e-15);
                accepted = true;
                break;
            }
            damping *= 10.0;
        }
        if !accepted {
            break; // no descent: the loop does not close from here
        }
    }
    // Every row, the dropped redundant ones included, must vanish.
    let all = all_rows(lp);
    position_velocity(plan, ws, q, &zero_v);
    let (g_all, _) = dense_rows(plan, ws, q, &all);
    if g_all.amax() > CLOSE_TOLERANCE {
        return Err(failure(lp, &all, &g_all));
    }
    if dep.is_empty() {
        return Ok(dep); // nothing kept (every row redundant) or nothing movable
    }
    // Dependent velocities from G v = 0.
    let gd = gm.select_columns(&dep);
    let gv = &gm * DVector::from_column_slice(v);
    if let Some(dvd) = gd.lu().solve(&(-gv)) {
        for (s, &k) in dvd.iter().zip(&dep) {
            v[k] += s;
        }
    }
    Ok(dep)
}

/// Build-time assembly: chooses the kept (independent) rows at `q0`, projects `q0` and `v0` onto
/// the constraints and records the independent coordinates. Logs the dropped rows and the
/// independent coordinates (`tracing::info!`).
pub(crate) fn assemble_initial(plan: &mut Plan) -> Result<(), SceneError> {
    if plan.loops.is_empty() {
        return Ok(());
    }
    let mut ws = Workspace::new(plan);
    let all = all_rows(&plan.loops);
    let zero_v = vec![0.0; plan.nv];
    let (mut q, mut v) = (plan.q0.clone(), plan.v0.clone());
    // Redundancy is structural: rank the rows at a generic position near the user's (q0
    // moved by a fixed pseudo-random 0.01 in every velocity direction), so that a start at a
    // singular position (a dead centre) does not pass for a redundant row.
    let dv: Vec<f64> = (0..plan.nv)
        .map(|k| 0.01 * (1.7 * k as f64 + 0.3).sin())
        .collect();
    let mut q_generic = q.clone();
    retract(plan, &mut q_generic, &dv);
    position_velocity(plan, &mut ws, &q_generic, &zero_v);
    let (_, gm) = dense_rows(plan, &ws, &q_generic, &all);
    let keep = rank_rows(&gm);
    plan.loops.kept = keep.iter().map(|&i| all[i]).collect();
    plan.loops.dropped = all
        .iter()
        .enumerate()
        .filter(|(i, _)| !keep.contains(i))
        .map(|(_, &(c, r))| {
            let cut = &plan.loops.cuts[c];
            format!("{}.{}", cut.name, cut.rows[r].label(r))
        })
        .collect();
    let dep = project(plan, &mut ws, &mut q, &mut v)?;
    plan.loops.independent = (0..plan.nv).filter(|k| !dep.contains(k)).collect();
    tracing::info!(
        kept_rows = plan.loops.kept.len(),
        dropped = ?plan.loops.dropped,
        independent = ?independent_names(plan, &plan.loops.independent),
        "kinematic loops assembled"
    );
    plan.q0 = q;
    plan.v0 = v;
    Ok(())
}

/// Names of velocity coordinates: the joint's scalar coordinate (`crank.phi`, `slide.s`), else
/// its velocity signal with an index (`ball.w[1]` for a quaternion kind).
pub(crate) fn independent_names(plan: &Plan, coords: &[usize]) -> Vec<String> {
    coords
        .iter()
        .filter_map(|&k| {
            let j = plan
                .joints
                .iter()
                .find(|j| k >= j.v_offset && k < j.v_offset + j.coord.nv())?;
            let i = k - j.v_offset;
            if let Some(c) = j.coord.coordinates().iter().find(|c| c.v == i) {
                return Some(format!("{}.{}", j.name, c.name));
            }
            let spec = j.coord.signals().iter().find(|s| {
                matches!(s.source, crate::joints::Source::V(off) if i >= off && i < off + s.dim)
            })?;
            let crate::joints::Source::V(off) = spec.source else {
                return None;
            };
            Some(if spec.dim == 1 {
                format!("{}.{}", j.name, spec.name)
            } else {
                format!("{}.{}[{}]", j.name, spec.name, i - off)
            })
        })
        .collect()
}

/// `Ġ v` = `(∂(G v)/∂q) q̇` at `q`, `v` with `v` held: central difference of `G v` along the
/// straight line `q ± h q̇` (the even error terms, the quaternions' norm drift among them,
/// cancel; the remaining error is O(h²) ≈ 1e-10 relative with `h |q̇| = 1e-5`). Only for the
/// consistent accelerations at restarts, which IDA's corrector refines anyway.
pub(crate) fn gdot_v(plan: &Plan, ws: &mut Workspace, q: &[f64], v: &[f64]) -> DVector<f64> {
    let lp = &plan.loops;
    let mut qd = vec![0.0; plan.nq];
    position_derivative(plan, q, v, &mut qd);
    let speed = qd.iter().fold(0.0f64, |m, x| m.max(x.abs()));
    if speed == 0.0 {
        return DVector::zeros(lp.m());
    }
    let h = 1e-5 / speed;
    let gv_at = |ws: &mut Workspace, s: f64| {
        let qs: Vec<f64> = q.iter().zip(&qd).map(|(a, b)| a + s * b).collect();
        position_velocity(plan, ws, &qs, v);
        let (_, gm) = dense_rows(plan, ws, &qs, &lp.kept);
        gm * DVector::from_column_slice(v)
    };
    let plus = gv_at(ws, h);
    let minus = gv_at(ws, -h);
    (plus - minus) / (2.0 * h)
}

/// The dense `G` (kept rows) at `q`. Allocates.
pub(crate) fn constraint_jacobian(plan: &Plan, ws: &mut Workspace, q: &[f64]) -> DMatrix<f64> {
    position_velocity(plan, ws, q, &vec![0.0; plan.nv]);
    dense_rows(plan, ws, q, &plan.loops.kept).1
}

/// Force \[N\] on obj2 and torque [N·m] on obj2 of cut `c` for its multipliers (kept rows of the
/// cut, in order), both resolved in obj1's frame, at the workspace state; the force acts at
/// obj2's origin, obj1 feels the opposite.
pub(crate) fn cut_wrench(
    plan: &Plan,
    ws: &Workspace,
    c: usize,
    lambda: &[f64],
) -> (Vector3<f64>, Vector3<f64>) {
    let (f, t, f1, _) = cut_wrench_world(plan, ws, c, lambda);
    (f1.rot.tr_mul(&f), f1.rot.tr_mul(&t))
}

/// [`cut_wrench`] resolved in world: force \[N\] and torque [N·m] on obj2 (the force acting at
/// obj2's origin), with obj1's and obj2's frames placed in world at the workspace state.
pub(crate) fn cut_wrench_world(
    plan: &Plan,
    ws: &Workspace,
    c: usize,
    lambda: &[f64],
) -> (Vector3<f64>, Vector3<f64>, Transform, Transform) {
    let lp = &plan.loops;
    let cut = &lp.cuts[c];
    let f1 = frame(ws, cut.body1, &cut.in_body1);
    let f2 = frame(ws, cut.body2, &cut.in_body2);
    let (mut f, mut t) = (Vector3::zeros(), Vector3::zeros());
    for (i, &(ci, r)) in lp.kept.iter().enumerate() {
        if ci == c {
            let (_, a, b) = row_eval(&cut.rows[r], &f1, &f2);
            t += lambda[i] * a;
            f += lambda[i] * b;
        }
    }
    (f, t, f1, f2)
}

/// Accelerations `v̇` and multipliers `λ` from the KKT system
/// `[M −Gᵀ; G 0] [v̇; λ] = [τ − C; −Ġ v]` at the workspace's positions `q`, velocities `v`, with
/// the prescribed accelerations already in `vd` (their rows are known: only the free
/// coordinates are unknown, the prescribed ones enter the right-hand sides). `blocks` are the
/// tree blocks of `M` ([`super::mass_matrix::tree_mass_matrices`]), `rhs` = `τ − C` per velocity
/// coordinate. `None` if the system is singular.
pub(crate) fn kkt_accelerations(
    plan: &Plan,
    ws: &mut Workspace,
    q: &[f64],
    v: &[f64],
    blocks: &[(Vec<usize>, DMatrix<f64>)],
    rhs: &[f64],
    vd: &mut [f64],
) -> Option<Vec<f64>> {
    let nv = plan.nv;
    let mut m = DMatrix::zeros(nv, nv);
    for (group, block) in blocks {
        for (c, &j) in group.iter().enumerate() {
            for (r, &i) in group.iter().enumerate() {
                m[(i, j)] = block[(r, c)];
            }
        }
    }
    let gamma = -gdot_v(plan, ws, q, v);
    let gm = constraint_jacobian(plan, ws, q);
    let free: Vec<usize> = (0..nv).filter(|&k| plan.prescribed[k].is_none()).collect();
    let (nf, nm) = (free.len(), plan.loops.m());
    let known = DVector::from_column_slice(vd); // prescribed accelerations, zero elsewhere
    let mk = &m * &known;
    let gk = &gm * &known;
    let mut a = DMatrix::zeros(nf + nm, nf + nm);
    let mut b = DVector::zeros(nf + nm);
    for (r, &i) in free.iter().enumerate() {
        for (c, &j) in free.iter().enumerate() {
            a[(r, c)] = m[(i, j)];
        }
        for l in 0..nm {
            a[(r, nf + l)] = -gm[(l, i)];
            a[(nf + l, r)] = gm[(l, i)];
        }
        b[r] = rhs[i] - mk[i];
    }
    for l in 0..nm {
        b[nf + l] = gamma[l] - gk[l];
    }
    let x = a.lu().solve(&b)?;
    if x.iter().any(|x| !x.is_finite()) {
        return None;
    }
    for (r, &i) in free.iter().enumerate() {
        vd[i] = x[r];
    }
    Some(x.rows(nf, nm).iter().copied().collect())
}
