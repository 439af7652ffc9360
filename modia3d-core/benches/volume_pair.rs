//! One pair's geometry per residual evaluation, the volume law beside the point law it replaces
//! (docs/contact-model.md §3.2): ns per call of the overlap (`polytope_overlap`,
//! `frustum_planes_overlap`) against the smoothed shapes' signed distance (MPR, GJK and the
//! normal's refinement) plus the contact patch, and the distance the root functions of a
//! volume pair use (the sharp shapes' signed distance; for a cylinder or cone the
//! separating-axis gap over the table's faces). Plain `std::time::Instant`, median of 15 batches. Run:
//! `cargo bench -p modia3d-core --bench volume_pair` (release profile).

use modia3d_core::geometry::overlap::{
    frustum_planes_gap, frustum_planes_overlap, polytope_overlap, OverlapScratch,
};
use modia3d_core::geometry::overlap::{Frustum, Polytope};
use modia3d_core::geometry::{
    contact_patch, signed_distance, Axis, CollisionShape, NarrowPhaseOptions, Shape,
};
use nalgebra::{Isometry3, Point3, Vector3};
use std::hint::black_box;
use std::time::Instant;

/// Median ns per call of `f` over 15 batches of `n` calls.
fn ns(n: usize, mut f: impl FnMut() -> f64) -> f64 {
    let mut t = Vec::with_capacity(15);
    let mut sink = 0.0;
    for _ in 0..15 {
        let t0 = Instant::now();
        for _ in 0..n {
            sink += f();
        }
        t.push(t0.elapsed().as_secs_f64() * 1e9 / n as f64);
    }
    black_box(sink);
    t.sort_by(f64::total_cmp);
    t[7]
}

fn main() {
    let table = Shape::Box {
        lengths: Vector3::new(2.0, 2.0, 0.1),
    };
    let table_pose = Isometry3::translation(0.0, 0.0, -0.05);
    let cube = Shape::Box {
        lengths: Vector3::repeat(0.1),
    };
    let hull = Shape::ConvexHull {
        points: (0..20)
            .map(|k| {
                let a = k as f64 * 2.399_963;
                let z = -1.0 + 2.0 * (k as f64 + 0.5) / 20.0;
                let r = (1.0 - z * z).sqrt();
                Point3::new(0.05 * r * a.cos(), 0.05 * r * a.sin(), 0.05 * z)
            })
            .collect(),
    };
    let cylinder = Shape::Cylinder {
        axis: Axis::Y,
        diameter: 0.1,
        length: 0.2,
    };
    let cases: Vec<(&str, Shape, Isometry3<f64>)> = vec![
        (
            "cube flat on a table (depth 5 nm, tilt 1e-4 rad)",
            cube.clone(),
            Isometry3::new(
                Vector3::new(0.3, 0.2, 0.05 - 5e-9),
                Vector3::new(1e-4, 0.0, 0.0),
            ),
        ),
        (
            "cube on an edge (0.3 rad, depth 1 µm)",
            cube.clone(),
            Isometry3::new(
                Vector3::new(0.0, 0.0, 0.05 * (0.3f64.sin() + 0.3f64.cos()) - 1e-6),
                Vector3::new(0.0, 0.3, 0.0),
            ),
        ),
        (
            "20-point hull on a table (depth 1 µm)",
            hull.clone(),
            Isometry3::new(Vector3::new(0.0, 0.0, 0.05 * 0.95 - 1e-6), Vector3::zeros()),
        ),
        (
            "cylinder on its side (depth 1 µm)",
            cylinder.clone(),
            Isometry3::new(Vector3::new(0.0, 0.0, 0.05 - 1e-6), Vector3::zeros()),
        ),
        (
            "beam 0.2 × 0.05 × 0.02 m flat on a table (depth 1 µm)",
            Shape::Beam {
                axis: Axis::X,
                length: 0.2,
                width: 0.05,
                thickness: 0.02,
            },
            Isometry3::new(Vector3::new(0.0, 0.0, 0.01 - 1e-6), Vector3::zeros()),
        ),
        (
            "beam on a rounded end, tilted 0.3 rad (depth 1 µm)",
            Shape::Beam {
                axis: Axis::X,
                length: 0.2,
                width: 0.05,
                thickness: 0.02,
            },
            Isometry3::new(
                Vector3::new(0.0, 0.0, 0.125 * 0.3f64.cos() + 0.01 * 0.3f64.sin() - 1e-6),
                Vector3::new(0.0, -(std::f64::consts::FRAC_PI_2 - 0.3), 0.0),
            ),
        ),
    ];
    let opts = NarrowPhaseOptions::default();
    let table_smooth = CollisionShape::new(&table).unwrap();
    let table_sharp = CollisionShape::with_smoothing(&table, 0.0).unwrap();
    let table_poly = Polytope::from_shape(&table).unwrap().unwrap();
    println!("| pair | point law: distance + patch [ns] | volume law: overlap [ns] | sharp distance (roots) [ns] | V [m³] |");
    println!("|---|---:|---:|---:|---:|");
    for (name, shape, pose) in cases {
        let smooth = CollisionShape::new(&shape).unwrap();
        // A beam's volume pairs use its polytope for the roots too (contact/preprocess.rs).
        let sharp = match (&shape, Polytope::from_shape(&shape).unwrap()) {
            (Shape::Beam { .. }, Some(p)) => Shape::ConvexHull {
                points: p.vertices().to_vec(),
            },
            _ => shape.clone(),
        };
        let sharp = CollisionShape::with_smoothing(&sharp, 0.0).unwrap();
        let point = ns(20_000, || {
            let sd = signed_distance(&table_smooth, &table_pose, &smooth, &pose, &opts).unwrap();
            contact_patch(&table_smooth, &table_pose, &smooth, &pose, &sd)
                .point
                .z
                + sd.distance
        });
        let mpr = || {
            ns(20_000, || {
                signed_distance(&table_sharp, &table_pose, &sharp, &pose, &opts)
                    .unwrap()
                    .distance
            })
        };
        let (volume, t, roots) = match (
            Polytope::from_shape(&shape).unwrap(),
            Frustum::from_shape(&shape),
        ) {
            (Some(p), _) => {
                let mut scratch = OverlapScratch::default();
                scratch.reserve_for(&table_poly, &p);
                let v = polytope_overlap(&table_poly, &table_pose, &p, &pose, &mut scratch).volume;
                let t = ns(20_000, || {
                    polytope_overlap(&table_poly, &table_pose, &p, &pose, &mut scratch).volume
                });
                (v, t, mpr())
            }
            (None, Some(f)) => {
                let planes = || {
                    table_poly.face_planes().map(|(n, h)| {
                        let nw = table_pose.rotation * n;
                        (nw, h + nw.dot(&table_pose.translation.vector))
                    })
                };
                let v = frustum_planes_overlap(&f, &pose, planes()).volume;
                // Its roots: the separating-axis gap over the table's faces
                // (contact/contact_set.rs, `frustum_gap`), not MPR.
                let gap = ns(20_000, || {
                    frustum_planes_gap(&f, &pose, planes()).map_or(0.0, |g| g.gap)
                });
                (
                    v,
                    ns(20_000, || {
                        frustum_planes_overlap(&f, &pose, planes()).volume
                    }),
                    gap,
                )
            }
            _ => unreachable!("every case is a polytope or a frustum"),
        };
        println!("| {name} | {point:.0} | {t:.0} | {roots:.0} | {volume:.3e} |");
    }
}
