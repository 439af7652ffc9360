//! Closed forms against MPR and parry where all apply, consistency of witness points, and
//! continuity of distance and normal along a smooth path (a box tipping over the edge of
//! another box).
mod common;

use common::*;
use modia3d_core::geometry::narrow_phase::{exact, Method};
use modia3d_core::geometry::{
    signed_distance, signed_distance_method, Axis, CollisionShape, NarrowPhaseOptions, Shape,
    ShapeKind,
};
use nalgebra::{Isometry3, Translation3, UnitQuaternion, Vector3};
use parry3d_f64::query;

fn oracle_core(
    a: &CollisionShape,
    pa: &Isometry3<f64>,
    b: &CollisionShape,
    pb: &Isometry3<f64>,
) -> f64 {
    let pos12 = pa.inv_mul(pb);
    let c =
        query::details::contact_support_map_support_map(&pos12, a.core(), b.core(), 1e6).unwrap();
    c.dist - a.margin() - b.margin()
}

/// Closed forms (exact) vs forced MPR vs parry (box–ellipsoid: its face closed form where it
/// applies, MPR elsewhere). Tolerances: where the cores are separated all
/// three compute the same exact core distance: closed form ↔ MPR+GJK within 2e-8 · size (the
/// GJK certificate bound measured in geometry_mpr_vs_parry), closed form ↔ parry within
/// 2e-5 · size (parry's own GJK accuracy on curved cores). Where the cores overlap (deep), MPR
/// only bounds δ from below: closed ≥ MPR − 1e-12 · size. Witness points: `p_b − p_a = δ n`
/// to 1e-12 · size for the closed forms (they are built that way, rounding only).
#[test]
fn closed_forms_agree_with_mpr_and_parry() {
    let pairs = [
        (ShapeKind::Sphere, ShapeKind::Sphere),
        (ShapeKind::Sphere, ShapeKind::Box),
        (ShapeKind::Box, ShapeKind::Sphere),
        (ShapeKind::Sphere, ShapeKind::Cylinder),
        (ShapeKind::Cylinder, ShapeKind::Sphere),
        (ShapeKind::Sphere, ShapeKind::Capsule),
        (ShapeKind::Capsule, ShapeKind::Sphere),
        (ShapeKind::Capsule, ShapeKind::Capsule),
        (ShapeKind::Box, ShapeKind::Ellipsoid),
        (ShapeKind::Ellipsoid, ShapeKind::Box),
    ];
    let exact = NarrowPhaseOptions::default();
    let forced = NarrowPhaseOptions {
        force_mpr: true,
        ..exact
    };
    let mut rng = Rng(7);
    for (ka, kb) in pairs {
        let (mut e_mpr, mut e_parry, mut e_deep, mut e_wit) = (0.0f64, 0.0f64, f64::MIN, 0.0f64);
        for _ in 0..3000 {
            let a = CollisionShape::with_smoothing(&random_shape(&mut rng, ka), 0.05).unwrap();
            let b = CollisionShape::with_smoothing(&random_shape(&mut rng, kb), 0.05).unwrap();
            let size = a.bounding_radius() + b.bounding_radius();
            let pa = random_pose(&mut rng, 0.1);
            let dir = rng.unit_vector();
            let pb = Isometry3::from_parts(
                Translation3::from(pa.translation.vector + dir * rng.range(0.0, 1.1) * size),
                rng.rotation(),
            );
            let (cf, method) = signed_distance_method(&a, &pa, &b, &pb, &exact).unwrap();
            let mp = signed_distance(&a, &pa, &b, &pb, &forced).unwrap();
            let pr = oracle_core(&a, &pa, &b, &pb);
            // (Box–ellipsoid has a closed form on the box's faces only; elsewhere MPR answers.)
            if method == Method::ClosedForm {
                let wit = (cf.point_b - cf.point_a - cf.normal * cf.distance).norm();
                e_wit = e_wit.max(wit / size);
            }
            if cf.distance > -(a.margin() + b.margin()) + 1e-9 {
                e_mpr = e_mpr.max((cf.distance - mp.distance).abs() / size);
                e_parry = e_parry.max((cf.distance - pr).abs() / size);
                if cf.distance + a.margin() + b.margin() > 1e-6 {
                    assert!(cf.normal.angle(&mp.normal) < 1e-4, "{ka:?}-{kb:?} normals");
                }
            } else {
                e_deep = e_deep.max((mp.distance - cf.distance) / size);
            }
        }
        println!(
            "{:<18} closed−MPR {e_mpr:.1e}  closed−parry {e_parry:.1e}  deep MPR−closed {e_deep:.1e}  witness {e_wit:.1e}",
            format!("{ka:?}-{kb:?}")
        );
        assert!(e_mpr < 2e-8, "{ka:?}-{kb:?}: closed vs MPR {e_mpr}");
        assert!(e_parry < 2e-5, "{ka:?}-{kb:?}: closed vs parry {e_parry}");
        assert!(
            e_deep < 1e-12,
            "{ka:?}-{kb:?}: MPR above the exact depth by {e_deep}"
        );
        assert!(e_wit < 1e-12, "{ka:?}-{kb:?}: witness {e_wit}");
    }
}

