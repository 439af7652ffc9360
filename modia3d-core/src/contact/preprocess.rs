//! Contact stage, preprocessing (docs/contact-model.md §2.1): once, when the plan is compiled, the collision
//! shapes and the rules that make two of them a candidate pair (not rigidly attached, not
//! joined by a joint with `can_collide = false`), with the material constants per pair of
//! contact materials. Immutable. The candidate pairs themselves are not stored (there are
//! N²/2 of them): [`ContactPlan::pair`] gives a pair and its constants on demand, for the
//! pairs the broad phase reports; [`ContactPlan::candidate_pairs`] enumerates them all (build
//! time and result queries only).

use crate::dynamics::plan::BodyPlan;
use crate::dynamics::{BodyId, IdVec, ObjectPlan};
use crate::geometry::overlap::{Frustum, OverlapScratch, Polytope};
use crate::geometry::{CollisionShape, MeshCollision, NarrowPhaseOptions, Shape, VolumeLaw};
use crate::scene::{CollisionFilter, ContactProfile, SceneError, ValidScene};
use crate::spatial::Transform;

/// A collision shape of the plan.
#[derive(Clone, Debug)]
pub(crate) struct ShapePlan {
    /// Scene object index (the shape frame is the object frame).
    pub object: usize,
    /// Index of this convex part of a decomposed mesh (`None` for every other shape): the
    /// pair names call it `<object>#<part>`.
    pub part: Option<usize>,
    /// Moving body it belongs to; `None` = fixed to the world.
    pub body: Option<BodyId>,
    /// The object frame placed in the body frame (or in world) \[m\].
    pub in_body: Transform,
    /// The shape, smoothed.
    pub shape: CollisionShape,
    /// Contact material name.
    pub contact_material: String,
    /// Index of the contact material in the plan's material table.
    material: usize,
    /// What the pair's geometry coefficients need of the user shape.
    geo: ShapeGeo,
    /// `c = E / (1 − ν²)` [N/m²].
    pub c: f64,
    /// The shape is a sphere: a point core at the shape frame's origin swept by its radius, so
    /// its geometry depends on the frame's position only (`contact_set.rs` places it without
    /// its rotation).
    pub round: bool,
    /// What the volume law needs of the shape ([`ContactProfile::Volume`]; boxes, hulls, mesh
    /// parts, beams, cylinders and cones), `None` otherwise.
    pub volume: Option<VolumeShape>,
    /// Mass \[kg\] of the body the shape is on (infinite for a shape fixed to the world): the
    /// volume law's resting damping (docs/contact-model.md §3.2).
    pub body_mass: f64,
}

/// A shape as the volume law sees it (docs/contact-model.md §3.2): sharp (not smoothed), with
/// its elastic layer.
#[derive(Clone, Debug)]
pub(crate) struct VolumeShape {
    /// The shape without smoothing: the signed distance (root functions) and bounding box of
    /// its volume pairs, so that the force is zero exactly where the distance is ≥ 0.
    pub sharp: CollisionShape,
    /// The solid whose overlap is integrated.
    pub solid: VolumeSolid,
    /// Stiffness per unit volume `κ_i = c_i / H_i` \[N/m³\] (`c_i = E/(1 − ν²)`, `H_i` the layer
    /// depth).
    pub kappa: f64,
    /// The shape takes part in at least one volume pair (else its bounding box stays that of
    /// the smoothed shape, and scenes without volume pairs keep their numbers bit for bit).
    pub in_volume_pair: bool,
}

/// The solid of a [`VolumeShape`].
#[derive(Clone, Debug)]
pub(crate) enum VolumeSolid {
    /// A box, convex hull, convex part of a mesh, or a beam (its rounded ends as inscribed
    /// polygons: `geometry::overlap::polytope::beam_points`).
    Polytope(Polytope),
    /// A cylinder or cone.
    Frustum(Frustum),
}

/// Which force law a pair has (docs/contact-model.md §3).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum PairLaw {
    /// The paper's single-point law (Hertz or linear, by `n_geo`) on the smoothed shapes.
    Point,
    /// The volume law for two polytopes.
    Polytopes,
    /// The volume law for a cylinder or cone (shape a if `frustum_is_a`, else shape b) on a
    /// face of a polytope.
    FrustumOnFace {
        /// Shape a is the frustum.
        frustum_is_a: bool,
    },
}

