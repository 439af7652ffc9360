//! A steel sphere bouncing on a steel box: free flight between events against the parabola,
//! and the end of the bouncing (no Zeno) thanks to `cor_reg`.

use modia3d::demo;
use modia3d::prelude::*;

const G: f64 = 9.81;

/// Vertical velocity of the ball at the output point recorded at time `t` (events are
/// recorded as output points).
fn vz_at(res: &SimulationResult, vz: &[f64], t: f64) -> f64 {
    let k = res
        .time()
        .iter()
        .rposition(|&x| x == t)
        .expect("event recorded");
    vz[k]
}

/// Between a contact-end event (speed v_out, δ = 0) and the next contact-start event
/// (δ = 2ε) the ball flies freely: t = 2 v_out/g + 2ε/v_out. The ε term is ε g / v_out²
/// relative (1e-6 at 0.3 m/s), so it is part of the reference; BDF integrates the parabola exactly (order ≥ 2), so at rtol 1e-8 the events are located to
/// about rtol · t: 1e-6 relative is the bound asked for.
#[test]
fn flight_time_between_events_is_two_v_out_over_g() {
    let model = demo::bouncing_sphere(0.1, 0.5, ContactPairMaterial::new(0.7, 0.0, 0.0))
        .build()
        .unwrap();
    let res = model
        .simulate(&SimOptions::new(1.5).tolerance(1e-8).interval(0.01))
        .unwrap();
    let vz = res.signal("ball.v_abs[2]").unwrap().values();
    let mut checked = 0;
    for w in res.events.windows(2) {
        if !w[0].ended.is_empty() && !w[1].started.is_empty() {
            let v_out = vz_at(&res, &vz, w[0].t);
            let flight = w[1].t - w[0].t;
            let expected = 2.0 * v_out / G + 2.0 * 1e-8 / v_out;
            let err = (flight - expected) / expected;
            println!("v_out = {v_out:.6} m/s: flight {flight:.9} s, 2 v_out/g + 2ε/v_out = {expected:.9} s, rel. error {err:+.2e}");
            assert!(err.abs() < 1e-6);
            checked += 1;
        }
    }
    assert!(checked >= 2, "at least two flights checked ({checked})");
}

/// Dropped from 0.1 m with cor = 0.9 an ideal ball would bounce infinitely often before
/// t∞ = t1 (1 + e)/(1 − e) ≈ 2.7 s. `cor_reg` makes impacts slower than ~v_min inelastic, so
/// the compliant ball stops after finitely many events, then rests: over 10 s the height
/// changes by less than 1e-9 m (static penetration ≈ 1e-6 m) and no event follows.
#[test]
fn bouncing_ends_after_finitely_many_events_and_the_ball_rests() {
    let model = demo::bouncing_sphere(0.1, 0.15, ContactPairMaterial::new(0.9, 0.0, 0.0))
        .build()
        .unwrap();
    let res = model
        .simulate(&SimOptions::new(14.0).tolerance(1e-6).interval(0.01))
        .unwrap();
    let last = res.events.last().unwrap().t;
    let t1 = (2.0 * 0.1 / G).sqrt();
    let t_inf = t1 * 1.9 / 0.1;
    println!(
        "{} events, last at {last:.4} s (ideal Zeno time {t_inf:.3} s); {} steps",
        res.events.len(),
        res.stats.solver.steps
    );
    assert!(res.events.len() < 1000);
    assert!(last < 4.0, "bouncing ends");
    assert!(
        !res.events.last().unwrap().started.is_empty(),
        "ends in contact"
    );
    let z = res.signal("ball.r_abs[2]").unwrap().values();
    let t = res.time();
    let k4 = t.iter().position(|&x| x >= 4.0).unwrap();
    let zmax = z[k4..].iter().cloned().fold(f64::MIN, f64::max);
    let zmin = z[k4..].iter().cloned().fold(f64::MAX, f64::min);
    println!(
        "rest height {:.9} m, drift over {:.1} s: {:.2e} m",
        z[k4],
        t[t.len() - 1] - t[k4],
        zmax - zmin
    );
    assert!(zmax - zmin < 1e-9);
    assert!((z[k4] - 0.05).abs() < 1e-5);
}
