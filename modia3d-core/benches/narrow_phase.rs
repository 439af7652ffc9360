//! Narrow-phase benchmark: ns per query, ours vs parry's `query::contact` on the equivalent
//! shapes. Plain `std::time::Instant`, median of 15 batches.
//! Run: `cargo bench -p modia3d-core --bench narrow_phase` (release profile).

use modia3d_core::geometry::narrow_phase::mpr_signed_distance;
use modia3d_core::geometry::{
    signed_distance, CollisionShape, CoreShape, NarrowPhaseOptions, Shape,
};
use nalgebra::{Isometry3, Point3, Translation3, UnitQuaternion, Vector3};
use parry3d_f64::shape::{
    Ball, Capsule, Cone, ConvexPolyhedron, Cuboid, Cylinder, RoundShape, SharedShape,
};
use std::hint::black_box;
use std::time::Instant;

struct Rng(u64);
impl Rng {
    fn f(&mut self) -> f64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        ((z ^ (z >> 31)) >> 11) as f64 / (1u64 << 53) as f64
    }
    fn r(&mut self, lo: f64, hi: f64) -> f64 {
        lo + (hi - lo) * self.f()
    }
}

fn parry_equivalent(cs: &CollisionShape) -> (SharedShape, Isometry3<f64>) {
    let r = cs.margin();
    let id = Isometry3::identity();
    match cs.core() {
        CoreShape::Point { .. } => (SharedShape::new(Ball::new(r)), id),
        CoreShape::Segment { axis, half_length } => {
            let e = axis.unit() * *half_length;
            (
                SharedShape::new(Capsule::new(Point3::from(-e), Point3::from(e), r)),
                id,
            )
        }
        CoreShape::Box { half_extents } => (
            SharedShape::new(RoundShape {
                inner_shape: Cuboid::new(*half_extents),
                border_radius: r,
            }),
            id,
        ),
        CoreShape::Frustum {
            axis,
            z0,
            z1,
            r0,
            r1,
        } => {
            let rot = UnitQuaternion::rotation_between(&Vector3::y(), &axis.unit())
                .unwrap_or_else(UnitQuaternion::identity);
            let pose =
                Isometry3::from_parts(Translation3::from(axis.unit() * (0.5 * (z0 + z1))), rot);
            let hh = 0.5 * (z1 - z0);
            if r0 == r1 {
                (
                    SharedShape::new(RoundShape {
                        inner_shape: Cylinder::new(hh, *r0),
                        border_radius: r,
                    }),
                    pose,
                )
            } else {
                (
                    SharedShape::new(RoundShape {
                        inner_shape: Cone::new(hh, *r0),
                        border_radius: r,
                    }),
                    pose,
                )
            }
        }
        CoreShape::Hull { vertices } => (
            SharedShape::new(RoundShape {
                inner_shape: ConvexPolyhedron::from_convex_hull(vertices).unwrap(),
                border_radius: r,
            }),
            id,
        ),
        CoreShape::Ellipsoid { .. } | CoreShape::Beam { .. } => unreachable!("not benchmarked"),
    }
}

fn median(mut v: Vec<f64>) -> f64 {
    v.sort_by(|a, b| a.total_cmp(b));
    v[v.len() / 2]
}

/// Median over 15 batches of the time per call [ns] of `f` over all poses.
fn time<F: FnMut(usize) -> f64>(n: usize, mut f: F) -> f64 {
    let mut batches = Vec::new();
    for _ in 0..15 {
        let t = Instant::now();
        let mut acc = 0.0;
        for i in 0..n {
            acc += f(i);
        }
        black_box(acc);
        batches.push(t.elapsed().as_secs_f64() * 1e9 / n as f64);
    }
    median(batches)
}

