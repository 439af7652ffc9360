//! Driver: why a run was slow. When a run reaches its work budget ([`SimOptions::max_steps`]
//! or [`SimOptions::max_wall_time`]) or its events chatter, the driver ends it with a typed
//! error whose [`WorkDiagnosis`] names the limiting cause, measured on the run itself:
//!
//! - **a chattering pair**: the pair with the most contact events among the last events, with
//!   their number and time span (events per time);
//! - **the stiffest element**: of the contacts in the contact set and the springs, the one with
//!   the shortest natural period `T = 2π·sqrt(m/k)` (`k` the contact's tangent stiffness at its
//!   current penetration, `m` the reduced mass of the two bodies), with a suggested `k_red`
//!   for contacts (below);
//! - **a fast body**: the body the tunnelling guard follows when the guard held the last step,
//!   or the fastest-spinning body when it turns within [`SPIN_RATIO`] steps and no stiff
//!   element explains the steps, with its speed and angular speed;
//! - **a deep contact**: a pair of the contact set deeper than half its thinner shape;
//! - **an ill-conditioned mass matrix**: when Newton failed more often than the error test, the
//!   coordinate with the largest `M_ii·(M⁻¹)_ii` if that exceeds [`ILL_CONDITIONED`];
//! - **a damping-limited contact** (when the steps collapsed): a pair of the set whose damping
//!   factor `1 + d·δ̇` is at its clamp, separating no faster than `1/d`;
//! - **the limiting state**: the component of `y` with the largest weighted local error at the
//!   last step (IDA's own error test), named by its joint and body.
//!
//! The suggested `k_red` scales the contact stiffness so that its period becomes
//! `T* = 50·h_b`, with `h_b = (stop − start)/max_steps` the mean step the budget allows (IDA
//! resolves an oscillation with some tens of steps per period): `k_red · (T/T*)²`.
//! The same causes are given when IDA itself gives up (`SimErrorKind::SolverStalled`).
//! Only read at the end of a failed run: allocates freely.

use crate::contact::initial::extent;
use crate::contact::{ContactPlan, ContactState};
use crate::dynamics::mass_matrix::tree_mass_matrices;
use crate::dynamics::{BodyId, ObjectId, Plan, Workspace};
use crate::joints::Source;
use crate::results::Event;
use crate::scene::ValidForce;

/// Which budget a run reached.
#[derive(Clone, Debug, PartialEq)]
pub enum Budget {
    /// [`SimOptions::max_steps`](super::SimOptions::max_steps) IDA steps, counted over the
    /// whole run (all restarts).
    Steps(u64),
    /// [`SimOptions::max_wall_time`](super::SimOptions::max_wall_time) seconds of wall time.
    WallTime(f64),
}

