//! Bad starts are build errors (issue 15, point 4): two solids that can collide and start
//! deeper inside each other than half the extent of the thinner one — a ball 90 % inside the
//! table, a ball with its centre inside it, coincident balls or boxes — are a typed
//! `SceneError::InitialPenetration` from `build()` naming the pair and the depth. Before, IDA
//! failed at t ≈ 5e-6 s with a hint about `max_num_steps`, or the run "succeeded" with the two
//! solids thrown apart. Shallow overlaps still build.
//!
//! References: the depths are analytic (a sphere centred a distance `h` below a face is
//! `r + h` deep; coincident spheres `r_1 + r_2`; coincident boxes the smaller edge), checked to
//! 1e-12 m (the closed forms are exact; for the boxes the deepest face's normal is among the
//! directions the check samples, so its value is exact too).
//!
//! During a run a contact deeper than the thinner shape's whole extent, or deeper than half of
//! it while IDA's steps collapse, ends the run with `SimErrorKind::TooDeep`
//! (`a_ball_falling_through_a_soft_table_ends_with_too_deep`; the collapsed case is the
//! recorded fuzz scene `tests/regressions/deep_contact_is_named.json`).

use modia3d::demo::{add_free_sphere, fixed_box, world};
use modia3d::prelude::*;

const WHAT_TO_DO: &str = "the contact force would throw them apart or stall the solver; move one of them out of the other, or turn collision off for one of them (`Solid::collision(false)`)";

/// A steel ball (Ø 0.1 m) whose lowest point lies `depth` below the top of a 1 × 1 × 0.1 m
/// steel table (top face at z = 0).
fn ball_in_table(depth: f64) -> SceneDesc {
    ball_in(0.1, depth, SceneOptions::default())
}

/// [`ball_in_table`] on a table `thickness` \[m\] thick, with the scene options `options`.
fn ball_in(thickness: f64, depth: f64, options: SceneOptions) -> SceneDesc {
    let mut s = SceneDesc::new();
    s.add(world(options)).add(fixed_box(
        "table",
        [1.0, 1.0, thickness],
        [0.0, 0.0, -0.5 * thickness],
        "Steel",
    ));
    add_free_sphere(
        &mut s,
        "ball",
        0.1,
        "Steel",
        None,
        [0.0, 0.0, 0.05 - depth],
        [0.0; 3],
        [0.0; 3],
    );
    s
}

/// The one error of a scene that must not build.
fn the_error(s: &SceneDesc) -> (SceneError, String) {
    let e = s.build().expect_err("the scene must not build");
    assert_eq!(e.0.len(), 1, "{e}");
    (e.0[0].clone(), e.to_string())
}

fn penetration(e: &SceneError) -> (f64, f64, bool) {
    match e {
        SceneError::InitialPenetration {
            depth,
            limit,
            coincident,
            ..
        } => (*depth, *limit, *coincident),
        e => panic!("expected InitialPenetration, got {e:?}"),
    }
}

#[test]
fn a_ball_ninety_percent_inside_the_table_is_a_build_error() {
    let (e, msg) = the_error(&ball_in_table(0.09));
    let (depth, limit, coincident) = penetration(&e);
    assert!((depth - 0.09).abs() < 1e-12, "depth {depth}");
    assert_eq!((limit, coincident), (0.05, false));
    assert_eq!(
        msg,
        format!("invalid scene: objects `ball` and `table` start 9.000e-2 m inside each other, deeper than 5.000e-2 m (half the extent of the thinner one): {WHAT_TO_DO}")
    );
}

#[test]
fn a_ball_with_its_centre_inside_the_table_is_a_build_error() {
    // Centre 1 mm below the top face: 51 mm deep.
    let (e, msg) = the_error(&ball_in_table(0.051));
    let (depth, limit, _) = penetration(&e);
    assert!((depth - 0.051).abs() < 1e-12, "depth {depth}");
    assert_eq!(limit, 0.05);
    assert_eq!(
        msg,
        format!("invalid scene: objects `ball` and `table` start 5.100e-2 m inside each other, deeper than 5.000e-2 m (half the extent of the thinner one): {WHAT_TO_DO}")
    );
}

#[test]
fn shallow_initial_overlaps_still_build_and_run() {
    // 10 % and 45 % of the diameter: below the bound (50 %), so the model builds; the shallow
    // one also runs (the contact pushes the ball out: it ends above its start).
    for depth in [0.01, 0.045] {
        ball_in_table(depth)
            .build()
            .unwrap_or_else(|e| panic!("depth {depth}: {e}"));
    }
    let res = ball_in_table(0.01)
        .build()
        .unwrap()
        .simulate(&SimOptions::new(0.05).progress(false))
        .unwrap();
    let z = res.signal("ball.r_abs").unwrap().component(2);
    assert!(z.last().unwrap() > &z[0], "z {z:?}");
}

