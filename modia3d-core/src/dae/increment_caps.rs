//! DAE stage: bounds on the difference-quotient increments of the positions that turn or
//! shift a body in contact ([`crate::solver::DaeSystem::increment_caps`] for the solver's
//! coloured quotients; the quaternion cap also for the pair-local quotients of free bodies
//! in `dae/jacobian.rs`).
//!
//! Why: the solver's rule (`solver::dq_increment`, `√ε` times the unknown's size) turns a body
//! by ~3e-10 rad, but the centre of pressure of a flat or line contact (`contact_patch`)
//! crosses the whole patch when a tilt lifts one side by the depth δ, i.e. within `δ/L` rad
//! for a patch of length L: 8e-9 rad for a resting 0.3 m steel body 2.4 nm deep. The quotient
//! then spans a good part of that sweep, Newton's matrix is wrong and the steps collapse.
//! Measured:
//! - a free 26 kg steel cylinder or cone sliding on its side on a steel table stalled at
//!   2e-7 s steps with 10,000 Newton failures, reaching 0.19 s of 0.34 s; with every pair
//!   increment scaled by 1e-1…1e-3 it ran to its end, with 1e-4 it stalled again, the narrow
//!   phase's noise then dominating (`tests/regressions/cylinder_slides_on_its_side.json`);
//! - a 1.3 mm steel hull resting on the table ~1e-10 m deep, root of a tree that carries a
//!   spinning steel box on a spherical joint (the solver's coloured quotients; random scene
//!   0x58dd003d9c279230 of the 10,000-scene batch): 55,344 Newton failures in 114,924 steps
//!   and t = 0.37 s of 0.55 s after 20 s of wall. The solver's increment of its translation,
//!   1.5e-10 m, lifted it out of the contact: capping the quaternion alone did not end the
//!   run, capping the translation at `SHIFT_FRACTION · δ` too (the Hertz law's secant over
//!   `0.1·δ` is within 2.5 % of its slope) ends it in 7,781 steps
//!   (`tests/regressions/spinning_box_on_a_resting_hull.json`).
//!
//! So in the solver's coloured quotients a position that turns a body (a quaternion
//! component, a joint angle) moves the far end of a contacting shape (`lever` from the centre
//! of the turn) by at most `DEPTH_FRACTION · δ`, and one that shifts it (a translation) by at
//! most `SHIFT_FRACTION · δ`; never by less than `NOISE_MULTIPLE` narrow-phase stopping
//! lengths, nor less than `DEPTH_FRACTION` of what the unknown moves in the step (`h·y'`:
//! Newton's corrections are of that size, and an impact's must see the law's secant over
//! them). Measured on the 102 scenes of the 2,000-scene batch (seed 0xd5d9f8b82aae72be) that
//! did not end within 2 s, replayed at 5 s: 22 end without caps, 25 with the turning caps
//! alone, 29 with both (no scene lost); the 21 that end in all three took 48.4 / 49.6 /
//! 53.7 s together.
//!
//! The pair-local quotients of free bodies (`dae/jacobian.rs`) cap only the quaternion:
//! capping their translations at `1e-3·δ` made the 0.65 g cylinder of
//! `tests/regressions/rolling_resistance_stalls_newton.json`, without its rolling
//! resistance, chatter on the table (1,683 events and 240,000 steps in 10 s instead of ending
//! in 0.05 s), and at `0.1·δ` a minimised capsule tipping over on its rounded end ended its
//! run, but with 821 contact events where it had 73 by the same time.
//! Allocation-free.

use super::MultibodyDae;
use crate::contact::{ContactPlan, ContactState};
use crate::dynamics::{kinematics, BodyId};
use crate::solver::JacobianArgs;
use nalgebra::{Point3, Vector3};

/// Largest motion of a contacting shape's far end under a turning increment, as a fraction
/// of the contact's penetration depth.
const DEPTH_FRACTION: f64 = 1e-3;
/// Largest shift of a contacting body under a translation's increment in the solver's
/// coloured quotients, as a fraction of the contact's penetration depth.
const SHIFT_FRACTION: f64 = 0.1;
/// Smallest motion in units of the narrow phase's stopping length
/// (`mpr_tolerance · size`, `geometry/narrow_phase/mod.rs`).
const NOISE_MULTIPLE: f64 = 1.0;

