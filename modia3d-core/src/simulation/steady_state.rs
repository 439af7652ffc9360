//! Steady-state initialisation of the components (`SimOptions::steady_state`): the
//! components' states `x` and the positions `q_k` of the coordinates their flanges drive are
//! solved for `ẋ = 0` and `v̇_k = 0` with `v_k = 0` — as many equations as unknowns — by
//! Newton's method on the consistent derivatives, with a difference-quotient Jacobian and
//! step halving. A servo then starts holding its load: its PI's state carries the gravity
//! torque, an elastic gear's deflection the spring's share. Not the hot path.
// Every index here is one of the plan's own layout of `y` (driven coordinates, component
// states, `0..n` of the unknowns), none comes from user input: the driver's rule against
// indexing (a user's value never panics) has nothing to guard.
#![allow(clippy::indexing_slicing)]

use super::SimErrorKind;
use crate::dae::MultibodyDae;
use nalgebra::{DMatrix, DVector};

/// Largest rate left at a steady state (relative to 1: rad/s², m/s², a state's unit per s).
const TOLERANCE: f64 = 1e-9;
/// How far a driven coordinate may move to its steady state [rad or m]: an elastic gear's
/// deflection under its load, not a swing to another equilibrium (a servo whose controller
/// cannot hold the load has one only where the load hangs, which is not a start a user asked
/// for).
const REACH: f64 = 0.05;
const MAX_ITERATIONS: usize = 50;

/// Solves for the steady state at `t` \[s\], changing `y` in place.
pub(super) fn solve(dae: &mut MultibodyDae, t: f64, y: &mut [f64]) -> Result<(), SimErrorKind> {
    let plan = dae.plan().clone();
    let cp = &plan.components;
    let (nq, xo) = (plan.nq, plan.x_offset());
    // The driven coordinates: (index in q, index in v).
    let mut driven: Vec<(usize, usize)> = cp.flange_coordinates().collect();
    driven.sort_unstable();
    driven.dedup();
    let mut unknowns: Vec<usize> = driven.iter().map(|&(q, _)| q).collect();
    unknowns.extend(xo..xo + cp.nx);
    let equations: Vec<usize> = driven
        .iter()
        .map(|&(_, v)| nq + v)
        .chain(xo..xo + cp.nx)
        .collect();
    let coordinate = |qi: usize| super::unknown_name(&plan, qi);
    let names: Vec<String> = driven
        .iter()
        .map(|&(q, _)| format!("the acceleration of {}", coordinate(q)))
        .chain(cp.state_names().map(|n| format!("d{n}/dt")))
        .collect();
    if unknowns.is_empty() {
        return Ok(());
    }
    for &(_, v) in &driven {
        y[nq + v] = 0.0;
    }
    let nominal: Vec<f64> = driven
        .iter()
        .map(|_| 1.0)
        .chain(cp.x_nominal.iter().copied())
        .collect();
    let rates = |dae: &mut MultibodyDae, y: &mut [f64]| -> Result<DVector<f64>, SimErrorKind> {
        let yp = dae
            .consistent_derivative(t, y)
            .map_err(|e| super::derivative_error(e, t))?;
        Ok(DVector::from_iterator(
            equations.len(),
            equations.iter().map(|&i| yp[i]),
        ))
    };
    let norm = |f: &DVector<f64>| f.iter().fold(0.0f64, |m, v| m.max(v.abs()));
    let start: Vec<f64> = unknowns.iter().map(|&u| y[u]).collect();
    let mut f = rates(dae, y)?;
    let n = unknowns.len();
    let mut iterations = 0;
    while norm(&f) > TOLERANCE && iterations < MAX_ITERATIONS {
        iterations += 1;
        let mut jac = DMatrix::zeros(n, n);
        for (j, &u) in unknowns.iter().enumerate() {
            let h = 1e-7 * y[u].abs().max(nominal[j]);
            let keep = y[u];
            y[u] = keep + h;
            let fj = rates(dae, y);
            y[u] = keep;
            let fj = fj?;
            jac.set_column(j, &((fj - &f) / h));
        }
        let Some(step) = jac.lu().solve(&(-&f)) else {
            break;
        };
        // Step halving: accept the first fraction that lowers the largest rate; a coordinate
        // moves at most `REACH` per step.
        let base: Vec<f64> = unknowns.iter().map(|&u| y[u]).collect();
        let q_step = (0..driven.len()).fold(0.0f64, |m, k| m.max(step[k].abs()));
        let mut lambda = if q_step > REACH { REACH / q_step } else { 1.0 };
        let mut accepted = false;
        for _ in 0..12 {
            for (k, &u) in unknowns.iter().enumerate() {
                y[u] = base[k] + lambda * step[k];
            }
            match rates(dae, y) {
                Ok(fn_) if norm(&fn_) < norm(&f) => {
                    f = fn_;
                    accepted = true;
                    break;
                }
                Ok(_) | Err(SimErrorKind::Inconsistent { .. }) => lambda *= 0.5,
                Err(e) => return Err(e),
            }
        }
        if !accepted {
            for (k, &u) in unknowns.iter().enumerate() {
                y[u] = base[k];
            }
            break;
        }
    }
    let r = norm(&f);
    if let Some(k) = (0..driven.len()).find(|&k| (y[unknowns[k]] - start[k]).abs() > REACH) {
        return Err(SimErrorKind::SteadyState {
            t,
            residual: r,
            worst: format!(
                "{}, whose steady state lies {:.3e} from its initial position, farther than {REACH}: the components cannot hold the load near it",
                coordinate(driven[k].0),
                y[unknowns[k]] - start[k]
            ),
            iterations,
        });
    }
    if r > TOLERANCE {
        let worst = f
            .iter()
            .enumerate()
            .max_by(|a, b| a.1.abs().total_cmp(&b.1.abs()))
            .map_or(0, |(i, _)| i);
        return Err(SimErrorKind::SteadyState {
            t,
            residual: r,
            worst: names.get(worst).cloned().unwrap_or_default(),
            iterations,
        });
    }
    // The contact set at the steady state's positions.
    dae.handle_event(t, y)?;
    Ok(())
}