/// `narrow_phase::exact` (which pairs always take a closed form; the DAE keeps the full
/// contact tightening for them only) against the dispatch itself: for every pair of kinds
/// (meshes are hulls to the narrow phase), 400 random poses from overlapping to apart. An
/// exact pair must answer every query in closed form; any other pair must go to MPR for at
/// least one of them (the ellipsoid on a box off the box's faces), so a closed form added to
/// the dispatch without `exact`, or the reverse, fails here.
#[test]
fn exact_names_the_pairs_the_dispatch_answers_in_closed_form() {
    use ShapeKind as K;
    let kinds = [
        K::Sphere,
        K::Box,
        K::Ellipsoid,
        K::Cylinder,
        K::Capsule,
        K::Cone,
        K::ConvexHull,
        K::Beam,
    ];
    let opts = NarrowPhaseOptions::default();
    let mut rng = Rng(11);
    for ka in kinds {
        for kb in kinds {
            let mut closed = 0;
            for _ in 0..400 {
                let a = CollisionShape::with_smoothing(&random_shape(&mut rng, ka), 0.05).unwrap();
                let b = CollisionShape::with_smoothing(&random_shape(&mut rng, kb), 0.05).unwrap();
                let size = a.bounding_radius() + b.bounding_radius();
                let pa = random_pose(&mut rng, 0.1);
                let pb = Isometry3::from_parts(
                    Translation3::from(
                        pa.translation.vector + rng.unit_vector() * rng.range(0.0, 1.1) * size,
                    ),
                    rng.rotation(),
                );
                let (_, method) = signed_distance_method(&a, &pa, &b, &pb, &opts).unwrap();
                closed += usize::from(method == Method::ClosedForm);
            }
            if exact(ka, kb) {
                assert_eq!(closed, 400, "{ka:?}-{kb:?} is exact but went to MPR");
            } else {
                assert!(
                    closed < 400,
                    "{ka:?}-{kb:?} always closed form but not exact"
                );
            }
        }
    }
}

/// An ellipsoid over the top face of a table (a 2 × 2 × 0.1 m box, smoothed by 5 mm) at random
/// orientations, positions over the face and heights from 5 cm apart to 5 mm deep, either
/// order. Reference, analytic: the lowest point of an ellipsoid with semi-axes `s` turned by
/// `R` lies `√(Σ_j (R_zj s_j)²)` below its centre, at `c − A² e_z / √(e_zᵀ A² e_z)` with
/// `A = R diag(s) Rᵀ`; the table's top is at z = 0 and its normal is +z. Tolerances: 1e-12 of
/// the size for the distance and the points, 1e-14 rad for the normal (rounding: the closed
/// form takes the box's face normal and one support point).
#[test]
fn ellipsoid_on_a_table_face_matches_the_analytic_lowest_point() {
    let table = CollisionShape::with_smoothing(
        &Shape::Box {
            lengths: Vector3::new(2.0, 2.0, 0.1),
        },
        0.05,
    )
    .unwrap();
    let pt = Isometry3::translation(0.0, 0.0, -0.05);
    let opts = NarrowPhaseOptions::default();
    let mut rng = Rng(31);
    let (mut e_d, mut e_n, mut e_p) = (0.0f64, 0.0f64, 0.0f64);
    for k in 0..500 {
        let s = Vector3::new(
            rng.range(0.02, 0.2),
            rng.range(0.02, 0.2),
            rng.range(0.02, 0.2),
        );
        let e = CollisionShape::new(&Shape::Ellipsoid { lengths: 2.0 * s }).unwrap();
        let rot = rng.rotation();
        let r = rot.to_rotation_matrix();
        let a2 = r.matrix()
            * nalgebra::Matrix3::from_diagonal(&s.component_mul(&s))
            * r.matrix().transpose();
        let below = a2[(2, 2)].sqrt();
        let gap = if k % 2 == 0 {
            rng.range(0.0, 0.05)
        } else {
            -rng.range(0.0, 0.005)
        };
        let c = Vector3::new(rng.range(-0.7, 0.7), rng.range(-0.7, 0.7), below + gap);
        let pe = Isometry3::from_parts(Translation3::from(c), rot);
        let lowest = c - a2.column(2) / below;
        let size = table.bounding_radius() + e.bounding_radius();
        for flip in [false, true] {
            let sd = if flip {
                signed_distance(&e, &pe, &table, &pt, &opts)
                    .unwrap()
                    .flipped()
            } else {
                signed_distance(&table, &pt, &e, &pe, &opts).unwrap()
            };
            e_d = e_d.max((sd.distance - gap).abs() / size);
            e_n = e_n.max((sd.normal - Vector3::z()).norm());
            e_p = e_p.max((sd.point_b.coords - lowest).norm() / size);
            let on_table = lowest - Vector3::z() * gap;
            e_p = e_p.max((sd.point_a.coords - on_table).norm() / size);
        }
    }
    println!("ellipsoid on a table face: distance {e_d:.1e}, normal {e_n:.1e} rad, points {e_p:.1e} of the size");
    assert!(e_d < 1e-12, "distance off by {e_d:e} of the size");
    assert!(e_n < 1e-14, "normal off by {e_n:e} rad");
    assert!(e_p < 1e-12, "points off by {e_p:e} of the size");
}

