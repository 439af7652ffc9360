//! Blocks in `model!` (docs/drive-trains.md, "In `model!`"): Modia3D's ServoWithRamp
//! (as `tests/drive_trains.rs` builds it with the builder API)
//! written with `model!` expands to the same builder calls, so its final states equal the
//! builder scene's bit for bit; the spec's compact form (one PI whose input is an expression
//! over signals) and a servo used twice as a sub-assembly with different parameters (and
//! Modia3D's `Servo` five times in one arm); blocks
//! reading accelerations (`der(slide.v)`) equal the builder scene reading `"der(slide.v)"`.

use modia3d::core::blocks::{Drive, Feedback, Gain, Ramp, Sampled, PI};
use modia3d::prelude::*;

type Res<T> = Result<T, Box<dyn std::error::Error>>;

/// The motor inertia of Modia3D's servo [kg·m²] (rotor and gear), as tests/drive_trains.rs.
const J_MOTOR: f64 = 0.0000135 + 0.000000409;

/// The builder scene of tests/drive_trains.rs, with the block names of the `model!` below.
fn builder_scene() -> SceneDesc {
    let mut scene = load_with_ramp();
    scene
        .add_component(ComponentDecl::new("gain_outer", Gain { k: 156.0 }).input("u", "ramp.y"))
        .add_component(
            ComponentDecl::new("angle_feedback", Feedback)
                .input("u1", "gain_outer.y")
                .input("u2", "drive.motor_phi"),
        )
        .add_component(
            ComponentDecl::new("gain_inner", Gain { k: 50.0 }).input("u", "angle_feedback.y"),
        )
        .add_component(
            ComponentDecl::new("speed_feedback", Feedback)
                .input("u1", "gain_inner.y")
                .input("u2", "drive.motor_w"),
        )
        .add_component(ComponentDecl::new("pi", PI::new(0.1, 1.0)).input("u", "speed_feedback.y"))
        .add_component(
            ComponentDecl::new("drive", Drive::rigid("rev", 156.0, J_MOTOR)).input("tau", "pi.y"),
        );
    scene
}

model! {
    /// Modia3D's ServoWithRamp: a load of inertia `j` on a revolute joint, driven by a motor
    /// through an ideal gear, a P–PI cascade following a ramp.
    pub ServoWithRamp(j: f64 = 0.32, ratio: f64 = 156.0, k1: f64 = 156.0, k2: f64 = 50.0) {
        world = Object3D(feature = Scene()),
        load = Object3D(feature = Solid(
            shape = Sphere(diameter = 0.1),
            mass_properties = MassProperties(
                mass = 1.0,
                inertia = [[j, 0.0, 0.0], [0.0, j, 0.0], [0.0, 0.0, j]],
            ),
        )),
        rev = Revolute(obj1 = world, obj2 = load, axis = 3),
        ramp = Ramp(height = 2.95, duration = 1.18),
        gain_outer = Gain(k = k1, u = ramp.y),
        angle_feedback = Feedback(u1 = gain_outer.y, u2 = drive.motor_phi),
        gain_inner = Gain(k = k2, u = angle_feedback.y),
        speed_feedback = Feedback(u1 = gain_inner.y, u2 = drive.motor_w),
        pi = PI(k = 0.1, T = 1.0, u = speed_feedback.y),
        drive = Drive(joint = rev, ratio = ratio, J_motor = 0.0000135 + 0.000000409, tau = pi.y),
    }
}

model! {
    /// The spec's compact form: the cascade as one expression over signals.
    pub CompactServo(j: f64 = 0.32, ratio: f64 = 156.0, k1: f64 = 156.0, k2: f64 = 50.0,
                     t2: f64 = 1.0) {
        world = Object3D(feature = Scene()),
        load = Object3D(feature = Solid(
            shape = Sphere(diameter = 0.1),
            mass_properties = MassProperties(
                mass = 1.0,
                inertia = [[j, 0.0, 0.0], [0.0, j, 0.0], [0.0, 0.0, j]],
            ),
        )),
        rev = Revolute(obj1 = world, obj2 = load, axis = 3),
        ramp = Ramp(height = 2.95, duration = 1.18),
        pi = PI(k = 0.1, T = t2, u = k2 * (k1 * ramp.y - drive.motor_phi) - drive.motor_w),
        drive = Drive(joint = rev, ratio = ratio, J_motor = 1.3909e-5, tau = pi.y),
    }
}

