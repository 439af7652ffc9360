//! Contact stage, preprocessing (docs/contact-model.md §2.1): once, when the plan is compiled, the collision
//! shapes, the candidate pairs (not rigidly attached, not joined by a joint with
//! `can_collide = false`) and each pair's material and geometry constants. Immutable.

use crate::dynamics::spatial::Transform;
use crate::dynamics::ObjectPlan;
use crate::geometry::{CollisionShape, NarrowPhaseOptions, Shape, ShapeKind};
use crate::scene::{CollisionFilter, ContactProfile, SceneError, ValidScene};

/// A collision shape of the plan.
#[derive(Clone, Debug)]
pub struct ShapePlan {
    /// Scene object index (the shape frame is the object frame).
    pub object: usize,
    /// Moving body it belongs to; `None` = fixed to the world.
    pub body: Option<usize>,
    /// The object frame placed in the body frame (or in world) \[m\].
    pub in_body: Transform,
    /// The shape, smoothed.
    pub shape: CollisionShape,
    /// Contact material name.
    pub contact_material: String,
    /// `c = E / (1 − ν²)` [N/m²].
    pub c: f64,
}

/// A candidate pair with its constants (fixed when the scene is compiled; the damping factor
/// is fixed when a contact starts).
#[derive(Clone, Debug)]
pub struct PairPlan {
    /// Shape index of object 1 (normal points from it to object 2).
    pub a: usize,
    /// Shape index of object 2.
    pub b: usize,
    /// Coefficient of restitution [-].
    pub cor: f64,
    /// Sliding friction coefficient [-].
    pub mu_k: f64,
    /// Rolling resistance coefficient [-].
    pub mu_r: f64,
    /// Regularisation velocity [m/s].
    pub v_min: f64,
    /// Regularisation angular velocity [rad/s].
    pub w_min: f64,
    /// `c_res = 1 / (1/c_1 + 1/c_2)` [N/m²].
    pub c_res: f64,
    /// `μ_geo` \[m\] (1 for two non-spheres in the 2019 profile).
    pub mu_geo: f64,
    /// `c_geo` [m^(1/2)] or 1.
    pub c_geo: f64,
    /// `n_geo` [-]: 3/2 (Hertz) or 1.
    pub n_geo: f64,
}

/// The compiled collision pipeline of a scene with at least one candidate pair.
#[derive(Clone, Debug)]
pub struct ContactPlan {
    /// Collision shapes.
    pub shapes: Vec<ShapePlan>,
    /// Candidate pairs.
    pub pairs: Vec<PairPlan>,
    /// Elastic contact reduction factor [-].
    pub k_red: f64,
    /// Damping bound [s/m].
    pub d_max: f64,
    /// `cor` of very slow impacts [-].
    pub cor_min: f64,
    /// Hysteresis ε \[m\].
    pub hysteresis: f64,
    /// Contact law variant.
    pub profile: ContactProfile,
    /// Damping from the exact restitution relation (`SceneOptions::exact_restitution`).
    pub exact_restitution: bool,
    /// Narrow-phase options.
    pub narrow: NarrowPhaseOptions,
    /// Candidate pair index of each shape pair `(a, b)`, `a < b` (the broad phase's filter).
    pub pair_of: std::collections::HashMap<(u32, u32), u32>,
    /// Broad-phase margin \[m\]: pairs whose AABBs are more than this apart on some axis are not
    /// looked at; their `z_AB` counts as `margin` (a positive constant), which keeps `z_2`
    /// continuous (`docs/contact-model.md` §2.2: far fewer than n² box tests).
    pub margin: f64,
    /// The largest step that keeps every passage through a contact visible (tunnelling).
    pub step_guard: super::step_guard::StepGuard,
}

impl ContactPlan {
    /// Display name of pair `p`: `"<object a>|<object b>"` (the owner part of its signals).
    pub fn pair_name(&self, scene: &ValidScene, p: usize) -> String {
        let pp = &self.pairs[p];
        format!(
            "{}|{}",
            scene.objects[self.shapes[pp.a].object].name,
            scene.objects[self.shapes[pp.b].object].name
        )
    }

