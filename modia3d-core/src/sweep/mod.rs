//! Sweep stage: parameter studies. A [`Sweep`] runs one simulation per parameter point — a
//! model built by the user's constructor closure from [`Params`], simulated with the sweep's
//! [`SimOptions`] — on all cores (rayon), and keeps of each run the final values of chosen
//! signals and scalar metrics computed by closures, in one [`SweepTable`] (a row per run, in
//! point order; failed runs are rows with their error). Shards of a sweep (`run_shard`) run on
//! the nodes of a cluster and their tables are merged (`SweepTable::merge`); the sweep file and
//! the command-line front end for job arrays are in `spec.rs`.
//!
//! Data flow: `ParamPoints` (made whole first, `points.rs`) → for each index in parallel:
//! `Params` → constructor → `Model::simulate` → outputs → `SweepRow` → collected in index order
//! (`table.rs`). Nothing a run computes depends on the thread that ran it, so the table is the
//! same bit for bit whatever the thread count or shard split.
#![deny(clippy::indexing_slicing)]

mod plot;
mod points;
mod spec;
mod table;

pub use points::{linspace, Distribution, ParamPoints, MAX_POINTS};
pub use spec::{sweep_main, SweepRegistry, SweepSpec};
pub use table::{ColumnInfo, RunError, SweepRow, SweepTable};

use crate::model::Model;
use crate::results::SimulationResult;
use crate::simulation::SimOptions;
use rayon::prelude::*;
use std::panic::{catch_unwind, AssertUnwindSafe};
use std::sync::Arc;

/// The error type user closures of a sweep return (anything that is an error: `?` converts).
pub type BoxError = Box<dyn std::error::Error + Send + Sync>;

/// A model constructor: the model of one parameter point.
pub type ModelFn = dyn Fn(&Params) -> Result<Model, BoxError> + Send + Sync;

/// A metric: a scalar computed from a successful run's result.
pub type MetricFn = dyn Fn(&SimulationResult) -> Result<f64, BoxError> + Send + Sync;

/// Errors of setting up, running, reading or merging sweeps (a failing *run* is not one of
/// them: it is a row of the table with its [`RunError`]).
#[derive(thiserror::Error, Debug)]
pub enum SweepError {
    /// The parameter points cannot be made.
    #[error("invalid parameter points: {reason}")]
    InvalidPoints {
        /// What is wrong, naming the parameter.
        reason: String,
    },
    /// A constructor asked [`Params::get`] for a parameter the sweep does not have.
    #[error("no parameter `{name}` in this sweep{}; the parameters are: {known}", match .hint { Some(h) => format!(" (did you mean `{h}`?)"), None => String::new() })]
    UnknownParam {
        /// The name asked for.
        name: String,
        /// A close existing name.
        hint: Option<String>,
        /// The parameter names.
        known: String,
    },
    /// The outputs asked for cannot be columns (a bad or repeated name).
    #[error("invalid outputs: {reason}")]
    InvalidOutputs {
        /// What is wrong.
        reason: String,
    },
    /// A shard index out of range, or none given.
    #[error("shard: {reason}")]
    Shard {
        /// What is wrong and how to give it.
        reason: String,
    },
    /// The thread pool could not be made.
    #[error("cannot start {threads} worker threads: {reason}")]
    ThreadPool {
        /// Threads asked for.
        threads: usize,
        /// The cause.
        reason: String,
    },
    /// A sweep file cannot be read or is not valid.
    #[error("sweep file `{path}`: {reason}")]
    Spec {
        /// The file.
        path: String,
        /// What is wrong, with the key.
        reason: String,
    },
    /// The sweep file names a model the registry does not have.
    #[error("no model `{name}` in the registry{}; the models are: {known}", match .hint { Some(h) => format!(" (did you mean `{h}`?)"), None => String::new() })]
    UnknownModel {
        /// The name in the file.
        name: String,
        /// A close registered name.
        hint: Option<String>,
        /// The registered names.
        known: String,
    },
    /// A file that should be a sweep table is not one.
    #[error("sweep table `{path}`, line {line}: {reason}")]
    Table {
        /// The file.
        path: String,
        /// The line (1 = header).
        line: usize,
        /// What is wrong.
        reason: String,
    },
    /// The parts of a sharded sweep do not join into one table.
    #[error("cannot merge the parts: {reason}")]
    Merge {
        /// Which rows or columns do not fit.
        reason: String,
    },
    /// Reading or writing a file failed.
    #[error("cannot read or write `{path}`: {source}")]
    Io {
        /// The path.
        path: String,
        /// The cause.
        source: std::io::Error,
    },
    /// An export could not be written (Arrow).
    #[error("cannot export `{path}`: {reason}")]
    Export {
        /// The path.
        path: String,
        /// Why.
        reason: String,
    },
    /// A wrong command line of [`sweep_main`].
    #[error("{reason}\n\n{usage}")]
    Usage {
        /// What is wrong.
        reason: String,
        /// The usage text.
        usage: &'static str,
    },
}

