//! Contact stage: the elastic response of one pair in contact (docs/contact-model.md §3). Pure function of the
//! pair's constants, its contact geometry and the two bodies' velocities; no allocation.

use super::preprocess::{ContactPlan, PairPlan};
use super::regularise::{reg, soft_clamp};
use crate::geometry::overlap::Overlap;
use crate::geometry::{ContactPatch, SignedDistance};
use nalgebra::Vector3;

/// Forces of one pair, all resolved in world.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub(crate) struct PairResponse {
    /// Penetration depth `δ = max(0, −δ_signed)` \[m\].
    pub penetration: f64,
    /// Penetration velocity `δ̇` [m/s] (> 0 while approaching).
    pub penetration_velocity: f64,
    /// Magnitude of the normal force `f_n` \[N\] (≥ 0).
    pub f_n: f64,
    /// Normal force on body 2 (`f_n · e_n`) \[N\].
    pub normal_force: Vector3<f64>,
    /// Sliding friction force on body 2 \[N\].
    pub friction_force: Vector3<f64>,
    /// Torque on body 2 [N·m]: rolling resistance plus the rocking damping of a contact patch
    /// (see [`pair_response`]).
    pub rolling_torque: Vector3<f64>,
    /// Contact point \[m\]: where the forces act (see [`crate::geometry::contact_point`]).
    pub point: Vector3<f64>,
    /// Unit normal from body 1 (shape a) to body 2 (shape b).
    pub normal: Vector3<f64>,
}

impl PairResponse {
    /// No contact: everything zero.
    pub(crate) const ZERO: PairResponse = PairResponse {
        penetration: 0.0,
        penetration_velocity: 0.0,
        f_n: 0.0,
        normal_force: Vector3::new(0.0, 0.0, 0.0),
        friction_force: Vector3::new(0.0, 0.0, 0.0),
        rolling_torque: Vector3::new(0.0, 0.0, 0.0),
        point: Vector3::new(0.0, 0.0, 0.0),
        normal: Vector3::new(0.0, 0.0, 0.0),
    };
}

/// The response law of docs/contact-model.md §3 for pair `pp` with damping factor `d` [s/m] (fixed at contact
/// start), contact geometry `sd` (normal a → b), the contact point `point` \[m\], the spread
/// `spread` \[m²\] of the pressure around it ([`crate::geometry::contact_patch`]; 0 for point
/// contacts) and the velocities of the two bodies' material points there and their angular
/// velocities (all world, [m/s], [rad/s]).
/// Body 2 receives `normal_force + friction_force` at `point` and `rolling_torque`; body 1 the
/// opposite.
///
/// Rocking damping of a patch: the law's damping term `c·δⁿ·d·δ̇` read as a density over the
/// patch (the elastic layer whose centre of pressure is `point`) also acts on the local
/// penetration rate `(ω_rel × x)·n` of a patch that rocks, which adds the torque
/// `−d·f_el·(spread/2)·ω_t` about the point (`f_el = k_red·c·c_geo·δⁿ`, `ω_t` the relative
/// angular velocity across the normal, `spread/2` the pressure's second moment per rocking
/// axis, taken as isotropic). The force law and the point are unchanged; a flat box thus damps
/// its rocking on a table like its bouncing (without it only the rolling resistance did, at a
/// damping ratio of ~1e-3 for a steel cube, and the undamped rocking at tens of kHz held IDA
/// to microsecond steps). Capped at `f_n·√spread`, the largest moment a non-negative pressure
/// of that spread can have.
// Inlined into its two callers (`contact_set.rs`): the 144-byte result is then written
// straight into the pair's state instead of through a copy.
#[inline(always)]
#[allow(clippy::too_many_arguments)]
pub(super) fn pair_response(
    cp: &ContactPlan,
    pp: &PairPlan,
    d: f64,
    sd: &SignedDistance,
    patch: &ContactPatch,
    v1: &Vector3<f64>,
    w1: &Vector3<f64>,
    v2: &Vector3<f64>,
    w2: &Vector3<f64>,
) -> PairResponse {
    let n = sd.normal;
    let point = patch.point.coords;
    let spread = patch.spread;
    let delta = (-sd.distance).max(0.0);
    let v_rel = v2 - v1;
    let vn = v_rel.dot(&n);
    let delta_dot = -vn;
    let v_t = v_rel - n * vn;
    let w_rel = w2 - w1;
    let delta_pow = if pp.n_geo == 1.5 {
        delta * delta.sqrt()
    } else if pp.n_geo == 1.0 {
        delta
    } else {
        delta.powf(pp.n_geo)
    };
    let f_el = cp.k_red * pp.c_res * pp.c_geo * delta_pow;
    let f_n = f_el * soft_clamp(1.0 + d * delta_dot);
    let (friction_force, mut rolling_torque) =
        friction_and_rolling(pp, f_n, &v_t, &w_rel, pp.mu_geo);
    if spread > 0.0 {
        let w_t = w_rel - n * n.dot(&w_rel);
        rolling_torque += capped(w_t * (-d * f_el * 0.5 * spread), f_n * spread.sqrt());
    }
    PairResponse {
        penetration: delta,
        penetration_velocity: delta_dot,
        f_n,
        normal_force: n * f_n,
        friction_force,
        rolling_torque,
        point,
        normal: n,
    }
}

