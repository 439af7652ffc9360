//! Results stage, plot axes: ticks at whole multiples of a 1-2-5 step (so a tick meant as 0 is
//! exactly 0, not an accumulated `-2.22e-16`) and one label format per axis (plain decimals
//! with as many decimals as the step needs, or scientific notation for the whole axis), chosen
//! from the axis' ticks and step. Used by the signal plots and the sweep plots.

use plotters::coord::ranged1d::{
    KeyPointHint, KeyPointWeight, NoDefaultFormatting, Ranged, ValueFormatter,
};
use plotters::coord::types::RangedCoordf64;
use std::ops::Range;

/// Labelled ticks on a y axis: at most this many.
pub(crate) const Y_TICKS: usize = 8;
/// Labelled ticks on a time axis (the long side): at most this many.
pub(crate) const X_TICKS: usize = 11;

/// Largest number of ticks `ticks` ever returns (a guard for degenerate ranges).
const TICK_LIMIT: usize = 1000;

/// The smallest step `m · 10^e` (`m` ∈ {1, 2, 5}) that puts at most `max` of its whole
/// multiples in `lo..=hi`, as `(m, e)`; `None` for an empty or non-finite range or `max` 0.
fn nice_step(lo: f64, hi: f64, max: usize) -> Option<(f64, i32)> {
    let span = hi - lo;
    if !(span.is_finite() && span > 0.0 && lo.is_finite() && hi.is_finite()) || max == 0 {
        return None;
    }
    // 10^e0 ≤ span / max: a step below that gives more than max ticks.
    let e0 = (span / max as f64).log10().floor() as i32;
    (e0 - 1..=e0 + 2)
        .flat_map(|e| [1.0, 2.0, 5.0].map(|m| (m, e)))
        .find(|&(m, e)| count(lo, hi, m * 10f64.powi(e)) <= max)
}

/// The range of whole multiples `k` of `step` in `lo..=hi` (with a relative slack of 1e-9 of
/// a step at both ends), as `(first, last)`.
fn multiples(lo: f64, hi: f64, step: f64) -> (f64, f64) {
    ((lo / step - 1e-9).ceil(), (hi / step + 1e-9).floor())
}

/// How many whole multiples of `step` lie in `lo..=hi`.
fn count(lo: f64, hi: f64, step: f64) -> usize {
    let (a, b) = multiples(lo, hi, step);
    if b >= a {
        (b - a + 1.0).min(usize::MAX as f64) as usize
    } else {
        0
    }
}

/// The whole multiples `k · step` in `lo..=hi` (each computed as one product: no accumulated
/// rounding), at most [`TICK_LIMIT`].
fn ticks(lo: f64, hi: f64, step: f64) -> Vec<f64> {
    let (a, b) = multiples(lo, hi, step);
    let mut out = vec![];
    let mut k = a;
    while k <= b && out.len() < TICK_LIMIT {
        out.push(k * step);
        k += 1.0;
    }
    out
}

/// Notation of an axis' tick labels.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Notation {
    /// `0.0015`, `80000`.
    Plain,
    /// `1.5e-7`, `1.6e5`.
    Scientific,
}

/// One label format for all ticks of an axis.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct TickFormat {
    notation: Notation,
    /// Digits after the decimal point (of the mantissa in scientific notation); `None`: the
    /// shortest form with at most 4 significant digits (logarithmic axes).
    decimals: Option<usize>,
    /// A tick within this of zero is labelled `0`.
    zero: f64,
}

/// Plain decimals are used for ticks from 1e-3 to 1e5 in magnitude.
fn plain_range(magnitude: f64) -> bool {
    (1e-3..1e5).contains(&magnitude)
}

impl TickFormat {
    /// The format of a linear axis with ticks at the multiples of `m · 10^e` up to `magnitude`
    /// (the largest |tick|): plain decimals when the ticks are from 1e-3 to 1e5 in magnitude
    /// and need at most 6 decimals, otherwise scientific notation, in both with the decimals
    /// the step needs. A tick within 1e-6 of a step of zero reads `0`.
    fn linear(magnitude: f64, (m, e): (f64, i32)) -> Self {
        let zero = 1e-6 * m * 10f64.powi(e);
        let plain_decimals = (-e).max(0) as usize;
        if plain_range(magnitude) && plain_decimals <= 6 {
            return TickFormat {
                notation: Notation::Plain,
                decimals: Some(plain_decimals),
                zero,
            };
        }
        let top = if magnitude > 0.0 {
            magnitude.log10().floor() as i32
        } else {
            e
        };
        TickFormat {
            notation: Notation::Scientific,
            decimals: Some((top - e).max(0) as usize),
            zero,
        }
    }

