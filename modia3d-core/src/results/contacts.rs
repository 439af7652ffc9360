//! Results stage: contact phases of the collision pairs — one [`ContactPhase`] per stretch of
//! time a pair spends in the contact set, from the event where it enters to the event where it
//! leaves, with its impact and exit speeds, maxima and impulses. The driver feeds the book
//! (`simulation/contact_phases.rs`: events, and the solver's steps by Gauss–Legendre
//! quadrature on IDA's interpolating polynomial); this module only keeps the sums.

use nalgebra::Vector3;

/// One contact phase of a pair `"a|b"`: from the event where the pair entered the contact set
/// to the event where it left (or the end of the run).
///
/// Sign convention (as the contact signals): the normal points from `a` (the first name) to `b`
/// (the second), forces and impulses are those acting **on `b`**, resolved in world; `a`
/// receives the opposite. The penetration velocity `δ̇ = −(v_b − v_a)·n` at the contact point is
/// positive while the two approach.
///
/// The impulses and maxima come from the solver's steps, not from the output grid: every IDA
/// step during the phase is integrated by 5-point Gauss–Legendre quadrature over IDA's own
/// interpolating polynomial, and the maxima are refined by a parabola through the samples
/// around the largest one, so a contact shorter than the output interval is measured as
/// accurately as the solver resolves it (see `simulation/contact_phases.rs` for the error
/// argument).
#[derive(Clone, Debug, PartialEq)]
pub struct ContactPhase {
    /// The pair `"a|b"` (as in [`SimulationResult::contact_pairs`](super::SimulationResult::contact_pairs)).
    pub pair: String,
    /// Time the pair entered the contact set \[s\] (the shapes touch; the start of the run for a
    /// pair in contact initially).
    pub start: f64,
    /// Time it left \[s\] (separated by twice the hysteresis ε); `None` if still in contact at
    /// the end of the run.
    pub end: Option<f64>,
    /// Impact speed `δ̇⁻` [m/s]: penetration velocity at the start (> 0 approaching).
    pub impact_speed: f64,
    /// Exit speed [m/s]: separation speed `−δ̇⁺` at the end (> 0 separating); `None` while in
    /// contact.
    pub exit_speed: Option<f64>,
    /// Largest penetration depth `δ` during the phase \[m\].
    pub max_penetration: f64,
    /// Largest normal force magnitude `f_n` during the phase \[N\].
    pub max_normal_force: f64,
    /// Time of the largest normal force \[s\].
    pub t_max_normal_force: f64,
    /// Normal impulse `∫ f_n dt` over the phase [N·s] (magnitude along the normal; ≥ 0).
    pub normal_impulse: f64,
    /// Tangential (friction) impulse `∫ f_t dt` on `b`, resolved in world [N·s].
    pub tangential_impulse: Vector3<f64>,
    /// Total impulse of the contact force (normal + friction) on `b`, resolved in world [N·s].
    pub impulse: Vector3<f64>,
}

/// Largest exit / impact speed of a phase that [`ContactPhase::restitution`] counts as an
/// impact \[1\] (see there).
const MAX_IMPACT_RESTITUTION: f64 = 1.01;

/// Smallest `max_penetration / (impact_speed · duration)` of a phase that
/// [`ContactPhase::restitution`] counts as an impact \[1\] (see there).
const MIN_IMPACT_PENETRATION: f64 = 0.005;

impl ContactPhase {
    /// Duration \[s\] (`None` while in contact).
    pub fn duration(&self) -> Option<f64> {
        self.end.map(|e| e - self.start)
    }

    /// Effective coefficient of restitution of an impact: exit speed / impact speed \[1\].
    /// `None` unless the phase is an impact, which here means all of:
    /// - it ended (`exit_speed` is known) with the bodies approaching at the start and
    ///   separating at the end (both speeds > 0);
    /// - the exit speed is at most 1.01 times the impact speed: a collision of two bodies
    ///   returns at most the normal motion it took (1 % allows for gravity and the solver's
    ///   error in an elastic impact, which measured 1 + 1e-5, `tests/contact_phases.rs`); a
    ///   faster exit means something else pushed them apart (a block tipping over a table's
    ///   edge left at 7.33 times the speed it touched down with, issue 44);
    /// - the largest penetration \[m\] is at least 0.005 times `impact_speed · duration`
    ///   ([m/s]·\[s\]): in an impact the contact force stops and reverses the approach within
    ///   the phase (steel ball on a steel table, `tests/user_messages.rs`: δ_max = 0.30 · v·T at
    ///   cor 0.8, 0.15 at 0.3, 0.06 at 0.1, 0.012 at 0.02, where the heavy damping draws out
    ///   the rebound), whereas a phase that rests, rolls or slides for long before it ends has
    ///   a penetration far below its impact speed times its duration (a block sliding 0.2 s on
    ///   a table before it tips off the edge: 0.0036), and its exit speed has nothing to do
    ///   with the impact.
    ///
    /// Why from these fields and not from the pair's `v_min`: they are what the phase
    /// measured, and an impact below `v_min` (where the regularised cor applies) is still an
    /// impact whose effective restitution this reports.
    pub fn restitution(&self) -> Option<f64> {
        let exit = self.exit_speed?;
        let (v, duration) = (self.impact_speed, self.duration()?);
        let impact = v > 0.0
            && exit > 0.0
            && exit <= MAX_IMPACT_RESTITUTION * v
            && self.max_penetration >= MIN_IMPACT_PENETRATION * v * duration;
        impact.then(|| exit / v)
    }