    /// Compiles the pipeline; `Ok(None)` when collision handling is off or there is no
    /// candidate pair. Errors: shapes that cannot be smoothed (missing contact-pair materials
    /// are validation errors).
    pub(crate) fn compile(
        scene: &ValidScene,
        objects: &[ObjectPlan],
    ) -> Result<Option<ContactPlan>, Vec<SceneError>> {
        let opts = &scene.options;
        if !opts.contact_detection {
            return Ok(None);
        }
        let mut errors = vec![];
        let mut shapes = vec![];
        for (i, o) in scene.objects.iter().enumerate() {
            let Some(s) = &o.solid else { continue };
            if !s.collision {
                continue;
            }
            let (Some(shape), Some(cm), Some(el)) =
                (&s.shape, &s.contact_material, &s.contact_elasticity)
            else {
                continue; // reported by validation
            };
            let r = s.smoothing_radius.unwrap_or(opts.smoothing_radius);
            let cs = match CollisionShape::with_smoothing(shape, r) {
                Ok(cs) => cs,
                Err(e) => {
                    errors.push(SceneError::InvalidValue {
                        what: format!("object `{}`: collision shape ({e})", o.name),
                        value: r,
                        expected: "a shape that can be smoothed with this radius",
                    });
                    continue;
                }
            };
            shapes.push(ShapePlan {
                object: i,
                body: objects[i].body,
                in_body: objects[i].in_body,
                shape: cs,
                contact_material: cm.clone(),
                c: el.young_modulus / (1.0 - el.poisson_ratio * el.poisson_ratio),
            });
        }
        // Which solids can meet: the scene's contact rules (`scene/contact_rules.rs`), which
        // validation also uses to report pairs without a material.
        let filter = CollisionFilter::new(scene);
        let mut pairs = vec![];
        for a in 0..shapes.len() {
            for b in a + 1..shapes.len() {
                let (sa, sb) = (&shapes[a], &shapes[b]);
                if !filter.can_meet(sa.object, sb.object) {
                    continue;
                }
                let Some(m) = scene.contact_pair(&sa.contact_material, &sb.contact_material) else {
                    continue; // a validation error (`missing_contact_pairs`)
                };
                // Keep a sphere first: μ_geo = r1 for sphere–other.
                let (a, b) = if sb.shape.kind() == ShapeKind::Sphere
                    && sa.shape.kind() != ShapeKind::Sphere
                {
                    (b, a)
                } else {
                    (a, b)
                };
                let (sa, sb) = (&shapes[a], &shapes[b]);
                let (mu_geo, c_geo, n_geo) =
                    geometry_coefficients(opts.contact_profile, scene, sa, sb);
                pairs.push(PairPlan {
                    a,
                    b,
                    cor: m.cor,
                    mu_k: m.mu_k,
                    mu_r: m.mu_r,
                    v_min: m.v_min.unwrap_or(opts.v_min),
                    w_min: m.w_min.unwrap_or(opts.w_min),
                    c_res: 1.0 / (1.0 / sa.c + 1.0 / sb.c),
                    mu_geo,
                    c_geo,
                    n_geo,
                });
            }
        }
        if !errors.is_empty() {
            return Err(errors);
        }
        if pairs.is_empty() {
            return Ok(None);
        }
        let pair_of = pairs
            .iter()
            .enumerate()
            .map(|(p, pp)| {
                let (a, b) = (pp.a.min(pp.b) as u32, pp.a.max(pp.b) as u32);
                ((a, b), p as u32)
            })
            .collect();
        // Half the smallest bounding radius: small enough that the broad phase prunes, any
        // positive value gives the same events.
        let margin = 0.5
            * shapes
                .iter()
                .map(|s| s.shape.bounding_radius())
                .fold(f64::INFINITY, f64::min);
        Ok(Some(ContactPlan {
            step_guard: super::step_guard::StepGuard::new(&shapes, &pairs),
            pair_of,
            margin,
            shapes,
            pairs,
            k_red: opts.k_red,
            d_max: opts.d_max,
            cor_min: opts.cor_min,
            hysteresis: opts.hysteresis,
            profile: opts.contact_profile,
            exact_restitution: opts.exact_restitution,
            narrow: NarrowPhaseOptions {
                mpr_tolerance: opts.mpr_tolerance,
                max_iterations: opts.mpr_max_iterations,
                ..Default::default()
            },
        }))
    }
}

/// The user shape of a shape plan.
fn user_shape<'a>(scene: &'a ValidScene, s: &ShapePlan) -> &'a Shape {
    scene.objects[s.object]
        .solid
        .as_ref()
        .and_then(|x| x.shape.as_ref())
        .expect("collision shapes come from solids with a shape")
}

/// `(μ_geo, c_geo, n_geo)` of a pair (docs/contact-model.md §3 table; later profile: Hertz for every pair).
fn geometry_coefficients(
    profile: ContactProfile,
    scene: &ValidScene,
    a: &ShapePlan,
    b: &ShapePlan,
) -> (f64, f64, f64) {
    let (sa, sb) = (user_shape(scene, a), user_shape(scene, b));
    match profile {
        ContactProfile::Paper2019 => match (sa, sb) {
            (Shape::Sphere { diameter: d1 }, Shape::Sphere { diameter: d2 }) => {
                let mu = 1.0 / (2.0 / d1 + 2.0 / d2);
                (mu, 4.0 / 3.0 * mu.sqrt(), 1.5)
            }
            (Shape::Sphere { diameter }, _) | (_, Shape::Sphere { diameter }) => {
                let r = 0.5 * diameter;
                (r, 4.0 / 3.0 * r.sqrt(), 1.5)
            }
            _ => (1.0, 1.0, 1.0),
        },
        ContactProfile::Modia3DLater => {
            let (ra, fa) = contact_radius(sa);
            let (rb, fb) = contact_radius(sb);
            let curvature = if fa { 0.0 } else { 1.0 / ra } + if fb { 0.0 } else { 1.0 / rb };
            let mu = if curvature > 0.0 {
                1.0 / curvature
            } else {
                1.0 / (1.0 / ra + 1.0 / rb)
            };
            (mu, 4.0 / 3.0 * mu.sqrt(), 1.5)
        }
    }
}

/// Contact radius \[m\] of a shape in the later Modia3D profile and whether it counts as flat.
fn contact_radius(s: &Shape) -> (f64, bool) {
    match s {
        Shape::Sphere { diameter } | Shape::Capsule { diameter, .. } => (0.5 * diameter, false),
        Shape::Box { lengths } => (0.5 * lengths.min(), true),
        Shape::Cylinder {
            diameter, length, ..
        } => (0.5 * diameter.min(*length), false),
        Shape::Cone {
            diameter,
            top_diameter,
            ..
        } => (0.25 * (diameter + top_diameter), false),
        Shape::Ellipsoid { lengths } => (0.5 * lengths.min(), false),
        Shape::ConvexHull { .. } => {
            let w = s
                .unit_mass_properties()
                .map(|u| u.volume.cbrt())
                .unwrap_or(1.0);
            (0.5 * w, true)
        }
    }
}