/// The regularised sliding friction force (`−μ_k·f_n·v_t/reg(|v_t|, v_slip)`, \[N\]) and the
/// rolling resistance torque (`−μ_r·lever·f_n·ω_rel/reg(|ω_rel|, ω_min)`, \[N·m\]) of pair
/// `pp` for normal force `f_n` \[N\], sliding velocity `v_t` [m/s], relative angular velocity
/// `w_rel` [rad/s] and the rolling lever `lever` \[m\] (docs/contact-model.md §3).
#[inline(always)]
fn friction_and_rolling(
    pp: &PairPlan,
    f_n: f64,
    v_t: &Vector3<f64>,
    w_rel: &Vector3<f64>,
    lever: f64,
) -> (Vector3<f64>, Vector3<f64>) {
    let friction = if pp.mu_k > 0.0 {
        v_t * (-pp.mu_k * f_n / reg(v_t.norm(), pp.v_slip))
    } else {
        Vector3::zeros()
    };
    let rolling = if pp.mu_r > 0.0 {
        w_rel * (-pp.mu_r * lever * f_n / reg(w_rel.norm(), pp.w_min))
    } else {
        Vector3::zeros()
    };
    (friction, rolling)
}

/// `torque` scaled down to the norm `cap` if it is longer (the largest moment a non-negative
/// pressure can have).
#[inline(always)]
fn capped(torque: Vector3<f64>, cap: f64) -> Vector3<f64> {
    let m = torque.norm();
    if m > cap {
        torque * (cap / m)
    } else {
        torque
    }
}

/// A volume-law pair's geometry: the overlap of its sharp shapes (area vector from shape a to
/// shape b) and, for a cylinder or cone, the unit axis of that body of revolution.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct VolumeGeometry {
    /// The overlap.
    pub overlap: Overlap,
    /// Unit axis of the pair's cylinder or cone, resolved in world; zero for two polytopes.
    pub axis: Vector3<f64>,
    /// The cylinder or cone is shape b (else shape a).
    pub axis_on_b: bool,
}

impl VolumeGeometry {
    /// No overlap.
    pub(crate) const NONE: VolumeGeometry = VolumeGeometry {
        overlap: Overlap::NONE,
        axis: Vector3::new(0.0, 0.0, 0.0),
        axis_on_b: false,
    };
}

/// Damping ratio of the contact modes of a volume-law contact that started slowly, and the
/// window speed it fades with (docs/contact-model.md §3.2, "Resting contacts").
pub(super) const RESTING_DAMPING_RATIO: f64 = 1.0;

/// The resting-damping coefficient `2·ζ_rest·√m` \[kg^½\] of a volume-law contact between
/// bodies of masses `m_a`, `m_b` \[kg\] (infinite for a shape fixed to the world), `m` their
/// reduced mass (translation only) and `ζ_rest` = [`RESTING_DAMPING_RATIO`]. The law's window
/// `ψ` keeps it to motions slower than `v_min`, so impacts keep the restitution of `d`.
pub(super) fn resting_damping(m_a: f64, m_b: f64) -> f64 {
    let m = if m_a.is_infinite() {
        m_b
    } else if m_b.is_infinite() {
        m_a
    } else {
        m_a * m_b / (m_a + m_b)
    };
    if !m.is_finite() {
        return 0.0;
    }
    2.0 * RESTING_DAMPING_RATIO * m.sqrt()
}

