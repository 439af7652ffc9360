//! Sweep stage, parameter points: the set of points a sweep runs, made whole before any run
//! (a grid, a list, or seeded random / Latin-hypercube samples), so that row `i` is point `i`
//! whatever the thread count or shard split. The random numbers come from SplitMix64 (Steele,
//! Lea, Flood 2014), written out here: one seed gives the same points on every platform and
//! version of this crate.
#![deny(clippy::indexing_slicing)]

use super::SweepError;
use std::sync::Arc;

/// A distribution of one parameter of a [random](ParamPoints::random) or
/// [Latin-hypercube](ParamPoints::latin_hypercube) sweep. Values are in the parameter's unit.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Distribution {
    /// Uniform on `[low, high)`.
    Uniform {
        /// Lower bound.
        low: f64,
        /// Upper bound (> `low`).
        high: f64,
    },
    /// Log-uniform on `[low, high)`: `ln x` uniform; `0 < low < high`.
    LogUniform {
        /// Lower bound (> 0).
        low: f64,
        /// Upper bound (> `low`).
        high: f64,
    },
    /// Normal with mean `mean` and standard deviation `std_dev` (> 0).
    Normal {
        /// Mean.
        mean: f64,
        /// Standard deviation (> 0).
        std_dev: f64,
    },
}

impl Distribution {
    /// The value at probability `u` ∈ (0, 1) (the inverse cumulative distribution function).
    pub fn quantile(&self, u: f64) -> f64 {
        match *self {
            Distribution::Uniform { low, high } => low + u * (high - low),
            Distribution::LogUniform { low, high } => (low.ln() + u * (high.ln() - low.ln())).exp(),
            Distribution::Normal { mean, std_dev } => mean + std_dev * normal_quantile(u),
        }
    }

    /// `Err` with what is wrong with the parameters, for parameter `name`.
    fn check(&self, name: &str) -> Result<(), SweepError> {
        let bad = |reason: String| {
            Err(SweepError::InvalidPoints {
                reason: format!("parameter `{name}`: {reason}"),
            })
        };
        match *self {
            Distribution::Uniform { low, high } | Distribution::LogUniform { low, high }
                if !(low.is_finite() && high.is_finite() && low < high) =>
            {
                bad(format!(
                    "the bounds [{low}, {high}) must be finite with low < high"
                ))
            }
            Distribution::LogUniform { low, .. } if low <= 0.0 => bad(format!(
                "a log-uniform distribution needs low > 0 (got {low})"
            )),
            Distribution::Normal { mean, std_dev }
                if !(mean.is_finite() && std_dev.is_finite() && std_dev > 0.0) =>
            {
                bad(format!(
                    "a normal distribution needs a finite mean and std_dev > 0 (got {mean}, {std_dev})"
                ))
            }
            _ => Ok(()),
        }
    }
}

/// `n` values evenly spaced from `start` to `end`, both included (`n = 1`: `[start]`).
pub fn linspace(start: f64, end: f64, n: usize) -> Vec<f64> {
    match n {
        0 => vec![],
        1 => vec![start],
        _ => (0..n)
            .map(|k| {
                if k + 1 == n {
                    end
                } else {
                    start + (end - start) * k as f64 / (n - 1) as f64
                }
            })
            .collect(),
    }
}

/// The parameter points of a sweep: names with units and one row of values per point, made
/// whole when constructed (a grid, a list, seeded random or Latin-hypercube samples). Row `i`
/// is run `i` of the sweep and row `i` of its table.
#[derive(Clone, Debug, PartialEq)]
pub struct ParamPoints {
    pub(crate) names: Arc<[String]>,
    pub(crate) units: Vec<String>,
    pub(crate) rows: Vec<Vec<f64>>,
}

/// Largest number of points a sweep may have (a grid's product of axis lengths included).
pub const MAX_POINTS: usize = 100_000_000;

