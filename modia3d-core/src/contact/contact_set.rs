//! Contact stage: the contact set (the paper's `contactDict`) and the zero-crossing functions
//! (docs/contact-model.md §4). `(&ContactPlan, &mut ContactState)` plus the dynamics workspace (read-only poses
//! and velocities; contact forces are added to `ws.f_ext`). No allocation after construction.

use super::preprocess::ContactPlan;
use super::regularise::{cor_reg, damping_factor, damping_factor_exact};
use super::response::{pair_response, PairResponse};
use crate::dynamics::forces::add_world_wrench;
use crate::dynamics::kinematics::point_velocity;
use crate::dynamics::spatial::Transform;
use crate::dynamics::{Plan, Workspace};
use crate::geometry::narrow_phase::Method;
use crate::geometry::BroadPhase;
use crate::geometry::{
    aabb_distance, contact_point, signed_distance_method, world_aabb, GeometryError, SignedDistance,
};
use nalgebra::{Isometry3, Point3, Rotation3, Translation3, UnitQuaternion, Vector3};
use parry3d_f64::bounding_volume::BoundingVolume;

/// How the collision stage is evaluated (docs/contact-model.md §4).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Mode {
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
pub struct PairState {
    /// Member of the contact set.
    pub in_contact: bool,
    /// Last `z_AB` \[m\] (AABB distance while the boxes are apart, signed distance otherwise).
    pub z: f64,
    /// Penetration velocity at contact start `δ̇⁻` [m/s] (> 0 approaching).
    pub delta_dot_minus: f64,
    /// Penetration velocity at the last contact end `δ̇⁺` [m/s] (< 0 separating).
    pub delta_dot_plus: f64,
    /// Damping factor `d` [s/m] fixed at contact start.
    pub d: f64,
    /// Last narrow-phase result (valid when the boxes overlapped).
    pub geometry: SignedDistance,
    /// Last response (zero when not in contact).
    pub response: PairResponse,
}

/// The contact set and scratch of a [`ContactPlan`].
#[derive(Clone, Debug)]
pub struct ContactState {
    /// One per candidate pair.
    pub pairs: Vec<PairState>,
    /// Indices of the pairs in the contact set.
    pub active: Vec<u32>,
    /// Pairs that entered the set at the last event.
    pub started: Vec<u32>,
    /// Pairs that left the set at the last event.
    pub ended: Vec<u32>,
    /// Narrow-phase calls so far.
    pub narrow_calls: u64,
    /// AABB distance tests (broad phase) so far.
    pub aabb_tests: u64,
    /// Narrow-phase calls that stopped at the MPR/GJK iteration limit so far (the best iterate
    /// was used; each pair is warned about once, by `tracing::warn!`).
    pub narrow_limits: u64,
    /// `limit_warned[p]`: pair `p` has been warned about its iteration limit.
    limit_warned: Vec<bool>,
    poses: Vec<Isometry3<f64>>,
    aabbs: Vec<crate::geometry::Aabb>,
    /// AABBs loosened by half the margin on every side, for the broad phase.
    grown: Vec<crate::geometry::Aabb>,
    broad: BroadPhase,
    /// Shape pairs reported by the broad phase at the last evaluation (capacity: all pairs).
    near_shapes: Vec<(u32, u32)>,
    /// Candidate pairs reported by the broad phase at the last evaluation.
    near: Vec<u32>,
    /// `in_near[p]`: pair `p` is in `near` (else its `z_AB` counts as the margin).
    in_near: Vec<bool>,
}

fn to_isometry(t: &Transform) -> Isometry3<f64> {
    Isometry3::from_parts(
        Translation3::from(t.pos),
        UnitQuaternion::from_rotation_matrix(&Rotation3::from_matrix_unchecked(t.rot)),
    )
}

/// Pose of shape `s` in world at the workspace state (`position_velocity` done).
pub(crate) fn shape_pose(cp: &ContactPlan, ws: &Workspace, s: usize) -> Isometry3<f64> {
    let sp = &cp.shapes[s];
    let t = match sp.body {
        Some(b) => ws.world[b].then(&sp.in_body),
        None => sp.in_body,
    };
    to_isometry(&t)
}

impl ContactState {
    /// The state of `cp`: empty contact set.
    pub fn new(cp: &ContactPlan) -> Self {
        let np = cp.pairs.len();
        let zero = PairState {
            in_contact: false,
            z: f64::INFINITY,
            delta_dot_minus: 0.0,
            delta_dot_plus: 0.0,
            d: 0.0,
            geometry: SignedDistance {
                distance: f64::INFINITY,
                normal: Vector3::z(),
                point_a: Point3::origin(),
                point_b: Point3::origin(),
            },
            response: PairResponse::default(),
        };
        let ns = cp.shapes.len();
        ContactState {
            pairs: vec![zero; np],
            active: Vec::with_capacity(np),
            started: Vec::with_capacity(np),
            ended: Vec::with_capacity(np),
            narrow_calls: 0,
            aabb_tests: 0,
            narrow_limits: 0,
            limit_warned: vec![false; np],
            poses: vec![Isometry3::identity(); ns],
            aabbs: vec![crate::geometry::Aabb::new_invalid(); ns],
            grown: vec![crate::geometry::Aabb::new_invalid(); ns],
            broad: BroadPhase::new(ns),
            near_shapes: Vec::with_capacity(np),
            near: Vec::with_capacity(np),
            in_near: vec![false; np],
        }
    }

