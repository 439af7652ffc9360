//! Error control in contact phases (issue 16, point 5): the contact times and rebound speeds of
//! a steel ball dropped on a steel table follow `rtol` — checked against the same scene at
//! rtol 1e-12 (an independent, 100× to 1e8× more accurate run of the same law).
//!
//! Without `SimOptions::contact_tightening` the contact times were off by 6–276 × rtol over
//! rtol 1e-4…1e-10 (IDA bounds the error of each step, and one contact phase takes ~100
//! steps); see docs/contact-model.md, "What rtol means".

use modia3d::demo;
use modia3d::prelude::*;

/// (start, end, impact speed, exit speed) of every finished contact phase of the ball
/// (Ø 0.1 m, dropped from a 0.5 m gap, pair cor 0.7) over 1.5 s at `rtol`.
fn phases(rtol: f64, exact: bool) -> Vec<(f64, f64, f64, f64)> {
    let steel = modia3d::core::scene::builtin_solid_material("Steel").unwrap();
    let options = SceneOptions {
        exact_restitution: exact,
        ..Default::default()
    };
    let pair = ContactPairMaterial::new(0.7, 0.0, 0.0);
    let model = demo::sphere_on_plane(0.1, steel, 0.0, 0.5, pair, options)
        .build()
        .unwrap();
    let res = model
        .simulate(
            &SimOptions::new(1.5)
                .tolerance(rtol)
                .interval(0.1)
                .contact_results(true),
        )
        .unwrap();
    res.contacts()
        .unwrap()
        .iter()
        .filter_map(|p| Some((p.start, p.end?, p.impact_speed, p.exit_speed?)))
        .collect()
}

/// Over rtol 1e-4 … 1e-10, for the paper's damping law and for exact restitution: every
/// contact start and end time within 3·rtol·t of the rtol 1e-12 run (t ≤ 1.5 s; seen ≤ 1.3·rtol
/// in absolute seconds), every rebound (exit) speed within 5·rtol relative (seen ≤ 3.1·rtol:
/// the exit speed is read at the end event, where the force has just vanished, so the error
/// of the whole phase is in it). The same phases in the same order (5 or 6 bounces).
#[test]
fn contact_times_follow_the_tolerance() {
    for exact in [false, true] {
        let reference = phases(1e-12, exact);
        assert!(reference.len() >= 5, "{} phases", reference.len());
        for k in 4..=10 {
            let rtol = 10f64.powi(-k);
            let ph = phases(rtol, exact);
            assert_eq!(ph.len(), reference.len(), "rtol {rtol:e}, exact {exact}");
            let (mut worst_t, mut worst_v) = (0.0f64, 0.0f64);
            for (p, r) in ph.iter().zip(&reference) {
                for (t, t_ref) in [(p.0, r.0), (p.1, r.1)] {
                    worst_t = worst_t.max((t - t_ref).abs() / (rtol * t_ref));
                }
                worst_v = worst_v.max((p.3 - r.3).abs() / (rtol * r.3));
            }
            println!(
                "exact {exact}, rtol {rtol:.0e}: contact times within {worst_t:.2}·rtol·t, rebound speeds within {worst_v:.2}·rtol"
            );
            assert!(
                worst_t <= 3.0,
                "exact {exact}, rtol {rtol:e}: contact times off by {worst_t}·rtol·t"
            );
            assert!(
                worst_v <= 5.0,
                "exact {exact}, rtol {rtol:e}: rebound speeds off by {worst_v}·rtol"
            );
        }
    }
}

/// Loose tolerances resolve resting and rolling contacts (issue 16, point 5): a steel ball
/// (Ø 0.1 m) launched sliding at 4 m/s on a steel table (μ 0.5) starts in contact and never
/// leaves it; at rtol 1e-3 it used to hop (26 contact events: the height's tolerance
/// `rtol·|z|` = 5e-5 m was 50× its static penetration). Now no event, and the speed after
/// rolling sets in (t = 0.7 s > 2v0/(7μg) = 0.233 s) is the rigid solution 5/7·v0 to
/// 10·rtol (a Hertz contact is not rigid, but the difference is ~1e-6 here; seen 1.7e-3).
/// At rtol 1e-2 and 1e-1 the scaled tightening alone (22×, 15×) left the ball hopping (18 and
/// 14 events); in contact the tolerance is now never looser than `LOOSEST_CONTACT_RTOL` =
/// 5e-5, so no hop there either, and the speed error is bounded by 2e-2 instead of 10·rtol
/// (seen 1.9e-3 at 1e-1, 3.4e-3 at 1e-2: the whole run is in contact, at the 5e-5 tolerance;
/// without the tightening the error is 0.29–0.46).
#[test]
fn a_rolling_ball_does_not_hop_at_loose_tolerances() {
    let v0 = 4.0;
    let model = demo::sliding_ball(0.1, v0, 0.0, ContactPairMaterial::new(0.7, 0.5, 0.0))
        .build()
        .unwrap();
    for rtol in [1e-3, 1e-2, 1e-1] {
        let res = model
            .simulate(&SimOptions::new(0.7).tolerance(rtol).interval(0.07))
            .unwrap();
        let v = res.signal("ball.v_abs").unwrap();
        let vx = v.last().unwrap()[0];
        let rel = (vx - 5.0 / 7.0 * v0).abs() / (5.0 / 7.0 * v0);
        println!(
            "rtol {rtol:e}: {} events, {} steps, speed error {rel:.2e}",
            res.events.len(),
            res.stats.solver.steps
        );
        assert_eq!(res.events.len(), 0, "rtol {rtol:e}: the ball hops");
        assert!(
            rel < (10.0 * rtol).min(2e-2),
            "rtol {rtol:e}: speed error {rel}"
        );
    }
}