/// What limited the step size of a run that reached its budget or whose solver gave up
/// ([`SimErrorKind::SolverStalled`](super::SimErrorKind::SolverStalled)).
#[derive(Clone, Debug, PartialEq)]
pub enum SlowCause {
    /// A contact starts and ends again and again.
    Chattering {
        /// The pair `"a|b"`.
        pair: String,
        /// Its events among the last events of the run.
        events: usize,
        /// Time span of those events \[s\].
        span: f64,
    },
    /// A contact in the contact set is the stiffest element.
    StiffContact {
        /// The pair `"a|b"`.
        pair: String,
        /// Its natural period at the current penetration \[s\].
        period: f64,
        /// A `k_red` that would make the period fit the budget (see the module docs).
        suggested_k_red: f64,
        /// Whether the pair has the paper's linear law (a pair without a sphere, `n_geo = 1`):
        /// then the message also names the later profile, whose Hertz law is far softer at
        /// small depths. Of the 27 runs of a 2,000-scene batch that reached their 2 s budget
        /// naming the stiffest contact, 24 named such a pair when replayed with 3 s, and 20 of
        /// those ran to the end with the later profile (2 of the 27 without it).
        linear_law: bool,
    },
    /// A spring (joint spring-damper or spring-damper) is the stiffest element.
    StiffSpring {
        /// The element: `"joint spring of `name`"` or `"spring-damper a–b"`.
        element: String,
        /// Its natural period \[s\].
        period: f64,
    },
    /// The steps collapsed far below the period of every element (the stiffest one's period
    /// is more than 1000 steps (`COLLAPSE_RATIO`), or already fits the budget), so no element's
    /// stiffness explains them: typically a force that is not smooth in the states (a deep or
    /// grazing contact, narrow-phase noise, a discontinuous user force).
    StepCollapse {
        /// The stiffest element's natural period \[s\] (`NaN` without one).
        stiffest_period: f64,
    },
    /// A body moves or spins so fast that its motion limits the steps: the tunnelling guard
    /// (`contact/step_guard.rs`: no collision shape may pass through another between two step
    /// ends) holds the steps (the last step is at least half (`GUARD_LIMITED`) of the guard's), or,
    /// when no stiff element explains the steps, the fastest-spinning body turns once in
    /// fewer than 300 (`SPIN_RATIO`) last steps (IDA's error test follows the rotation).
    /// Typically a small body under a large force or torque (found in random scenes: a 3 mm
    /// ellipsoid under 0.1 N·m spinning at 1e7 rad/s, a 1 g body pushed to km/s).
    FastBody {
        /// The body's first object.
        object: String,
        /// Speed of its frame origin [m/s].
        speed: f64,
        /// Its angular speed [rad/s].
        spin: f64,
        /// The tunnelling guard's largest step \[s\] when the guard limited the steps, else
        /// `None` (the rotation did).
        guard_step: Option<f64>,
    },
    /// A contact in the contact set is deeper than half (`DEEP_CONTACT`) of its thinner shape's
    /// smallest extent: one shape has passed far into the other, where the narrow phase's
    /// normal and point (the shortest way out) jump with the pose, so the contact force is
    /// not smooth in the states (found in random scenes: a 3 g ellipsoid yanked by a spring
    /// into a table at 30 m/s under k_red = 3e-3, 3.7 cm deep for a 1.3 cm shape).
    DeepContact {
        /// The pair `"a|b"`.
        pair: String,
        /// Its penetration \[m\].
        depth: f64,
        /// The smallest extent of the thinner shape \[m\] (edge of its own bounding box).
        thickness: f64,
    },
    /// The mass matrix is ill-conditioned and Newton's method failed more often than the error
    /// test: coordinate `coordinate`'s effective inertia (with every other coordinate free)
    /// is `1/ratio` of its own diagonal inertia (`ratio = M_ii·(M⁻¹)_ii` ≥ 1e6 (`ILL_CONDITIONED`)),
    /// typically a light body carrying a heavy one through a joint (found in random scenes: a
    /// 2 mm, 4 µg sphere on a revolute joint carrying 78 kg by a free joint). Newton's
    /// direction for that coordinate is the small difference of large terms, and the
    /// difference-quotient Jacobian (relative error ~1e-8) cannot resolve it.
    IllConditioned {
        /// The coordinate, e.g. ``"velocity `j0.w` of joint `j0` (object `b0`)"``.
        coordinate: String,
        /// `M_ii·(M⁻¹)_ii` [-] (1 for a coordinate that moves its inertia alone).
        ratio: f64,
    },
    /// The steps collapsed (or no cause was found) and the narrow phase of a contact in the
    /// contact set is not smooth in the pose: moved by 1e-9 or 1e-7 m (`ROUGHNESS_TESTS`), its
    /// normal or depth jumps far more than a smooth surface allows, so the
    /// contact force jumps between steps and IDA's error test follows the jumps. Found in
    /// random scenes (BENCHMARKS.md, "Random scenes"): GJK stopped at its tolerance on curved
    /// cores (cylinder, ellipsoid, capsule pairs) gives normals 1e-6 to 1e-5 rad apart at poses
    /// 1e-12 m apart, and MPR's estimate of a 4 cm overlap jumps by 2e-7 m; under forces of
    /// 1e2 to 1e9 N the tangential part of that jump held the steps at 1e-12 to 1e-15 s. A
    /// limitation of the narrow phase, not of the scene.
    NarrowPhaseNoise {
        /// The pair `"a|b"`.
        pair: String,
        /// The move of shape b that showed it \[m\].
        step: f64,
        /// The largest second difference of the normal over the moves \[rad\].
        normal_jump: f64,
        /// The largest second difference of the signed distance over the moves \[m\].
        depth_jump: f64,
        /// The pair's normal force \[N\].
        force: f64,
    },
    /// The steps collapsed (or no cause was found) while a contact of the set separates no
    /// faster than its damping allows: its damping factor `1 + d·δ̇` of the normal force is
    /// at or below the soft clamp's band (`contact/regularise.rs`), so the force is the small
    /// rest of a stiff elastic force times a nearly cancelling damper, with a slope of
    /// `f_el·d` in the penetration velocity and a knee where the clamp ends, on which Newton's
    /// method fails. Typically shapes that started inside each other: a contact present at
    /// the start has `δ̇⁻ = 0` and so the largest damping factor, and the law lets it out at
    /// `1/d` (found in random scenes: a 36 g ellipsoid starting 5.9 cm inside a fixed sphere
    /// crept out at 1 mm/s for 0.13 s and then failed at 1.7e-9 s steps).
    DampingLimited {
        /// The pair `"a|b"`.
        pair: String,
        /// Its penetration \[m\].
        depth: f64,
        /// The separation speed `1/d` the damping allows [m/s].
        speed: f64,
        /// The pair's normal force \[N\].
        force: f64,
    },
    /// The steps collapsed (or no cause was found) while a contact of the set presses so hard
    /// on a light body that its regularised friction or rolling resistance
    /// (`contact/response.rs`: viscous below `v_min` or `w_min`, Coulomb above) acts on the
    /// body as a damper with a time constant (`m·v_min/(3 μ_k f_n)`, or `I·w_min/(3 μ_r μ_geo
    /// f_n)` with the body's smallest principal inertia `I`; `reg ≥ v_min/3`) of at most
    /// 10 (`FRICTION_RATIO`) last steps and at least a thousandth of one. Newton's method does
    /// not cross the law's band from slip to stick (where the slope jumps from ~0 to
    /// `3 μ f_n / v_min`) unless the body's inertia over the step outweighs that slope, so the
    /// steps fall to a few time constants. Found in random scenes: a 0.65 g steel cylinder 3.5
    /// mm across, rocking on its side on a steel table at 351 N (the non-spheres' linear law at
    /// `k_red = 1`, 2 nm deep), rolling resistance time constant 1e-11 s, IDA gave up at
    /// 1.7e-10 s steps; with `μ_r = 0` it runs to the end.
    StiffFriction {
        /// The pair `"a|b"`.
        pair: String,
        /// `"friction"` or `"rolling resistance"`.
        law: String,
        /// The body's first object.
        object: String,
        /// The damper's time constant \[s\].
        time_constant: f64,
        /// The pair's normal force \[N\].
        force: f64,
    },
    /// The steps collapsed while a contact under the paper's force law for pairs without a
    /// sphere (`f = k_red·c_res·δ·(1 + d·δ̇)`, linear: `n_geo = 1`; docs/contact-model.md §3)
    /// sat at its touch: penetration at most 1e3 (`KINK_BAND`) narrow-phase stopping lengths
    /// (`mpr_tolerance` times the two shapes' bounding radii). There the law's stiffness jumps
    /// from 0 to `k_red·c_res` (no Hertz root to soften it), and Newton's method, whose
    /// iterates straddle the touch, converges only in steps far below the contact's period. A
    /// lift-off or a grazing roll of a small hard body keeps a contact there for thousands of
    /// steps. Found in random scenes: a 1 g steel capsule and a 6 g steel tetrahedron on a thin
    /// steel table, stalled at 1e-10 s steps, run to the end with the later profile (Hertz for
    /// every pair, smooth at touch); 18 of the 30 "collapsed, nothing named" runs of a
    /// 2,000-scene batch did.
    LinearLawAtTouch {
        /// The pair `"a|b"`.
        pair: String,
        /// Its penetration \[m\] (0 when the shapes are apart within the set's hysteresis).
        depth: f64,
        /// The law's stiffness past the touch, `k_red·c_res` \[N/m\].
        stiffness: f64,
        /// The contact's period `2π sqrt(m/k)` with its bodies' reduced mass \[s\].
        period: f64,
    },
    /// None of the above was found.
    Unknown,
}