    fn narrow(
        &mut self,
        plan: &Plan,
        cp: &ContactPlan,
        p: usize,
        t: f64,
    ) -> Result<SignedDistance, ContactError> {
        let pp = &cp.pairs[p];
        self.narrow_calls += 1;
        let (sd, method) = signed_distance_method(
            &cp.shapes[pp.a].shape,
            &self.poses[pp.a],
            &cp.shapes[pp.b].shape,
            &self.poses[pp.b],
            &cp.narrow,
        )
        .map_err(|source| ContactError {
            pair: cp.pair_name(&plan.scene, p),
            t,
            source,
        })?;
        if method == Method::IterationLimit {
            // The iterate is still usable (a lower bound of the distance); say so once per
            // pair, since a pair that needs more iterations usually does so at every call.
            self.narrow_limits += 1;
            if !self.limit_warned[p] {
                self.limit_warned[p] = true;
                tracing::warn!(
                    pair = %cp.pair_name(&plan.scene, p),
                    t,
                    max_iterations = cp.narrow.max_iterations,
                    "the narrow phase stopped at its iteration limit before meeting \
                     mpr_tolerance; the best iterate is used (raise mpr_max_iterations or \
                     loosen mpr_tolerance if this repeats)"
                );
            }
        }
        Ok(sd)
    }

    /// Point of application of pair `p`'s force for its narrow-phase result `sd` (poses of the
    /// same call).
    fn point(&self, cp: &ContactPlan, p: usize, sd: &SignedDistance) -> Vector3<f64> {
        let pp = &cp.pairs[p];
        contact_point(
            &cp.shapes[pp.a].shape,
            &self.poses[pp.a],
            &cp.shapes[pp.b].shape,
            &self.poses[pp.b],
            sd,
        )
        .coords
    }

    /// Evaluates the collision stage in `mode` at the workspace state (`position_velocity`
    /// done). `Continuous` adds the contact forces to `ws.f_ext`; `Event` also fills
    /// `started`/`ended`.
    pub fn evaluate(
        &mut self,
        plan: &Plan,
        cp: &ContactPlan,
        ws: &mut Workspace,
        mode: Mode,
        t: f64,
    ) -> Result<(), ContactError> {
        match mode {
            Mode::Continuous => {
                for k in 0..self.active.len() {
                    let p = self.active[k] as usize;
                    let pp = &cp.pairs[p];
                    self.poses[pp.a] = shape_pose(cp, ws, pp.a);
                    self.poses[pp.b] = shape_pose(cp, ws, pp.b);
                    let sd = self.narrow(plan, cp, p, t)?;
                    let point = self.point(cp, p, &sd);
                    let ps = &mut self.pairs[p];
                    ps.geometry = sd;
                    ps.z = sd.distance;
                    apply(cp, p, ps, &point, ws);
                }
                Ok(())
            }
            Mode::ZeroCrossing | Mode::Event => {
                for s in 0..cp.shapes.len() {
                    self.poses[s] = shape_pose(cp, ws, s);
                    self.aabbs[s] = world_aabb(&cp.shapes[s].shape, &self.poses[s]);
                    self.grown[s] = BoundingVolume::loosened(&self.aabbs[s], 0.5 * cp.margin);
                }
                // Broad phase: only candidate pairs whose loosened boxes overlap get a z_AB;
                // the others count as `margin` (see ContactPlan::margin).
                let pair_of = &cp.pair_of;
                self.broad.update(
                    &self.grown,
                    |a, b| pair_of.contains_key(&(a, b)),
                    &mut self.near_shapes,
                );
                self.aabb_tests += self.broad.box_tests();
                for &p in &self.near {
                    self.in_near[p as usize] = false;
                }
                self.near.clear();
                for &(a, b) in &self.near_shapes {
                    let p = pair_of[&(a, b)];
                    self.in_near[p as usize] = true;
                    self.near.push(p);
                }
                for k in 0..self.near.len() {
                    let p = self.near[k] as usize;
                    let pp = &cp.pairs[p];
                    let da = aabb_distance(&self.aabbs[pp.a], &self.aabbs[pp.b]);
                    // The AABB distance is a lower bound of the shapes' distance; above the
                    // end level 2ε it decides nothing (see `Hysteresis`), below it the narrow
                    // phase gives the exact value the contact-set decision needs.
                    if da > cp.hysteresis_band().end {
                        self.pairs[p].z = da;
                    } else {
                        let sd = self.narrow(plan, cp, p, t)?;
                        self.pairs[p].geometry = sd;
                        self.pairs[p].z = sd.distance;
                    }
                }
                // A pair still in the set but no longer reported moved far apart in one step:
                // its z_AB (positive) lets z_1 cross upwards.
                for k in 0..self.active.len() {
                    let p = self.active[k] as usize;
                    if !self.in_near[p] {
                        let pp = &cp.pairs[p];
                        self.pairs[p].z = aabb_distance(&self.aabbs[pp.a], &self.aabbs[pp.b]);
                    }
                }
                if mode == Mode::Event {
                    self.rebuild(cp, ws);
                }
                Ok(())
            }
        }
    }