impl ParamPoints {
    /// Every combination of the axes' values, `(name, unit, values)` each; the first axis
    /// varies slowest (as nested loops in the order given): `grid([("h", "m", [1, 2]), ("c",
    /// "1", [0.5, 0.7])])` is `(1, 0.5), (1, 0.7), (2, 0.5), (2, 0.7)`.
    pub fn grid<S: AsRef<str>>(axes: &[(S, S, Vec<f64>)]) -> Result<Self, SweepError> {
        let (names, units) = names_units(axes.iter().map(|(n, u, _)| (n, u)))?;
        let mut total: usize = 1;
        for (name, _, values) in axes {
            if values.is_empty() {
                return Err(invalid(format!(
                    "grid axis `{}` has no values: give at least one",
                    name.as_ref()
                )));
            }
            check_finite(name.as_ref(), values)?;
            total = total
                .checked_mul(values.len())
                .filter(|&t| t <= MAX_POINTS)
                .ok_or_else(|| {
                    invalid(format!(
                        "the grid has more than {MAX_POINTS} points: split it into several sweeps"
                    ))
                })?;
        }
        let mut rows = Vec::with_capacity(total);
        for i in 0..total {
            // Mixed-radix digits of i, the last axis fastest.
            let mut rest = i;
            let mut row = vec![0.0; axes.len()];
            for ((_, _, values), slot) in axes.iter().zip(row.iter_mut()).rev() {
                let len = values.len();
                *slot = values.get(rest % len).copied().unwrap_or(f64::NAN);
                rest /= len;
            }
            rows.push(row);
        }
        Ok(ParamPoints { names, units, rows })
    }

    /// The given points: `params` as `(name, unit)`, one row of values per point, each as long
    /// as `params`.
    pub fn list<S: AsRef<str>>(params: &[(S, S)], rows: Vec<Vec<f64>>) -> Result<Self, SweepError> {
        let (names, units) = names_units(params.iter().map(|(n, u)| (n, u)))?;
        if rows.is_empty() {
            return Err(invalid(
                "the list has no points: give at least one row".into(),
            ));
        }
        if rows.len() > MAX_POINTS {
            return Err(invalid(format!(
                "the list has more than {MAX_POINTS} points"
            )));
        }
        for (i, row) in rows.iter().enumerate() {
            if row.len() != names.len() {
                return Err(invalid(format!(
                    "row {i} has {} values for {} parameters ({})",
                    row.len(),
                    names.len(),
                    names.join(", ")
                )));
            }
            for (name, v) in names.iter().zip(row) {
                check_finite(name, std::slice::from_ref(v))?;
            }
        }
        Ok(ParamPoints { names, units, rows })
    }

    /// `n` independent random points: each parameter `(name, unit, distribution)` drawn from
    /// its distribution, from the random stream of `seed` (point by point, parameter by
    /// parameter). The same seed gives the same points.
    pub fn random<S: AsRef<str>>(
        params: &[(S, S, Distribution)],
        n: usize,
        seed: u64,
    ) -> Result<Self, SweepError> {
        let (names, units) = check_random(params, n)?;
        let mut rng = SplitMix64::new(seed);
        let rows = (0..n)
            .map(|_| {
                params
                    .iter()
                    .map(|(_, _, d)| d.quantile(rng.open01()))
                    .collect()
            })
            .collect();
        Ok(ParamPoints { names, units, rows })
    }

    /// `n` points of a Latin hypercube from `seed`: each parameter's probability range (0, 1)
    /// is cut into `n` equal strata and every stratum holds exactly one point, at a uniformly
    /// random place inside it; the strata are paired across parameters by independent random
    /// permutations. The value is the distribution's quantile at that probability, so the
    /// samples are stratified in probability (for a uniform parameter: in value).
    pub fn latin_hypercube<S: AsRef<str>>(
        params: &[(S, S, Distribution)],
        n: usize,
        seed: u64,
    ) -> Result<Self, SweepError> {
        let (names, units) = check_random(params, n)?;
        let mut rng = SplitMix64::new(seed);
        let mut rows = vec![Vec::with_capacity(params.len()); n];
        for (_, _, dist) in params {
            // Fisher–Yates shuffle of the strata.
            let mut strata: Vec<usize> = (0..n).collect();
            for k in (1..n).rev() {
                strata.swap(k, rng.below(k + 1));
            }
            for (row, stratum) in rows.iter_mut().zip(strata) {
                let u = (stratum as f64 + rng.open01()) / n as f64;
                row.push(dist.quantile(u.min(1.0 - f64::EPSILON / 2.0)));
            }
        }
        Ok(ParamPoints { names, units, rows })
    }

    /// Number of points.
    pub fn len(&self) -> usize {
        self.rows.len()
    }

    /// True without points (never for points made by the constructors).
    pub fn is_empty(&self) -> bool {
        self.rows.is_empty()
    }

