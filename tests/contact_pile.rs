//! Stress scene: twelve steel balls dropped into an open steel box (`demo::ball_pile`), with
//! about a thousand impacts per second in clusters against the floor, the walls and each other.
//! Checked against conservation laws rather than against itself.

use modia3d::demo::{self, sphere_mass, PILE_BALLS, PILE_BALL_DIAMETER, PILE_BOX_WIDTH};
use modia3d::prelude::*;

const G: f64 = 9.81;

fn balls() -> Vec<String> {
    (0..PILE_BALLS).map(|k| format!("b{k}")).collect()
}

fn is_ball(name: &str) -> bool {
    name.starts_with('b') && name[1..].parse::<usize>().is_ok()
}

/// Kinetic + potential energy of the balls at every output point [J] (steel: 8000 kg/m³).
fn rigid_energy(res: &SimulationResult) -> Vec<f64> {
    let m = sphere_mass(PILE_BALL_DIAMETER, 8000.0);
    let i_c = 0.1 * m * PILE_BALL_DIAMETER * PILE_BALL_DIAMETER;
    let sq = |v: &[f64]| v.iter().map(|x| x * x).sum::<f64>();
    let mut e = vec![0.0; res.time().len()];
    for b in balls() {
        let v = res.signal(&format!("{b}.v_abs")).unwrap();
        let w = res.signal(&format!("{b}.w_abs")).unwrap();
        let r = res.signal(&format!("{b}.r_abs")).unwrap();
        for (k, e) in e.iter_mut().enumerate() {
            *e += 0.5 * m * sq(v.at(k).unwrap())
                + 0.5 * i_c * sq(w.at(k).unwrap())
                + m * G * r.at(k).unwrap()[2];
        }
    }
    e
}

/// Every ball inside the box, up to `slack` \[m\] of penetration.
fn assert_inside(res: &SimulationResult, slack: f64) {
    let r = 0.5 * PILE_BALL_DIAMETER;
    let half = 0.5 * PILE_BOX_WIDTH - r;
    for b in balls() {
        let s = res.signal(&format!("{b}.r_abs")).unwrap();
        for k in 0..res.time().len() {
            let p = s.at(k).unwrap();
            assert!(
                p[0].abs() <= half + slack && p[1].abs() <= half + slack && p[2] >= r - slack,
                "{b} left the box at t = {}: {p:?}",
                res.time()[k]
            );
        }
    }
}

#[test]
fn elastic_pile_conserves_energy_including_the_hertz_energy() {
    // cor = 1 with cor_min = 1 (no damping at any impact speed), no friction, no rolling
    // resistance: the contact forces are conservative, f_n = K δ^(3/2), so the kinetic and
    // potential energy of the balls plus the elastic energy of the active contacts,
    // U = ∫ f_n dδ = (2/5) f_n δ, is constant. At rtol 1e-8 over ~1000 impacts the measured
    // drift is 3.3e-6 of E (4.3e-4 at 1e-6, 1.1e-7 at 1e-10: it converges with the
    // tolerance); 2e-5 leaves headroom for another machine's step sequence, and would catch
    // a force that is not the gradient of U (a wrong contact point, normal or depth: such
    // errors show at the percent level — a 2.5 % mass error did).
    let options = SceneOptions {
        cor_min: 1.0,
        ..Default::default()
    };
    let model = demo::ball_pile(options, ContactPairMaterial::new(1.0, 0.0, 0.0))
        .build()
        .unwrap();
    let res = model
        .simulate(
            &SimOptions::new(1.0)
                .tolerance(1e-8)
                .interval(1.0 / 400.0)
                .contact_results(true),
        )
        .unwrap();
    let pairs = res.contact_pairs();
    let f_n: Vec<Signal> = pairs
        .iter()
        .map(|p| res.signal(&format!("{p}.f_n")).unwrap())
        .collect();
    let depth: Vec<Signal> = pairs
        .iter()
        .map(|p| res.signal(&format!("{p}.penetration")).unwrap())
        .collect();
    let rigid = rigid_energy(&res);
    let energy = |k: usize| {
        let elastic: f64 = f_n
            .iter()
            .zip(&depth)
            .map(|(f, d)| 0.4 * f.at(k).unwrap()[0] * d.at(k).unwrap()[0])
            .sum();
        rigid[k] + elastic
    };
    let e0 = energy(0);
    let drift = (0..res.time().len())
        .map(|k| (energy(k) - e0).abs())
        .fold(0.0, f64::max);
    println!(
        "{} events, {} steps; max |E − E0| = {drift:.3e} J of {e0:.4} J ({:.2e})",
        res.stats.events,
        res.stats.solver.steps,
        drift / e0
    );
    assert!(
        res.stats.events > 500,
        "a stress scene: {} events",
        res.stats.events
    );
    assert!(drift / e0 < 2e-5, "energy drift {:.3e}", drift / e0);
    // Hertz penetrations here stay below 0.1 mm; nothing tunnels through a wall.
    assert_inside(&res, 2e-4);
}

