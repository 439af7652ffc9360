//! Contact stage: the contact set (the paper's `contactDict`) and the zero-crossing functions
//! (docs/contact-model.md §4). `(&ContactPlan, &mut ContactState)` plus the dynamics workspace (read-only poses
//! and velocities; contact forces are added to `ws.f_ext`).
//!
//! Only pairs the broad phase reports near (and pairs in the contact set) have a state: a slot
//! with the pair's constants ([`ContactPlan::pair`], computed when the pair is first reported)
//! and its [`PairState`], found by shape pair through a map with a fast hasher in root
//! evaluations and by slot index in the residual. Memory is linear in the number of shapes
//! and near pairs, not in the N²/2 candidate pairs. No allocation once the slot pool and the
//! map have grown to the largest near set (the warm-up).

use super::preprocess::{ContactPlan, PairLaw, PairPlan, VolumeSolid};
use super::regularise::{cor_reg, damping_factor, damping_factor_exact};
use super::response::{
    pair_response, resting_damping, volume_response, PairResponse, VolumeGeometry,
};
use crate::dynamics::forces::{add_world_wrench, world_wrench_in_body};
use crate::dynamics::kinematics::point_velocity;
use crate::dynamics::{Plan, Workspace};
use crate::geometry::narrow_phase::Method;
use crate::geometry::overlap::{
    frustum_planes_gap, frustum_planes_overlap, polytope_overlap, Overlap, OverlapScratch,
};
use crate::geometry::BroadPhase;
use crate::geometry::CollisionShape;
use crate::geometry::{
    aabb_distance, contact_patch, signed_distance_method, world_aabb, ContactPatch, GeometryError,
    SignedDistance,
};
use crate::spatial::Force;
use crate::spatial::Transform;
use nalgebra::{Isometry3, Point3, Rotation3, Translation3, UnitQuaternion, Vector3};
use parry3d_f64::bounding_volume::BoundingVolume;

/// How the collision stage is evaluated (docs/contact-model.md §4).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Mode {
    /// At an event: all `z_AB`, rebuild the contact set, store `δ̇⁻` of new contacts.
    Event,
    /// IDA asks for root values: all `z_AB`, the set is kept.
    ZeroCrossing,
    /// Residual and output points: pairs in the set only, forces applied.
    Continuous,
}

/// The narrow phase failed for a pair.
#[derive(thiserror::Error, Debug, Clone, PartialEq)]
#[error("collision of `{pair}` at t = {t} s: {source}; check the shapes' dimensions and poses")]
pub struct ContactError {
    /// Pair name `"a|b"`.
    pub pair: String,
    /// Time \[s\].
    pub t: f64,
    /// The geometry error.
    pub source: GeometryError,
}

/// Mutable state of one candidate pair.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct PairState {
    /// Member of the contact set.
    pub in_contact: bool,
    /// Last `z_AB` \[m\] (AABB distance while the boxes are apart, signed distance otherwise).
    pub z: f64,
    /// Penetration velocity at contact start `δ̇⁻` [m/s].
    pub delta_dot_minus: f64,
    /// Damping factor `d` [s/m] fixed at contact start.
    pub d: f64,
    /// Volume law: the resting-damping coefficient \[kg^½\] fixed at contact start
    /// (`response::resting_damping`; 0 for point laws).
    pub rest: f64,
    /// Last narrow-phase result (valid when the boxes overlapped).
    pub geometry: SignedDistance,
    /// Last response (zero when not in contact).
    pub response: PairResponse,
}

/// A pair the broad phase reported near, or one in the contact set.
#[derive(Clone, Debug)]
pub(super) struct PairSlot {
    /// Id of the pair ([`ContactPlan::pair_id`]), set when the pair enters the contact set
    /// (it costs a scan of one row of shapes, so the root functions never compute it).
    pub id: u32,
    /// The pair and its constants.
    pub plan: PairPlan,
    /// Its contact state.
    pub state: PairState,
    /// Evaluation stamp at which the broad phase last reported it.
    seen: u64,
    /// The slot holds a pair (else it is on the free list).
    used: bool,
}

/// A pair of the contact set at rest along its normal ([`ContactState::resting_volume_pairs`]).
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct RestingPair {
    /// Index in the contact set.
    pub k: usize,
    /// The bodies of shape a and shape b (`None` = fixed to the world).
    pub bodies: [Option<crate::dynamics::BodyId>; 2],
    /// Point \[m\] and unit normal (from a to b), resolved in world, at the touch.
    pub point: Vector3<f64>,
    /// See `point`.
    pub normal: Vector3<f64>,
}

/// Key of the shape pair `{a, b}` (either order).
#[inline]
fn key(a: usize, b: usize) -> u64 {
    ((a.min(b) as u64) << 32) | a.max(b) as u64
}

/// The contact set and scratch of a [`ContactPlan`].
#[derive(Clone, Debug)]
pub(crate) struct ContactState {
    /// Pair slots (indices are stable while a pair stays near or in contact).
    slots: Vec<PairSlot>,
    /// Unused slots.
    free: Vec<u32>,
    /// Slot of each shape pair that has one.
    slot_of: std::collections::HashMap<u64, u32, foldhash::fast::FixedState>,
    /// Evaluation stamp of the last root or event evaluation.
    stamp: u64,
    /// Slots of the pairs in the contact set (slot indices, not pair ids: see
    /// [`Self::active_pairs`]).
    active: Vec<u32>,
    /// Ids of the pairs that entered the set at the last event ([`ContactPlan::pair_id`]).
    pub started: Vec<u32>,
    /// Ids of the pairs that left the set at the last event.
    pub ended: Vec<u32>,
    /// Penetration velocity `δ̇⁻` \[m/s\] at contact start of each pair in `started` (> 0
    /// approaching).
    pub started_speed: Vec<f64>,
    /// Penetration velocity `δ̇⁺` \[m/s\] at contact end of each pair in `ended` (< 0
    /// separating).
    pub ended_speed: Vec<f64>,
    /// Narrow-phase calls so far.
    pub narrow_calls: u64,
    /// AABB distance tests (broad phase) so far.
    pub aabb_tests: u64,
    /// Narrow-phase calls that stopped at the MPR/GJK iteration limit so far (the best iterate
    /// was used; each pair is warned about once, by `tracing::warn!`).
    pub narrow_limits: u64,
    /// Keys of the pairs warned about their iteration limit.
    limit_warned: Vec<u64>,
    poses: Vec<Isometry3<f64>>,
    aabbs: Vec<crate::geometry::Aabb>,
    /// AABBs loosened by half the margin on every side, for the broad phase.
    grown: Vec<crate::geometry::Aabb>,
    broad: BroadPhase,
    /// Shape pairs reported by the broad phase at the last evaluation.
    near_shapes: Vec<(u32, u32)>,
    /// `near_shapes` of the evaluation that last looked the slots up: while the broad phase
    /// reports the same pairs in the same order (most steps), `near` holds their slots.
    looked_up: Vec<(u32, u32)>,
    /// Slots of the pairs reported by the broad phase at the last evaluation.
    near: Vec<u32>,
    /// Scratch of continuous mode: the contact patch of each pair in `active` (resized with
    /// `active` at events, so residuals do not allocate).
    patches: Vec<ContactPatch>,
    /// Scratch of continuous mode: the overlap of each volume-law pair in `active` (sized with
    /// `patches`; unused entries for point-law pairs).
    overlaps: Vec<VolumeGeometry>,
    /// The narrow phase and patch of each pair in `active` at the point of the last
    /// [`Self::begin_quotients`]: what the Jacobian's quotient residuals reuse for the pairs
    /// whose bodies their perturbation does not move (sized with `patches`).
    base: Vec<PairGeometry>,
    /// Scratch buffers of the polytope overlaps, sized by the plan (a `RefCell` so that the
    /// read-only queries of the Jacobian, [`Self::pair_geometry`], can use them too).
    scratch: std::cell::RefCell<OverlapScratch>,
}