    /// The format of a logarithmic axis over `lo..hi` (both > 0): plain when the whole range is
    /// from 1e-3 to 1e5, otherwise scientific; each label the shortest with at most 4
    /// significant digits.
    pub(crate) fn log(lo: f64, hi: f64) -> Self {
        TickFormat {
            notation: if plain_range(lo) && plain_range(hi) {
                Notation::Plain
            } else {
                Notation::Scientific
            },
            decimals: None,
            zero: 0.0,
        }
    }

    /// The label of tick value `v`.
    pub(crate) fn label(&self, v: f64) -> String {
        if v.abs() <= self.zero || v == 0.0 {
            return "0".into();
        }
        if !v.is_finite() {
            return format!("{v}");
        }
        match (self.notation, self.decimals) {
            (Notation::Plain, Some(d)) => format!("{v:.d$}"),
            (Notation::Scientific, Some(d)) => format!("{v:.d$e}"),
            (Notation::Plain, None) => {
                // At most 4 significant digits, trailing zeros dropped.
                let d = (3 - v.abs().log10().floor() as i32).clamp(0, 6) as usize;
                trim_zeros(&format!("{v:.d$}")).to_string()
            }
            (Notation::Scientific, None) => {
                let s = format!("{v:.3e}");
                match s.split_once('e') {
                    Some((m, e)) => format!("{}e{e}", trim_zeros(m)),
                    None => s,
                }
            }
        }
    }
}

/// `1.500` → `1.5`, `2.000` → `2`; a number without a decimal point as it is.
fn trim_zeros(s: &str) -> &str {
    if s.contains('.') {
        s.trim_end_matches('0').trim_end_matches('.')
    } else {
        s
    }
}

/// A linear axis from `lo` to `hi` whose ticks are whole multiples of a 1-2-5 step, labelled in
/// one format (see the module doc). Grid lines between the labelled ticks are at a fifth (a
/// quarter for a step of 2 · 10^e) of the step.
#[derive(Clone)]
pub(crate) struct TickAxis {
    coord: RangedCoordf64,
    lo: f64,
    hi: f64,
    /// At most this many labelled ticks.
    max: usize,
    format: TickFormat,
}

impl TickAxis {
    /// The axis over `lo..hi` (ordered, finite, hi > lo: the plots pad their ranges) with at
    /// most `max` labelled ticks.
    pub(crate) fn new(lo: f64, hi: f64, max: usize) -> Self {
        let step = nice_step(lo, hi, max).unwrap_or((1.0, 0));
        let magnitude = ticks(lo, hi, step.0 * 10f64.powi(step.1))
            .iter()
            .fold(0.0f64, |a, t| a.max(t.abs()));
        TickAxis {
            coord: RangedCoordf64::from(lo..hi),
            lo,
            hi,
            max,
            format: TickFormat::linear(magnitude, step),
        }
    }

    /// The label of a tick of this axis.
    pub(crate) fn label(&self, v: f64) -> String {
        self.format.label(v)
    }

    /// The labelled ticks, or the grid lines when at most `light` of them are asked for.
    fn points(&self, light: Option<usize>) -> Vec<f64> {
        let Some((m, e)) = nice_step(self.lo, self.hi, self.max) else {
            return vec![];
        };
        let step = m * 10f64.powi(e);
        if let Some(light) = light {
            let minor = step / if m == 2.0 { 4.0 } else { 5.0 };
            if count(self.lo, self.hi, minor) <= light {
                return ticks(self.lo, self.hi, minor);
            }
        }
        ticks(self.lo, self.hi, step)
    }

    /// The labelled tick values (as the plot's mesh draws them).
    #[cfg(test)]
    pub(crate) fn tick_values(&self) -> Vec<f64> {
        self.points(None)
    }
}

impl Ranged for TickAxis {
    type FormatOption = NoDefaultFormatting;
    type ValueType = f64;

    fn map(&self, value: &f64, limit: (i32, i32)) -> i32 {
        self.coord.map(value, limit)
    }

    fn key_points<Hint: KeyPointHint>(&self, hint: Hint) -> Vec<f64> {
        let light = match hint.weight() {
            KeyPointWeight::Bold => None,
            KeyPointWeight::Any => Some(hint.max_num_points()),
        };
        self.points(light)
    }

    fn range(&self) -> Range<f64> {
        self.lo..self.hi
    }
}

impl ValueFormatter<f64> for TickAxis {
    fn format_ext(&self, value: &f64) -> String {
        self.label(*value)
    }
}

#[cfg(test)]
// In tests an out-of-range index is a failure report like any assertion.
#[allow(clippy::indexing_slicing)]
mod tests {
    use super::*;

    /// The notation and number of decimals (of the mantissa) of a label; `0` has none.
    fn shape(label: &str) -> Option<(bool, usize)> {
        if label == "0" {
            return None;
        }
        let (mantissa, sci) = match label.split_once('e') {
            Some((m, _)) => (m, true),
            None => (label, false),
        };
        Some((sci, mantissa.split_once('.').map_or(0, |(_, d)| d.len())))
    }

