//! Validation stage, topology: parent cycles, objects moved by two joints, the rigid clusters
//! (objects merged by parent links and `Fix` joints; everything attached to the world is one
//! cluster), the spanning joint tree rooted at the world, kinematic loops, parts not connected
//! to the world and FreeMotions written the wrong way round. Runs inside
//! [`SceneDesc::validate`](crate::SceneDesc::validate), so these errors come in the same round
//! as every other; the result travels in [`ValidScene::topology`](super::ValidScene) to the
//! plan, which only lays the tree out. Touches only resolved scene data.
//!
//! The choice of the tree is one function, [`spanning_tree`]: it returns the tree edges and the
//! joints that close loops. A loop-closing joint becomes a *cut joint*: it stays out of the tree
//! and the plan enforces it by constraints (`dynamics/loops.rs`). The tree is breadth-first from
//! the world over the joints in declaration order, first without the joints the user marked
//! (`Joint::cut`), then with them, so a marked joint is cut whenever it closes a loop, and
//! otherwise the loop's last-reached joint in declaration order is. Still errors: a loop whose
//! only moving joint joins two objects of one rigid part (it locks nothing and cannot move), a
//! loop of parent links and Fix joints only, and an object that is obj2 of two joints of which
//! more than one is no part of any loop (a body moved by two joints without a loop).

use super::validate::{SceneError, ValidJoint, ValidObject};
use std::collections::{HashMap, VecDeque};

/// A joint of the spanning tree, in breadth-first order from the world (parents first).
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct TreeEdge {
    /// Index into `ValidScene::joints`.
    pub joint: usize,
    /// Cluster (see [`Topology::cluster`]) on the world side of the joint.
    pub parent_cluster: usize,
    /// The joint's end on the far side of the world.
    pub child_obj: usize,
    /// The joint's end on the world side.
    pub parent_obj: usize,
    /// True when the tree runs from obj2 to obj1 (the joint is traversed backwards).
    pub flipped: bool,
}

/// The scene's topology: rigid clusters and the spanning joint tree.
#[derive(Clone, Debug, PartialEq, Default)]
pub(crate) struct Topology {
    /// Cluster of each object, named by a representative object index; two objects are
    /// rigidly attached exactly when their clusters are equal.
    pub cluster: Vec<usize>,
    /// Cluster of the world (the `Scene` object).
    pub world_cluster: usize,
    /// The moving joints of the tree, parents before children.
    pub tree: Vec<TreeEdge>,
    /// The cut joints, one per independent loop, in the order the tree search met them.
    pub cuts: Vec<CutEdge>,
}

/// A joint that closes a kinematic loop, kept out of the tree (see the module docs).
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct CutEdge {
    /// Index into `ValidScene::joints`.
    pub joint: usize,
    /// The joints of its loop (indices into `ValidScene::joints`): the cut joint first, then the
    /// tree joints of both ends' paths up to their common ancestor.
    pub loop_joints: Vec<usize>,
}

struct UnionFind(Vec<usize>);
impl UnionFind {
    fn find(&mut self, mut i: usize) -> usize {
        while self.0[i] != i {
            self.0[i] = self.0[self.0[i]];
            i = self.0[i];
        }
        i
    }
    /// false if already joined (a loop)
    fn union(&mut self, a: usize, b: usize) -> bool {
        let (ra, rb) = (self.find(a), self.find(b));
        if ra == rb {
            return false;
        }
        self.0[ra] = rb;
        true
    }
}