/// A contact of the paper's linear law counts as sitting at its touch for
/// [`SlowCause::LinearLawAtTouch`] when its penetration is at most this many narrow-phase
/// stopping lengths: the depth is known only to about one of them, so Newton's iterates, whose
/// corrections at the collapsed steps are of that order, fall on both sides of the kink.
pub(super) const KINK_BAND: f64 = 1e3;

/// The contact of the set under the paper's linear law ([`SlowCause::LinearLawAtTouch`]) that
/// sits at its touch, with the shortest period if several, provided the last step `h_last`
/// \[s\] is below that period (longer steps would cross the kink as they are).
pub(crate) fn linear_law_at_touch(
    plan: &Plan,
    cp: Option<&ContactPlan>,
    cs: Option<&ContactState>,
    h_last: f64,
) -> Option<SlowCause> {
    let (cp, cs) = (cp?, cs?);
    let mut best: Option<(f64, SlowCause)> = None;
    for (_, pp, ps) in cs.active_pairs() {
        if pp.n_geo != 1.0 || pp.law != crate::contact::PairLaw::Point {
            continue;
        }
        let (Some(sa), Some(sb)) = (cp.shapes.get(pp.a), cp.shapes.get(pp.b)) else {
            continue;
        };
        let depth = ps.response.penetration;
        // A NaN depth is not at the touch either.
        if depth.is_nan() || depth > KINK_BAND * cp.stopping_length(pp.a, pp.b) {
            continue;
        }
        let k = cp.k_red * pp.c_res * pp.c_geo;
        let t = period(reduced(mass(plan, sa.body), mass(plan, sb.body)), k);
        if !(t.is_finite() && h_last < t) || best.as_ref().is_some_and(|(b, _)| *b <= t) {
            continue;
        }
        best = Some((
            t,
            SlowCause::LinearLawAtTouch {
                pair: cp.pair_name(&plan.scene, pp),
                depth,
                stiffness: k,
                period: t,
            },
        ));
    }
    best.map(|(_, c)| c)
}

/// [`SlowCause::StiffFriction`] explains the steps when its time constant is at most this many
/// last steps (the steps of a collapse sit at a few time constants: 18 in the cylinder above).
pub(super) const FRICTION_RATIO: f64 = 10.0;

/// The tests of [`SlowCause::NarrowPhaseNoise`]: (move \[m\], second difference of the normal
/// \[rad\], of the signed distance \[m\]) above which a narrow phase counts as not smooth. A
/// smooth surface of curvature κ gives `(move·κ)²` and `move²·κ`: at 1e-9 m below 1e-8 rad down
/// to radii of 10 µm (GJK's jumps on curved cores, 1e-6 to 1e-5 rad, show at every move from
/// 1e-12 m on); at 1e-7 m below 1e-5 rad down to 0.03 mm (MPR's estimate of a 4 cm overlap
/// showed 4e-11 rad at 1e-9 m at one pose, but 3.6e-5 rad and 4.3e-7 m at 1e-7 m). The depth's
/// bounds (1e-10 m, 1e-8 m) stay above the narrow phase's own tolerance (`mpr_tolerance` ≤ 1e-9
/// relative to the shapes' size, ≤ 1e-9 m for a 1 m shape).
pub(super) const ROUGHNESS_TESTS: [(f64, f64, f64); 2] = [(1e-9, 1e-8, 1e-10), (1e-7, 1e-5, 1e-8)];