/// The geometry of one pair in contact as the force law needs it: the narrow phase (for a
/// volume-law pair: distance `−V/A`, normal and witness points at the overlap's centroid), the
/// contact patch (point of application and spread) and, for a volume-law pair, the overlap
/// (else [`VolumeGeometry::NONE`]).
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct PairGeometry(pub SignedDistance, pub ContactPatch, pub VolumeGeometry);

/// The shapes the narrow phase of pair `pp` uses: the sharp ones for a volume-law pair, the
/// smoothed ones otherwise.
#[inline]
fn narrow_shapes<'a>(
    cp: &'a ContactPlan,
    pp: &PairPlan,
) -> (&'a CollisionShape, &'a CollisionShape) {
    let (sa, sb) = (&cp.shapes[pp.a], &cp.shapes[pp.b]);
    match (pp.law, &sa.volume, &sb.volume) {
        (PairLaw::Point, _, _) => (&sa.shape, &sb.shape),
        (_, Some(va), Some(vb)) => (&va.sharp, &vb.sharp),
        _ => (&sa.shape, &sb.shape),
    }
}

/// The overlap of volume-law pair `pp` at poses `pa`, `pb` of its shapes, its area vector
/// pointing from shape a to shape b.
fn volume_overlap(
    cp: &ContactPlan,
    pp: &PairPlan,
    pa: &Isometry3<f64>,
    pb: &Isometry3<f64>,
    scratch: &mut OverlapScratch,
) -> VolumeGeometry {
    let (Some(va), Some(vb)) = (&cp.shapes[pp.a].volume, &cp.shapes[pp.b].volume) else {
        return VolumeGeometry::NONE;
    };
    match (&va.solid, &vb.solid) {
        (VolumeSolid::Polytope(a), VolumeSolid::Polytope(b)) => VolumeGeometry {
            overlap: polytope_overlap(a, pa, b, pb, scratch),
            ..VolumeGeometry::NONE
        },
        (VolumeSolid::Frustum(f), VolumeSolid::Polytope(p)) => {
            let mut ov = frustum_planes_overlap(f, pa, world_planes(p, pb));
            ov.area_vector = -ov.area_vector;
            VolumeGeometry {
                overlap: ov,
                axis: pa.rotation * f.axis.unit(),
                axis_on_b: false,
            }
        }
        (VolumeSolid::Polytope(p), VolumeSolid::Frustum(f)) => VolumeGeometry {
            overlap: frustum_planes_overlap(f, pb, world_planes(p, pa)),
            axis: pb.rotation * f.axis.unit(),
            axis_on_b: true,
        },
        (VolumeSolid::Frustum(_), VolumeSolid::Frustum(_)) => VolumeGeometry::NONE,
    }
}

/// The signed distance the root functions of a volume-law pair of a cylinder or cone and a
/// polytope use: the separating-axis gap over the polytope's faces ([`frustum_planes_gap`]),
/// the same face test [`frustum_planes_overlap`] chooses its face by, so the overlap is
/// non-empty exactly where this is negative and the force is zero at both events (the
/// Euclidean distance of the sharp shapes, which MPR gave before, is positive near a face's
/// edge where the overlap, which takes the face as unbounded, is not zero yet). It is the
/// Euclidean distance wherever a face's plane separates, and costs 0.12 µs instead of MPR's
/// 1.1 µs (a cylinder on a box, `benches/volume_pair.rs`). `None` for every other pair.
fn frustum_gap(
    cp: &ContactPlan,
    pp: &PairPlan,
    pa: &Isometry3<f64>,
    pb: &Isometry3<f64>,
) -> Option<SignedDistance> {
    if pp.law == PairLaw::Point {
        return None;
    }
    let (Some(va), Some(vb)) = (&cp.shapes[pp.a].volume, &cp.shapes[pp.b].volume) else {
        return None;
    };
    // (gap, the polytope's side as a, the frustum's as b) with the normal from a to b.
    let (g, flip) = match (&va.solid, &vb.solid) {
        (VolumeSolid::Polytope(p), VolumeSolid::Frustum(f)) => {
            (frustum_planes_gap(f, pb, world_planes(p, pa))?, false)
        }
        (VolumeSolid::Frustum(f), VolumeSolid::Polytope(p)) => {
            (frustum_planes_gap(f, pa, world_planes(p, pb))?, true)
        }
        _ => return None,
    };
    let sd = SignedDistance {
        distance: g.gap,
        normal: g.normal,
        point_a: g.lowest - g.normal * g.gap,
        point_b: g.lowest,
    };
    Some(if flip { sd.flipped() } else { sd })
}

/// The face planes `(n, h)` of polytope `p` at `pose`, resolved in world (`n·x ≤ h` inside).
fn world_planes<'a>(
    p: &'a crate::geometry::overlap::Polytope,
    pose: &'a Isometry3<f64>,
) -> impl Iterator<Item = (Vector3<f64>, f64)> + 'a {
    p.face_planes().map(move |(n, h)| {
        let nw = pose.rotation * n;
        (nw, h + nw.dot(&pose.translation.vector))
    })
}

