//! Support maps, smoothing and AABBs against parry's shapes and against the given dimensions.
mod common;

use common::*;
use modia3d_core::geometry::{aabb_distance, world_aabb, Aabb, CollisionShape, Shape};
use nalgebra::{Point3, Vector3};
use parry3d_f64::shape::SupportMap;

/// Support *function* values `d·s(d)` of our shape (core + margin) and of the parry equivalent
/// agree. Tolerance 1e-12 m: both are closed forms on dimensions ≤ 1 m, only rounding differs.
#[test]
fn support_function_matches_parry_equivalents() {
    let mut rng = Rng(1);
    for kind in KINDS {
        for _ in 0..50 {
            let shape = random_shape(&mut rng, kind);
            let cs = CollisionShape::with_smoothing(&shape, 0.05).unwrap();
            let Some((ps, local)) = parry_equivalent(&cs) else {
                continue;
            };
            let sm = ps.as_support_map().unwrap();
            for _ in 0..50 {
                let d = rng.unit_vector();
                let ours = d.dot(&cs.support(&d).coords);
                let theirs = d.dot(&sm.support_point(&local, &d).coords);
                assert!(
                    (ours - theirs).abs() < 1e-12,
                    "{kind:?}: {ours} vs {theirs}"
                );
            }
        }
    }
}

/// Ellipsoid support: the support point lies on the surface and its normal is `d`.
#[test]
fn ellipsoid_support_is_on_surface_with_normal_d() {
    let mut rng = Rng(2);
    let l = Vector3::new(0.4, 1.0, 0.7);
    let cs = CollisionShape::new(&Shape::Ellipsoid { lengths: l }).unwrap();
    let a = l / 2.0;
    for _ in 0..1000 {
        let d = rng.unit_vector();
        let p = cs.support(&d);
        let q = p.coords.component_div(&a);
        assert!((q.norm_squared() - 1.0).abs() < 1e-13);
        // Gradient of x²/a² is parallel to d.
        let g = p.coords.component_div(&a.component_mul(&a)).normalize();
        assert!((g - d).norm() < 1e-12);
    }
}