/// The contact of the set whose narrow phase is roughest (see [`SlowCause::NarrowPhaseNoise`])
/// if it is rough at all; its force weighs the jumps (`normal_jump·f_n`).
pub(crate) fn rough_contact(
    plan: &Plan,
    cp: Option<&ContactPlan>,
    cs: Option<&ContactState>,
    ws: &Workspace,
) -> Option<SlowCause> {
    let (cp, cs) = (cp?, cs?);
    let mut best: Option<(f64, SlowCause)> = None;
    for (k, (_, pp, ps)) in cs.active_pairs().enumerate() {
        let rough = ROUGHNESS_TESTS.iter().find_map(|&(step, n_max, d_max)| {
            cs.pair_roughness(cp, ws, k, step)
                .filter(|&(n, d)| n > n_max || d > d_max)
                .map(|(n, d)| (step, n, d))
        });
        let Some((step, normal_jump, depth_jump)) = rough else {
            continue;
        };
        let force = ps.response.f_n;
        let weight = force * normal_jump.max(depth_jump);
        if best.as_ref().is_none_or(|(w, _)| weight > *w) {
            best = Some((
                weight,
                SlowCause::NarrowPhaseNoise {
                    pair: cp.pair_name(&plan.scene, pp),
                    step,
                    normal_jump,
                    depth_jump,
                    force,
                },
            ));
        }
    }
    best.map(|(_, c)| c)
}

/// The contact of the set whose damping factor `1 + d·δ̇` is at or below the soft clamp's
/// band ([`SlowCause::DampingLimited`]), the deepest if several.
pub(crate) fn damping_limited(
    plan: &Plan,
    cp: Option<&ContactPlan>,
    cs: Option<&ContactState>,
) -> Option<SlowCause> {
    let (cp, cs) = (cp?, cs?);
    cs.active_pairs()
        .filter(|(_, _, ps)| {
            let x = 1.0 + ps.d * ps.response.penetration_velocity;
            ps.d > 0.0 && ps.response.penetration > 0.0 && x < crate::contact::CLAMP_BAND
        })
        .max_by(|a, b| {
            a.2.response
                .penetration
                .total_cmp(&b.2.response.penetration)
        })
        .map(|(_, pp, ps)| SlowCause::DampingLimited {
            pair: cp.pair_name(&plan.scene, pp),
            depth: ps.response.penetration,
            speed: 1.0 / ps.d,
            force: ps.response.f_n,
        })
}

/// The contact of the set whose friction or rolling resistance is the stiffest damper on one
/// of its bodies ([`SlowCause::StiffFriction`]), if that damper's time constant lies between a
/// thousandth of the last step `h_last` \[s\] and [`FRICTION_RATIO`] of them.
pub(crate) fn stiff_friction(
    plan: &Plan,
    cp: Option<&ContactPlan>,
    cs: Option<&ContactState>,
    h_last: f64,
) -> Option<SlowCause> {
    let (cp, cs) = (cp?, cs?);
    // (time constant, law, pair, body, normal force) of the stiffest damper so far.
    let mut best: Option<(f64, &str, _, BodyId, f64)> = None;
    for (_, pp, ps) in cs.active_pairs() {
        let f_n = ps.response.f_n;
        if f_n.is_nan() || f_n <= 0.0 {
            continue;
        }
        for s in [pp.a, pp.b] {
            let Some(b) = cp.shapes.get(s).and_then(|s| s.body) else {
                continue;
            };
            let Some(body) = plan.bodies.get(b) else {
                continue;
            };
            let i_min = body.inertia.inertia_com.symmetric_eigenvalues().min();
            let laws = [
                (
                    "friction",
                    body.inertia.mass * pp.v_slip / (3.0 * pp.mu_k * f_n),
                ),
                (
                    "rolling resistance",
                    i_min * pp.w_min / (3.0 * pp.mu_r * pp.mu_geo * f_n),
                ),
            ];
            for (law, tau) in laws {
                if tau.is_finite() && tau > 0.0 && best.is_none_or(|x| tau < x.0) {
                    best = Some((tau, law, pp, b, f_n));
                }
            }
        }
    }
    let (tau, law, pp, b, force) =
        best.filter(|x| x.0 <= FRICTION_RATIO * h_last && x.0 >= 1e-3 * h_last)?;
    Some(SlowCause::StiffFriction {
        pair: cp.pair_name(&plan.scene, pp),
        law: law.to_string(),
        object: body_name(plan, b),
        time_constant: tau,
        force,
    })
}

/// Penetration, as a fraction of the thinner shape's smallest extent, above which a contact
/// counts as deep for [`SlowCause::DeepContact`].
pub(super) const DEEP_CONTACT: f64 = 0.5;

/// `M_ii·(M⁻¹)_ii` above which the mass matrix counts as ill-conditioned for
/// [`SlowCause::IllConditioned`]: the difference-quotient Jacobian's relative error (~1e-8,
/// √ε) times this is 1 % of the coordinate's effective inertia.
pub(super) const ILL_CONDITIONED: f64 = 1e6;

/// A spin explains the steps when the body turns once within this many of them: IDA's error
/// test on a rotation at order 5 allows a turn per step of about `rtol^(1/6)` rad, so some 30
/// steps per turn at rtol 1e-4 and 200 at 1e-9 (in random scenes a 1.3e3 rad/s body at 1,000
/// steps per turn was held by Newton failures, not by its rotation).
pub(super) const SPIN_RATIO: f64 = 300.0;

/// The tunnelling guard limits the steps when the last step is at least this fraction of the
/// guard's step (IDA grows a step by at most 2x, so a step held by a cap sits between ½ and
/// 1 of it).
pub(super) const GUARD_LIMITED: f64 = 0.5;

/// A stiff element explains the steps only when its period is within this many of them (a
/// resolved oscillation takes some tens of steps per period).
pub(super) const COLLAPSE_RATIO: f64 = 1000.0;

