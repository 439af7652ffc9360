//! Joint loads (results stage's dynamics, on demand): the wrench that obj1 exerts on obj2
//! through a tree joint, and through a rigid link (a `Fix` joint or a parent link) between two
//! parts of a merged body, at one stored state. Nothing here runs in the residual: a result
//! calls it when a load signal is read.
//!
//! # Method
//!
//! At a state `(t, q, v)` with the loops' multipliers `λ` of the run and the contact wrenches it
//! recorded: the applied forces as the residual forms them (`forces::applied_forces`: force
//! elements, user force closures, point gravity, joint springs), the loops' constraint wrenches
//! of `λ` (`LoopWork::apply_forces`) and the contact wrenches as external forces; the
//! accelerations `v̇` from `M v̇ = τ_applied − C` per joint tree
//! (`mass_matrix::accelerations_given_loop_forces`: the loop forces are the given ones, so the
//! loads agree with the cut joints' `<cut>.f` of the same `λ`); then one recursive Newton–Euler
//! pass (`rnea::inverse_dynamics`), whose backward sweep leaves in `ws.f[b]` the spatial force
//! that body `b`'s joint transmits from the parent side to `b` (Featherstone's `f_i`, about
//! `b`'s origin, resolved in `b`'s frame). Uniform gravity is the pass's base acceleration.
//! Since `v̇` solves the model's own equations at the stored state, the loads are as accurate as
//! the state (the solver's accuracy); `Sᵀ f = τ_applied` holds, so a load includes the joint's
//! spring, damper and drive along its free directions.
//!
//! A rigid link between parts of one body is cut by hand: the side of obj2 (the objects still
//! rigidly connected to obj2 when the link is removed; the rigid links form a forest, rigid loops
//! being scene errors) is a free body whose parts move with the body, so the link's wrench on it
//! is `Σ (I_o a + v ×* I_o v) − Σ (external wrenches on its objects) − Σ (wrenches of the joints
//! attached to its objects)`, each part's mass properties its own solid's, its external
//! wrenches those acting on its own objects (force elements by object through
//! `forces::element_wrenches`, contacts by shape, point gravity as the body's field at its centre
//! of mass, `a` per unit mass, applied at the part's centre of mass, as the model applies it).
//!
//! # Convention
//!
//! [`LinkWrench`]: the force \[N\] that obj1 exerts on obj2 and the torque [N·m] about obj2's
//! origin, both resolved in world, with obj1's orientation to resolve them in obj1's frame (the
//! cut joints' `<cut>.f` convention, `loops::cut_wrench`).

use super::forces::{add_world_wrench, element_wrenches, point_gravity_at, UserFault};
use super::ids::{JointId, ObjectId};
use super::kinematics::object_in_world;
use super::loops::{cut_wrench_world, LoopWork};
use super::mass_matrix::accelerations_given_loop_forces;
use super::{Plan, Workspace};
use crate::spatial::{Force, Inertia, Motion, Transform};
use nalgebra::{Matrix3, Vector3};

/// A contact wrench on one object, all resolved in world: `force` \[N\] acting at `point` \[m\]
/// and a pure `torque` [N·m].
#[derive(Clone, Copy, Debug)]
pub(crate) struct ObjectWrench {
    /// The object it acts on.
    pub object: ObjectId,
    /// Point of application, world \[m\].
    pub point: Vector3<f64>,
    /// Force, world \[N\].
    pub force: Vector3<f64>,
    /// Pure torque, world [N·m].
    pub torque: Vector3<f64>,
}

/// Why the loads at a state could not be computed.
#[derive(Clone, Debug, PartialEq)]
pub(crate) enum LoadError {
    /// The mass matrix is singular at the state: no accelerations.
    Singular,
    /// A user force law failed at the state.
    User(UserFault),
}

/// The wrench obj1 exerts on obj2 through a joint or rigid link: `force` \[N\] and `torque`
/// [N·m] about obj2's origin, both resolved in world; `obj1_rot` and `obj2_rot` turn obj1's and
/// obj2's frames into world.
#[derive(Clone, Copy, Debug)]
pub(crate) struct LinkWrench {
    /// Force on obj2, resolved in world \[N\].
    pub force: Vector3<f64>,
    /// Torque on obj2 about obj2's origin, resolved in world [N·m].
    pub torque: Vector3<f64>,
    /// obj1's orientation in world (columns = obj1's axes).
    pub obj1_rot: Matrix3<f64>,
    /// obj2's orientation in world (columns = obj2's axes).
    pub obj2_rot: Matrix3<f64>,
}

/// A rigid link between two objects of one body (or of the world's cluster).
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) enum RigidLink {
    /// A `Fix` joint of the tree's merging (index in `ValidScene::joints`).
    Fix(usize),
    /// The parent link of this object to its parent.
    Parent(usize),
}

