//! The tunnelling guard: the largest step after which no collision shape can have passed
//! through another unseen. IDA sees a contact only as a sign change of the zero-crossing
//! function `z_2` between two step ends; a step long enough to carry a shape from one side of
//! another to the other side shows no sign change, and the contact is lost. From first touch to
//! last touch the two shapes move by about the sum of their thicknesses relative to each other,
//! so limiting the relative displacement per step to half of the thinnest pair's sum keeps every
//! passage through a contact visible. Computed from the body velocities of the last evaluation;
//! costs one pass over the moving collision bodies per step (restarts and steps, never the
//! residual).

use super::preprocess::{ContactPlan, ShapePlan};
use crate::dynamics::Workspace;
use crate::geometry::world_aabb;
use nalgebra::{Isometry3, Vector3};

/// Fraction of the thinnest pair's thickness sum a pair may move relative to each other per
/// step, with both bodies at the fastest body's speed (hence ½ · ½).
const SAFETY: f64 = 0.25;

/// What the guard needs of a contact plan.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct StepGuard {
    /// min over candidate pairs of `t_a + t_b` \[m\], `t` the smallest edge of a shape's own
    /// bounding box (its diameter for a sphere, its smallest edge for a box).
    thinnest_pair: f64,
    /// `(body, R)` for every moving body with a collision shape: R \[m\] bounds the distance of
    /// its shapes' points from the body origin, so `|v| + |ω| R` bounds their speed.
    reach: Vec<(crate::dynamics::BodyId, f64)>,
}

impl StepGuard {
    /// The guard of a contact plan's shapes and candidate pairs.
    pub(crate) fn new(cp: &ContactPlan) -> Self {
        let shapes = &cp.shapes;
        let local = |s: &ShapePlan| world_aabb(&s.shape, &Isometry3::identity());
        let thickness = |s: &ShapePlan| {
            let b = local(s);
            (b.maxs - b.mins).min()
        };
        // The thinnest candidate pair without enumerating all pairs: shapes by thickness, and
        // for each the first partner in that order that can meet it (later ones are thicker).
        let t: Vec<f64> = shapes.iter().map(thickness).collect();
        let mut order: Vec<usize> = (0..shapes.len()).collect();
        order.sort_by(|&i, &j| t[i].total_cmp(&t[j]));
        let mut thinnest_pair = f64::INFINITY;
        for (k, &i) in order.iter().enumerate() {
            if 2.0 * t[i] >= thinnest_pair {
                break;
            }
            for &j in &order[k + 1..] {
                if t[i] + t[j] >= thinnest_pair {
                    break;
                }
                if cp.can_meet(i, j) {
                    thinnest_pair = t[i] + t[j];
                    break;
                }
            }
        }
        let mut reach: Vec<(crate::dynamics::BodyId, f64)> = vec![];
        for s in shapes {
            let Some(body) = s.body else { continue };
            let b = local(s);
            let r = s.in_body.pos.norm() + b.mins.coords.abs().sup(&b.maxs.coords.abs()).norm();
            match reach.iter_mut().find(|(bb, _)| *bb == body) {
                Some((_, rr)) => *rr = rr.max(r),
                None => reach.push((body, r)),
            }
        }
        StepGuard {
            thinnest_pair,
            reach,
        }
    }

    /// The largest safe step \[s\] at the body velocities and accelerations of the last
    /// evaluation in `ws` (accelerations as the residual's inverse dynamics left them, which
    /// include the world's `−g`: adding `g` gives the body's own; `gravity` resolved in world
    /// [m/s²]). Every shape point moves by at most `s h + ½ a h²` in a step h, with
    /// `s = |v| + |ω| R` and `a = |a_o| + |ω| |v| + |ω̇| R`; h is the largest step for which that is ¼ of the
    /// thinnest pair's thickness sum for the fastest body (two bodies approaching each other
    /// move by twice that relative to each other, ½ the sum). `None` when nothing moves.
    pub(crate) fn max_step(&self, ws: &Workspace, gravity: &Vector3<f64>) -> Option<f64> {
        let (mut s_max, mut a_max) = (0.0f64, 0.0f64);
        for &(b, r) in &self.reach {
            let (vel, acc) = (&ws.vel[b], &ws.acc[b]);
            let (v, w) = (vel.v.norm(), vel.w.norm());
            s_max = s_max.max(v + w * r);
            // Spatial → classical acceleration of the origin: + ω × v (bounded by |ω| |v|).
            let a_o = (acc.v + ws.world[b].rot.tr_mul(gravity)).norm();
            a_max = a_max.max(a_o + w * v + acc.w.norm() * r);
        }
        let d = SAFETY * self.thinnest_pair;
        let h = 2.0 * d / (s_max + (s_max * s_max + 2.0 * a_max * d).sqrt());
        (h.is_finite() && h > 0.0).then_some(h)
    }

    /// The body whose shapes move farthest in a step `h` \[s\] by the bound of
    /// [`Self::max_step`] (`s h + ½ a h²`): the one that sets the guard. For diagnoses (a run
    /// whose steps the guard limits); `None` when no body with a collision shape moves.
    pub(crate) fn fastest_body(
        &self,
        ws: &Workspace,
        gravity: &Vector3<f64>,
        h: f64,
    ) -> Option<crate::dynamics::BodyId> {
        let mut best: Option<(crate::dynamics::BodyId, f64)> = None;
        for &(b, r) in &self.reach {
            let (vel, acc) = (&ws.vel[b], &ws.acc[b]);
            let (v, w) = (vel.v.norm(), vel.w.norm());
            let a_o = (acc.v + ws.world[b].rot.tr_mul(gravity)).norm();
            let a = a_o + w * v + acc.w.norm() * r;
            let reach = (v + w * r) * h + 0.5 * a * h * h;
            if reach > 0.0 && best.is_none_or(|(_, x)| reach > x) {
                best = Some((b, reach));
            }
        }
        best.map(|(b, _)| b)
    }
}