model! {
    /// One servo axis: its own base (attached to the `parent` handed to it), load, joint,
    /// reference, controller and drive.
    pub assembly ServoAxis(height: f64 = 2.95, duration: f64 = 1.18, j: f64 = 0.32) {
        base = Object3D(),
        load = Object3D(feature = Solid(
            shape = Sphere(diameter = 0.1),
            mass_properties = MassProperties(
                mass = 1.0,
                inertia = [[j, 0.0, 0.0], [0.0, j, 0.0], [0.0, 0.0, j]],
            ),
        )),
        rev = Revolute(obj1 = base, obj2 = load, axis = 3),
        ramp = Ramp(height = height, duration = duration),
        pi = PI(k = 0.1, T = 1.0, u = 50.0 * (156.0 * ramp.y - drive.motor_phi) - drive.motor_w),
        drive = Drive(joint = rev, ratio = 156.0, J_motor = 1.3909e-5, tau = pi.y),
    }
}

model! {
    /// Two servo axes with different references; a block reads signals inside both.
    pub TwoServos(second_height: f64 = 1.0) {
        world = Object3D(feature = Scene()),
        axis1 = ServoAxis(parent = world),
        axis2 = ServoAxis(parent = world, height = second_height),
        difference = Feedback(u1 = axis1.rev.phi, u2 = axis2.drive.motor_phi / 156.0),
    }
}

/// The final values of `names` after Modia3D's 4 s at tolerance 1e-6.
fn final_values(scene: SceneDesc, names: &[&str]) -> Res<Vec<f64>> {
    final_values_at(scene, names, 4.0)
}

/// The final values of `names` after `stop` s at tolerance 1e-6.
fn final_values_at(scene: SceneDesc, names: &[&str], stop: f64) -> Res<Vec<f64>> {
    let r = scene
        .build()?
        .simulate(&SimOptions::new(stop).tolerance(1e-6))?;
    names
        .iter()
        .map(|s| Ok(r.signal(s)?.last().ok_or("no output point")?[0]))
        .collect()
}

const STATES: [&str; 3] = ["pi.x", "rev.phi", "rev.w"];

#[test]
fn servo_with_ramp_in_model_equals_the_builder_scene_bit_for_bit() -> Res<()> {
    let built = final_values(builder_scene(), &STATES)?;
    let macro_ = final_values(ServoWithRamp::default().scene(), &STATES)?;
    let bits = |v: &[f64]| v.iter().map(|x| x.to_bits()).collect::<Vec<_>>();
    assert_eq!(bits(&macro_), bits(&built), "{macro_:?} vs {built:?}");
    // The servo follows the ramp to 2.95 rad (Modia3D's reference; 4 s, the ramp ends at
    // 1.18 s): within the controller's steady error, which the PI drives to zero.
    assert!((built[1] - 2.95).abs() < 1e-2, "{built:?}");
    Ok(())
}

#[test]
fn compact_servo_follows_the_same_trajectory() -> Res<()> {
    // One PI reading an expression in place of four algebraic blocks: the same equations (the
    // cascade's arithmetic in the same order), so the same trajectory within the run's
    // tolerance (1e-6), not necessarily the same bits (other blocks, other evaluation).
    let full = final_values(ServoWithRamp::default().scene(), &STATES)?;
    let compact = final_values(CompactServo::default().scene(), &STATES)?;
    for (a, b) in full.iter().zip(&compact) {
        assert!(
            (a - b).abs() <= 1e-4 * (1.0 + a.abs()),
            "{full:?} vs {compact:?}"
        );
    }
    Ok(())
}