/// The parameter values of one run, as the constructor sees them.
#[derive(Clone, Debug)]
pub struct Params {
    names: Arc<[String]>,
    values: Vec<f64>,
    index: usize,
    seed: u64,
}

impl Params {
    /// The value of parameter `name` (in the unit the points give it);
    /// [`SweepError::UnknownParam`] (with a did-you-mean) for a name the sweep does not have.
    pub fn get(&self, name: &str) -> Result<f64, SweepError> {
        match self.names.iter().position(|n| n == name) {
            Some(k) => Ok(self.values.get(k).copied().unwrap_or(f64::NAN)),
            None => Err(SweepError::UnknownParam {
                name: name.into(),
                hint: self
                    .names
                    .iter()
                    .filter(|n| strsim::levenshtein(n, name) <= 2)
                    .min_by_key(|n| strsim::levenshtein(n, name))
                    .cloned(),
                known: self.names.join(", "),
            }),
        }
    }

    /// The value of parameter `name`, or `default` when the sweep does not vary it.
    pub fn get_or(&self, name: &str, default: f64) -> f64 {
        self.get(name).unwrap_or(default)
    }

    /// The parameter names, in column order.
    pub fn names(&self) -> &[String] {
        &self.names
    }

    /// The values, in the order of [`Self::names`].
    pub fn values(&self) -> &[f64] {
        &self.values
    }

    /// The index of this point (its row in the table).
    pub fn index(&self) -> usize {
        self.index
    }

    /// A seed for randomness inside the constructor (noise, random initial states): derived
    /// from [`Sweep::seed`] and the index only, so a rerun, another thread count or another
    /// shard split sees the same value.
    pub fn seed(&self) -> u64 {
        let mut r = points::SplitMix64::new(self.seed ^ (self.index as u64).rotate_left(32));
        r.next_u64()
    }
}

/// A parameter study: a model constructor, parameter points, simulation options and what to
/// keep of each run. Build with [`Sweep::new`] and the setters, run with [`Sweep::run`].
///
/// ```no_run
/// use modia3d_core::{linspace, ParamPoints, SimOptions, Sweep};
/// # fn scene(h0: f64) -> modia3d_core::SceneDesc { unimplemented!() }
/// let sweep = Sweep::new(|p| Ok(scene(p.get("h0")?).build()?))
///     .points(ParamPoints::grid(&[("h0", "m", linspace(0.2, 1.0, 9))])?)
///     .options(SimOptions::new(2.0).tolerance(1e-6))
///     .final_value("ball.r_abs[2]")
///     .metric("z_min", "m", |res| {
///         Ok(res.signal("ball.r_abs[2]")?.values().into_iter().fold(f64::INFINITY, f64::min))
///     });
/// let table = sweep.run()?;
/// table.write_csv("out/sweep.csv")?;
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
#[derive(Clone)]
pub struct Sweep {
    constructor: Arc<ModelFn>,
    points: Option<ParamPoints>,
    options: SimOptions,
    final_values: Vec<String>,
    metrics: Vec<(ColumnInfo, Arc<MetricFn>)>,
    threads: Option<usize>,
    progress: bool,
    seed: u64,
}

