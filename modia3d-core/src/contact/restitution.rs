//! Damping that gives the coefficient of restitution asked for (`SceneOptions::exact_restitution`,
//! docs/contact-model.md §3).
//!
//! The normal law `f = k δⁿ · max(0, 1 + d δ̇)` of a two-body impact at speed `v` (no other
//! forces during the short contact) has one dimensionless parameter: with `δ = δ* x`,
//! `t = (δ*/v) τ` and `δ* = (m v²/k)^{1/(n+1)}` it reads
//!
//! ```text
//!     x'' = −xⁿ · max(0, 1 + χ x'),   x(0) = 0,  x'(0) = 1,   χ = d · v.
//! ```
//!
//! In the potential-energy coordinate `w = x^{n+1}/(n+1)` (so `dw = xⁿ dx`) the speed `p = x'`
//! obeys `p dp/dw = −(1 + χ p)`, whatever `n`: compression from `p = 1` to `0` and rebound from
//! `0` to `−e` integrate in closed form to
//!
//! ```text
//!     −χe − ln(1 − χe) = χ − ln(1 + χ),      with χ e < 1,
//! ```
//!
//! so the rebound speed ratio `e` depends on `χ` alone — for every mass, stiffness, speed and
//! exponent (Hertz 3/2 and linear alike). The paper's `d = 8(1 − e)/(5 e v)` approximates the
//! inverse (cor 0.9 gives about 0.894); [`chi_for_restitution`] solves it exactly.

/// The damping parameter `χ = d · v` [-] for which the impact rebounds with speed ratio `e`:
/// the root in `(0, 1/e)` of `g(χ) = χ − ln(1 + χ) + χe + ln(1 − χe)` (positive near 0, → −∞ at
/// 1/e), by bisection in `u = χe` to machine precision (60 halvings; contact starts only).
/// `e ≥ 1` gives 0, `e ≤ 0` gives `+∞` (the caller's `d_max` caps it).
pub(super) fn chi_for_restitution(e: f64) -> f64 {
    if e >= 1.0 {
        return 0.0;
    }
    if e.is_nan() || e <= 0.0 {
        return f64::INFINITY;
    }
    let g = |u: f64| {
        let chi = u / e;
        (chi - chi.ln_1p()) + (u + (-u).ln_1p())
    };
    let (mut lo, mut hi) = (0.0f64, 1.0f64);
    for _ in 0..60 {
        let mid = 0.5 * (lo + hi);
        // Near u = 0 both terms are O(u²) and g > 0; the root is where g turns negative.
        if mid > 0.0 && g(mid) > 0.0 {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    0.5 * (lo + hi) / e
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Rebound speed ratio of the dimensionless impact, by integrating the equation of motion
    /// directly (RK4, step ≤ 1e-3 of the contact time and of the damping's time scale): the
    /// independent reference for the closed form.
    fn rebound_ratio(chi: f64, n: f64) -> f64 {
        let acc = |x: f64, v: f64| -x.max(0.0).powf(n) * (1.0 + chi * v).max(0.0);
        let h = (1e-3f64).min(0.1 / (1.0 + chi));
        let (mut x, mut v, mut t) = (0.0f64, 1.0f64, 0.0);
        loop {
            let (k1x, k1v) = (v, acc(x, v));
            let (k2x, k2v) = (v + 0.5 * h * k1v, acc(x + 0.5 * h * k1x, v + 0.5 * h * k1v));
            let (k3x, k3v) = (v + 0.5 * h * k2v, acc(x + 0.5 * h * k2x, v + 0.5 * h * k2v));
            let (k4x, k4v) = (v + h * k3v, acc(x + h * k3x, v + h * k3v));
            let xn = x + h / 6.0 * (k1x + 2.0 * k2x + 2.0 * k3x + k4x);
            let vn = v + h / 6.0 * (k1v + 2.0 * k2v + 2.0 * k3v + k4v);
            t += h;
            if xn <= 0.0 && t > h {
                // Separation inside this step, where the force is ≈ 0: v is linear there.
                return -(vn + (v - vn) * xn / (xn - x));
            }
            (x, v) = (xn, vn);
        }
    }

    /// The closed form against direct integration, for the linear and the Hertz law: the rebound
    /// of the χ found for e is e, to 1e-5 (the RK4 separation estimate; the bisection itself is
    /// exact to rounding). The two exponents give the same e, as the derivation says.
    #[test]
    fn the_closed_form_matches_integrating_the_impact() {
        for e in [0.05, 0.1, 0.3, 0.5, 0.7, 0.9, 0.99] {
            let chi = chi_for_restitution(e);
            for n in [1.0, 1.5] {
                let got = rebound_ratio(chi, n);
                assert!(
                    (got - e).abs() < 1e-5,
                    "e = {e}, n = {n}: χ = {chi}, rebound {got}"
                );
            }
        }
        assert_eq!(chi_for_restitution(1.0), 0.0);
        assert_eq!(chi_for_restitution(0.0), f64::INFINITY);
    }

    /// Small damping against the first-order energy balance (a second independent limit): the
    /// damping force `k d δⁿ δ̇` dissipates `(2/3) m d v³` over the elastic path for n = 1 and
    /// n = 3/2 alike, so `1 − e² = (4/3) χ` and `χ/(1 − e) → 3/2` as e → 1 (Hunt and Crossley's
    /// `d = 3(1 − e)/(2v)`). At e = 0.999 the second-order terms are ~1e-3: 0.5 % is the bound.
    #[test]
    fn small_damping_limit_is_the_energy_balance() {
        let ratio = chi_for_restitution(0.999) / (1.0 - 0.999);
        assert!((ratio - 1.5).abs() < 0.0075, "χ/(1 − e) = {ratio}");
    }
}