#[test]
fn a_servo_sub_assembly_used_twice_with_different_parameters() -> Res<()> {
    let scene = TwoServos::default().scene();
    let names: Vec<&str> = scene.components.iter().map(|c| c.name.as_str()).collect();
    assert_eq!(
        names,
        [
            "axis1.ramp",
            "axis1.pi",
            "axis1.drive",
            "axis2.ramp",
            "axis2.pi",
            "axis2.drive",
            "difference"
        ]
    );
    let v = final_values(
        scene,
        &[
            "axis1.rev.phi",
            "axis2.rev.phi",
            "axis2.drive.motor_phi",
            "difference.y",
        ],
    )?;
    // Each axis follows its own ramp: 2.95 rad and 1.0 rad (as the single servo, within
    // its steady error).
    assert!((v[0] - 2.95).abs() < 1e-2, "{v:?}");
    assert!((v[1] - 1.0).abs() < 1e-2, "{v:?}");
    // The motor angle is the gear ratio times the joint's; the difference block reads both.
    assert!((v[2] - 156.0 * v[1]).abs() <= 1e-9 * v[2].abs(), "{v:?}");
    assert!((v[3] - (v[0] - v[1])).abs() <= 1e-9, "{v:?}");
    Ok(())
}

model! {
    /// The servo's load driven through an elastic gear by a DC motor, the PI's output its
    /// voltage.
    pub DcServo(k1: f64 = 156.0, k2: f64 = 50.0) {
        world = Object3D(feature = Scene()),
        load = Object3D(feature = Solid(
            shape = Sphere(diameter = 0.1),
            mass_properties = MassProperties(
                mass = 1.0,
                inertia = [[0.32, 0.0, 0.0], [0.0, 0.32, 0.0], [0.0, 0.0, 0.32]],
            ),
        )),
        rev = Revolute(obj1 = world, obj2 = load, axis = 3),
        ramp = Ramp(height = 2.95, duration = 1.18),
        pi = PI(k = 0.1, T = 1.0, u = k2 * (k1 * ramp.y - drive.motor_phi) - drive.motor_w),
        drive = Drive(joint = rev, ratio = 156.0, J_motor = 1.3909e-5,
                      gear = Elastic(c = 1e4, d = 10.0), motor = Dc(R = 0.5, L = 1e-3, k = 0.3),
                      v = pi.y),
    }
}

/// Modia3D's servo load (1 kg, 0.32 kg·m² about z) on revolute `rev` and its `ramp`
/// (2.95 rad in 1.18 s), the start of the builder scenes below.
fn load_with_ramp() -> SceneDesc {
    let mut scene = SceneDesc::new();
    scene
        .add(Object3D::new("world").scene(SceneOptions::default()))
        .add(Object3D::new("load").solid(
            Solid::new(Shape::Sphere { diameter: 0.1 }).mass_properties(
                1.0,
                Vector3::zeros(),
                Matrix3::from_diagonal_element(0.32),
            ),
        ))
        .add_joint(Joint::new("rev", "world", "load", JointKind::revolute(3)));
    scene.add_component(ComponentDecl::new(
        "ramp",
        Ramp {
            height: 2.95,
            duration: 1.18,
            ..Default::default()
        },
    ));
    scene
}

#[test]
fn elastic_gear_and_dc_motor_in_model_equal_the_builder_scene_bit_for_bit() -> Res<()> {
    let mut scene = load_with_ramp();
    scene
        .add_component(ComponentDecl::new("pi", PI::new(0.1, 1.0)).input(
            "u",
            Src::expr(&["ramp.y", "drive.motor_phi", "drive.motor_w"], |_, v| {
                50.0 * (156.0 * v[0] - v[1]) - v[2]
            }),
        ))
        .add_component(
            ComponentDecl::new(
                "drive",
                Drive::rigid("rev", 156.0, 1.3909e-5)
                    .elastic(1e4, 10.0)
                    .dc_motor(0.5, 1e-3, 0.3),
            )
            .input("v", "pi.y"),
        );
    let names = ["pi.x", "rev.phi", "rev.w", "drive.phi_gear", "drive.i"];
    let built = final_values(scene, &names)?;
    let macro_ = final_values(DcServo::default().scene(), &names)?;
    let bits = |v: &[f64]| v.iter().map(|x| x.to_bits()).collect::<Vec<_>>();
    assert_eq!(bits(&macro_), bits(&built), "{macro_:?} vs {built:?}");
    assert!(built.iter().all(|v| v.is_finite()), "{built:?}");
    Ok(())
}