    /// The parameter names, in column order.
    pub fn names(&self) -> &[String] {
        &self.names
    }

    /// The parameter units, in column order (`""` where none was given).
    pub fn units(&self) -> &[String] {
        &self.units
    }

    /// Point `i`'s values, in the order of [`Self::names`].
    pub fn row(&self, i: usize) -> Option<&[f64]> {
        self.rows.get(i).map(Vec::as_slice)
    }
}

fn invalid(reason: String) -> SweepError {
    SweepError::InvalidPoints { reason }
}

fn check_finite(name: &str, values: &[f64]) -> Result<(), SweepError> {
    match values.iter().find(|v| !v.is_finite()) {
        Some(v) => Err(invalid(format!(
            "parameter `{name}` has the value {v}: give finite numbers"
        ))),
        None => Ok(()),
    }
}

fn check_random<S: AsRef<str>>(
    params: &[(S, S, Distribution)],
    n: usize,
) -> Result<(Arc<[String]>, Vec<String>), SweepError> {
    let nu = names_units(params.iter().map(|(n, u, _)| (n, u)))?;
    if n == 0 || n > MAX_POINTS {
        return Err(invalid(format!(
            "{n} points asked for: give between 1 and {MAX_POINTS}"
        )));
    }
    for (name, _, d) in params {
        d.check(name.as_ref())?;
    }
    Ok(nu)
}

/// Checks that parameter names are usable column names: non-empty, unique, without `,`, `"`,
/// line breaks or a ` [` (which starts the unit in a table header); units without `]`.
fn names_units<'a, S: AsRef<str> + 'a>(
    params: impl Iterator<Item = (&'a S, &'a S)>,
) -> Result<(Arc<[String]>, Vec<String>), SweepError> {
    let mut names: Vec<String> = vec![];
    let mut units = vec![];
    for (name, unit) in params {
        let (name, unit) = (name.as_ref(), unit.as_ref());
        check_column_name(name, "parameter")?;
        if unit.contains([']', '\n', '\r', ',', '"']) {
            return Err(invalid(format!(
                "the unit `{unit}` of parameter `{name}` must not contain `]`, `,`, `\"` or a line break"
            )));
        }
        if names.iter().any(|n| n == name) {
            return Err(invalid(format!("parameter `{name}` is given twice")));
        }
        names.push(name.to_string());
        units.push(unit.to_string());
    }
    if names.is_empty() {
        return Err(invalid(
            "no parameters given: a sweep needs at least one".into(),
        ));
    }
    Ok((names.into(), units))
}

/// `Err` unless `name` can be a column of a sweep table (see [`names_units`]).
pub(crate) fn check_column_name(name: &str, what: &str) -> Result<(), SweepError> {
    if name.is_empty()
        || name.contains([',', '"', '\n', '\r'])
        || name.contains(" [")
        || name != name.trim()
    {
        return Err(invalid(format!(
            "{what} name `{name}` cannot be a column name: give a non-empty name without `,`, `\"`, line breaks, ` [` or surrounding spaces"
        )));
    }
    Ok(())
}

/// SplitMix64: a 64-bit state advanced by a constant, output mixed (passes BigCrush).
pub(crate) struct SplitMix64(u64);

impl SplitMix64 {
    pub(crate) fn new(seed: u64) -> Self {
        SplitMix64(seed)
    }

    pub(crate) fn next_u64(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9e37_79b9_7f4a_7c15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
        z ^ (z >> 31)
    }

    /// Uniform in the open interval (0, 1): 53 random bits, centred in their cell.
    pub(crate) fn open01(&mut self) -> f64 {
        ((self.next_u64() >> 11) as f64 + 0.5) * (1.0 / (1u64 << 53) as f64)
    }

    /// Uniform integer in `0..n` (`n ≥ 1`), by rejection (no modulo bias).
    fn below(&mut self, n: usize) -> usize {
        let n = n as u64;
        let zone = u64::MAX - u64::MAX % n;
        loop {
            let x = self.next_u64();
            if x < zone {
                return (x % n) as usize;
            }
        }
    }
}

