//! Segmented simulation (dynamic structure): attach, release and delete change the state
//! layout between IDA segments. Checked against conservation laws (momentum across a plastic
//! attach and a release), the closed form of free fall after a release, and the continuity of
//! the object signals across segments. Every tolerance is argued where it is asserted.

use modia3d::prelude::*;

const G: f64 = 9.81;

fn world(gravity: [f64; 3]) -> Object3D {
    Object3D::new("world").scene(SceneOptions {
        gravity: Vector3::from(gravity),
        ..Default::default()
    })
}

/// A solid without shape (no collisions) with its centre of mass at its origin.
fn explicit(mass: f64, inertia: [f64; 3]) -> Solid {
    Solid {
        mass_properties: MassSpec::Explicit {
            mass,
            com: Vector3::zeros(),
            inertia: Matrix3::from_diagonal(&Vector3::from(inertia)),
        },
        ..Default::default()
    }
}

fn free(r: [f64; 3], rot: [f64; 3], v: [f64; 3], w: [f64; 3]) -> JointKind {
    JointKind::FreeMotion {
        r: Vector3::from(r),
        rot: FreeRotation::Cardan(rot),
        v: Vector3::from(v),
        w: Vector3::from(w),
    }
}

/// The bodies (object, mass \[kg\], inertia about the centre of mass in the object frame
/// [kg·m²]) of the free-floating arm.
const FLOATING: [(&str, f64, [f64; 3]); 3] = [
    ("base", 3.0, [0.05, 0.06, 0.07]),
    ("link", 1.0, [0.002, 0.03, 0.03]),
    ("box", 0.5, [0.001, 0.0012, 0.0014]),
];

/// A two-link arm floating free in space (gravity off): a base on a FreeMotion and a link on
/// the elbow, a gripper frame at the link's tip, and a box on its own FreeMotion moving
/// differently, so that attaching it is a genuine plastic impact.
fn floating_arm() -> Model {
    let [(base, mb, ib), (link, ml, il), (boxn, mx, ix)] = FLOATING;
    let mut s = SceneDesc::new();
    s.add(world([0.0; 3]))
        .add(Object3D::new(base).solid(explicit(mb, ib)))
        .add(
            Object3D::new("base_tip")
                .parent(base)
                .translation([0.3, 0.0, 0.0]),
        )
        .add(Object3D::new(link).solid(explicit(ml, il)))
        .add(
            Object3D::new("link_root")
                .parent(link)
                .translation([-0.25, 0.0, 0.0]),
        )
        .add(
            Object3D::new("gripper")
                .parent(link)
                .translation([0.25, 0.0, 0.0]),
        )
        .add(Object3D::new(boxn).solid(explicit(mx, ix)))
        .add_joint(Joint::new(
            "base_free",
            "world",
            base,
            free(
                [0.0; 3],
                [0.1, 0.2, 0.3],
                [0.1, -0.2, 0.05],
                [0.3, -0.1, 0.2],
            ),
        ))
        .add_joint(
            Joint::new("elbow", "base_tip", "link_root", JointKind::revolute(3))
                .init_position(0.4)
                .init_velocity(1.5),
        )
        .add_joint(Joint::new(
            "box_free",
            "world",
            boxn,
            free(
                [0.6, 0.3, 0.1],
                [0.0, 0.3, -0.2],
                [-0.3, 0.2, 0.1],
                [1.0, 0.5, -0.2],
            ),
        ));
    s.build().unwrap()
}

/// Signal `name` at output point `k`.
fn at(res: &SimulationResult, name: &str, k: usize) -> Vector3<f64> {
    let s = res.signal(name).unwrap();
    Vector3::from_column_slice(s.at(k).unwrap())
}

