//! Validation of scene options and user contact-pair materials: values in their ranges.

use super::{Checker, SceneError};
use crate::scene::desc::{SceneDesc, SceneOptions};
use crate::scene::GravityField;

/// The user's contact-pair materials: `cor` in [0, 1], friction ≥ 0, regularisation > 0.
pub(super) fn contact_pair_materials(c: &mut Checker, desc: &SceneDesc) {
    for (a, b, m) in &desc.contact_pairs {
        let what = |f: &str| format!("contact pair material `{a}`–`{b}`: {f}");
        c.value(
            || what("cor"),
            m.cor,
            (0.0..=1.0).contains(&m.cor),
            "in [0, 1]",
        );
        c.non_negative(|| what("mu_k"), m.mu_k);
        c.non_negative(|| what("mu_r"), m.mu_r);
        if let Some(v) = m.v_min {
            c.positive(|| what("v_min [m/s]"), v);
        }
        if let Some(w) = m.w_min {
            c.positive(|| what("w_min [rad/s]"), w);
        }
    }
}

pub(super) fn check_options(c: &mut Checker, scene: &str, o: &SceneOptions) {
    let what = |f: &str| format!("scene `{scene}`: {f}");
    c.positive(|| what("k_red"), o.k_red);
    c.positive(|| what("d_max [s/m]"), o.d_max);
    c.value(
        || what("cor_min"),
        o.cor_min,
        o.cor_min > 0.0 && o.cor_min <= 1.0,
        "in (0, 1]",
    );
    c.positive(|| what("v_min [m/s]"), o.v_min);
    c.positive(|| what("v_min_volume [m/s]"), o.v_min_volume);
    c.positive(|| what("w_min [rad/s]"), o.w_min);
    c.positive(|| what("hysteresis [m]"), o.hysteresis);
    // Relative accuracy of the narrow phase: the distance error it admits (tolerance × the
    // pair's size) acts through the contact stiffness. A 0.1 m steel cube resting on a steel
    // table (tests/contact_mpr_options.rs) takes 19,942 steps at 1e-11 and at 1e-9, 39,061 at 1e-8,
    // 34,367 at 1e-7, and never finishes at 2e-7 or 1e-6 (the step collapses to 1e-13 s).
    c.value(
        || what("mpr_tolerance (relative MPR/GJK tolerance)"),
        o.mpr_tolerance,
        o.mpr_tolerance > 0.0 && o.mpr_tolerance <= 1e-9,
        "in (0, 1e-9]",
    );
    c.value(
        || what("MPR iteration limit"),
        o.mpr_max_iterations as f64,
        o.mpr_max_iterations > 0,
        "> 0",
    );
    c.non_negative(|| what("smoothing radius [m]"), o.smoothing_radius);
    match o.gravity_field {
        Some(_) if o.gravity != SceneOptions::default().gravity => {
            c.errors.push(SceneError::ConflictingOptions {
                scene: scene.to_string(),
                first: "gravity",
                second: "gravity_field",
            })
        }
        Some(GravityField::Uniform(g)) => c.finite(|| what("gravity field [m/s²]"), g.as_slice()),
        Some(GravityField::Point { mu, centre }) => {
            c.positive(|| what("point gravity's mu [m³/s²]"), mu);
            c.finite(|| what("point gravity's centre [m]"), centre.as_slice());
        }
        Some(GravityField::None) | None => {}
    }
}