/// `cause` (from [`stiffest`]) unless the steps do not follow from it: the element's period is
/// more than [`COLLAPSE_RATIO`] last steps `h_last` \[s\], or it would fit the budget step
/// `h_budget` \[s\] as it is (for a contact: the suggested `k_red` is the current one). Then the
/// cause is a [`SlowCause::StepCollapse`].
pub(crate) fn limiting(cause: SlowCause, h_last: f64, h_budget: f64) -> SlowCause {
    let period = match &cause {
        SlowCause::StiffContact { period, .. } | SlowCause::StiffSpring { period, .. } => *period,
        _ => return cause,
    };
    let fits_budget = period >= 50.0 * h_budget;
    if (h_last > 0.0 && period > COLLAPSE_RATIO * h_last) || fits_budget {
        SlowCause::StepCollapse {
            stiffest_period: period,
        }
    } else {
        cause
    }
}

/// The diagnosis carried by [`SimErrorKind::WorkBudget`](super::SimErrorKind::WorkBudget).
#[derive(Clone, Debug, PartialEq)]
pub struct WorkDiagnosis {
    /// The budget that was reached.
    pub budget: Budget,
    /// Time reached \[s\].
    pub t: f64,
    /// IDA steps of the run so far.
    pub steps: u64,
    /// Contact events of the run so far.
    pub events: usize,
    /// Size of the last step \[s\].
    pub last_step: f64,
    /// IDA's error-test failures over the run.
    pub error_test_failures: u64,
    /// IDA's Newton (nonlinear) convergence failures over the run.
    pub newton_failures: u64,
    /// What limited the steps.
    pub cause: SlowCause,
    /// The state with the largest weighted local error at the last step, e.g.
    /// ``"velocity `rev.w` of joint `rev` (object `arm`)"`` (the joint signal holding it; else its index, ``"velocity 5 of joint `ball.free` (object `ball`)"``).
    pub limiting_state: Option<String>,
}

impl std::fmt::Display for WorkDiagnosis {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match &self.budget {
            Budget::Steps(n) => write!(f, "the run reached its budget of {n} IDA steps")?,
            Budget::WallTime(w) => write!(f, "the run reached its wall-time budget of {w} s")?,
        }
        write!(
            f,
            " at t = {} s ({} steps, {} events, last step {:.3e} s, {} error-test and {} Newton \
             failures): ",
            self.t,
            self.steps,
            self.events,
            self.last_step,
            self.error_test_failures,
            self.newton_failures
        )?;
        write!(f, "{}", self.cause)?;
        if let Some(s) = &self.limiting_state {
            write!(f, "; the step is limited by {s}")?;
        }
        Ok(())
    }
}

impl std::fmt::Display for SlowCause {
    /// What limited the steps and what to do, as one clause (without the run's numbers).
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            SlowCause::Chattering { pair, events, span } => write!(
                f,
                "contact `{pair}` chatters ({events} events in {span:.3e} s); check its initial \
                 overlap, loosen mpr_tolerance no further than the default, or lower k_red"
            )?,
            SlowCause::StiffContact {
                pair,
                period,
                suggested_k_red,
                linear_law,
            } => {
                write!(
                    f,
                    "contact `{pair}` is the stiffest element (period {period:.3e} s); \
                     k_red = {suggested_k_red:.1e} would fit the budget (or raise max_steps)"
                )?;
                if *linear_law {
                    write!(
                        f,
                        "; it has the paper's linear law (a pair without a sphere), stiff from \
                         the touch on: the later profile (SceneOptions::modia3d_later(): Hertz \
                         for every pair) is far softer at small depths"
                    )?;
                }
            }
            SlowCause::StiffSpring { element, period } => write!(
                f,
                "the {element} is the stiffest element (period {period:.3e} s); soften it or \
                 raise max_steps"
            )?,
            SlowCause::StepCollapse { stiffest_period } => write!(
                f,
                "the steps collapsed far below the period of every element (stiffest \
                 {stiffest_period:.3e} s): a force that is not smooth in the states — check \
                 initial overlaps and grazing contacts, keep mpr_tolerance at its default, \
                 make user forces continuous — or loosen the tolerance"
            )?,
            SlowCause::FastBody {
                object,
                speed,
                spin,
                guard_step,
            } => {
                write!(
                    f,
                    "object `{object}` moves at {speed:.3e} m/s and spins at {spin:.3e} rad/s"
                )?;
                if *spin > 0.0 {
                    let turn = 2.0 * std::f64::consts::PI / spin;
                    write!(f, " (a turn in {turn:.3e} s)")?;
                }
                match guard_step {
                    Some(g) => write!(
                        f,
                        "; the tunnelling guard (no shape may pass through another unseen) \
                         limits the steps to {g:.3e} s"
                    )?,
                    None => write!(f, "; its rotation limits the steps")?,
                }
                write!(
                    f,
                    ": check the forces and torques on it against its mass and inertia, or \
                     raise max_steps"
                )?
            }
            SlowCause::DeepContact {
                pair,
                depth,
                thickness,
            } => write!(
                f,
                "contact `{pair}` is {depth:.3e} m deep, more than half its thinner shape \
                 ({thickness:.3e} m): one shape has passed into the other and the contact's \
                 normal jumps — check the forces that drive them together and k_red"
            )?,
            SlowCause::IllConditioned { coordinate, ratio } => write!(
                f,
                "the mass matrix is ill-conditioned: the {coordinate} moves an effective inertia \
                 {:.1e} of its own (a light body carrying a heavy one?), and Newton's method \
                 fails on it — make the carrying body heavier or attach the heavy one elsewhere",
                1.0 / ratio
            )?,
            SlowCause::NarrowPhaseNoise {
                pair,
                step,
                normal_jump,
                depth_jump,
                force,
            } => write!(
                f,
                "the steps collapsed: the narrow phase of contact `{pair}` is not smooth here — \
                 moved by ±{step:.0e} m its normal jumps by {normal_jump:.1e} rad and its depth by \
                 {depth_jump:.1e} m under a normal force of {force:.3e} N (a limitation of the \
                 collision query on curved or deeply overlapping shapes, not of the scene); \
                 loosen the tolerance, lower the force that presses the pair (k_red, the driving \
                 forces), or raise max_steps"
            )?,
            SlowCause::DampingLimited {
                pair,
                depth,
                speed,
                force,
            } => write!(
                f,
                "the steps collapsed: contact `{pair}` is {depth:.3e} m deep and separates no \
                 faster than its damping allows ({speed:.3e} m/s; its normal force \
                 {force:.3e} N is the small rest of a stiff elastic force and a damper at its \
                 clamp) — typically shapes that started inside each other (see the initial \
                 penetration warning): move them apart, or lower k_red"
            )?,
            SlowCause::StiffFriction {
                pair,
                law,
                object,
                time_constant,
                force,
            } => write!(
                f,
                "the steps collapsed: the {law} of contact `{pair}` (normal force {force:.3e} N) \
                 acts on object `{object}` as a damper of time constant {time_constant:.3e} s \
                 below its regularisation speed, a band Newton's method crosses only in steps of \
                 a few time constants — raise the pair's v_min / w_min, lower its friction \
                 coefficients, or lower k_red (a softer, shallower contact presses less)"
            )?,
            SlowCause::LinearLawAtTouch {
                pair,
                depth,
                stiffness,
                period,
            } => write!(
                f,
                "the steps collapsed at the touch of contact `{pair}` ({depth:.1e} m deep): a \
                 pair without a sphere has the paper's linear force law, whose stiffness jumps \
                 from 0 to {stiffness:.3e} N/m where the shapes touch (period {period:.3e} s \
                 with its bodies' masses), a kink Newton's method crosses only in steps far \
                 below that period — use the later profile (SceneOptions::modia3d_later(): \
                 Hertz for every pair, smooth at the touch), or lower k_red"
            )?,
            SlowCause::Unknown => write!(
                f,
                "no chattering contact or stiff element found; raise max_steps or loosen the \
                 tolerance"
            )?,
        }
        Ok(())
    }
}