/// What the geometry coefficients of a pair (docs/contact-model.md §3) need of a user shape.
#[derive(Clone, Copy, Debug)]
struct ShapeGeo {
    /// Diameter \[m\] of a sphere, `None` for other shapes.
    sphere_diameter: Option<f64>,
    /// Contact radius \[m\] in the later Modia3D profile.
    radius: f64,
    /// The shape counts as flat in the later profile.
    flat: bool,
}

/// A candidate pair with its constants (from the plan, on demand: [`ContactPlan::pair`]; the
/// damping factor is fixed when a contact starts).
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct PairPlan {
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
    /// Regularisation velocity [m/s] of the `cor` blend, the resting damping's window and
    /// (point laws) friction.
    pub v_min: f64,
    /// Regularisation velocity [m/s] of sliding and spin friction: `v_min` for point laws, the
    /// pair material's `v_min` or the scene's `v_min_volume` for the volume law.
    pub v_slip: f64,
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
    /// The force law.
    pub law: PairLaw,
    /// Volume law: `κ = κ_a κ_b / (κ_a + κ_b)` \[N/m³\] (0 for point laws).
    pub kappa: f64,
}

/// The compiled collision pipeline of a scene with at least one candidate pair.
#[derive(Clone, Debug)]
pub(crate) struct ContactPlan {
    /// Collision shapes.
    pub shapes: Vec<ShapePlan>,
    /// Number of candidate pairs (they are enumerated by [`Self::candidate_pairs`]).
    pub n_pairs: usize,
    /// `row_start[a]`: number of candidate pairs `(a', b)` with `a' < a` (len: shapes + 1),
    /// so that a pair's id (its index in [`Self::candidate_pairs`]) costs one row scan.
    row_start: Vec<usize>,
    /// Which objects can meet (rigid clusters, joints with `can_collide = false`).
    filter: CollisionFilter,
    /// The pair material of contact materials `i` and `j` at `i · n_materials + j` (`None`: a
    /// validation error, never in a compiled plan).
    materials: Vec<Option<PairMaterial>>,
    /// Number of distinct contact materials.
    n_materials: usize,
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
    /// Shapes on moving bodies (the others' poses and boxes are computed once, in
    /// `ContactState::new`).
    pub moving: Vec<usize>,
    /// Broad-phase margin \[m\]: pairs whose AABBs are more than this apart on some axis are not
    /// looked at; their `z_AB` counts as `margin` (a positive constant), which keeps `z_2`
    /// continuous (`docs/contact-model.md` §2.2: far fewer than n² box tests).
    pub margin: f64,
    /// The weight of the scene's moving bodies, `|g|·Σ m` \[N\]: a bound on the normal force
    /// a resting contact carries, for the floor of [`SLIP_TIME_CONSTANT`].
    pub scene_weight: f64,
}

/// Shortest time constant \[s\] of the volume law's regularised friction as a damper on the
/// lighter body of a pair, `m·v_slip/(3 μ_k f_n)`, with `f_n` up to the weight of the whole
/// scene ([`ContactPlan::scene_weight`]): a pair whose material sets no `v_min` regularises
/// its friction at `max(v_min_volume, 3 μ_k·W·τ/m)`, at most [`SLIP_FLOOR_CAP`]` · v_min_volume`
/// and the scene's `v_min`. Why: below `v_slip` the friction is a stiff viscous law that
/// Newton's method crosses only in steps of a few of its time constants (the `StiffFriction`
/// diagnosis). A light body pressed at 9.2 N had 8e-8 s with `v_slip` = 1e-3 m/s and ended
/// its run; with 1e-4, 8e-9 s, and its run stalled at 1e-9 s steps (random scene
/// 0x5106701ba2d5f142, `tests/regressions/light_body_under_heavy_load.json`; BENCHMARKS.md
/// "Friction regularised at 1e-4 m/s"). Bodies of similar masses reach the floor only in
/// scenes of ~40 of them: the benchmark and test scenes keep `v_min_volume` exactly.
pub(crate) const SLIP_TIME_CONSTANT: f64 = 1e-7;

