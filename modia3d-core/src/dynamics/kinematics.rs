//! Forward kinematics: joint positions and velocities → body placements and spatial velocities
//! (parents first), and the kinematic part of the residual `q̇ − q̇(q, v)`.

use super::plan::BodyPlan;
use super::{BodyId, ObjectId, Plan, Workspace};
use crate::spatial::{Motion, Transform};
use nalgebra::Vector3;

/// Computes `ws.x`, `ws.world`, `ws.vj`, `ws.vel` (and `ws.cj` of joints whose motion
/// subspace depends on `q`) from `q`, `v`; each joint's kind gives its transform and motion.
pub(crate) fn position_velocity(plan: &Plan, ws: &mut Workspace, q: &[f64], v: &[f64]) {
    place_bodies(plan, ws, plan.bodies.iter().enumerate(), q, v);
}

/// Places `bodies` (index and plan, parents before children) in the workspace: each body's
/// joint placement and velocity, and its placement and velocity in world from its parent's.
/// One loop for the whole scene ([`position_velocity`]) and for a chain
/// ([`chain_position_velocity`]), instantiated for each.
#[inline(always)]
fn place_bodies<'p>(
    plan: &Plan,
    ws: &mut Workspace,
    bodies: impl Iterator<Item = (usize, &'p BodyPlan)>,
    q: &[f64],
    v: &[f64],
) {
    for (i, b) in bodies {
        let j = &plan.joints[b.joint];
        let qj = &q[j.q_offset..j.q_offset + j.coord.nq()];
        let vj_ = &v[j.v_offset..j.v_offset + j.coord.nv()];
        let xj = j.coord.transform(qj);
        let vj = j.coord.motion_at(&xj, qj, vj_);
        if j.coord.has_bias() {
            ws.cj[i] = j.coord.bias(qj, vj_, &vj);
        }
        let x = if j.tree_identity {
            xj
        } else {
            j.tree.then(&xj)
        };
        ws.x[i] = x;
        ws.xj[i] = xj;
        ws.vj[i] = vj;
        match b.parent {
            Some(p) => {
                ws.world[i] = ws.world[p].then(&x);
                ws.vel[i] = x.motion_to_child(&ws.vel[p]) + vj;
            }
            None => {
                ws.world[i] = x;
                ws.vel[i] = vj;
            }
        }
    }
}

/// The placements and velocities of every body as [`position_velocity`] leaves them in the
/// workspace (`x`, `world`, `vel`, `vj`, `cj`), kept to be restored: the state of a Jacobian's
/// point, for its difference quotients ([`touched_position_velocity`]).
#[derive(Clone, Debug)]
pub(crate) struct BodyStates {
    x: Vec<Transform>,
    xj: Vec<Transform>,
    world: Vec<Transform>,
    vel: Vec<Motion>,
    vj: Vec<Motion>,
    cj: Vec<Motion>,
}

impl BodyStates {
    /// Storage for `plan`'s bodies (allocates; the values are set by [`BodyStates::save`]).
    pub(crate) fn new(plan: &Plan) -> Self {
        let nb = plan.bodies.len();
        BodyStates {
            x: vec![Transform::default(); nb],
            xj: vec![Transform::default(); nb],
            world: vec![Transform::default(); nb],
            vel: vec![Motion::zero(); nb],
            vj: vec![Motion::zero(); nb],
            cj: vec![Motion::zero(); nb],
        }
    }

    /// Keeps the workspace's placements and velocities. Allocation-free.
    pub(crate) fn save(&mut self, ws: &Workspace) {
        for i in 0..self.x.len() {
            self.x[i] = ws.x[i];
            self.xj[i] = ws.xj[i];
            self.world[i] = ws.world[i];
            self.vel[i] = ws.vel[i];
            self.vj[i] = ws.vj[i];
            self.cj[i] = ws.cj[i];
        }
    }
}