/// How far \[m\] a quotient's increment may move a shape of active pair `k` (a turn: its far
/// end) whose penetration depth is `depth` \[m\]: `fraction · depth`, but at least
/// `NOISE_MULTIPLE` stopping lengths of the pair's narrow phase.
fn tip_allowance(cp: &ContactPlan, cs: &ContactState, k: usize, fraction: f64, depth: f64) -> f64 {
    let (sa, sb) = cs.active_shapes(k);
    let noise = NOISE_MULTIPLE * cp.stopping_length(sa, sb);
    (fraction * depth.max(0.0)).max(noise)
}

/// Bounding radius \[m\] of body `b`'s shape in active pair `k`.
fn own_radius(cp: &ContactPlan, cs: &ContactState, k: usize, b: BodyId) -> f64 {
    let (sa, sb) = cs.active_shapes(k);
    let s = if cp.shapes[sa].body == Some(b) {
        sa
    } else {
        sb
    };
    cp.shapes[s].shape.bounding_radius()
}

/// Cap \[-\] on the increments of body `b`'s quaternion components in the pair-local
/// quotients of active pair `k`, `depth` \[m\] deep with its contact point `point` \[m, world\]
/// and `b`'s origin at `origin` \[m, world\] (`δθ ≈ 2 δq`).
pub(super) fn rotation_cap(
    cp: &ContactPlan,
    cs: &ContactState,
    k: usize,
    b: BodyId,
    depth: f64,
    point: &Point3<f64>,
    origin: &Vector3<f64>,
) -> f64 {
    let lever = (point.coords - origin).norm() + own_radius(cp, cs, k, b);
    tip_allowance(cp, cs, k, DEPTH_FRACTION, depth) / (2.0 * lever)
}

/// `cap` on unknown `j`'s increment, but not below `DEPTH_FRACTION` of what the unknown
/// moves in the step (`|h·y'_j|`, see the module header).
pub(super) fn with_step_floor(cap: f64, args: &JacobianArgs<'_>, j: usize) -> f64 {
    cap.max(DEPTH_FRACTION * (args.h * args.yp[j]).abs())
}

impl MultibodyDae {
    /// [`crate::solver::DaeSystem::increment_caps`]: for every pair in the contact set with a
    /// body whose tree takes the solver's quotients, every turning and shifting position of
    /// the joints from that body up to its root (`JointCoord::for_each_turning_position`,
    /// `for_each_shifting_position`) is capped as the module header says, a turn's centre
    /// being the joint frame's origin (the child body's origin). One narrow phase per such
    /// pair and Jacobian.
    pub(super) fn position_caps(&mut self, args: &JacobianArgs<'_>, caps: &mut [f64]) -> bool {
        self.caps_of(args, caps, false)
    }

