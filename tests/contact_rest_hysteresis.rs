//! Resting contact rests at the default options (issue 15, point 2): the contact-set hysteresis
//! lies on the separated side of the contact (`Hysteresis` in the core's `contact/contact_set.rs`,
//! docs/contact-hysteresis.md), so it does no work and a body at rest stays in the contact set
//! whatever its static penetration `m·g/k`.
//!
//! Before the change a 0.1 m steel cube on a steel table (linear law, k = c_res =
//! 1.1e11 N/m, m·g/k = 7.1e-10 m, below the old band 2ε = 2e-8 m) had 5,918 contact events
//! in 0.2 s; the same scene now has none after its first contact.

use modia3d::demo::{self, c_res};
use modia3d::prelude::*;

const G: f64 = 9.81;

fn steel() -> SolidMaterial {
    modia3d::core::scene::builtin_solid_material("Steel").unwrap()
}

fn cube() -> Shape {
    Shape::Box {
        lengths: Vector3::new(0.1, 0.1, 0.1),
    }
}

/// Runs `scene` under the paper's law (`ContactProfile::Paper2019`: these tests are about its
/// linear law for pairs without a sphere; the default volume law's resting contacts are
/// tested in `tests/contact_volume.rs`).
fn run(scene: SceneDesc, opts: SimOptions) -> SimulationResult {
    let model = modia3d::demo::with_profile(scene, ContactProfile::Paper2019)
        .build()
        .unwrap();
    match model.simulate(&opts.progress(false).contact_results(true)) {
        Ok(r) => r,
        Err(e) => panic!("stopped at t = {:?}: {}", e.partial.time().last(), e.kind),
    }
}

/// The static penetration of a linear (non-sphere) steel–steel contact carrying `m` \[kg\].
fn delta_static(m: f64, k_red: f64) -> f64 {
    m * G / (k_red * c_res(&steel(), &steel()))
}

/// A steel cube on a steel table at the default options (k_red = 1, rtol 1e-6) for 0.2 s:
/// one contact event at most (before: 5,918), and the cube stays in contact around its static
/// penetration: the height never leaves [h/2 − 2δ, h/2] (it starts touching, so it oscillates
/// between δ = 0 and 2·m·g/k at most; the old hovering was 8e-9 m = 11·m·g/k above the table).
#[test]
fn steel_box_on_steel_table_rests_at_default_options() {
    let res = run(
        demo::stack(cube(), 0.1, [0.0; 3], 1, 1.0),
        SimOptions::new(0.2),
    );
    let m = steel().density * 1e-3;
    let d = delta_static(m, 1.0);
    let z = res.signal("b0.r_abs[2]").unwrap().values();
    let (lo, hi) = z
        .iter()
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), &x| {
            (a.min(x), b.max(x))
        });
    println!(
        "box: {} events, {} steps, wall {:.2} s; z in [{lo:.12}, {hi:.12}], δ_static {d:.3e}",
        res.stats.events, res.stats.solver.steps, res.stats.wall_time
    );
    assert!(res.stats.events <= 1, "{} events", res.stats.events);
    assert!(
        lo >= 0.05 - 2.0 * d - 1e-12 && hi <= 0.05 + 1e-12,
        "z in [{lo}, {hi}]"
    );
}

