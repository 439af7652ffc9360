//! Plan stage: `ValidScene` → immutable `Plan`. Lays out the clusters and the spanning joint
//! tree that validation computed (`scene/topology.rs`) as bodies and tree joints (axes of
//! reversed joints negated), places the objects in their body frames, lays out the state
//! vector and the inputs and combines mass properties. Objects fixed to the world carry no
//! states. Touches only scene data.

use super::ids::{BodyId, IdVec, JointId, ObjectId};
pub(crate) use crate::joints::JointCoord;
use crate::scene::{GravityField, ValidInputKind, ValidScene};
use crate::spatial::{Inertia, Transform};
use nalgebra::{Isometry3, Vector3};

/// A moving body: the objects rigidly attached to each other, moved by one joint.
#[derive(Clone, Debug)]
pub(crate) struct BodyPlan {
    /// Parent body; `None` = the world.
    pub parent: Option<BodyId>,
    /// Its joint.
    pub joint: JointId,
    /// Combined mass properties about the body frame origin, resolved in the body frame.
    pub inertia: Inertia,
    /// The scene objects in this body.
    pub objects: Vec<ObjectId>,
}

/// A joint of the tree (Fix joints are merged away).
#[derive(Clone, Debug)]
pub(crate) struct JointPlan {
    /// Name.
    pub name: String,
    /// Index in `ValidScene::joints`.
    pub scene_joint: usize,
    /// Coordinates.
    pub coord: JointCoord,
    /// The body it moves.
    pub body: BodyId,
    /// Placement of the joint frame in the parent body's frame (world for the world cluster).
    pub tree: Transform,
    /// `tree` is exactly the identity (a joint frame at its parent's origin, axes aligned):
    /// the kinematics then take the joint transform as the body's placement without the
    /// product (the same values).
    pub tree_identity: bool,
    /// Offset of its positions in the position vector `q`.
    pub q_offset: usize,
    /// Offset of its velocities in the velocity vector `v`.
    pub v_offset: usize,
    /// True when the tree runs from obj2 to obj1 (axis negated; coordinates unchanged).
    pub flipped: bool,
}

/// Where a scene object sits.
#[derive(Clone, Debug)]
pub(crate) struct ObjectPlan {
    /// Name.
    pub name: String,
    /// The moving body it belongs to; `None` = fixed to the world.
    pub body: Option<BodyId>,
    /// Its frame placed in the body frame (or in world) \[m\].
    pub in_body: Transform,
}

/// What an input drives, with plan indices.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) enum InputTarget {
    /// Generalised force on a scalar coordinate of tree joint `joint` (1 value).
    JointForce {
        /// The tree joint.
        joint: JointId,
        /// Index into the kind's scalar coordinates.
        coordinate: usize,
    },
    /// Prescribed acceleration of a scalar coordinate of tree joint `joint` (1 value).
    JointAcceleration {
        /// The tree joint.
        joint: JointId,
        /// Index into the kind's scalar coordinates.
        coordinate: usize,
    },
    /// World force then torque on object `object`'s origin (6 values).
    ObjectWrench {
        /// The object.
        object: ObjectId,
    },
}

