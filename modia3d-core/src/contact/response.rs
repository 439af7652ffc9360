//! Contact stage: the elastic response of one pair in contact (docs/contact-model.md §3). Pure function of the
//! pair's constants, its contact geometry and the two bodies' velocities; no allocation.

use super::preprocess::{ContactPlan, PairPlan};
use super::regularise::reg;
use crate::geometry::SignedDistance;
use nalgebra::Vector3;

/// Forces of one pair, all resolved in world.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct PairResponse {
    /// Penetration depth `δ = max(0, −δ_signed)` [m].
    pub penetration: f64,
    /// Penetration velocity `δ̇` [m/s] (> 0 while approaching).
    pub penetration_velocity: f64,
    /// Magnitude of the normal force `f_n` [N] (≥ 0).
    pub f_n: f64,
    /// Normal force on body 2 (`f_n · e_n`) [N].
    pub normal_force: Vector3<f64>,
    /// Sliding friction force on body 2 [N].
    pub friction_force: Vector3<f64>,
    /// Rolling-resistance torque on body 2 [N·m].
    pub rolling_torque: Vector3<f64>,
    /// Contact point [m]: where the forces act (see [`crate::geometry::contact_point`]).
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
/// start), contact geometry `sd` (normal a → b), the contact point `point` [m] and the
/// velocities of the two bodies' material points there and their angular velocities (all
/// world, [m/s], [rad/s]).
/// Body 2 receives `normal_force + friction_force` at `point` and `rolling_torque`; body 1 the
/// opposite.
#[inline]
#[allow(clippy::too_many_arguments)]
pub fn pair_response(
    cp: &ContactPlan,
    pp: &PairPlan,
    d: f64,
    sd: &SignedDistance,
    point: &Vector3<f64>,
    v1: &Vector3<f64>,
    w1: &Vector3<f64>,
    v2: &Vector3<f64>,
    w2: &Vector3<f64>,
) -> PairResponse {
    let n = sd.normal;
    let point = *point;
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
    let f_n = cp.k_red * (pp.c_res * pp.c_geo * delta_pow * (1.0 + d * delta_dot)).max(0.0);
    let friction_force = if pp.mu_k > 0.0 {
        v_t * (-pp.mu_k * f_n / reg(v_t.norm(), pp.v_min))
    } else {
        Vector3::zeros()
    };
    let rolling_torque = if pp.mu_r > 0.0 {
        w_rel * (-pp.mu_r * pp.mu_geo * f_n / reg(w_rel.norm(), pp.w_min))
    } else {
        Vector3::zeros()
    };
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
