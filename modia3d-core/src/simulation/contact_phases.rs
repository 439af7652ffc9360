//! Driver: contact phases measured on the solver's steps (`results/contacts.rs` keeps the
//! book). After every IDA step with pairs in the contact set, the step `[t_a, t_b]` is
//! integrated by 5-point Gauss–Legendre quadrature on IDA's interpolating polynomial
//! (`Ida::interpolate`, i.e. `IDAGetDky`), and the maxima are sampled at the nodes and the
//! step's ends and refined by a parabola through the largest sample and its neighbours.
//! Only with `SimOptions::contact_results`; reads the solver, writes only the result's book.
//!
//! Accuracy. Within a step the contact set is fixed and the force is a smooth function of the
//! state, which IDA represents by its polynomial of order `k ≤ 5` with a local error the error
//! test keeps below the tolerances. The 5-point rule is exact for polynomials of degree 9, so
//! its own error, `h¹⁰ f⁽¹⁰⁾/…`, is far below the interpolant's; the impulse therefore carries
//! the solver's local error per step, summed over the steps of the phase — the same error the
//! velocities have, so `∫ f dt` matches the momentum change of the simulated motion to about
//! the tolerance, whatever the output grid (the grid never steers the steps). The first step
//! of a contact integrates `δ^{3/2}` from `δ = 0`, where the integrand is not smooth; IDA's
//! step there is its small restart step, and the rule's error on `t^{3/2}` over it is
//! `O(h^{5/2})` of that step's tiny contribution. A parabola through three samples spaced
//! `h/6` apart locates a smooth maximum to `O(h³)` in time, and the maximum is then evaluated
//! at that time, so its relative error is of second order in that offset.

use super::{SimErrorKind, Simulation};

/// Gauss–Legendre nodes on `[−1, 1]` (5 points).
const GL_NODES: [f64; 5] = [
    -0.906_179_845_938_664,
    -0.538_469_310_105_683,
    0.0,
    0.538_469_310_105_683,
    0.906_179_845_938_664,
];
/// Gauss–Legendre weights of [`GL_NODES`] (they sum to 2).
const GL_WEIGHTS: [f64; 5] = [
    0.236_926_885_056_189_1,
    0.478_628_670_499_366_5,
    0.568_888_888_888_888_9,
    0.478_628_670_499_366_5,
    0.236_926_885_056_189_1,
];
/// Samples per step: the start, the five nodes, the end.
pub(super) const SAMPLES: usize = 7;

/// The vertex `(t, value)` of the parabola through three samples, if it opens downwards.
fn parabola_max(t: [f64; 3], f: [f64; 3]) -> Option<(f64, f64)> {
    let [t0, t1, t2] = t;
    let [f0, f1, f2] = f;
    let d01 = (f1 - f0) / (t1 - t0);
    let d12 = (f2 - f1) / (t2 - t1);
    let a = (d12 - d01) / (t2 - t0);
    if a.is_nan() || a >= 0.0 {
        return None;
    }
    // f(t) = f1 + b (t − t1) + a (t − t1)², b the slope at t1.
    let b = d01 + a * (t1 - t0);
    let dt = -b / (2.0 * a);
    let tv = (t1 + dt).clamp(t0, t2);
    Some((tv, f1 + b * (tv - t1) + a * (tv - t1) * (tv - t1)))
}

impl Simulation {
    /// Interpolates the state at `t` \[s\] (within the last step) and updates the forces of the
    /// pairs in the contact set there.
    fn contacts_at(&mut self, t: f64) -> Result<(), SimErrorKind> {
        let mut y = std::mem::take(&mut self.y_out);
        y.resize(self.ida.y().len(), 0.0);
        let done = self.ida.interpolate(t, &mut y);
        if done.is_ok() {
            // A narrow-phase failure here shows up in the next residual anyway.
            let _ = self.ida.system_mut().update_contacts(t, &y);
        }
        self.y_out = y;
        Ok(done?)
    }

    /// The state of pair `id` (`ContactPlan::pair_id`) if it is in the contact set, at the
    /// last evaluation.
    fn active_state(&self, id: usize) -> Option<&crate::contact::PairState> {
        self.ida
            .system()
            .contact()?
            .active_pairs()
            .find(|(i, _, _)| *i == id)
            .map(|(_, _, st)| st)
    }

    /// Penetration \[m\] and normal force \[N\] of pair `id` at the last evaluation.
    fn pair_sample(&self, id: usize) -> (f64, f64) {
        self.active_state(id)
            .map_or((0.0, 0.0), |ps| (ps.response.penetration, ps.response.f_n))
    }