/// Total linear momentum [kg·m/s], angular momentum about the world origin [kg·m²/s] and
/// kinetic energy \[J\] of `bodies` at output point `k`, from the object signals (centres of
/// mass at the object origins).
fn momentum(
    res: &SimulationResult,
    bodies: &[(&str, f64, [f64; 3])],
    k: usize,
) -> (Vector3<f64>, Vector3<f64>, f64) {
    let (mut p, mut l, mut e) = (Vector3::zeros(), Vector3::zeros(), 0.0);
    for &(name, m, inertia) in bodies {
        let r = at(res, &format!("{name}.r_abs"), k);
        let v = at(res, &format!("{name}.v_abs"), k);
        let w = at(res, &format!("{name}.w_abs"), k);
        let rot = res.signal(&format!("{name}.R_abs")).unwrap();
        // R_abs is row-major with the object axes as columns.
        let rot = Matrix3::from_row_slice(rot.at(k).unwrap());
        let i_world = rot * Matrix3::from_diagonal(&Vector3::from(inertia)) * rot.transpose();
        p += m * v;
        l += i_world * w + r.cross(&(m * v));
        e += 0.5 * (m * v.norm_squared() + w.dot(&(i_world * w)));
    }
    (p, l, e)
}

/// The two output points at time `t`: the last of the old segment and the first of the new.
fn action_points(res: &SimulationResult, t: f64) -> (usize, usize) {
    let ks: Vec<usize> = (0..res.time().len())
        .filter(|&k| res.time()[k] == t)
        .collect();
    assert_eq!(ks.len(), 2, "two output points at the action's time {t}");
    (ks[0], ks[1])
}

#[test]
fn attach_and_release_conserve_momentum() {
    let model = floating_arm();
    let mut sim = model
        .simulation(&SimOptions::new(1.0).tolerance(1e-10))
        .unwrap();
    sim.advance_to(0.3).unwrap();
    sim.attach("box", "gripper", f64::INFINITY).unwrap();
    sim.advance_to(0.6).unwrap();
    sim.release("box").unwrap();
    sim.advance_to(1.0).unwrap();
    let res = sim.into_result();
    assert_eq!(res.segment_count(), 3);
    for (t, plastic) in [(0.3, true), (0.6, false)] {
        let (k0, k1) = action_points(&res, t);
        let (p0, l0, e0) = momentum(&res, &FLOATING, k0);
        let (p1, l1, e1) = momentum(&res, &FLOATING, k1);
        // Nothing outside the system takes up an impulse (no world joint, no gravity): the
        // projection conserves both momenta exactly; what is left is the round-off of the
        // mass-matrix solve and the signals (≈ 1e-15 relative), asserted at the brief's 1e-9.
        let (dp, dl) = ((p1 - p0).norm() / p0.norm(), (l1 - l0).norm() / l0.norm());
        assert!(dp < 1e-9, "t = {t}: linear momentum {p0} → {p1} ({dp:.2e})");
        assert!(
            dl < 1e-9,
            "t = {t}: angular momentum {l0} → {l1} ({dl:.2e})"
        );
        if plastic {
            // A plastic impact dissipates: the box moved relative to the gripper.
            assert!(e1 < e0 * (1.0 - 1e-3), "kinetic energy {e0} → {e1}");
        } else {
            // A release is no impact: every motion goes on (round-off only).
            assert!((e1 - e0).abs() < 1e-12 * e0, "kinetic energy {e0} → {e1}");
            for (name, _, _) in FLOATING {
                for q in ["v_abs", "w_abs"] {
                    let n = format!("{name}.{q}");
                    let d = (at(&res, &n, k1) - at(&res, &n, k0)).norm();
                    assert!(d < 1e-12, "{n} jumps by {d:.2e} at the release");
                }
            }
        }
        // Poses are kept exactly (up to the quaternion round trip of a new FreeMotion).
        for (name, _, _) in FLOATING {
            let n = format!("{name}.r_abs");
            let d = (at(&res, &n, k1) - at(&res, &n, k0)).norm();
            assert!(d < 1e-12, "{n} jumps by {d:.2e} at t = {t}");
        }
    }
    // Between the actions momentum is conserved by the integration alone (rtol 1e-10).
    let (p_start, l_start, _) = momentum(&res, &FLOATING, 0);
    let (p_end, l_end, _) = momentum(&res, &FLOATING, res.time().len() - 1);
    assert!((p_end - p_start).norm() < 1e-7 * p_start.norm());
    assert!((l_end - l_start).norm() < 1e-7 * l_start.norm());
    // The box's free joint: signals where it exists, NaN while the box is attached.
    let r = res.signal("box_free.r").unwrap();
    assert_eq!(r.len(), res.time().len());
    let k_mid = res.time().iter().position(|&t| t > 0.45).unwrap();
    assert!(r.at(k_mid).unwrap().iter().all(|x| x.is_nan()));
    assert!(r.last().unwrap().iter().all(|x| x.is_finite()));
    // The actions are events of the log.
    let described: Vec<_> = res.events.iter().map(|e| e.description.as_str()).collect();
    assert!(described
        .iter()
        .any(|d| d.contains("attach `box` to `gripper`")));
    assert!(described.iter().any(|d| d.contains("release `box`")));
}