/// Runs the load pass at `(t, q, v)` with multipliers `lambda` (`Plan::loops.m()` of them),
/// the contact wrenches `contacts` and the generalised forces `joint_forces` (velocity index,
/// value: the joint limits' stops, `contact/limits.rs`): afterwards `ws` holds positions, velocities, accelerations
/// (`ws.acc`, gravity's base acceleration included) and joint forces (`ws.f`).
pub(crate) fn load_pass(
    plan: &Plan,
    ws: &mut Workspace,
    (t, q, v): (f64, &[f64], &[f64]),
    lambda: &[f64],
    contacts: &[ObjectWrench],
    joint_forces: &[(usize, f64)],
) -> Result<(), LoadError> {
    let mut lw = LoopWork::new(plan);
    ws.fault = None;
    let vd = accelerations_given_loop_forces(plan, ws, t, q, v, &mut |plan, ws| {
        if plan.loops.m() > 0 {
            lw.evaluate(plan, ws);
            lw.apply_forces(plan, ws, lambda);
        }
        for c in contacts {
            let body = plan.objects[c.object].body;
            add_world_wrench(ws, body, &c.point, &c.force, &c.torque);
        }
        for &(k, f) in joint_forces {
            if let Some(tau) = ws.tau_applied.get_mut(k) {
                *tau += f;
            }
        }
    });
    if let Some(fault) = ws.fault.take() {
        return Err(LoadError::User(fault));
    }
    let vd = vd.ok_or(LoadError::Singular)?;
    if vd.iter().any(|x| !x.is_finite()) {
        return Err(LoadError::Singular);
    }
    let mut tau = vec![0.0; plan.nv];
    super::rnea::inverse_dynamics(plan, ws, q, &vd, &plan.gravity, &mut tau);
    Ok(())
}

/// The moment about `to` of a wrench with moment `n` about `from` and force `f` (all world).
#[inline]
fn moment_about(
    n: &Vector3<f64>,
    f: &Vector3<f64>,
    from: &Vector3<f64>,
    to: &Vector3<f64>,
) -> Vector3<f64> {
    n + (from - to).cross(f)
}

/// Tree joint `j`'s wrench on obj2 after [`load_pass`].
pub(crate) fn tree_joint_wrench(plan: &Plan, ws: &Workspace, j: JointId) -> LinkWrench {
    let jp = &plan.joints[j];
    let sj = &plan.scene.joints[jp.scene_joint];
    let b = jp.body;
    let xb = &ws.world[b];
    // On the body (the child side), about its origin, resolved in world.
    let f = xb.rot * ws.f[b].f;
    let n = xb.rot * ws.f[b].n;
    let x1 = object_in_world(plan, ws, ObjectId(sj.obj1));
    let x2 = object_in_world(plan, ws, ObjectId(sj.obj2));
    let n2 = moment_about(&n, &f, &xb.pos, &x2.pos);
    // A flipped joint's child side is obj1: obj2 feels the opposite.
    let (force, torque) = if jp.flipped { (-f, -n2) } else { (f, n2) };
    LinkWrench {
        force,
        torque,
        obj1_rot: x1.rot,
        obj2_rot: x2.rot,
    }
}

/// The two objects of a rigid link, obj1 (the parent side) first.
pub(crate) fn link_ends(plan: &Plan, link: RigidLink) -> Option<(usize, usize)> {
    let scene = &plan.scene;
    match link {
        RigidLink::Fix(sj) => {
            let j = scene.joints.get(sj)?;
            (j.kind.is_rigid()).then_some((j.obj1, j.obj2))
        }
        RigidLink::Parent(o) => Some((scene.objects.get(o)?.parent?, o)),
    }
}

/// The objects on obj2's side of `link` (a flag per object): those rigidly connected to obj2
/// without the link. `None` if obj1 is among them (a rigid loop, which validation rejects).
fn obj2_side(plan: &Plan, link: RigidLink) -> Option<Vec<bool>> {
    let scene = &plan.scene;
    let n = scene.objects.len();
    let (o1, o2) = link_ends(plan, link)?;
    let cut_joint = |sj: usize| plan.loops.cuts.iter().any(|c| c.scene_joint == sj);
    let mut adj: Vec<Vec<(usize, RigidLink)>> = vec![vec![]; n];
    for (i, o) in scene.objects.iter().enumerate() {
        if let Some(p) = o.parent {
            adj[p].push((i, RigidLink::Parent(i)));
            adj[i].push((p, RigidLink::Parent(i)));
        }
    }
    for (sj, j) in scene.joints.iter().enumerate() {
        if j.kind.is_rigid() && !cut_joint(sj) {
            adj[j.obj1].push((j.obj2, RigidLink::Fix(sj)));
            adj[j.obj2].push((j.obj1, RigidLink::Fix(sj)));
        }
    }
    let mut side = vec![false; n];
    side[o2] = true;
    let mut stack = vec![o2];
    while let Some(a) = stack.pop() {
        for &(b, via) in &adj[a] {
            if via != link && !side[b] {
                side[b] = true;
                stack.push(b);
            }
        }
    }
    (!side[o1]).then_some(side)
}

