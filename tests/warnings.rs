//! `result.warnings`: what a run finds suspicious without failing, each naming its culprit.

use modia3d::demo;
use modia3d::prelude::*;

fn steel() -> SolidMaterial {
    modia3d::core::scene::builtin_solid_material("Steel").unwrap()
}

/// The unit slip of issue 12: a ball of diameter 100 (meant as 100 mm) placed as if it were
/// 0.1 m, 5 mm into a 1 m table (shallower than the build error's half table thickness, deeper
/// than the 1 mm smoothing radius): the penetration warning names the pair and its depth, the
/// size warning names the ball.
#[test]
fn diameter_100_ball_on_a_table() {
    let pair = ContactPairMaterial::new(0.7, 0.0, 0.0);
    let model = demo::sphere_on_plane(100.0, steel(), 0.0, -0.005, pair, SceneOptions::default())
        .build()
        .unwrap();
    let sim = Simulation::new(&model, &SimOptions::new(1e-3).progress(false)).unwrap();
    let w = &sim.result().warnings;
    println!(
        "{}",
        w.iter()
            .map(|w| w.to_string())
            .collect::<Vec<_>>()
            .join("\n")
    );
    let pen = w
        .iter()
        .find_map(|w| match w {
            SimWarning::InitialPenetration { pair, depth, .. } => Some((pair.clone(), *depth)),
            _ => None,
        })
        .expect("a penetration warning");
    assert_eq!(pen.0, "ball|plane");
    // The depth is the placement's 5 mm (closed-form sphere–box distance).
    assert!((pen.1 - 0.005).abs() < 1e-9, "depth {}", pen.1);
    assert!(w.iter().any(|w| matches!(w,
        SimWarning::ScaleOutlier { object, quantity: "size", .. } if object == "ball")));
    let text = w.iter().map(|w| w.to_string()).collect::<String>();
    assert!(text.contains("`ball|plane`") && text.contains("units"));
    // The penetration names the size slip as its likely cause (issue 44, point 8).
    assert!(
        text.contains("5.000e-3 m deep inside each other")
            && text.contains("likely cause: `ball` is 1.000e2 m across"),
        "{text}"
    );
}

/// A ball on a Prismatic joint from the world (can_collide = false, the default) can never
/// touch the table fixed to the world: no collision pair, and a warning naming both solids and
/// the joint. With can_collide = true the pair exists and there is no warning.
#[test]
fn joint_without_collision_is_named() {
    let scene = |can_collide: bool| modia3d::demo::ball_on_a_slide(can_collide).build().unwrap();
    let opts = SimOptions::new(0.01).progress(false);
    let res = scene(false).simulate(&opts).unwrap();
    assert_eq!(res.stats.root_functions, 0);
    assert_eq!(
        res.warnings,
        vec![SimWarning::NeverCollide {
            a: "table".into(),
            b: "ball".into(),
            joint: "slide".into()
        }]
    );
    let res = scene(true).simulate(&opts).unwrap();
    assert_eq!(res.stats.root_functions, 2);
    assert!(res.warnings.is_empty(), "{:?}", res.warnings);
}

/// A 0.07 ms impact between two 10 ms output points is named; with output_steps it is not.
#[test]
fn contact_between_output_points_is_named() {
    let pair = ContactPairMaterial::new(0.9, 0.0, 0.0);
    let model = demo::sphere_on_plane(0.02, steel(), 0.0, 0.05, pair, SceneOptions::default())
        .build()
        .unwrap();
    let opts = SimOptions::new(0.15).interval(0.01).progress(false);
    let res = model.simulate(&opts).unwrap();
    let missed: Vec<_> = res
        .warnings
        .iter()
        .filter_map(|w| match w {
            SimWarning::MissedContacts {
                pair,
                phases,
                shortest,
                ..
            } => Some((pair.clone(), *phases, *shortest)),
            _ => None,
        })
        .collect();
    assert_eq!(missed.len(), 1, "{:?}", res.warnings);
    assert_eq!(missed[0].0, "ball|plane");
    assert_eq!(missed[0].1, 1);
    // The phase: from the first event with a start to the first with an end.
    let t0 = res.events.iter().find(|e| !e.started.is_empty()).unwrap().t;
    let t1 = res.events.iter().find(|e| !e.ended.is_empty()).unwrap().t;
    assert_eq!(missed[0].2, t1 - t0);
    let res = model.simulate(&opts.clone().output_steps(true)).unwrap();
    assert!(res.warnings.is_empty(), "{:?}", res.warnings);
}