impl std::fmt::Debug for Sweep {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Sweep")
            .field("points", &self.points.as_ref().map(ParamPoints::len))
            .field("options", &self.options)
            .field("final_values", &self.final_values)
            .field(
                "metrics",
                &self
                    .metrics
                    .iter()
                    .map(|(c, _)| &c.name)
                    .collect::<Vec<_>>(),
            )
            .field("threads", &self.threads)
            .finish_non_exhaustive()
    }
}

impl Sweep {
    /// A sweep of the models `constructor` builds from each point's [`Params`]; a `model!`
    /// type works through the closure: `|p| Ok(Pendulum { l: p.get("l")?, ..Default::default()
    /// }.build()?)`. Defaults: no points yet ([`Self::points`]), `SimOptions::new(1.0)`, no
    /// final values or metrics (the table still has `t_end`), all cores, a progress bar when
    /// standard error is a terminal, seed 0.
    pub fn new(
        constructor: impl Fn(&Params) -> Result<Model, BoxError> + Send + Sync + 'static,
    ) -> Self {
        Sweep {
            constructor: Arc::new(constructor),
            points: None,
            options: SimOptions::new(1.0),
            final_values: vec![],
            metrics: vec![],
            threads: None,
            progress: true,
            seed: 0,
        }
    }

    /// Sets the parameter points.
    pub fn points(mut self, points: ParamPoints) -> Self {
        self.points = Some(points);
        self
    }

    /// Sets the options of every run (their progress bar is always off, the sweep has one; and
    /// they are always [`quiet`](SimOptions::quiet): no warnings on standard error).
    pub fn options(mut self, options: SimOptions) -> Self {
        self.options = options;
        self
    }

    /// Keeps the final value of signal `name` (a scalar signal or a component, e.g.
    /// `"ball.r_abs[2]"`; its unit becomes the column's).
    pub fn final_value(mut self, name: impl Into<String>) -> Self {
        self.final_values.push(name.into());
        self
    }

    /// Keeps a metric: `f` computes a scalar in `unit` (`""` for none) from a successful run's
    /// result; an `Err` or a panic of `f` marks the row failed (status `output` or `panic`).
    pub fn metric(
        mut self,
        name: impl Into<String>,
        unit: impl Into<String>,
        f: impl Fn(&SimulationResult) -> Result<f64, BoxError> + Send + Sync + 'static,
    ) -> Self {
        let col = ColumnInfo {
            name: name.into(),
            unit: unit.into(),
        };
        self.metrics.push((col, Arc::new(f)));
        self
    }

    /// Runs on `n` worker threads (≥ 1) instead of rayon's default (all cores, or the
    /// environment variable `RAYON_NUM_THREADS`).
    pub fn threads(mut self, n: usize) -> Self {
        self.threads = Some(n);
        self
    }

    /// Shows (default, on a terminal only) or hides the progress bar.
    pub fn progress(mut self, on: bool) -> Self {
        self.progress = on;
        self
    }

    /// Sets the seed of [`Params::seed`].
    pub fn seed(mut self, seed: u64) -> Self {
        self.seed = seed;
        self
    }

    /// The parameter points (`None` until set).
    pub fn param_points(&self) -> Option<&ParamPoints> {
        self.points.as_ref()
    }

    /// The simulation options of every run.
    pub fn sim_options(&self) -> &SimOptions {
        &self.options
    }

    /// Runs every point; the table has a row per point, in point order. Errors only for a
    /// sweep that cannot start (no points, bad output names, no threads); failing runs are rows.
    pub fn run(&self) -> Result<SweepTable, SweepError> {
        let n = self.require_points()?.len();
        self.run_indices((0..n).collect())
    }

    /// Runs shard `shard` of `of` (0-based): the points `shard`, `shard + of`, `shard + 2·of`, …
    /// (interleaved, so that a grid's slow corner is spread over the shards). Merging the
    /// tables of shards `0..of` ([`SweepTable::merge`]) gives [`Self::run`]'s table.
    pub fn run_shard(&self, shard: usize, of: usize) -> Result<SweepTable, SweepError> {
        if of == 0 || shard >= of {
            return Err(SweepError::Shard {
                reason: format!("shard {shard} of {of}: the index must be in 0..{of} (0-based)"),
            });
        }
        let n = self.require_points()?.len();
        self.run_indices((shard..n).step_by(of).collect())
    }

