//! Contact stage: joint limits as compliant stops (docs/joint-limits.md). Each bound of a
//! limited scalar coordinate is a *stop*, one more "pair" of the contact events: its gap
//! `z = s·(q − bound)` (`s = +1` at a lower, `−1` at an upper bound; > 0 inside the range)
//! enters the same two root functions with the same hysteresis as the collision pairs
//! (docs/contact-model.md §4, `Hysteresis`), and in contact its generalised force is the
//! contact law of §3 in joint space, linear (`n = 1`):
//!
//! ```text
//!     δ = max(0, −z),  δ̇ = −s·q̇,  f = s · k·δ · soft_clamp(1 + d·δ̇)     on the coordinate
//! ```
//!
//! with `d` fixed at the stop's start event from the stop's cor at the impact speed `δ̇⁻` by the
//! contacts' own functions (`regularise.rs`: `cor_reg`, `damping_factor` or, with
//! `SceneOptions::exact_restitution`, `damping_factor_exact`). `(&LimitPlan, &mut LimitState)`
//! read the coordinates `q`, `v` directly (no kinematics) and add into the generalised forces
//! `ws.tau_applied`. A scene without limits has no `LimitPlan`: none of this runs.

use super::contact_set::Hysteresis;
use super::regularise::{
    cor_reg, damping_factor, damping_factor_exact, soft_clamp, soft_clamp_slope,
};
use crate::dynamics::{mass_matrix, Plan, Workspace};
use crate::scene::ContactProfile;

/// The angular frequency `ω_s` [rad/s] of a stop whose stiffness is not given: `k = M_kk·ω_s²`
/// with `M_kk` the coordinate's effective inertia \[kg·m² or kg\] at the initial state
/// (docs/joint-limits.md argues it: a contact lasting `π/ω_s` ≈ 0.3 ms, a static penetration
/// `(g/l)/ω_s²` = 1e-7 rad for a 1 m pendulum resting on its stop).
pub const DEFAULT_STOP_FREQUENCY: f64 = 1e4;

/// Regularisation speed `v_min` of the stops' cor \[rad/s or m/s\] (the contacts' default
/// `v_min`, in the coordinate's unit per second).
const STOP_V_MIN: f64 = 0.01;

/// One bound of a limited coordinate.
#[derive(Clone, Debug)]
pub(crate) struct Stop {
    /// `"<joint>.<coordinate>.lower"` or `".upper"` (events and contact phases).
    pub name: String,
    /// Index into [`LimitPlan::limits`].
    pub limit: usize,
    /// Index of the coordinate's position in `q`.
    pub q: usize,
    /// Index of its velocity in `v`.
    pub v: usize,
    /// The bound \[rad or m\].
    pub bound: f64,
    /// `+1` at a lower bound (the stop pushes `q` up), `−1` at an upper one.
    pub sign: f64,
    /// Stiffness \[N·m/rad or N/m\].
    pub k: f64,
    /// Coefficient of restitution \[-\].
    pub cor: f64,
}

/// A limited coordinate: its signal.
#[derive(Clone, Debug)]
pub(crate) struct LimitSignal {
    /// `"<joint>.limit_f"` (a joint with one scalar coordinate) or `"<joint>.limit_f_<coordinate>"`.
    pub name: String,
    /// `"N·m"` (an angle) or `"N"` (a translation).
    pub unit: &'static str,
    /// Index of the coordinate's velocity in `v` (the row its force enters).
    pub v: usize,
}

/// The stops of a plan (immutable once built).
#[derive(Clone, Debug)]
pub(crate) struct LimitPlan {
    /// Every stop, in joint and coordinate order, the lower before the upper.
    pub stops: Vec<Stop>,
    /// The limited coordinates (the stops' `limit`).
    pub limits: Vec<LimitSignal>,
    band: Hysteresis,
    profile: ContactProfile,
    cor_min: f64,
    d_max: f64,
    exact: bool,
}