#[test]
fn dissipative_pile_comes_to_rest_in_static_equilibrium() {
    // The built-in steel pair (cor 0.7, μ_k 0.5, μ_r 0.001), k_red = 1e-3. After 4 s the balls
    // lie in the box (measured max speed 8e-4 m/s: slow rolling, decelerated by 5/7·μ_r·g ≈
    // 7e-3 m/s²), so the vertical contact forces of the floor and walls on the balls carry
    // their weight: Σ F_z = 12 m g up to Σ m a_z, which is zero for rolling on the floor and
    // tiny for residual vibration (measured 6e-7 relative; bound 1e-4).
    let options = SceneOptions {
        k_red: 1e-3,
        ..Default::default()
    };
    let model = demo::ball_pile(options, demo::STEEL_STEEL).build().unwrap();
    let res = model
        .simulate(
            &SimOptions::new(4.0)
                .tolerance(1e-6)
                .interval(4.0 / 400.0)
                .contact_results(true),
        )
        .unwrap();
    let last = res.time().len() - 1;
    let v_max = balls()
        .iter()
        .map(|b| {
            let v = res.signal(&format!("{b}.v_abs")).unwrap();
            v.at(last)
                .unwrap()
                .iter()
                .map(|x| x * x)
                .sum::<f64>()
                .sqrt()
        })
        .fold(0.0, f64::max);
    let mut f_z = 0.0;
    for p in res.contact_pairs() {
        let (a, b) = p.split_once('|').unwrap();
        if is_ball(a) == is_ball(b) {
            continue; // internal (ball–ball) or not involving a ball
        }
        let f_n = res.signal(&format!("{p}.f_n")).unwrap().at(last).unwrap()[0];
        let n_z = res
            .signal(&format!("{p}.normal"))
            .unwrap()
            .at(last)
            .unwrap()[2];
        let ft_z = res
            .signal(&format!("{p}.friction_force"))
            .unwrap()
            .at(last)
            .unwrap()[2];
        // The second object of a pair receives f_n·n + f_t, the first the opposite.
        let on_second = f_n * n_z + ft_z;
        f_z += if is_ball(b) { on_second } else { -on_second };
    }
    let weight = PILE_BALLS as f64 * sphere_mass(PILE_BALL_DIAMETER, 8000.0) * G;
    println!(
        "{} events; final max speed {v_max:.2e} m/s; Σ F_z = {f_z:.5} N, weight {weight:.5} N",
        res.stats.events
    );
    assert!(v_max < 1e-2, "still moving: {v_max} m/s");
    assert!(
        (f_z / weight - 1.0).abs() < 1e-4,
        "vertical equilibrium: {f_z} N vs {weight} N"
    );
    assert_inside(&res, 2e-3);
}
