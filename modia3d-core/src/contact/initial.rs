//! Contact stage, build-time check of the initial state: candidate pairs that start deeper
//! inside each other than the contact law can sensibly push apart (issue 15, point 4).
//!
//! The compliant contact law (docs/contact-model.md §3) is meant for penetrations far smaller
//! than the shapes. Two solids that start with coincident centres, a ball whose centre lies
//! inside another solid, or any overlap deeper than half the thinner shape's extent make the
//! first contact force enormous (or the direction of the normal arbitrary): IDA then fails after
//! a few microseconds with a message about its step count, or the run "succeeds" with the two
//! solids flying apart. Such a start is reported when the model is built, naming the pair and
//! the depth, with the same narrow phase the simulation uses (a deep MPR estimate is tightened
//! by [`sampled_depth`]).

use super::contact_set::shape_pose;
use super::preprocess::ContactPlan;
use crate::dynamics::{kinematics, Plan, Workspace};
use crate::geometry::narrow_phase::Method;
use crate::geometry::{signed_distance_method, world_aabb, BroadPhase, CollisionShape};
use crate::scene::{SceneError, SizeSlip};
use nalgebra::{Isometry3, Vector3};

/// Deepest admissible initial penetration relative to the thinner shape's extent [-]: a
/// penetration of more than half the extent puts the centre of a ball (or the mid-plane of a
/// plate) inside the other solid.
pub(crate) const MAX_INITIAL_DEPTH_RATIO: f64 = 0.5;

/// Extent of a shape \[m\]: the smallest edge of its bounding box in its own frame (the diameter
/// of a sphere, the thickness of a plate, the smaller of diameter and length of a cylinder).
pub(crate) fn extent(s: &CollisionShape) -> f64 {
    2.0 * s.local_half_extents().min()
}

/// A moving collision solid this many times larger than the median of the others is a
/// suspected unit slip (a length in mm where m was meant is 1000 times too large; a billiard
/// ball on its table is 1/44 of it, a marble on a floor smaller still).
pub(crate) const SIZE_RATIO: f64 = 50.0;

/// The median of `values` without entry `k`.
pub(crate) fn median_of_others(values: &[f64], k: usize) -> Option<f64> {
    let mut v: Vec<f64> = values
        .iter()
        .enumerate()
        .filter(|&(i, _)| i != k)
        .map(|(_, &x)| x)
        .collect();
    v.sort_by(f64::total_cmp);
    let n = v.len();
    let hi = v.get(n / 2).copied()?;
    Some(if n % 2 == 0 {
        0.5 * (hi + v.get(n / 2 - 1).copied().unwrap_or(hi))
    } else {
        hi
    })
}

/// The unit check of sizes: every moving collision shape of `cp` whose largest extent
/// \[m\] is more than [`SIZE_RATIO`] times the median of the other shapes', as the shape's
/// object name with the size (its value, and the median of the others). Build-time: the
/// initial-penetration error names it as the likely cause, and every run warns about it
/// (`SimWarning::ScaleOutlier`).
pub(crate) fn size_outliers(scene: &crate::scene::ValidScene, cp: &ContactPlan) -> Vec<SizeSlip> {
    let sizes: Vec<f64> = cp
        .shapes
        .iter()
        .map(|s| 2.0 * s.shape.local_half_extents().max())
        .collect();
    let mut out = vec![];
    for (k, s) in cp.shapes.iter().enumerate() {
        let (Some(_), Some(&size)) = (s.body, sizes.get(k)) else {
            continue;
        };
        if let Some(median) =
            median_of_others(&sizes, k).filter(|&m| m > 0.0 && size > SIZE_RATIO * m)
        {
            out.push(SizeSlip {
                object: scene
                    .objects
                    .get(s.object)
                    .map_or_else(String::new, |o| o.name.clone()),
                size,
                median,
            });
        }
    }
    out
}

/// The size slip among `slips` of either object of the pair named `pair` (`"a|b"`, a
/// decomposed mesh's part named `<object>#<k>`), if any.
pub(crate) fn slip_of_pair<'a>(slips: &'a [SizeSlip], pair: &str) -> Option<&'a SizeSlip> {
    let (a, b) = pair.split_once('|').unwrap_or((pair, ""));
    let is = |s: &SizeSlip, name: &str| name.split('#').next() == Some(s.object.as_str());
    slips.iter().find(|s| is(s, a) || is(s, b))
}