    /// The same phase seen from the pair in the other order, `"b|a"`: impulses on `a` (the
    /// sign of the vectors flips; speeds, maxima and the normal impulse's magnitude stay).
    pub(crate) fn reversed(&self, name: &str) -> ContactPhase {
        ContactPhase {
            pair: name.to_string(),
            tangential_impulse: -self.tangential_impulse,
            impulse: -self.impulse,
            ..self.clone()
        }
    }
}

/// The phases of a run and the open phase of each pair.
#[derive(Clone, Debug, Default)]
pub(crate) struct PhaseBook {
    /// Phases in the order they started.
    pub phases: Vec<ContactPhase>,
    /// `open[p]`: index into `phases` of pair `p`'s current phase.
    open: Vec<Option<usize>>,
}

impl PhaseBook {
    /// A book for `pairs` candidate pairs.
    pub(crate) fn new(pairs: usize) -> Self {
        PhaseBook {
            phases: vec![],
            open: vec![None; pairs],
        }
    }

    /// Room for pairs (and stops) `0..n`.
    pub(crate) fn grow(&mut self, n: usize) {
        if self.open.len() < n {
            self.open.resize(n, None);
        }
    }

    /// True if pair `p` has an open phase.
    pub(crate) fn is_open(&self, p: usize) -> bool {
        matches!(self.open.get(p), Some(Some(_)))
    }

    fn open_phase(&mut self, p: usize) -> Option<&mut ContactPhase> {
        let k = (*self.open.get(p)?)?;
        self.phases.get_mut(k)
    }

    /// Opens and closes phases after an event at `t` \[s\] (or at the start of the run) from the
    /// `started`/`ended` lists (ids, each with its penetration speed: of a contact set's pairs,
    /// or of the joint limits' stops) offset by `base`; `name(p)` gives pair `p`'s name.
    pub(crate) fn event(
        &mut self,
        t: f64,
        (started, started_speed): (&[u32], &[f64]),
        (ended, ended_speed): (&[u32], &[f64]),
        base: usize,
        name: impl Fn(usize) -> String,
    ) {
        for (&p, &dd) in ended.iter().zip(ended_speed) {
            let p = base + p as usize;
            let exit = -dd;
            if let Some(ph) = self.open_phase(p) {
                ph.end = Some(t);
                ph.exit_speed = Some(exit);
            }
            if let Some(o) = self.open.get_mut(p) {
                *o = None;
            }
        }
        for (&p, &impact) in started.iter().zip(started_speed) {
            let p = base + p as usize;
            if let Some(o) = self.open.get_mut(p) {
                *o = Some(self.phases.len());
                self.phases.push(ContactPhase {
                    pair: name(p),
                    start: t,
                    end: None,
                    impact_speed: impact,
                    exit_speed: None,
                    max_penetration: 0.0,
                    max_normal_force: 0.0,
                    t_max_normal_force: t,
                    normal_impulse: 0.0,
                    tangential_impulse: Vector3::zeros(),
                    impulse: Vector3::zeros(),
                });
            }
        }
    }

    /// Adds `weight` \[s\] times pair `p`'s forces `(f_n, f_t)` (on `b`, world) to its impulses.
    pub(crate) fn add_impulse(
        &mut self,
        p: usize,
        weight: f64,
        f_n: f64,
        normal: &Vector3<f64>,
        f_t: &Vector3<f64>,
    ) {
        if let Some(ph) = self.open_phase(p) {
            ph.normal_impulse += weight * f_n;
            ph.tangential_impulse += weight * f_t;
            ph.impulse += weight * (normal * f_n + f_t);
        }
    }

    /// Pair `p`'s maxima so far: (penetration \[m\], normal force \[N\]).
    pub(crate) fn maxima(&self, p: usize) -> Option<(f64, f64)> {
        let k = (*self.open.get(p)?)?;
        self.phases
            .get(k)
            .map(|ph| (ph.max_penetration, ph.max_normal_force))
    }

    /// Takes a sample of pair `p` at `t` \[s\] into its maxima.
    pub(crate) fn sample_max(&mut self, p: usize, t: f64, penetration: f64, f_n: f64) {
        if let Some(ph) = self.open_phase(p) {
            ph.max_penetration = ph.max_penetration.max(penetration);
            if f_n > ph.max_normal_force {
                ph.max_normal_force = f_n;
                ph.t_max_normal_force = t;
            }
        }
    }
}

/// The vertex `(t, value)` of the parabola through three samples, if it opens downwards: the
/// refinement of a maximum sampled at discrete times (contact phases, joint load peaks).
pub(crate) fn parabola_max(t: [f64; 3], f: [f64; 3]) -> Option<(f64, f64)> {
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

#[cfg(test)]
mod tests {
    use super::parabola_max;

    /// The vertex of an exact parabola is found exactly.
    #[test]
    fn parabola_vertex() {
        let f = |t: f64| 3.0 - 2.0 * (t - 0.37) * (t - 0.37);
        let (tv, fv) = parabola_max([0.1, 0.3, 0.6], [f(0.1), f(0.3), f(0.6)]).unwrap();
        assert!((tv - 0.37).abs() < 1e-12 && (fv - 3.0).abs() < 1e-12);
    }
}
