//! `SceneOptions::exact_restitution`: the damping from the exact rebound relation of the force
//! law (modia3d-core/src/contact/restitution.rs) makes a free impact rebound with the pair's
//! cor, for every cor, mass, size, stiffness and speed — against the definition of the
//! coefficient of restitution (rebound speed / impact speed), measured on the simulated ball.

use modia3d::demo;
use modia3d::prelude::*;

fn steel() -> SolidMaterial {
    modia3d::core::scene::builtin_solid_material("Steel").unwrap()
}

/// Rebound speed / impact speed of a ball (Ø `d`, material `mat`) hitting the steel plane at
/// `v0` without gravity, with damping from the exact relation (`exact = true`) or the paper's
/// approximation.
fn rebound(d: f64, mat: SolidMaterial, v0: f64, cor: f64, k_red: f64, exact: bool) -> f64 {
    let options = SceneOptions {
        gravity: Vector3::zeros(),
        k_red,
        exact_restitution: exact,
        ..Default::default()
    };
    let pair = ContactPairMaterial::new(cor, 0.0, 0.0);
    let model = demo::sphere_on_plane(d, mat, v0, 1e-5, pair, options)
        .build()
        .unwrap();
    demo::rebound_ratio(&model, v0)
        .unwrap()
        .unwrap_or_else(|| panic!("the ball rebounds (cor {cor})"))
}

/// cor 0.1 … 0.99 on a steel ball at 1 m/s, and at cor 0.5 and 0.9 also a heavy ball (density
/// ×2), a large one (Ø ×2), a soft contact (k_red 1e-3) and a fast impact (3 m/s): the rebound
/// ratio is the cor to 1e-6 (seen: ≤ 6e-8). What remains is the regularisation `cor_reg`
/// (exp(−4.6·v0/v_min) ≈ 1e-200 here), the hysteresis band (the contact is decided at δ = −ε,
/// not 0: work of order ε/δ_max ≈ 1e-5 of the force's, nearly all of it elastic) and the
/// integration error at rtol 1e-9.
/// The paper's law, run alongside, misses cor 0.9 by about 6e-3 (0.894), which this bound
/// would reject.
#[test]
fn the_rebound_ratio_is_the_cor_asked_for() {
    let heavy = SolidMaterial {
        density: 16000.0,
        ..steel()
    };
    for cor in [0.1, 0.3, 0.5, 0.7, 0.9, 0.99] {
        let mut cases = vec![(
            "steel Ø 20 mm at 1 m/s",
            rebound(0.02, steel(), 1.0, cor, 1.0, true),
        )];
        if cor == 0.5 || cor == 0.9 {
            cases.push(("heavy", rebound(0.02, heavy, 1.0, cor, 1.0, true)));
            cases.push(("Ø 40 mm", rebound(0.04, steel(), 1.0, cor, 1.0, true)));
            cases.push(("k_red 1e-3", rebound(0.02, steel(), 1.0, cor, 1e-3, true)));
            cases.push(("3 m/s", rebound(0.02, steel(), 3.0, cor, 1.0, true)));
        }
        let paper = rebound(0.02, steel(), 1.0, cor, 1.0, false);
        for (what, e) in &cases {
            println!("cor {cor}: {what}: rebound ratio {e:.9} (paper's law {paper:.6})");
            assert!((e - cor).abs() < 1e-6, "cor {cor}, {what}: {e}");
        }
        if cor == 0.9 {
            assert!(
                (paper - cor).abs() > 3e-3,
                "the paper's law is approximate: {paper}"
            );
        }
    }
}

/// The bouncing ball of the Rapier comparison (docs/rapier-comparison.md, scene 2): a steel
/// ball Ø 0.1 m dropped from h = 0.5 m onto a steel plate with cor 0.9 and exact restitution,
/// at rtol 1e-6. Reference: the rigid bounce, apex n at h·0.9^(2n). The apex is read where the
/// upward speed at contact end has decayed (`t_e + v/g`), from IDA's own polynomial. Bound
/// 1e-3 on |apex_n/h − 0.9^(2n)| for n = 1…5 (issue 16's acceptance): the compliant contact
/// under gravity rebounds short of the cor by ≈ 0.21·g·t_c/v (t_c = 0.3 ms, gravity acts
/// during the contact; exact restitution is exact for a free impact only), which compounds to
/// 3.2e-4 at the fifth apex (seen). The paper's damping (cor 0.9 acting as ≈ 0.894) misses by
/// more than 1e-2, which the bound rejects.
#[test]
fn bounce_apexes_follow_the_cor() {
    let (d, h, g, cor) = (0.1, 0.5, 9.81, 0.9);
    let apex_errors = |exact: bool| -> Vec<f64> {
        let s = demo::steel_drop(d, h, cor, exact);
        let res = s
            .build()
            .unwrap()
            .simulate(
                &SimOptions::new(2.6)
                    .tolerance(1e-6)
                    .interval(0.026)
                    .dense_output(true)
                    .progress(false),
            )
            .unwrap();
        let ends: Vec<f64> = res
            .events
            .iter()
            .filter(|e| !e.ended.is_empty())
            .map(|e| e.t)
            .collect();
        assert!(ends.len() >= 5, "five bounces by 2.6 s: {ends:?}");
        ends[..5]
            .iter()
            .enumerate()
            .map(|(k, &te)| {
                let v = res.signal_at("ball.v_abs", te).unwrap()[2];
                let apex = res.signal_at("ball.r_abs", te + v / g).unwrap()[2] - d / 2.0;
                (apex / h - cor.powi(2 * (k as i32 + 1))).abs()
            })
            .collect()
    };
    let exact = apex_errors(true);
    println!("apex errors, exact restitution: {exact:?}");
    assert!(exact.iter().all(|e| *e < 1e-3), "{exact:?}");
    let paper = apex_errors(false);
    println!("apex errors, paper's law: {paper:?}");
    assert!(paper.iter().any(|e| *e > 1e-2), "{paper:?}");
}
