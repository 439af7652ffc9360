//! Running a [`SceneSpec`] and classifying its outcome: `ok`, `build:<SceneError kind>`,
//! `sim:<SimErrorKind>` (solver errors with their IDA flag), `panic`, `nonfinite` (a NaN or
//! infinite value in any result signal, of a finished or a failed run), `overbudget` (a run
//! that ended without a typed error later than twice its `max_wall_time`). `abort` and `hang`
//! are given by the batch driver when a worker process dies or stops answering.

use super::{build, InputSpec, SceneSpec};
use modia3d::prelude::*;
use std::panic::{catch_unwind, AssertUnwindSafe};
use std::time::Instant;

/// The outcome of one scene.
#[derive(Clone, Debug, PartialEq)]
pub struct Outcome {
    /// Outcome class (see the module documentation).
    pub class: String,
    /// The error message, the non-finite signal, or an ok run's warnings, for reports.
    pub detail: String,
    /// Wall time of build + run \[s\].
    pub wall: f64,
}

/// Classes that fail the batch.
pub fn is_failure(class: &str) -> bool {
    matches!(
        class,
        "panic" | "abort" | "hang" | "nonfinite" | "overbudget"
    )
}

/// The variant name of a `Debug` form (`"InitialPenetration { .. }"` → `"InitialPenetration"`).
fn variant(debug: &str) -> String {
    debug
        .split(|c: char| !c.is_alphanumeric() && c != '_')
        .next()
        .unwrap_or("")
        .to_string()
}

/// The class of a simulation error.
pub fn sim_class(kind: &SimErrorKind) -> String {
    match kind {
        SimErrorKind::Solver(modia3d::core::IdaError::Flag { name, .. }) => {
            format!("sim:Solver:{name}")
        }
        // Classed by IDA's flag as before the diagnosis, so batches stay comparable.
        SimErrorKind::SolverStalled { error, .. } => match &**error {
            modia3d::core::IdaError::Flag { name, .. } => format!("sim:Solver:{name}"),
            e => format!("sim:Solver:{}", variant(&format!("{e:?}"))),
        },
        SimErrorKind::Solver(e) => format!("sim:Solver:{}", variant(&format!("{e:?}"))),
        k => format!("sim:{}", variant(&format!("{k:?}"))),
    }
}

/// The first signal of `r` with a non-finite value (time included), if any.
pub fn non_finite(r: &SimulationResult) -> Option<String> {
    if let Some(t) = r.time().iter().find(|t| !t.is_finite()) {
        return Some(format!("time {t}"));
    }
    let mut names = r.signal_names();
    names.extend(
        r.contact_pairs()
            .iter()
            .flat_map(|p| ["penetration", "f_n", "normal", "point"].map(|s| format!("{p}.{s}"))),
    );
    for n in names {
        if let Ok(s) = r.signal(&n) {
            if let Some(v) = s.data.iter().find(|v| !v.is_finite()) {
                return Some(format!("signal `{n}` = {v}"));
            }
        }
    }
    None
}

fn finish(res: Result<SimulationResult, SimError>) -> (String, String) {
    let (class, detail, result) = match res {
        // An ok run's detail: its warnings (for `detail_contains` in `tests/regressions/`).
        Ok(r) => {
            let warnings: Vec<String> = r.warnings.iter().map(|w| w.to_string()).collect();
            ("ok".to_string(), warnings.join("; "), r)
        }
        Err(e) => (sim_class(&e.kind), e.kind.to_string(), *e.partial),
    };
    match non_finite(&result) {
        Some(what) => ("nonfinite".into(), format!("{what} ({class}: {detail})")),
        None => (class, detail),
    }
}

/// The step-wise API: set the inputs, advance, repeat; the result is the recorded one.
fn stepwise(model: &Model, s: &SceneSpec, opts: &SimOptions) -> Result<SimulationResult, SimError> {
    let mut sim = Simulation::new(model, opts)?;
    for step in s.run.steps.as_deref().unwrap_or_default() {
        for (i, values) in &step.inputs {
            if let Err(e) = sim.set_input(&format!("i{i}"), values) {
                panic!("the generator set an invalid input: {e}");
            }
        }
        sim.advance_to(step.t)?;
    }
    Ok(sim.into_result())
}

