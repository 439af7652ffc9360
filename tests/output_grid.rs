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

/// A 1 m × 1 m × 5 mm steel plate with its top face at z = 0.
fn steel_plate() -> SceneDesc {
    let mut scene = SceneDesc::new();
    scene
        .add(demo::world(SceneOptions::default()))
        .add(demo::fixed_box(
            "plate",
            [1.0, 1.0, 0.005],
            [0.0, 0.0, -0.0025],
            "Steel",
        ));
    scene
}

/// A steel ball dropped from 20 m (20 m/s at impact) onto a 5 mm steel plate, at a loose
/// tolerance and with only 10 output points: free fall is a parabola, so the error test alone
/// would let steps grow to a large part of a second and carry the ball through the plate
/// between two step ends, unseen. The step guard keeps every passage visible: the ball
/// bounces (a contact event), stays above the plate, and rises again close to the height the
/// restitution gives (cor 0.7 → 0.49 · 20 m; 10 % for the regularised, compliant law).
#[test]
fn a_fast_ball_does_not_tunnel_through_a_thin_plate() {
    let mut scene = steel_plate();
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

/// The guard holds each body to the thinnest pair it takes part in, not the fastest body to the
/// thinnest pair of the scene: a 0.2 m steel ball thrown at 20 m/s high above a 5 mm plate on
/// which a 2 cm bead rests takes steps of up to ¼ · (0.2 + 0.02) m / 20 m/s = 2.75 ms (its
/// thinnest pair is with the bead), while a guard for the whole scene held every step to
/// ¼ · (0.02 + 0.005) m / 20 m/s = 0.31 ms, at least 960 steps for 0.3 s. The run must take
/// fewer than half of those, follow the throw's parabola and keep the bead at rest.
#[test]
fn a_fast_body_is_not_held_to_a_thin_pair_it_is_not_part_of() {
    let mut scene = steel_plate();
    let (d_bead, d_ball, v0, z0) = (0.02, 0.2, 20.0, 1.0);
    let bead_z = 0.5 * d_bead;
    demo::add_free_sphere(
        &mut scene,
        "bead",
        d_bead,
        "Steel",
        None,
        [0.0, 0.0, bead_z],
        [0.0; 3],
        [0.0; 3],
    );
    demo::add_free_sphere(
        &mut scene,
        "ball",
        d_ball,
        "Steel",
        None,
        [-3.0, 0.0, z0],
        [v0, 0.0, 0.0],
        [0.0; 3],
    );
    let model = scene.build().unwrap();
    let stop = 0.3;
    let res = model
        .simulate(
            &SimOptions::new(stop)
                .tolerance(1e-6)
                .interval(0.01)
                .progress(false),
        )
        .unwrap();
    let scene_guard_steps = stop / (0.25 * (d_bead + 0.005) / v0);
    let steps = res.stats.solver.steps;
    let (t, x, z) = (
        res.time(),
        res.signal("ball.r_abs[0]").unwrap().values(),
        res.signal("ball.r_abs[2]").unwrap().values(),
    );
    let path_err = t
        .iter()
        .zip(x.iter().zip(&z))
        .map(|(t, (x, z))| {
            let (xe, ze) = (-3.0 + v0 * t, z0 - 0.5 * G * t * t);
            (x - xe).hypot(z - ze)
        })
        .fold(0.0, f64::max);
    let bead = res.signal("bead.r_abs[2]").unwrap().values();
    let bead_dev = bead.iter().map(|z| (z - bead_z).abs()).fold(0.0, f64::max);
    println!(
        "{steps} steps (a scene-wide guard: >= {scene_guard_steps:.0}); ball off the parabola by {path_err:.2e} m; bead moved {bead_dev:.2e} m"
    );
    assert!((steps as f64) < 0.5 * scene_guard_steps, "{steps} steps");
    // rtol 1e-6 on a 6 m path: a few µm (measured 6.7e-6 m).
    assert!(path_err < 2e-5, "ball off its parabola by {path_err:e} m");
    // The bead's static penetration is ~8e-8 m (Hertz, 0.32 N on a 1 cm radius).
    assert!(bead_dev < 1e-6, "bead moved {bead_dev:e} m");
}
