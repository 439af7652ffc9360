//! Bench hooks (hidden from the docs, not part of the supported API): crate-internal stages run
//! in isolation at a given state, for `examples/contact_cost.rs` and BENCHMARKS.md. They build
//! their own scratch (allocation is fine here); the timed loops call the hot-path functions
//! exactly as the residual does.

use crate::contact::{ContactError, ContactState, Mode};
use crate::dynamics::{kinematics, Workspace};
use crate::Model;
use std::hint::black_box;
use std::time::Instant;

/// Cost of the contact stage of one residual evaluation at one state (see
/// [`contact_stage_cost`]).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ContactStageCost {
    /// Pairs in the contact set at the state (the pairs continuous mode evaluates).
    pub active_pairs: usize,
    /// Of them, pairs of two moving shapes (ball–ball).
    pub moving_pairs: usize,
    /// Median wall time \[ns\] of one continuous-mode evaluation of the whole set (per pair:
    /// poses, narrow phase, contact point, relative velocity, force law, friction, wrenches
    /// added to both bodies).
    pub stage_ns: f64,
    /// Median wall time \[ns\] of the narrow-phase distance calls alone for the same pairs at
    /// the same poses.
    pub narrow_ns: f64,
}

impl ContactStageCost {
    /// `(stage − narrow) / active pairs` \[ns\]: the cost per active contact beyond the narrow
    /// phase (the difference of the two medians).
    pub fn per_pair_beyond_narrow_ns(&self) -> f64 {
        (self.stage_ns - self.narrow_ns) / self.active_pairs.max(1) as f64
    }
}

/// Number of pairs in the contact set that an event at `(t, y)` forms (`y = [q; v]` of the
/// model's layout); 0 for a scene without contacts or a state of the wrong length.
pub fn active_pairs_at(model: &Model, t: f64, y: &[f64]) -> Result<usize, ContactError> {
    Ok(stage_at(model, t, y)?.map_or(0, |(_, cs, _)| cs.active_pairs().count()))
}

/// Builds the contact set at `(t, y)` (event mode) and times `evaluations` continuous-mode
/// evaluations of it against `evaluations` rounds of only the narrow-phase calls of the same
/// pairs at the same poses, `repeats` times each, interleaved; returns the medians per
/// evaluation. `None` for a scene without contacts or a state of the wrong length.
pub fn contact_stage_cost(
    model: &Model,
    t: f64,
    y: &[f64],
    evaluations: usize,
    repeats: usize,
) -> Result<Option<ContactStageCost>, ContactError> {
    let Some((mut ws, mut cs, cp)) = stage_at(model, t, y)? else {
        return Ok(None);
    };
    let plan = &*model.plan;
    let (evaluations, repeats) = (evaluations.max(1), repeats.max(1));
    // Warm-up; also sets the poses the narrow-phase loop uses.
    cs.evaluate(plan, &cp, &mut ws, Mode::Continuous, t)?;
    let (mut stage, mut narrow) = (Vec::new(), Vec::new());
    for _ in 0..repeats {
        let start = Instant::now();
        for _ in 0..evaluations {
            cs.evaluate(plan, &cp, black_box(&mut ws), Mode::Continuous, t)?;
        }
        stage.push(start.elapsed().as_secs_f64());
        let start = Instant::now();
        for _ in 0..evaluations {
            black_box(cs.narrow_phase_only(black_box(&cp)));
        }
        narrow.push(start.elapsed().as_secs_f64());
    }
    let moving_pairs = cs
        .active_pairs()
        .filter(|(_, pp, _)| cp.shapes[pp.a].body.is_some() && cp.shapes[pp.b].body.is_some())
        .count();
    Ok(Some(ContactStageCost {
        active_pairs: cs.active_pairs().count(),
        moving_pairs,
        stage_ns: median_ns(&mut stage, evaluations),
        narrow_ns: median_ns(&mut narrow, evaluations),
    }))
}

/// Median \[ns\] per evaluation of chunk times `v` \[s\] of `evaluations` evaluations each
/// (`v` not empty).
fn median_ns(v: &mut [f64], evaluations: usize) -> f64 {
    v.sort_by(f64::total_cmp);
    1e9 * v[v.len() / 2] / evaluations as f64
}

/// Workspace at `(t, y)` (`position_velocity` done) and the contact set an event there forms.
#[allow(clippy::type_complexity)]
fn stage_at(
    model: &Model,
    t: f64,
    y: &[f64],
) -> Result<
    Option<(
        Workspace,
        ContactState,
        std::sync::Arc<crate::contact::ContactPlan>,
    )>,
    ContactError,
> {
    let plan = &*model.plan;
    let Some(cp) = model.contact.clone() else {
        return Ok(None);
    };
    if y.len() != plan.nq + plan.nv {
        return Ok(None);
    }
    let mut ws = Workspace::new(plan);
    let mut cs = ContactState::new(&cp);
    let (q, v) = y.split_at(plan.nq);
    kinematics::position_velocity(plan, &mut ws, q, v);
    cs.evaluate(plan, &cp, &mut ws, Mode::Event, t)?;
    Ok(Some((ws, cs, cp)))
}