    fn require_points(&self) -> Result<&ParamPoints, SweepError> {
        self.points
            .as_ref()
            .ok_or_else(|| SweepError::InvalidPoints {
                reason: "the sweep has no points: call `Sweep::points`".into(),
            })
    }

    /// The output columns: final values (unit filled in from the runs), metrics, `t_end`.
    fn output_columns(&self, points: &ParamPoints) -> Result<Vec<ColumnInfo>, SweepError> {
        let mut cols: Vec<ColumnInfo> = self
            .final_values
            .iter()
            .map(|n| ColumnInfo {
                name: n.clone(),
                unit: String::new(),
            })
            .collect();
        cols.extend(self.metrics.iter().map(|(c, _)| c.clone()));
        cols.push(ColumnInfo {
            name: "t_end".into(),
            unit: "s".into(),
        });
        for (k, c) in cols.iter().enumerate() {
            let invalid = |reason| SweepError::InvalidOutputs { reason };
            points::check_column_name(&c.name, "output").map_err(|e| invalid(e.to_string()))?;
            if ["index", "status", "message"].contains(&c.name.as_str())
                || points.names().contains(&c.name)
                || cols.iter().take(k).any(|d| d.name == c.name)
            {
                return Err(invalid(format!(
                    "the column `{}` is there twice (a parameter, another output, or one of index, status, message, t_end): rename it",
                    c.name
                )));
            }
            if c.unit.contains([']', ',', '"', '\n']) {
                return Err(invalid(format!(
                    "the unit `{}` of `{}` must not contain `]`, `,`, `\"` or a line break",
                    c.unit, c.name
                )));
            }
        }
        Ok(cols)
    }

    fn run_indices(&self, indices: Vec<usize>) -> Result<SweepTable, SweepError> {
        let points = self.require_points()?;
        let mut outputs = self.output_columns(points)?;
        // The runs are quiet; the notice of an unoptimised build is the sweep's (once per process).
        crate::build_profile::notice_once(crate::simulation::subscriber_installed());
        let bar = self.progress_bar(indices.len());
        let work = || {
            // Every run its own stealable job: rayon otherwise hands a thread a block of points
            // to run in sequence, and a block of slow runs (a grid's costly corner) at the end
            // keeps one thread busy while the other waits. A job costs microseconds, a run
            // milliseconds.
            indices
                .par_iter()
                .with_max_len(1)
                .map(|&i| {
                    let row = self.run_one(points, i);
                    if let Some(b) = &bar {
                        b.inc(1);
                    }
                    row
                })
                .collect::<Vec<_>>()
        };
        let results = match self.threads {
            None => work(),
            Some(threads) => rayon::ThreadPoolBuilder::new()
                .num_threads(threads.max(1))
                .build()
                .map_err(|e| SweepError::ThreadPool {
                    threads,
                    reason: e.to_string(),
                })?
                .install(work),
        };
        if let Some(b) = bar {
            b.finish_and_clear();
        }
        // Units of the final values: from the first run that produced them.
        for (k, col) in outputs.iter_mut().enumerate().take(self.final_values.len()) {
            if let Some(u) = results
                .iter()
                .find_map(|(_, units)| units.get(k)?.as_deref())
            {
                col.unit = u.to_string();
            }
        }
        Ok(SweepTable {
            params: points
                .names()
                .iter()
                .zip(points.units())
                .map(|(n, u)| ColumnInfo {
                    name: n.clone(),
                    unit: u.clone(),
                })
                .collect(),
            outputs,
            rows: results.into_iter().map(|(row, _)| row).collect(),
        })
    }

    fn progress_bar(&self, len: usize) -> Option<indicatif::ProgressBar> {
        use std::io::IsTerminal;
        (self.progress && std::io::stderr().is_terminal()).then(|| {
            let bar = indicatif::ProgressBar::new(len as u64);
            bar.set_style(
                indicatif::ProgressStyle::with_template(
                    "{bar:40} {pos}/{len} runs, {elapsed} (ETA {eta})",
                )
                .unwrap_or_else(|_| indicatif::ProgressStyle::default_bar()),
            );
            bar
        })
    }