    /// Every label of an axis has one notation and one number of decimals (`0` aside), and
    /// reads back (as a number) the tick value to half a unit of its last digit.
    fn assert_one_format(lo: f64, hi: f64) -> Vec<String> {
        let axis = TickAxis::new(lo, hi, Y_TICKS);
        let values = axis.tick_values();
        let labels: Vec<String> = values.iter().map(|&v| axis.label(v)).collect();
        assert!(
            (2..=Y_TICKS).contains(&labels.len()),
            "{lo}..{hi}: {labels:?}"
        );
        let shapes: Vec<(bool, usize)> = labels.iter().filter_map(|l| shape(l)).collect();
        assert!(
            shapes.windows(2).all(|w| w[0] == w[1]),
            "{lo}..{hi}: mixed formats {labels:?}"
        );
        for (v, l) in values.iter().zip(&labels) {
            let back: f64 = l.parse().unwrap();
            let (sci, d) = shape(l).unwrap_or((false, 0));
            let exp = if sci { v.abs().log10().floor() } else { 0.0 };
            let half_unit = 0.5 * 10f64.powf(exp - d as f64) * (1.0 + 1e-9);
            assert!((back - v).abs() <= half_unit, "{l} for {v}");
        }
        labels
    }

    /// A range symmetric about 0 (a flat signal padded by ±0.5, as the plot does, and a
    /// velocity ±1) has an exact `0` tick: plotters' own ticks, accumulated from the lower end,
    /// read `-1.11e-16` there (what issue 44 saw as `-2.22e-16`).
    #[test]
    fn a_tick_meant_as_zero_reads_0() {
        for (lo, hi) in [(-0.5, 0.5), (-1.05, 1.05), (-0.3, 0.7), (-2.2e-3, 7.9e-3)] {
            let labels = assert_one_format(lo, hi);
            assert!(labels.iter().any(|l| l == "0"), "{lo}..{hi}: {labels:?}");
            assert!(
                labels.iter().all(|l| !l.contains("e-1")),
                "{lo}..{hi}: {labels:?}"
            );
        }
        // Even a value one rounding off zero reads 0 on an axis of unit step.
        assert_eq!(TickAxis::new(-1.0, 4.0, Y_TICKS).label(-2.22e-16), "0");
    }

    /// A force axis up to 1.7e5 N reads all in scientific notation with one mantissa decimal
    /// (the step 2e4 or 5e4 needs one below the top exponent): no `80000` beside `1.6e5`. A
    /// millimetre axis in plain decimals with the step's decimals (`0.0005`, `0.0010`), and
    /// tiny values in scientific notation.
    #[test]
    fn one_format_per_axis() {
        let labels = assert_one_format(-8.5e3, 1.785e5);
        assert!(labels.iter().any(|l| l == "1.0e5"), "{labels:?}");
        assert!(labels.iter().all(|l| l == "0" || l.contains('e')));
        assert_eq!(
            assert_one_format(-1.0e-4, 2.2e-3),
            ["0", "0.0005", "0.0010", "0.0015", "0.0020"]
        );
        assert_eq!(
            assert_one_format(0.0, 0.02),
            ["0", "0.005", "0.010", "0.015", "0.020"]
        );
        assert_eq!(
            assert_one_format(-3.0e-7, 3.0e-7),
            ["-3e-7", "-2e-7", "-1e-7", "0", "1e-7", "2e-7", "3e-7"]
        );
        for (lo, hi) in [
            (0.0, 1.0),
            (-7.0, 3.0),
            (1e4, 1.2e5),
            (0.99, 1.01),
            (2.0, 2.0001),
        ] {
            assert_one_format(lo, hi);
        }
    }

    /// Degenerate ranges give no ticks rather than a panic or an endless loop.
    #[test]
    fn degenerate_ranges_have_no_ticks() {
        for (lo, hi) in [
            (1.0, 1.0),
            (f64::NAN, 1.0),
            (0.0, f64::INFINITY),
            (2.0, 1.0),
        ] {
            assert!(TickAxis::new(lo, hi, Y_TICKS).tick_values().is_empty());
        }
    }

    /// Logarithmic axes: one notation for the axis.
    #[test]
    fn log_axis_labels() {
        let f = TickFormat::log(0.5, 2000.0);
        assert_eq!(
            [f.label(1.0), f.label(100.0), f.label(0.5)],
            ["1", "100", "0.5"]
        );
        let f = TickFormat::log(1e-2, 1e6);
        assert_eq!(
            [f.label(1.0), f.label(1e5), f.label(0.02)],
            ["1e0", "1e5", "2e-2"]
        );
    }
}