/// The narrow-phase view and patch of an overlap `ov` (for results, diagnosis and the
/// Jacobian's caps): distance `−V/A` (the mean depth), the normal, the centroid as both
/// witness points, and the spread `tr Σ_n / V`.
fn overlap_geometry(ov: &Overlap) -> (SignedDistance, ContactPatch) {
    let area = ov.area_vector.norm();
    let (depth, normal) = if ov.volume > 0.0 && area > 0.0 {
        (ov.volume / area, ov.area_vector / area)
    } else {
        (0.0, Vector3::new(0.0, 0.0, 1.0))
    };
    // tr([n]× Σ [n]×ᵀ) = tr Σ − nᵀ Σ n for a unit n: the trace without the 3 × 3 products the
    // force law forms itself (`volume_response`).
    let spread = if ov.volume > 0.0 {
        ((ov.second_moment.trace() - normal.dot(&(ov.second_moment * normal))) / ov.volume).max(0.0)
    } else {
        0.0
    };
    (
        SignedDistance {
            distance: -depth,
            normal,
            point_a: ov.centroid,
            point_b: ov.centroid,
        },
        ContactPatch {
            point: ov.centroid,
            spread,
        },
    )
}

fn to_isometry(t: &Transform) -> Isometry3<f64> {
    Isometry3::from_parts(
        Translation3::from(t.pos),
        UnitQuaternion::from_rotation_matrix(&Rotation3::from_matrix_unchecked(t.rot)),
    )
}

/// Pose of shape `s` in world at the workspace state (`position_velocity` done). A sphere
/// (`ShapePlan::round`) gets its position and the identity rotation: its core is a point at
/// the frame origin, so every query (narrow phase, contact point, AABB) depends on the
/// position alone, and the rotation matrix → quaternion conversion is skipped.
pub(crate) fn shape_pose(cp: &ContactPlan, ws: &Workspace, s: usize) -> Isometry3<f64> {
    let sp = &cp.shapes[s];
    match sp.body {
        Some(b) if sp.round => {
            let x = &ws.world[b];
            Isometry3::from_parts(
                Translation3::from(x.pos + x.rot * sp.in_body.pos),
                UnitQuaternion::identity(),
            )
        }
        Some(b) => to_isometry(&ws.world[b].then(&sp.in_body)),
        None => to_isometry(&sp.in_body),
    }
}

impl ContactState {
    /// The state of `cp`: empty contact set.
    pub(crate) fn new(cp: &ContactPlan) -> Self {
        let ns = cp.shapes.len();
        let mut cs = ContactState {
            slots: Vec::with_capacity(ns),
            free: Vec::with_capacity(ns),
            slot_of: std::collections::HashMap::with_capacity_and_hasher(
                ns,
                foldhash::fast::FixedState::default(),
            ),
            stamp: 0,
            active: Vec::with_capacity(ns),
            started: Vec::with_capacity(ns),
            ended: Vec::with_capacity(ns),
            started_speed: Vec::with_capacity(ns),
            ended_speed: Vec::with_capacity(ns),
            narrow_calls: 0,
            aabb_tests: 0,
            narrow_limits: 0,
            limit_warned: vec![],
            poses: vec![Isometry3::identity(); ns],
            aabbs: vec![crate::geometry::Aabb::new_invalid(); ns],
            grown: vec![crate::geometry::Aabb::new_invalid(); ns],
            broad: BroadPhase::new(ns),
            near_shapes: Vec::with_capacity(ns),
            looked_up: Vec::with_capacity(ns),
            near: Vec::with_capacity(ns),
            patches: Vec::with_capacity(ns),
            overlaps: Vec::with_capacity(ns),
            base: Vec::with_capacity(ns),
            scratch: std::cell::RefCell::new(cp.overlap_scratch()),
        };
        // Shapes fixed to the world: pose and boxes once (the evaluations update moving ones).
        for (s, sp) in cp.shapes.iter().enumerate() {
            if sp.body.is_none() {
                cs.poses[s] = to_isometry(&sp.in_body);
                cs.aabbs[s] = shape_aabb(cp, s, &cs.poses[s]);
                cs.grown[s] = BoundingVolume::loosened(&cs.aabbs[s], 0.5 * cp.margin);
            }
        }
        cs
    }

    /// Shape indices of the pair in slot `p`.
    #[inline]
    fn shapes_of(&self, p: usize) -> (usize, usize) {
        let pp = &self.slots[p].plan;
        (pp.a, pp.b)
    }

    fn narrow(
        &mut self,
        plan: &Plan,
        cp: &ContactPlan,
        p: usize,
        t: f64,
    ) -> Result<SignedDistance, ContactError> {
        let (a, b) = self.shapes_of(p);
        self.narrow_calls += 1;
        if let Some(sd) = frustum_gap(cp, &self.slots[p].plan, &self.poses[a], &self.poses[b]) {
            return Ok(sd);
        }
        let (sa, sb) = narrow_shapes(cp, &self.slots[p].plan);
        let r = signed_distance_method(sa, &self.poses[a], sb, &self.poses[b], &cp.narrow);
        match r {
            Ok((sd, Method::IterationLimit)) => {
                self.limit_reached(plan, cp, p, t);
                Ok(sd)
            }
            Ok((sd, _)) => Ok(sd),
            Err(source) => Err(self.narrow_error(plan, cp, p, t, source)),
        }
    }

    /// The narrow phase of slot `p` stopped at its iteration limit: the iterate is still
    /// usable (a lower bound of the distance); say so once per pair, since a pair that needs
    /// more iterations usually does so at every call.
    #[cold]
    fn limit_reached(&mut self, plan: &Plan, cp: &ContactPlan, p: usize, t: f64) {
        self.narrow_limits += 1;
        let pp = &self.slots[p].plan;
        let k = key(pp.a, pp.b);
        if !self.limit_warned.contains(&k) {
            self.limit_warned.push(k);
            tracing::warn!(
                pair = %cp.pair_name(&plan.scene, pp),
                t,
                max_iterations = cp.narrow.max_iterations,
                "the narrow phase stopped at its iteration limit before meeting \
                 mpr_tolerance; the best iterate is used (raise mpr_max_iterations or \
                 loosen mpr_tolerance if this repeats)"
            );
        }
    }

    /// Point of application of the force of the pair in slot `p` for its narrow-phase result
    /// `sd` (poses of the same call).
    fn point(&self, cp: &ContactPlan, p: usize, sd: &SignedDistance) -> Vector3<f64> {
        self.patch(cp, p, sd).point.coords
    }

    /// [`Self::point`] with the spread of the pressure and the penetration there
    /// (`contact_patch`).
    fn patch(&self, cp: &ContactPlan, p: usize, sd: &SignedDistance) -> ContactPatch {
        let pp = &self.slots[p].plan;
        if pp.law != PairLaw::Point {
            // The sharp shapes' witness points (a volume pair's touch: where it starts).
            return ContactPatch {
                point: Point3::from((sd.point_a.coords + sd.point_b.coords) * 0.5),
                spread: 0.0,
            };
        }
        contact_patch(
            &cp.shapes[pp.a].shape,
            &self.poses[pp.a],
            &cp.shapes[pp.b].shape,
            &self.poses[pp.b],
            sd,
        )
    }