model! {
    /// The compact servo with a digital PI: sampled at 10 kHz (zero-order hold, forward Euler
    /// from tick to tick). The cascade's speed loop has a pole near 3700 rad/s (156 · 0.1 ·
    /// 156 N·m·s/rad on 0.66 kg·m²): at 1 kHz (h·a ≈ 3.7 > 2) the sampled loop diverges.
    pub DigitalServo(k1: f64 = 156.0, k2: f64 = 50.0) {
        world = Object3D(feature = Scene()),
        load = Object3D(feature = Solid(
            shape = Sphere(diameter = 0.1),
            mass_properties = MassProperties(
                mass = 1.0,
                inertia = [[0.32, 0.0, 0.0], [0.0, 0.32, 0.0], [0.0, 0.0, 0.32]],
            ),
        )),
        rev = Revolute(obj1 = world, obj2 = load, axis = 3),
        ramp = Ramp(height = 2.95, duration = 1.18),
        pi = Sampled(period = 1e-4, inner = PI(k = 0.1, T = 1.0),
                     u = k2 * (k1 * ramp.y - drive.motor_phi) - drive.motor_w),
        drive = Drive(joint = rev, ratio = 156.0, J_motor = 1.3909e-5, tau = pi.y),
    }
}

#[test]
fn sampled_pi_in_model_equals_the_builder_scene_bit_for_bit() -> Res<()> {
    let mut scene = load_with_ramp();
    scene
        .add_component(
            ComponentDecl::new("pi", Sampled::new(1e-4, PI::new(0.1, 1.0))).input(
                "u",
                Src::expr(&["ramp.y", "drive.motor_phi", "drive.motor_w"], |_, v| {
                    50.0 * (156.0 * v[0] - v[1]) - v[2]
                }),
            ),
        )
        .add_component(
            ComponentDecl::new("drive", Drive::rigid("rev", 156.0, 1.3909e-5)).input("tau", "pi.y"),
        );
    // 2 s (20,000 ticks, each a time event): the ramp has ended at 1.18 s.
    let names = ["pi.x", "pi.y", "rev.phi", "rev.w"];
    let built = final_values_at(scene, &names, 2.0)?;
    let macro_ = final_values_at(DigitalServo::default().scene(), &names, 2.0)?;
    let bits = |v: &[f64]| v.iter().map(|x| x.to_bits()).collect::<Vec<_>>();
    assert_eq!(bits(&macro_), bits(&built), "{macro_:?} vs {built:?}");
    // The digital loop follows the ramp as the continuous one does.
    let continuous = final_values_at(CompactServo::default().scene(), &["rev.phi"], 2.0)?;
    assert!(
        (built[2] - continuous[0]).abs() < 1e-2,
        "{built:?} vs {continuous:?}"
    );
    Ok(())
}

model! {
    /// Modia3D's `PPI` controller: a P loop on the motor angle around a PI loop on its speed;
    /// the reference and the measured angle and speed are signals of the outer model.
    pub assembly Ppi(reference: SignalRef = SignalRef::time(),
                     phi: SignalRef = SignalRef::time(),
                     w: SignalRef = SignalRef::time()) {
        gainOuter = Gain(k = 156.0, u = reference),
        angleFeedback = Feedback(u1 = gainOuter.y, u2 = phi),
        gainInner = Gain(k = 50.0, u = angleFeedback.y),
        speedFeedback = Feedback(u1 = gainInner.y, u2 = w),
        PI = PI(k = 0.1, T = 1.0, u = speedFeedback.y),
    }
}

