//! Driver: contact phases measured on the solver's steps (`results/contacts.rs` keeps the
//! book). After every IDA step with pairs in the contact set, the step `[t_a, t_b]` is
//! integrated by 4-point Gauss–Lobatto quadrature on IDA's interpolating polynomial
//! (`Ida::interpolate`, i.e. `IDAGetDky`), and the maxima are sampled at the nodes (the step's
//! ends among them) and refined by a parabola through the largest sample and its neighbours.
//! Only with `SimOptions::contact_results`; reads the solver, writes only the result's book.
//!
//! Accuracy. Within a step the contact set is fixed and the force is a smooth function of the
//! state, which IDA represents by its polynomial of order `k ≤ 5` with a local error the error
//! test keeps below the tolerances. The 4-point Lobatto rule is exact for polynomials of degree
//! 5, IDA's highest order: a force linear in the state is integrated exactly on the
//! interpolant, and otherwise the rule's own error, `h⁷ f⁽⁶⁾/1.5e6`, is ~1e-5 of the error the
//! interpolant's `h^{k+1}` term puts into the impulse. The impulse therefore carries the
//! solver's local error per step, summed over the steps of the phase — the same error the
//! velocities have, so `∫ f dt` matches the momentum change of the simulated motion to about
//! the tolerance, whatever the output grid (the grid never steers the steps). The first step
//! of a contact integrates `δ^{3/2}` from `δ = 0`, where the integrand is not smooth; IDA's
//! step there is its small restart step, and the rule's error on `t^{3/2}` over it is
//! `O(h^{5/2})` of that step's tiny contribution. A parabola through three samples locates a
//! smooth maximum to `O(s³)` in time (`s` the samples' spacing, ≤ 0.55 h), and the maximum is
//! then evaluated at that time, so its relative error is of second order in that offset.
//!
//! Cost. The rule's nodes include both ends, and IDA's polynomial on a step passes through the
//! state the step started from, so the start sample is the previous step's end sample, kept
//! unless an event or a restart came between: a step costs three contact evaluations (two
//! nodes and the end, which is evaluated last so that the contact set holds the forces at
//! IDA's state afterwards), plus one per refined maximum. The 5-point Gauss–Legendre rule this
//! replaces took seven, and on random scenes that record contact results and end at their
//! work budget the measurement was the larger part of the run (BENCHMARKS.md).

use super::{SimErrorKind, Simulation};
use crate::results::parabola_max;
use nalgebra::Vector3;

/// Gauss–Lobatto nodes on `[−1, 1]` (4 points: the ends and `±1/√5`).
const NODES: [f64; SAMPLES] = [-1.0, -0.447_213_595_499_958, 0.447_213_595_499_958, 1.0];
/// Gauss–Lobatto weights of [`NODES`] (1/6, 5/6, 5/6, 1/6: they sum to 2).
const WEIGHTS: [f64; SAMPLES] = [1.0 / 6.0, 5.0 / 6.0, 5.0 / 6.0, 1.0 / 6.0];
/// Samples per step: the nodes.
pub(super) const SAMPLES: usize = 4;

/// One pair at one time: what the quadrature and the maxima need.
#[derive(Clone, Copy, Debug, Default)]
pub(super) struct Sample {
    /// Penetration \[m\].
    pen: f64,
    /// Normal force magnitude \[N\].
    f_n: f64,
    /// Unit normal, body 1 → body 2, resolved in world.
    normal: Vector3<f64>,
    /// Sliding friction force on body 2 \[N\], resolved in world.
    f_t: Vector3<f64>,
}

/// Scratch of `measure_step`, kept between steps (no allocation once grown).
#[derive(Debug)]
pub(super) struct PhaseScratch {
    /// The pairs measured on this step (pair ids).
    active: Vec<usize>,
    /// Samples per measured pair and node.
    samples: Vec<[Sample; SAMPLES]>,
    /// The end samples of the last measured step, per pair id, valid at `end_t`.
    end: Vec<(usize, Sample)>,
    /// Time \[s\] of `end`; NaN when an event or a restart came after it.
    end_t: f64,
}

impl Default for PhaseScratch {
    fn default() -> Self {
        PhaseScratch {
            active: Vec::new(),
            samples: Vec::new(),
            end: Vec::new(),
            end_t: f64::NAN,
        }
    }
}

impl PhaseScratch {
    /// Forgets the last end samples (after an event or a restart, whose state or contact set
    /// need not be the one they were taken in).
    pub(super) fn forget(&mut self) {
        self.end_t = f64::NAN;
    }
}

