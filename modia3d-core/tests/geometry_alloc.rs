//! No heap allocation per narrow-phase query, per AABB and per broad-phase update once warmed
//! up (a counting global allocator; this test binary holds a single test so that nothing else
//! allocates concurrently).
mod common;

use common::*;
use modia3d_core::geometry::{
    contact_point, signed_distance, world_aabb, world_aabbs_into, BroadPhase, CollisionShape,
    NarrowPhaseOptions,
};
#[path = "common/counting_alloc.rs"]
mod counting_alloc;
use counting_alloc::allocs;

#[test]
fn queries_and_updates_do_not_allocate() {
    let mut rng = Rng(99);
    let shapes: Vec<CollisionShape> = KINDS
        .iter()
        .flat_map(|&k| (0..4).map(move |i| (k, i)))
        .map(|(k, _)| {
            CollisionShape::with_smoothing(&random_shape(&mut Rng(k as u64 + 1), k), 0.05).unwrap()
        })
        .collect();
    let poses: Vec<_> = (0..shapes.len())
        .map(|_| random_pose(&mut rng, 0.8))
        .collect();
    let mut aabbs: Vec<_> = shapes
        .iter()
        .zip(&poses)
        .map(|(s, p)| world_aabb(s, p))
        .collect();
    let mut bp = BroadPhase::new(shapes.len());
    let mut pairs = Vec::with_capacity(shapes.len() * shapes.len());
    bp.update(&aabbs, |_, _| true, &mut pairs); // warm-up
    let forced = NarrowPhaseOptions {
        force_mpr: true,
        ..Default::default()
    };
    let default = NarrowPhaseOptions::default();

    let before = allocs();
    let mut acc = 0.0;
    for round in 0..20 {
        for (k, (s, p)) in shapes.iter().zip(&poses).enumerate() {
            aabbs[k] = world_aabb(
                s,
                &(p * nalgebra::Translation3::new(0.001 * round as f64, 0.0, 0.0)),
            );
        }
        bp.update(&aabbs, |_, _| true, &mut pairs);
        world_aabbs_into(&shapes, &poses, &mut aabbs);
        for i in 0..shapes.len() {
            for j in 0..shapes.len() {
                for opts in [&forced, &default] {
                    let r = signed_distance(&shapes[i], &poses[i], &shapes[j], &poses[j], opts)
                        .unwrap();
                    acc += r.distance;
                    // The force's point of application, for every pair of kinds.
                    let c = contact_point(&shapes[i], &poses[i], &shapes[j], &poses[j], &r);
                    acc += c.x;
                }
            }
        }
    }
    let after = allocs();
    assert!(acc.is_finite());
    assert_eq!(after - before, 0, "allocations during queries and updates");
}