/// Cost of one DAE residual evaluation at one state (see [`residual_cost`]).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ResidualCost {
    /// Moving bodies of the model (each on its own joint).
    pub bodies: usize,
    /// Pairs in the contact set at the state.
    pub active_pairs: usize,
    /// Median wall time \[ns\] of one residual evaluation (kinematics, the contact stage of
    /// the pairs in the contact set, forces, Newton–Euler, position and velocity residuals),
    /// what IDA calls per Newton iteration.
    pub residual_ns: f64,
    /// Median wall time \[ns\] of one evaluation of the root functions at the same state.
    pub roots_ns: f64,
}

impl ResidualCost {
    /// `residual_ns / bodies` \[ns\]: the residual's cost per body per evaluation (issue 16
    /// asks ≤ 200 ns for billiards16).
    pub fn per_body_ns(&self) -> f64 {
        self.residual_ns / self.bodies.max(1) as f64
    }
}

/// Times the model's DAE residual (and its root functions) at `(t, y)`: the contact set an
/// event there forms, `y'` consistent with `y`, then `repeats` chunks of `evaluations`
/// residual evaluations, interleaved with as many chunks of root evaluations; returns the
/// medians per evaluation. `None` for a state of the wrong length or one where no consistent
/// derivative exists (a singular mass matrix, a failing force law).
pub fn residual_cost(
    model: &Model,
    t: f64,
    y: &[f64],
    evaluations: usize,
    repeats: usize,
) -> Result<Option<ResidualCost>, ContactError> {
    use crate::dae::MultibodyDae;
    use crate::solver::DaeSystem;
    let plan = &*model.plan;
    if y.len() != plan.nq + plan.nv || !plan.loops.is_empty() {
        return Ok(None);
    }
    let mut dae = MultibodyDae::new(model.plan.clone(), model.contact.clone());
    dae.handle_event(t, y)?;
    let mut y = y.to_vec();
    let Ok(yp) = dae.consistent_derivative(t, &mut y) else {
        return Ok(None);
    };
    let mut res = vec![0.0; dae.len()];
    let mut g = vec![0.0; 2];
    let (evaluations, repeats) = (evaluations.max(1), repeats.max(1));
    // Warm-up.
    if dae.residual(t, &y, &yp, &mut res).is_err() {
        return Ok(None);
    }
    dae.roots(t, &y, &yp, &mut g);
    let (mut residual, mut roots) = (Vec::new(), Vec::new());
    for _ in 0..repeats {
        let start = Instant::now();
        for _ in 0..evaluations {
            // The result is checked once above; errors here cannot differ (same state).
            let _ = dae.residual(t, black_box(&y), black_box(&yp), black_box(&mut res));
        }
        residual.push(start.elapsed().as_secs_f64());
        let start = Instant::now();
        for _ in 0..evaluations {
            dae.roots(t, black_box(&y), black_box(&yp), black_box(&mut g));
        }
        roots.push(start.elapsed().as_secs_f64());
    }
    Ok(Some(ResidualCost {
        bodies: plan.bodies.len(),
        active_pairs: active_pairs_at(model, t, &y)?,
        residual_ns: median_ns(&mut residual, evaluations),
        roots_ns: median_ns(&mut roots, evaluations),
    }))
}

/// Index of the output point of `res` whose state has the most pairs in the contact set (the
/// first of equals; 0 when no state has any), for timing a stage where it works hardest.
pub fn busiest_output(model: &Model, res: &crate::SimulationResult) -> Result<usize, ContactError> {
    let mut best = (0, 0);
    for (k, &t) in res.time().iter().enumerate() {
        let Some(y) = res.state(k) else { break };
        let n = active_pairs_at(model, t, y)?;
        if n > best.0 {
            best = (n, k);
        }
    }
    Ok(best.1)
}

/// The timing examples' command line `[evaluations repeats]` (chunk length and number of
/// chunks), each falling back to the given default when absent or not a number.
pub fn chunk_args(evaluations: usize, repeats: usize) -> (usize, usize) {
    let args: Vec<usize> = std::env::args()
        .skip(1)
        .filter_map(|a| a.parse().ok())
        .collect();
    (
        args.first().copied().unwrap_or(evaluations),
        args.get(1).copied().unwrap_or(repeats),
    )
}

/// Wall times and last results of an A/B comparison in one process ([`alternate`]):
/// index 0 with the first options, 1 with the second.
pub struct Alternated {
    /// Wall time \[s\] of each run of each setting, in run order.
    pub walls: [Vec<f64>; 2],
    /// The last run's result of each setting.
    pub last: [crate::SimulationResult; 2],
}

/// Runs `model` `rounds` times (at least once) with each of the two `options` — the first, then
/// the second, alternately, so that a change of the machine's load hits both alike. For
/// comparisons of a switch such as [`SimOptions::analytic_jacobian`](crate::SimOptions::analytic_jacobian)
/// or [`SimOptions::dense_lu`](crate::SimOptions::dense_lu).
pub fn alternate(
    model: &Model,
    options: [&crate::SimOptions; 2],
    rounds: usize,
) -> Result<Alternated, crate::SimError> {
    let timed = |opts: &crate::SimOptions, walls: &mut Vec<f64>| {
        let t0 = Instant::now();
        let res = model.simulate(opts);
        walls.push(t0.elapsed().as_secs_f64());
        res
    };
    let mut walls = [Vec::new(), Vec::new()];
    let [w_a, w_b] = &mut walls;
    let [a, b] = options;
    let mut last = [timed(a, w_a)?, timed(b, w_b)?];
    for _ in 1..rounds {
        last = [timed(a, w_a)?, timed(b, w_b)?];
    }
    Ok(Alternated { walls, last })
}