    /// [`MultibodyDae::position_caps`] for the trees that take the solver's quotients
    /// (`hinge` false), or for the hinge trees whose columns are exact in this Jacobian
    /// (`hinge` true: their contacts' pair-local quotients, `dae/hinge_jacobian.rs`).
    pub(super) fn caps_of(
        &mut self,
        args: &JacobianArgs<'_>,
        caps: &mut [f64],
        hinge: bool,
    ) -> bool {
        let (Some(tb), Some(cs), Some(cp)) = (
            &self.blocks,
            self.contact.as_ref(),
            self.contact_plan.as_deref(),
        ) else {
            return false;
        };
        let analytic = &self.analytic;
        let is_hinge = &self.hinge.is_hinge;
        let quotients = |b: Option<BodyId>| {
            b.is_some_and(|b| {
                let t = tb.of_body[b.index()];
                let exact = analytic.get(t).copied().unwrap_or(false);
                if hinge {
                    exact && is_hinge.get(t).copied().unwrap_or(false)
                } else {
                    !exact
                }
            })
        };
        let needed = |k: usize| {
            let (ba, bb) = cs.active_bodies(cp, k);
            quotients(ba) || quotients(bb)
        };
        if !(0..cs.n_in_contact()).any(needed) {
            return false;
        }
        let plan = &*self.plan;
        let (nq, nv) = (plan.nq, plan.nv);
        let ws = &mut self.ws;
        kinematics::position_velocity(plan, ws, &args.y[..nq], &args.y[nq..nq + nv]);
        let mut any = false;
        for k in (0..cs.n_in_contact()).filter(|&k| needed(k)) {
            // A pair whose narrow phase fails here fails in the residual too, which reports it.
            let Ok(crate::contact::PairGeometry(sd, patch, _)) =
                cs.pair_geometry(plan, cp, ws, k, args.t)
            else {
                continue;
            };
            let depth = -sd.distance;
            let allowed = tip_allowance(cp, cs, k, DEPTH_FRACTION, depth);
            let shift = tip_allowance(cp, cs, k, SHIFT_FRACTION, depth);
            let (ba, bb) = cs.active_bodies(cp, k);
            for b in [ba, bb].into_iter().flatten() {
                if !quotients(Some(b)) {
                    continue;
                }
                let own = own_radius(cp, cs, k, b);
                let mut on_path = Some(b);
                while let Some(c) = on_path {
                    let body = &plan.bodies[c];
                    let joint = &plan.joints[body.joint];
                    let lever = (patch.point.coords - ws.world[c].pos).norm() + own;
                    joint.coord.for_each_shifting_position(|i| {
                        let j = joint.q_offset + i;
                        caps[j] = caps[j].min(shift);
                        any = true;
                    });
                    joint.coord.for_each_turning_position(|i, rad_per_unit| {
                        let j = joint.q_offset + i;
                        caps[j] = caps[j].min(allowed / (rad_per_unit * lever));
                        any = true;
                    });
                    on_path = body.parent;
                }
            }
        }
        if any {
            for (j, cap) in caps.iter_mut().enumerate().take(nq) {
                if cap.is_finite() {
                    *cap = with_step_floor(*cap, args, j);
                }
            }
        }
        any
    }
}

#[cfg(test)]
mod tests {
    use super::super::MultibodyDae;
    use crate::counting_alloc::allocs;
    use crate::solver::{BlockStructure, DaeSystem, JacobianArgs};
    use crate::{Joint, JointKind, Object3D, SceneDesc, SceneOptions, Shape, Solid};
    use nalgebra::Vector3;

    const R: f64 = 0.03;
    const DELTA: f64 = 1e-7;