/// Smoothing keeps the outer dimensions: support values along the frame axes equal the given
/// half lengths (boxes, cylinders, cone base), and a shrunk hull swept by r reaches every
/// original face plane. Tolerance 1e-12 m (rounding of closed forms / a 3×3 solve).
#[test]
fn smoothing_keeps_outer_dimensions() {
    let l = Vector3::new(0.3, 0.5, 0.9);
    let b = CollisionShape::with_smoothing(&Shape::Box { lengths: l }, 0.02).unwrap();
    assert_eq!(b.smoothing_radius(), 0.02);
    for i in 0..3 {
        let mut e = Vector3::zeros();
        e[i] = 1.0;
        assert!((b.support(&e)[i] - 0.5 * l[i]).abs() < 1e-15);
    }
    // Clamped to 10 % of the smallest dimension.
    let b = CollisionShape::with_smoothing(&Shape::Box { lengths: l }, 1.0).unwrap();
    assert!((b.smoothing_radius() - 0.03).abs() < 1e-15);

    let c = CollisionShape::with_smoothing(
        &Shape::Cylinder {
            axis: modia3d_core::geometry::Axis::X,
            diameter: 0.4,
            length: 1.0,
        },
        0.01,
    )
    .unwrap();
    assert!((c.support(&Vector3::x()).x - 0.5).abs() < 1e-15);
    assert!((c.support(&Vector3::y()).y - 0.2).abs() < 1e-15);

    let cone = CollisionShape::with_smoothing(
        &Shape::Cone {
            axis: modia3d_core::geometry::Axis::Z,
            diameter: 0.4,
            length: 1.0,
            top_diameter: 0.1,
        },
        0.01,
    )
    .unwrap();
    assert!(
        cone.support(&-Vector3::z()).z.abs() < 1e-15,
        "base stays at z = 0"
    );
    assert!(
        (cone.support(&Vector3::z()).z - 1.0).abs() < 1e-15,
        "top stays at z = length"
    );
    // Lateral line from (0.2, 0) to (0.05, 1): its outward normal direction.
    let nl = Vector3::new(1.0, 0.0, 0.15).normalize();
    let h_true = nl.dot(&Vector3::new(0.2, 0.0, 0.0));
    assert!((nl.dot(&cone.support(&nl).coords) - h_true).abs() < 1e-14);

    let mut rng = Rng(3);
    for _ in 0..20 {
        let shape = random_shape(&mut rng, modia3d_core::geometry::ShapeKind::ConvexHull);
        let Shape::ConvexHull { points } = &shape else {
            unreachable!()
        };
        let hull = parry3d_f64::shape::ConvexPolyhedron::from_convex_hull(points).unwrap();
        let cs = CollisionShape::with_smoothing(&shape, 0.02).unwrap();
        assert!(cs.smoothing_radius() > 0.0);
        // Faces much wider than 2r keep their plane; faces narrower than that may vanish when
        // shrunk (correct geometry: rounding eats small facets), so only count them.
        let mut kept = 0;
        for f in hull.faces() {
            let nrm = f.normal.into_inner();
            let h_true = hull
                .points()
                .iter()
                .map(|p| nrm.dot(&p.coords))
                .fold(f64::MIN, f64::max);
            let h_ours = nrm.dot(&cs.support(&nrm).coords);
            assert!(h_ours <= h_true + 1e-12);
            if (h_ours - h_true).abs() < 1e-12 {
                kept += 1;
            }
        }
        assert!(2 * kept >= hull.faces().len(), "most face planes kept");
        // And the whole smoothed hull stays inside the original one.
        for _ in 0..100 {
            let d = rng.unit_vector();
            let ours = d.dot(&cs.support(&d).coords);
            let orig = d.dot(&hull.local_support_point(&d).coords);
            assert!(ours <= orig + 1e-12);
        }
    }
}

/// World AABBs are tight: every face of the box touches the shape (support value along the
/// world axis equals the box bound, 1e-12 m) — checked against parry's own AABB of the
/// equivalent round shape where it exists (parry's round-shape AABBs are tight too).
#[test]
fn world_aabb_is_tight() {
    let mut rng = Rng(4);
    for kind in KINDS {
        for _ in 0..200 {
            let shape = random_shape(&mut rng, kind);
            let cs = CollisionShape::with_smoothing(&shape, 0.05).unwrap();
            let pose = random_pose(&mut rng, 2.0);
            let bb = world_aabb(&cs, &pose);
            for i in 0..3 {
                let mut e = Vector3::zeros();
                e[i] = 1.0;
                let hi = (pose * cs.support(&pose.rotation.inverse_transform_vector(&e)))[i];
                let lo = (pose * cs.support(&pose.rotation.inverse_transform_vector(&-e)))[i];
                assert!(
                    (bb.maxs[i] - hi).abs() < 1e-12 && (bb.mins[i] - lo).abs() < 1e-12,
                    "{kind:?}"
                );
            }
            if let Some((ps, local)) = parry_equivalent(&cs) {
                let pb = ps.compute_aabb(&(pose * local));
                assert!(
                    (pb.mins - bb.mins).norm() < 1e-9 && (pb.maxs - bb.maxs).norm() < 1e-9,
                    "{kind:?}"
                );
            }
        }
    }
}