model! {
    /// Modia3D's `Servo`: the PPI controller and a motor with an ideal gear on a joint of the
    /// outer model, following one of its signals.
    pub assembly Servo(joint: JointRef = JointRef::default(),
                       reference: SignalRef = SignalRef::time()) {
        ppi = Ppi(reference = reference, phi = drive.motor_phi, w = drive.motor_w),
        drive = Drive(joint = joint, ratio = 156.0, J_motor = 0.0000135 + 0.000000409,
                      tau = ppi.PI.y),
    }
}

model! {
    /// ServoWithRamp as Modia3D writes it: the servo a sub-model on the outer joint.
    pub NestedServoWithRamp(j: f64 = 0.32) {
        world = Object3D(feature = Scene()),
        load = Object3D(feature = Solid(
            shape = Sphere(diameter = 0.1),
            mass_properties = MassProperties(
                mass = 1.0,
                inertia = [[j, 0.0, 0.0], [0.0, j, 0.0], [0.0, 0.0, j]],
            ),
        )),
        rev = Revolute(obj1 = world, obj2 = load, axis = 3),
        ramp = Ramp(height = 2.95, duration = 1.18),
        servo = Servo(joint = rev, reference = ramp.y),
    }
}

/// tests/drive_trains.rs's `servo`: Modia3D's controller and drive on joint `joint`, under
/// `servo.`, built with the builder API.
fn builder_servo(scene: &mut SceneDesc, joint: &str, reference: &str) {
    scene
        .add_component(
            ComponentDecl::new("servo.ppi.gainOuter", Gain { k: 156.0 }).input("u", reference),
        )
        .add_component(
            ComponentDecl::new("servo.ppi.angleFeedback", Feedback)
                .input("u1", "servo.ppi.gainOuter.y")
                .input("u2", "servo.drive.motor_phi"),
        )
        .add_component(
            ComponentDecl::new("servo.ppi.gainInner", Gain { k: 50.0 })
                .input("u", "servo.ppi.angleFeedback.y"),
        )
        .add_component(
            ComponentDecl::new("servo.ppi.speedFeedback", Feedback)
                .input("u1", "servo.ppi.gainInner.y")
                .input("u2", "servo.drive.motor_w"),
        )
        .add_component(
            ComponentDecl::new("servo.ppi.PI", PI::new(0.1, 1.0))
                .input("u", "servo.ppi.speedFeedback.y"),
        )
        .add_component(
            ComponentDecl::new("servo.drive", Drive::rigid(joint, 156.0, J_MOTOR))
                .input("tau", "servo.ppi.PI.y"),
        );
}

#[test]
fn servo_sub_models_on_an_outer_joint_equal_drive_trains_scene_bit_for_bit() -> Res<()> {
    // tests/drive_trains.rs's scene, names and all.
    let mut scene = SceneDesc::new();
    scene
        .add(Object3D::new("world").scene(SceneOptions::default()))
        .add(Object3D::new("load").solid(
            Solid::new(Shape::Sphere { diameter: 0.1 }).mass_properties(
                1.0,
                Vector3::zeros(),
                Matrix3::from_diagonal_element(0.32),
            ),
        ))
        .add_joint(Joint::new("rev", "world", "load", JointKind::revolute(3)));
    scene.add_component(ComponentDecl::new(
        "ramp",
        Ramp {
            height: 2.95,
            duration: 1.18,
            ..Default::default()
        },
    ));
    builder_servo(&mut scene, "rev", "ramp.y");
    let nested = NestedServoWithRamp::default().scene();
    let names =
        |s: &SceneDesc| -> Vec<String> { s.components.iter().map(|c| c.name.clone()).collect() };
    assert_eq!(names(&nested), names(&scene));
    let states = ["servo.ppi.PI.x", "rev.phi", "rev.w"];
    let built = final_values(scene, &states)?;
    let macro_ = final_values(nested, &states)?;
    let bits = |v: &[f64]| v.iter().map(|x| x.to_bits()).collect::<Vec<_>>();
    assert_eq!(bits(&macro_), bits(&built), "{macro_:?} vs {built:?}");
    Ok(())
}