/// An input and its place in the input value vector.
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct InputPlan {
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
pub(crate) struct Plan {
    /// Moving bodies, parents before children.
    pub bodies: IdVec<BodyId, BodyPlan>,
    /// Tree joints, `joints[bodies[i].joint]` moves body i.
    pub joints: IdVec<JointId, JointPlan>,
    /// Every scene object.
    pub objects: IdVec<ObjectId, ObjectPlan>,
    /// For each joint of the scene (`scene.joints`), its index in `joints` (`None` for Fix
    /// joints, which are merged away). Force elements refer to scene joints through it.
    pub tree_joint_of: Vec<Option<JointId>>,
    /// Number of position coordinates.
    pub nq: usize,
    /// Number of velocity coordinates.
    pub nv: usize,
    /// Initial positions.
    pub q0: Vec<f64>,
    /// Initial velocities.
    pub v0: Vec<f64>,
    /// Uniform gravity, resolved in world [m/s²] (zero for no field and for point gravity):
    /// the base acceleration of the recursive Newton–Euler pass.
    pub gravity: Vector3<f64>,
    /// Point gravity `(μ [m³/s²], centre resolved in world [m])`, applied per body in
    /// `forces::applied_forces` (it differs from body to body, so it is no base acceleration).
    pub point_gravity: Option<(f64, Vector3<f64>)>,
    /// The validated scene it was compiled from.
    pub scene: ValidScene,
    /// Inputs, in declaration order.
    pub inputs: Vec<InputPlan>,
    /// Total number of input values.
    pub n_inputs: usize,
    /// For each velocity coordinate, the input offset of its prescribed acceleration, if any.
    pub prescribed: Vec<Option<usize>>,
    /// The cut joints of closed loops and their kept constraint rows (`dynamics/loops.rs`);
    /// the rows are chosen by `loops::assemble_initial` when the model is built.
    pub loops: super::loops::LoopPlan,
    /// The components with states (`dynamics/components.rs`); their states follow `[q; v]`
    /// and the loops' multipliers in `y`.
    pub components: super::components::ComponentPlan,
    /// Per velocity coordinate, the inertia rigidly geared to it by components' flanges
    /// ([kg·m²] or \[kg\]; `M_kk += armature_k`); empty when there is none.
    pub armature: Vec<f64>,
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

/// The bodies and tree joints laid out from the spanning tree, with the state layout.
struct TreeLayout {
    bodies: Vec<BodyPlan>,
    joints: Vec<JointPlan>,
    /// Body of each cluster (`None` for the world's and for clusters not in the tree).
    cluster_body: Vec<Option<BodyId>>,
    q0: Vec<f64>,
    v0: Vec<f64>,
}

/// Placement of every object in its cluster's reference frame: the world for the world's
/// cluster, else the tree joint's child-side object.
fn placements(scene: &ValidScene) -> Vec<Transform> {
    let n = scene.objects.len();
    let topo = &scene.topology;
    let cluster = &topo.cluster;
    // Rigid edges: (b, placement of b's frame in a's frame), for parent links and Fix joints.
    let mut rigid: Vec<Vec<(usize, Transform)>> = vec![vec![]; n];
    for (i, o) in scene.objects.iter().enumerate() {
        if let Some(p) = o.parent {
            let t = iso_to_transform(&o.pose);
            rigid[p].push((i, t));
            rigid[i].push((p, inverse(&t)));
        }
    }
    for j in &scene.joints {
        if j.kind.is_rigid() {
            rigid[j.obj1].push((j.obj2, Transform::default()));
            rigid[j.obj2].push((j.obj1, Transform::default()));
        }
    }
    let mut ref_obj: Vec<usize> = vec![usize::MAX; n];
    ref_obj[topo.world_cluster] = scene.world;
    for e in &topo.tree {
        ref_obj[cluster[e.child_obj]] = e.child_obj;
    }
    let mut in_ref = vec![Transform::default(); n];
    let mut placed = vec![false; n];
    for start in 0..n {
        if ref_obj[cluster[start]] != start {
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
    in_ref
}

/// Bodies and joints in breadth-first (topological) order, with initial values; axes of
/// joints traversed from obj2 to obj1 negated.
fn tree_layout(scene: &ValidScene, in_ref: &[Transform]) -> TreeLayout {
    let topo = &scene.topology;
    let mut l = TreeLayout {
        bodies: vec![],
        joints: vec![],
        cluster_body: vec![None; scene.objects.len()],
        q0: vec![],
        v0: vec![],
    };
    let (mut nq, mut nv) = (0, 0);
    for e in &topo.tree {
        let sj = &scene.joints[e.joint];
        let body = l.bodies.len();
        let coord = JointCoord::new(&sj.kind, e.flipped, &mut l.q0, &mut l.v0);
        let parent_body = l.cluster_body[e.parent_cluster];
        l.cluster_body[topo.cluster[e.child_obj]] = Some(BodyId(body));
        l.joints.push(JointPlan {
            name: sj.name.clone(),
            scene_joint: e.joint,
            coord,
            body: BodyId(body),
            tree: in_ref[e.parent_obj],
            tree_identity: in_ref[e.parent_obj] == Transform::default(),
            q_offset: nq,
            v_offset: nv,
            flipped: e.flipped,
        });
        nq += coord.nq();
        nv += coord.nv();
        l.bodies.push(BodyPlan {
            parent: parent_body,
            joint: JointId(l.joints.len() - 1),
            inertia: Inertia::zero(),
            objects: vec![],
        });
    }
    l
}

/// Resolves the velocities of the FreeMotion joints of bodies alone in their tree (obj1 fixed
/// to the world, no body on them), `round` (every collision shape a sphere centred on the
/// origin, or none) and whose centre of mass is their origin in obj1, turning their initial
/// velocities there; the other free joints keep them in the child frame (`joints/free.rs` says
/// why). "Is their origin": `|c|² ≤ 1e-12 · tr(I_c)/m` (a millionth of the body's radius of
/// gyration, so a body symmetric about its origin passes whatever the rounding of its parts'
/// sum).
fn resolve_free_velocities(
    joints: &mut [JointPlan],
    bodies: &[BodyPlan],
    round: &[bool],
    q0: &[f64],
    v0: &mut [f64],
) {
    let mut carries = vec![false; bodies.len()];
    for b in bodies {
        if let Some(p) = b.parent {
            carries[p.index()] = true;
        }
    }
    for j in joints.iter_mut() {
        let b = &bodies[j.body.index()];
        let i = &b.inertia;
        let centred =
            i.mass > 0.0 && i.com.norm_squared() <= 1e-12 * i.inertia_com.trace() / i.mass;
        let alone = b.parent.is_none() && !carries[j.body.index()] && round[j.body.index()];
        if alone && centred {
            let (nq, nv) = (j.coord.nq(), j.coord.nv());
            j.coord.resolve_in_obj1(
                &q0[j.q_offset..j.q_offset + nq],
                &mut v0[j.v_offset..j.v_offset + nv],
            );
        }
    }
}

/// Inputs with plan indices and offsets into the input vector, and for each velocity
/// coordinate the input offset of its prescribed acceleration.
fn input_layout(
    scene: &ValidScene,
    joints: &[JointPlan],
    tree_joint_of: &[Option<JointId>],
    nv: usize,
) -> (Vec<InputPlan>, usize, Vec<Option<usize>>) {
    let mut inputs = vec![];
    let mut n_inputs = 0;
    let mut prescribed = vec![None; nv];
    for inp in &scene.inputs {
        let (target, len) = match inp.kind {
            ValidInputKind::JointForce(sj, coordinate) => match tree_joint_of[sj] {
                Some(joint) => (InputTarget::JointForce { joint, coordinate }, 1),
                None => continue, // validated: joints with scalar coordinates are in the tree
            },
            ValidInputKind::JointAcceleration(sj, coordinate) => match tree_joint_of[sj] {
                Some(joint) => {
                    let j = &joints[joint.index()];
                    let c = j.coord.coordinates()[coordinate];
                    prescribed[j.v_offset + c.v] = Some(n_inputs);
                    (InputTarget::JointAcceleration { joint, coordinate }, 1)
                }
                None => continue,
            },
            ValidInputKind::ObjectWrench(object) => (
                InputTarget::ObjectWrench {
                    object: ObjectId(object),
                },
                6,
            ),
        };
        inputs.push(InputPlan {
            name: inp.name.clone(),
            target,
            offset: n_inputs,
            len,
        });
        n_inputs += len;
    }
    (inputs, n_inputs, prescribed)
}

impl Plan {
    /// Lays out a validated scene, whose topology (clusters, spanning tree) validation has
    /// already checked: bodies and joints in tree order, object placements, state layout,
    /// combined mass properties, inputs. Layout only: it cannot fail. The mass-matrix
    /// positivity check ([`super::mass_matrix::check_inertia`]) needs the finished plan and runs after it.
    pub(crate) fn compile(scene: ValidScene) -> Plan {
        let in_ref = placements(&scene);
        let TreeLayout {
            mut bodies,
            mut joints,
            cluster_body,
            q0,
            mut v0,
        } = tree_layout(&scene, &in_ref);
        let cluster = &scene.topology.cluster;
        let mut objects = Vec::with_capacity(scene.objects.len());
        for (i, o) in scene.objects.iter().enumerate() {
            let body = cluster_body[cluster[i]];
            if let Some(b) = body {
                bodies[b.index()].objects.push(ObjectId(i));
                if let Some(s) = &o.solid {
                    let part = Inertia {
                        mass: s.mass.mass,
                        com: s.mass.com,
                        inertia_com: s.mass.inertia,
                    };
                    bodies[b.index()].inertia =
                        bodies[b.index()].inertia.add_transformed(&part, &in_ref[i]);
                }
            }
            objects.push(ObjectPlan {
                name: o.name.clone(),
                body,
                in_body: in_ref[i],
            });
        }
        // A body is round if every collision shape on it is a sphere, or a cylinder under the
        // volume law (`ContactProfile::Volume`, the default), centred on its origin: it rolls,
        // and its velocities are resolved in obj1 (`resolve_free_velocities`). A cylinder
        // rolling on its side at 20° took 255 IDA steps at rtol 1e-2 with its velocities in its
        // own frame (sinusoids of its spin; 43 Newton failures) and 131 in obj1 (4), its
        // acceleration 2.5e-3 and 7.6e-6 off (BENCHMARKS.md, "Face contacts"). Under the point
        // laws of the other profiles a cylinder rocks on single points, and in obj1 it lost:
        // `falling_boxes` under the paper's law took 17,557 steps instead of 15,859, the
        // spinning steel cylinder of `tests/regressions.rs` ~20 s instead of ~7.5 s.
        let volume_law = scene.options.contact_profile == crate::scene::ContactProfile::Volume;
        let mut round = vec![true; bodies.len()];
        for (i, o) in scene.objects.iter().enumerate() {
            let (Some(b), Some(s)) = (cluster_body[cluster[i]], &o.solid) else {
                continue;
            };
            let size = match s.shape.as_ref() {
                Some(crate::geometry::Shape::Cylinder { diameter, .. }) if volume_law => {
                    Some(*diameter)
                }
                sh => sh.and_then(|sh| sh.ball_diameter()),
            };
            let centred_round = size.is_some_and(|d| in_ref[i].pos.norm() <= 1e-12 * d);
            if s.collision && !centred_round {
                round[b.index()] = false;
            }
        }
        resolve_free_velocities(&mut joints, &bodies, &round, &q0, &mut v0);
        let mut tree_joint_of = vec![None; scene.joints.len()];
        for (tj, j) in joints.iter().enumerate() {
            tree_joint_of[j.scene_joint] = Some(JointId(tj));
        }
        let (nq, nv) = (q0.len(), v0.len());
        let (inputs, n_inputs, prescribed) = input_layout(&scene, &joints, &tree_joint_of, nv);
        let loops = super::loops::cut_plans(&scene, &in_ref, &cluster_body);
        let (components, armature) = super::components::ComponentPlan::compile(
            &scene.components,
            &tree_joint_of,
            &joints,
            nv,
        );
        Plan {
            loops,
            components,
            armature,
            inputs,
            n_inputs,
            prescribed,
            bodies: bodies.into(),
            joints: joints.into(),
            objects: objects.into(),
            tree_joint_of,
            nq,
            nv,
            q0,
            v0,
            gravity: match scene.options.field() {
                GravityField::Uniform(g) => g,
                GravityField::None | GravityField::Point { .. } => Vector3::zeros(),
            },
            point_gravity: match scene.options.field() {
                GravityField::Point { mu, centre } => Some((mu, centre)),
                _ => None,
            },
            scene,
        }
    }

    /// The object with this name.
    pub(crate) fn object_index(&self, name: &str) -> Option<ObjectId> {
        self.objects
            .iter()
            .position(|o| o.name == name)
            .map(ObjectId)
    }

    /// The tree joint with this name.
    pub(crate) fn joint_index(&self, name: &str) -> Option<JointId> {
        self.joints.iter().position(|j| j.name == name).map(JointId)
    }

    /// The independent joint trees: for each body the index of its tree (one per root body,
    /// i.e. per body whose parent is the world), and the number of trees. `M(q)` is block
    /// diagonal over the trees, and the rows of one tree depend on another's state only through
    /// forces between them (spring-dampers, forces of other stages).
    pub(crate) fn trees(&self) -> (Vec<usize>, usize) {
        let mut tree = vec![0; self.bodies.len()];
        let mut n = 0;
        // Bodies come parents first, so a parent's tree is known when its children are reached.
        for (b, body) in self.bodies.iter().enumerate() {
            tree[b] = match body.parent {
                None => {
                    n += 1;
                    n - 1
                }
                Some(p) => tree[p.index()],
            };
        }
        (tree, n)
    }

    /// Velocity indices of each joint tree (see [`Plan::trees`]), ascending.
    pub(crate) fn velocity_groups(&self) -> Vec<Vec<usize>> {
        let (tree, n) = self.trees();
        let mut groups = vec![vec![]; n];
        for j in &self.joints {
            groups[tree[j.body.index()]].extend(j.v_offset..j.v_offset + j.coord.nv());
        }
        for g in &mut groups {
            g.sort_unstable();
        }
        groups
    }

    /// Initial state `y0 = [q0; v0]`.
    pub(crate) fn y0(&self) -> Vec<f64> {
        [self.q0.as_slice(), self.v0.as_slice()].concat()
    }
    /// Offset of the components' states in `y` (after `[q; v]` and the loops' multipliers).
    pub(crate) fn x_offset(&self) -> usize {
        self.nq + self.nv + 2 * self.loops.m()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::{Axis, Shape};
    use crate::scene::{
        ContactProfile, FreeRotation, Joint, JointKind, Object3D, SceneDesc, SceneOptions, Solid,
    };

    /// Whether the free joint of a body of `shape` alone on the world resolves its velocities
    /// in obj1, under `profile`.
    fn in_obj1(shape: Shape, profile: ContactProfile) -> bool {
        let options = SceneOptions {
            contact_profile: profile,
            ..SceneOptions::default()
        };
        let mut s = SceneDesc::new();
        s.add(Object3D::new("world").scene(options))
            .add(Object3D::new("body").solid(Solid::new(shape).material("DryWood").collision(true)))
            .add_joint(Joint::new(
                "free",
                "world",
                "body",
                JointKind::FreeMotion {
                    r: Vector3::new(0.0, 0.0, 1.0),
                    rot: FreeRotation::Cardan([0.1, 0.2, 0.3]),
                    v: Vector3::new(0.5, 0.0, 0.0),
                    w: Vector3::new(0.0, 3.0, 0.0),
                },
            ));
        let plan = Plan::compile(s.validated().expect("valid scene"));
        plan.joints[JointId(0)]
            .coord
            .free_velocities()
            .expect("a free joint")
    }

    /// Balls resolve their velocities in obj1 under every profile, cylinders only under the
    /// volume law (they roll on a line contact there, and rock on single points under the
    /// point laws, where obj1 lost: the comment in `Plan::compile`), boxes never.
    #[test]
    fn round_bodies_resolve_their_velocities_in_obj1() {
        let ball = || Shape::Sphere { diameter: 0.1 };
        let cylinder = || Shape::Cylinder {
            axis: Axis::Y,
            diameter: 0.1,
            length: 0.2,
        };
        let cube = || Shape::Box {
            lengths: Vector3::new(0.1, 0.1, 0.1),
        };
        for profile in [
            ContactProfile::Volume,
            ContactProfile::Paper2019,
            ContactProfile::Modia3DLater,
        ] {
            assert!(in_obj1(ball(), profile), "{profile:?}");
            assert_eq!(
                in_obj1(cylinder(), profile),
                profile == ContactProfile::Volume,
                "{profile:?}"
            );
            assert!(!in_obj1(cube(), profile), "{profile:?}");
        }
    }
}