#[test]
fn attach_to_an_arm_on_the_world_conserves_the_axial_angular_momentum() {
    // An arm on a world revolute about z (gravity off) catches a moving ball at its tip. The
    // joint takes up an impulse, so the total momentum is not conserved; the projection keeps
    // the momentum conjugate to every motion the new structure can make — here the rotation
    // about the joint axis: the angular momentum about z through the pivot.
    let bodies = [("arm", 2.0, [0.01, 0.2, 0.2]), ("ball", 0.5, [0.001; 3])];
    let mut s = SceneDesc::new();
    s.add(world([0.0; 3]))
        .add(Object3D::new("arm").solid(explicit(bodies[0].1, bodies[0].2)))
        .add(
            Object3D::new("pivot")
                .parent("arm")
                .translation([-0.5, 0.0, 0.0]),
        )
        .add(
            Object3D::new("hand")
                .parent("arm")
                .translation([0.5, 0.0, 0.0]),
        )
        .add(Object3D::new("ball").solid(explicit(bodies[1].1, bodies[1].2)))
        .add_joint(Joint::new("spin", "world", "pivot", JointKind::revolute(3)).init_velocity(2.0))
        .add_joint(Joint::new(
            "fly",
            "world",
            "ball",
            free([1.0, 0.0, 0.0], [0.0; 3], [0.0, -0.3, 0.2], [0.5, 0.0, 1.0]),
        ));
    let mut sim = s
        .build()
        .unwrap()
        .simulation(&SimOptions::new(0.5).tolerance(1e-10))
        .unwrap();
    sim.attach("ball", "hand", 1e-9).unwrap();
    sim.advance_to(0.5).unwrap();
    let res = sim.into_result();
    let (k0, k1) = action_points(&res, 0.0);
    let (p0, l0, _) = momentum(&res, &bodies, k0);
    let (p1, l1, _) = momentum(&res, &bodies, k1);
    // About z through the pivot (the world origin): round-off only.
    assert!(
        (l1.z - l0.z).abs() < 1e-9 * l0.z.abs(),
        "L_z {} → {}",
        l0.z,
        l1.z
    );
    // The joint took up an impulse: the linear momentum changed.
    assert!((p1 - p0).norm() > 0.1 * p0.norm(), "p {p0} → {p1}");
    // Afterwards it is conserved by the integration (no torque about z; rtol 1e-10).
    let (_, l_end, _) = momentum(&res, &bodies, res.time().len() - 1);
    assert!((l_end.z - l1.z).abs() < 1e-7 * l1.z.abs());
}