/// The floor of [`SLIP_TIME_CONSTANT`] raises `v_slip` to at most this multiple of
/// `v_min_volume` (1e-3 m/s by default, the value before 1e-4): with the scene's `v_min`
/// (0.01 m/s) as the only cap, 4 random scenes that had ended in 0.2–8 s at 1e-3 reached the
/// 20 s budget.
pub(crate) const SLIP_FLOOR_CAP: f64 = 10.0;

/// The constants of a pair of contact materials, the scene's defaults filled in.
#[derive(Clone, Copy, Debug)]
struct PairMaterial {
    cor: f64,
    mu_k: f64,
    mu_r: f64,
    v_min: f64,
    /// The volume law's friction regularisation (the pair's own `v_min`, else the scene's
    /// `v_min_volume`).
    v_slip_volume: f64,
    /// Whether `v_slip_volume` is the scene's (the pair sets no `v_min`): only then does the
    /// floor of [`SLIP_TIME_CONSTANT`] apply.
    slip_floor: bool,
    w_min: f64,
}

impl ContactPlan {
    /// Whether the scene can have a pair under the volume law: a shape on a moving body and
    /// another shape with the volume law's form (`ContactProfile::Volume`; boxes, beams,
    /// hulls, mesh parts, cylinders, cones). Sufficient for the run's settings that such
    /// pairs need (`simulation.rs`, `ida_options`), not a promise that two of them meet.
    pub(crate) fn has_volume_law(&self) -> bool {
        let mut volumes = self.shapes.iter().filter(|s| s.volume.is_some());
        let n = volumes.clone().count();
        n >= 2 && volumes.any(|s| s.body.is_some())
    }

    /// The narrow phase's stopping length \[m\] for shapes `a` and `b`: `mpr_tolerance` times
    /// the sum of their bounding radii (`geometry/narrow_phase/mod.rs`), the precision to
    /// which their signed distance is known.
    pub(crate) fn stopping_length(&self, a: usize, b: usize) -> f64 {
        self.narrow.mpr_tolerance
            * (self.shapes[a].shape.bounding_radius() + self.shapes[b].shape.bounding_radius())
    }

    /// Display name of pair `pp`: `"<object a>|<object b>"` (the owner part of its signals).
    pub(crate) fn pair_name(&self, scene: &ValidScene, pp: &PairPlan) -> String {
        format!(
            "{}|{}",
            self.shape_name(scene, pp.a),
            self.shape_name(scene, pp.b)
        )
    }

    /// Display name of shape `s`: its object's name, `"<object>#<k>"` for part `k` of a
    /// decomposed mesh (the halves of [`Self::pair_name`]).
    pub(crate) fn shape_name(&self, scene: &ValidScene, s: usize) -> String {
        let sp = &self.shapes[s];
        let o = &scene.objects[sp.object].name;
        match sp.part {
            Some(k) => format!("{o}#{k}"),
            None => o.clone(),
        }
    }

