//! Every validation error names its culprit (and hints at a fix where one exists).

use modia3d::prelude::*;

fn base() -> SceneDesc {
    let mut s = SceneDesc::new();
    s.add(Object3D::new("world").scene(SceneOptions::default()));
    s
}

fn ball(name: &str) -> Object3D {
    Object3D::new(name).solid(Solid::new(Shape::Sphere { diameter: 0.1 }).material("Steel"))
}

/// Builds `s` and returns the error messages.
fn errors(s: &SceneDesc) -> Vec<String> {
    match s.build() {
        Ok(_) => panic!("the scene should be rejected"),
        Err(e) => e.0.iter().map(|e| e.to_string()).collect(),
    }
}

fn assert_one(s: &SceneDesc, needles: &[&str]) {
    let errs = errors(s);
    assert!(
        errs.iter().any(|e| needles.iter().all(|n| e.contains(n))),
        "no error contains all of {needles:?}: {errs:#?}"
    );
}

#[test]
fn unknown_parent_with_hint() {
    let mut s = base();
    s.add(ball("arm")).add(Object3D::new("tip").parent("amr"));
    assert_one(
        &s,
        &["object `tip`'s parent", "`amr`", "did you mean `arm`"],
    );
}

#[test]
fn unknown_joint_end() {
    let mut s = base();
    s.add(ball("ball"))
        .add_joint(Joint::new("j", "wrld", "ball", JointKind::free()));
    assert_one(&s, &["joint `j`'s obj1", "`wrld`", "did you mean `world`"]);
}

#[test]
fn parent_cycle() {
    let mut s = base();
    s.add(ball("a").parent("c"))
        .add(Object3D::new("b").parent("a"))
        .add(Object3D::new("c").parent("b"));
    assert_one(&s, &["parent cycle", "`a`", "`b`", "`c`"]);
}

#[test]
fn no_scene_and_several_scenes() {
    let mut s = SceneDesc::new();
    s.add(ball("ball"));
    assert_one(&s, &["no `Scene` object"]);
    let mut s = base();
    s.add(Object3D::new("world2").scene(SceneOptions::default()));
    assert_one(&s, &["several `Scene` objects", "`world`", "`world2`"]);
}

#[test]
fn scene_with_parent() {
    let mut s = SceneDesc::new();
    s.add(
        Object3D::new("world")
            .parent("holder")
            .scene(SceneOptions::default()),
    )
    .add(Object3D::new("holder"));
    assert_one(&s, &["`Scene` object `world` has a parent"]);
}

#[test]
fn duplicate_names() {
    let mut s = base();
    s.add(ball("ball").parent("world"))
        .add(ball("ball").parent("world"));
    assert_one(&s, &["duplicate object name `ball`"]);
}

#[test]
fn identical_joint_ends() {
    let mut s = base();
    s.add(ball("ball"))
        .add_joint(Joint::new("j", "ball", "ball", JointKind::revolute(1)));
    assert_one(&s, &["joint `j` joins `ball` to itself"]);
}

/// A closed chain of moving joints is no error (its loop-closing joint is cut); a loop that
/// cannot move (a joint between two objects of one rigid part) still is, naming its objects.
#[test]
fn rigid_loop_lists_its_objects_and_moving_loops_build() {
    let mut s = base();
    s.add(ball("a"))
        .add(ball("b"))
        .add_joint(Joint::new("j1", "world", "a", JointKind::revolute(1)))
        .add_joint(Joint::new("j2", "a", "b", JointKind::revolute(1)))
        .add_joint(Joint::new("j3", "b", "world", JointKind::revolute(1)));
    let model = s.build().unwrap();
    let loops = model.loops();
    assert_eq!(loops.len(), 1, "{loops:?}");
    // Breadth-first from the world, j1 and j3 reach a and b; j2 closes the loop.
    assert_eq!(loops[0].cut, "j2");
    assert_eq!(loops[0].joints, ["j2", "j1", "j3"]);
    // All three axes are the world's x axis through the origin: the loop locks nothing, every
    // one of the cut revolute's five rows is redundant.
    assert_eq!((loops[0].rows, loops[0].dropped.len()), (0, 5), "{loops:?}");
    // A parent link closing a loop through a joint is a rigid loop.
    let mut s = base();
    s.add(ball("a").parent("world")).add_joint(Joint::new(
        "j",
        "world",
        "a",
        JointKind::revolute(1),
    ));
    assert_one(&s, &["rigid kinematic loop", "`world`", "`a`"]);
}