/// A two-link arm on the world (shoulder and elbow about y, held by spring-dampers under
/// gravity), a gripper frame at its tip and a free cube `box` 5 mm below the gripper.
fn gripper_scene(box_offset: f64) -> SceneDesc {
    let cube = 0.3 * 0.05 * 0.05 / 6.0; // cube of 5 cm, 0.3 kg: isotropic inertia
    let mut s = SceneDesc::new();
    s.add(world([0.0, 0.0, -G]))
        .add(Object3D::new("link1").solid(explicit(2.0, [0.001, 0.04, 0.04])))
        .add(
            Object3D::new("l1_root")
                .parent("link1")
                .translation([-0.25, 0.0, 0.0]),
        )
        .add(
            Object3D::new("l1_tip")
                .parent("link1")
                .translation([0.25, 0.0, 0.0]),
        )
        .add(Object3D::new("link2").solid(explicit(1.0, [0.001, 0.015, 0.015])))
        .add(
            Object3D::new("l2_root")
                .parent("link2")
                .translation([-0.2, 0.0, 0.0]),
        )
        .add(
            Object3D::new("gripper")
                .parent("link2")
                .translation([0.2, 0.0, 0.0]),
        )
        .add(Object3D::new("box").solid(explicit(0.3, [cube; 3])))
        .add_joint(Joint::new(
            "shoulder",
            "world",
            "l1_root",
            JointKind::revolute(2),
        ))
        .add_joint(Joint::new(
            "elbow",
            "l1_tip",
            "l2_root",
            JointKind::revolute(2),
        ))
        .add_joint(Joint::new(
            "box_free",
            "world",
            "box",
            free([0.9, 0.0, -box_offset], [0.0; 3], [0.0; 3], [0.0; 3]),
        ))
        .add_force(ForceElement::JointSpringDamper {
            joint: "shoulder".into(),
            coordinate: None,
            stiffness: 200.0,
            damping: 5.0,
            offset: -0.6,
        })
        .add_force(ForceElement::JointSpringDamper {
            joint: "elbow".into(),
            coordinate: None,
            stiffness: 100.0,
            damping: 2.0,
            offset: -0.8,
        });
    s
}

#[test]
fn released_box_falls_freely_and_delete_shrinks_the_state() {
    let rtol = 1e-9;
    let model = gripper_scene(0.005).build().unwrap();
    let opts = SimOptions::new(1.5).tolerance(rtol).interval(0.01);
    let mut sim = model.simulation(&opts).unwrap();
    // Within the gap (5 mm apart, gap 1 cm): gripped at the start.
    sim.attach("box", "gripper", 0.01).unwrap();
    let n_attached = sim.state().len();
    sim.advance_to(0.7).unwrap();
    sim.release("box").unwrap();
    // The box's FreeMotion adds 7 positions and 6 velocities.
    assert_eq!(sim.state().len(), n_attached + 13);
    sim.advance_to(1.2).unwrap();
    let n_free = sim.state().len();
    sim.delete("box").unwrap();
    assert_eq!(sim.state().len(), n_free - 13);
    assert_eq!(sim.model().state_len(), n_free - 13);
    sim.advance_to(1.5).unwrap();
    let res = sim.into_result();
    assert_eq!(res.segment_count(), 4);

    // Free fall after the release at t_r from the state there (new segment's first point).
    let (_, k_r) = action_points(&res, 0.7);
    let (r0, v0) = (at(&res, "box.r_abs", k_r), at(&res, "box.v_abs", k_r));
    assert!(v0.norm() > 0.1, "the arm throws the box ({v0})");
    let g = Vector3::new(0.0, 0.0, -G);
    let (_, k_d) = action_points(&res, 1.2);
    let mut worst: f64 = 0.0;
    for k in k_r..=k_d {
        let dt = res.time()[k] - 0.7;
        let exact = r0 + v0 * dt + 0.5 * g * dt * dt;
        worst = worst.max((at(&res, "box.r_abs", k) - exact).norm());
    }
    // The motion is a quadratic in t, which BDF of order ≥ 2 and IDA's interpolating
    // polynomial reproduce exactly: what remains is the Newton iterations' error, bounded by
    // the local error test (rtol 1e-9 on positions of order 1 m) → 1e-7 m is 100× that.
    assert!(worst < 1e-7, "free fall off by {worst:.2e} m");

    // Delete: the box's signals end (NaN), the arm goes on continuously.
    let (k0, k1) = action_points(&res, 1.2);
    let gone = res.signal("box.r_abs").unwrap();
    assert!(gone.at(k0).unwrap()[0].is_finite());
    assert!(gone.at(k1).unwrap()[0].is_nan());
    assert!(gone.last().unwrap()[0].is_nan());
    for name in ["link2.r_abs", "link2.v_abs", "gripper.r_abs"] {
        let d = (at(&res, name, k1) - at(&res, name, k0)).norm();
        assert!(d < 1e-12, "{name} jumps by {d:.2e} at the delete");
    }
    // While attached, the box moves with the gripper at its 5 mm offset.
    let k = res.time().iter().position(|&t| t > 0.5).unwrap();
    let offset = at(&res, "box.r_abs", k) - at(&res, "gripper.r_abs", k);
    assert!((offset.norm() - 0.005).abs() < 1e-12, "offset {offset}");
    // `signal_at` at an action's time gives the new segment's value.
    let after = res.signal_at("box.r_abs", 1.2).unwrap();
    assert!(after[0].is_nan());
}

