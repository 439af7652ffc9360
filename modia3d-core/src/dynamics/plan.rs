//! Plan stage: `ValidScene` → immutable `Plan`. Merges rigidly attached objects into bodies,
//! builds the joint tree rooted at the world, lays out the state vector and combines mass
//! properties. Objects fixed to the world carry no states. Touches only scene data.

use super::spatial::{Inertia, Transform};
use crate::scene::{SceneError, SceneErrors, ValidInputKind, ValidJointKind, ValidScene};
use nalgebra::{Isometry3, Vector3};
use std::collections::VecDeque;

/// Coordinates of a joint in the tree.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum JointCoord {
    /// Rotation about a unit axis resolved in the joint frame (= child body frame axis);
    /// one position `phi` [rad], one velocity `w` [rad/s].
    Revolute {
        /// Unit axis (already negated when the joint is traversed from obj2 to obj1).
        axis: Vector3<f64>,
    },
    /// Translation along a unit axis resolved in the joint frame;
    /// one position `s` [m], one velocity `v` [m/s].
    Prismatic {
        /// Unit axis (already negated when traversed from obj2 to obj1).
        axis: Vector3<f64>,
    },
    /// Six degrees of freedom: positions `r` (3, [m], resolved in obj1) and a quaternion
    /// `(w, x, y, z)` (4); velocities `ω` then `v` of obj2 relative to obj1, both resolved in obj2
    /// ([rad/s], [m/s]).
    Free,
}

impl JointCoord {
    /// Number of position coordinates.
    pub fn nq(&self) -> usize {
        match self {
            JointCoord::Free => 7,
            _ => 1,
        }
    }
    /// Number of velocity coordinates.
    pub fn nv(&self) -> usize {
        match self {
            JointCoord::Free => 6,
            _ => 1,
        }
    }
}

/// A moving body: the objects rigidly attached to each other, moved by one joint.
#[derive(Clone, Debug)]
pub struct BodyPlan {
    /// Parent body; `None` = the world.
    pub parent: Option<usize>,
    /// Index of its joint in `Plan::joints`.
    pub joint: usize,
    /// Combined mass properties about the body frame origin, resolved in the body frame.
    pub inertia: Inertia,
    /// Indices of the scene objects in this body.
    pub objects: Vec<usize>,
}

/// A joint of the tree (Fix joints are merged away).
#[derive(Clone, Debug)]
pub struct JointPlan {
    /// Name.
    pub name: String,
    /// Index in `ValidScene::joints`.
    pub scene_joint: usize,
    /// Coordinates.
    pub coord: JointCoord,
    /// The body it moves.
    pub body: usize,
    /// Placement of the joint frame in the parent body's frame (world for the world cluster).
    pub tree: Transform,
    /// Offset of its positions in the position vector `q`.
    pub q_offset: usize,
    /// Offset of its velocities in the velocity vector `v`.
    pub v_offset: usize,
    /// True when the tree runs from obj2 to obj1 (axis negated; coordinates unchanged).
    pub flipped: bool,
}

/// Where a scene object sits.
#[derive(Clone, Debug)]
pub struct ObjectPlan {
    /// Name.
    pub name: String,
    /// The moving body it belongs to; `None` = fixed to the world.
    pub body: Option<usize>,
    /// Its frame placed in the body frame (or in world) [m].
    pub in_body: Transform,
}

/// What an input drives, with plan indices.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum InputTarget {
    /// Generalised force on tree joint `joint` (1 value).
    JointForce {
        /// Index into `Plan::joints`.
        joint: usize,
    },
    /// Prescribed acceleration of tree joint `joint` (1 value).
    JointAcceleration {
        /// Index into `Plan::joints`.
        joint: usize,
    },
    /// World force then torque on object `object`'s origin (6 values).
    ObjectWrench {
        /// Index into `Plan::objects`.
        object: usize,
    },
}

/// An input and its place in the input value vector.
#[derive(Clone, Debug, PartialEq)]
pub struct InputPlan {
    /// Name.
    pub name: String,
    /// What it drives.
    pub target: InputTarget,
    /// Offset of its values in the input vector.
    pub offset: usize,
    /// Number of values.
    pub len: usize,
}