/// The volume law of docs/contact-model.md §3.2 for pair `pp` (a volume-law pair), damping
/// factor `d` [s/m] and resting-damping coefficient `rest` [kg^½] ([`resting_damping`]), both
/// fixed at contact start, the overlap `ov` of the two sharp shapes (its area vector pointing
/// from shape a to shape b) and the velocities of the two bodies' material points at the
/// overlap's centroid and their angular velocities (world, [m/s], [rad/s]).
///
/// With `κ_v = k_red·κ`, `V` the volume, `A = |area vector|` (the overlap's area across the
/// normal `n`), `Σ` the second moment about the centroid and `Σ_n = [n]× Σ [n]×ᵀ` its part that
/// rocking about axes across `n` sees (zero for rotation about a line contact's own axis and
/// for spin about `n`):
///
/// ```text
/// f_el  = κ_v·V
/// c_r   = rest·√(κ_v·A)·ψ,   ψ = exp(−(δ̇² + ω_lᵀΣ_n ω_l/V)/v_min²)   resting damping [N·s/m]
/// f_n   = f_el·soft_clamp(1 + (d + c_r/f_el)·δ̇)                      at the centroid, along n
/// τ_rock = −(κ_v·d + c_r/V)·Σ_n·ω_l,  |τ_rock| ≤ f_n·√(1.5·tr Σ_n/V)
/// F_t   = −μ_k·f_n·v_t/reg(|v_t|, v_slip)                            at the centroid
/// τ_r   = −μ_r·ρ·f_n·ω_rel/reg(|ω_rel|, ω_min),   ρ = √(tr Σ_n/V)
/// τ_s   = −μ_k·f_n·l·(l·ω_n)/reg(|l·ω_n|, v_slip)·n,   l = (2√2/3)·ρ,  ω_n = n·ω_rel
/// ```
///
/// `ω_l` is `ω_rel` less the spin of a cylinder or cone about its own axis (which does not move
/// its surface). The damping per unit volume `κ_v·d·h·ḣ` of a layer of local depth `h` integrates to the
/// `d` terms exactly (the centroid's first moment vanishes), so heave and rocking are damped
/// alike. Body 2 receives `normal_force + friction_force` at `point` and `rolling_torque`;
/// body 1 the opposite.
#[inline]
#[allow(clippy::too_many_arguments)]
pub(super) fn volume_response(
    cp: &ContactPlan,
    pp: &PairPlan,
    d: f64,
    rest: f64,
    vg: &VolumeGeometry,
    v1: &Vector3<f64>,
    w1: &Vector3<f64>,
    v2: &Vector3<f64>,
    w2: &Vector3<f64>,
) -> PairResponse {
    let ov = &vg.overlap;
    let area = ov.area_vector.norm();
    let point = ov.centroid.coords;
    if !(ov.volume > 0.0 && area > 0.0) {
        return PairResponse {
            point,
            ..PairResponse::ZERO
        };
    }
    let n = ov.area_vector / area;
    let kv = cp.k_red * pp.kappa;
    let volume = ov.volume;
    let f_el = kv * volume;
    let v_rel = v2 - v1;
    let vn = v_rel.dot(&n);
    let delta_dot = -vn;
    let v_t = v_rel - n * vn;
    let w_rel = w2 - w1;
    // What the layer sees: a body of revolution spinning about its own axis does not move its
    // surface, so that spin neither compresses nor relaxes the layer (a cylinder rolls on its
    // line contact without damping; rolling resistance is μ_r's).
    let w_layer = {
        let w_side = if vg.axis_on_b { w2 } else { w1 };
        let spin = vg.axis * vg.axis.dot(w_side);
        if vg.axis_on_b {
            w_rel - spin
        } else {
            w_rel + spin
        }
    };
    let nx = n.cross_matrix();
    let sigma_n = nx * ov.second_moment * nx.transpose();
    let rho2 = (sigma_n.trace() / volume).max(0.0);
    // The mean square of the local penetration rates over the overlap: heave plus rocking
    // (a rolling cylinder's line contact sees only the strip's width).
    let rock2 = (w_layer.dot(&(sigma_n * w_layer)) / volume).max(0.0);
    let window = (delta_dot * delta_dot + rock2) / (pp.v_min * pp.v_min);
    let c_rest = rest * (kv * area).sqrt() * (-window).exp();
    let f_n = f_el * soft_clamp(1.0 + (d + c_rest / f_el) * delta_dot);
    let (friction_force, mut rolling_torque) =
        friction_and_rolling(pp, f_n, &v_t, &w_rel, rho2.sqrt());
    // Spin friction: the sliding friction of a patch spinning about its normal, its lever the
    // Coulomb lever (2√2/3)·ρ of a uniform disc or square patch of rms radius ρ, regularised
    // like sliding at the patch's rms slip speed.
    if pp.mu_k > 0.0 {
        let lever = 2.0 * std::f64::consts::SQRT_2 / 3.0 * rho2.sqrt();
        let w_n = n.dot(&w_rel);
        let slip = w_n * lever;
        rolling_torque += n * (-pp.mu_k * f_n * lever * slip / reg(slip, pp.v_slip));
    }
    let rocking = sigma_n * w_layer * (-(kv * d + c_rest / volume));
    rolling_torque += capped(rocking, f_n * (1.5 * rho2).sqrt());
    PairResponse {
        penetration: volume / area,
        penetration_velocity: delta_dot,
        f_n,
        normal_force: n * f_n,
        friction_force,
        rolling_torque,
        point,
        normal: n,
    }
}