#[test]
fn scheduled_actions_run_at_their_times_and_log_events() {
    let mut scene = gripper_scene(0.005);
    scene
        .add_action(Action::attach("pick", 0.0, "box", "gripper", 0.01))
        .add_action(Action::release("drop", 0.7, "box"))
        .add_action(Action::delete("gone", 1.2, "box"));
    let res = scene
        .build()
        .unwrap()
        .simulate(&SimOptions::new(1.5).tolerance(1e-8))
        .unwrap();
    assert_eq!(res.segment_count(), 4);
    let actions: Vec<_> = res
        .events
        .iter()
        .filter(|e| e.description.starts_with("action"))
        .map(|e| (e.t, e.description.clone()))
        .collect();
    assert_eq!(actions.len(), 3, "{actions:?}");
    assert_eq!(actions[0].0, 0.0);
    assert!(actions[0].1.contains("`pick`: attach `box` to `gripper`"));
    assert_eq!(actions[1].0, 0.7);
    assert!(actions[1].1.contains("`drop`: release `box`"));
    assert_eq!(actions[2].0, 1.2);
    assert!(actions[2].1.contains("`gone`: delete `box`"));
}

/// `Simulation::step` never steps past a scheduled action: the actions run at their times,
/// as in a one-shot run, and a step starting at an action's time carries it out first.
#[test]
fn single_steps_stop_at_scheduled_actions() {
    let mut scene = gripper_scene(0.005);
    scene
        .add_action(Action::attach("pick", 0.0, "box", "gripper", 0.01))
        .add_action(Action::release("drop", 0.7, "box"));
    let mut sim = scene
        .build()
        .unwrap()
        .simulation(&SimOptions::new(1.0).tolerance(1e-8))
        .unwrap();
    let mut times = vec![];
    while sim.time() < 1.0 {
        times.push(sim.step().unwrap());
    }
    assert!(times.contains(&0.7), "no step ended at the release");
    let res = sim.into_result();
    assert_eq!(res.segment_count(), 3);
    let at: Vec<f64> = res
        .events
        .iter()
        .filter(|e| e.description.starts_with("action"))
        .map(|e| e.t)
        .collect();
    assert_eq!(at, [0.0, 0.7]);
}

