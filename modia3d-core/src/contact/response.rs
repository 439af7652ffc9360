//! Contact stage: the elastic response of one pair in contact (docs/contact-model.md §3). Pure function of the
//! pair's constants, its contact geometry and the two bodies' velocities; no allocation.

use super::preprocess::{ContactPlan, PairPlan};
use super::regularise::{reg, soft_clamp};
use crate::geometry::{ContactPatch, SignedDistance};
use nalgebra::Vector3;

/// Forces of one pair, all resolved in world.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct PairResponse {
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
    pub const ZERO: PairResponse = PairResponse {
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
pub fn pair_response(
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
    let friction_force = if pp.mu_k > 0.0 {
        v_t * (-pp.mu_k * f_n / reg(v_t.norm(), pp.v_min))
    } else {
        Vector3::zeros()
    };
    let mut rolling_torque = if pp.mu_r > 0.0 {
        w_rel * (-pp.mu_r * pp.mu_geo * f_n / reg(w_rel.norm(), pp.w_min))
    } else {
        Vector3::zeros()
    };
    if spread > 0.0 {
        let w_t = w_rel - n * n.dot(&w_rel);
        let rocking = w_t * (-d * f_el * 0.5 * spread);
        let cap = f_n * spread.sqrt();
        let m = rocking.norm();
        rolling_torque += if m > cap {
            rocking * (cap / m)
        } else {
            rocking
        };
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
