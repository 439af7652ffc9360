//! Driver: the checks behind `SimulationResult::warnings` ([`SimWarning`]). At the start of a
//! run: meshes repaired when the scene was built, collision solids that can never meet, unit slips (sizes and masses far from the
//! scene's others), initial penetrations deeper than the smoothing radius. After each
//! `advance_to`: chattering contacts and contact phases the output grid missed. Reads the
//! model, the initial contact set and the recorded result; allocates freely (not a hot path).

use crate::contact::initial::{median_of_others, size_outliers, slip_of_pair};
use crate::contact::ContactState;
use crate::model::Model;
use crate::results::{SimWarning, SimulationResult};
use crate::scene::SizeSlip;
use crate::scene::{colliding_objects, CollisionFilter};

/// A body this many times heavier or lighter than the median of the others.
pub(super) const MASS_RATIO: f64 = 1e6;
/// Chattering: this many contact-set changes of one pair ...
pub(super) const CHATTER_WARN_EVENTS: usize = 20;
/// ... within this fraction of the run's duration.
pub(super) const CHATTER_WARN_SPAN: f64 = 1e-3;

/// At most this many warnings are printed in full by [`report`]; the rest are counted.
pub(super) const REPORTED_WARNINGS: usize = 5;

/// The text printed to standard error for the warnings `new` a run found (see
/// `SimOptions::quiet`): a header with their number and how to silence it, then each
/// warning's full message (it names the culprit and what to check), at most
/// [`REPORTED_WARNINGS`] of them.
pub(super) fn report(new: &[SimWarning]) -> String {
    let n = new.len();
    let mut text = format!(
        "modia3d: the run found {n} warning{} (kept in `result.warnings`; `SimOptions::quiet(true)` hides this):\n",
        if n == 1 { "" } else { "s" }
    );
    for w in new.iter().take(REPORTED_WARNINGS) {
        text.push_str(&format!("  - {w}\n"));
    }
    if n > REPORTED_WARNINGS {
        text.push_str(&format!("  … and {} more\n", n - REPORTED_WARNINGS));
    }
    text
}

/// Warnings about the model and its initial state `cs` (the contact set at the start time).
pub(super) fn start_warnings(model: &Model, cs: Option<&ContactState>) -> Vec<SimWarning> {
    let mut out = never_collide(model);
    let slips = model
        .contact
        .as_deref()
        .map(|cp| size_outliers(&model.plan.scene, cp))
        .unwrap_or_default();
    out.extend(scale_outliers(model, &slips));
    out.extend(model.plan.scene.objects.iter().filter_map(|o| {
        let repair = o.solid.as_ref()?.mesh_repair.clone()?;
        Some(SimWarning::MeshRepaired {
            object: o.name.clone(),
            repair,
        })
    }));
    if let (Some(cs), Some(cp)) = (cs, model.contact.as_deref()) {
        let radius = model.plan.scene.options.smoothing_radius;
        for (_, pp, st) in cs.active_pairs() {
            let depth = -st.z;
            if depth > radius {
                let pair = cp.pair_name(&model.plan.scene, pp);
                let size_slip = slip_of_pair(&slips, &pair).cloned();
                out.push(SimWarning::InitialPenetration {
                    pair,
                    depth,
                    radius,
                    size_slip,
                });
            }
        }
    }
    out
}

/// Collision solids on bodies that a joint with `can_collide = false` keeps apart.
fn never_collide(model: &Model) -> Vec<SimWarning> {
    let scene = &model.plan.scene;
    let objects = colliding_objects(scene);
    let filter = CollisionFilter::new(scene);
    let mut out = vec![];
    for (i, &a) in objects.iter().enumerate() {
        for &b in objects.iter().skip(i + 1) {
            let Some(j) = filter.excluded_by(a, b) else {
                continue;
            };
            let name = |o: usize| scene.objects.get(o).map(|x| x.name.clone());
            if let (Some(a), Some(b), Some(joint)) = (
                name(a),
                name(b),
                scene.joints.get(j).map(|j| j.name.clone()),
            ) {
                out.push(SimWarning::NeverCollide { a, b, joint });
            }
        }
    }
    out
}