/// The standard normal quantile Φ⁻¹(p), p ∈ (0, 1): Acklam's rational approximation, relative
/// error below 1.15e-9 (far below any sampling error of a sweep).
pub(crate) fn normal_quantile(p: f64) -> f64 {
    const A: [f64; 6] = [
        -3.969683028665376e1,
        2.209460984245205e2,
        -2.759285104469687e2,
        1.38357751867269e2,
        -3.066479806614716e1,
        2.506628277459239,
    ];
    const B: [f64; 5] = [
        -5.447609879822406e1,
        1.615858368580409e2,
        -1.556989798598866e2,
        6.680131188771972e1,
        -1.328068155288572e1,
    ];
    const C: [f64; 6] = [
        -7.784894002430293e-3,
        -3.223964580411365e-1,
        -2.400758277161838,
        -2.549732539343734,
        4.374664141464968,
        2.938163982698783,
    ];
    const D: [f64; 4] = [
        7.784695709041462e-3,
        3.224671290700398e-1,
        2.445134137142996,
        3.754408661907416,
    ];
    if p.is_nan() || p <= 0.0 || p >= 1.0 {
        return match p {
            0.0 => f64::NEG_INFINITY,
            1.0 => f64::INFINITY,
            _ => f64::NAN,
        };
    }
    let tail = |q: f64| {
        (((((C[0] * q + C[1]) * q + C[2]) * q + C[3]) * q + C[4]) * q + C[5])
            / ((((D[0] * q + D[1]) * q + D[2]) * q + D[3]) * q + 1.0)
    };
    let p_low = 0.02425;
    if p < p_low {
        tail((-2.0 * p.ln()).sqrt())
    } else if p <= 1.0 - p_low {
        let q = p - 0.5;
        let r = q * q;
        (((((A[0] * r + A[1]) * r + A[2]) * r + A[3]) * r + A[4]) * r + A[5]) * q
            / (((((B[0] * r + B[1]) * r + B[2]) * r + B[3]) * r + B[4]) * r + 1.0)
    } else {
        -tail((-2.0 * (1.0 - p).ln()).sqrt())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn normal_quantile_matches_reference_values() {
        // Φ⁻¹ reference values (Python's statistics.NormalDist().inv_cdf, 17 digits).
        for (p, x) in [
            (0.5, 0.0),
            (0.975, 1.959963984540054),
            (0.025, -1.959963984540054),
            (0.8413447460685429, 1.0),
            (1e-6, -4.753424308822899),
            (0.999, 3.090232306167813),
        ] {
            let got = normal_quantile(p);
            assert!(
                (got - x).abs() <= 1e-8 * x.abs().max(1.0),
                "{p}: {got} vs {x}"
            );
        }
    }

    #[test]
    fn grid_order_first_axis_slowest() {
        let p = ParamPoints::grid(&[("a", "m", vec![1.0, 2.0]), ("b", "", vec![5.0, 6.0, 7.0])])
            .unwrap();
        let rows: Vec<&[f64]> = (0..p.len()).filter_map(|i| p.row(i)).collect();
        assert_eq!(
            rows,
            [
                [1.0, 5.0],
                [1.0, 6.0],
                [1.0, 7.0],
                [2.0, 5.0],
                [2.0, 6.0],
                [2.0, 7.0]
            ]
        );
    }

    #[test]
    fn invalid_points_are_typed_errors() {
        let e = |r: Result<ParamPoints, SweepError>| r.unwrap_err().to_string();
        assert!(e(ParamPoints::grid(&[("a", "m", vec![])])).contains("no values"));
        assert!(e(ParamPoints::grid(&[("a", "m", vec![f64::NAN])])).contains("finite"));
        assert!(e(ParamPoints::grid(&[("a,b", "m", vec![1.0])])).contains("column name"));
        assert!(e(ParamPoints::list(
            &[("a", ""), ("a", "")],
            vec![vec![1.0, 2.0]]
        ))
        .contains("twice"));
        assert!(e(ParamPoints::list(&[("a", "")], vec![vec![1.0, 2.0]])).contains("row 0"));
        let d = Distribution::LogUniform {
            low: 0.0,
            high: 1.0,
        };
        assert!(e(ParamPoints::random(&[("a", "", d)], 4, 0)).contains("low > 0"));
        let u = Distribution::Uniform {
            low: 0.0,
            high: 1.0,
        };
        assert!(e(ParamPoints::latin_hypercube(&[("a", "", u)], 0, 0)).contains("1 and"));
        let big = vec![0.0; 100_000];
        assert!(
            e(ParamPoints::grid(&[("a", "", big.clone()), ("b", "", big)])).contains("more than")
        );
    }
}
