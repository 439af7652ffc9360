//! Scene stage, contact rules: which colliding solids can meet, and which of those lack a
//! contact-pair material. Solver-free: the contact preprocessing (`contact/preprocess.rs`)
//! builds its candidate pairs with [`CollisionFilter`], and the `model!` macro reports missing
//! pairs at compile time with [`missing_contact_pairs`] — one rule for both.
//! Touches only the validated scene.

use super::desc::SceneDesc;
use super::validate::{SceneError, ValidScene};

/// Which objects can collide with which (docs/contact-model.md §2.1, as in Modia3D): two solids meet unless they
/// are on one rigid body (parent links and `Fix` joints merge objects; everything attached to
/// the world is one body) or on the two bodies of a joint with `can_collide = false` that is a
/// mechanical connection (Revolute, Prismatic, Spherical, Universal, Cylindrical, Planar). A
/// FreeMotion is no mechanical connection: it never excludes a pair.
#[derive(Clone, Debug)]
pub(crate) struct CollisionFilter {
    /// Rigid body (a representative object index) of every object.
    body: Vec<usize>,
    /// Body pairs joined by a joint that forbids collisions, with the joint's index.
    excluded: Vec<(usize, usize, usize)>,
}

impl CollisionFilter {
    /// The filter of a validated scene.
    pub(crate) fn new(scene: &ValidScene) -> Self {
        // Rigid bodies = the topology's clusters (parent links and Fix joints merged).
        let body = scene.topology.cluster.clone();
        let excluded = scene
            .joints
            .iter()
            .enumerate()
            .filter(|(_, j)| {
                // A rigid joint's objects are one body already.
                j.kind.connects() && !j.kind.is_rigid() && !j.can_collide
            })
            .map(|(k, j)| (body[j.obj1], body[j.obj2], k))
            .collect();
        CollisionFilter { body, excluded }
    }

    /// Whether objects `a` and `b` (indices into `ValidScene::objects`) can touch.
    pub(crate) fn can_meet(&self, a: usize, b: usize) -> bool {
        self.body[a] != self.body[b] && self.excluded_by(a, b).is_none()
    }

    /// The joint (index into `ValidScene::joints`) with `can_collide = false` that keeps
    /// objects `a` and `b` apart, if any.
    pub(crate) fn excluded_by(&self, a: usize, b: usize) -> Option<usize> {
        let (ba, bb) = (self.body[a], self.body[b]);
        self.excluded
            .iter()
            .find(|&&(x, y, _)| (x, y) == (ba, bb) || (y, x) == (ba, bb))
            .map(|&(_, _, k)| k)
    }
}

/// The objects that take part in collision handling: collision solids with a shape, a contact
/// material and its elasticity (the others are validation errors), in declaration order; none
/// when the scene's `contact_detection` is off.
pub(crate) fn colliding_objects(scene: &ValidScene) -> Vec<usize> {
    if !scene.options.contact_detection {
        return vec![];
    }
    scene
        .objects
        .iter()
        .enumerate()
        .filter(|(_, o)| {
            o.solid.as_ref().is_some_and(|s| {
                s.collision
                    && s.shape.is_some()
                    && s.contact_material.is_some()
                    && s.contact_elasticity.is_some()
            })
        })
        .map(|(i, _)| i)
        .collect()
}

/// [`SceneError::MissingContactPair`] for every pair of contact materials that two colliding
/// solids which can meet ([`CollisionFilter`]) need and neither the scene nor the built-in
/// palette defines; once per material pair, naming the first two objects that need it (in
/// declaration order). A pair averaged from its self-pairs (`SceneOptions::average_missing_pairs`)
/// is not an error but is warned about here, once per material pair.
pub(super) fn missing_contact_pairs(scene: &ValidScene) -> Vec<SceneError> {
    let objects = colliding_objects(scene);
    let filter = CollisionFilter::new(scene);
    let material = |i: usize| {
        scene.objects[i]
            .solid
            .as_ref()
            .and_then(|s| s.contact_material.as_deref())
            .unwrap_or_default()
    };
    let mut seen: Vec<(&str, &str)> = vec![];
    let mut errors = vec![];
    for (k, &a) in objects.iter().enumerate() {
        for &b in &objects[k + 1..] {
            let (ma, mb) = (material(a), material(b));
            if !filter.can_meet(a, b) {
                continue;
            }
            let averaged = scene.averaged_contact_pair(ma, mb);
            if averaged.is_none() && scene.contact_pair(ma, mb).is_some() {
                continue;
            }
            let key = if ma <= mb { (ma, mb) } else { (mb, ma) };
            if seen.contains(&key) {
                continue;
            }
            seen.push(key);
            if let Some(m) = averaged {
                tracing::warn!(
                    "no contact-pair material for `{ma}` and `{mb}` (solids `{}` and `{}` can \
                     collide): using the mean of the self-pairs `{ma}|{ma}` and `{mb}|{mb}` \
                     (cor {}, mu_k {}, mu_r {}) because SceneOptions::average_missing_pairs is \
                     on; define the pair to silence this",
                    scene.objects[a].name,
                    scene.objects[b].name,
                    m.cor,
                    m.mu_k,
                    m.mu_r
                );
                continue;
            }
            errors.push(SceneError::MissingContactPair {
                material1: ma.to_string(),
                material2: mb.to_string(),
                object1: scene.objects[a].name.clone(),
                object2: scene.objects[b].name.clone(),
            });
        }
    }
    errors
}

impl SceneDesc {
    /// Every error [`SceneDesc::validate`] finds (missing contact pairs
    /// (`missing_contact_pairs`) and the topology included); empty for a valid scene. This is
    /// the check the `model!` macro runs on the literal part of a block at compile time;
    /// `build()` runs the same validation plus the plan's own checks.
    pub fn scene_errors(&self) -> Vec<SceneError> {
        match self.validated() {
            Err(e) => e.0,
            Ok(_) => vec![],
        }
    }
}