/// Moving collision solids far larger than the others (`slips`, the unit check of sizes),
/// bodies far heavier or lighter.
fn scale_outliers(model: &Model, slips: &[SizeSlip]) -> Vec<SimWarning> {
    let plan = &model.plan;
    let mut out: Vec<SimWarning> = slips
        .iter()
        .map(|slip| SimWarning::ScaleOutlier {
            object: slip.object.clone(),
            quantity: "size",
            value: slip.size,
            median: slip.median,
            ratio: slip.size / slip.median,
            unit: "m",
            what: "collision solids",
        })
        .collect();
    let masses: Vec<f64> = plan.bodies.iter().map(|b| b.inertia.mass).collect();
    for (k, b) in plan.bodies.iter().enumerate() {
        let Some(&mass) = masses.get(k) else { continue };
        let Some(m) = median_of_others(&masses, k).filter(|&m| m > 0.0) else {
            continue;
        };
        let ratio = mass / m;
        if !(1.0 / MASS_RATIO..=MASS_RATIO).contains(&ratio) {
            let object = b
                .objects
                .first()
                .and_then(|&o| plan.objects.get(o))
                .map_or_else(String::new, |o| o.name.clone());
            out.push(SimWarning::ScaleOutlier {
                object,
                quantity: "mass",
                value: mass,
                median: m,
                ratio,
                unit: "kg",
                what: "bodies",
            });
        }
    }
    out
}

/// Warnings about the run recorded in `result` so far: chattering pairs and contact phases
/// with no output point inside (unless every step is an output point).
pub(super) fn run_warnings(
    result: &SimulationResult,
    span: f64,
    interval: f64,
    output_steps: bool,
) -> Vec<SimWarning> {
    let mut out = vec![];
    let time = result.time();
    // Only a pair that started or ended contact at an event can chatter or miss a phase: its
    // changes in event order, gathered in one pass over the events. The pairs are taken in
    // the order of `contact_pairs()` (by shape indices), without making all N²/2 names of it
    // (at 1024 balls 524,800 names: 33 MB of heap and ~6 s at the end of every `advance_to`,
    // BENCHMARKS.md "Peak memory at 1024 balls"); names that are not
    // candidate pairs of the result's model are skipped, as that list never held them.
    let mut of_pair: std::collections::HashMap<&str, Vec<(f64, bool)>> =
        std::collections::HashMap::new();
    for e in &result.events {
        for p in &e.started {
            of_pair.entry(p).or_default().push((e.t, true));
        }
        for p in &e.ended {
            of_pair.entry(p).or_default().push((e.t, false));
        }
    }
    let lookup = result.pair_lookup();
    let mut pairs: Vec<_> = of_pair
        .into_iter()
        .filter_map(|(p, changes)| Some((lookup(p)?, p, changes)))
        .collect();
    pairs.sort_by_key(|pair| pair.0);
    for (_, pair, changes) in pairs {
        let pair = pair.to_string();
        // Chattering: CHATTER_WARN_EVENTS changes within CHATTER_WARN_SPAN of the run.
        let window = CHATTER_WARN_EVENTS.saturating_sub(1);
        if let Some((first, last)) = changes
            .iter()
            .zip(changes.iter().skip(window))
            .find(|(a, b)| b.0 - a.0 <= CHATTER_WARN_SPAN * span)
        {
            out.push(SimWarning::Chattering {
                pair: pair.clone(),
                events: CHATTER_WARN_EVENTS,
                span: last.0 - first.0,
                t: first.0,
            });
        }
        if output_steps {
            continue;
        }
        // Phases with no output point strictly inside (start, end).
        let mut start = None;
        let (mut missed, mut shortest) = (0, f64::INFINITY);
        for &(t, started) in &changes {
            match (started, start) {
                (true, _) => start = Some(t),
                (false, Some(t0)) => {
                    let k = time.partition_point(|&x| x <= t0);
                    if time.get(k).is_none_or(|&x| x >= t) {
                        missed += 1;
                        shortest = shortest.min(t - t0);
                    }
                    start = None;
                }
                (false, None) => {}
            }
        }
        if missed > 0 {
            out.push(SimWarning::MissedContacts {
                pair,
                phases: missed,
                shortest,
                interval,
            });
        }
    }
    out
}

#[cfg(test)]
// In tests an out-of-range index is a failure report like any assertion.
#[allow(clippy::indexing_slicing)]
mod tests {
    use super::*;
    use crate::results::Event;

    /// Eight steel balls on a steel table (`dae/alloc_tests.rs`); the pair used here is
    /// `ball0|table`.
    fn ball_and_table() -> Model {
        crate::dae::alloc_tests::balls_on_a_table().build().unwrap()
    }