    /// Rebuilds the contact set from the current `z` values (in contact iff `z < ε`, see
    /// [`Hysteresis`]) and fixes `δ̇⁻` and `d` of new contacts.
    fn rebuild(&mut self, cp: &ContactPlan, ws: &Workspace) {
        self.started.clear();
        self.ended.clear();
        // Pairs the broad phase no longer reports are far apart: they leave the set.
        for k in 0..self.active.len() {
            let p = self.active[k] as usize;
            if !self.in_near[p] {
                self.pairs[p].delta_dot_plus = self.normal_speed(cp, ws, p);
                self.pairs[p].in_contact = false;
                self.pairs[p].response = PairResponse::default();
                self.ended.push(p as u32);
            }
        }
        self.active.clear();
        for k in 0..self.near.len() {
            let p = self.near[k] as usize;
            let pp = &cp.pairs[p];
            let now = self.pairs[p].z < cp.hysteresis_band().decide;
            let dd = if now != self.pairs[p].in_contact {
                self.normal_speed(cp, ws, p)
            } else {
                0.0
            };
            let ps = &mut self.pairs[p];
            if now && !ps.in_contact {
                ps.delta_dot_minus = dd;
                let c = cor_reg(cp.profile, pp.cor, cp.cor_min, dd, pp.v_min);
                ps.d = if cp.exact_restitution {
                    damping_factor_exact(c, dd, pp.v_min, cp.d_max)
                } else {
                    damping_factor(c, dd, pp.v_min, cp.d_max)
                };
                self.started.push(p as u32);
            } else if !now && ps.in_contact {
                ps.delta_dot_plus = dd;
                self.ended.push(p as u32);
                ps.response = PairResponse::default();
            }
            ps.in_contact = now;
            if now {
                self.active.push(p as u32);
            }
        }
    }

    /// Penetration velocity `δ̇ = −(v_b − v_a)·n` [m/s] of pair `p` at its contact point (from
    /// the last narrow-phase result; > 0 approaching), at the workspace velocities.
    fn normal_speed(&self, cp: &ContactPlan, ws: &Workspace, p: usize) -> f64 {
        let pp = &cp.pairs[p];
        let sd = &self.pairs[p].geometry;
        let point = self.point(cp, p, sd);
        let (v1, _) = point_velocity(ws, cp.shapes[pp.a].body, &point);
        let (v2, _) = point_velocity(ws, cp.shapes[pp.b].body, &point);
        -(v2 - v1).dot(&sd.normal)
    }

    /// The two root functions from the last `z` values \[m\]: `z_1` = max over pairs in contact
    /// of `z − 2ε` (−42 if none), `z_2` = min over the others of `z`, where pairs the broad
    /// phase does not report count as `margin` apart (so `z_2 ≤ margin`). See [`Hysteresis`].
    pub fn roots(&self, cp: &ContactPlan) -> (f64, f64) {
        let band = cp.hysteresis_band();
        let mut z1 = -42.0f64;
        let mut any = false;
        for &p in &self.active {
            let z = self.pairs[p as usize].z - band.end;
            z1 = if any { z1.max(z) } else { z };
            any = true;
        }
        let mut z2 = cp.margin - band.start;
        for &p in &self.near {
            let ps = &self.pairs[p as usize];
            if !ps.in_contact {
                z2 = z2.min(ps.z - band.start);
            }
        }
        (z1, z2)
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
pub struct Hysteresis {
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
    pub fn hysteresis_band(&self) -> Hysteresis {
        Hysteresis {
            start: 0.0,
            decide: self.hysteresis,
            end: 2.0 * self.hysteresis,
        }
    }
}

/// Response of pair `p` in contact, applied to both bodies.
fn apply(cp: &ContactPlan, p: usize, ps: &mut PairState, point: &Vector3<f64>, ws: &mut Workspace) {
    let pp = &cp.pairs[p];
    let (ba, bb) = (cp.shapes[pp.a].body, cp.shapes[pp.b].body);
    let sd = &ps.geometry;
    let (v1, w1) = point_velocity(ws, ba, point);
    let (v2, w2) = point_velocity(ws, bb, point);
    let r = pair_response(cp, pp, ps.d, sd, point, &v1, &w1, &v2, &w2);
    let f = r.normal_force + r.friction_force;
    add_world_wrench(ws, bb, &r.point, &f, &r.rolling_torque);
    add_world_wrench(ws, ba, &r.point, &-f, &-r.rolling_torque);
    ps.response = r;
}