/// The convex hull of a box's corners, smoothed, is the smoothed box (support values equal to
/// 1e-12 m, the accuracy of the 3×3 solves in the shrinking).
#[test]
fn smoothed_box_hull_is_smoothed_box() {
    let l = Vector3::new(0.2, 0.5, 1.1);
    let mut pts = Vec::new();
    for i in 0..8 {
        let s = |k: usize| if i & (1 << k) != 0 { 0.5 } else { -0.5 };
        pts.push(Point3::new(s(0) * l.x, s(1) * l.y, s(2) * l.z));
    }
    let hull = CollisionShape::with_smoothing(&Shape::ConvexHull { points: pts }, 0.01).unwrap();
    let bx = CollisionShape::with_smoothing(&Shape::Box { lengths: l }, 0.01).unwrap();
    assert_eq!(hull.smoothing_radius(), 0.01);
    let mut rng = Rng(5);
    for _ in 0..1000 {
        let d = rng.unit_vector();
        assert!((d.dot(&hull.support(&d).coords) - d.dot(&bx.support(&d).coords)).abs() < 1e-12);
    }
}

#[test]
fn aabb_distance_is_euclidean_gap() {
    let a = Aabb::new(Point3::new(0.0, 0.0, 0.0), Point3::new(1.0, 1.0, 1.0));
    let b = Aabb::new(Point3::new(2.0, 3.0, 0.5), Point3::new(3.0, 4.0, 2.0));
    assert!((aabb_distance(&a, &b) - 5f64.sqrt()).abs() < 1e-15);
    assert!((aabb_distance(&b, &a) - 5f64.sqrt()).abs() < 1e-15);
    let c = Aabb::new(Point3::new(0.5, 0.5, 0.5), Point3::new(3.0, 3.0, 3.0));
    assert_eq!(aabb_distance(&a, &c), 0.0);
}

#[test]
fn invalid_shapes_are_rejected() {
    assert!(CollisionShape::new(&Shape::Sphere { diameter: -1.0 }).is_err());
    assert!(CollisionShape::new(&Shape::Box {
        lengths: Vector3::new(1.0, f64::NAN, 1.0)
    })
    .is_err());
    let flat = (0..5)
        .map(|i| Point3::new(i as f64, (i * i) as f64, 0.0))
        .collect();
    assert!(CollisionShape::new(&Shape::ConvexHull { points: flat }).is_err());
    assert!(CollisionShape::with_smoothing(&Shape::Sphere { diameter: 1.0 }, -1.0).is_err());
}

/// A cube written as OBJ (two objects, plus an interior vertex) loads as the hull of its
/// vertices: the same support function as the box (1e-12 m); a missing file is a typed error.
#[test]
fn convex_hull_from_obj_file() {
    let dir = std::env::temp_dir().join(format!("modia3d-obj-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let path = dir.join("cube.obj");
    let mut text = String::from("o first\n");
    for i in 0..8 {
        let s = |k: usize| if i & (1 << k) != 0 { 0.5 } else { -0.5 };
        if i == 4 {
            text.push_str("o second\n");
        }
        text.push_str(&format!("v {} {} {}\n", s(0), s(1), s(2)));
    }
    // Faces (tobj keeps only vertices referenced by faces); vertex 9 is interior.
    text.push_str("v 0.1 0.0 0.2\nf 1 2 3\nf 2 3 4\nf 5 6 7\nf 6 7 8\nf 1 5 9\n");
    std::fs::write(&path, text).unwrap();
    let scale = Vector3::new(0.2, 0.5, 1.1);
    let shape = modia3d_core::geometry::convex_hull_from_obj(&path, scale).unwrap();
    let hull = CollisionShape::with_smoothing(&shape, 0.01).unwrap();
    let bx = CollisionShape::with_smoothing(&Shape::Box { lengths: scale }, 0.01).unwrap();
    let mut rng = Rng(8);
    for _ in 0..200 {
        let d = rng.unit_vector();
        assert!((d.dot(&hull.support(&d).coords) - d.dot(&bx.support(&d).coords)).abs() < 1e-12);
    }
    let missing = modia3d_core::geometry::convex_hull_from_obj(&dir.join("nope.obj"), scale);
    assert!(matches!(
        missing,
        Err(modia3d_core::geometry::GeometryError::MeshFile { .. })
    ));
    std::fs::remove_dir_all(&dir).ok();
}