model! {
    /// A mass falling on a vertical prismatic joint, reading its own acceleration.
    pub assembly Faller(m: f64 = 1.0) {
        base = Object3D(),
        mass = Object3D(feature = Solid(
            shape = Sphere(diameter = 0.1),
            mass_properties = MassProperties(
                mass = m,
                inertia = [[0.01, 0.0, 0.0], [0.0, 0.01, 0.0], [0.0, 0.0, 0.01]],
            ),
        )),
        slide = Prismatic(obj1 = base, obj2 = mass, axis = 3),
        acc = Gain(k = 1.0, u = der(slide.v)),
    }
}

model! {
    /// Blocks reading accelerations: alone, in an expression, inside a sub-assembly and into
    /// one.
    pub FallingMasses(m_extra: f64 = 0.5) {
        world = Object3D(feature = Scene()),
        mass = Object3D(feature = Solid(
            shape = Sphere(diameter = 0.1),
            mass_properties = MassProperties(
                mass = 2.0,
                inertia = [[0.01, 0.0, 0.0], [0.0, 0.01, 0.0], [0.0, 0.0, 0.01]],
            ),
        )),
        slide = Prismatic(obj1 = world, obj2 = mass, axis = 3),
        ramp = Ramp(height = 1.0, duration = 1.0),
        acc = Gain(k = 1.0, u = der(slide.v)),
        force = Gain(k = 1.0, u = m_extra * der(slide.v) + ramp.y),
        inner = Faller(parent = world),
        inner_acc = Gain(k = 2.0, u = der(inner.slide.v)),
    }
}

/// `FallingMasses` with the builder API.
fn builder_falling_masses() -> SceneDesc {
    let m_extra = 0.5;
    let solid = |m: f64| {
        Solid::new(Shape::Sphere { diameter: 0.1 }).mass_properties(
            m,
            Vector3::zeros(),
            Matrix3::from_diagonal_element(0.01),
        )
    };
    let mut scene = SceneDesc::new();
    scene
        .add(Object3D::new("world").scene(SceneOptions::default()))
        .add(Object3D::new("mass").solid(solid(2.0)))
        .add_joint(Joint::new(
            "slide",
            "world",
            "mass",
            JointKind::prismatic(3),
        ));
    scene
        .add_component(ComponentDecl::new(
            "ramp",
            Ramp {
                height: 1.0,
                duration: 1.0,
                ..Default::default()
            },
        ))
        .add_component(ComponentDecl::new("acc", Gain { k: 1.0 }).input("u", "der(slide.v)"))
        .add_component(ComponentDecl::new("force", Gain { k: 1.0 }).input(
            "u",
            Src::expr(&["der(slide.v)", "ramp.y"], move |_, v| {
                m_extra * v[0] + v[1]
            }),
        ));
    scene
        .add(Object3D::new("inner.base").parent("world"))
        .add(Object3D::new("inner.mass").solid(solid(1.0)))
        .add_joint(Joint::new(
            "inner.slide",
            "inner.base",
            "inner.mass",
            JointKind::prismatic(3),
        ));
    scene
        .add_component(
            ComponentDecl::new("inner.acc", Gain { k: 1.0 }).input("u", "der(inner.slide.v)"),
        )
        .add_component(
            ComponentDecl::new("inner_acc", Gain { k: 2.0 }).input("u", "der(inner.slide.v)"),
        );
    scene
}

#[test]
fn accelerations_read_in_model_equal_the_builder_scene_bit_for_bit() -> Res<()> {
    let names = ["acc.y", "force.y", "inner.acc.y", "inner_acc.y", "slide.s"];
    let built = final_values_at(builder_falling_masses(), &names, 1.5)?;
    let macro_ = final_values_at(FallingMasses::default().scene(), &names, 1.5)?;
    let bits = |v: &[f64]| v.iter().map(|x| x.to_bits()).collect::<Vec<_>>();
    assert_eq!(bits(&macro_), bits(&built), "{macro_:?} vs {built:?}");
    // Free fall: −g on both joints, whatever the mass.
    let g = 9.81;
    assert!((built[0] + g).abs() < 1e-9, "{built:?}");
    assert!((built[1] - (0.5 * -g + 1.0)).abs() < 1e-9, "{built:?}");
    assert!((built[2] + g).abs() < 1e-9, "{built:?}");
    assert!((built[3] + 2.0 * g).abs() < 1e-9, "{built:?}");
    Ok(())
}

