//! The contact force's point of application (`contact_point`): centred on flat face-on
//! contacts and continuous in the orientation, where the GJK witness points are an arbitrary
//! corner.

use modia3d_core::geometry::{
    contact_point, signed_distance, Axis, CollisionShape, NarrowPhaseOptions, Shape,
};
use nalgebra::{Isometry3, Vector3};

fn table() -> (CollisionShape, Isometry3<f64>) {
    let s = Shape::Box {
        lengths: Vector3::new(2.0, 2.0, 0.1),
    };
    (
        CollisionShape::new(&s).unwrap(),
        Isometry3::translation(0.0, 0.0, -0.05),
    )
}

/// Contact point of `shape` placed with its lowest point `depth` \[m\] into the table top, at
/// horizontal position (x, y), rotated by `rot` (axis-angle) about its centre.
fn point_on_table(
    shape: &Shape,
    half_height: f64,
    xy: (f64, f64),
    rot: Vector3<f64>,
) -> Vector3<f64> {
    let (t, pt) = table();
    let b = CollisionShape::new(shape).unwrap();
    let opts = NarrowPhaseOptions::default();
    let mut pose = Isometry3::new(Vector3::new(xy.0, xy.1, half_height), rot);
    // Put the lowest point 1e-6 m below the table top.
    let sd = signed_distance(&t, &pt, &b, &pose, &opts).unwrap();
    pose.translation.vector.z -= sd.distance + 1e-6;
    let sd = signed_distance(&t, &pt, &b, &pose, &opts).unwrap();
    assert!((sd.distance + 1e-6).abs() < 1e-9, "{}", sd.distance);
    contact_point(&t, &pt, &b, &pose, &sd).coords
}

#[test]
fn face_on_contacts_are_centred() {
    let bx = Shape::Box {
        lengths: Vector3::new(0.2, 0.1, 0.05),
    };
    let p = point_on_table(&bx, 0.025, (-0.4, 0.3), Vector3::z() * 0.3);
    // The table's own feature centroid pulls with a weight of ~(0.0125/2)² ≈ 4e-5.
    assert!(
        (p.x + 0.4).abs() < 1e-4 && (p.y - 0.3).abs() < 1e-4,
        "{p:?}"
    );
    assert!((p.z + 0.5e-6).abs() < 1e-9, "{p:?}");
    let side = Shape::Cylinder {
        axis: Axis::X,
        diameter: 0.08,
        length: 0.2,
    };
    let p = point_on_table(&side, 0.04, (0.1, 0.0), Vector3::zeros());
    assert!((p.x - 0.1).abs() < 1e-4 && p.y.abs() < 1e-4, "{p:?}");
    let base = Shape::Cylinder {
        axis: Axis::Z,
        diameter: 0.1,
        length: 0.1,
    };
    let p = point_on_table(&base, 0.05, (0.0, 0.2), Vector3::zeros());
    assert!(p.x.abs() < 1e-4 && (p.y - 0.2).abs() < 1e-4, "{p:?}");
}

/// Tilting a face-on box through 0 (±3e-5 rad, depth 1e-6 m, so the far edge lifts off at
/// 1e-6/0.2 = 5e-6 rad) moves the point continuously towards the lower edge; the largest
/// step between tilts 1e-7 rad apart is a small fraction of the half length 0.1 m. Past the
/// lift-off the loaded strip is `depth/θ` long and its centre of pressure (a linear layer) a
/// third of that from the edge: at 3e-5 rad, `h − depth/(3θ)` with the core's half length
/// h = 0.1 − 0.001 m, to 1e-5 m (the table's own feature pulls with a weight of ~1e-4). (The
/// rotation itself moves the point by ~h·Δθ: hence 1e-7 m of slack in the monotonicity.)
#[test]
fn tilting_moves_the_point_continuously() {
    let bx = Shape::Box {
        lengths: Vector3::new(0.2, 0.1, 0.05),
    };
    let mut prev: Option<f64> = None;
    let mut max_step: f64 = 0.0;
    for k in -300..=300 {
        let tilt = k as f64 * 1e-7;
        let x = point_on_table(&bx, 0.025, (0.0, 0.0), Vector3::y() * tilt).x;
        if let Some(px) = prev {
            max_step = max_step.max((x - px).abs());
            assert!(x >= px - 1e-7, "not monotonic at tilt {tilt}: {px} → {x}");
        }
        prev = Some(x);
    }
    let (lo, hi) = (
        point_on_table(&bx, 0.025, (0.0, 0.0), Vector3::y() * -3e-5).x,
        point_on_table(&bx, 0.025, (0.0, 0.0), Vector3::y() * 3e-5).x,
    );
    println!("x from {lo} to {hi}, largest step {max_step}");
    let layer = 0.099 - 1e-6 / (3.0 * 3e-5);
    assert!(
        (hi - layer).abs() < 1e-5 && (lo + layer).abs() < 1e-5,
        "{lo} {hi} vs ±{layer}"
    );
    assert!(max_step < 0.01, "largest step {max_step}");
}