impl LimitPlan {
    /// The stops of `plan`'s joints; `None` without any. The default stiffness needs the
    /// effective inertia of each limited coordinate: the diagonal of the mass matrix at the
    /// initial state (one pass per tree, at build time). A limit on a joint that is not in
    /// the spanning tree (a cut joint) is refused by validation (`SceneError::LimitOnCutJoint`).
    pub(crate) fn compile(plan: &Plan) -> Option<LimitPlan> {
        let scene = &plan.scene;
        if scene.joints.iter().all(|j| j.limits.is_empty()) {
            return None;
        }
        let mut ws = Workspace::new(plan);
        let mut inertia = vec![0.0; plan.nv];
        for (g, m) in mass_matrix::tree_mass_matrices(plan, &mut ws, &plan.q0) {
            for (r, &i) in g.iter().enumerate() {
                inertia[i] = m[(r, r)];
            }
        }
        let (mut stops, mut limits) = (vec![], vec![]);
        for (sj, j) in scene.joints.iter().enumerate() {
            if j.limits.is_empty() {
                continue;
            }
            // Validation refuses limits on a cut joint (`SceneError::LimitOnCutJoint`).
            let Some(tj) = plan.tree_joint_of.get(sj).copied().flatten() else {
                continue;
            };
            let jp = &plan.joints[tj];
            let coords = jp.coord.coordinates();
            for l in &j.limits {
                let c = &coords[l.coordinate];
                let (q, v) = (jp.q_offset + c.q, jp.v_offset + c.v);
                let k = l
                    .stiffness
                    .unwrap_or(inertia[v].max(f64::MIN_POSITIVE) * DEFAULT_STOP_FREQUENCY.powi(2));
                let limit = limits.len();
                limits.push(LimitSignal {
                    name: if coords.len() == 1 {
                        format!("{}.limit_f", j.name)
                    } else {
                        format!("{}.limit_f_{}", j.name, c.name)
                    },
                    unit: if c.unit == "rad" { "N·m" } else { "N" },
                    v,
                });
                for (side, bound, sign) in [("lower", l.lower, 1.0), ("upper", l.upper, -1.0)] {
                    if bound.is_finite() {
                        stops.push(Stop {
                            name: format!("{}.{}.{side}", j.name, c.name),
                            limit,
                            q,
                            v,
                            bound,
                            sign,
                            k,
                            cor: l.cor,
                        });
                    }
                }
            }
        }
        let o = &scene.options;
        (!stops.is_empty()).then(|| LimitPlan {
            stops,
            limits,
            band: Hysteresis::of(o.hysteresis),
            profile: o.contact_profile,
            cor_min: o.cor_min,
            d_max: o.d_max,
            exact: o.exact_restitution,
        })
    }

    /// Gap `z` \[rad or m\] of stop `s` at positions `q` (> 0 inside the range).
    #[inline]
    fn gap(&self, s: usize, q: &[f64]) -> f64 {
        let st = &self.stops[s];
        st.sign * (q[st.q] - st.bound)
    }
}

/// Mutable state of the stops: which are in contact, their damping, last forces, and the
/// stops that started and ended at the last event (ids: indices into [`LimitPlan::stops`]).
#[derive(Clone, Debug)]
pub(crate) struct LimitState {
    /// Per stop: member of the contact set.
    in_contact: Vec<bool>,
    /// Per stop: damping factor `d` [s/rad or s/m] fixed at its start.
    d: Vec<f64>,
    /// Per stop: penetration `δ` \[rad or m\] and force magnitude `k·δ·soft_clamp(…)` at the
    /// last evaluation of the stops in contact (zero for the others; [`Self::sample`]).
    penetration: Vec<f64>,
    /// See `penetration`.
    f_n: Vec<f64>,
    /// Stops in contact, in stop order.
    active: Vec<u32>,
    /// Stops that entered the contact set at the last event.
    pub started: Vec<u32>,
    /// Stops that left it.
    pub ended: Vec<u32>,
    /// Approach speed `δ̇⁻` \[rad/s or m/s\] of each stop in `started` (> 0 approaching).
    pub started_speed: Vec<f64>,
    /// `δ̇⁺` of each stop in `ended` (< 0 separating).
    pub ended_speed: Vec<f64>,
}

impl LimitState {
    /// No stop in contact (the first event decides).
    pub(crate) fn new(lp: &LimitPlan) -> Self {
        let n = lp.stops.len();
        LimitState {
            in_contact: vec![false; n],
            d: vec![0.0; n],
            penetration: vec![0.0; n],
            f_n: vec![0.0; n],
            active: Vec::with_capacity(n),
            started: Vec::with_capacity(n),
            ended: Vec::with_capacity(n),
            started_speed: Vec::with_capacity(n),
            ended_speed: Vec::with_capacity(n),
        }
    }

    /// Penetration \[rad or m\] and force magnitude \[N·m or N\] of stop `s` at the last
    /// evaluation (zero while apart); `None` for no such stop.
    pub(crate) fn sample(&self, s: usize) -> Option<(f64, f64)> {
        Some((*self.penetration.get(s)?, *self.f_n.get(s)?))
    }

