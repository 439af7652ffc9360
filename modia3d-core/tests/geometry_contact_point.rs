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

/// A 0.1 m cube lying on the table 7.1e-10 m deep (a steel cube at rest, `k_red = 1`),
/// tilted by ±θ about x, θ from 1e-12 to 1e-9 rad: the vertex–face contact's normal is the
/// table's face normal exactly, its distance the analytic one of the lowest corner
/// (`z_c − h_core·(cos θ + |sin θ|) − r`, to 1e-17 m), and the point of application the
/// Winkler centroid of the tilted face, `−sgn θ · h_core·(a/6)/(1 − a/2)` with
/// `a = 2·h_core·|sin θ|/δ` (docs/contact-model.md §3), plus the face centre's own shift
/// `h_core·sin θ`, to 1e-3 (the table's own centroid pulls with a weight of ~1e-6).
/// GJK alone stops within its tolerance (~1e-11 m) with a normal up to 1e-10 rad off, which
/// moved this point by up to 0.15 mm between neighbouring tilts and made a resting cube's
/// residual noisy to Newton's method.
#[test]
fn nanometre_face_contacts_are_exact() {
    let (t, pt) = table();
    let cube = CollisionShape::new(&Shape::Box {
        lengths: Vector3::new(0.1, 0.1, 0.1),
    })
    .unwrap();
    let (r, h_core) = (cube.margin(), 0.05 - cube.margin());
    let opts = NarrowPhaseOptions::default();
    let z_c = 0.05 - 7.1e-10;
    for k in [-9, -10, -11, -12] {
        for sign in [-1.0, 1.0] {
            let theta = sign * 10f64.powi(k);
            let pose = Isometry3::new(Vector3::new(0.0, 0.0, z_c), Vector3::x() * theta);
            let sd = signed_distance(&t, &pt, &cube, &pose, &opts).unwrap();
            assert_eq!(sd.normal, Vector3::z(), "θ = {theta:e}");
            let (s, c) = theta.sin_cos();
            let expected = z_c - h_core * (c + s.abs()) - r;
            assert!(
                (sd.distance - expected).abs() < 1e-17,
                "θ = {theta:e}: distance {:e} vs {expected:e}",
                sd.distance
            );
            let p = contact_point(&t, &pt, &cube, &pose, &sd).coords;
            let a = 2.0 * h_core * s.abs() / -sd.distance;
            let y = -theta.signum() * h_core * (a / 6.0) / (1.0 - a / 2.0) * c + h_core * s;
            assert!(
                (p.y - y).abs() < 1e-3 * y.abs() && p.x.abs() < 1e-18,
                "θ = {theta:e}: point {p:?}, expected y {y:e}"
            );
        }
    }
}