    /// Compiles the pipeline; `Ok(None)` when collision handling is off or there is no
    /// candidate pair. Errors: shapes that cannot be smoothed (missing contact-pair materials
    /// are validation errors).
    pub(crate) fn compile(
        scene: &ValidScene,
        objects: &[ObjectPlan],
        bodies: &IdVec<BodyId, BodyPlan>,
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
            // One collision shape per convex part (a decomposed mesh has several, all on the
            // same body, so they never pair with each other).
            let decomposed = matches!(
                shape,
                Shape::Mesh {
                    collision: MeshCollision::ConvexDecomposition,
                    ..
                }
            );
            for (k, shape) in shape.collision_parts().iter().enumerate() {
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
                let c = el.young_modulus / (1.0 - el.poisson_ratio * el.poisson_ratio);
                let volume = if opts.contact_profile == ContactProfile::Volume {
                    match volume_shape(shape, s.layer_depth, c) {
                        Ok(v) => v,
                        Err(e) => {
                            errors.push(SceneError::InvalidValue {
                                what: format!("object `{}`: collision shape ({e})", o.name),
                                value: f64::NAN,
                                expected: "a shape with a volume (not flat)",
                            });
                            continue;
                        }
                    }
                } else {
                    None
                };
                shapes.push(ShapePlan {
                    object: i,
                    volume,
                    body_mass: objects[i]
                        .body
                        .map_or(f64::INFINITY, |b| bodies[b].inertia.mass),
                    part: decomposed.then_some(k),
                    body: objects[i].body,
                    in_body: objects[i].in_body,
                    shape: cs,
                    contact_material: cm.clone(),
                    c,
                    round: shape.ball_diameter().is_some(),
                    material: 0, // set below
                    geo: {
                        let (radius, flat) = shape.contact_radius();
                        let sphere_diameter = shape.ball_diameter();
                        ShapeGeo {
                            sphere_diameter,
                            radius,
                            flat,
                        }
                    },
                });
            }
        }
        // Which solids can meet: the scene's contact rules (`scene/contact_rules.rs`), which
        // validation also uses to report pairs without a material.
        let filter = CollisionFilter::new(scene);
        // One entry per pair of contact materials (a handful), not per pair of shapes.
        let mut names: Vec<&str> = vec![];
        for sp in &mut shapes {
            sp.material = match names.iter().position(|n| *n == sp.contact_material) {
                Some(k) => k,
                None => {
                    names.push(&sp.contact_material);
                    names.len() - 1
                }
            };
        }
        let n_materials = names.len();
        let mut materials = Vec::with_capacity(n_materials * n_materials);
        for a in &names {
            for b in &names {
                materials.push(scene.contact_pair(a, b).map(|m| PairMaterial {
                    cor: m.cor,
                    mu_k: m.mu_k,
                    mu_r: m.mu_r,
                    v_min: m.v_min.unwrap_or(opts.v_min),
                    v_slip_volume: m.v_min.unwrap_or(opts.v_min_volume),
                    slip_floor: m.v_min.is_none(),
                    w_min: m.w_min.unwrap_or(opts.w_min),
                }));
            }
        }
        if !errors.is_empty() {
            return Err(errors);
        }
        // Half the smallest bounding radius: small enough that the broad phase prunes, any
        // positive value gives the same events.
        let margin = 0.5
            * shapes
                .iter()
                .map(|s| s.shape.bounding_radius())
                .fold(f64::INFINITY, f64::min);
        let moving = (0..shapes.len())
            .filter(|&s| shapes[s].body.is_some())
            .collect();
        let scene_weight = opts.gravity.norm() * bodies.iter().map(|b| b.inertia.mass).sum::<f64>();
        let mut cp = ContactPlan {
            moving,
            margin,
            scene_weight,
            shapes,
            n_pairs: 0,
            row_start: vec![],
            filter,
            materials,
            n_materials,
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
        };
        // Counting is O(N²) in time (a few ns per shape pair); one number per shape is stored.
        let n = cp.shapes.len();
        let mut row_start = Vec::with_capacity(n + 1);
        let mut count = 0;
        for a in 0..n {
            row_start.push(count);
            count += (a + 1..n).filter(|&b| cp.can_meet(a, b)).count();
        }
        row_start.push(count);
        cp.row_start = row_start;
        cp.n_pairs = count;
        // Which shapes are in a volume pair (O(n²) over the volume shapes, at build time).
        let vol: Vec<usize> = (0..n).filter(|&s| cp.shapes[s].volume.is_some()).collect();
        for (i, &a) in vol.iter().enumerate() {
            for &b in &vol[i + 1..] {
                if cp.can_meet(a, b) && volume_law(&cp.shapes[a], &cp.shapes[b]).is_some() {
                    for s in [a, b] {
                        if let Some(v) = cp.shapes[s].volume.as_mut() {
                            v.in_volume_pair = true;
                        }
                    }
                }
            }
        }
        if cp.n_pairs == 0 {
            return Ok(None);
        }
        Ok(Some(cp))
    }

    /// Whether shapes `a` and `b` form a candidate pair (either order; the broad phase's
    /// filter): on bodies that can meet, with a pair material. O(1) for scenes without
    /// joints that forbid collisions.
    #[inline]
    pub(crate) fn can_meet(&self, a: usize, b: usize) -> bool {
        let (sa, sb) = (&self.shapes[a], &self.shapes[b]);
        a != b
            && self.materials[sa.material * self.n_materials + sb.material].is_some()
            && self.filter.can_meet(sa.object, sb.object)
    }

    /// Candidate pair of shapes `a` and `b` (either order) with its constants, `None` if they
    /// cannot meet. A sphere comes first (`μ_geo = r_1` for sphere–other), else the lower
    /// shape index. A few flops: called when the broad phase first reports a pair.
    pub(crate) fn pair(&self, a: usize, b: usize) -> Option<PairPlan> {
        if !self.can_meet(a, b) {
            return None;
        }
        let (a, b) = (a.min(b), a.max(b));
        let (a, b) = if self.shapes[b].round && !self.shapes[a].round {
            (b, a)
        } else {
            (a, b)
        };
        let (sa, sb) = (&self.shapes[a], &self.shapes[b]);
        let m = self.materials[sa.material * self.n_materials + sb.material]?;
        let (law, kappa) = match volume_law(sa, sb) {
            Some(law) => {
                let (ka, kb) = (
                    sa.volume.as_ref().map_or(0.0, |v| v.kappa),
                    sb.volume.as_ref().map_or(0.0, |v| v.kappa),
                );
                (law, ka * kb / (ka + kb))
            }
            None => (PairLaw::Point, 0.0),
        };
        let (mu_geo, c_geo, n_geo) = geometry_coefficients(self.profile, &sa.geo, &sb.geo);
        Some(PairPlan {
            law,
            kappa,
            a,
            b,
            cor: m.cor,
            mu_k: m.mu_k,
            mu_r: m.mu_r,
            v_min: m.v_min,
            v_slip: match law {
                PairLaw::Point => m.v_min,
                _ if m.slip_floor => {
                    let light = sa.body_mass.min(sb.body_mass);
                    let floor = 3.0 * m.mu_k * self.scene_weight * SLIP_TIME_CONSTANT / light;
                    m.v_slip_volume
                        .max(floor.min(SLIP_FLOOR_CAP * m.v_slip_volume).min(m.v_min))
                }
                _ => m.v_slip_volume,
            },
            w_min: m.w_min,
            c_res: 1.0 / (1.0 / sa.c + 1.0 / sb.c),
            mu_geo,
            c_geo,
            n_geo,
        })
    }

    /// Id of the candidate pair of shapes `a`, `b` (either order): its index in
    /// [`Self::candidate_pairs`] (the order of the contact signals); `None` if they cannot
    /// meet. O(|a − b|): for events and results, not the root functions.
    pub(crate) fn pair_id(&self, a: usize, b: usize) -> Option<usize> {
        if !self.can_meet(a, b) {
            return None;
        }
        let (lo, hi) = (a.min(b), a.max(b));
        Some(self.row_start[lo] + (lo + 1..hi).filter(|&c| self.can_meet(lo, c)).count())
    }

    /// The candidate pair with id `id` (see [`Self::pair_id`]), `None` for `id ≥ n_pairs`.
    /// O(log N + N).
    pub(crate) fn pair_by_id(&self, id: usize) -> Option<PairPlan> {
        if id >= self.n_pairs {
            return None;
        }
        let a = self.row_start.partition_point(|&r| r <= id) - 1;
        let k = id - self.row_start[a];
        let b = (a + 1..self.shapes.len())
            .filter(|&b| self.can_meet(a, b))
            .nth(k)?;
        self.pair(a, b)
    }

    /// All candidate pairs, shape pairs in lexicographic order of their lower and higher
    /// index (the order of the contact signals). O(N²) in time; for build-time checks and
    /// result queries, never the simulation.
    pub(crate) fn candidate_pairs(&self) -> impl Iterator<Item = PairPlan> + '_ {
        let n = self.shapes.len();
        (0..n).flat_map(move |a| (a + 1..n).filter_map(move |b| self.pair(a, b)))
    }
}
/// The volume law of shapes `a` and `b` (in this order), `None` where the pair has a point law:
/// two polytopes, or a frustum and a polytope (docs/contact-model.md §3.2).
fn volume_law(a: &ShapePlan, b: &ShapePlan) -> Option<PairLaw> {
    use VolumeSolid::{Frustum as F, Polytope as P};
    match (&a.volume.as_ref()?.solid, &b.volume.as_ref()?.solid) {
        (P(_), P(_)) => Some(PairLaw::Polytopes),
        (F(_), P(_)) => Some(PairLaw::FrustumOnFace { frustum_is_a: true }),
        (P(_), F(_)) => Some(PairLaw::FrustumOnFace {
            frustum_is_a: false,
        }),
        (F(_), F(_)) => None,
    }
}

