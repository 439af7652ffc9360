//! Contact stage: the regularisations of docs/contact-model.md §3 (pure functions, no state).

use crate::scene::ContactProfile;

/// Regularised absolute value [same unit as `v`]: `|v|` for `|v| ≥ v_min`, otherwise the C²
/// polynomial `|v|²/v_min · (1 − |v|/(3 v_min)) + v_min/3` (minimum `v_min/3` at 0).
#[inline]
pub(super) fn reg(v: f64, v_min: f64) -> f64 {
    let a = v.abs();
    if a >= v_min {
        a
    } else {
        a * a / v_min * (1.0 - a / (3.0 * v_min)) + v_min / 3.0
    }
}

/// Slope `d reg(v)/d|v|` [-] of [`reg`] at `|v|` (1 above `v_min`, `2|v|/v_min − |v|²/v_min²`
/// below; 0 at 0).
#[inline]
pub(super) fn reg_slope(v: f64, v_min: f64) -> f64 {
    let a = v.abs();
    if a >= v_min {
        1.0
    } else {
        a / v_min * (2.0 - a / v_min)
    }
}

/// Half-width of the band of [`soft_clamp`] [-].
pub(crate) const CLAMP_BAND: f64 = 1e-4;

/// `max(0, x)` made C¹ over `|x| < CLAMP_BAND` by the parabola `(x + b)²/(4b)`: the damping
/// factor `1 + d·δ̇` of the normal force. Why: a contact whose bodies separate at `1/d` (1 mm/s
/// at `d = d_max`) sits on the clamp's kink with the huge slope `f_el·d` on one side, and
/// Newton's method cannot converge across it (measured: a 10 g box 1.2 cm deep against a
/// spinning 4.5 kg cylinder, found by the scene fuzzer, stalled at 5e-12 s steps; with the band
/// it takes 931 steps to separate). Outside the band the law is unchanged; inside, the force is
/// at most `f_el·b/4` larger than the clamp's; the extra impulse is of order `b²` (with
/// b = 1e-3 an exact-restitution rebound at cor 0.1 came out 0.10001, with 1e-4 exact to 1e-9).
#[inline]
pub(super) fn soft_clamp(x: f64) -> f64 {
    let b = CLAMP_BAND;
    if x >= b {
        x
    } else if x <= -b {
        0.0
    } else {
        (x + b) * (x + b) / (4.0 * b)
    }
}

/// Slope `d soft_clamp(x)/dx` [-] of [`soft_clamp`]: 1 above the band, 0 below, `(x + b)/(2b)`
/// inside (the branch [`soft_clamp`] evaluates at its ends).
#[inline]
pub(super) fn soft_clamp_slope(x: f64) -> f64 {
    let b = CLAMP_BAND;
    if x >= b {
        1.0
    } else if x <= -b {
        0.0
    } else {
        (x + b) / (2.0 * b)
    }
}

/// Regularised coefficient of restitution [-] for the contact-start penetration velocity
/// `dd_minus` [m/s]: `Paper2019` and `Volume`: `cor + (cor_min − cor)·exp(ln(0.01)·|δ̇⁻|/v_min)`;
/// `Modia3DLater`: 0 when `|δ̇⁻| ≤ v_min`, else `cor`.
#[inline]
pub(super) fn cor_reg(
    profile: ContactProfile,
    cor: f64,
    cor_min: f64,
    dd_minus: f64,
    v_min: f64,
) -> f64 {
    match profile {
        ContactProfile::Paper2019 | ContactProfile::Volume => {
            cor + (cor_min - cor) * (0.01f64.ln() * dd_minus.abs() / v_min).exp()
        }
        ContactProfile::Modia3DLater => {
            if dd_minus.abs() <= v_min {
                0.0
            } else {
                cor
            }
        }
    }
}

/// Damping factor `d` [s/m] fixed at contact start:
/// `min(d_max, 8 (1 − cor_reg) / (5 · cor_reg · reg(δ̇⁻, v_min)))` (`d_max` when `cor_reg = 0`).
#[inline]
pub(super) fn damping_factor(cor_reg: f64, dd_minus: f64, v_min: f64, d_max: f64) -> f64 {
    if cor_reg <= 0.0 {
        return d_max;
    }
    let d = 8.0 * (1.0 - cor_reg) / (5.0 * cor_reg * reg(dd_minus, v_min));
    d.min(d_max)
}

/// Damping factor `d` [s/m] fixed at contact start that makes the impact rebound with exactly
/// `cor_reg` ([`super::restitution::chi_for_restitution`]): `min(d_max, χ(cor_reg) / reg(δ̇⁻,
/// v_min))` (`d_max` when `cor_reg = 0`).
#[inline]
pub(super) fn damping_factor_exact(cor_reg: f64, dd_minus: f64, v_min: f64, d_max: f64) -> f64 {
    let chi = super::restitution::chi_for_restitution(cor_reg);
    (chi / reg(dd_minus, v_min)).min(d_max)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn reg_is_c1_at_v_min_and_has_its_minimum_at_zero() {
        let vm = 0.01;
        assert!((reg(0.0, vm) - vm / 3.0).abs() < 1e-15);
        assert!((reg(vm * (1.0 - 1e-9), vm) - vm).abs() < 1e-10);
        let h = 1e-7;
        let slope = (reg(vm, vm) - reg(vm - h, vm)) / h;
        assert!((slope - 1.0).abs() < 1e-4, "slope {slope}");
        assert_eq!(reg(-0.5, vm), 0.5);
    }

    #[test]
    fn soft_clamp_is_c1_and_the_clamp_outside_its_band() {
        let b = CLAMP_BAND;
        assert_eq!(soft_clamp(0.7), 0.7);
        assert_eq!(soft_clamp(-0.3), 0.0);
        assert_eq!(soft_clamp(b), b);
        assert_eq!(soft_clamp(-b), 0.0);
        assert!((soft_clamp(0.0) - b / 4.0).abs() < 1e-18);
        // Slopes meet at both ends of the band: 1 at +b, 0 at −b.
        let h = 1e-9 * b;
        let slope = |x: f64| (soft_clamp(x + h) - soft_clamp(x - h)) / (2.0 * h);
        assert!((slope(b - 2.0 * h) - 1.0).abs() < 1e-5 && slope(-b + 2.0 * h).abs() < 1e-5);
    }

    #[test]
    fn cor_reg_blends_from_cor_min_to_cor() {
        let p = ContactProfile::Paper2019;
        assert!((cor_reg(p, 0.7, 0.001, 0.0, 0.01) - 0.001).abs() < 1e-15);
        assert!((cor_reg(p, 0.7, 0.001, 1.0, 0.01) - 0.7).abs() < 1e-12);
        let l = ContactProfile::Modia3DLater;
        assert_eq!(cor_reg(l, 0.7, 0.001, 0.005, 0.01), 0.0);
        assert_eq!(cor_reg(l, 0.7, 0.001, 0.02, 0.01), 0.7);
        assert_eq!(damping_factor(0.0, 1.0, 0.01, 1000.0), 1000.0);
        assert_eq!(damping_factor(1.0, 1.0, 0.01, 1000.0), 0.0);
    }
}