    /// Run `i`: its row and the units of its final values (`None` where not computed).
    fn run_one(&self, points: &ParamPoints, i: usize) -> (SweepRow, Vec<Option<&'static str>>) {
        let values = points.row(i).unwrap_or_default().to_vec();
        let params = Params {
            names: points.names.clone(),
            values,
            index: i,
            seed: self.seed,
        };
        let mut outputs = vec![f64::NAN; self.final_values.len() + self.metrics.len() + 1];
        let mut units = vec![None; self.final_values.len()];
        let error = self.outcome(&params, &mut outputs, &mut units);
        let row = SweepRow {
            index: i,
            params: params.values,
            outputs,
            error,
        };
        (row, units)
    }

    /// Builds and runs the model of `params`, fills in `outputs` (final values, metrics,
    /// `t_end`) and the final values' `units`; the first error, if any.
    fn outcome(
        &self,
        params: &Params,
        outputs: &mut [f64],
        units: &mut [Option<&'static str>],
    ) -> Option<RunError> {
        let model = match catch_unwind(AssertUnwindSafe(|| (self.constructor)(params))) {
            Ok(Ok(m)) => m,
            Ok(Err(e)) => return Some(RunError::Build(e.to_string())),
            Err(p) => {
                let msg = format!("the model constructor panicked: {}", panic_text(&*p));
                return Some(RunError::Panic(msg));
            }
        };
        // Quiet: a sweep of many runs would flood standard error with the same warnings; they
        // stay in each run's result.
        let opts = self.options.clone().progress(false).quiet(true);
        let res = match catch_unwind(AssertUnwindSafe(|| model.simulate(&opts))) {
            Ok(Ok(res)) => res,
            Ok(Err(e)) => {
                if let Some(last) = outputs.last_mut() {
                    *last = e.partial.time().last().copied().unwrap_or(f64::NAN);
                }
                return Some(RunError::Simulation(e.to_string()));
            }
            Err(p) => {
                let msg = format!("the simulation panicked: {}", panic_text(&*p));
                return Some(RunError::Panic(msg));
            }
        };
        let mut error = None;
        for ((name, slot), unit) in self
            .final_values
            .iter()
            .zip(outputs.iter_mut())
            .zip(units.iter_mut())
        {
            match res.signal(name) {
                Ok(s) if s.dim == 1 => {
                    *slot = s
                        .last()
                        .and_then(|v| v.first().copied())
                        .unwrap_or(f64::NAN);
                    *unit = Some(s.unit);
                }
                Ok(s) => {
                    error.get_or_insert(RunError::Output(format!(
                        "final value of `{name}`: the signal has {} components; name one, e.g. `{name}[0]`",
                        s.dim
                    )));
                }
                Err(e) => {
                    error.get_or_insert(RunError::Output(format!("final value: {e}")));
                }
            }
        }
        for ((col, f), slot) in self
            .metrics
            .iter()
            .zip(outputs.iter_mut().skip(self.final_values.len()))
        {
            match catch_unwind(AssertUnwindSafe(|| f(&res))) {
                Ok(Ok(v)) => *slot = v,
                Ok(Err(e)) => {
                    error.get_or_insert(RunError::Output(format!("metric `{}`: {e}", col.name)));
                }
                Err(p) => {
                    error.get_or_insert(RunError::Panic(format!(
                        "metric `{}` panicked: {}",
                        col.name,
                        panic_text(&*p)
                    )));
                }
            }
        }
        if let Some(last) = outputs.last_mut() {
            *last = res.time().last().copied().unwrap_or(f64::NAN);
        }
        error
    }
}

/// The message of a caught panic (a `&str` or `String` payload; otherwise a placeholder).
fn panic_text(p: &(dyn std::any::Any + Send)) -> String {
    p.downcast_ref::<&str>()
        .map(|s| s.to_string())
        .or_else(|| p.downcast_ref::<String>().cloned())
        .unwrap_or_else(|| "(a panic without a message)".into())
}