/// One [`SceneError::InitialPenetration`] for every candidate pair of `cp` whose signed
/// distance at the plan's initial state `y0` is below `−MAX_INITIAL_DEPTH_RATIO · extent` of
/// the thinner shape, naming a size slip of either object ([`size_outliers`]) as the likely
/// cause. Pairs whose narrow phase fails here are left to the simulation, which reports the
/// failure with its time.
pub(crate) fn initial_penetrations(plan: &Plan, cp: &ContactPlan) -> Vec<SceneError> {
    let mut ws = Workspace::new(plan);
    let y0 = plan.y0();
    let (q, v) = y0.split_at(plan.nq);
    kinematics::position_velocity(plan, &mut ws, q, v);
    let poses: Vec<_> = (0..cp.shapes.len())
        .map(|s| shape_pose(cp, &ws, s))
        .collect();
    // Only pairs whose boxes overlap can penetrate: the broad phase finds them without
    // looking at all N²/2 candidate pairs.
    let aabbs: Vec<_> = cp
        .shapes
        .iter()
        .zip(&poses)
        .map(|(s, p)| world_aabb(&s.shape, p))
        .collect();
    let mut overlapping = vec![];
    BroadPhase::new(aabbs.len()).update(
        &aabbs,
        |a, b| cp.can_meet(a as usize, b as usize),
        &mut overlapping,
    );
    overlapping.sort_unstable();
    let mut errors = vec![];
    let mut slips = None;
    for pp in overlapping
        .iter()
        .filter_map(|&(a, b)| cp.pair(a as usize, b as usize))
    {
        let (a, b) = (&cp.shapes[pp.a].shape, &cp.shapes[pp.b].shape);
        let (pa, pb) = (&poses[pp.a], &poses[pp.b]);
        let Ok((sd, method)) = signed_distance_method(a, pa, b, pb, &cp.narrow) else {
            continue;
        };
        let limit = MAX_INITIAL_DEPTH_RATIO * extent(a).min(extent(b));
        let mut depth = -sd.distance;
        if depth > limit && method != Method::ClosedForm {
            // MPR's depth along the centre ray can exceed the true one (coincident boxes:
            // the depth along x instead of the thinnest axis).
            depth = depth.min(sampled_depth(a, pa, b, pb));
        }
        if depth > limit {
            let centre_gap = (pb * b.centre() - pa * a.centre()).norm();
            let size = a.bounding_radius() + b.bounding_radius();
            let names = cp.pair_name(&plan.scene, &pp);
            let (object1, object2) = names.split_once('|').unwrap_or((&names, ""));
            let slips = slips.get_or_insert_with(|| size_outliers(&plan.scene, cp));
            let size_slip = slip_of_pair(slips, &names).cloned().map(Box::new);
            errors.push(SceneError::InitialPenetration {
                object1: object1.to_string(),
                object2: object2.to_string(),
                depth,
                limit,
                coincident: centre_gap <= 1e-9 * size,
                size_slip,
            });
        }
    }
    errors
}

/// Penetration depth \[m\] of two overlapping shapes as the smallest support value
/// `h_M(n) = h_b(n) + h_a(−n)` of their Minkowski difference `M = b ⊖ a` over a set of
/// directions: both shapes' frame axes (the face normals of boxes) and 400 directions spread
/// evenly over the sphere (Fibonacci lattice). For convex shapes whose difference contains the
/// origin the depth is `min_n h_M(n)` over all unit `n`, so this is an upper bound, exact when
/// the deepest-face normal is among the directions and within a few per cent otherwise. Used
/// where MPR's centre-ray estimate is deep (build time only: it costs 800 support points).
pub(crate) fn sampled_depth(
    a: &CollisionShape,
    pa: &Isometry3<f64>,
    b: &CollisionShape,
    pb: &Isometry3<f64>,
) -> f64 {
    let h = |n: &Vector3<f64>| {
        n.dot(&(b.core_support_world(pb, n) - a.core_support_world(pa, &-n)))
            + a.margin()
            + b.margin()
    };
    let axes = (0..3).flat_map(|i| {
        let e = Vector3::ith(i, 1.0);
        [pa.rotation * e, pb.rotation * e]
    });
    const N: usize = 400;
    let golden = std::f64::consts::PI * (3.0 - 5f64.sqrt());
    let lattice = (0..N).map(|k| {
        let z = 1.0 - (2 * k + 1) as f64 / N as f64;
        let r = (1.0 - z * z).sqrt();
        let phi = golden * k as f64;
        Vector3::new(r * phi.cos(), r * phi.sin(), z)
    });
    axes.flat_map(|n| [n, -n])
        .chain(lattice)
        .map(|n| h(&n))
        .fold(f64::INFINITY, f64::min)
}