fn main() {
    let bx = |l: f64| Shape::Box {
        lengths: Vector3::new(l, 0.8 * l, 1.2 * l),
    };
    let hull = {
        let mut rng = Rng(5);
        let pts = (0..20)
            .map(|_| Point3::new(rng.r(-0.3, 0.3), rng.r(-0.3, 0.3), rng.r(-0.3, 0.3)))
            .collect();
        Shape::ConvexHull { points: pts }
    };
    let cases: Vec<(&str, Shape, Shape, bool)> = vec![
        (
            "sphere-sphere (closed)",
            Shape::Sphere { diameter: 0.5 },
            Shape::Sphere { diameter: 0.4 },
            false,
        ),
        (
            "sphere-box (closed)",
            Shape::Sphere { diameter: 0.5 },
            bx(0.6),
            false,
        ),
        (
            "capsule-capsule (closed)",
            Shape::Capsule {
                axis: modia3d_core::geometry::Axis::Z,
                diameter: 0.3,
                length: 0.6,
            },
            Shape::Capsule {
                axis: modia3d_core::geometry::Axis::X,
                diameter: 0.2,
                length: 0.5,
            },
            false,
        ),
        ("box-box (MPR)", bx(0.6), bx(0.5), false),
        ("box-box (MPR alone)", bx(0.6), bx(0.5), true),
        (
            "box-cylinder (MPR)",
            bx(0.6),
            Shape::Cylinder {
                axis: modia3d_core::geometry::Axis::Z,
                diameter: 0.5,
                length: 0.6,
            },
            false,
        ),
        (
            "cylinder-cone (MPR)",
            Shape::Cylinder {
                axis: modia3d_core::geometry::Axis::Z,
                diameter: 0.5,
                length: 0.6,
            },
            Shape::Cone {
                axis: modia3d_core::geometry::Axis::Y,
                diameter: 0.5,
                length: 0.6,
                top_diameter: 0.0,
            },
            false,
        ),
        ("hull-hull (MPR)", hull.clone(), hull.clone(), false),
        // Curved cores without a parry equivalent (parry has no ellipsoid): ours only, with
        // the Newton refinement of the normal (`narrow_phase/curved.rs`).
        (
            "sphere-ellipsoid (MPR)",
            Shape::Sphere { diameter: 0.5 },
            Shape::Ellipsoid {
                lengths: Vector3::new(0.6, 0.4, 0.3),
            },
            false,
        ),
        // An ellipsoid against a box: the face closed form where the ellipsoid's support
        // point lies over a face (`closed_form.rs::box_face`), MPR elsewhere; beside MPR alone.
        (
            "box-ellipsoid (dispatch: face form)",
            bx(0.6),
            Shape::Ellipsoid {
                lengths: Vector3::new(0.6, 0.4, 0.3),
            },
            false,
        ),
        (
            "box-ellipsoid (MPR)",
            bx(0.6),
            Shape::Ellipsoid {
                lengths: Vector3::new(0.6, 0.4, 0.3),
            },
            false,
        ),
        (
            "ellipsoid-ellipsoid (MPR)",
            Shape::Ellipsoid {
                lengths: Vector3::new(0.6, 0.4, 0.3),
            },
            Shape::Ellipsoid {
                lengths: Vector3::new(0.5, 0.5, 0.2),
            },
            false,
        ),
    ];
    let n = 2000;
    println!("| pair kind | regime | ours [ns] | parry contact [ns] | ratio ours/parry |");
    println!("|---|---|---:|---:|---:|");
    for (name, sa, sb, mpr_alone) in &cases {
        let a = CollisionShape::with_smoothing(sa, 0.01).unwrap();
        let b = CollisionShape::with_smoothing(sb, 0.01).unwrap();
        let curved_only = |c: &CollisionShape| matches!(c.core(), CoreShape::Ellipsoid { .. });
        let parry = (!curved_only(&a) && !curved_only(&b))
            .then(|| (parry_equivalent(&a), parry_equivalent(&b)));
        for regime in ["near contact", "penetrating"] {
            let mut rng = Rng(11);
            let size = a.bounding_radius() + b.bounding_radius();
            // Poses at centre distances giving |δ| < a few cm ("near contact": cores
            // separated, shallow or separated shapes) or cores overlapping ("penetrating").
            let poses: Vec<(Isometry3<f64>, Isometry3<f64>)> = (0..n)
                .map(|_| {
                    let rot = |rng: &mut Rng| {
                        UnitQuaternion::from_euler_angles(
                            rng.r(0.0, 6.3),
                            rng.r(0.0, 6.3),
                            rng.r(0.0, 6.3),
                        )
                    };
                    let pa = Isometry3::from_parts(Translation3::identity(), rot(&mut rng));
                    let mut pb =
                        Isometry3::from_parts(Translation3::new(0.0, 0.0, 0.0), rot(&mut rng));
                    let d = Vector3::new(rng.r(-1.0, 1.0), rng.r(-1.0, 1.0), rng.r(-1.0, 1.0))
                        .normalize();
                    // Bisection on the centre distance for a target δ.
                    let target = if regime == "near contact" {
                        rng.r(-0.01, 0.02)
                    } else {
                        rng.r(-0.15, -0.05)
                    };
                    let (mut lo, mut hi) = (0.0, size);
                    for _ in 0..40 {
                        let mid = 0.5 * (lo + hi);
                        pb.translation = Translation3::from(d * mid);
                        let r = signed_distance(&a, &pa, &b, &pb, &NarrowPhaseOptions::default())
                            .unwrap();
                        if r.distance < target {
                            lo = mid
                        } else {
                            hi = mid
                        }
                    }
                    (pa, pb)
                })
                .collect();
            let opts = NarrowPhaseOptions {
                exact_separation: !mpr_alone,
                ..Default::default()
            };
            let ours = time(n, |i| {
                let (pa, pb) = &poses[i];
                if name.contains("MPR") {
                    mpr_signed_distance(black_box(&a), pa, black_box(&b), pb, &opts)
                        .unwrap()
                        .0
                        .distance
                } else {
                    signed_distance(black_box(&a), pa, black_box(&b), pb, &opts)
                        .unwrap()
                        .distance
                }
            });
            let Some(((pa_s, la), (pb_s, lb))) = &parry else {
                println!("| {name} | {regime} | {ours:.0} | — | — |");
                continue;
            };
            let theirs = time(n, |i| {
                let (pa, pb) = &poses[i];
                parry3d_f64::query::contact(
                    &(pa * la),
                    pa_s.as_ref(),
                    &(pb * lb),
                    pb_s.as_ref(),
                    1.0,
                )
                .unwrap()
                .map_or(0.0, |c| c.dist)
            });
            println!(
                "| {name} | {regime} | {ours:.0} | {theirs:.0} | {:.2} |",
                ours / theirs
            );
        }
    }
}