/// The name of body `b`: its first object's.
fn body_name(plan: &Plan, b: BodyId) -> String {
    plan.bodies
        .get(b)
        .and_then(|b| b.objects.first())
        .and_then(|&o| plan.objects.get(o))
        .map(|o| o.name.clone())
        .unwrap_or_default()
}

/// The contact of the set that is deepest relative to its thinner shape's smallest extent
/// (its own bounding box's smallest edge), if deeper than [`DEEP_CONTACT`] of it.
pub(crate) fn deep_contact(
    plan: &Plan,
    cp: Option<&ContactPlan>,
    cs: Option<&ContactState>,
) -> Option<SlowCause> {
    let (cp, cs) = (cp?, cs?);
    let thickness = |s: usize| cp.shapes.get(s).map_or(f64::NAN, |s| extent(&s.shape));
    let mut best: Option<(f64, SlowCause)> = None;
    for (_, pp, ps) in cs.active_pairs() {
        let depth = ps.response.penetration;
        let thick = thickness(pp.a).min(thickness(pp.b));
        let rel = depth / thick;
        if rel.is_finite() && rel > DEEP_CONTACT && best.as_ref().is_none_or(|(r, _)| rel > *r) {
            let cause = SlowCause::DeepContact {
                pair: cp.pair_name(&plan.scene, pp),
                depth,
                thickness: thick,
            };
            best = Some((rel, cause));
        }
    }
    best.map(|(_, c)| c)
}

/// The free coordinate (velocity index) of `M(q)` with the largest `M_ii·(M⁻¹)_ii`, and that
/// ratio; `None` without free coordinates or when a tree's block is singular.
pub(crate) fn worst_conditioned(plan: &Plan, q: &[f64]) -> Option<(usize, f64)> {
    let mut ws = Workspace::new(plan);
    let mut best: Option<(usize, f64)> = None;
    for (group, m) in tree_mass_matrices(plan, &mut ws, q) {
        // Velocity indices of the free (not prescribed) coordinates of this tree, and their
        // rows in the block.
        let free: Vec<(usize, usize)> = group
            .iter()
            .enumerate()
            .filter(|(_, &i)| plan.prescribed.get(i).is_some_and(|p| p.is_none()))
            .map(|(r, &i)| (r, i))
            .collect();
        let rows: Vec<usize> = free.iter().map(|&(r, _)| r).collect();
        let mf = m.select_rows(&rows).select_columns(&rows);
        let inv = nalgebra::Cholesky::new(mf.clone())?.inverse();
        for (k, &(_, i)) in free.iter().enumerate() {
            let (Some(a), Some(b)) = (mf.get((k, k)), inv.get((k, k))) else {
                continue;
            };
            let ratio = a * b;
            if ratio.is_finite() && best.is_none_or(|(_, x)| ratio > x) {
                best = Some((i, ratio));
            }
        }
    }
    best
}

