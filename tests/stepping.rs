//! Step-wise simulation and inputs, against one-shot runs and closed forms.

use modia3d::prelude::*;

#[allow(dead_code)] // only the model type is used, not the example's main
#[path = "../examples/double_pendulum.rs"]
mod double_pendulum_example;

fn double_pendulum() -> SceneDesc {
    double_pendulum_example::DoublePendulum::default().scene()
}

/// `step()` takes the solver's own steps: stepping to the stop time is the one-shot run bit
/// for bit (the same calls of IDA in the same order), one solver step per call, and a
/// monitor can stop at a crossing the way `mj_step` users do, locating it within the step by
/// the dense output.
#[test]
fn solver_steps_one_at_a_time_are_the_one_shot_run() {
    let model = double_pendulum().build().unwrap();
    let opts = SimOptions::new(0.5)
        .tolerance(1e-8)
        .interval(0.01)
        .dense_output(true);
    let once = model.simulate(&opts).unwrap();
    let mut sim = model.simulation(&opts).unwrap();
    let mut calls = 0u64;
    let mut t_prev = sim.time();
    while sim.time() < 0.5 {
        let t = sim.step().unwrap();
        assert!(t > t_prev, "step() did not advance from {t_prev}");
        t_prev = t;
        calls += 1;
    }
    // At the stop time it does nothing.
    assert_eq!(sim.step().unwrap(), 0.5);
    let stepped = sim.into_result();
    assert_eq!(once.stats.solver, stepped.stats.solver);
    assert_eq!(calls, stepped.stats.solver.steps);
    assert_eq!(once.time(), stepped.time());
    assert_eq!(
        once.signal("rev1.phi").unwrap().data,
        stepped.signal("rev1.phi").unwrap().data
    );

    // A monitor: the first time rev1.phi crosses a level it reaches after 0.25 s (the mean
    // of its values at 0.25 s and 0.26 s), located in the step by bisection on the dense
    // output, which reaches past the last output point to the step's end, against the same
    // crossing found on a 1e-5 s grid of the one-shot run (both read IDA's interpolant of
    // the same steps: 1e-9 s covers the grid run's linear interpolation, O(h²·φ''/φ') with
    // h = 1e-5 s).
    let level = 0.5
        * (once.signal_at("rev1.phi", 0.25).unwrap()[0]
            + once.signal_at("rev1.phi", 0.26).unwrap()[0]);
    let mut sim = model.simulation(&opts).unwrap();
    let phi = |sim: &mut Simulation| sim.output("rev1.phi").unwrap()[0];
    let side = phi(&mut sim) > level;
    let (mut a, mut b) = (0.0, 0.0);
    while sim.time() < 0.5 {
        a = sim.time();
        b = sim.step().unwrap();
        if (phi(&mut sim) > level) != side {
            break;
        }
    }
    let res = sim.result();
    for _ in 0..60 {
        let m = 0.5 * (a + b);
        if (res.signal_at("rev1.phi", m).unwrap()[0] > level) == side {
            a = m;
        } else {
            b = m;
        }
    }
    let fine = model
        .simulate(&opts.clone().interval(1e-5).dense_output(false))
        .unwrap();
    let (t, v) = (fine.time(), fine.signal("rev1.phi").unwrap().values());
    let k = (1..t.len()).find(|&k| (v[k] > level) != side).unwrap();
    let grid = t[k - 1] + (t[k] - t[k - 1]) * (level - v[k - 1]) / (v[k] - v[k - 1]);
    assert!((a - grid).abs() < 1e-9, "monitor {a} against grid {grid}");
}

#[test]
fn stepping_in_1ms_steps_matches_one_simulate_call() {
    let model = double_pendulum().build().unwrap();
    let opts = SimOptions::new(1.0).tolerance(1e-9).interval(0.1);
    let once = model.simulate(&opts).unwrap();
    let mut sim = model.simulation(&opts).unwrap();
    for k in 1..=1000 {
        sim.advance_to(k as f64 * 1e-3).unwrap();
    }
    assert!((sim.time() - 1.0).abs() < 1e-12);
    let a = once.final_state().unwrap();
    let b = sim.state();
    let diff = a
        .iter()
        .zip(b)
        .map(|(x, y)| (x - y).abs())
        .fold(0.0, f64::max);
    println!("1 ms stepping vs one call: max state difference at 1 s {diff:.2e}");
    // Both runs are error-controlled at rtol 1e-9 but take different steps (every 1 ms is a
    // stop time); their difference is bounded by the two global errors, which for this
    // chaotic pendulum at 1 s are ~3e-8 (tests/multibody.rs): 1e-6 leaves margin for growth.
    assert!(diff < 1e-6, "difference {diff:e}");
    // Every advance_to target is an output point, plus the grid points in between.
    assert!(sim.result().time().len() >= 1001);
    // Output by name equals the recorded final value.
    let phi = sim.output("rev1.phi").unwrap();
    assert_eq!(
        phi[0],
        *sim.result()
            .signal("rev1.phi")
            .unwrap()
            .last()
            .unwrap()
            .first()
            .unwrap()
    );
}