    /// A steel ball (Ø 2R = 0.06 m, `offset` \[m\] from its body's origin) on joint `kind`
    /// from the world's origin to the body, resting δ = 1e-7 m deep on a fixed 2 × 2 × 0.1 m
    /// steel table (top at z = −R + δ): the caps of its y at the initial state, and the
    /// allowances `max(f·δ, mpr_tolerance·(R + r_table))` for the fractions `f` = 1e-3 and
    /// 0.1 computed from the construction. Asserts that the tree's own pair-local quotients
    /// (`dae/hinge_jacobian.rs`) and, with those off, the solver's quotients get the same
    /// caps, and that the call allocates nothing once warmed up.
    fn caps_of_a_resting_ball(kind: JointKind, offset: [f64; 3]) -> (Vec<f64>, f64, f64) {
        let mut s = SceneDesc::new();
        s.add(Object3D::new("world").scene(SceneOptions::default()))
            .add(
                Object3D::new("table")
                    .parent("world")
                    .translation([0.0, 0.0, -R + DELTA - 0.05])
                    .solid(
                        Solid::new(Shape::Box {
                            lengths: Vector3::new(2.0, 2.0, 0.1),
                        })
                        .material("Steel")
                        .collision(true),
                    ),
            )
            .add(Object3D::new("arm"))
            .add(
                Object3D::new("ball")
                    .parent("arm")
                    .translation(offset)
                    .solid(
                        Solid::new(Shape::Sphere { diameter: 2.0 * R })
                            .material("Steel")
                            .collision(true),
                    ),
            )
            .add_joint(Joint::new("joint", "world", "arm", kind).can_collide(true));
        let model = s.build().unwrap();
        let mpr_tolerance = model.contact.as_ref().unwrap().narrow.mpr_tolerance;
        let mut dae = MultibodyDae::new(model.plan.clone(), model.contact.clone());
        let y = model.plan.y0();
        let n = y.len();
        dae.handle_event(0.0, &y).unwrap();
        let yp = dae.consistent_derivative(0.0, &mut y.clone()).unwrap();
        let mut st = BlockStructure::default();
        assert!(dae.jacobian_structure(&mut st));
        assert!(
            st.analytic[0],
            "a hinge tree against a fixed table: exact columns (dae/hinge_jacobian.rs)"
        );
        let zero_size = vec![1e-2; n];
        let args = JacobianArgs {
            t: 0.0,
            c_j: 1e3,
            h: 1e-4,
            y: &y,
            yp: &yp,
            zero_size: &zero_size,
        };
        // The caps of its own pair-local quotients.
        let mut exact = vec![f64::INFINITY; n];
        assert!(dae.caps_of(&args, &mut exact, true));
        // With the exact columns off, the solver's quotients: the same caps.
        dae.analytic_enabled = false;
        assert!(dae.jacobian_structure(&mut st));
        assert!(!st.analytic[0], "the solver's quotients");
        let mut caps = vec![f64::INFINITY; n];
        assert!(dae.increment_caps(&args, &mut caps));
        assert_eq!(exact, caps, "one rule for both paths");
        let mut again = vec![0.0; n];
        let before = allocs();
        for _ in 0..100 {
            again.fill(f64::INFINITY);
            dae.increment_caps(&args, &mut again);
        }
        assert_eq!(allocs() - before, 0, "allocations in increment_caps");
        assert_eq!(again, caps);
        let r_table = (2.0f64 * 2.0 + 0.1 * 0.1 / 4.0).sqrt();
        let noise = mpr_tolerance * (R + r_table);
        (caps, (1e-3 * DELTA).max(noise), (0.1 * DELTA).max(noise))
    }

    /// The ball at the end of a horizontal arm of length L = 0.4 m on a revolute joint about
    /// y: the angle's increment turns the far end of the ball (lever from the pivot to the
    /// contact point, which lies within δ of (L, 0, −R), plus R) by at most 1e-3·δ.
    /// Relative tolerance 1e-6: the lever is known to ~δ = 1e-7 m of 0.43 m.
    #[test]
    fn a_ball_on_an_arm_caps_its_angle_by_the_depth_over_the_lever() {
        let l = 0.4;
        let kind = JointKind::Revolute {
            axis: Vector3::y(),
            phi: 0.0,
            w: 0.0,
        };
        let (caps, turn, _) = caps_of_a_resting_ball(kind, [l, 0.0, 0.0]);
        assert_eq!(caps.len(), 2, "one angle, one angular velocity");
        let expected = turn / ((l * l + R * R).sqrt() + R);
        assert!(
            (caps[0] - expected).abs() <= 1e-6 * expected,
            "cap {:e}, expected {expected:e}",
            caps[0]
        );
        assert!(caps[1].is_infinite(), "velocities keep the solver's rule");
    }

    /// The ball on a vertical prismatic joint: its position's increment shifts it by at most
    /// 0.1·δ (to rounding: the cap is computed from the same depth).
    #[test]
    fn a_ball_on_a_slider_caps_its_shift_by_a_tenth_of_the_depth() {
        let kind = JointKind::Prismatic {
            axis: Vector3::z(),
            s: 0.0,
            v: 0.0,
        };
        let (caps, _, shift) = caps_of_a_resting_ball(kind, [0.0; 3]);
        assert_eq!(caps.len(), 2, "one position, one velocity");
        assert!(
            (caps[0] - shift).abs() <= 1e-6 * shift,
            "cap {:e}, expected {shift:e}",
            caps[0]
        );
        assert!(caps[1].is_infinite(), "velocities keep the solver's rule");
    }
}