model! {
    /// One link of [`FiveServoArm`]: a ball of 1 kg with its far end 0.3 m along x.
    pub assembly ArmLink() {
        body = Object3D(feature = Solid(
            shape = Sphere(diameter = 0.1),
            mass_properties = MassProperties(
                mass = 1.0,
                inertia = [[0.01, 0.0, 0.0], [0.0, 0.01, 0.0], [0.0, 0.0, 0.01]],
            ),
        )),
        tip = Object3D(parent = body, translation = [0.3, 0.0, 0.0]),
    }
}

model! {
    /// The arm: Modia3D's `Servo` sub-model used five times in one arm, a chain of
    /// five links hinged about z (gravity along −z loads none of the joints), each servo on
    /// its own joint following its own ramp.
    pub FiveServoArm(h1: f64 = 0.5, h2: f64 = -0.4, h3: f64 = 0.3, h4: f64 = -0.2,
                     h5: f64 = 0.1) {
        world = Object3D(feature = Scene()),
        link1 = ArmLink(),
        link2 = ArmLink(),
        link3 = ArmLink(),
        link4 = ArmLink(),
        link5 = ArmLink(),
        rev1 = Revolute(obj1 = world, obj2 = link1.body, axis = 3),
        rev2 = Revolute(obj1 = link1.tip, obj2 = link2.body, axis = 3),
        rev3 = Revolute(obj1 = link2.tip, obj2 = link3.body, axis = 3),
        rev4 = Revolute(obj1 = link3.tip, obj2 = link4.body, axis = 3),
        rev5 = Revolute(obj1 = link4.tip, obj2 = link5.body, axis = 3),
        ramp1 = Ramp(height = h1, duration = 1.0),
        ramp2 = Ramp(height = h2, duration = 1.0),
        ramp3 = Ramp(height = h3, duration = 1.0),
        ramp4 = Ramp(height = h4, duration = 1.0),
        ramp5 = Ramp(height = h5, duration = 1.0),
        servo1 = Servo(joint = rev1, reference = ramp1.y),
        servo2 = Servo(joint = rev2, reference = ramp2.y),
        servo3 = Servo(joint = rev3, reference = ramp3.y),
        servo4 = Servo(joint = rev4, reference = ramp4.y),
        servo5 = Servo(joint = rev5, reference = ramp5.y),
    }
}

#[test]
fn a_servo_sub_model_used_five_times_in_one_arm() -> Res<()> {
    // Reference: each joint at its ramp's end value. The arm is unloaded at rest (gravity
    // along the joints' axes), so once the ramps end (1 s) the PIs integrate the errors away:
    // measured 1.2e-7…2.8e-7 rad at 4 s; 1e-4 leaves room for the run's rtol 1e-6 and is far
    // below a wiring mistake (five different heights: a servo on another's joint or ramp
    // misses by ≥ 0.1 rad).
    let arm = FiveServoArm::default();
    let heights = [arm.h1, arm.h2, arm.h3, arm.h4, arm.h5];
    let scene = arm.scene();
    let servos = scene
        .components
        .iter()
        .filter(|c| c.name.ends_with(".drive"))
        .count();
    assert_eq!(servos, 5, "five drives, one per Servo");
    let names: Vec<String> = (1..=5).map(|k| format!("rev{k}.phi")).collect();
    let names: Vec<&str> = names.iter().map(String::as_str).collect();
    let v = final_values(scene, &names)?;
    eprintln!("five servos at 4 s: {v:?} against {heights:?}");
    for (k, (phi, h)) in v.iter().zip(heights).enumerate() {
        assert!(
            (phi - h).abs() < 1e-4,
            "joint {}: {phi} rad, ramp to {h}",
            k + 1
        );
    }
    Ok(())
}
