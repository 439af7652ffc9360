//! The contact preload at the start (`SimOptions::preload_contacts`, docs/contact-model.md
//! §3.2 "Contacts at the start"): bodies placed resting on one another under the volume law
//! start pressed in by their static load, so a resting stack carries its weight from the
//! first instant instead of ringing about it; pairs with a sphere, bodies not at rest along
//! the normal and bodies placed deep in one another start as given.

use modia3d::demo::{box_stack, on_incline};
use modia3d::prelude::*;

const G: f64 = 9.81;
/// A 0.1 m DryWood cube \[kg\].
const M: f64 = 700.0 * 1e-3;

/// Largest relative error over every recorded point (every solver step and t = 0) of the
/// three interface forces of a stack of three wooden cubes against the weight above them.
fn stack_force_error(preload: bool) -> (f64, SimulationResult) {
    let res = box_stack([0.1; 3], 3, 0.0, SceneOptions::default())
        .build()
        .unwrap()
        .simulate(
            &SimOptions::new(0.02)
                .interval(1e-3)
                .contact_results(true)
                .output_steps(true)
                .preload_contacts(preload),
        )
        .unwrap();
    let mut worst = 0.0f64;
    for (k, p) in ["table|b0", "b0|b1", "b1|b2"].iter().enumerate() {
        let w = (3 - k) as f64 * M * G;
        let f = res.signal(&format!("{p}.f_n")).unwrap();
        for v in f.component(0) {
            worst = worst.max(((v - w) / w).abs());
        }
    }
    (worst, res)
}

/// Rigid statics: each interface of a resting stack carries the weight above it at every
/// instant, the first included. Preloaded, every recorded force (every solver step of the
/// first 20 ms, and t = 0) is within 1e-6 of it: the preload leaves 1e-8 of the acceleration
/// it starts from, and the integration at rtol 1e-6 keeps the balance to about its tolerance.
/// From zero depth the same stack starts with no force at all and rings about its weight:
/// the check fails there (relative error 1 at t = 0), which is what the preload removes.
#[test]
fn a_preloaded_stack_carries_its_weight_from_the_first_instant() {
    let (preloaded, res) = stack_force_error(true);
    let (given, res0) = stack_force_error(false);
    println!(
        "worst interface-force error: preloaded {preloaded:.2e} ({} steps), from zero depth {given:.2e} ({} steps)",
        res.stats.solver.steps, res0.stats.solver.steps
    );
    assert!(preloaded < 1e-6, "preloaded: {preloaded:.3e}");
    assert!(given > 0.5, "from zero depth: {given:.3e}");
    assert!(res.events.is_empty(), "events: {:?}", res.events);
}

/// The preload moves each cube down by its static depth and nothing else: the volume law's
/// face stiffness is `κ·A` (κ the pair's stiffness per volume, A = 0.01 m² the face), so the
/// bottom cube sinks `3mg/(κA)` into the table and each interface above adds the depth of the
/// weight it carries (the cubes' own interfaces have the same κ: wood on wood, 0.05 m layers).
/// 1e-3: the overlap of a face is `A·δ` exactly, the Newton residual leaves 1e-8, and the
/// rest is the rounding of differences of coordinates of ~0.1 m at depths of ~1e-8 m
/// (1e-17/1e-8 = 1e-9). Rotations and velocities keep their given values exactly, the
/// horizontal positions to 1e-15 m (the difference Jacobian's columns across the normal are
/// rounding noise, which the smallest step still follows: ~1e-22 m here).
#[test]
fn the_preload_moves_each_cube_by_its_static_depth_only() {
    let model = box_stack([0.1; 3], 3, 0.0, SceneOptions::default())
        .build()
        .unwrap();
    let kappa = model.contact_pairs()[0]
        .volume_stiffness
        .expect("volume law");
    let depth = |w: f64| w / (kappa * 0.01);
    let res = model
        .simulate(&SimOptions::new(1e-3).interval(1e-3))
        .unwrap();
    let mut expected_sink = 0.0;
    for i in 0..3 {
        expected_sink += depth((3 - i) as f64 * M * G);
        let r = res.signal(&format!("b{i}.r_abs")).unwrap();
        let r0 = r.first().unwrap();
        let given = [0.0, 0.0, 0.1 * (i as f64 + 0.5)];
        let sink = given[2] - r0[2];
        println!("b{i}: sank {sink:.4e} m, static depth sum {expected_sink:.4e} m");
        assert!(
            ((sink - expected_sink) / expected_sink).abs() < 1e-3,
            "b{i}: {sink:.6e} vs {expected_sink:.6e}"
        );
        assert!(
            r0[0].abs().max(r0[1].abs()) < 1e-15,
            "b{i} moved sideways: {r0:?}"
        );
        let rot = res.signal(&format!("b{i}.R_abs")).unwrap();
        let rot0 = rot.first().unwrap();
        let identity = [1.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0];
        assert_eq!(rot0, identity.as_slice(), "b{i} turned");
        let v = res.signal(&format!("b{i}.v_abs")).unwrap();
        assert_eq!(v.first().unwrap(), [0.0; 3].as_slice(), "b{i}'s velocity");
    }
}

/// What the preload leaves as given, bit for bit against `preload_contacts(false)`: a ball
/// resting on a table (a pair with a sphere keeps the paper's law and its start), a cube
/// dropped onto the table at 0.5 m/s from touching (an impact, not a body at rest along the
/// normal), and a cube placed 2 cm deep in the table (its static depth lies farther than
/// the preload's reach of 1 mm: such a start is a user's to give, and the run starts as
/// given).
#[test]
fn spheres_impacts_and_deep_starts_start_as_given() {
    let ball = on_plank(Shape::Sphere { diameter: 0.1 }, 0.05);
    let cube = |height: f64| box_drop(height, if height < 0.05 { 0.0 } else { -0.5 });
    for (name, scene) in [
        ("ball at rest", ball),
        ("cube dropped at 0.5 m/s", cube(0.05)),
        ("cube 2 cm deep", cube(0.03)),
    ] {
        let model = scene.build().unwrap();
        let run = |on: bool| {
            model
                .simulate(&SimOptions::new(0.02).interval(1e-3).preload_contacts(on))
                .unwrap()
        };
        let (a, b) = (run(true), run(false));
        assert_eq!(a.stats.solver.steps, b.stats.solver.steps, "{name}");
        for s in ["body.r_abs", "body.v_abs"] {
            assert_eq!(a.signal(s).unwrap(), b.signal(s).unwrap(), "{name}: {s}");
        }
    }
}

/// A DryWood `shape` (`body`) at rest above a flat DryWood plank (`plank`, top face at
/// z = 0) with its centre at `height` \[m\].
fn on_plank(shape: Shape, height: f64) -> SceneDesc {
    on_incline(
        shape,
        height,
        0.0,
        0.0,
        0.0,
        [0.0; 3],
        "DryWood",
        ContactPairMaterial::new(0.6, 0.3, 0.001),
        SceneOptions::default(),
    )
}

/// A 0.1 m DryWood cube on [`on_plank`] with its centre at `height` \[m\], moving vertically
/// at `vz` [m/s].
fn box_drop(height: f64, vz: f64) -> SceneDesc {
    let mut s = on_plank(
        Shape::Box {
            lengths: Vector3::new(0.1, 0.1, 0.1),
        },
        height,
    );
    for j in &mut s.joints {
        if let JointKind::FreeMotion { v, .. } = &mut j.kind {
            v.z = vz;
        }
    }
    s
}