/// [`position_velocity`] at a point that differs from the one `base` was saved at only in
/// the coordinates of the bodies flagged in `touched` (a flagged body's descendants must be
/// flagged too): those bodies are placed as [`position_velocity`] places them (the same
/// operations, so the same bits), every other body's entries are restored from `base`.
/// Allocation-free.
pub(crate) fn touched_position_velocity(
    plan: &Plan,
    ws: &mut Workspace,
    base: &BodyStates,
    touched: &[bool],
    q: &[f64],
    v: &[f64],
) {
    for (i, &t) in touched.iter().enumerate() {
        if !t {
            ws.x[i] = base.x[i];
            ws.xj[i] = base.xj[i];
            ws.world[i] = base.world[i];
            ws.vel[i] = base.vel[i];
            ws.vj[i] = base.vj[i];
            ws.cj[i] = base.cj[i];
        }
    }
    // Parents come first, and an untouched parent has just been restored.
    let bodies = plan.bodies.iter().enumerate().filter(|&(i, _)| touched[i]);
    place_bodies(plan, ws, bodies, q, v);
}

/// Body `b` and its ancestors, root first: the bodies [`chain_position_velocity`] places.
/// For results, not the hot path (allocates).
pub(crate) fn ancestor_chain(plan: &Plan, b: Option<BodyId>) -> Vec<BodyId> {
    let mut chain = Vec::new();
    let mut at = b;
    while let Some(i) = at {
        chain.push(i);
        at = plan.bodies.get(i).and_then(|bp| bp.parent);
    }
    chain.reverse();
    chain
}

/// [`position_velocity`] for the bodies of `chain` only (an [`ancestor_chain`]): the same
/// operations for those bodies, so their placements and velocities are the same to the last
/// bit, at the cost of the chain instead of the whole scene. The other bodies' entries in the
/// workspace are left as they were.
pub(crate) fn chain_position_velocity(
    plan: &Plan,
    ws: &mut Workspace,
    chain: &[BodyId],
    q: &[f64],
    v: &[f64],
) {
    let bodies = chain.iter().map(|&i| (i.index(), &plan.bodies[i]));
    place_bodies(plan, ws, bodies, q, v);
}

/// Kinematic residual `q̇ − q̇(q, v)` into `res` (len nq), joint by joint.
pub(crate) fn position_residual(plan: &Plan, q: &[f64], v: &[f64], qd: &[f64], res: &mut [f64]) {
    for j in &plan.joints {
        let (qr, vr) = (
            j.q_offset..j.q_offset + j.coord.nq(),
            j.v_offset..j.v_offset + j.coord.nv(),
        );
        j.coord
            .position_residual(&q[qr.clone()], &v[vr], &qd[qr.clone()], &mut res[qr]);
    }
}

/// `q̇(q, v)` into `qd` (len nq): the derivative of the positions implied by the velocities.
/// Allocates; for initial values and restarts only.
pub(crate) fn position_derivative(plan: &Plan, q: &[f64], v: &[f64], qd: &mut [f64]) {
    position_residual(plan, q, v, &vec![0.0; plan.nq], qd);
    qd.iter_mut().for_each(|x| *x = -*x);
}

/// Placement of object `o` in world at the current workspace state.
#[inline]
pub(crate) fn object_in_world(plan: &Plan, ws: &Workspace, o: ObjectId) -> Transform {
    let op = &plan.objects[o];
    match op.body {
        Some(b) => ws.world[b].then(&op.in_body),
        None => op.in_body,
    }
}

