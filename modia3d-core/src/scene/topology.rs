//! Validation stage, topology: parent cycles, objects moved by two joints, the rigid clusters
//! (objects merged by parent links and `Fix` joints; everything attached to the world is one
//! cluster), the spanning joint tree rooted at the world, kinematic loops, parts not connected
//! to the world and FreeMotions written the wrong way round. Runs inside
//! [`SceneDesc::validate`](crate::SceneDesc::validate), so these errors come in the same round
//! as every other; the result travels in [`ValidScene::topology`](super::ValidScene) to the
//! plan, which only lays the tree out. Touches only resolved scene data.
//!
//! The choice of the tree is one function, [`spanning_tree`]: it returns the tree edges and the
//! joints that close loops. Today every loop-closing joint is an error; closed chains with cut
//! joints would keep them instead.

use super::validate::{SceneError, ValidJoint, ValidJointKind, ValidObject};
use std::collections::{HashMap, VecDeque};

/// A joint of the spanning tree, in breadth-first order from the world (parents first).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TreeEdge {
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
pub struct Topology {
    /// Cluster of each object, named by a representative object index; two objects are
    /// rigidly attached exactly when their clusters are equal.
    pub cluster: Vec<usize>,
    /// Cluster of the world (the `Scene` object).
    pub world_cluster: usize,
    /// The moving joints of the tree, parents before children.
    pub tree: Vec<TreeEdge>,
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
    let extra_movers = two_parents(objects, joints, errors);
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
        if j.kind == ValidJointKind::Fix && !uf.union(j.obj1, j.obj2) {
            errors.push(SceneError::KinematicLoop {
                objects: names(&[j.obj1, j.obj2]),
            });
        }
    }
    let cluster: Vec<usize> = (0..n).map(|i| uf.find(i)).collect();
    let Some(world) = world else {
        // No world (reported): no tree to check against.
        return Topology {
            cluster,
            world_cluster: 0,
            tree: vec![],
        };
    };
    let world_cluster = cluster[world];
    let candidates: Vec<usize> = (0..joints.len())
        .filter(|&j| joints[j].kind != ValidJointKind::Fix && !extra_movers[j])
        .collect();
    let (tree, closing, reached_by) =
        spanning_tree(joints, &cluster, world_cluster, &candidates, n);
    for j in closing {
        errors.push(SceneError::KinematicLoop {
            objects: names(&loop_objects(joints, &cluster, &reached_by, j)),
        });
    }
    for e in &tree {
        let sj = &joints[e.joint];
        let reversible = crate::joints::info(sj.kind.name()).is_none_or(|i| i.reversible);
        if e.flipped && !reversible {
            let (joint, obj1, obj2) = (
                sj.name.clone(),
                objects[sj.obj1].name.clone(),
                objects[sj.obj2].name.clone(),
            );
            errors.push(match sj.kind.name() {
                "FreeMotion" => SceneError::ReversedFreeMotion { joint, obj1, obj2 },
                kind => SceneError::ReversedJoint {
                    joint,
                    kind,
                    obj1,
                    obj2,
                },
            });
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
    }
}

/// The spanning joint tree: breadth-first over clusters through the `candidates` (moving
/// joints, in declaration order) from the world cluster. Returns the tree edges, the joints
/// that close a loop (both ends already reached), and for each cluster the tree edge that
/// reached it (parent cluster, joint).
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
    let mut queue = VecDeque::from([world_cluster]);
    let (mut tree, mut closing) = (vec![], vec![]);
    while let Some(c) = queue.pop_front() {
        for &j in candidates {
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
    (tree, closing, reached_by)
}

/// The objects of the loop closed by joint `j`: both ends' tree paths up to their common
/// ancestor, closed by `j`, without repetitions.
fn loop_objects(
    joints: &[ValidJoint],
    cluster: &[usize],
    reached_by: &[Option<(usize, usize)>],
    j: usize,
) -> Vec<usize> {
    let sj = &joints[j];
    // (cluster, joint to its parent cluster) up to the world.
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
    let mut ids = vec![sj.obj1, sj.obj2];
    for p in [&p1, &p2] {
        for &(k, via) in p {
            if p1.iter().any(|x| x.0 == k) && p2.iter().any(|x| x.0 == k) {
                break; // common ancestor reached
            }
            if let Some(via) = via {
                let tj = &joints[via];
                ids.extend([tj.obj1, tj.obj2]);
            }
        }
    }
    let mut seen = vec![];
    ids.retain(|i| {
        let new = !seen.contains(i);
        seen.push(*i);
        new
    });
    ids
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

/// Reports objects that are obj2 of several joints; returns, per joint, whether it is such a
/// second (or later) mover, which the tree then leaves out (no follow-up loop error).
fn two_parents(
    objects: &[ValidObject],
    joints: &[ValidJoint],
    errors: &mut Vec<SceneError>,
) -> Vec<bool> {
    let mut movers: HashMap<usize, Vec<usize>> = HashMap::new();
    for (k, j) in joints.iter().enumerate() {
        movers.entry(j.obj2).or_default().push(k);
    }
    let mut two: Vec<_> = movers.into_iter().filter(|(_, v)| v.len() > 1).collect();
    two.sort();
    let mut extra = vec![false; joints.len()];
    for (o, js) in two {
        for &k in &js[1..] {
            extra[k] = true;
        }
        errors.push(SceneError::TwoParents {
            object: objects[o].name.clone(),
            joints: js.iter().map(|&k| joints[k].name.clone()).collect(),
        });
    }
    extra
}
