//! MPR options that cannot hang (issue 15, point 5): at the loosest `mpr_tolerance` the
//! validation accepts (1e-9, relative) a steel box resting on a steel table still rests and the
//! run ends — at 1e-6, the range's former bound, the same run never ended (the step collapsed
//! to 1e-13 s at t = 1.5 ms; 2e-7 the same, 1e-7 and 1e-8 took twice the steps of 1e-9); with
//! the smallest iteration limit (1) MPR/GJK stop at their limit on every call, return the best
//! iterate, and the run still ends, within its wall budget — the stops are counted in
//! `SimStats::narrow_phase_limits` (and warned about once per pair).
//!
//! Reference: the box's static penetration `m·g/k` of the linear law (k = c_res = 1.1e11 N/m
//! for steel on steel, 7.1e-10 m): the height stays within `[h/2 − 2δ − tol, h/2 + tol]` with
//! `tol` = the narrow phase's admitted error, `mpr_tolerance · size` (size = sum of the two
//! bounding radii, 0.80 m here: below 1e-9 m at 1e-9).

mod recorder;

use modia3d::demo::{c_res, fixed_box, world};
use modia3d::prelude::*;
use recorder::Recorder;

fn steel() -> SolidMaterial {
    modia3d::core::scene::builtin_solid_material("Steel").unwrap()
}

/// A 0.1 m steel cube resting (touching, at rest) on a 1 × 1 × 0.1 m steel table.
fn box_on_table(options: SceneOptions) -> SceneDesc {
    let mut s = SceneDesc::new();
    s.add(world(options))
        .add(fixed_box(
            "table",
            [1.0, 1.0, 0.1],
            [0.0, 0.0, -0.05],
            "Steel",
        ))
        .add(
            Object3D::new("box").solid(
                Solid::new(Shape::Box {
                    lengths: Vector3::new(0.1, 0.1, 0.1),
                })
                .material("Steel")
                .collision(true),
            ),
        )
        .add_joint(Joint::new(
            "box.free",
            "world",
            "box",
            JointKind::FreeMotion {
                r: Vector3::new(0.0, 0.0, 0.05),
                rot: FreeRotation::Cardan([0.0; 3]),
                v: Vector3::zeros(),
                w: Vector3::zeros(),
            },
        ));
    s
}

/// Runs 0.2 s with a 60 s wall budget (a run that does not end fails with the budget error
/// instead of hanging the test) and checks that the box rests within `tol` \[m\] of the band.
///
/// Under the paper's law (`ContactProfile::Paper2019`): the band is that of its linear law, and
/// the narrow phase whose tolerance this file varies is what its force depends on (the default
/// volume law's box pairs take their force from the overlap instead).
fn rests(options: SceneOptions, tol: f64) -> SimulationResult {
    let options = SceneOptions {
        contact_profile: ContactProfile::Paper2019,
        ..options
    };
    let opts = SimOptions::new(0.2).max_wall_time(60.0).progress(false);
    let res = match box_on_table(options).build().unwrap().simulate(&opts) {
        Ok(r) => r,
        Err(e) => panic!("the run did not end normally: {}", e.kind),
    };
    let d = steel().density * 1e-3 * 9.81 / c_res(&steel(), &steel());
    let z = res.signal("box.r_abs[2]").unwrap().values();
    let (lo, hi) = z
        .iter()
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), &x| {
            (a.min(x), b.max(x))
        });
    println!(
        "{} events, {} steps, {} narrow-phase calls ({} at the iteration limit), wall {:.2} s; z in [{lo:.12}, {hi:.12}]",
        res.stats.events,
        res.stats.solver.steps,
        res.stats.narrow_phase_calls,
        res.stats.narrow_phase_limits,
        res.stats.wall_time
    );
    assert!(
        lo >= 0.05 - 2.0 * d - tol && hi <= 0.05 + tol,
        "z in [{lo}, {hi}], band [{}, 0.05] ± {tol}",
        0.05 - 2.0 * d
    );
    res
}

#[test]
fn box_on_table_at_the_loosest_mpr_tolerance_rests_and_ends() {
    // size < 1 m, so the admitted error is below 1e-9 m.
    let res = rests(
        SceneOptions {
            mpr_tolerance: 1e-9,
            ..Default::default()
        },
        1e-9,
    );
    assert!(res.stats.events <= 5, "{} events", res.stats.events);
    assert_eq!(res.stats.narrow_phase_limits, 0, "{:?}", res.stats);
}

#[test]
fn mpr_at_its_iteration_limit_returns_its_best_iterate_and_the_run_ends() {
    // One iteration: the box–table pair goes through MPR + GJK (no closed form), which stop
    // after one iteration and are counted. The distances are then too rough for the box to
    // rest (the run may reach its budget), but the run ends, within twice its wall budget.
    let options = SceneOptions {
        mpr_max_iterations: 1,
        ..Default::default()
    };
    let opts = SimOptions::new(0.2).max_wall_time(2.0).progress(false);
    let model = box_on_table(options).build().unwrap();
    let rec = std::sync::Arc::new(Recorder(std::sync::Mutex::new(vec![])));
    let t0 = std::time::Instant::now();
    let res = tracing::subscriber::with_default(rec.clone(), || model.simulate(&opts));
    let stats = match res {
        Ok(r) => r.stats,
        Err(SimError {
            kind: SimErrorKind::WorkBudget(_),
            partial,
        }) => partial.stats,
        Err(e) => panic!("unexpected error: {}", e.kind),
    };
    let wall = t0.elapsed().as_secs_f64();
    println!("{stats:?}, wall {wall:.2} s");
    assert!(wall < 4.0, "wall {wall}");
    assert!(
        stats.narrow_phase_limits > 0,
        "no call stopped at the limit"
    );
    assert!(stats.narrow_phase_limits <= stats.narrow_phase_calls);
    // Warned once for the one pair, however often the limit was hit.
    let msgs = rec.0.lock().unwrap();
    let warned: Vec<_> = msgs
        .iter()
        .filter(|m| m.contains("iteration limit"))
        .collect();
    assert_eq!(warned.len(), 1, "{warned:#?}");
    assert!(warned[0].contains("pair=table|box"), "{}", warned[0]);
}