    /// The slot of the candidate pair of shapes `a`, `b`, taken from the free list (or grown)
    /// with a fresh state if the pair has none; `None` if they cannot meet.
    fn slot(&mut self, cp: &ContactPlan, a: usize, b: usize) -> Option<u32> {
        let k = key(a, b);
        if let Some(&p) = self.slot_of.get(&k) {
            return Some(p);
        }
        let slot = PairSlot {
            plan: cp.pair(a, b)?,
            id: u32::MAX,
            state: PairState::APART,
            seen: 0,
            used: true,
        };
        let p = match self.free.pop() {
            Some(p) => {
                self.slots[p as usize] = slot;
                p
            }
            None => {
                self.slots.push(slot);
                (self.slots.len() - 1) as u32
            }
        };
        self.slot_of.insert(k, p);
        Some(p)
    }

    /// Frees the slots of pairs neither reported at this evaluation nor in the contact set:
    /// their state is that of a pair apart, rebuilt when the broad phase reports them again.
    fn release_far(&mut self) {
        for p in 0..self.slots.len() {
            let sl = &mut self.slots[p];
            if sl.used && sl.seen != self.stamp && !sl.state.in_contact {
                sl.used = false;
                self.slot_of.remove(&key(sl.plan.a, sl.plan.b));
                self.free.push(p as u32);
            }
        }
    }

    /// Evaluates the collision stage in `mode` at the workspace state (`position_velocity`
    /// done). `Continuous` adds the contact forces to `ws.f_ext`; `Event` also fills
    /// `started`/`ended`.
    pub(crate) fn evaluate(
        &mut self,
        plan: &Plan,
        cp: &ContactPlan,
        ws: &mut Workspace,
        mode: Mode,
        t: f64,
    ) -> Result<(), ContactError> {
        match mode {
            Mode::Continuous => self.continuous(plan, cp, ws, t, None),
            Mode::ZeroCrossing | Mode::Event => {
                for &s in &cp.moving {
                    self.poses[s] = shape_pose(cp, ws, s);
                    self.aabbs[s] = shape_aabb(cp, s, &self.poses[s]);
                    self.grown[s] = BoundingVolume::loosened(&self.aabbs[s], 0.5 * cp.margin);
                }
                // Broad phase: only candidate pairs whose loosened boxes overlap get a z_AB;
                // the others count as `margin` (see ContactPlan::margin).
                self.broad.update(
                    &self.grown,
                    |a, b| cp.can_meet(a as usize, b as usize),
                    &mut self.near_shapes,
                );
                self.aabb_tests += self.broad.box_tests();
                self.stamp += 1;
                if self.near_shapes == self.looked_up {
                    // The same pairs as at the last evaluation: `near` holds their slots (a
                    // slot is released only when its pair is not reported), no lookups.
                    for &p in &self.near {
                        self.slots[p as usize].seen = self.stamp;
                    }
                } else {
                    self.near.clear();
                    for k in 0..self.near_shapes.len() {
                        let (a, b) = self.near_shapes[k];
                        if let Some(p) = self.slot(cp, a as usize, b as usize) {
                            self.slots[p as usize].seen = self.stamp;
                            self.near.push(p);
                        }
                    }
                    self.looked_up.clone_from(&self.near_shapes);
                }
                for k in 0..self.near.len() {
                    let p = self.near[k] as usize;
                    let (a, b) = self.shapes_of(p);
                    let da = aabb_distance(&self.aabbs[a], &self.aabbs[b]);
                    // The AABB distance is a lower bound of the shapes' distance; above the
                    // end level 2ε it decides nothing (see `Hysteresis`), below it the narrow
                    // phase gives the exact value the contact-set decision needs.
                    if da > cp.hysteresis_band().end {
                        self.slots[p].state.z = da;
                    } else {
                        let sd = self.narrow(plan, cp, p, t)?;
                        self.slots[p].state.geometry = sd;
                        self.slots[p].state.z = sd.distance;
                    }
                }
                // A pair still in the set but no longer reported moved far apart in one step:
                // its z_AB (positive) lets z_1 cross upwards.
                for k in 0..self.active.len() {
                    let p = self.active[k] as usize;
                    if self.slots[p].seen != self.stamp {
                        let pp = self.slots[p].plan;
                        self.slots[p].state.z = aabb_distance(&self.aabbs[pp.a], &self.aabbs[pp.b]);
                    }
                }
                if mode == Mode::Event {
                    self.rebuild(cp, ws);
                }
                self.release_far();
                Ok(())
            }
        }
    }

    /// Continuous mode: the contact forces of the pairs in the set, added to `ws.f_ext`. With
    /// `moved` (a flag per body), the pairs none of whose bodies is flagged take the geometry
    /// of the last [`Self::begin_quotients`] instead of a new narrow phase: the Jacobian's
    /// quotient residuals, whose perturbation leaves those bodies where they were (the same
    /// poses, so the same bits: the narrow phase is a function of the two poses alone).
    fn continuous(
        &mut self,
        plan: &Plan,
        cp: &ContactPlan,
        ws: &mut Workspace,
        t: f64,
        moved: Option<&[bool]>,
    ) -> Result<(), ContactError> {
        // Two passes: the geometry of every pair, then the responses and wrenches (added in
        // the same pair order, so the same bits as one pass). One pair's work in one pass is
        // ~900 instructions with long chains of square roots and divisions, more than the
        // processor's reorder window: in two shorter loops consecutive pairs' chains overlap
        // (BENCHMARKS.md, "Cost per active contact").
        if self.patches.len() < self.active.len() {
            // Only if an evaluation comes before any event sized it.
            self.patches.resize(self.active.len(), EMPTY_PATCH);
            self.overlaps
                .resize(self.active.len(), VolumeGeometry::NONE);
        }
        // `base` covers the set whenever `begin_quotients` came after the last event (the DAE
        // asks for reuse only then); otherwise every pair is computed.
        let moved = moved.filter(|_| self.base.len() >= self.active.len());
        for k in 0..self.active.len() {
            let p = self.active[k] as usize;
            if let Some(moved) = moved {
                let (a, b) = self.shapes_of(p);
                let moves = |s: usize| cp.shapes[s].body.is_some_and(|x| moved[x.index()]);
                if !moves(a) && !moves(b) {
                    let PairGeometry(sd, patch, ov) = self.base[k];
                    let sl = &mut self.slots[p];
                    sl.state.geometry = sd;
                    if sl.plan.law == PairLaw::Point {
                        sl.state.z = sd.distance;
                    }
                    self.patches[k] = patch;
                    self.overlaps[k] = ov;
                    continue;
                }
            }
            if self.slots[p].plan.law == PairLaw::Point {
                self.patches[k] = self.continuous_geometry(plan, cp, ws, p, t)?;
            } else {
                let (a, b) = self.shapes_of(p);
                for s in [a, b] {
                    if cp.shapes[s].body.is_some() {
                        self.poses[s] = shape_pose(cp, ws, s);
                    }
                }
                let ov = volume_overlap(
                    cp,
                    &self.slots[p].plan,
                    &self.poses[a],
                    &self.poses[b],
                    self.scratch.get_mut(),
                );
                let (sd, patch) = overlap_geometry(&ov.overlap);
                self.slots[p].state.geometry = sd;
                self.patches[k] = patch;
                self.overlaps[k] = ov;
            }
        }
        for k in 0..self.active.len() {
            let sl = &mut self.slots[self.active[k] as usize];
            apply(
                cp,
                &sl.plan,
                &mut sl.state,
                &self.patches[k],
                &self.overlaps[k],
                ws,
            );
        }
        Ok(())
    }