    /// The stops in contact (ids).
    pub(crate) fn active(&self) -> impl Iterator<Item = usize> + '_ {
        self.active.iter().map(|&s| s as usize)
    }

    /// Event mode at `(q, v)`: a stop is in contact iff `z < ε` (`Hysteresis::decide`); a stop
    /// that enters stores `δ̇⁻` and its damping. Returns whether the set changed.
    pub(crate) fn event(&mut self, lp: &LimitPlan, q: &[f64], v: &[f64]) -> bool {
        self.started.clear();
        self.ended.clear();
        self.started_speed.clear();
        self.ended_speed.clear();
        self.active.clear();
        for (s, st) in lp.stops.iter().enumerate() {
            let now = lp.gap(s, q) < lp.band.decide;
            let dd = -st.sign * v[st.v];
            if now && !self.in_contact[s] {
                let c = cor_reg(lp.profile, st.cor, lp.cor_min, dd, STOP_V_MIN);
                self.d[s] = if lp.exact {
                    damping_factor_exact(c, dd, STOP_V_MIN, lp.d_max)
                } else {
                    damping_factor(c, dd, STOP_V_MIN, lp.d_max)
                };
                self.started.push(s as u32);
                self.started_speed.push(dd);
            } else if !now && self.in_contact[s] {
                self.ended.push(s as u32);
                self.ended_speed.push(dd);
                self.penetration[s] = 0.0;
                self.f_n[s] = 0.0;
            }
            self.in_contact[s] = now;
            if now {
                self.active.push(s as u32);
            }
        }
        !self.started.is_empty() || !self.ended.is_empty()
    }

    /// The two root functions over the stops, as `ContactState::roots` forms them over pairs:
    /// `z_1` = max over stops in contact of `z − 2ε` (−42 if none), `z_2` = min over the others
    /// of `z` (42 if none).
    pub(crate) fn roots(&self, lp: &LimitPlan, q: &[f64]) -> (f64, f64) {
        let (mut z1, mut z2) = (-42.0f64, 42.0f64);
        let mut any = false;
        for s in 0..lp.stops.len() {
            let z = lp.gap(s, q);
            if self.in_contact[s] {
                let z = z - lp.band.end;
                z1 = if any { z1.max(z) } else { z };
                any = true;
            } else {
                z2 = z2.min(z - lp.band.start);
            }
        }
        (z1, z2)
    }

    /// Continuous mode: the generalised forces of the stops in contact at `(q, v)` added to
    /// `tau` (indexed by velocity).
    pub(crate) fn apply(&mut self, lp: &LimitPlan, q: &[f64], v: &[f64], tau: &mut [f64]) {
        self.evaluate(lp, q, v);
        for &s in &self.active {
            let st = &lp.stops[s as usize];
            tau[st.v] += st.sign * self.f_n[s as usize];
        }
    }

    /// The penetrations and force magnitudes of the stops in contact at `(q, v)` (for output
    /// points and contact phases; [`Self::apply`] also adds them to the dynamics).
    pub(crate) fn evaluate(&mut self, lp: &LimitPlan, q: &[f64], v: &[f64]) {
        for &s in &self.active {
            let s = s as usize;
            let st = &lp.stops[s];
            let delta = (-lp.gap(s, q)).max(0.0);
            let dd = -st.sign * v[st.v];
            self.penetration[s] = delta;
            self.f_n[s] = st.k * delta * soft_clamp(1.0 + self.d[s] * dd);
        }
    }

    /// The derivatives of the dynamics rows (`… − τ`) with respect to the coordinate and its
    /// rate, `(∂/∂q, ∂/∂q̇)` of `−s·f`, of the stops in contact at `(q, v)`, added per
    /// velocity index into `kd` (the analytic Jacobian of hinge trees).
    pub(crate) fn row_derivatives(
        &self,
        lp: &LimitPlan,
        q: &[f64],
        v: &[f64],
        kd: &mut [(f64, f64)],
    ) {
        for &s in &self.active {
            let s = s as usize;
            let st = &lp.stops[s];
            let delta = (-lp.gap(s, q)).max(0.0);
            if delta <= 0.0 {
                continue;
            }
            let x = 1.0 + self.d[s] * (-st.sign * v[st.v]);
            // −s·f with δ = −s(q − b), δ̇ = −s q̇: ∂/∂q = k·soft_clamp(x), ∂/∂q̇ = k·δ·d·soft_clamp'(x).
            kd[st.v].0 += st.k * soft_clamp(x);
            kd[st.v].1 += st.k * delta * self.d[s] * soft_clamp_slope(x);
        }
    }

    /// The generalised force \[N·m or N\] of each limited coordinate (`LimitPlan::limits`)
    /// at the last evaluation, into `out` (cleared first).
    pub(crate) fn forces(&self, lp: &LimitPlan, out: &mut Vec<f64>) {
        out.clear();
        out.resize(lp.limits.len(), 0.0);
        for &s in &self.active {
            let st = &lp.stops[s as usize];
            out[st.limit] += st.sign * self.f_n[s as usize];
        }
    }
}
