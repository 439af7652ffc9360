//! The narrow phase at its iteration limit (issue 15, point 5): MPR and GJK always stop after
//! `max_iterations`, returning their best iterate marked `Method::IterationLimit`, never an
//! error or a loop. On 2,000 random ellipsoid pairs (curved: MPR and GJK need many iterations)
//! with limits 1, 2 and 3, every answer is finite and on the documented side of the truth
//! (parry's GJK/EPA on the same cores, margins subtracted): MPR's penetrating estimate is a
//! lower bound of the signed distance (`−h(m)` for any unit `m`), GJK's separated iterate an
//! upper bound (the distance of a point of the Minkowski difference). Tolerance 1e-9 of the
//! pair's size: parry's own accuracy on curved cores.
mod common;

use common::*;
use modia3d_core::geometry::narrow_phase::{mpr_signed_distance, Method};
use modia3d_core::geometry::{CollisionShape, NarrowPhaseOptions, ShapeKind};
use nalgebra::Isometry3;
use parry3d_f64::query;

fn truth(a: &CollisionShape, pa: &Isometry3<f64>, b: &CollisionShape, pb: &Isometry3<f64>) -> f64 {
    let pos12 = pa.inv_mul(pb);
    query::details::contact_support_map_support_map(&pos12, a.core(), b.core(), 1e6)
        .expect("prediction is huge")
        .dist
        - a.margin()
        - b.margin()
}

#[test]
fn mpr_and_gjk_stop_at_the_iteration_limit_with_a_bounded_best_iterate() {
    let mut rng = Rng(0x1515);
    let mut limited = 0;
    for k in 0..2000 {
        let a = CollisionShape::new(&random_shape(&mut rng, ShapeKind::Ellipsoid)).unwrap();
        let b = CollisionShape::new(&random_shape(&mut rng, ShapeKind::Ellipsoid)).unwrap();
        let (pa, pb) = (random_pose(&mut rng, 0.4), random_pose(&mut rng, 0.4));
        let size = a.bounding_radius() + b.bounding_radius();
        let opts = NarrowPhaseOptions {
            max_iterations: 1 + k % 3,
            ..Default::default()
        };
        let (sd, method) = mpr_signed_distance(&a, &pa, &b, &pb, &opts)
            .unwrap_or_else(|e| panic!("case {k}: {e}"));
        assert!(sd.distance.is_finite() && sd.normal.iter().all(|x| x.is_finite()));
        if method != Method::IterationLimit {
            continue;
        }
        limited += 1;
        let t = truth(&a, &pa, &b, &pb);
        if t < -(a.margin() + b.margin()) {
            // Cores penetrating: MPR's estimate.
            assert!(
                sd.distance <= t + 1e-9 * size,
                "case {k}: {} > {t}",
                sd.distance
            );
        } else if sd.distance > 0.0 {
            // Separated, GJK's iterate.
            assert!(
                sd.distance >= t - 1e-9 * size,
                "case {k}: {} < {t}",
                sd.distance
            );
        }
    }
    println!("{limited} of 2000 calls stopped at the iteration limit");
    // Most of them must have reached the limit for the test to mean something.
    assert!(limited > 1000, "only {limited} calls stopped at the limit");
}