/// The immutable compiled scene: bodies in topological order (parents first), joints, state
/// layout `y = [q; v]`, initial values and force elements.
#[derive(Clone, Debug)]
pub struct Plan {
    /// Moving bodies, parents before children.
    pub bodies: Vec<BodyPlan>,
    /// Tree joints, `joints[bodies[i].joint]` moves body i.
    pub joints: Vec<JointPlan>,
    /// Every scene object.
    pub objects: Vec<ObjectPlan>,
    /// For each joint of the scene (`scene.joints`), its index in `joints` (`None` for Fix
    /// joints, which are merged away). Force elements refer to scene joints through it.
    pub tree_joint_of: Vec<Option<usize>>,
    /// Number of position coordinates.
    pub nq: usize,
    /// Number of velocity coordinates.
    pub nv: usize,
    /// Initial positions.
    pub q0: Vec<f64>,
    /// Initial velocities.
    pub v0: Vec<f64>,
    /// Gravity, resolved in world [m/s²].
    pub gravity: Vector3<f64>,
    /// The validated scene it was compiled from.
    pub scene: ValidScene,
    /// Inputs, in declaration order.
    pub inputs: Vec<InputPlan>,
    /// Total number of input values.
    pub n_inputs: usize,
    /// For each velocity coordinate, the input offset of its prescribed acceleration, if any.
    pub prescribed: Vec<Option<usize>>,
}

fn iso_to_transform(iso: &Isometry3<f64>) -> Transform {
    Transform {
        rot: iso.rotation.to_rotation_matrix().into_inner(),
        pos: iso.translation.vector,
    }
}

