//! The tunnelling guard: the largest step after which no collision shape can have passed
//! through another unseen. IDA sees a contact only as a sign change of the zero-crossing
//! function `z_2` between two step ends; a step long enough to carry a shape from one side of
//! another to the other side shows no sign change, and the contact is lost. From first touch to
//! last touch the two shapes move by about the sum of their thicknesses relative to each other,
//! so limiting the relative displacement per step to half of that sum keeps every passage
//! through a contact visible. Each body is held to a quarter of the thinnest pair it takes
//! part in (so two bodies approaching each other move by at most half of their pair's sum):
//! a fast body is not held to the thickness of a thin pair elsewhere, nor a thin slow pair to
//! the speed of a thick fast body. Computed from the body velocities of the last evaluation;
//! costs one pass over the moving collision bodies per step (restarts and steps, never the
//! residual).

use super::preprocess::{ContactPlan, ShapePlan};
use crate::dynamics::Workspace;
use crate::geometry::world_aabb;
use nalgebra::{Isometry3, Vector3};

/// Fraction of the thickness sum of the thinnest pair a body takes part in that the body may
/// move per step (two bodies approaching each other: ½ of their pair's sum).
const SAFETY: f64 = 0.25;

/// A moving body with collision shapes, as the guard sees it.
#[derive(Clone, Debug, PartialEq)]
struct GuardBody {
    body: crate::dynamics::BodyId,
    /// Bounds the distance of its shapes' points from the body origin \[m\], so `|v| + |ω| R`
    /// bounds their speed.
    reach: f64,
    /// min over the candidate pairs of its shapes of `t_a + t_b` \[m\], `t` the smallest edge
    /// of a shape's own bounding box (its diameter for a sphere, its smallest edge for a box);
    /// infinite if none of its shapes can meet another.
    thinnest_pair: f64,
}

/// What the guard needs of a contact plan.
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct StepGuard {
    /// Every moving body with a collision shape.
    bodies: Vec<GuardBody>,
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
        // For each shape the thinnest partner that can meet it, without enumerating all pairs:
        // partners in thickness order, the first that can meet it (later ones are thicker).
        let t: Vec<f64> = shapes.iter().map(thickness).collect();
        let mut order: Vec<usize> = (0..shapes.len()).collect();
        order.sort_by(|&i, &j| t[i].total_cmp(&t[j]));
        let mut bodies: Vec<GuardBody> = vec![];
        for (i, s) in shapes.iter().enumerate() {
            let Some(body) = s.body else { continue };
            let partner = order
                .iter()
                .find(|&&j| j != i && cp.can_meet(i, j))
                .map_or(f64::INFINITY, |&j| t[i] + t[j]);
            let b = local(s);
            let r = s.in_body.pos.norm() + b.mins.coords.abs().sup(&b.maxs.coords.abs()).norm();
            match bodies.iter_mut().find(|g| g.body == body) {
                Some(g) => {
                    g.reach = g.reach.max(r);
                    g.thinnest_pair = g.thinnest_pair.min(partner);
                }
                None => bodies.push(GuardBody {
                    body,
                    reach: r,
                    thinnest_pair: partner,
                }),
            }
        }
        bodies.retain(|g| g.thinnest_pair.is_finite());
        StepGuard { bodies }
    }

    /// Body `g`'s speed and acceleration bounds `(s, a)` of its shapes' points at the last
    /// evaluation in `ws` (see [`Self::max_step`]).
    fn motion_bounds(g: &GuardBody, ws: &Workspace, gravity: &Vector3<f64>) -> (f64, f64) {
        let (vel, acc) = (&ws.vel[g.body], &ws.acc[g.body]);
        let (v, w) = (vel.v.norm(), vel.w.norm());
        // Spatial → classical acceleration of the origin: + ω × v (bounded by |ω| |v|).
        let a_o = (acc.v + ws.world[g.body].rot.tr_mul(gravity)).norm();
        (v + w * g.reach, a_o + w * v + acc.w.norm() * g.reach)
    }

    /// Body `g`'s largest step \[s\]: `s h + ½ a h² = ¼` of its thinnest pair (infinite if it
    /// does not move).
    fn body_step(g: &GuardBody, ws: &Workspace, gravity: &Vector3<f64>) -> f64 {
        let (s, a) = Self::motion_bounds(g, ws, gravity);
        let d = SAFETY * g.thinnest_pair;
        2.0 * d / (s + (s * s + 2.0 * a * d).sqrt())
    }

    /// The body that sets the guard and its largest safe step \[s\], at the body velocities
    /// and accelerations of the last evaluation in `ws` (accelerations as the residual's
    /// inverse dynamics left them, which include the world's `−g`: adding `g` gives the body's
    /// own; `gravity` resolved in world [m/s²]). Every shape point of a body moves by at most
    /// `s h + ½ a h²` in a step h, with `s = |v| + |ω| R` and `a = |a_o| + |ω| |v| + |ω̇| R`;
    /// h is the largest step for which that is ¼ of the thinnest pair the body takes part in,
    /// for every body (two bodies approaching each other move by at most ½ of their pair's sum
    /// relative to each other). `None` when nothing moves.
    pub(crate) fn limit(
        &self,
        ws: &Workspace,
        gravity: &Vector3<f64>,
    ) -> Option<(crate::dynamics::BodyId, f64)> {
        self.bodies
            .iter()
            .map(|g| (g.body, Self::body_step(g, ws, gravity)))
            .filter(|&(_, h)| h.is_finite() && h > 0.0)
            .min_by(|x, y| x.1.total_cmp(&y.1))
    }
}