/// The wrench of rigid link `link` on obj2's side after [`load_pass`] at the same state
/// (`(t, q, v)`, `lambda`, `contacts`: the pass's); `None` if `link` is no rigid link.
pub(crate) fn rigid_link_wrench(
    plan: &Plan,
    ws: &Workspace,
    link: RigidLink,
    (t, q, v): (f64, &[f64], &[f64]),
    lambda: &[f64],
    contacts: &[ObjectWrench],
) -> Result<Option<LinkWrench>, LoadError> {
    let (Some((o1, o2)), Some(side)) = (link_ends(plan, link), obj2_side(plan, link)) else {
        return Ok(None);
    };
    let scene = &plan.scene;
    let x1 = object_in_world(plan, ws, ObjectId(o1));
    let x2 = object_in_world(plan, ws, ObjectId(o2));
    let p2 = x2.pos;
    let (mut f, mut n) = (Vector3::zeros(), Vector3::zeros());
    // What the link must supply, accumulated as (force, moment about p2), both world.
    let mut add = |ff: &Vector3<f64>, nn: &Vector3<f64>, at: &Vector3<f64>, sign: f64| {
        f += sign * ff;
        n += sign * moment_about(nn, ff, at, &p2);
    };
    let a_world = Motion {
        w: Vector3::zeros(),
        v: -plan.gravity,
    };
    // The parts' rates of momentum (gravity as the base acceleration: `I (a − g)`).
    for (o, obj) in scene.objects.iter().enumerate() {
        let (true, Some(s)) = (side[o], &obj.solid) else {
            continue;
        };
        let op = &plan.objects[ObjectId(o)];
        let part = Inertia {
            mass: s.mass.mass,
            com: s.mass.com,
            inertia_com: s.mass.inertia,
        };
        let inertia = Inertia::zero().add_transformed(&part, &op.in_body);
        let (a, vel, xb) = match op.body {
            Some(b) => (ws.acc[b], ws.vel[b], ws.world[b]),
            None => (a_world, Motion::zero(), Transform::default()),
        };
        let fb: Force = inertia.mul_motion(&a) + inertia.bias_force(&vel);
        add(&(xb.rot * fb.f), &(xb.rot * fb.n), &xb.pos, 1.0);
    }
    // External wrenches on the side's objects: force elements, point gravity, contacts.
    let mut scratch = ws.clone();
    scratch.fault = None;
    for e in 0..scene.forces.len() {
        element_wrenches(plan, &mut scratch, t, q, v, e, &mut |_, o, at, ff, nn| {
            if side[o.index()] {
                add(ff, nn, at, -1.0);
            }
        });
    }
    if let Some(fault) = scratch.fault.take() {
        return Err(LoadError::User(fault));
    }
    if let Some((mu, centre)) = plan.point_gravity {
        for (o, obj) in scene.objects.iter().enumerate() {
            let (true, Some(s), Some(b)) = (side[o], &obj.solid, plan.objects[ObjectId(o)].body)
            else {
                continue;
            };
            if plan.bodies[b].inertia.mass == 0.0 {
                continue;
            }
            let (g, _) = point_gravity_at(&super::forces::body_com(plan, ws, b), mu, &centre);
            let xo = object_in_world(plan, ws, ObjectId(o));
            let c = xo.pos + xo.rot * s.mass.com;
            add(&(g * s.mass.mass), &Vector3::zeros(), &c, -1.0);
        }
    }
    for c in contacts.iter().filter(|c| side[c.object.index()]) {
        add(&c.force, &c.torque, &c.point, -1.0);
    }
    // Joints attached to the side's objects: tree joints and the loops' cut joints.
    for j in 0..plan.joints.len() {
        let sj = &scene.joints[plan.joints[JointId(j)].scene_joint];
        let (on2, on1) = (side[sj.obj2], side[sj.obj1]);
        if on2 || on1 {
            let w = tree_joint_wrench(plan, ws, JointId(j));
            let at = object_in_world(plan, ws, ObjectId(sj.obj2)).pos;
            let sign = if on2 { -1.0 } else { 1.0 };
            add(&w.force, &w.torque, &at, sign);
        }
    }
    for (c, cut) in plan.loops.cuts.iter().enumerate() {
        let sj = &scene.joints[cut.scene_joint];
        let (on2, on1) = (side[sj.obj2], side[sj.obj1]);
        if on2 || on1 {
            let (ff, nn, _, x2) = cut_wrench_world(plan, ws, c, lambda);
            let sign = if on2 { -1.0 } else { 1.0 };
            add(&ff, &nn, &x2.pos, sign);
        }
    }
    Ok(Some(LinkWrench {
        force: f,
        torque: n,
        obj1_rot: x1.rot,
        obj2_rot: x2.rot,
    }))
}