fn inverse(t: &Transform) -> Transform {
    Transform {
        rot: t.rot.transpose(),
        pos: -(t.rot.transpose() * t.pos),
    }
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

impl Plan {
    /// Compiles a validated scene. Errors: kinematic loops, parts not connected to the world,
    /// reversed free motions, bodies without inertia.
    pub fn compile(scene: ValidScene) -> Result<Plan, SceneErrors> {
        let n = scene.objects.len();
        let mut errors = vec![];
        let names = |ids: &[usize]| -> Vec<String> {
            ids.iter().map(|&i| scene.objects[i].name.clone()).collect()
        };

        // Rigid edges: (a, b, placement of b's frame in a's frame).
        let mut rigid: Vec<Vec<(usize, Transform)>> = vec![vec![]; n];
        let mut uf = UnionFind((0..n).collect());
        for (i, o) in scene.objects.iter().enumerate() {
            if let Some(p) = o.parent {
                let t = iso_to_transform(&o.pose);
                rigid[p].push((i, t));
                rigid[i].push((p, inverse(&t)));
                uf.union(p, i);
            }
        }
        for j in &scene.joints {
            if j.kind == ValidJointKind::Fix {
                if !uf.union(j.obj1, j.obj2) {
                    errors.push(SceneError::KinematicLoop {
                        objects: names(&[j.obj1, j.obj2]),
                    });
                }
                rigid[j.obj1].push((j.obj2, Transform::default()));
                rigid[j.obj2].push((j.obj1, Transform::default()));
            }
        }
        let cluster: Vec<usize> = (0..n).map(|i| uf.find(i)).collect();
        let world_cluster = cluster[scene.world];

        // Breadth-first over clusters through moving joints, starting at the world.
        let moving: Vec<usize> = (0..scene.joints.len())
            .filter(|&j| scene.joints[j].kind != ValidJointKind::Fix)
            .collect();
        let mut visited = vec![false; n]; // indexed by cluster representative
        visited[world_cluster] = true;
        // For each cluster: (body index or None for world), reference object.
        let mut cluster_body: Vec<Option<usize>> = vec![None; n];
        let mut ref_obj: Vec<usize> = vec![usize::MAX; n];
        ref_obj[world_cluster] = scene.world;
        let mut used = vec![false; scene.joints.len()];
        // Tree edge that reached each cluster: (parent cluster, scene joint).
        let mut reached_by: Vec<Option<(usize, usize)>> = vec![None; n];
        let mut queue = VecDeque::from([world_cluster]);
        // (joint, parent cluster, child-side object, parent-side object, flipped)
        let mut tree_edges = vec![];
        while let Some(c) = queue.pop_front() {
            for &j in &moving {
                if used[j] {
                    continue;
                }
                let sj = &scene.joints[j];
                let (c1, c2) = (cluster[sj.obj1], cluster[sj.obj2]);
                let (child_obj, parent_obj, flipped) = if c1 == c {
                    (sj.obj2, sj.obj1, false)
                } else if c2 == c {
                    (sj.obj1, sj.obj2, true)
                } else {
                    continue;
                };
                used[j] = true;
                let cc = cluster[child_obj];
                if visited[cc] {
                    // The loop: both ends' tree paths up to their common ancestor, closed by j.
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
                    let (p1, p2) = (path(c1), path(c2));
                    let mut ids = vec![sj.obj1, sj.obj2];
                    for p in [&p1, &p2] {
                        for &(k, via) in p {
                            if p1.iter().any(|x| x.0 == k) && p2.iter().any(|x| x.0 == k) {
                                break; // common ancestor reached
                            }
                            if let Some(via) = via {
                                let tj = &scene.joints[via];
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
                    errors.push(SceneError::KinematicLoop {
                        objects: names(&ids),
                    });
                    continue;
                }
                visited[cc] = true;
                reached_by[cc] = Some((c, j));
                ref_obj[cc] = child_obj;
                tree_edges.push((j, c, child_obj, parent_obj, flipped));
                queue.push_back(cc);
            }
        }
        for i in 0..n {
            if !visited[cluster[i]] {
                errors.push(SceneError::NotConnected {
                    object: scene.objects[i].name.clone(),
                });
                visited[cluster[i]] = true; // one message per unconnected part
            }
        }
        if !errors.is_empty() {
            return Err(SceneErrors(errors));
        }

        // Placement of every object in its cluster's reference frame.
        let mut in_ref = vec![Transform::default(); n];
        let mut placed = vec![false; n];
        for start in 0..n {
            let c = cluster[start];
            if ref_obj[c] != start {
                continue;
            }
            placed[start] = true;
            let mut stack = vec![start];
            while let Some(a) = stack.pop() {
                for &(b, t) in &rigid[a] {
                    if !placed[b] {
                        placed[b] = true;
                        in_ref[b] = in_ref[a].then(&t);
                        stack.push(b);
                    }
                }
            }
        }

        // Bodies and joints in breadth-first (topological) order.
        let mut bodies = vec![];
        let mut joints = vec![];
        let (mut nq, mut nv) = (0, 0);
        let (mut q0, mut v0) = (vec![], vec![]);
        for &(j, parent_cluster, child_obj, parent_obj, flipped) in &tree_edges {
            let sj = &scene.joints[j];
            let body = bodies.len();
            let coord = match &sj.kind {
                ValidJointKind::Revolute { axis, phi, w } => {
                    q0.push(*phi);
                    v0.push(*w);
                    JointCoord::Revolute {
                        axis: if flipped { -axis } else { *axis },
                    }
                }
                ValidJointKind::Prismatic { axis, s, v } => {
                    q0.push(*s);
                    v0.push(*v);
                    JointCoord::Prismatic {
                        axis: if flipped { -axis } else { *axis },
                    }
                }
                ValidJointKind::FreeMotion { r, rot, v, w } => {
                    if flipped {
                        errors.push(SceneError::ReversedFreeMotion {
                            joint: sj.name.clone(),
                            obj1: scene.objects[sj.obj1].name.clone(),
                            obj2: scene.objects[sj.obj2].name.clone(),
                        });
                    }
                    q0.extend_from_slice(r.as_slice());
                    q0.extend_from_slice(&[rot.w, rot.i, rot.j, rot.k]);
                    v0.extend_from_slice(w.as_slice());
                    v0.extend_from_slice((rot.inverse() * v).as_slice());
                    JointCoord::Free
                }
                ValidJointKind::Fix => unreachable!("fix joints are merged"),
            };
            let parent_body = cluster_body[parent_cluster];
            cluster_body[cluster[child_obj]] = Some(body);
            joints.push(JointPlan {
                name: sj.name.clone(),
                scene_joint: j,
                coord,
                body,
                tree: in_ref[parent_obj],
                q_offset: nq,
                v_offset: nv,
                flipped,
            });
            nq += coord.nq();
            nv += coord.nv();
            bodies.push(BodyPlan {
                parent: parent_body,
                joint: joints.len() - 1,
                inertia: Inertia::zero(),
                objects: vec![],
            });
        }

        let mut objects = Vec::with_capacity(n);
        for (i, o) in scene.objects.iter().enumerate() {
            let body = cluster_body[cluster[i]];
            if let Some(b) = body {
                bodies[b].objects.push(i);
                if let Some(s) = &o.solid {
                    let part = Inertia {
                        mass: s.mass.mass,
                        com: s.mass.com,
                        inertia_com: s.mass.inertia,
                    };
                    bodies[b].inertia = bodies[b].inertia.add_transformed(&part, &in_ref[i]);
                }
            }
            objects.push(ObjectPlan {
                name: o.name.clone(),
                body,
                in_body: in_ref[i],
            });
        }

        let mut tree_joint_of = vec![None; scene.joints.len()];
        for (tj, j) in joints.iter().enumerate() {
            tree_joint_of[j.scene_joint] = Some(tj);
        }

        if !errors.is_empty() {
            return Err(SceneErrors(errors));
        }
        let mut inputs = vec![];
        let mut n_inputs = 0;
        let mut prescribed = vec![None; nv];
        let tree_joint = |sj: usize| tree_joint_of[sj];
        for inp in &scene.inputs {
            let (target, len) = match inp.kind {
                ValidInputKind::JointForce(sj) => match tree_joint(sj) {
                    Some(joint) => (InputTarget::JointForce { joint }, 1),
                    None => continue, // validated: scalar joints are in the tree
                },
                ValidInputKind::JointAcceleration(sj) => match tree_joint(sj) {
                    Some(joint) => {
                        prescribed[joints[joint].v_offset] = Some(n_inputs);
                        (InputTarget::JointAcceleration { joint }, 1)
                    }
                    None => continue,
                },
                ValidInputKind::ObjectWrench(object) => (InputTarget::ObjectWrench { object }, 6),
            };
            inputs.push(InputPlan {
                name: inp.name.clone(),
                target,
                offset: n_inputs,
                len,
            });
            n_inputs += len;
        }
        let plan = Plan {
            inputs,
            n_inputs,
            prescribed,
            bodies,
            joints,
            objects,
            tree_joint_of,
            nq,
            nv,
            q0,
            v0,
            gravity: scene.options.gravity,
            scene,
        };
        Ok(plan)
    }

    /// The mass matrix of the coordinates that are not prescribed must be positive definite at
    /// the initial state; otherwise names the joint whose coordinate has no inertia.
    pub(crate) fn check_inertia(&self) -> Result<(), SceneErrors> {
        let mut ws = super::Workspace::new(self);
        let singular = super::mass_matrix::tree_mass_matrices(self, &mut ws, &self.q0)
            .into_iter()
            .find_map(|(group, m)| super::mass_matrix::free_cholesky(self, &group, &m).1.err());
        if let Some(k) = singular {
            let j = self
                .joints
                .iter()
                .find(|j| k >= j.v_offset && k < j.v_offset + j.coord.nv())
                .expect("every velocity belongs to a joint");
            let body = &self.bodies[j.body];
            let problem = if body.inertia.mass == 0.0 {
                "has no mass"
            } else {
                "has a singular inertia for its degrees of freedom"
            };
            return Err(SceneErrors(vec![SceneError::SingularMass {
                joint: j.name.clone(),
                objects: body
                    .objects
                    .iter()
                    .map(|&o| self.objects[o].name.clone())
                    .collect(),
                problem,
            }]));
        }
        Ok(())
    }

    /// Index of the object with this name.
    pub fn object_index(&self, name: &str) -> Option<usize> {
        self.objects.iter().position(|o| o.name == name)
    }

    /// Index of the tree joint with this name.
    pub fn joint_index(&self, name: &str) -> Option<usize> {
        self.joints.iter().position(|j| j.name == name)
    }

    /// The independent joint trees: for each body the index of its tree (one per root body,
    /// i.e. per body whose parent is the world), and the number of trees. `M(q)` is block
    /// diagonal over the trees, and the rows of one tree depend on another's state only through
    /// forces between them (spring-dampers, forces of other stages).
    pub fn trees(&self) -> (Vec<usize>, usize) {
        let mut tree = vec![0; self.bodies.len()];
        let mut n = 0;
        // Bodies come parents first, so a parent's tree is known when its children are reached.
        for (b, body) in self.bodies.iter().enumerate() {
            tree[b] = match body.parent {
                None => {
                    n += 1;
                    n - 1
                }
                Some(p) => tree[p],
            };
        }
        (tree, n)
    }

    /// Velocity indices of each joint tree (see [`Plan::trees`]), ascending.
    pub fn velocity_groups(&self) -> Vec<Vec<usize>> {
        let (tree, n) = self.trees();
        let mut groups = vec![vec![]; n];
        for j in &self.joints {
            groups[tree[j.body]].extend(j.v_offset..j.v_offset + j.coord.nv());
        }
        for g in &mut groups {
            g.sort_unstable();
        }
        groups
    }

    /// Initial state `y0 = [q0; v0]`.
    pub fn y0(&self) -> Vec<f64> {
        [self.q0.as_slice(), self.v0.as_slice()].concat()
    }
}