#[test]
fn two_coincident_steel_balls_are_a_build_error() {
    let mut s = SceneDesc::new();
    s.add(world(SceneOptions::default()));
    for name in ["a", "b"] {
        add_free_sphere(
            &mut s,
            name,
            0.1,
            "Steel",
            None,
            [0.0, 0.0, 1.0],
            [0.0; 3],
            [0.0; 3],
        );
    }
    let (e, msg) = the_error(&s);
    let (depth, limit, coincident) = penetration(&e);
    assert!((depth - 0.1).abs() < 1e-12, "depth {depth}");
    assert_eq!((limit, coincident), (0.05, true));
    assert_eq!(
        msg,
        format!("invalid scene: objects `a` and `b` start 1.000e-1 m inside each other (their centres coincide), deeper than 5.000e-2 m (half the extent of the thinner one): {WHAT_TO_DO}")
    );
    // Without collisions for one of them, the same scene builds (what the message suggests).
    if let Feature::Solid(solid) = &mut s.objects[2].feature {
        solid.collision = false;
    }
    s.build().unwrap();
}

#[test]
fn two_coincident_boxes_are_a_build_error_with_the_exact_depth() {
    // 0.2 × 0.1 × 0.3 m boxes at one place: the shallowest way out is along y, 0.1 m (MPR's
    // ray from the shifted centre gives the 0.2 m along x; the check's sampled support values
    // include the boxes' axes and give the true depth).
    let mut s = SceneDesc::new();
    s.add(world(SceneOptions::default()));
    for name in ["p", "q"] {
        s.add(
            Object3D::new(name).solid(
                Solid::new(Shape::Box {
                    lengths: Vector3::new(0.2, 0.1, 0.3),
                })
                .material("Steel")
                .collision(true),
            ),
        )
        .add_joint(Joint::new(
            &format!("{name}.free"),
            "world",
            name,
            JointKind::FreeMotion {
                r: Vector3::new(0.0, 0.0, 1.0),
                rot: FreeRotation::Cardan([0.0; 3]),
                v: Vector3::zeros(),
                w: Vector3::zeros(),
            },
        ));
    }
    let (e, msg) = the_error(&s);
    let (depth, limit, coincident) = penetration(&e);
    assert!((depth - 0.1).abs() < 1e-12, "depth {depth}");
    assert!((limit - 0.05).abs() < 1e-15 && coincident, "{e:?}");
    assert_eq!(
        msg,
        format!("invalid scene: objects `p` and `q` start 1.000e-1 m inside each other (their centres coincide), deeper than 5.000e-2 m (half the extent of the thinner one): {WHAT_TO_DO}")
    );
}

/// A ball may not pass into the table either: a steel ball (Ø 0.1 m, 4.1 kg) released 5 cm
/// above a 0.4 m thick table (thicker than the ball, so that the ball's centre stays nearer the
/// top face than the bottom one until it is a diameter deep) whose contact is made 1e9 times softer (`k_red = 1e-9`) falls into it; the run
/// ends with `SimErrorKind::TooDeep` when the ball is a whole diameter deep (the half-diameter
/// limit of a start ends a run only where IDA's steps collapse, which they do not in this
/// free fall).
///
/// Reference: free fall. The Hertz force at a diameter's depth is `k_red·(4/3)·E*·√R·δ^1.5` ≈
/// 1 N (steel, E* ≈ 1.1e11 N/m², R = 0.05 m, δ = 0.1 m) against a weight of 40 N, which moves the
/// ball by < 1e-3 m over the 0.07 s in contact: its lowest point reaches 0.1 m below the face
/// after falling 0.15 m, at `t = √(2·0.15/g)` = 0.1749 s. The check runs after every accepted
/// step, so the error comes at the first step past the limit: the depth in the error lies
/// above 0.1 m by at most one step's travel (v·h ≈ 1.7 m/s × a few ms), and the time within a
/// step of the reference. Tolerances: depth in (0.1, 0.11], time within 3 %; the partial
/// results follow free fall to 1e-3 m.
#[test]
fn a_ball_falling_through_a_soft_table_ends_with_too_deep() {
    let options = SceneOptions {
        k_red: 1e-9,
        ..SceneOptions::default()
    };
    // Its lowest point 5 cm above the table.
    let e = ball_in(0.4, -0.05, options)
        .build()
        .expect("the ball starts 5 cm above the table")
        .simulate(&SimOptions::new(0.5).progress(false))
        .expect_err("the ball must not pass through the table silently");
    let SimErrorKind::TooDeep {
        pair,
        depth,
        extent,
        t,
    } = &e.kind
    else {
        panic!("expected TooDeep, got {e:?}");
    };
    assert!(pair == "table|ball" || pair == "ball|table", "{pair}");
    assert!((extent - 0.1).abs() < 1e-12, "extent {extent}");
    assert!(*depth > 0.1 && *depth <= 0.11, "depth {depth}");
    let t_ref = (2.0 * 0.15 / 9.81_f64).sqrt();
    assert!((t - t_ref).abs() < 0.03 * t_ref, "t {t} against {t_ref}");
    // The results up to the failure: the ball fell freely until then.
    let z = e.partial.signal("ball.r_abs").unwrap().component(2);
    let time = e.partial.time();
    let (t_last, z_last) = (*time.last().unwrap(), *z.last().unwrap());
    assert!(t_last <= *t && t_last > 0.0, "last output {t_last}");
    let z_free = 0.1 - 0.5 * 9.81 * t_last * t_last;
    assert!(
        (z_last - z_free).abs() < 1e-3,
        "z {z_last} against free fall {z_free}"
    );
    println!("TooDeep at t = {t} s (free fall {t_ref} s), depth {depth} m");
    let text = e.to_string();
    assert!(
        text.contains("past the depth limit of its thinner shape"),
        "{text}"
    );
}