/// A disc on a revolute joint about the vertical axis (gravity does no work), driven by inputs.
fn turntable() -> (SceneDesc, f64) {
    let (m, r) = (2.0, 0.3);
    let j = 0.5 * m * r * r; // solid disc about its axis
    let mut s = SceneDesc::new();
    s.add(Object3D::new("world").scene(SceneOptions::default()))
        .add(
            Object3D::new("disc").solid(
                Solid::new(Shape::Cylinder {
                    axis: Axis::Z,
                    diameter: 2.0 * r,
                    length: 0.05,
                })
                .mass(m),
            ),
        )
        .add_joint(Joint::new("rev", "world", "disc", JointKind::revolute(3)))
        .add_input(Input::joint_force("tau", "rev"));
    (s, j)
}

#[test]
fn constant_torque_input_gives_quadratic_angle() {
    let (s, j) = turntable();
    let tau = 0.7;
    let model = s.build().unwrap();
    let mut sim = model
        .simulation(&SimOptions::new(2.0).tolerance(1e-10))
        .unwrap();
    // Torque-free until 0.5 s, then a constant torque: φ(t) = ½ τ/J (t − 0.5)².
    sim.advance_to(0.5).unwrap();
    assert!(sim.output("rev.phi").unwrap()[0].abs() < 1e-15);
    sim.set_input("tau", &[tau]).unwrap();
    for k in 1..=15 {
        let t = 0.5 + 0.1 * k as f64;
        sim.advance_to(t).unwrap();
        let phi = sim.output("rev.phi").unwrap()[0];
        let exact = 0.5 * tau / j * (t - 0.5) * (t - 0.5);
        // A quadratic is integrated exactly by BDF of order ≥ 2; what remains is the start-up
        // at order 1 after the restart, bounded by the tolerance: 1e-8 absolute on ~50 rad.
        assert!((phi - exact).abs() < 1e-8, "t = {t}: {phi} vs {exact}");
    }
}

#[test]
fn prescribed_acceleration_and_object_wrench() {
    // A slider with a prescribed acceleration, carrying a pendulum; and a free ball pushed by
    // a world force.
    let mut s = SceneDesc::new();
    s.add(Object3D::new("world").scene(SceneOptions {
        gravity: Vector3::zeros(),
        ..Default::default()
    }))
    .add(
        Object3D::new("cart").solid(
            Solid::new(Shape::Box {
                lengths: Vector3::new(0.2, 0.1, 0.1),
            })
            .mass(1.0),
        ),
    )
    .add(Object3D::new("ball").solid(Solid::new(Shape::Sphere { diameter: 0.1 }).mass(0.5)))
    .add_joint(Joint::new("slide", "world", "cart", JointKind::prismatic(1)).init_velocity(0.2))
    .add_joint(Joint::new("free", "world", "ball", JointKind::free()))
    .add_input(Input::joint_acceleration("a", "slide"))
    .add_input(Input::object_wrench("push", "ball"));
    let model = s.build().unwrap();
    let mut sim = model
        .simulation(&SimOptions::new(1.0).tolerance(1e-10))
        .unwrap();
    sim.set_input("a", &[1.5]).unwrap();
    sim.set_input("push", &[0.0, 0.25, 0.0, 0.0, 0.0, 0.0])
        .unwrap();
    sim.advance_to(1.0).unwrap();
    let s_cart = sim.output("slide.s").unwrap()[0];
    let r_ball = sim.output("ball.r_abs").unwrap();
    // s = v0 t + ½ a t², r_y = ½ F/m t²: exact quadratics (see above for the tolerance).
    assert!((s_cart - (0.2 + 0.75)).abs() < 1e-9, "{s_cart}");
    assert!((r_ball[1] - 0.25).abs() < 1e-9, "{r_ball:?}");
    assert!(r_ball[0].abs() < 1e-12 && r_ball[2].abs() < 1e-12);
}

