//! Contact preload at the start (`SimOptions::preload_contacts`, docs/contact-model.md §3.2):
//! bodies a scene places resting on one another under the volume law start pressed in by
//! their static load instead of at zero depth.
//!
//! A block set on a table at zero depth is, for the compliant law, a block dropped from zero
//! height: it sinks to the depth whose force carries it (~1e-8 m for a wooden cube) and rings
//! about it at the contact's frequency until the damping has taken the ringing out, ~1 ms. The
//! rigid body the user meant has no such transient, and resolving it was most of the steps of
//! a run of bodies at rest: 45 of the 56 IDA steps of a stack of three wooden cubes resting
//! for 0.5 s at rtol 1e-2, which takes 11 from the preloaded start (BENCHMARKS.md, "Face
//! contacts").
//!
//! What is solved: for every pair of the initial contact set under the volume law whose
//! bodies are at rest along its normal (`|δ̇⁻| ≤` [`REST_SPEED`]), the normal component of the
//! relative acceleration of its bodies at its contact point is zero — the acceleration a
//! rigid contact would leave, so the force the pair starts with is the one a rigid contact
//! carries there (the weight on a stack, `m g cos α` on an incline, the reaction at a pivoting
//! edge). The unknowns are the translations of the free joints (`FreeMotion`) of the pairs'
//! bodies: rotations, velocities and every other joint keep their given values. There are
//! usually more unknowns than equations (three translations per body, one equation per
//! pair), and the step taken is the smallest that solves the linearised equations
//! (Gauss–Newton with the pseudo-inverse), so a body moves only along the normals of its
//! pairs. The Jacobian is formed once by central differences of
//! `MultibodyDae::consistent_derivative` and then updated by Broyden's rank-one formula from
//! each step taken (a new difference Jacobian only when a step fails); each step is halved
//! until the residual falls, since the law is not smooth at zero depth, where a pair starts
//! (an edge's force grows with the square of its depth: its derivative there is zero). A
//! stack of three cubes takes 23 derivative evaluations, a cube on its edge 16. Not the hot
//! path.
//!
//! When there is nothing to solve, or the solution is not found within [`MAX_ITERATIONS`] or
//! lies farther than [`REACH`] from the given positions (the bodies were not placed resting),
//! the run starts from the given positions, as with `preload_contacts(false)`. Pairs with a
//! sphere keep the paper's law and its start unchanged.
// Every index here is one of the plan's own layout of `y` (free joints' translations, `0..n`
// of the unknowns and pairs), none comes from user input: the driver's rule against indexing
// (a user's value never panics) has nothing to guard.
#![allow(clippy::indexing_slicing)]

use crate::contact::RestingPair;
use crate::dae::MultibodyDae;
use nalgebra::{DMatrix, DVector};

/// Largest penetration speed at a pair's start \[m/s\] that counts as placed at rest along
/// its normal: a body set down (any faster is an impact, whose start the law's damping
/// handles).
const REST_SPEED: f64 = 1e-6;
/// The normal accelerations left, relative to the largest at the given positions \[-\]: the
/// ringing left is this fraction of the static depth.
const TOLERANCE: f64 = 1e-8;
/// Largest move of a translation from its given value \[m\]: a static depth (micrometres for
/// wood and steel, far less than this for any solid of the material table), not a body
/// placed deep in another.
const REACH: f64 = 1e-3;
/// Largest change of a translation in one Newton step \[m\].
const STEP_CAP: f64 = 1e-4;
const MAX_ITERATIONS: usize = 30;
const MAX_HALVINGS: usize = 40;
/// Largest number of unknowns (64 free bodies): a pile larger than this settles by
/// integration as without the preload (a difference Jacobian costs two derivative
/// evaluations per unknown).
const MAX_UNKNOWNS: usize = 192;