    /// Keeps the narrow phase and patch of every pair in the set as the last continuous
    /// evaluation left them (called right after the residual at the point of a Jacobian), for
    /// the quotient residuals of [`Self::evaluate_moved`]. Allocation-free once the set has
    /// been sized at an event.
    pub(crate) fn begin_quotients(&mut self) {
        if self.base.len() < self.active.len() {
            self.base.resize(self.active.len(), EMPTY_GEOMETRY);
        }
        for k in 0..self.active.len() {
            let p = self.active[k] as usize;
            self.base[k] = PairGeometry(
                self.slots[p].state.geometry,
                self.patches[k],
                self.overlaps[k],
            );
        }
    }

    /// Continuous mode for a quotient residual of the Jacobian: as [`Self::evaluate`] in
    /// [`Mode::Continuous`], at a point whose positions differ from those of the last
    /// [`Self::begin_quotients`] only for the bodies flagged in `moved` (indexed by body):
    /// the pairs of unflagged bodies reuse that call's narrow phase. The same forces, to the
    /// last bit.
    pub(crate) fn evaluate_moved(
        &mut self,
        plan: &Plan,
        cp: &ContactPlan,
        ws: &mut Workspace,
        t: f64,
        moved: &[bool],
    ) -> Result<(), ContactError> {
        self.continuous(plan, cp, ws, t, Some(moved))
    }

    /// Continuous mode's geometry of the pair in slot `p` (in the contact set): poses of its
    /// moving shapes, narrow phase (stored in the pair's state) and the contact patch
    /// (returned). The per-pair work of every residual evaluation, so written out here rather
    /// than through [`Self::narrow`] and [`Self::patch`]: the shapes are looked up once, a
    /// round shape's pose is updated in its translation only (its rotation stays the identity,
    /// [`shape_pose`]), and the error path is out of line (BENCHMARKS.md, "Cost per active
    /// contact"). The same operations in the same order as those functions.
    #[inline]
    fn continuous_geometry(
        &mut self,
        plan: &Plan,
        cp: &ContactPlan,
        ws: &Workspace,
        p: usize,
        t: f64,
    ) -> Result<ContactPatch, ContactError> {
        let (a, b) = self.shapes_of(p);
        let (sa, sb) = (&cp.shapes[a], &cp.shapes[b]);
        for (s, sp) in [(a, sa), (b, sb)] {
            match sp.body {
                Some(body) if sp.round => {
                    // The rotation of a round moving shape's pose is always the identity
                    // (`shape_pose`; the pose array starts as identities).
                    debug_assert!(self.poses[s].rotation == UnitQuaternion::identity());
                    let x = &ws.world[body];
                    self.poses[s].translation.vector = x.pos + x.rot * sp.in_body.pos;
                }
                Some(_) => self.poses[s] = shape_pose(cp, ws, s),
                None => {}
            }
        }
        let (pa, pb) = (&self.poses[a], &self.poses[b]);
        self.narrow_calls += 1;
        let sd = match signed_distance_method(&sa.shape, pa, &sb.shape, pb, &cp.narrow) {
            Ok((sd, Method::IterationLimit)) => {
                self.limit_reached(plan, cp, p, t);
                sd
            }
            Ok((sd, _)) => sd,
            Err(source) => return Err(self.narrow_error(plan, cp, p, t, source)),
        };
        let (pa, pb) = (&self.poses[a], &self.poses[b]);
        let patch = contact_patch(&sa.shape, pa, &sb.shape, pb, &sd);
        let sl = &mut self.slots[p];
        sl.state.geometry = sd;
        sl.state.z = sd.distance;
        Ok(patch)
    }

    /// The error of a failed narrow phase of slot `p` (the pair's name made here, off the hot
    /// path).
    #[cold]
    #[inline(never)]
    fn narrow_error(
        &self,
        plan: &Plan,
        cp: &ContactPlan,
        p: usize,
        t: f64,
        source: GeometryError,
    ) -> ContactError {
        ContactError {
            pair: cp.pair_name(&plan.scene, &self.slots[p].plan),
            t,
            source,
        }
    }