#[test]
fn attach_out_of_the_gap_is_a_typed_error() {
    // 5 cm apart, gap 1 cm: the scheduled attach fails, naming both and the distance (the
    // frame origins' distance, as neither has a shape).
    let mut scene = gripper_scene(0.05);
    scene.add_action(Action::attach("pick", 0.1, "box", "gripper", 0.01));
    let err = scene
        .build()
        .unwrap()
        .simulate(&SimOptions::new(0.5))
        .unwrap_err();
    let SimErrorKind::Action { t, error } = &err.kind else {
        panic!("expected an action error, got {err}");
    };
    assert_eq!(*t, 0.1);
    let ActionError::OutOfGap {
        object,
        to,
        distance,
        gap,
    } = &**error
    else {
        panic!("expected OutOfGap, got {error}");
    };
    assert_eq!(
        (object.as_str(), to.as_str(), *gap),
        ("box", "gripper", 0.01)
    );
    // The box falls from 5 cm below the gripper while the arm sags: more than 5 cm apart.
    assert!(*distance > 0.05, "distance {distance}");
    assert!(err.to_string().contains("more than the gap"));
    // The partial result reaches the action's time.
    assert_eq!(err.partial.time().last(), Some(&0.1));

    // Step-wise: the same check, and the simulation is unchanged and goes on.
    let model = gripper_scene(0.05).build().unwrap();
    let mut sim = model.simulation(&SimOptions::new(0.5)).unwrap();
    let e = sim.attach("box", "gripper", 0.01).unwrap_err();
    assert!(
        matches!(e, ActionError::OutOfGap { distance, .. } if (distance - 0.05).abs() < 1e-12),
        "{e}"
    );
    let e = sim.attach("bx", "gripper", 0.01).unwrap_err();
    assert!(e.to_string().contains("did you mean `box`"), "{e}");
    let e = sim.release("box").unwrap_err();
    assert!(matches!(e, ActionError::NotAttached { .. }), "{e}");
    let e = sim.attach("link2", "gripper", 1.0).unwrap_err();
    assert!(matches!(e, ActionError::NotFree { .. }), "{e}");
    sim.advance_to(0.5).unwrap();
    assert_eq!(sim.result().segment_count(), 1);
}

#[test]
fn actions_naming_unknown_objects_are_scene_errors() {
    let mut scene = gripper_scene(0.005);
    scene
        .add_action(Action::attach("pick", 0.1, "bx", "gripper", 0.01))
        .add_action(Action::release("drop", -1.0, "box"));
    let errors = scene.build().unwrap_err().to_string();
    assert!(errors.contains("action `pick`'s object names unknown object `bx`"));
    assert!(errors.contains("did you mean `box`"));
    assert!(errors.contains("action `drop`: time [s] is -1"));
}

#[allow(dead_code)] // only `run` is used, not the example's main
#[path = "../examples/gripper.rs"]
mod gripper_example;