/// Builds and runs `s` (panics are caught and classified).
pub fn run_scene(s: &SceneSpec) -> Outcome {
    let started = Instant::now();
    let attempt = catch_unwind(AssertUnwindSafe(|| {
        let model = match build::scene(s).build() {
            Ok(m) => m,
            Err(e) => {
                let first = e.0.first().map(|x| variant(&format!("{x:?}")));
                return (
                    format!("build:{}", first.unwrap_or_default()),
                    e.to_string(),
                );
            }
        };
        let opts = build::options(s);
        let res = if s.run.steps.is_some() {
            stepwise(&model, s, &opts)
        } else {
            model.simulate(&opts)
        };
        finish(res)
    }));
    let wall = started.elapsed().as_secs_f64();
    let (class, detail) = match attempt {
        Ok((class, detail)) => {
            let typed_error = class.starts_with("build:") || class.starts_with("sim:");
            if !typed_error && wall > 2.0 * s.run.max_wall_time {
                ("overbudget".into(), format!("{class} after {wall:.2} s"))
            } else {
                (class, detail)
            }
        }
        Err(payload) => {
            let msg = payload
                .downcast_ref::<String>()
                .cloned()
                .or_else(|| payload.downcast_ref::<&str>().map(|s| s.to_string()))
                .unwrap_or_default();
            ("panic".into(), msg)
        }
    };
    Outcome {
        class,
        detail,
        wall,
    }
}

/// Whether the inputs of `s` are used by its steps (for the minimiser).
pub fn uses_inputs(s: &SceneSpec) -> bool {
    !s.inputs.is_empty() && s.run.steps.is_some()
}

/// Removes body `k` and everything that refers to it (children, forces, inputs); indices
/// above `k` shift down by one.
pub fn without_body(s: &SceneSpec, k: usize) -> Option<SceneSpec> {
    if s.bodies.iter().any(|b| b.parent == Some(k)) {
        return None; // remove the children first
    }
    let mut t = s.clone();
    t.bodies.remove(k);
    let shift = |i: usize| if i > k { i - 1 } else { i };
    for b in &mut t.bodies {
        b.parent = b.parent.map(shift);
    }
    use super::ForceSpec as F;
    t.forces.retain(|f| match f {
        F::Spring { a, b, .. } => *b != k && *a != Some(k),
        F::JointSpring { body, .. } | F::Constant { body, .. } | F::Drag { body, .. } => *body != k,
    });
    for f in &mut t.forces {
        match f {
            F::Spring { a, b, .. } => {
                *a = a.map(shift);
                *b = shift(*b);
            }
            F::JointSpring { body, .. } | F::Constant { body, .. } | F::Drag { body, .. } => {
                *body = shift(*body)
            }
        }
    }
    let body_of = |i: &InputSpec| match i {
        InputSpec::JointForce(b) | InputSpec::JointAcceleration(b) | InputSpec::Wrench(b) => *b,
    };
    if t.inputs.iter().any(|i| body_of(i) == k) {
        return None; // inputs are removed as a whole (below)
    }
    for i in &mut t.inputs {
        match i {
            InputSpec::JointForce(b) | InputSpec::JointAcceleration(b) | InputSpec::Wrench(b) => {
                *b = shift(*b)
            }
        }
    }
    Some(t)
}

/// Greedy minimisation: the smallest variant of `s` (fewer bodies, forces, inputs, steps,
/// table, pairs) that `same` still accepts.
pub fn minimise(s: &SceneSpec, same: &dyn Fn(&SceneSpec) -> bool) -> SceneSpec {
    let mut best = s.clone();
    loop {
        let mut candidates = vec![];
        for k in (0..best.bodies.len()).rev() {
            candidates.extend(without_body(&best, k));
        }
        for i in 0..best.forces.len() {
            let mut t = best.clone();
            t.forces.remove(i);
            candidates.push(t);
        }
        if best.run.steps.is_some() {
            let mut t = best.clone();
            t.run.steps = None;
            t.inputs.clear();
            candidates.push(t);
        }
        if best.table.is_some() {
            let mut t = best.clone();
            t.table = None;
            candidates.push(t);
        }
        if best.run.contact_results || best.run.interval.is_some() {
            let mut t = best.clone();
            t.run.contact_results = false;
            t.run.interval = None;
            candidates.push(t);
        }
        match candidates.into_iter().find(|c| same(c)) {
            Some(c) => best = c,
            None => return best,
        }
    }
}