/// The volume law's view of `shape` with stiffness `c = E/(1 − ν²)` \[N/m²\] and the solid's
/// layer depth `layer_depth` \[m\] (`None`: the shape's own): `Ok(None)` for shapes that keep a
/// point law (spheres, capsules, ellipsoids); an error for a degenerate hull.
fn volume_shape(
    shape: &Shape,
    layer_depth: Option<f64>,
    c: f64,
) -> Result<Option<VolumeShape>, crate::geometry::GeometryError> {
    // The kind's solid (`geometry/kinds/<kind>.rs`, `volume_solid`).
    let (solid, own_depth, inscribed) = match shape.volume_solid()? {
        VolumeLaw::Polytope {
            polytope,
            inscribed,
        } => {
            let h = polytope.layer_depth();
            (VolumeSolid::Polytope(polytope), h, inscribed)
        }
        VolumeLaw::Frustum(f) => (VolumeSolid::Frustum(f), f.layer_depth(), false),
        VolumeLaw::None => return Ok(None),
    };
    let h = layer_depth.unwrap_or(own_depth);
    // A polytope inscribed in the shape (a beam's, rounded ends as polygons) is the volume: its
    // signed distance must be of the same solid, so that the force is zero at both events.
    let exact = || CollisionShape::with_smoothing(shape, 0.0);
    let sharp = if inscribed {
        match &solid {
            VolumeSolid::Polytope(p) => CollisionShape::with_smoothing(
                &Shape::ConvexHull {
                    points: p.vertices().to_vec(),
                },
                0.0,
            )?,
            VolumeSolid::Frustum(_) => exact()?,
        }
    } else {
        exact()?
    };
    Ok(Some(VolumeShape {
        sharp,
        solid,
        kappa: c / h,
        in_volume_pair: false,
    }))
}

