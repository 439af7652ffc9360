//! Results stage: [`SimWarning`], what a run found suspicious without failing. The driver's
//! checks (`simulation/warnings.rs`) fill `SimulationResult::warnings` and trace each warning.

/// Something a run found suspicious but not wrong enough to stop: each names its culprit and
/// says what to check. Also traced with `tracing::warn!` when found.
#[derive(thiserror::Error, Clone, Debug, PartialEq)]
pub enum SimWarning {
    /// A colliding pair starts deeper inside each other than the smoothing radius (deeper than
    /// half the thinner shape's extent is already a build error,
    /// `SceneError::InitialPenetration`).
    #[error("`{pair}` starts {depth:.3e} m deep inside each other (more than the smoothing radius {radius:.1e} m): the contact pushes them apart with a large force at t = 0; {}", match .size_slip { Some(s) => format!("likely cause: {s}"), None => "check the initial positions and the units (mm vs m)".into() })]
    InitialPenetration {
        /// The pair `"a|b"`.
        pair: String,
        /// Penetration depth \[m\].
        depth: f64,
        /// The scene's smoothing radius \[m\].
        radius: f64,
        /// One of the two far larger than the scene's other collision solids (the unit check
        /// of sizes, also a [`SimWarning::ScaleOutlier`]): the likely cause.
        size_slip: Option<crate::scene::SizeSlip>,
    },
    /// A collision solid far larger or smaller than the scene's others (often a length in mm
    /// where m was meant), or a body far heavier or lighter than the others.
    #[error("`{object}`: {quantity} {value:.3e} {unit} is {ratio:.0e} times the median {median:.3e} {unit} of the scene's other {what}; check its units (a diameter of 100 meant as 100 mm is 0.1 m)")]
    ScaleOutlier {
        /// The object (for a body: its first object).
        object: String,
        /// `"size"` (largest extent of a collision solid) or `"mass"` (of a body).
        quantity: &'static str,
        /// Its value \[m\] or \[kg\].
        value: f64,
        /// The median of the others \[m\] or \[kg\].
        median: f64,
        /// `value / median`.
        ratio: f64,
        /// Unit of `value`.
        unit: &'static str,
        /// What it was compared with ("collision solids", "bodies").
        what: &'static str,
    },
    /// Two collision solids that can never touch: a joint between their bodies has
    /// `can_collide = false`, so they have no collision pair.
    #[error("collision solids `{a}` and `{b}` can never touch: joint `{joint}` between their bodies has can_collide = false; set `can_collide(true)` on it if they should collide")]
    NeverCollide {
        /// First solid.
        a: String,
        /// Second solid.
        b: String,
        /// The joint that excludes the pair.
        joint: String,
    },
    /// A pair entered and left the contact set many times within a short time (below the
    /// chattering guard that stops the run).
    #[error("contact `{pair}` chatters: {events} starts and ends within {span:.3e} s from t = {t:.6} s; check its initial overlap, cor and v_min, or lower k_red")]
    Chattering {
        /// The pair `"a|b"`.
        pair: String,
        /// Number of its events in the window.
        events: usize,
        /// Their time span \[s\].
        span: f64,
        /// Time of the first of them \[s\].
        t: f64,
    },
    /// IDA's error test failed repeatedly (`IDA_ERR_FAIL`) while the error test of the bodies
    /// in contact was tightened ([`SimOptions::contact_tightening`](crate::SimOptions::contact_tightening)):
    /// the run went on from the last step with the factor divided by 10 (1 = off) for the rest
    /// of the run (segment). Found in random scenes: at rtol 1.4e-9 the tightened tolerance
    /// ~5e-12 was below what the contact forces' rounding allows, and the step fell to 2e-14 s.
    #[error("at t = {t:.6e} s the error test failed repeatedly with the error test of bodies in contact {from:.3e} times tighter than rtol; the run goes on with {to:.3e} (SimOptions::contact_tightening): loosen rtol, or set contact_tightening lower, to avoid this")]
    ContactTighteningRelaxed {
        /// Time of the failure (the last step reached) \[s\].
        t: f64,
        /// The tightening factor that failed [-].
        from: f64,
        /// The factor used from then on [-] (1 = off).
        to: f64,
    },
    /// Contact phases that began and ended between two output points: the signals never show
    /// them.
    #[error("{phases} contact phase(s) of `{pair}` fell between output points (the shortest {shortest:.3e} s, output interval {interval:.3e} s): the signals do not show them; use `SimOptions::output_steps(true)` or read `result.contacts()` (with `contact_results(true)`)")]
    MissedContacts {
        /// The pair `"a|b"`.
        pair: String,
        /// Number of phases with no output point inside.
        phases: usize,
        /// Duration of the shortest \[s\].
        shortest: f64,
        /// The output interval \[s\].
        interval: f64,
    },
    /// A solid's mesh was repaired for its mass properties when the scene was built
    /// (`geometry::repair_mesh`: coincident vertices merged, small holes closed): the message
    /// says what was repaired and how much it changed the volume.
    #[error("solid `{object}`: {repair}; if the change matters, repair the file or give the mass properties explicitly")]
    MeshRepaired {
        /// The solid.
        object: String,
        /// What was repaired, with the volumes before and after \[m³\].
        repair: crate::geometry::MeshRepair,
    },
}

impl SimWarning {
    /// A one-line summary (the culprit and the number that matters; the `Display` message
    /// adds what to check), as [`SimulationResult::summary`](super::SimulationResult::summary)
    /// lists it. Lengths in m, masses in kg, times in s.
    pub fn headline(&self) -> String {
        match self {
            SimWarning::InitialPenetration { pair, depth, .. } => {
                format!("`{pair}` starts {depth:.3e} m deep inside each other")
            }
            SimWarning::ScaleOutlier {
                object,
                quantity,
                value,
                ratio,
                unit,
                ..
            } => format!(
                "`{object}`: {quantity} {value:.3e} {unit}, {ratio:.0e} times the median (units?)"
            ),
            SimWarning::NeverCollide { a, b, joint } => {
                format!("`{a}` and `{b}` can never touch (joint `{joint}` has can_collide = false)")
            }
            SimWarning::Chattering {
                pair, events, t, ..
            } => format!("contact `{pair}` chatters: {events} events from t = {t:.6} s"),
            SimWarning::ContactTighteningRelaxed { t, from, to } => {
                format!("contact tightening relaxed from {from:.3e} to {to:.3e} at t = {t:.6e} s")
            }
            SimWarning::MissedContacts { pair, phases, .. } => {
                format!("{phases} contact phase(s) of `{pair}` fell between output points")
            }
            SimWarning::MeshRepaired { object, repair } => format!(
                "`{object}`: mesh repaired ({} vertices merged, {} hole(s) closed), volume {:+.3} %",
                repair.merged_vertices,
                repair.holes,
                100.0 * repair.relative_volume_change()
            ),
        }
    }
}