/// A 0.4 m box slides and tips over the rounded top edge of a 1 m box (smoothing 1 cm each),
/// staying within the exact band (|δ| < r_a + r_b). Path parameter s ∈ [0, 1], 20,000 steps.
/// Lipschitz bounds: |dδ/ds| ≤ v_max, the largest speed of a point of the moving box
/// (0.6 m translation + 0.6 rad rotation at ≤ 0.35 m + 0.02 m vertical ⇒ v_max ≤ 0.83 m);
/// |dn/ds| ≤ v_max / (r_a + r_b) + |dθ/ds| (the normal turns along the rounded edge, whose
/// Minkowski radius is r_a + r_b, or with the face of the turning box). A jump would show as a
/// step larger than that times the step size; we allow a factor 2.
#[test]
fn distance_and_normal_are_continuous_over_an_edge() {
    let a = CollisionShape::with_smoothing(
        &Shape::Box {
            lengths: Vector3::repeat(1.0),
        },
        0.01,
    )
    .unwrap();
    let b = CollisionShape::with_smoothing(
        &Shape::Box {
            lengths: Vector3::repeat(0.4),
        },
        0.01,
    )
    .unwrap();
    let pa = Isometry3::identity();
    let opts = NarrowPhaseOptions::default();
    let pose_b = |s: f64| {
        let x = 0.2 + 0.6 * s;
        let th = 0.6 * (s - 0.5);
        let z = 0.5 + 0.2 * (th.cos() + th.abs().sin()) - 0.005 + 0.01 * (6.0 * s).sin();
        Isometry3::from_parts(
            Translation3::new(x, 0.1, z),
            UnitQuaternion::from_axis_angle(&Vector3::y_axis(), th),
        )
    };
    let n_steps = 20_000;
    let h = 1.0 / n_steps as f64;
    let v_max = 0.83;
    let l_delta = v_max;
    let l_normal = v_max / 0.02 + 0.6;
    let mut prev = signed_distance(&a, &pa, &b, &pose_b(0.0), &opts).unwrap();
    let (mut max_dd, mut max_dn) = (0.0f64, 0.0f64);
    let (mut dmin, mut dmax) = (f64::MAX, f64::MIN);
    for k in 1..=n_steps {
        let r = signed_distance(&a, &pa, &b, &pose_b(k as f64 * h), &opts).unwrap();
        max_dd = max_dd.max((r.distance - prev.distance).abs() / h);
        max_dn = max_dn.max((r.normal - prev.normal).norm() / h);
        dmin = dmin.min(r.distance);
        dmax = dmax.max(r.distance);
        prev = r;
    }
    println!("δ in [{dmin:.4}, {dmax:.4}] m; max |Δδ|/h = {max_dd:.3} (bound {l_delta:.2}), max |Δn|/h = {max_dn:.2} (bound {l_normal:.1})");
    assert!(dmin > -0.02, "path stays in the exact band or separated");
    assert!(dmin < 0.0 && dmax > 0.0, "path crosses contact");
    assert!(max_dd <= 2.0 * l_delta);
    assert!(max_dn <= 2.0 * l_normal);
    let _ = Axis::X;
}