/// `cause` (from [`limiting`]) unless a fast body explains the steps better: the tunnelling
/// guard limited the last step `h_last` \[s\] (`guard`: its step \[s\] and the body that sets
/// it), or `cause` names no stiff element and the fastest-spinning body (`speeds`: per body
/// the speed of its origin [m/s] and its angular speed [rad/s], in body order) turns once
/// within [`SPIN_RATIO`] last steps. See [`SlowCause::FastBody`]. An ill-conditioned mass
/// matrix (`ill`, [`SlowCause::IllConditioned`], given when Newton failed more often than the
/// error test) comes first: the Newton failures cut the steps whatever the guard allows.
pub(crate) fn with_fast_body(
    cause: SlowCause,
    plan: &Plan,
    speeds: &[(f64, f64)],
    guard: Option<(f64, BodyId)>,
    ill: Option<SlowCause>,
    h_last: f64,
) -> SlowCause {
    let fast = |b: BodyId, guard_step: Option<f64>| {
        let (speed, spin) = speeds.get(b.0).copied().unwrap_or((f64::NAN, f64::NAN));
        SlowCause::FastBody {
            object: body_name(plan, b),
            speed,
            spin,
            guard_step,
        }
    };
    if let Some(c) = ill {
        return c;
    }
    if let Some((g, b)) = guard {
        if h_last > 0.0 && h_last >= GUARD_LIMITED * g {
            return fast(b, Some(g));
        }
    }
    if matches!(
        cause,
        SlowCause::StiffContact { .. } | SlowCause::StiffSpring { .. }
    ) {
        return cause;
    }
    let spinning = speeds
        .iter()
        .enumerate()
        .filter(|(_, (_, w))| w.is_finite() && *w > 0.0)
        .max_by(|a, b| a.1 .1.total_cmp(&b.1 .1));
    match spinning {
        Some((b, &(_, w)))
            if h_last > 0.0 && 2.0 * std::f64::consts::PI / w <= SPIN_RATIO * h_last =>
        {
            fast(BodyId(b), None)
        }
        _ => cause,
    }
}

/// Events of one pair among the last `window` events: the pair with the most, their number and
/// time span \[s\].
pub(crate) fn busiest_pair(events: &[Event], window: usize) -> Option<(String, usize, f64)> {
    let recent = events.iter().skip(events.len().saturating_sub(window));
    let mut counts: Vec<(&str, usize, f64, f64)> = vec![];
    for e in recent {
        for p in e.started.iter().chain(&e.ended) {
            match counts.iter_mut().find(|c| c.0 == p) {
                Some(c) => {
                    c.1 += 1;
                    c.3 = e.t;
                }
                None => counts.push((p, 1, e.t, e.t)),
            }
        }
    }
    counts
        .into_iter()
        .max_by_key(|c| c.1)
        .map(|(p, n, t0, t1)| (p.to_string(), n, t1 - t0))
}

/// Mass \[kg\] of body `b` (`None` = the world: infinite).
fn mass(plan: &Plan, b: Option<BodyId>) -> f64 {
    b.and_then(|b| plan.bodies.get(b))
        .map_or(f64::INFINITY, |b| b.inertia.mass)
}

fn reduced(m1: f64, m2: f64) -> f64 {
    if m1.is_infinite() {
        m2
    } else if m2.is_infinite() {
        m1
    } else {
        m1 * m2 / (m1 + m2)
    }
}

fn period(m: f64, k: f64) -> f64 {
    2.0 * std::f64::consts::PI * (m / k).sqrt()
}

/// The stiffest element: contacts in the set (with the suggested `k_red` for a budget step
/// `h_budget` \[s\]) and springs.
pub(crate) fn stiffest(
    plan: &Plan,
    cp: Option<&ContactPlan>,
    cs: Option<&ContactState>,
    h_budget: f64,
) -> SlowCause {
    let mut best = SlowCause::Unknown;
    let mut best_t = f64::INFINITY;
    if let (Some(cs), Some(cp)) = (cs, cp) {
        for (_, pp, ps) in cs.active_pairs() {
            let body = |s: usize| cp.shapes.get(s).and_then(|s| s.body);
            let delta = ps.response.penetration;
            let k = if pp.law == crate::contact::PairLaw::Point {
                cp.k_red * pp.c_res * pp.c_geo * pp.n_geo * delta.powf(pp.n_geo - 1.0)
            } else {
                // The volume law's stiffness k_red·κ·A is its force over its mean depth V/A
                // at rest (the damping's share aside).
                ps.response.f_n / delta
            };
            let m = reduced(mass(plan, body(pp.a)), mass(plan, body(pp.b)));
            let t = period(m, k);
            if k > 0.0 && t.is_finite() && t < best_t {
                best_t = t;
                let target = 50.0 * h_budget;
                best = SlowCause::StiffContact {
                    pair: cp.pair_name(&plan.scene, pp),
                    period: t,
                    suggested_k_red: cp.k_red * (t / target).powi(2).min(1.0),
                    linear_law: pp.n_geo == 1.0 && pp.law == crate::contact::PairLaw::Point,
                };
            }
        }
    }
    for f in &plan.scene.forces {
        let (element, m, k) = match f {
            ValidForce::JointSpringDamper {
                joint,
                coordinate,
                stiffness,
                ..
            } => {
                let Some(j) = plan.joints.iter().find(|j| j.scene_joint == *joint) else {
                    continue;
                };
                let Some(b) = plan.bodies.get(j.body) else {
                    continue;
                };
                // The inertia the spring's coordinate sees when its body alone moves:
                // `sᵀ I s` with `s` the coordinate's motion at the initial state (about the
                // axis through the body frame origin for a rotation, the mass for a
                // translation).
                let Some(c) = j.coord.coordinates().get(*coordinate) else {
                    continue;
                };
                let mut unit = [0.0; 6];
                let Some(qj) = plan.q0.get(j.q_offset..j.q_offset + j.coord.nq()) else {
                    continue;
                };
                if let Some(u) = unit.get_mut(c.v) {
                    *u = 1.0;
                }
                let Some(e) = unit.get(..j.coord.nv()) else {
                    continue;
                };
                let s = j.coord.motion(qj, e);
                let f = b.inertia.mul_motion(&s);
                let m = (f.n.dot(&s.w) + f.f.dot(&s.v)).max(0.0);
                (format!("joint spring of `{}`", j.name), m, *stiffness)
            }
            ValidForce::SpringDamper {
                obj1, obj2, spring, ..
            } => {
                // A nonlinear law has no single stiffness to report.
                let Some(stiffness) = spring.coefficient() else {
                    continue;
                };
                let (Some(o1), Some(o2)) = (
                    plan.objects.get(ObjectId(*obj1)),
                    plan.objects.get(ObjectId(*obj2)),
                ) else {
                    continue;
                };
                let m = reduced(mass(plan, o1.body), mass(plan, o2.body));
                (
                    format!("spring-damper `{}`–`{}`", o1.name, o2.name),
                    m,
                    stiffness,
                )
            }
            _ => continue,
        };
        let t = period(m, k);
        if k > 0.0 && t.is_finite() && t < best_t {
            best_t = t;
            best = SlowCause::StiffSpring { element, period: t };
        }
    }
    best
}