/// Checks the topology of resolved objects and joints and computes clusters and tree.
/// `suspect` marks objects whose links were dropped because of other errors (an unknown
/// parent, a joint with a bad end or value): a part containing one is not reported as
/// unconnected, since that follows from the error already reported. Parent cycles are cut
/// (and their objects marked suspect) so that the later passes terminate.
pub(crate) fn check_topology(
    objects: &mut [ValidObject],
    joints: &[ValidJoint],
    world: Option<usize>,
    suspect: &mut [bool],
    errors: &mut Vec<SceneError>,
) -> Topology {
    parent_cycles(objects, suspect, errors);
    let n = objects.len();
    let names =
        |ids: &[usize]| -> Vec<String> { ids.iter().map(|&i| objects[i].name.clone()).collect() };

    let mut uf = UnionFind((0..n).collect());
    for (i, o) in objects.iter().enumerate() {
        if let Some(p) = o.parent {
            uf.union(p, i);
        }
    }
    for j in joints {
        if j.kind.is_rigid() && !uf.union(j.obj1, j.obj2) {
            errors.push(SceneError::KinematicLoop {
                objects: names(&[j.obj1, j.obj2]),
            });
        }
    }
    let cluster: Vec<usize> = (0..n).map(|i| uf.find(i)).collect();
    let Some(world) = world else {
        // No world (reported): no tree to check against.
        two_parents(objects, joints, &vec![false; joints.len()], errors);
        return Topology {
            cluster,
            world_cluster: 0,
            tree: vec![],
            cuts: vec![],
        };
    };
    let world_cluster = cluster[world];
    let candidates: Vec<usize> = (0..joints.len())
        .filter(|&j| !joints[j].kind.is_rigid())
        .collect();
    let (tree, closing, reached_by) =
        spanning_tree(joints, &cluster, world_cluster, &candidates, n);
    let mut cuts = vec![];
    let mut on_loop = vec![false; joints.len()];
    for j in closing {
        if cluster[joints[j].obj1] == cluster[joints[j].obj2] {
            // Both ends in one rigid part: the joint can never move.
            errors.push(SceneError::KinematicLoop {
                objects: names(&[joints[j].obj1, joints[j].obj2]),
            });
            on_loop[j] = true; // reported: no follow-up `TwoParents`
            continue;
        }
        let loop_joints = loop_joints(joints, &cluster, &reached_by, j);
        for &k in &loop_joints {
            on_loop[k] = true;
        }
        cuts.push(CutEdge {
            joint: j,
            loop_joints,
        });
    }
    two_parents(objects, joints, &on_loop, errors);
    for e in &tree {
        let sj = &joints[e.joint];
        if let (true, Some(reversed)) = (e.flipped, sj.kind.facts().reversed) {
            errors.push(reversed(
                sj.name.clone(),
                objects[sj.obj1].name.clone(),
                objects[sj.obj2].name.clone(),
            ));
        }
    }
    let mut reached = vec![false; n];
    reached[world_cluster] = true;
    for e in &tree {
        reached[cluster[e.child_obj]] = true;
    }
    let mut excused = vec![false; n];
    for i in (0..n).filter(|&i| suspect[i]) {
        excused[cluster[i]] = true;
    }
    for i in 0..n {
        if !reached[cluster[i]] {
            if !excused[cluster[i]] {
                errors.push(SceneError::NotConnected {
                    object: objects[i].name.clone(),
                });
            }
            reached[cluster[i]] = true; // one message per unconnected part
        }
    }
    Topology {
        cluster,
        world_cluster,
        tree,
        cuts,
    }
}

/// The spanning joint tree: breadth-first over clusters from the world cluster through the
/// `candidates` (moving joints, in declaration order), first through the joints not marked
/// `cut`, then through all. Returns the tree edges, the joints that close a loop (both ends
/// already reached), and for each cluster the tree edge that reached it (parent cluster, joint).
#[allow(clippy::type_complexity)]
pub(crate) fn spanning_tree(
    joints: &[ValidJoint],
    cluster: &[usize],
    world_cluster: usize,
    candidates: &[usize],
    n: usize,
) -> (Vec<TreeEdge>, Vec<usize>, Vec<Option<(usize, usize)>>) {
    let mut visited = vec![false; n]; // indexed by cluster representative
    visited[world_cluster] = true;
    let mut used = vec![false; joints.len()];
    let mut reached_by: Vec<Option<(usize, usize)>> = vec![None; n];
    let (mut tree, mut closing) = (vec![], vec![]);
    let unmarked: Vec<usize> = candidates
        .iter()
        .copied()
        .filter(|&j| !joints[j].cut)
        .collect();
    for phase in [&unmarked[..], candidates] {
        // Every cluster reached so far is searched again with the joints of this phase.
        let mut queue: VecDeque<usize> = std::iter::once(world_cluster)
            .chain(tree.iter().map(|e: &TreeEdge| cluster[e.child_obj]))
            .collect();
        while let Some(c) = queue.pop_front() {
            for &j in phase {
                if used[j] {
                    continue;
                }
                let sj = &joints[j];
                let (child_obj, parent_obj, flipped) = if cluster[sj.obj1] == c {
                    (sj.obj2, sj.obj1, false)
                } else if cluster[sj.obj2] == c {
                    (sj.obj1, sj.obj2, true)
                } else {
                    continue;
                };
                used[j] = true;
                let cc = cluster[child_obj];
                if visited[cc] {
                    closing.push(j);
                    continue;
                }
                visited[cc] = true;
                reached_by[cc] = Some((c, j));
                tree.push(TreeEdge {
                    joint: j,
                    parent_cluster: c,
                    child_obj,
                    parent_obj,
                    flipped,
                });
                queue.push_back(cc);
            }
        }
    }
    (tree, closing, reached_by)
}