/// Ten steel cubes stacked on the table hold 10 s at the default options (k_red = 1, rtol
/// 1e-6; issue 15's acceptance): no event at all (every pair touches at the start and stays
/// in the set), and each support force equals the weight above it within 1e-3 (the stack is
/// at rest after 10 s: the damping of the law, d = d_max, settles it within a fraction of a
/// second; IDA's force error at rtol 1e-6 is far below 1e-3). Its cost is a bench row
/// (BENCHMARKS.md, `examples/resting_stack.rs`), not asserted here.
#[test]
fn stack_of_ten_steel_boxes_holds() {
    let n = 10;
    let res = run(
        demo::stack(cube(), 0.1, [0.0; 3], n, 1.0),
        SimOptions::new(10.0),
    );
    let m = steel().density * 1e-3;
    println!(
        "stack: {} events, {} steps, wall {:.2} s",
        res.stats.events, res.stats.solver.steps, res.stats.wall_time
    );
    assert_eq!(res.stats.events, 0);
    for i in 0..n {
        let pair = if i == 0 {
            "table|b0".to_string()
        } else {
            format!("b{}|b{i}", i - 1)
        };
        let f = res.signal(&format!("{pair}.f_n")).unwrap().last().unwrap()[0];
        let w = (n - i) as f64 * m * G;
        assert!(
            (f - w).abs() < 1e-3 * w,
            "{pair}: f_n {f} N vs weight {w} N"
        );
        let v = res
            .signal(&format!("b{i}.v_abs"))
            .unwrap()
            .last()
            .unwrap()
            .to_vec();
        assert!(v.iter().all(|x| x.abs() < 1e-6), "b{i} moves: {v:?}");
    }
}

/// A steel cylinder on its side and a steel ellipsoid lying flat, at the default options for
/// 1 s: no event after the start (both start touching), the support force averaged over the
/// run equals the weight within 2 % (the first milliseconds oscillate: they start at zero
/// penetration), and at the end it equals the weight within 1e-3 for the cylinder and 1e-2 for
/// the ellipsoid. Why the ellipsoid's is looser: under the paper's linear law its point
/// contact carries the weight at a static penetration of 1.5e-9 m, whose heave mode (period
/// 8e-5 s) the law does not damp at rest (the damping is `k·δ·d·δ̇`); the error test in
/// contact (rtol/κ = 1e-8 of the height 0.02 m, 2e-10 m) lets the penetration, and with it the
/// force, wander by up to 13 %. Measured: ±0.5 % over the run, a slow drift of the
/// interpolated penetration by ~5e-12 m; the ellipsoid's normal is the table's exactly
/// (`box_face`), so what drifts is the integration, not the geometry. The volume profile's
/// Hertz law gives the weight to 1e-7 in the same scene.
#[test]
fn cylinder_on_its_side_and_ellipsoid_rest_at_default_options() {
    let cases = demo::lying_shapes();
    for (what, shape, h, volume) in cases.into_iter().skip(1) {
        let res = run(
            demo::stack(shape, h, [0.0; 3], 1, 1.0),
            SimOptions::new(1.0).interval(1e-4),
        );
        let f = res.signal("table|b0.f_n").unwrap().values();
        let mean = f.iter().sum::<f64>() / f.len() as f64;
        let w = steel().density * volume * G;
        println!(
            "{what}: {} events, {} steps, wall {:.2} s, mean f_n {mean:.4} N, weight {w:.4} N",
            res.stats.events, res.stats.solver.steps, res.stats.wall_time
        );
        assert_eq!(res.stats.events, 0, "{what}");
        assert!(
            (mean - w).abs() < 0.02 * w,
            "{what}: mean f_n {mean} vs {w}"
        );
        let last = f[f.len() - 1];
        let tol = if what == "ellipsoid" { 1e-2 } else { 1e-3 };
        assert!(
            (last - w).abs() < tol * w,
            "{what}: f_n {last} N at 1 s vs {w} N"
        );
    }
}

/// The acceptance run of issue 15: the steel cube at the default options for 10 s rests with
/// at most 5 contact events (measured: 0) and carries its weight.
#[test]
fn steel_box_rests_ten_seconds() {
    let res = run(
        demo::stack(cube(), 0.1, [0.0; 3], 1, 1.0),
        SimOptions::new(10.0),
    );
    println!(
        "box 10 s: {} events, {} steps, wall {:.2} s",
        res.stats.events, res.stats.solver.steps, res.stats.wall_time
    );
    assert!(res.stats.events <= 5);
    let w = steel().density * 1e-3 * G;
    let f = res.signal("table|b0.f_n").unwrap().last().unwrap()[0];
    assert!((f - w).abs() < 1e-4 * w, "f_n {f} N vs weight {w} N");
}
