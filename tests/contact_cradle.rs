//! Newton's cradle with gaps: five steel balls (cor = 1, no friction) on 0.5 m pendulums.

use modia3d::demo::{self, sphere_mass};
use modia3d::prelude::*;

/// With 1 mm gaps at 0.5 m/s the balls are 2 ms apart in time while a contact lasts ~0.1 ms,
/// so the impacts are sequential binary ones: each hands the full speed on, the last ball
/// leaves with the impact speed. Deviations: gravity acting along the arc during ~9 ms of
/// swing (angles ≤ 1e-3 rad: speed change ~ g·θ·t ≈ 1e-4 m/s, 2e-4 relative) — so 1 % is a
/// loose bound. Energy (kinetic + potential) and x-momentum are compared before and after.
#[test]
fn each_impact_hands_the_motion_on() {
    let (d, gap, v0) = (0.05, 1e-3, 0.5);
    let model = demo::newtons_cradle(d, gap, v0, ContactPairMaterial::new(1.0, 0.0, 0.0))
        .build()
        .unwrap();
    let t_end = 5.0 * gap / v0 + 0.002;
    let res = model
        .simulate(&SimOptions::new(t_end).tolerance(1e-8).interval(1e-4))
        .unwrap();
    for e in &res.events {
        println!("t = {:.6} s: {}", e.t, e.description);
    }
    let pairs = ["ball0|ball1", "ball1|ball2", "ball2|ball3", "ball3|ball4"];
    for p in pairs {
        let started: Vec<f64> = res
            .events
            .iter()
            .filter(|e| e.started.iter().any(|s| s == p))
            .map(|e| e.t)
            .collect();
        assert_eq!(started.len(), 1, "one impact of {p}");
    }
    let m = sphere_mass(d, 8000.0);
    let i_c = 0.4 * m * (d / 2.0) * (d / 2.0);
    let energy_momentum = |k: usize| {
        let (mut e, mut p) = (0.0, 0.0);
        for b in 0..5 {
            let v = res.signal(&format!("ball{b}.v_abs")).unwrap();
            let w = res.signal(&format!("ball{b}.w_abs")).unwrap();
            let r = res.signal(&format!("ball{b}.r_abs")).unwrap();
            let (v, w, r) = (v.at(k).unwrap(), w.at(k).unwrap(), r.at(k).unwrap());
            e += 0.5 * m * (v[0] * v[0] + v[1] * v[1] + v[2] * v[2])
                + 0.5 * i_c * (w[0] * w[0] + w[1] * w[1] + w[2] * w[2])
                + m * 9.81 * r[2];
            p += m * v[0];
        }
        (e, p)
    };
    let last = res.time().len() - 1;
    let (e0, p0) = energy_momentum(0);
    let (e1, p1) = energy_momentum(last);
    let v_last = res.signal("ball4.v_abs[0]").unwrap().last().unwrap()[0];
    let v_others: f64 = (0..4)
        .map(|b| {
            res.signal(&format!("ball{b}.v_abs[0]"))
                .unwrap()
                .last()
                .unwrap()[0]
                .abs()
        })
        .fold(0.0, f64::max);
    let ke0 = 0.5 * (m + i_c / 0.25) * v0 * v0; // ball 0 swings about its pivot 0.5 m above
    println!(
        "last ball {v_last:.6} m/s (impact speed {v0}), others ≤ {v_others:.2e} m/s; energy {e0:.6e} → {e1:.6e} J (rel. {:.1e}, KE0 {ke0:.4e} J), momentum {p0:.6e} → {p1:.6e} kg·m/s (rel. {:.1e})",
        (e1 - e0) / ke0,
        (p1 - p0) / p0
    );
    assert!((v_last - v0).abs() / v0 < 0.01);
    assert!(v_others < 0.01 * v0);
    assert!((e1 - e0).abs() / ke0 < 0.01);
    assert!((p1 - p0).abs() / p0.abs() < 0.01);
}