#[test]
fn gripper_example_picks_carries_and_drops_the_box() {
    let res = gripper_example::run(3.0, true).unwrap();
    assert_eq!(res.segment_count(), 3);
    // The actions declared in the `model!` ran at their times.
    let actions: Vec<f64> = res
        .events
        .iter()
        .filter(|e| e.description.starts_with("action"))
        .map(|e| e.t)
        .collect();
    assert_eq!(actions, [1.0, 2.2]);
    // Carried rigidly: the cube keeps its distance to the gripper while attached (round-off).
    let (_, k_pick) = action_points(&res, 1.0);
    let (k_drop, k_free) = action_points(&res, 2.2);
    let dist = |k| (at(&res, "cube.r_abs", k) - at(&res, "gripper.r_abs", k)).norm();
    let d0 = dist(k_pick);
    for k in k_pick..=k_drop {
        assert!(
            (dist(k) - d0).abs() < 1e-12,
            "held cube moved by {}",
            dist(k) - d0
        );
    }
    let lifted = (k_pick..=k_drop)
        .map(|k| at(&res, "cube.r_abs", k).z)
        .fold(f64::MIN, f64::max);
    assert!(lifted > 0.2, "the cube was lifted to {lifted} m");
    // Free fall from the release to the first contact with the table.
    let t_land = res
        .events
        .iter()
        .find(|e| e.t > 2.2 && !e.started.is_empty())
        .unwrap()
        .t;
    let (r0, v0) = (
        at(&res, "cube.r_abs", k_free),
        at(&res, "cube.v_abs", k_free),
    );
    let g = Vector3::new(0.0, 0.0, -G);
    for k in (k_free..res.time().len()).take_while(|&k| res.time()[k] < t_land) {
        let dt = res.time()[k] - 2.2;
        let err = (at(&res, "cube.r_abs", k) - (r0 + v0 * dt + 0.5 * g * dt * dt)).norm();
        // A quadratic is integrated exactly by BDF of order ≥ 2; the Newton iterations' error
        // is bounded by the local error test (rtol 1e-6 on positions of 0.1 m scale): 1e-6 m.
        assert!(
            err < 1e-6,
            "free fall off by {err:.2e} m at t = {}",
            res.time()[k]
        );
    }
    // It comes to rest on the table (static penetration at k_red = 1e-3 ≈ 1e-6 m).
    let r = res.signal("cube.r_abs").unwrap();
    let v = res.signal("cube.v_abs").unwrap();
    assert!((r.last().unwrap()[2] - 0.025).abs() < 1e-4);
    assert!(Vector3::from_column_slice(v.last().unwrap()).norm() < 1e-3);
    // Contact phases go on across segments: the resting phase open at the pick is closed at
    // its time (no exit speed: the pair did not separate), and the new segment opens one that
    // ends when the arm lifts the cube.
    let phases = res.contact_phases("table|cube").unwrap();
    let cut = phases.iter().find(|p| p.end == Some(1.0)).unwrap();
    assert_eq!((cut.start, cut.exit_speed), (0.0, None));
    let lifted_off = phases.iter().find(|p| p.start == 1.0).unwrap();
    assert!(lifted_off.end.unwrap() > 1.0 && lifted_off.end.unwrap() < 1.3);
    // Contact signals span every segment.
    assert_eq!(
        res.signal("table|cube.in_contact").unwrap().len(),
        res.time().len()
    );
}

#[test]
fn dense_output_reads_each_segment_in_its_own_layout() {
    // The same segmented run with and without IDA's dense output: `signal_at` between output
    // points goes to the segment holding t, whose states have that segment's layout (13 more
    // unknowns while the box is free). Both interpolate a 1e-10 run; a layout mix-up would be
    // off by metres, the interpolations differ by far less than 1e-6 m.
    let run = |dense: bool| {
        let opts = SimOptions::new(0.9)
            .tolerance(1e-10)
            .interval(0.01)
            .dense_output(dense);
        let mut sim = floating_arm().simulation(&opts).unwrap();
        sim.advance_to(0.3).unwrap();
        sim.attach("box", "gripper", f64::INFINITY).unwrap();
        sim.advance_to(0.6).unwrap();
        sim.release("box").unwrap();
        sim.advance_to(0.9).unwrap();
        sim.into_result()
    };
    let (dense, cubic) = (run(true), run(false));
    for t in [0.155, 0.455, 0.755] {
        for name in ["box.r_abs", "link.r_abs", "elbow.phi"] {
            let (a, b) = (
                dense.signal_at(name, t).unwrap(),
                cubic.signal_at(name, t).unwrap(),
            );
            let d = a
                .iter()
                .zip(&b)
                .map(|(x, y)| (x - y).abs())
                .fold(0.0, f64::max);
            assert!(d < 1e-6, "{name} at {t}: {a:?} vs {b:?}");
        }
    }
    // The box's free joint is NaN while it is attached, in both.
    assert!(dense.signal_at("box_free.r", 0.455).unwrap()[0].is_nan());
}