    fn event(t: f64, started: bool, pair: &str) -> Event {
        let (s, e) = if started {
            (vec![pair.to_string()], vec![])
        } else {
            (vec![], vec![pair.to_string()])
        };
        Event {
            t,
            description: String::new(),
            started: s,
            ended: e,
        }
    }

    /// A record over 1 s with output points every 0.1 s (and at the events): ten contacts of
    /// 1e-5 s each, 2e-5 s apart, from t = 0.5 s (20 changes within 2e-4 s < 1e-3 of the run:
    /// chattering; all between two grid points: 10 missed phases, the shortest 1e-5 s), then
    /// one contact from 0.75 to 0.85 s that contains the grid point 0.8 (not missed).
    #[test]
    fn chattering_and_missed_phases() {
        let model = ball_and_table();
        let n = model.plan.nq + model.plan.nv;
        let y = vec![0.0; n];
        let mut res = SimulationResult::new(model);
        let mut times: Vec<f64> = (0..=10).map(|k| 0.1 * k as f64).collect();
        for i in 0..10 {
            let t0 = 0.5 + 2e-5 * i as f64 + 1e-6;
            res.events.push(event(t0, true, "ball0|table"));
            res.events.push(event(t0 + 1e-5, false, "ball0|table"));
            times.extend([t0, t0 + 1e-5]);
        }
        res.events.push(event(0.75, true, "ball0|table"));
        res.events.push(event(0.85, false, "ball0|table"));
        times.extend([0.75, 0.85]);
        times.sort_by(f64::total_cmp);
        for t in times {
            res.push(t, &y);
        }
        let w = run_warnings(&res, 1.0, 0.1, false);
        assert_eq!(w.len(), 2, "{w:?}");
        match w.first().unwrap() {
            SimWarning::Chattering {
                pair, events, span, ..
            } => {
                assert_eq!((pair.as_str(), *events), ("ball0|table", 20));
                assert!((span - (19.0 * 1e-5)).abs() < 1e-12, "{span}");
            }
            other => panic!("{other:?}"),
        }
        match w.get(1).unwrap() {
            SimWarning::MissedContacts {
                pair,
                phases,
                shortest,
                ..
            } => {
                assert_eq!((pair.as_str(), *phases), ("ball0|table", 10));
                assert!((shortest - 1e-5).abs() < 1e-12);
            }
            other => panic!("{other:?}"),
        }
        // Every step an output point: nothing missed, the chattering stays.
        let w = run_warnings(&res, 1.0, 0.1, true);
        assert_eq!(w.len(), 1);
    }

    /// The warnings come in the order of `contact_pairs()` whatever the order of the pairs'
    /// events, and a name that `contact_pairs()` does not hold (the reversed order, an unknown
    /// object) gets none: what scanning that whole list gave, which the warnings did before
    /// they were gathered from the events.
    #[test]
    fn warnings_in_candidate_pair_order() {
        let model = ball_and_table();
        let n = model.plan.nq + model.plan.nv;
        let mut res = SimulationResult::new(model);
        let names = res.contact_pairs();
        let find = |ball: &str| {
            names
                .iter()
                .position(|p| p.split('|').any(|o| o == ball))
                .unwrap()
        };
        let (i2, i5) = (find("ball2"), find("ball5"));
        assert!(i2 < i5);
        let (p2, p5) = (names[i2].clone(), names[i5].clone());
        let (a, b) = p2.split_once('|').unwrap();
        let reversed = format!("{b}|{a}");
        // 20 changes within 2e-4 s each (< 1e-3 of the 1 s run): every pair chatters.
        for (k, pair) in [p5.as_str(), p2.as_str(), &reversed, "nobody|table"]
            .into_iter()
            .enumerate()
        {
            for i in 0..10 {
                let t0 = 0.1 + 0.2 * k as f64 + 2e-5 * i as f64;
                res.events.push(event(t0, true, pair));
                res.events.push(event(t0 + 1e-5, false, pair));
            }
        }
        for k in 0..=10 {
            res.push(0.1 * k as f64, &vec![0.0; n]);
        }
        let w = run_warnings(&res, 1.0, 0.1, true);
        let pairs: Vec<&str> = w
            .iter()
            .map(|w| match w {
                SimWarning::Chattering { pair, .. } => pair.as_str(),
                other => panic!("{other:?}"),
            })
            .collect();
        assert_eq!(pairs, [p2.as_str(), p5.as_str()]);
    }
}