impl ContactPlan {
    /// Scratch buffers of the polytope overlaps of this plan, sized for its largest polytopes
    /// (so that the residual allocates nothing).
    pub(crate) fn overlap_scratch(&self) -> OverlapScratch {
        let mut scratch = OverlapScratch::default();
        let largest = self
            .shapes
            .iter()
            .filter_map(|s| match s.volume.as_ref().map(|v| &v.solid) {
                Some(VolumeSolid::Polytope(p)) => Some(p),
                _ => None,
            })
            .max_by_key(|p| p.vertices().len());
        if let Some(p) = largest {
            scratch.reserve_for(p, p);
        }
        scratch
    }
}

/// `(μ_geo, c_geo, n_geo)` of a pair (docs/contact-model.md §3 table; later profile: Hertz for
/// every pair; the volume profile: the paper's for pairs with a sphere and, for the pairs
/// without a sphere that keep a point law (capsules, ellipsoids, two cylinders or cones), the
/// later profile's Hertz: the paper's linear law has its full stiffness from the first
/// nanometre, and such a pair collapsed the steps at its touch).
fn geometry_coefficients(profile: ContactProfile, a: &ShapeGeo, b: &ShapeGeo) -> (f64, f64, f64) {
    let hertz_by_curvature = || {
        let (ra, fa) = (a.radius, a.flat);
        let (rb, fb) = (b.radius, b.flat);
        let curvature = if fa { 0.0 } else { 1.0 / ra } + if fb { 0.0 } else { 1.0 / rb };
        let mu = if curvature > 0.0 {
            1.0 / curvature
        } else {
            1.0 / (1.0 / ra + 1.0 / rb)
        };
        (mu, 4.0 / 3.0 * mu.sqrt(), 1.5)
    };
    match profile {
        ContactProfile::Paper2019 | ContactProfile::Volume => {
            match (a.sphere_diameter, b.sphere_diameter) {
                (Some(d1), Some(d2)) => {
                    let mu = 1.0 / (2.0 / d1 + 2.0 / d2);
                    (mu, 4.0 / 3.0 * mu.sqrt(), 1.5)
                }
                (Some(diameter), None) | (None, Some(diameter)) => {
                    let r = 0.5 * diameter;
                    (r, 4.0 / 3.0 * r.sqrt(), 1.5)
                }
                (None, None) if profile == ContactProfile::Volume => hertz_by_curvature(),
                (None, None) => (1.0, 1.0, 1.0),
            }
        }
        ContactProfile::Modia3DLater => hertz_by_curvature(),
    }
}
