//! The output grid does not steer the integration, and no contact is stepped over: IDA takes one
//! internal step per call and output points are read off its interpolating polynomial
//! (simulation.rs), and the step is limited so that no collision shape can pass through
//! another between two step ends (contact/step_guard.rs).

use modia3d::demo;
use modia3d::prelude::*;

const G: f64 = 9.81;

/// The same bouncing ball with 1,500 and 150,000 output points takes the same steps, evaluates
/// the root functions the same number of times and finds the same events at the same times (to
/// round-off: the runs are the same sequence of floating-point operations but for the output).
#[test]
fn a_fine_output_grid_takes_the_same_steps_and_finds_the_same_events() {
    let model = demo::bouncing_sphere(0.1, 0.5, demo::STEEL_STEEL)
        .build()
        .unwrap();
    let run = |dt: f64| {
        model
            .simulate(
                &SimOptions::new(1.5)
                    .tolerance(1e-6)
                    .interval(dt)
                    .progress(false),
            )
            .unwrap()
    };
    let (coarse, fine) = (run(1e-3), run(1e-5));
    let (c, f) = (&coarse.stats.solver, &fine.stats.solver);
    println!(
        "coarse: {} points, {} steps, {} root evaluations; fine: {} points, {} steps, {} root evaluations",
        coarse.time().len(),
        c.steps,
        c.root_evals,
        fine.time().len(),
        f.steps,
        f.root_evals
    );
    assert!(fine.time().len() > 90 * coarse.time().len());
    assert_eq!(
        (c.steps, c.residual_evals, c.root_evals),
        (f.steps, f.residual_evals, f.root_evals)
    );
    assert!(
        coarse.events.len() >= 4,
        "the ball bounces: {} events",
        coarse.events.len()
    );
    assert_eq!(coarse.events.len(), fine.events.len());
    for (a, b) in coarse.events.iter().zip(&fine.events) {
        assert_eq!(a.t, b.t, "{} vs {}", a.description, b.description);
    }
}

/// Output points inside a step are IDA's interpolation, as accurate as the steps: a ball in free
/// fall (no contact before t = 0.25 s, dropped from 1 m) against z = h0 − g t²/2 at every one of
/// 250 grid points, to 1e-9 m (BDF of order ≥ 2 integrates a parabola exactly; what remains is
/// round-off and the tolerance-scaled Newton error at rtol 1e-10).
#[test]
fn interpolated_output_points_match_free_fall() {
    let model = demo::bouncing_sphere(0.1, 1.0, demo::STEEL_STEEL)
        .build()
        .unwrap();
    let res = model
        .simulate(
            &SimOptions::new(0.25)
                .tolerance(1e-10)
                .interval(1e-3)
                .progress(false),
        )
        .unwrap();
    let z = res.signal("ball.r_abs[2]").unwrap().values();
    let err = res
        .time()
        .iter()
        .zip(&z)
        .map(|(t, z)| (z - (1.0 - 0.5 * G * t * t)).abs())
        .fold(0.0, f64::max);
    println!("{} points, max |z − z_exact| = {err:.2e} m", z.len());
    assert!(z.len() >= 250);
    assert!(err < 1e-9, "max error {err:e} m");
}

/// A steel ball dropped from 20 m (20 m/s at impact) onto a 5 mm steel plate, at a loose
/// tolerance and with only 10 output points: free fall is a parabola, so the error test alone
/// would let steps grow to a large part of a second and carry the ball through the plate
/// between two step ends, unseen. The step guard keeps every passage visible: the ball
/// bounces (a contact event), stays above the plate, and rises again close to the height the
/// restitution gives (cor 0.7 → 0.49 · 20 m; 10 % for the regularised, compliant law).
#[test]
fn a_fast_ball_does_not_tunnel_through_a_thin_plate() {
    let mut scene = SceneDesc::new();
    scene
        .add(demo::world(SceneOptions::default()))
        .add(demo::fixed_box(
            "plate",
            [1.0, 1.0, 0.005],
            [0.0, 0.0, -0.0025],
            "Steel",
        ));
    demo::add_free_sphere(
        &mut scene,
        "ball",
        0.05,
        "Steel",
        None,
        [0.0, 0.0, 20.0],
        [0.0; 3],
        [0.0; 3],
    );
    let model = scene.build().unwrap();
    let res = model
        .simulate(
            &SimOptions::new(4.0)
                .tolerance(1e-3)
                .interval(0.4)
                .progress(false),
        )
        .unwrap();
    let z = res.signal("ball.r_abs[2]").unwrap().values();
    let z_min = z.iter().copied().fold(f64::INFINITY, f64::min);
    let t_impact = (2.0 * 19.975 / G).sqrt();
    let apex = res
        .time()
        .iter()
        .zip(&z)
        .filter(|(t, _)| **t > t_impact)
        .map(|(_, z)| *z)
        .fold(0.0, f64::max);
    println!(
        "{} events, {} steps, lowest output point z = {z_min:.4} m, highest after the impact {apex:.3} m",
        res.events.len(),
        res.stats.solver.steps
    );
    assert!(!res.events.is_empty(), "the impact is seen");
    assert!(z_min > 0.0, "the ball stays above the plate");
    assert!(apex > 0.5 * 0.49 * 20.0, "the ball rebounds ({apex} m)");
}