/// An object moved by two joints without a loop (the second joint hangs a body off it) is
/// still an error; two joints that move one object around a loop are not.
#[test]
fn two_movers_without_a_loop() {
    let mut s = base();
    s.add(ball("a"))
        .add(ball("hanging"))
        .add_joint(Joint::new("j1", "world", "a", JointKind::revolute(1)))
        .add_joint(Joint::new("j2", "hanging", "a", JointKind::revolute(2)));
    assert_one(&s, &["object `a` has two parents", "`j1`", "`j2`"]);
}

#[test]
fn not_connected() {
    let mut s = base();
    s.add(ball("floating"));
    assert_one(&s, &["`floating` is not connected to the world"]);
}

#[test]
fn massless_and_singular_bodies() {
    // A revolute joint moving a bare frame: no mass at all.
    let mut s = base();
    s.add(Object3D::new("frame")).add_joint(Joint::new(
        "rev",
        "world",
        "frame",
        JointKind::revolute(1),
    ));
    assert_one(&s, &["joint `rev`", "`frame`", "has no mass"]);
    // A point mass on a free joint: mass but no rotational inertia.
    let mut s = base();
    s.add(Object3D::new("point").solid(
        Solid::new(Shape::Sphere { diameter: 0.1 }).mass_properties(
            1.0,
            Vector3::zeros(),
            Matrix3::zeros(),
        ),
    ))
    .add_joint(Joint::new("free", "world", "point", JointKind::free()));
    assert_one(&s, &["joint `free`", "`point`", "singular inertia"]);
}

#[test]
fn bad_numbers_name_the_value() {
    let mut s = base();
    s.add(
        Object3D::new("a")
            .parent("world")
            .solid(Solid::new(Shape::Sphere { diameter: f64::NAN }).material("Steel")),
    )
    .add(
        Object3D::new("b").parent("world").solid(
            Solid::new(Shape::Box {
                lengths: Vector3::new(1.0, -0.1, 1.0),
            })
            .material("Steel"),
        ),
    )
    .add(
        Object3D::new("c")
            .parent("world")
            .solid(Solid::new(Shape::Sphere { diameter: 0.1 }).mass(-2.0)),
    )
    .add(
        Object3D::new("d")
            .parent("world")
            .translation([0.0, f64::INFINITY, 0.0]),
    )
    .add(Object3D::new("e").parent("world").solid(
        Solid::new(Shape::Sphere { diameter: 0.1 }).material_value(SolidMaterial {
            density: -1.0,
            young_modulus: 1e9,
            poisson_ratio: 0.3,
        }),
    ));
    let errs = errors(&s);
    let has = |needles: &[&str]| errs.iter().any(|e| needles.iter().all(|n| e.contains(n)));
    assert!(has(&["object `a`", "diameter", "NaN"]), "{errs:#?}");
    assert!(has(&["object `b`", "lengths[1]", "-0.1"]), "{errs:#?}");
    assert!(has(&["solid `c`", "mass", "-2"]), "{errs:#?}");
    assert!(has(&["object `d`", "translation", "inf"]), "{errs:#?}");
    assert!(has(&["solid `e`", "density", "-1"]), "{errs:#?}");
    // All errors come in one pass.
    assert_eq!(errs.len(), 5, "{errs:#?}");
}

#[test]
fn unknown_material_with_hint() {
    let mut s = base();
    s.add(
        Object3D::new("ball")
            .parent("world")
            .solid(Solid::new(Shape::Sphere { diameter: 0.1 }).material("Steell")),
    );
    assert_one(&s, &["solid `ball`", "`Steell`", "did you mean `Steel`"]);
}

