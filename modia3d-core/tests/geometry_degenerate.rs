//! Degenerate configurations never panic and give finite, sensible answers: coinciding
//! centres, parallel faces, aligned axes, exact touching.
mod common;

use common::*;
use modia3d_core::geometry::{signed_distance, Axis, CollisionShape, NarrowPhaseOptions, Shape};
use nalgebra::{Isometry3, Translation3, UnitQuaternion, Vector3};

#[test]
fn coinciding_centres_for_every_pair() {
    let mut rng = Rng(3);
    for opts in [
        NarrowPhaseOptions::default(),
        NarrowPhaseOptions {
            force_mpr: true,
            ..Default::default()
        },
    ] {
        for &ka in &KINDS {
            for &kb in &KINDS {
                let a = CollisionShape::new(&random_shape(&mut rng, ka)).unwrap();
                let b = CollisionShape::new(&random_shape(&mut rng, kb)).unwrap();
                for pose_b in [
                    Isometry3::identity(),
                    Isometry3::rotation(Vector3::new(0.3, 0.2, 0.1)),
                ] {
                    // Put b's core centre exactly on a's core centre.
                    let shift = a.centre() - pose_b * b.centre();
                    let pb = Translation3::from(shift) * pose_b;
                    let r = signed_distance(&a, &Isometry3::identity(), &b, &pb, &opts).unwrap();
                    assert!(r.distance < 0.0, "{ka:?}-{kb:?}: {}", r.distance);
                    assert!((r.normal.norm() - 1.0).abs() < 1e-12, "{ka:?}-{kb:?}");
                    assert!(r
                        .point_a
                        .coords
                        .iter()
                        .chain(r.point_b.coords.iter())
                        .all(|x| x.is_finite()));
                }
            }
        }
    }
}

/// Parallel faces: two aligned boxes face to face, separated by 1 mm and penetrating by 1 mm:
/// exact (1e-12 m) distance with normal +z, by MPR.
#[test]
fn parallel_faces() {
    let a = CollisionShape::new(&Shape::Box {
        lengths: Vector3::new(1.0, 1.0, 1.0),
    })
    .unwrap();
    let b = CollisionShape::new(&Shape::Box {
        lengths: Vector3::new(0.5, 0.5, 0.5),
    })
    .unwrap();
    for gap in [1e-3, 0.0, -1e-3, -0.1] {
        let pb = Isometry3::translation(0.1, -0.05, 0.75 + gap);
        let r = signed_distance(
            &a,
            &Isometry3::identity(),
            &b,
            &pb,
            &NarrowPhaseOptions::default(),
        )
        .unwrap();
        assert!(
            (r.distance - gap).abs() < 1e-12,
            "gap {gap}: {}",
            r.distance
        );
        assert!(
            (r.normal - Vector3::z()).norm() < 1e-9,
            "gap {gap}: {:?}",
            r.normal
        );
    }
}

/// Parallel capsules and coaxial cylinders.
#[test]
fn parallel_axes() {
    let c = CollisionShape::new(&Shape::Capsule {
        axis: Axis::X,
        diameter: 0.2,
        length: 1.0,
    })
    .unwrap();
    for opts in [
        NarrowPhaseOptions::default(),
        NarrowPhaseOptions {
            force_mpr: true,
            ..Default::default()
        },
    ] {
        let r = signed_distance(
            &c,
            &Isometry3::identity(),
            &c,
            &Isometry3::translation(0.3, 0.25, 0.0),
            &opts,
        )
        .unwrap();
        assert!((r.distance - 0.05).abs() < 1e-9, "{}", r.distance);
        assert!((r.normal - Vector3::y()).norm() < 1e-6);
        // Exactly overlapping segments.
        let r = signed_distance(
            &c,
            &Isometry3::identity(),
            &c,
            &Isometry3::identity(),
            &opts,
        )
        .unwrap();
        assert!(r.distance.is_finite() && r.distance <= -0.2 + 1e-9);
    }
    let cyl = CollisionShape::new(&Shape::Cylinder {
        axis: Axis::Z,
        diameter: 0.4,
        length: 1.0,
    })
    .unwrap();
    let r = signed_distance(
        &cyl,
        &Isometry3::identity(),
        &cyl,
        &Isometry3::from_parts(
            Translation3::new(0.0, 0.0, 1.01),
            UnitQuaternion::identity(),
        ),
        &NarrowPhaseOptions::default(),
    )
    .unwrap();
    assert!((r.distance - 0.01).abs() < 1e-12 && (r.normal - Vector3::z()).norm() < 1e-9);
}

/// MPR alone (`exact_separation: false`) where the closest features lie on the centre ray:
/// shapes symmetric about the z axis of their frame, stacked along z (b turned about z only).
/// Then the MPR distance is exact: within 1e-6 · size of the exact answer (measured ~1e-12;
/// MPR's tolerance is 1e-11 · size), for separated and penetrating poses.
#[test]
fn mpr_alone_is_exact_on_the_centre_ray() {
    let kinds = |d: f64| {
        vec![
            Shape::Sphere { diameter: d },
            Shape::Box {
                lengths: Vector3::new(d, 0.7 * d, 0.9 * d),
            },
            Shape::Cylinder {
                axis: Axis::Z,
                diameter: d,
                length: 0.8 * d,
            },
            Shape::Capsule {
                axis: Axis::Z,
                diameter: 0.5 * d,
                length: 0.8 * d,
            },
            Shape::Ellipsoid {
                lengths: Vector3::new(d, 0.6 * d, 0.8 * d),
            },
        ]
    };
    let pure = NarrowPhaseOptions {
        force_mpr: true,
        exact_separation: false,
        ..Default::default()
    };
    let mut worst: f64 = 0.0;
    for sa in kinds(0.6) {
        for sb in kinds(0.4) {
            let a = CollisionShape::with_smoothing(&sa, 0.01).unwrap();
            let b = CollisionShape::with_smoothing(&sb, 0.01).unwrap();
            let size = a.bounding_radius() + b.bounding_radius();
            // Exact answer: the extents along z.
            let top_a = a.support(&Vector3::z()).z;
            let bottom_b = b.support(&-Vector3::z()).z;
            for (k, gap) in [0.05, 0.001, -0.001, -0.02].into_iter().enumerate() {
                let pb = Isometry3::from_parts(
                    Translation3::new(0.0, 0.0, top_a - bottom_b + gap),
                    UnitQuaternion::from_axis_angle(&Vector3::z_axis(), 0.4 * k as f64),
                );
                let r = signed_distance(&a, &Isometry3::identity(), &b, &pb, &pure).unwrap();
                worst = worst.max((r.distance - gap).abs() / size);
                assert!(
                    (r.normal - Vector3::z()).norm() < 1e-6,
                    "{sa:?} {sb:?} {:?}",
                    r.normal
                );
            }
        }
    }
    println!("MPR alone on the centre ray: worst |δ − exact| / size = {worst:.1e}");
    assert!(worst < 1e-6);
}