/// The three of `pts` (sorted by time) and `v` around the largest value: it and its
/// neighbours in time, or the three nearest it when it is the first or the last.
fn bracket(pts: [(f64, f64); 3], v: (f64, f64)) -> [(f64, f64); 3] {
    let mut all = [pts[0], pts[1], pts[2], v];
    all.sort_by(|a, b| a.0.total_cmp(&b.0));
    let best = all
        .iter()
        .enumerate()
        .max_by(|a, b| a.1 .1.total_cmp(&b.1 .1))
        .map_or(1, |(i, _)| i);
    let [p0, p1, p2, p3] = all;
    if best <= 1 {
        [p0, p1, p2]
    } else {
        [p1, p2, p3]
    }
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

    /// Samples of the pairs `active` (pair ids, in the contact set) at the last evaluation,
    /// written to `column` of `rows` (zero for a pair no longer in the set).
    fn take_samples(&self, active: &[usize], rows: &mut [[Sample; SAMPLES]], column: usize) {
        for row in rows.iter_mut() {
            if let Some(slot) = row.get_mut(column) {
                *slot = Sample::default();
            }
        }
        // Stops of joint limits (ids after the pairs', listed after them).
        if let Some((_, ls)) = self.ida.system().limits() {
            let base = self.stop_base();
            for (&id, row) in active.iter().zip(rows.iter_mut()) {
                let sample = id.checked_sub(base).and_then(|s| ls.sample(s));
                if let (Some((pen, f_n)), Some(slot)) = (sample, row.get_mut(column)) {
                    *slot = Sample {
                        pen,
                        f_n,
                        normal: Vector3::zeros(),
                        f_t: Vector3::zeros(),
                    };
                }
            }
        }
        let Some(cs) = self.ida.system().contact() else {
            return;
        };
        // `active` lists a subsequence of the set in its order (the set does not change within
        // a step), so one walk pairs them up.
        let mut i = 0;
        for (id, _, st) in cs.active_pairs() {
            if active.get(i) != Some(&id) {
                continue;
            }
            i += 1;
            if let Some(slot) = rows.get_mut(i - 1).and_then(|r| r.get_mut(column)) {
                let r = &st.response;
                *slot = Sample {
                    pen: r.penetration,
                    f_n: r.f_n,
                    normal: r.normal,
                    f_t: r.friction_force,
                };
            }
        }
    }

    /// The id of the joint limits' first stop in the phase book (after the pairs').
    fn stop_base(&self) -> usize {
        self.ida.system().contact_plan().map_or(0, |cp| cp.n_pairs)
    }

    /// Penetration \[m\] and normal force \[N\] of pair `id` at the last evaluation.
    fn pair_sample(&self, id: usize) -> (f64, f64) {
        if let (Some(s), Some((_, ls))) =
            (id.checked_sub(self.stop_base()), self.ida.system().limits())
        {
            return ls.sample(s).unwrap_or((0.0, 0.0));
        }
        self.ida
            .system()
            .contact()
            .and_then(|cs| cs.active_pairs().find(|(i, _, _)| *i == id))
            .map_or((0.0, 0.0), |(_, _, ps)| {
                (ps.response.penetration, ps.response.f_n)
            })
    }

    /// Measures the last step `[t_a, t_b]` \[s\] into the contact phases of the pairs in the
    /// contact set (see the module header). Nothing without `contact_results` or contacts.
    pub(super) fn measure_step(&mut self, t_a: f64, t_b: f64) -> Result<(), SimErrorKind> {
        let Some(book) = self.result.phases() else {
            return Ok(());
        };
        let mut sc = std::mem::take(&mut self.phase_scratch);
        sc.active.clear();
        if let Some(cs) = self.ida.system().contact() {
            sc.active.extend(
                cs.active_pairs()
                    .map(|(id, _, _)| id)
                    .filter(|&p| book.is_open(p)),
            );
        }
        if let Some((_, ls)) = self.ida.system().limits() {
            let base = self.stop_base();
            sc.active
                .extend(ls.active().map(|s| base + s).filter(|&p| book.is_open(p)));
        }
        // Interpolation is defined on the last step only, [t_n − h_u, t_n].
        let t_a = t_a.max(t_b - self.ida.stats().last_step);
        if sc.active.is_empty() || t_b <= t_a {
            sc.forget();
            self.phase_scratch = sc;
            return Ok(());
        }
        let (mid, half) = (0.5 * (t_a + t_b), 0.5 * (t_b - t_a));
        let mut times = [t_b; SAMPLES];
        for (slot, x) in times.iter_mut().zip(NODES) {
            *slot = mid + half * x;
        }
        times[0] = t_a;
        sc.samples.clear();
        sc.samples
            .resize(sc.active.len(), [Sample::default(); SAMPLES]);
        // The start sample: the last step's end if it was taken at t_a for every pair.
        let mut kept = sc.end_t == t_a;
        if kept {
            for (&p, row) in sc.active.iter().zip(sc.samples.iter_mut()) {
                match sc.end.iter().find(|(q, _)| *q == p) {
                    Some((_, s)) => row[0] = *s,
                    None => kept = false,
                }
            }
        }
        // The end last, so the contact set holds the forces at IDA's current state afterwards.
        for (i, &t) in times.iter().enumerate() {
            if i == 0 && kept {
                continue;
            }
            self.contacts_at(t)?;
            self.take_samples(&sc.active, &mut sc.samples, i);
        }
        if let Some(book) = self.result.phases_mut() {
            for (&p, row) in sc.active.iter().zip(sc.samples.iter()) {
                for ((s, &w), &t) in row.iter().zip(&WEIGHTS).zip(&times) {
                    book.add_impulse(p, w * half, s.f_n, &s.normal, &s.f_t);
                    book.sample_max(p, t, s.pen, s.f_n);
                }
            }
        }
        sc.end.clear();
        sc.end.extend(
            sc.active
                .iter()
                .zip(&sc.samples)
                .map(|(&p, row)| (p, row[SAMPLES - 1])),
        );
        sc.end_t = t_b;
        let mut refined = false;
        for (&p, row) in sc.active.iter().zip(sc.samples.iter()) {
            // Refine each maximum that lies inside the step.
            for which in [0, 1] {
                let value = row.map(|s| if which == 0 { s.pen } else { s.f_n });
                let Some(i) = value
                    .iter()
                    .enumerate()
                    .max_by(|a, b| a.1.total_cmp(b.1))
                    .map(|(i, _)| i)
                else {
                    continue;
                };
                // The three samples around the largest (at an end: the three nearest it, as the
                // maximum may lie between the end and its neighbour).
                let c = i.clamp(1, SAMPLES - 2);
                let three = |x: &[f64; SAMPLES]| -> Option<[f64; 3]> {
                    x.get(c - 1..=c + 1)?.try_into().ok()
                };
                let Some((tt, ff)) = three(&times).zip(three(&value)) else {
                    continue;
                };
                let Some((tv, fv)) = parabola_max(tt, ff) else {
                    continue;
                };
                let best = self
                    .result
                    .phases()
                    .and_then(|b| b.maxima(p))
                    .map_or(0.0, |m| if which == 0 { m.0 } else { m.1 });
                if fv > best && !times.contains(&tv) {
                    refined = true;
                    // Successive parabolic interpolation (the samples lie up to 0.55 h apart):
                    // the vertex, then the vertex of the parabola through the largest of the
                    // four points and its neighbours.
                    let mut pts = [(tt[0], ff[0]), (tt[1], ff[1]), (tt[2], ff[2])];
                    let mut tv = tv;
                    for _ in 0..2 {
                        self.contacts_at(tv)?;
                        let (pen, f_n) = self.pair_sample(p);
                        if let Some(book) = self.result.phases_mut() {
                            book.sample_max(p, tv, pen, f_n);
                        }
                        pts = bracket(pts, (tv, if which == 0 { pen } else { f_n }));
                        match parabola_max(pts.map(|q| q.0), pts.map(|q| q.1)) {
                            Some((t_next, _)) if !pts.iter().any(|q| q.0 == t_next) => tv = t_next,
                            _ => break,
                        }
                    }
                }
            }
        }
        self.phase_scratch = sc;
        if refined {
            self.contacts_at(t_b)?;
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The rule integrates polynomials up to degree 5 exactly (here t⁵ on [0, 2]: 2⁶/6) and
    /// not degree 6 (exact minus rule is `−(b − a)⁷ f⁽⁶⁾/1,512,000`: −2⁷·720/1.512e6 on t⁶).
    #[test]
    fn gauss_lobatto_is_exact_to_degree_five() {
        let (a, b) = (0.0, 2.0);
        let (mid, half) = (0.5 * (a + b), 0.5 * (b - a));
        let rule = |k: i32| -> f64 {
            NODES
                .iter()
                .zip(WEIGHTS)
                .map(|(x, w)| w * half * (mid + half * x).powi(k))
                .sum()
        };
        for k in 0..=5 {
            let exact = 2f64.powi(k + 1) / f64::from(k + 1);
            assert!((rule(k) - exact).abs() < 1e-14 * exact, "degree {k}");
        }
        let err = 2f64.powi(7) / 7.0 - rule(6);
        assert!((err + 128.0 * 720.0 / 1_512_000.0).abs() < 1e-12, "{err}");
    }
}