#[test]
fn bad_rotation_matrix_and_axis() {
    let mut s = base();
    s.add(
        Object3D::new("a")
            .parent("world")
            .rotation(Rotation::Matrix(Matrix3::identity() * 2.0)),
    )
    .add(ball("b"))
    .add_joint(Joint::new("j", "world", "b", JointKind::revolute(4)));
    let errs = errors(&s);
    assert!(
        errs.iter()
            .any(|e| e.contains("object `a`") && e.contains("rotation")),
        "{errs:#?}"
    );
    assert!(
        errs.iter()
            .any(|e| e.contains("joint `j`") && e.contains("axis")),
        "{errs:#?}"
    );
}

#[test]
fn reversed_free_motion() {
    let mut s = base();
    s.add(ball("ball"))
        .add_joint(Joint::new("free", "ball", "world", JointKind::free()));
    assert_one(&s, &["FreeMotion `free`", "swap obj1 and obj2"]);
}

#[test]
fn reversed_revolute_is_fine() {
    // obj1 on the far side: the tree runs from obj2 to obj1 with the axis negated, which must
    // give the same motion as the joint written the other way round with phi negated.
    let make = |reversed: bool| {
        let mut s = base();
        s.add(ball("bob")).add(
            Object3D::new("pivot")
                .parent("bob")
                .translation([0.0, 0.0, 1.0]),
        );
        if reversed {
            s.add_joint(
                Joint::new("rev", "pivot", "world", JointKind::revolute(1)).init_position(-0.4),
            );
        } else {
            s.add_joint(
                Joint::new("rev", "world", "pivot", JointKind::revolute(1)).init_position(0.4),
            );
        }
        s.build()
            .unwrap()
            .simulate(&SimOptions::new(1.0).tolerance(1e-10))
            .unwrap()
    };
    let (a, b) = (make(false), make(true));
    let ra = a.signal("bob.r_abs").unwrap();
    let rb = b.signal("bob.r_abs").unwrap();
    let diff = ra
        .data
        .iter()
        .zip(&rb.data)
        .map(|(x, y)| (x - y).abs())
        .fold(0.0, f64::max);
    assert!(diff < 1e-9, "{diff:e}");
}

#[test]
fn unknown_signal_has_a_hint() {
    let mut s = base();
    s.add(ball("ball"))
        .add_joint(Joint::new("rev", "world", "ball", JointKind::revolute(1)));
    let r = s.build().unwrap().simulate(&SimOptions::new(0.1)).unwrap();
    let e = r.signal("rev.ph").unwrap_err().to_string();
    assert!(
        e.contains("`rev.ph`") && e.contains("did you mean `rev.phi`"),
        "{e}"
    );
    let e = r.signal("ball.r_abs[3]").unwrap_err().to_string();
    assert!(e.contains("index 3 out of range"), "{e}");
}

#[test]
fn invalid_options_return_partial_results() {
    let mut s = base();
    s.add(ball("ball"))
        .add_joint(Joint::new("rev", "world", "ball", JointKind::revolute(1)));
    let m = s.build().unwrap();
    let e = m.simulate(&SimOptions::new(-1.0)).unwrap_err();
    assert!(e.to_string().contains("stop time"), "{e}");
    assert!(e.partial.time().is_empty());
}

#[test]
fn failed_run_carries_results_up_to_the_failure() {
    // A force law that panics after 0.3 s: the run fails with an error naming the time, and
    // the results up to then are kept.
    let mut s = base();
    s.add(ball("ball"))
        .add(
            Object3D::new("pivot")
                .parent("ball")
                .translation([0.0, 0.0, 1.0]),
        )
        .add_joint(Joint::new("rev", "world", "pivot", JointKind::revolute(1)).init_position(0.3))
        .add_force(ForceElement::ObjectForce {
            object: "ball".into(),
            law: ForceFn::new(|t, _| {
                if t > 0.3 {
                    panic!("sensor failed");
                }
                Wrench::default()
            }),
        });
    let e = s
        .build()
        .unwrap()
        .simulate(&SimOptions::new(1.0).interval(0.01))
        .unwrap_err();
    let msg = e.to_string();
    assert!(msg.contains("sensor failed"), "{msg}");
    let last = *e.partial.time().last().unwrap();
    assert!(last > 0.25 && last <= 0.31, "last output at {last}");
}