/// The joints of the loop closed by joint `j`: `j`, then the tree joints of both ends' paths
/// up to their common ancestor.
fn loop_joints(
    joints: &[ValidJoint],
    cluster: &[usize],
    reached_by: &[Option<(usize, usize)>],
    j: usize,
) -> Vec<usize> {
    let sj = &joints[j];
    let path = |mut k: usize| {
        let mut p = vec![];
        loop {
            let r = reached_by[k];
            p.push((k, r.map(|x: (usize, usize)| x.1)));
            match r {
                Some((up, _)) => k = up,
                None => return p,
            }
        }
    };
    let (p1, p2) = (path(cluster[sj.obj1]), path(cluster[sj.obj2]));
    let mut out = vec![j];
    for (p, other) in [(&p1, &p2), (&p2, &p1)] {
        for &(k, via) in p {
            if other.iter().any(|x| x.0 == k) {
                break; // common ancestor reached
            }
            out.extend(via);
        }
    }
    out
}

/// Reports parent chains that do not end at a root, and cuts each cycle.
fn parent_cycles(objects: &mut [ValidObject], suspect: &mut [bool], errors: &mut Vec<SceneError>) {
    let n = objects.len();
    let mut state = vec![0u8; n]; // 0 new, 1 on current chain, 2 done
    for start in 0..n {
        let mut chain = vec![];
        let mut i = start;
        while state[i] == 0 {
            state[i] = 1;
            chain.push(i);
            match objects[i].parent {
                Some(p) => i = p,
                None => break,
            }
        }
        if state[i] == 1 && objects[i].parent.is_some() && chain.contains(&i) {
            let pos = chain.iter().position(|&k| k == i).unwrap_or(0);
            errors.push(SceneError::ParentCycle {
                objects: chain[pos..]
                    .iter()
                    .map(|&k| objects[k].name.clone())
                    .collect(),
            });
            // Cut the cycle so later passes terminate.
            let k = chain[chain.len() - 1];
            objects[k].parent = None;
            suspect[k] = true;
        }
        for k in chain {
            state[k] = 2;
        }
    }
}

/// Reports objects that are obj2 of several joints of which more than one lies on no loop
/// (`on_loop`, per joint): such an object is moved by two joints without a loop. Two joints
/// that move one object and close a loop together are a closed chain, not an error.
fn two_parents(
    objects: &[ValidObject],
    joints: &[ValidJoint],
    on_loop: &[bool],
    errors: &mut Vec<SceneError>,
) {
    let mut movers: HashMap<usize, Vec<usize>> = HashMap::new();
    for (k, j) in joints.iter().enumerate() {
        movers.entry(j.obj2).or_default().push(k);
    }
    let mut two: Vec<_> = movers
        .into_iter()
        .filter(|(_, v)| v.iter().filter(|&&k| !on_loop[k]).count() > 1)
        .collect();
    two.sort();
    for (o, js) in two {
        errors.push(SceneError::TwoParents {
            object: objects[o].name.clone(),
            joints: js.iter().map(|&k| joints[k].name.clone()).collect(),
        });
    }
}