    /// Measures the last step `[t_a, t_b]` \[s\] into the contact phases of the pairs in the
    /// contact set (see the module header). Nothing without `contact_results` or contacts.
    pub(super) fn measure_step(&mut self, t_a: f64, t_b: f64) -> Result<(), SimErrorKind> {
        let Some(book) = self.result.phases() else {
            return Ok(());
        };
        let mut active = std::mem::take(&mut self.active_scratch);
        active.clear();
        if let Some(cs) = self.ida.system().contact() {
            active.extend(
                cs.active_pairs()
                    .map(|(id, _, _)| id)
                    .filter(|&p| book.is_open(p)),
            );
        }
        if active.is_empty() {
            self.active_scratch = active;
            return Ok(());
        }
        // Interpolation is defined on the last step only, [t_n − h_u, t_n].
        let t_a = t_a.max(t_b - self.ida.stats().last_step);
        if t_b <= t_a {
            self.active_scratch = active;
            return Ok(());
        }
        let (mid, half) = (0.5 * (t_a + t_b), 0.5 * (t_b - t_a));
        let mut times = [t_b; SAMPLES];
        times[0] = t_a;
        for (slot, x) in times.iter_mut().skip(1).zip(GL_NODES) {
            *slot = mid + half * x;
        }
        let mut samples = std::mem::take(&mut self.sample_scratch);
        samples.clear();
        samples.resize(active.len(), [(0.0, 0.0); SAMPLES]);
        // The end last, so the contact set holds the forces at IDA's current state afterwards.
        for (i, &t) in times.iter().enumerate() {
            self.contacts_at(t)?;
            // Samples 1..=5 are the quadrature nodes.
            let weight = i
                .checked_sub(1)
                .and_then(|j| GL_WEIGHTS.get(j))
                .map(|w| w * half);
            for (&p, row) in active.iter().zip(samples.iter_mut()) {
                if let Some(slot) = row.get_mut(i) {
                    *slot = self.pair_sample(p);
                }
                let r = self.active_state(p).map(|ps| ps.response);
                if let (Some(w), Some(r), Some(book)) = (weight, r, self.result.phases_mut()) {
                    book.add_impulse(p, w, r.f_n, &r.normal, &r.friction_force);
                }
            }
        }
        let mut refined = false;
        for (&p, row) in active.iter().zip(samples.iter()) {
            if let Some(book) = self.result.phases_mut() {
                for (&t, &(pen, f_n)) in times.iter().zip(row) {
                    book.sample_max(p, t, pen, f_n);
                }
            }
            // Refine each maximum that lies inside the step.
            for which in [0, 1] {
                let value = row.map(|(pen, f_n)| if which == 0 { pen } else { f_n });
                let Some(i) = value
                    .iter()
                    .enumerate()
                    .max_by(|a, b| a.1.total_cmp(b.1))
                    .map(|(i, _)| i)
                else {
                    continue;
                };
                let three = |x: &[f64; SAMPLES]| -> Option<[f64; 3]> {
                    x.get(i.checked_sub(1)?..=i + 1)?.try_into().ok()
                };
                let Some((tv, fv)) = three(&times)
                    .zip(three(&value))
                    .and_then(|(tt, ff)| parabola_max(tt, ff))
                else {
                    continue;
                };
                let best = self
                    .result
                    .phases()
                    .and_then(|b| b.maxima(p))
                    .map_or(0.0, |m| if which == 0 { m.0 } else { m.1 });
                if fv > best {
                    refined = true;
                    self.contacts_at(tv)?;
                    let (pen, f_n) = self.pair_sample(p);
                    if let Some(book) = self.result.phases_mut() {
                        book.sample_max(p, tv, pen, f_n);
                    }
                }
            }
        }
        self.sample_scratch = samples;
        self.active_scratch = active;
        if refined {
            self.contacts_at(t_b)?;
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The rule integrates polynomials up to degree 9 exactly (here t⁹ on [0, 2]: 2¹⁰/10).
    #[test]
    fn gauss_legendre_is_exact_to_degree_nine() {
        let (a, b) = (0.0, 2.0);
        let (mid, half) = (0.5 * (a + b), 0.5 * (b - a));
        let sum: f64 = GL_NODES
            .iter()
            .zip(GL_WEIGHTS)
            .map(|(x, w)| w * half * (mid + half * x).powi(9))
            .sum();
        assert!((sum - 102.4).abs() < 1e-12 * 102.4, "{sum}");
    }

    /// The vertex of an exact parabola is found exactly.
    #[test]
    fn parabola_vertex() {
        let f = |t: f64| 3.0 - 2.0 * (t - 0.37) * (t - 0.37);
        let (tv, fv) = parabola_max([0.1, 0.3, 0.6], [f(0.1), f(0.3), f(0.6)]).unwrap();
        assert!((tv - 0.37).abs() < 1e-12 && (fv - 3.0).abs() < 1e-12);
    }
}