/// Topology is checked in validation, with everything else: a typo, a kinematic loop, a body
/// not connected to the world and a bad value all come back from one `build()` call (before,
/// loops and connectivity were found only once every other error was fixed), and nothing
/// else — no follow-up error of the typo (the object with the unknown parent is not reported
/// as unconnected).
#[test]
fn typo_loop_disconnected_body_and_bad_value_in_one_call() {
    let mut s = base();
    s.add(ball("a"))
        .add(ball("b"))
        .add(ball("floating"))
        .add(ball("tip").parent("aa"))
        .add(
            Object3D::new("c")
                .parent("world")
                .solid(Solid::new(Shape::Sphere { diameter: -0.1 }).material("Steel")),
        )
        .add(ball("r").parent("world"))
        .add_joint(Joint::new("j1", "world", "a", JointKind::revolute(1)))
        .add_joint(Joint::new("j2", "a", "b", JointKind::revolute(1)))
        .add_joint(Joint::new("jr", "world", "r", JointKind::revolute(1)));
    let errs = errors(&s);
    let has = |needles: &[&str]| errs.iter().any(|e| needles.iter().all(|n| e.contains(n)));
    assert!(
        has(&["object `tip`'s parent", "`aa`", "did you mean `a`"]),
        "{errs:#?}"
    );
    assert!(
        has(&["rigid kinematic loop", "`world`", "`r`"]),
        "{errs:#?}"
    );
    assert!(
        has(&["`floating` is not connected to the world"]),
        "{errs:#?}"
    );
    assert!(has(&["object `c`", "diameter", "-0.1"]), "{errs:#?}");
    assert_eq!(errs.len(), 4, "{errs:#?}");
}

/// The new joint kinds' parameters and coordinates: a Universal joint's axes must be
/// perpendicular, axes non-zero, a Spherical joint must have obj1 on the world side, and a
/// spring-damper or input on a joint with several coordinates must name one that exists.
#[test]
fn new_joint_kinds_and_their_coordinates_are_checked() {
    let mut s = base();
    s.add(ball("a"))
        .add(ball("b"))
        .add(ball("c"))
        .add_joint(Joint::new(
            "crooked",
            "world",
            "a",
            JointKind::Universal {
                axis1: Vector3::x(),
                axis2: Vector3::new(1.0, 1.0, 0.0),
                phi1: 0.0,
                phi2: 0.0,
                w1: 0.0,
                w2: 0.0,
            },
        ))
        .add_joint(Joint::new(
            "flat",
            "world",
            "b",
            JointKind::Planar {
                normal: Vector3::zeros(),
                x: 0.0,
                y: 0.0,
                phi: 0.0,
                vx: 0.0,
                vy: 0.0,
                w: 0.0,
            },
        ))
        .add_joint(Joint::new(
            "backwards",
            "c",
            "world",
            JointKind::spherical(),
        ));
    let errs = errors(&s);
    let has = |needles: &[&str]| errs.iter().any(|e| needles.iter().all(|n| e.contains(n)));
    assert!(
        has(&["joint `crooked`", "axis1 and axis2", "perpendicular"]),
        "{errs:#?}"
    );
    assert!(
        has(&["joint `flat`", "axis length", "non-zero"]),
        "{errs:#?}"
    );
    assert!(
        has(&["Spherical joint `backwards`", "world side", "swap"]),
        "{errs:#?}"
    );

    let mut s = base();
    s.add(ball("a"))
        .add_joint(Joint::new("uj", "world", "a", JointKind::universal(1, 2)))
        .add_input(Input::joint_force("tau", "uj"))
        .add_input(Input::joint_acceleration("drive", "uj").coordinate("phi3"));
    s.add_force(ForceElement::JointSpringDamper {
        joint: "uj".into(),
        coordinate: Some("phi2".into()),
        stiffness: 1.0,
        damping: 0.0,
        offset: 0.0,
    });
    let errs = errors(&s);
    let has = |needles: &[&str]| errs.iter().any(|e| needles.iter().all(|n| e.contains(n)));
    assert!(
        has(&["input `tau`", "`phi1`, `phi2`", "name one"]),
        "{errs:#?}"
    );
    assert!(
        has(&["input `drive`", "`phi3`", "did you mean `phi1`"]),
        "{errs:#?}"
    );
    // The spring on `phi2` is valid: exactly the two input errors.
    assert_eq!(errs.len(), 2, "{errs:#?}");
}
