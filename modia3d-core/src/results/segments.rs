//! Results of a segmented run (structure changes by actions: attach, release, delete; see
//! `simulation/segments.rs`): one [`SimulationResult`] over all segments.
//!
//! Each finished segment is kept as a single-segment result of its own model (its states have
//! that model's layout); the result's own fields hold the current segment, and the run's time
//! axis is kept whole beside them. A signal is each segment's signal, concatenated in time:
//! an object's motion (`r_abs`, `v_abs`, `R_abs`, `w_abs`) continues across segments (the
//! action keeps poses exactly and velocities up to the plastic impulse of an attach). In a
//! segment where the signal's owner does not exist (the FreeMotion joint of an attached object,
//! a deleted object, a contact pair of a deleted or attached solid) its values are NaN, so every
//! signal has one value per output point of the run. At an action's time the run has two output
//! points, the last of the old segment and the first of the new one; `signal_at` there gives
//! the new segment's value (as at an event). A name unknown in every segment is an error.

use super::contacts::PhaseBook;
use super::{ResultError, Signal, SimulationResult};
use crate::model::Model;

/// The finished segments of a run and its whole time axis.
#[derive(Clone, Debug, Default)]
pub(crate) struct Segments {
    /// Finished segments in time order, each a single-segment result of its model.
    done: Vec<SimulationResult>,
    /// Every output time of the run \[s\], all segments.
    pub(super) time: Vec<f64>,
}

impl SimulationResult {
    /// Ends the current segment at the last output point and starts one of `model`: the
    /// statistics, events and warnings go on; contact phases still open are closed at `t` \[s\]
    /// (a pair still touching opens a new phase in the new segment's initial contact set).
    pub(crate) fn begin_segment(&mut self, model: Model, t: f64) {
        let mut old = std::mem::replace(self, SimulationResult::new(model));
        self.stats = old.stats;
        self.events.clone_from(&old.events);
        self.warnings.clone_from(&old.warnings);
        let mut segs = old.segments.take().map(|s| *s).unwrap_or_else(|| Segments {
            done: vec![],
            time: old.time.clone(),
        });
        if old.contacts.is_some() || old.phases.is_some() || old.phases_off {
            self.enable_contact_record(!old.phases_off);
        }
        if let Some(book) = old.phases.as_mut() {
            for ph in book.phases.iter_mut().filter(|ph| ph.end.is_none()) {
                ph.end = Some(t);
            }
            let n = self.model.contact.as_ref().map_or(0, |c| c.n_pairs);
            let mut carried = PhaseBook::new(n);
            carried.phases.clone_from(&book.phases);
            self.phases = Some(carried);
        }
        segs.done.push(old);
        self.segments = Some(Box::new(segs));
    }

    /// Number of segments (1 for a run without structure changes).
    pub fn segment_count(&self) -> usize {
        self.segments.as_ref().map_or(1, |s| s.done.len() + 1)
    }

    /// Every segment, in time order: the finished ones, then the current one (self's fields).
    fn segment_list(&self) -> Vec<&SimulationResult> {
        let mut all: Vec<&SimulationResult> = match &self.segments {
            Some(s) => s.done.iter().collect(),
            None => vec![],
        };
        all.push(self);
        all
    }

    /// The segment holding output point `k` of the run and `k`'s index within it.
    pub(super) fn segment_of(&self, k: usize) -> Option<(&SimulationResult, usize)> {
        let mut k = k;
        for seg in self.segment_list() {
            let n = seg.time.len();
            if k < n {
                return Some((seg, k));
            }
            k -= n;
        }
        None
    }

    /// [`Self::signal`] of a segmented run: each segment's signal, NaN where its owner is
    /// missing (see the module docs).
    pub(super) fn segmented_signal(&self, name: &str) -> Result<Signal, ResultError> {
        let parts: Vec<_> = self
            .segment_list()
            .into_iter()
            .map(|seg| (seg.time.len(), seg.signal_one(name)))
            .collect();
        let Some(model) = parts.iter().find_map(|(_, p)| p.as_ref().ok()) else {
            // Unknown everywhere: the current segment's error (with its hint).
            return self.signal_one(name);
        };
        let (unit, dim) = (model.unit, model.dim);
        let mut data = Vec::with_capacity(dim * self.time().len());
        for (n, part) in &parts {
            match part {
                Ok(s) => data.extend_from_slice(&s.data),
                Err(ResultError::ContactResultsOff { what }) => {
                    return Err(ResultError::ContactResultsOff { what: what.clone() })
                }
                Err(_) => data.extend(std::iter::repeat_n(f64::NAN, n * dim)),
            }
        }
        Ok(Signal {
            name: name.to_string(),
            unit,
            dim,
            data,
        })
    }

    /// [`Self::signal_at`] of a segmented run: the last segment whose time span holds `t`
    /// answers; NaN if the signal's owner does not exist there.
    pub(super) fn segmented_signal_at(&self, name: &str, t: f64) -> Result<Vec<f64>, ResultError> {
        let dim = self.segmented_signal(name)?.dim;
        let seg = self.segment_list().into_iter().rev().find(
            |s| matches!((s.time.first(), s.time.last()), (Some(&a), Some(&b)) if a <= t && t <= b),
        );
        let Some(seg) = seg else {
            let time = self.time();
            return Err(ResultError::OutOfRange {
                name: name.into(),
                t,
                start: time.first().copied().unwrap_or(f64::NAN),
                end: time.last().copied().unwrap_or(f64::NAN),
            });
        };
        Ok(seg
            .signal_at_one(name, t)
            .unwrap_or_else(|_| vec![f64::NAN; dim]))
    }

    /// [`Self::signal_names`] of a segmented run: every segment's names, first appearance first.
    pub(super) fn segmented_signal_names(&self) -> Vec<String> {
        let mut names: Vec<String> = vec![];
        for seg in self.segment_list() {
            for n in seg.signal_names_one() {
                if !names.contains(&n) {
                    names.push(n);
                }
            }
        }
        names
    }
}