    /// Rebuilds the contact set from the current `z` values (in contact iff `z < ε`, see
    /// [`Hysteresis`]) and fixes `δ̇⁻` and `d` of new contacts.
    fn rebuild(&mut self, cp: &ContactPlan, ws: &Workspace) {
        self.started.clear();
        self.ended.clear();
        self.started_speed.clear();
        self.ended_speed.clear();
        // Pairs the broad phase no longer reports are far apart: they leave the set.
        for k in 0..self.active.len() {
            let p = self.active[k] as usize;
            if self.slots[p].seen != self.stamp {
                let dd = self.normal_speed(cp, ws, p);
                self.ended_speed.push(dd);
            }
            let sl = &mut self.slots[p];
            if sl.seen != self.stamp {
                sl.state.in_contact = false;
                sl.state.response = PairResponse::default();
                self.ended.push(sl.id);
            }
        }
        self.active.clear();
        for k in 0..self.near.len() {
            let p = self.near[k] as usize;
            let now = self.slots[p].state.z < cp.hysteresis_band().decide;
            if !now && self.slots[p].state.in_contact {
                let dd = self.normal_speed(cp, ws, p);
                self.ended_speed.push(dd);
            }
            let point = if now && !self.slots[p].state.in_contact {
                self.point(cp, p, &self.slots[p].state.geometry)
            } else {
                Vector3::zeros()
            };
            let sl = &mut self.slots[p];
            let (pp, ps) = (&sl.plan, &mut sl.state);
            if now && !ps.in_contact {
                let sd = &ps.geometry;
                let (v1, _) = point_velocity(ws, cp.shapes[pp.a].body, &point);
                let (v2, _) = point_velocity(ws, cp.shapes[pp.b].body, &point);
                let dd = -(v2 - v1).dot(&sd.normal);
                ps.delta_dot_minus = dd;
                self.started_speed.push(dd);
                // The volume law: the pair's cor at the contact-start speed, at least v_min; a
                // slow contact gets the resting damping below instead of the paper's blend
                // towards cor_min (which only hits d_max) (docs/contact-model.md §3.2).
                let (c, dd_d) = if pp.law == PairLaw::Point {
                    (cor_reg(cp.profile, pp.cor, cp.cor_min, dd, pp.v_min), dd)
                } else {
                    (pp.cor, dd.abs().max(pp.v_min))
                };
                ps.d = if cp.exact_restitution {
                    damping_factor_exact(c, dd_d, pp.v_min, cp.d_max)
                } else {
                    damping_factor(c, dd_d, pp.v_min, cp.d_max)
                };
                ps.rest = if pp.law == PairLaw::Point {
                    0.0
                } else {
                    let m = |s: usize| cp.shapes[s].body_mass;
                    resting_damping(m(pp.a), m(pp.b))
                };
                sl.id = cp.pair_id(pp.a, pp.b).map_or(u32::MAX, |i| i as u32);
                self.started.push(sl.id);
            } else if !now && ps.in_contact {
                self.ended.push(sl.id);
                ps.response = PairResponse::default();
            }
            ps.in_contact = now;
            if now {
                self.active.push(p as u32);
            }
        }
        self.patches.resize(self.active.len(), EMPTY_PATCH);
        self.overlaps
            .resize(self.active.len(), VolumeGeometry::NONE);
        self.base.resize(self.active.len(), EMPTY_GEOMETRY);
    }

    /// Penetration velocity `δ̇ = −(v_b − v_a)·n` \[m/s\] of slot `p`'s pair at its contact
    /// point (from the last narrow-phase result; > 0 approaching), at the workspace velocities.
    fn normal_speed(&self, cp: &ContactPlan, ws: &Workspace, p: usize) -> f64 {
        let sl = &self.slots[p];
        let sd = &sl.state.geometry;
        let point = self.point(cp, p, sd);
        let (v1, _) = point_velocity(ws, cp.shapes[sl.plan.a].body, &point);
        let (v2, _) = point_velocity(ws, cp.shapes[sl.plan.b].body, &point);
        -(v2 - v1).dot(&sd.normal)
    }

    /// The two root functions from the last `z` values \[m\]: `z_1` = max over pairs in contact
    /// of `z − 2ε` (−42 if none), `z_2` = min over the others of `z`, where pairs the broad
    /// phase does not report count as `margin` apart (so `z_2 ≤ margin`). See [`Hysteresis`].
    pub(crate) fn roots(&self, cp: &ContactPlan) -> (f64, f64) {
        let band = cp.hysteresis_band();
        let mut z1 = -42.0f64;
        let mut any = false;
        for &p in &self.active {
            let z = self.slots[p as usize].state.z - band.end;
            z1 = if any { z1.max(z) } else { z };
            any = true;
        }
        let mut z2 = cp.margin - band.start;
        for &p in &self.near {
            let ps = &self.slots[p as usize].state;
            if !ps.in_contact {
                z2 = z2.min(ps.z - band.start);
            }
        }
        (z1, z2)
    }

    /// Number of pairs in the contact set (the `k` of [`Self::active_bodies`],
    /// [`Self::pair_geometry`], [`Self::pair_wrenches`]).
    pub(crate) fn n_in_contact(&self) -> usize {
        self.active.len()
    }

    /// The shapes (indices into `ContactPlan::shapes`) of the `k`-th pair in the contact set.
    pub(crate) fn active_shapes(&self, k: usize) -> (usize, usize) {
        self.shapes_of(self.active[k] as usize)
    }

    /// Bodies (`None` = fixed to the world) of shape a and shape b of the `k`-th pair in the
    /// contact set.
    pub(crate) fn active_bodies(
        &self,
        cp: &ContactPlan,
        k: usize,
    ) -> (
        Option<crate::dynamics::BodyId>,
        Option<crate::dynamics::BodyId>,
    ) {
        let pp = &self.slots[self.active[k] as usize].plan;
        (cp.shapes[pp.a].body, cp.shapes[pp.b].body)
    }

    /// Whether the narrow phase of shapes `a`, `b` has stopped at its iteration limit in this
    /// run (the pair was warned about): its geometry is rough at the scale of a difference
    /// quotient's increment.
    pub(crate) fn hit_iteration_limit(&self, a: usize, b: usize) -> bool {
        !self.limit_warned.is_empty() && self.limit_warned.contains(&key(a, b))
    }

    /// Whether the geometry of the `k`-th pair in the contact set is independent of the
    /// rotation of body `b`: its shapes on `b` are spheres centred at the body origin (placed
    /// by position only, see [`shape_pose`]).
    pub(crate) fn rotation_free(
        &self,
        cp: &ContactPlan,
        k: usize,
        b: crate::dynamics::BodyId,
    ) -> bool {
        let (sa, sb) = self.shapes_of(self.active[k] as usize);
        [sa, sb].into_iter().all(|s| {
            let sp = &cp.shapes[s];
            sp.body != Some(b) || (sp.round && sp.in_body.pos == Vector3::zeros())
        })
    }

    /// How far the narrow phase of the `k`-th pair in the contact set is from smooth at the
    /// workspace poses: the largest central second difference of its unit normal [rad] and of
    /// its signed distance \[m\] when shape b moves by `±step` \[m\] along each world axis.
    /// A smooth narrow phase gives `~step²·κ²` (κ the curvature, 1/m): nothing at
    /// `step` = 1e-9 m; a narrow phase whose answer jumps with the pose (an iteration stopped at
    /// its tolerance on a curved core, MPR's portal on a deep overlap) gives the jump itself.
    /// For the work-budget diagnosis only (not on the hot path); `None` if a query fails.
    pub(crate) fn pair_roughness(
        &self,
        cp: &ContactPlan,
        ws: &Workspace,
        k: usize,
        step: f64,
    ) -> Option<(f64, f64)> {
        let p = *self.active.get(k)? as usize;
        let (a, b) = self.shapes_of(p);
        let pose = |s: usize| {
            if cp.shapes[s].body.is_some() {
                shape_pose(cp, ws, s)
            } else {
                self.poses[s]
            }
        };
        let (pa, pb) = (pose(a), pose(b));
        let (sa, sb) = narrow_shapes(cp, &self.slots[p].plan);
        let query = |d: Vector3<f64>| {
            let mut moved = pb;
            moved.translation.vector += d;
            signed_distance_method(sa, &pa, sb, &moved, &cp.narrow)
                .ok()
                .map(|(sd, _)| sd)
        };
        let centre = query(Vector3::zeros())?;
        let (mut normal, mut distance) = (0.0f64, 0.0f64);
        for axis in 0..3 {
            let mut e = Vector3::zeros();
            e[axis] = step;
            let (plus, minus) = (query(e)?, query(-e)?);
            normal = normal.max((plus.normal - 2.0 * centre.normal + minus.normal).norm());
            distance = distance.max((plus.distance - 2.0 * centre.distance + minus.distance).abs());
        }
        Some((normal, distance))
    }