#[test]
fn reset_reruns_identically_and_inputs_are_checked() {
    let (s, _) = turntable();
    let model = s.build().unwrap();
    let mut sim = model.simulation(&SimOptions::new(1.0)).unwrap();
    let run = |sim: &mut Simulation| {
        sim.set_input("tau", &[0.3]).unwrap();
        sim.advance_to(1.0).unwrap();
        sim.output("rev.w").unwrap()[0]
    };
    let first = run(&mut sim);
    sim.reset().unwrap();
    assert_eq!(sim.time(), 0.0);
    assert_eq!(sim.output("rev.w").unwrap()[0], 0.0);
    let second = run(&mut sim);
    assert_eq!(first, second, "a reset run is the same computation");
    let e = sim.set_input("tua", &[1.0]).unwrap_err().to_string();
    assert!(
        e.contains("`tua`") && e.contains("did you mean `tau`"),
        "{e}"
    );
    let e = sim.set_input("tau", &[1.0, 2.0]).unwrap_err().to_string();
    assert!(e.contains("takes 1 value"), "{e}");
    let e = sim.set_input("tau", &[f64::NAN]).unwrap_err().to_string();
    assert!(e.contains("non-finite"), "{e}");
    // Advancing backwards or beyond the stop time is an error, not a panic.
    assert!(sim.advance_to(0.5).is_err());
}

#[test]
fn input_declarations_are_validated() {
    let (mut s, _) = turntable();
    s.add_input(Input::joint_force("bad", "rv"))
        .add_input(Input::object_wrench("bad2", "dsc"));
    let e = s.build().unwrap_err().to_string();
    assert!(
        e.contains("input `bad`") && e.contains("did you mean `rev`"),
        "{e}"
    );
    assert!(
        e.contains("input `bad2`") && e.contains("did you mean `disc`"),
        "{e}"
    );
}

#[path = "../examples/controlled_arm.rs"]
mod controlled_arm;

#[test]
fn controlled_arm_tracks_reproducibly() {
    let a = controlled_arm::run_controller(2.0).unwrap();
    let b = controlled_arm::run_controller(2.0).unwrap();
    println!("controlled arm: max {:.4} rad, rms {:.4} rad", a.max, a.rms);
    // Same inputs, same computation: bit-identical errors.
    assert_eq!((a.max, a.rms), (b.max, b.rms));
    assert_eq!(a.updates, 2000);
    // The PD loop (kp 300/100 N·m/rad) holds the error to a few hundredths of a radian against
    // an uncompensated gravity torque of ~6 N·m at the shoulder (6/300 = 0.02 rad); a broken
    // input path would leave the arm hanging, 0.6 rad off.
    assert!(a.max < 0.05, "max tracking error {}", a.max);
}

mod recorder;
use recorder::Recorder;

#[test]
fn events_are_traced() {
    let rec = std::sync::Arc::new(Recorder(std::sync::Mutex::new(vec![])));
    let model = modia3d::demo::bouncing_sphere(0.02, 0.1, ContactPairMaterial::new(0.7, 0.0, 0.0))
        .build()
        .unwrap();
    let res = tracing::subscriber::with_default(rec.clone(), || {
        model
            .simulate(&SimOptions::new(0.5).progress(false))
            .unwrap()
    });
    let msgs = rec.0.lock().unwrap();
    let traced = msgs.iter().filter(|m| m.contains("message=event")).count();
    assert!(res.events.len() >= 2, "the ball bounces");
    assert_eq!(traced, res.events.len(), "{msgs:#?}");
    assert!(msgs.iter().any(|m| m.contains("contact started")));
    assert!(msgs.iter().any(|m| m.contains("simulation finished")));
}

#[test]
fn contact_force_is_an_output_while_stepping() {
    // A steel ball resting on a steel table (analytic static penetration from Hertz): stepping
    // with contact results on, the normal force read by name balances the weight.
    let d = 0.05;
    let mut scene =
        modia3d::demo::bouncing_sphere(d, 0.0, ContactPairMaterial::new(0.7, 0.5, 0.001));
    // Start at the resting height so the ball is in contact from t = 0.
    if let JointKind::FreeMotion { r, .. } = &mut scene.joints[0].kind {
        r.z = modia3d::demo::resting_steel_ball_height(d);
    }
    let model = scene.build().unwrap();
    let mut sim = model
        .simulation(&SimOptions::new(0.2).tolerance(1e-8).contact_results(true))
        .unwrap();
    sim.advance_to(0.2).unwrap();
    let names = sim.result().contact_pairs();
    assert_eq!(names.len(), 1, "{names:?}");
    let f_n = sim.output(&format!("{}.f_n", names[0])).unwrap()[0];
    let weight = modia3d::demo::sphere_mass(d, 8000.0) * 9.81;
    // At rest the contact force equals the weight; the ball settles from the analytic resting
    // height within the tolerance, so 1e-4 relative is a safe bound.
    assert!(
        (f_n - weight).abs() < 1e-4 * weight,
        "f_n {f_n} N vs weight {weight} N"
    );
}