/// Preloads the resting volume-law pairs of the contact set at `t` \[s\], changing the
/// translations in `y` in place; returns whether it moved them (then the caller rebuilds the
/// contact set at the new positions). Without a solution `y` is left as given, and so is it
/// when a derivative fails: at the given `y` the caller's own evaluation then reports it.
pub(super) fn solve(dae: &mut MultibodyDae, t: f64, y: &mut [f64]) -> bool {
    let pairs = dae.resting_volume_pairs(REST_SPEED);
    if pairs.is_empty() {
        return false;
    }
    let plan = dae.plan();
    let (nq, nv) = (plan.nq, plan.nv);
    // The translations of the free joints of the pairs' bodies; pairs none of whose bodies
    // has one are left out (nothing here can move them).
    let translation = |b: crate::dynamics::BodyId| {
        plan.joints
            .iter()
            .find(|j| j.body == b && j.coord.free_velocities().is_some())
            .map(|j| j.q_offset)
    };
    let mut unknowns: Vec<usize> = vec![];
    let pairs: Vec<RestingPair> = pairs
        .into_iter()
        .filter(|p| {
            let mut any = false;
            for q in p.bodies.iter().flatten().filter_map(|&b| translation(b)) {
                unknowns.extend(q..q + 3);
                any = true;
            }
            any
        })
        .collect();
    unknowns.sort_unstable();
    unknowns.dedup();
    if unknowns.is_empty() || unknowns.len() > MAX_UNKNOWNS {
        return false;
    }
    let start: Vec<f64> = unknowns.iter().map(|&u| y[u]).collect();
    let mut buf = Vec::with_capacity(pairs.len());
    let mut accelerations = |dae: &mut MultibodyDae, y: &mut [f64]| -> Option<DVector<f64>> {
        let yp = dae.consistent_derivative(t, y).ok()?;
        dae.normal_accelerations(&y[..nq], &yp[nq..nq + nv], &pairs, &mut buf);
        buf.iter()
            .all(|a| a.is_finite())
            .then(|| DVector::from_column_slice(&buf))
    };
    // Writes `x` into the unknowns of `y`.
    let put = |y: &mut [f64], x: &[f64]| {
        for (&u, &v) in unknowns.iter().zip(x) {
            y[u] = v;
        }
    };
    let Some(mut f) = accelerations(dae, y) else {
        put(y, &start);
        return false;
    };
    if f.amax() == 0.0 {
        return false;
    }
    let tol = TOLERANCE * f.amax();
    let mut solved = false;
    // The Jacobian by central differences, then Broyden's rank-one updates from each step
    // taken (one evaluation per iteration instead of `2n + 1`); a new difference Jacobian
    // when a step from an updated one does not lower the residual.
    let mut jac = DMatrix::zeros(f.len(), unknowns.len());
    let mut stale = true;
    for _ in 0..MAX_ITERATIONS {
        let fresh = stale;
        if stale && !difference_jacobian(dae, y, &unknowns, &mut accelerations, &mut jac) {
            break;
        }
        stale = false;
        // The smallest step that solves the linearised equations.
        let svd = jac.clone().svd(true, true);
        let cutoff = 1e-12 * svd.singular_values.max();
        let Ok(mut step) = svd.solve(&(-&f), cutoff) else {
            break;
        };
        let longest = step.amax();
        if !longest.is_finite() || longest == 0.0 {
            break;
        }
        if longest > STEP_CAP {
            step *= STEP_CAP / longest;
        }
        let base: Vec<f64> = unknowns.iter().map(|&u| y[u]).collect();
        let mut lambda = 1.0;
        let mut next = None;
        let mut trial = base.clone();
        for _ in 0..MAX_HALVINGS {
            for ((x, b), s) in trial.iter_mut().zip(&base).zip(step.iter()) {
                *x = b + lambda * s;
            }
            put(y, &trial);
            match accelerations(dae, y) {
                Some(g) if g.norm() < f.norm() => {
                    next = Some(g);
                    break;
                }
                _ => lambda *= 0.5,
            }
        }
        let Some(g) = next else {
            put(y, &base);
            if fresh {
                break;
            }
            stale = true;
            continue;
        };
        // Broyden: J += (Δf − J s) sᵀ / (sᵀ s) for the step s taken.
        let s_taken = step * lambda;
        let change = &g - &f - &jac * &s_taken;
        jac += change * s_taken.transpose() / s_taken.norm_squared();
        f = g;
        solved = f.amax() <= tol;
        if solved {
            break;
        }
    }
    let near = unknowns
        .iter()
        .zip(&start)
        .all(|(&u, &s)| (y[u] - s).abs() <= REACH);
    if !(solved && near) {
        put(y, &start);
        return false;
    }
    true
}

/// The Jacobian of `f` (the normal accelerations) with respect to the `unknowns` of `y` by
/// central differences, into `jac`; false if an evaluation fails.
fn difference_jacobian(
    dae: &mut MultibodyDae,
    y: &mut [f64],
    unknowns: &[usize],
    f: &mut impl FnMut(&mut MultibodyDae, &mut [f64]) -> Option<DVector<f64>>,
    jac: &mut DMatrix<f64>,
) -> bool {
    for (j, &u) in unknowns.iter().enumerate() {
        let keep = y[u];
        // ~1e-11 m: far below a static depth, far above the rounding of the overlap.
        let h = 1e-11 + 1e-13 * keep.abs();
        y[u] = keep + h;
        let plus = f(dae, y);
        y[u] = keep - h;
        let minus = f(dae, y);
        y[u] = keep;
        let (Some(plus), Some(minus)) = (plus, minus) else {
            return false;
        };
        jac.set_column(j, &((plus - minus) / (2.0 * h)));
    }
    true
}