    /// Narrow phase and contact patch of the `k`-th pair in the contact set at the workspace
    /// poses, as continuous mode computes them, but touching no pair state, pose or counter:
    /// for pair-local difference quotients of the Jacobian (`dae/jacobian.rs`).
    pub(crate) fn pair_geometry(
        &self,
        plan: &Plan,
        cp: &ContactPlan,
        ws: &Workspace,
        k: usize,
        t: f64,
    ) -> Result<PairGeometry, ContactError> {
        let p = self.active[k] as usize;
        let (a, b) = self.shapes_of(p);
        let pose = |s: usize| {
            if cp.shapes[s].body.is_some() {
                shape_pose(cp, ws, s)
            } else {
                self.poses[s]
            }
        };
        let (pa, pb) = (pose(a), pose(b));
        let pp = &self.slots[p].plan;
        if pp.law != PairLaw::Point {
            let ov = volume_overlap(cp, pp, &pa, &pb, &mut self.scratch.borrow_mut());
            let (sd, patch) = overlap_geometry(&ov.overlap);
            return Ok(PairGeometry(sd, patch, ov));
        }
        let (sa, sb) = (&cp.shapes[a].shape, &cp.shapes[b].shape);
        let sd = match signed_distance_method(sa, &pa, sb, &pb, &cp.narrow) {
            Ok((sd, _)) => sd,
            Err(source) => {
                return Err(ContactError {
                    pair: cp.pair_name(&plan.scene, &self.slots[p].plan),
                    t,
                    source,
                })
            }
        };
        Ok(PairGeometry(
            sd,
            contact_patch(sa, &pa, sb, &pb, &sd),
            VolumeGeometry::NONE,
        ))
    }

    /// The wrenches (about the body origins, resolved in the body frames) of the `k`-th pair
    /// in the contact set on its bodies a and b (`None` for a fixed shape), for the geometry
    /// `geo` of [`Self::pair_geometry`] and the workspace velocities: what continuous mode adds
    /// to `ws.f_ext`, without touching the pair's state.
    pub(crate) fn pair_wrenches(
        &self,
        cp: &ContactPlan,
        ws: &Workspace,
        k: usize,
        geo: &PairGeometry,
    ) -> (Option<Force>, Option<Force>) {
        let sl = &self.slots[self.active[k] as usize];
        let (ba, bb) = (cp.shapes[sl.plan.a].body, cp.shapes[sl.plan.b].body);
        let PairGeometry(sd, patch, ov) = geo;
        let point = &patch.point.coords;
        let (v1, w1) = point_velocity(ws, ba, point);
        let (v2, w2) = point_velocity(ws, bb, point);
        let r = if sl.plan.law == PairLaw::Point {
            pair_response(cp, &sl.plan, sl.state.d, sd, patch, &v1, &w1, &v2, &w2)
        } else {
            volume_response(
                cp,
                &sl.plan,
                sl.state.d,
                sl.state.rest,
                ov,
                &v1,
                &w1,
                &v2,
                &w2,
            )
        };
        let f = r.normal_force + r.friction_force;
        (
            ba.map(|b| world_wrench_in_body(ws, b, &r.point, &-f, &-r.rolling_torque)),
            bb.map(|b| world_wrench_in_body(ws, b, &r.point, &f, &r.rolling_torque)),
        )
    }

    /// Constants and state of the `k`-th pair in the contact set (for the exact pair derivatives
    /// of `contact/pair_jacobian.rs`).
    pub(crate) fn active_pair(&self, k: usize) -> (&PairPlan, &PairState) {
        let sl = &self.slots[self.active[k] as usize];
        (&sl.plan, &sl.state)
    }

    /// The pairs of the contact set under the volume law whose penetration velocity at their
    /// start `δ̇⁻` is at most `speed` \[m/s\] in size (bodies placed resting on one another),
    /// each with its index `k` in the set, its bodies (shape a's, shape b's; `None` = fixed)
    /// and the point \[m\] and unit normal (from a to b) of its last narrow phase (for the
    /// contact preload, `simulation/preload.rs`: right after an event, where a touching pair's
    /// overlap is still empty, these are its touch).
    pub(crate) fn resting_volume_pairs(&self, cp: &ContactPlan, speed: f64) -> Vec<RestingPair> {
        (0..self.active.len())
            .filter_map(|k| {
                let p = self.active[k] as usize;
                let sl = &self.slots[p];
                (sl.plan.law != PairLaw::Point && sl.state.delta_dot_minus.abs() <= speed).then(
                    || {
                        let sd = &sl.state.geometry;
                        RestingPair {
                            k,
                            bodies: [cp.shapes[sl.plan.a].body, cp.shapes[sl.plan.b].body],
                            point: self.point(cp, p, sd),
                            normal: sd.normal,
                        }
                    },
                )
            })
            .collect()
    }

    /// Pose of shape `s` as the last evaluation placed it (for a shape fixed to the world: its
    /// constant pose).
    pub(crate) fn pose(&self, s: usize) -> &Isometry3<f64> {
        &self.poses[s]
    }

    /// The narrow-phase distance calls of continuous mode alone, for the pairs in the set at
    /// the poses of the last evaluation (no state touched): the sum of the distances \[m\]
    /// (errors count as 0). For the bench hook `crate::bench::contact_stage_cost`, which
    /// subtracts this from a whole continuous evaluation.
    pub(crate) fn narrow_phase_only(&self, cp: &ContactPlan) -> f64 {
        let mut sum = 0.0;
        for &p in &self.active {
            let (a, b) = self.shapes_of(p as usize);
            let (sa, sb) = narrow_shapes(cp, &self.slots[p as usize].plan);
            if let Ok((sd, _)) =
                signed_distance_method(sa, &self.poses[a], sb, &self.poses[b], &cp.narrow)
            {
                sum += sd.distance;
            }
        }
        sum
    }

