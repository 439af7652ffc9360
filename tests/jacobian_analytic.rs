//! The DAE's own Jacobian columns for free bodies (`modia3d-core/src/dae/jacobian.rs`: exact
//! blocks, pair-local quotients for the contacts) against the coloured difference quotients
//! of every block (`SimOptions::analytic_jacobian(false)`), at rtol 1e-5: the same events (the same pairs starting and ending, in order),
//! final positions as close to a tight reference run (rtol 1e-9) as the quotients' run, and no
//! residual evaluation spent on Jacobians. The entries themselves are checked against central
//! differences by the unit tests next to the code.

use modia3d::demo;
use modia3d::prelude::*;

fn final_positions(res: &SimulationResult, bodies: &[String]) -> Vec<f64> {
    bodies
        .iter()
        .flat_map(|b| {
            res.signal(&format!("{b}.r_abs"))
                .unwrap()
                .last()
                .unwrap()
                .to_vec()
        })
        .collect()
}

/// Largest distance \[m\] between the bodies' final positions of two runs.
fn distance(a: &[f64], b: &[f64]) -> f64 {
    a.chunks(3)
        .zip(b.chunks(3))
        .map(|(p, q)| {
            ((p[0] - q[0]).powi(2) + (p[1] - q[1]).powi(2) + (p[2] - q[2]).powi(2)).sqrt()
        })
        .fold(0.0, f64::max)
}

fn pairs(res: &SimulationResult) -> Vec<(Vec<String>, Vec<String>)> {
    res.events
        .iter()
        .map(|e| (e.started.clone(), e.ended.clone()))
        .collect()
}

#[test]
fn analytic_free_body_columns_keep_the_physics() {
    let mut balls: Vec<String> = (1..=15).map(|k| format!("ball{k}")).collect();
    balls.push("cue".into());
    let cases = [
        (
            "billiards16",
            demo::billiards16([3.0, 0.1, 0.0], 1.0),
            5.0,
            balls,
        ),
        (
            "bouncing_sphere",
            demo::bouncing_sphere(0.1, 0.5, ContactPairMaterial::new(0.7, 0.0, 0.0)),
            1.5,
            vec!["ball".to_string()],
        ),
        (
            "sliding_rolling_ball",
            demo::sliding_ball(0.1, 4.0, 0.0, ContactPairMaterial::new(0.7, 0.5, 0.0)),
            0.7,
            vec!["ball".to_string()],
        ),
        (
            "two_balls",
            demo::two_balls(2.0),
            1.0,
            vec!["cue".to_string(), "ball".to_string()],
        ),
    ];
    let rtol = 1e-5;
    for (name, scene, stop, bodies) in cases {
        let model = scene.build().unwrap();
        let opts = |rtol: f64| SimOptions::new(stop).tolerance(rtol).interval(stop / 100.0);
        let quotients = model
            .simulate(&opts(rtol).analytic_jacobian(false))
            .unwrap();
        let analytic = model.simulate(&opts(rtol)).unwrap();
        let reference = model.simulate(&opts(1e-9)).unwrap();
        assert_eq!(
            pairs(&analytic),
            pairs(&quotients),
            "{name}: the same contacts start and end, in the same order"
        );
        let r_ref = final_positions(&reference, &bodies);
        let err_analytic = distance(&final_positions(&analytic, &bodies), &r_ref);
        let err_quotients = distance(&final_positions(&quotients, &bodies), &r_ref);
        // Both are rtol-1e-5 solutions of the same DAE; the Jacobian only steers Newton (and
        // through it the steps), so their errors against the tight run are of one size
        // (BENCHMARKS.md: 2.4e-2 m for billiards16, whose collisions amplify, 7e-6 m for the
        // bouncing sphere), but not equal: measured for two_balls over rtol 1e-4 … 1e-7, the
        // ratio of the two errors ranged from 0.26 to 3.6, either way (2.25 at 1e-5). So: at
        // most 4× the quotients' error, or 10·rtol·1 m where that is tiny.
        assert!(
            err_analytic <= (4.0 * err_quotients).max(10.0 * rtol),
            "{name}: error {err_analytic:e} m against {err_quotients:e} m with quotients"
        );
        let (a, q) = (analytic.stats.solver, quotients.stats.solver);
        assert_eq!(a.residual_evals_for_jacobian, 0, "{name}: only free bodies");
        assert!(
            q.residual_evals_for_jacobian > 0,
            "{name}: the switch works"
        );
        eprintln!(
            "{name}: analytic {} steps, {} residuals, {} Jacobians, error {err_analytic:.2e} m; \
             quotients {} steps, {} (+{}) residuals, {} Jacobians, error {err_quotients:.2e} m; {} events",
            a.steps,
            a.residual_evals,
            a.jacobian_evals,
            q.steps,
            q.residual_evals,
            q.residual_evals_for_jacobian,
            q.jacobian_evals,
            analytic.events.len()
        );
    }
}