/// Name of component `i` of `y = [q; v]`: its joint coordinate and the body's first object.
pub(crate) fn state_name(plan: &Plan, i: usize) -> Option<String> {
    let (kind, k) = if i < plan.nq {
        ("position", i)
    } else {
        ("velocity", i - plan.nq)
    };
    let j = plan.joints.iter().find(|j| {
        let (off, n) = if i < plan.nq {
            (j.q_offset, j.coord.nq())
        } else {
            (j.v_offset, j.coord.nv())
        };
        (off..off + n).contains(&k)
    })?;
    let off = if i < plan.nq { j.q_offset } else { j.v_offset };
    let object = plan
        .bodies
        .get(j.body)
        .and_then(|b| b.objects.first())
        .and_then(|&o| plan.objects.get(o))
        .map(|o| o.name.clone())
        .unwrap_or_default();
    // The kind's signal that holds this component, e.g. `uj.phi2` or `ball.q[3]`.
    let at = k - off;
    let signal = j.coord.signals().iter().find_map(|s| {
        let start = match s.source {
            Source::Q(o) if i < plan.nq => o,
            Source::V(o) if i >= plan.nq => o,
            _ => return None,
        };
        (start..start + s.dim).contains(&at).then(|| match s.dim {
            1 => format!("`{}.{}`", j.name, s.name),
            _ => format!("`{}.{}[{}]`", j.name, s.name, at - start),
        })
    });
    Some(match signal {
        Some(sig) => format!("{kind} {sig} of joint `{}` (object `{object}`)", j.name),
        None => format!("{kind} {at} of joint `{}` (object `{object}`)", j.name),
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn contact(period: f64) -> SlowCause {
        SlowCause::StiffContact {
            pair: "a|b".into(),
            period,
            suggested_k_red: 0.5,
            linear_law: false,
        }
    }

    /// The stiffest contact's message names the later profile only for the paper's linear
    /// law, and the suggested `k_red` either way.
    #[test]
    fn a_stiff_linear_law_contact_names_the_later_profile() {
        let hertz = contact(1e-6).to_string();
        let SlowCause::StiffContact { pair, period, .. } = contact(1e-6) else {
            unreachable!()
        };
        let linear = SlowCause::StiffContact {
            pair,
            period,
            suggested_k_red: 0.5,
            linear_law: true,
        }
        .to_string();
        assert!(!hertz.contains("modia3d_later") && hertz.contains("k_red = 5.0e-1"));
        assert!(linear.contains("modia3d_later()") && linear.contains("k_red = 5.0e-1"));
    }

    /// A contact of period 1e-3 s cannot explain steps of 1e-10 s (seen in fuzzed scenes, where
    /// the diagnosis then suggested the k_red the run already had); one of period 1e-6 s with
    /// steps of 1e-8 s and a budget step of 1e-7 s can (50 budget steps per period would be
    /// 5e-6 s); a period that already fits the budget explains nothing either.
    #[test]
    fn a_stiff_element_is_the_cause_only_when_its_period_matches_the_steps() {
        assert_eq!(
            limiting(contact(1e-3), 1e-10, 1e-7),
            SlowCause::StepCollapse {
                stiffest_period: 1e-3
            }
        );
        assert_eq!(limiting(contact(1e-6), 1e-8, 1e-7), contact(1e-6));
        assert!(matches!(
            limiting(contact(1e-5), 1e-8, 1e-7),
            SlowCause::StepCollapse { .. }
        ));
        assert_eq!(
            limiting(SlowCause::Unknown, 1e-10, 1e-7),
            SlowCause::Unknown
        );
    }
}