    /// Number of pairs in the contact set.
    #[cfg(test)]
    pub(crate) fn n_active(&self) -> usize {
        self.active.len()
    }

    /// Number of pairs that have a state (reported near at the last root or event
    /// evaluation, or in the contact set).
    #[cfg(test)]
    pub(crate) fn pairs_with_state(&self) -> usize {
        self.slot_of.len()
    }

    /// The pairs in the contact set: their ids ([`ContactPlan::pair_id`]), constants and
    /// states.
    pub(crate) fn active_pairs(&self) -> impl Iterator<Item = (usize, &PairPlan, &PairState)> {
        self.active.iter().map(|&p| {
            let sl = &self.slots[p as usize];
            (sl.id as usize, &sl.plan, &sl.state)
        })
    }

    /// The state of the pair of shapes `a`, `b` (either order), `None` while the broad phase
    /// does not report it (apart: not in contact, zero response).
    pub(crate) fn state_of(&self, a: usize, b: usize) -> Option<&PairState> {
        self.slot_of
            .get(&key(a, b))
            .map(|&p| &self.slots[p as usize].state)
    }
}

impl PairState {
    /// The state of a pair apart: not in contact, `z` infinite, zero response.
    pub(crate) const APART: PairState = PairState {
        in_contact: false,
        z: f64::INFINITY,
        delta_dot_minus: 0.0,
        d: 0.0,
        rest: 0.0,
        geometry: SignedDistance {
            distance: f64::INFINITY,
            normal: Vector3::new(0.0, 0.0, 1.0),
            point_a: Point3::new(0.0, 0.0, 0.0),
            point_b: Point3::new(0.0, 0.0, 0.0),
        },
        response: PairResponse::ZERO,
    };
}

/// A placeholder patch for `ContactState::patches` before its first evaluation.
const EMPTY_PATCH: ContactPatch = ContactPatch {
    point: Point3::new(0.0, 0.0, 0.0),
    spread: 0.0,
};

/// A placeholder for `ContactState::base`.
const EMPTY_GEOMETRY: PairGeometry =
    PairGeometry(PairState::APART.geometry, EMPTY_PATCH, VolumeGeometry::NONE);

/// World AABB of shape `s` at `pose`: of the sharp shape if it takes part in a volume pair (it
/// contains the smoothed one, and its distance must bound the sharp shapes'), else of the
/// smoothed shape.
fn shape_aabb(cp: &ContactPlan, s: usize, pose: &Isometry3<f64>) -> crate::geometry::Aabb {
    let sp = &cp.shapes[s];
    match &sp.volume {
        Some(v) if v.in_volume_pair => world_aabb(&v.sharp, pose),
        _ => world_aabb(&sp.shape, pose),
    }
}

/// The levels of the contact-set hysteresis, in values of `z_AB` \[m\] (signed distance:
/// negative = penetrating), for `ε` = [`SceneOptions::hysteresis`](crate::scene::SceneOptions):
///
/// | level | `z_AB` | meaning |
/// |---|---|---|
/// | `start` | 0 | a pair not in contact enters at the event where `z_2` crosses it downwards (the shapes touch) |
/// | `decide` | ε | at an event, a pair is in the contact set iff `z_AB < ε` |
/// | `end` | 2ε | a pair in contact leaves at the event where `z_1` crosses it upwards |
///
/// Every root value is thus at least ε away from zero at a restart (the purpose of the
/// paper's hysteresis). The band lies on the *separated* side, where the force law gives zero
/// force, unlike the paper's (start at `z_AB = −2ε`, end at 0, decision at `−ε`). Why: with the
/// band inside the penetration the force jumps from 0 to `k·2ε` when a contact starts, so a
/// body that falls through the band without force and rises through it with force gains the
/// work of that loop, `2kε²` (linear law) per cycle. A resting body whose static penetration
/// `m·g/k` is smaller than 2ε then never settles: the measured steel box (0.1 m cube on a
/// steel table, k = 1.1e11 N/m, m·g/k = 7.1e-10 m ≪ 2ε = 2e-8 m) bounced 5,918 times in
/// 0.2 s, hovering 8 nm above the table (376,863 IDA steps). With the band outside the
/// penetration the force is continuous (zero at `z_AB = 0`, where the contact starts, and zero
/// up to the end level), the loop does no work and resting contact rests for every mass and
/// stiffness, without deriving a band from the pair. The contact-start velocity `δ̇⁻` is taken
/// at touch instead of at 2ε of depth, the same within `2ε/v` of time. docs/contact-hysteresis.md
/// has the full argument and the measurements.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct Hysteresis {
    /// Level \[m\] at which a contact starts (0: touching).
    pub start: f64,
    /// Level \[m\] that decides membership at an event (ε).
    pub decide: f64,
    /// Level \[m\] at which a contact ends (2ε).
    pub end: f64,
}

impl ContactPlan {
    /// The hysteresis levels of this plan (see [`Hysteresis`]).
    #[inline]
    pub(crate) fn hysteresis_band(&self) -> Hysteresis {
        Hysteresis::of(self.hysteresis)
    }
}

impl Hysteresis {
    /// The levels for the hysteresis `ε` (`SceneOptions::hysteresis`): 0, ε, 2ε.
    #[inline]
    pub(crate) fn of(eps: f64) -> Hysteresis {
        Hysteresis {
            start: 0.0,
            decide: eps,
            end: 2.0 * eps,
        }
    }
}

/// Response of pair `pp` in contact (state `ps`, overlap `ov` for a volume-law pair), applied
/// to both bodies.
fn apply(
    cp: &ContactPlan,
    pp: &PairPlan,
    ps: &mut PairState,
    patch: &ContactPatch,
    ov: &VolumeGeometry,
    ws: &mut Workspace,
) {
    let (ba, bb) = (cp.shapes[pp.a].body, cp.shapes[pp.b].body);
    let sd = &ps.geometry;
    let point = &patch.point.coords;
    let (v1, w1) = point_velocity(ws, ba, point);
    let (v2, w2) = point_velocity(ws, bb, point);
    // Written into the pair's state directly (a 144-byte copy per pair and evaluation less).
    ps.response = if pp.law == PairLaw::Point {
        pair_response(cp, pp, ps.d, sd, patch, &v1, &w1, &v2, &w2)
    } else {
        volume_response(cp, pp, ps.d, ps.rest, ov, &v1, &w1, &v2, &w2)
    };
    let r = &ps.response;
    let f = r.normal_force + r.friction_force;
    add_world_wrench(ws, bb, &r.point, &f, &r.rolling_torque);
    add_world_wrench(ws, ba, &r.point, &-f, &-r.rolling_torque);
}