/// Velocity [m/s] and angular velocity [rad/s], both resolved in world, of the material point
/// `p` (given in world \[m\]) of body `b` (`None` = world: at rest).
#[inline]
pub(crate) fn point_velocity(
    ws: &Workspace,
    b: Option<BodyId>,
    p: &Vector3<f64>,
) -> (Vector3<f64>, Vector3<f64>) {
    match b {
        None => (Vector3::zeros(), Vector3::zeros()),
        Some(b) => {
            let r = &ws.world[b].rot;
            let w = r * ws.vel[b].w;
            let v0 = r * ws.vel[b].v;
            (v0 + w.cross(&(p - ws.world[b].pos)), w)
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::{FreeRotation, Joint, JointKind, Object3D, SceneDesc, Shape, Solid};

    fn body(name: &str, parent: Option<&str>) -> Object3D {
        let o = Object3D::new(name).solid(
            Solid::new(Shape::Box {
                lengths: Vector3::new(0.1, 0.2, 0.3),
            })
            .material("Steel"),
        );
        match parent {
            Some(p) => o.parent(p).translation([0.1, -0.2, 0.05]),
            None => o,
        }
    }

    /// A chain's placements and velocities are those of the whole scene's pass to the last
    /// bit, for every body of a tree three levels deep (revolute → prismatic → free relative
    /// to its parent, an object rigidly attached to the last) and a free root body, at random
    /// states; the chain holds the body and its ancestors, root first.
    #[test]
    fn a_body_chain_places_its_bodies_as_the_whole_pass_does() {
        let mut s = SceneDesc::new();
        s.add(Object3D::new("world").scene(crate::SceneOptions::default()))
            .add(body("a", None))
            .add(body("b", None))
            .add(body("c", None))
            .add(body("c_tip", Some("c")))
            .add(body("d", None));
        let free = |r: [f64; 3]| JointKind::FreeMotion {
            r: Vector3::from(r),
            rot: FreeRotation::Cardan([0.1, 0.2, 0.3]),
            v: Vector3::zeros(),
            w: Vector3::zeros(),
        };
        s.add_joint(Joint::new(
            "ja",
            "world",
            "a",
            JointKind::Revolute {
                axis: Vector3::new(0.0, 0.6, 0.8),
                phi: 0.3,
                w: 0.0,
            },
        ))
        .add_joint(Joint::new(
            "jb",
            "a",
            "b",
            JointKind::Prismatic {
                axis: Vector3::x(),
                s: 0.2,
                v: 0.0,
            },
        ))
        .add_joint(Joint::new("jc", "b", "c", free([0.0, 0.3, -0.1])))
        .add_joint(Joint::new("jd", "world", "d", free([1.0, 0.0, 0.5])));
        let plan = Plan::compile(s.validated().expect("valid scene"));
        let mut rnd = crate::test_rng::uniform(0x5851f42d4c957f2d);
        let bits = |m: &[f64]| m.iter().map(|v| v.to_bits()).collect::<Vec<_>>();
        for _ in 0..5 {
            let q: Vec<f64> = (0..plan.nq).map(|_| rnd()).collect();
            let v: Vec<f64> = (0..plan.nv).map(|_| 10.0 * rnd()).collect();
            let mut all = Workspace::new(&plan);
            position_velocity(&plan, &mut all, &q, &v);
            for b in (0..plan.bodies.len()).map(BodyId) {
                let chain = ancestor_chain(&plan, Some(b));
                assert_eq!(chain.last(), Some(&b));
                for w in chain.windows(2) {
                    assert_eq!(plan.bodies[w[1]].parent, Some(w[0]), "chain {chain:?}");
                }
                assert_eq!(plan.bodies[chain[0]].parent, None);
                let mut one = Workspace::new(&plan);
                chain_position_velocity(&plan, &mut one, &chain, &q, &v);
                assert_eq!(
                    bits(one.world[b].pos.as_slice()),
                    bits(all.world[b].pos.as_slice())
                );
                assert_eq!(
                    bits(one.world[b].rot.as_slice()),
                    bits(all.world[b].rot.as_slice())
                );
                assert_eq!(bits(one.vel[b].w.as_slice()), bits(all.vel[b].w.as_slice()));
                assert_eq!(bits(one.vel[b].v.as_slice()), bits(all.vel[b].v.as_slice()));
            }
            // The deepest body's chain is the three bodies of its tree.
            let deepest = (0..plan.bodies.len())
                .map(BodyId)
                .max_by_key(|&b| ancestor_chain(&plan, Some(b)).len())
                .unwrap_or(BodyId(0));
            assert_eq!(ancestor_chain(&plan, Some(deepest)).len(), 3);
        }
        assert!(ancestor_chain(&plan, None).is_empty());
    }
}
