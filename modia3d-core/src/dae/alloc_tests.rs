//! The contact hot path allocates nothing: residual (continuous mode), root functions
//! (zero-crossing mode) and event mode of a scene with candidate pairs, once warmed up. The
//! crate's unit-test binary counts allocations per thread (`counting_alloc`, test builds
//! only), so tests running on other threads meanwhile are not seen.

use super::MultibodyDae;
use crate::counting_alloc::allocs;
use crate::solver::DaeSystem;
use crate::{FreeRotation, Joint, JointKind, Object3D, SceneDesc, SceneOptions, Shape, Solid};
use nalgebra::Vector3;

/// Eight steel balls (d = 0.06 m) on a steel table, each 1e-7 m into it (in contact from the
/// start), 0.02 m apart from each other: 8 ball–table contacts, 28 ball–ball candidate pairs
/// (all separated), exercising the broad phase, narrow phase and response of both kinds.
fn balls_on_a_table() -> SceneDesc {
    let d = 0.06;
    let mut s = SceneDesc::new();
    s.add(Object3D::new("world").scene(SceneOptions::default()))
        .add(
            Object3D::new("table")
                .parent("world")
                .translation([0.0, 0.0, -0.05])
                .solid(
                    Solid::new(Shape::Box {
                        lengths: Vector3::new(1.0, 1.0, 0.1),
                    })
                    .material("Steel")
                    .collision(true),
                ),
        );
    for i in 0..8 {
        let name = format!("ball{i}");
        let (x, y) = ((i % 4) as f64 * (d + 0.02), (i / 4) as f64 * (d + 0.02));
        s.add(
            Object3D::new(&name).solid(
                Solid::new(Shape::Sphere { diameter: d })
                    .material("Steel")
                    .collision(true),
            ),
        )
        .add_joint(Joint::new(
            &format!("{name}.free"),
            "world",
            &name,
            JointKind::FreeMotion {
                r: Vector3::new(x, y, 0.5 * d - 1e-7),
                rot: FreeRotation::Cardan([0.0; 3]),
                v: Vector3::zeros(),
                w: Vector3::zeros(),
            },
        ));
    }
    s
}

#[test]
fn residual_roots_and_events_do_not_allocate() {
    let model = balls_on_a_table().build().unwrap();
    assert!(model.contact.is_some(), "the scene has candidate pairs");
    let mut dae = MultibodyDae::new(model.plan.clone(), model.contact.clone());
    let y = model.plan.y0();
    let n = y.len();
    dae.handle_event(0.0, &y).unwrap();
    let yp = dae.consistent_derivative(0.0, &mut y.clone()).unwrap();
    let mut res = vec![0.0; n];
    let mut g = vec![0.0; 2];
    // Warm up.
    dae.residual(0.0, &y, &yp, &mut res).unwrap();
    dae.roots(0.0, &y, &yp, &mut g);
    let before = allocs();
    for k in 0..100 {
        let t = k as f64 * 1e-3;
        dae.residual(t, &y, &yp, &mut res).unwrap();
        dae.roots(t, &y, &yp, &mut g);
        dae.handle_event(t, &y).unwrap();
    }
    let after = allocs();
    assert_eq!(after - before, 0, "allocations on the contact hot path");
    assert!(
        g[0] < 0.0 && g[1] > 0.0,
        "balls rest on the table, none touch each other: {g:?}"
    );
    // The consistent derivative solves the residual to round-off of the forces (m g ≈ 8.7 N
    // per ball; 1e-6 is far above round-off and far below any missed term).
    assert!(res.iter().all(|r| r.abs() < 1e-6), "consistent start");
}
