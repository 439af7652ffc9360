//! Sweep stage, files and the command line: a sweep described by a JSON file (the model by its
//! name in the user's [`SweepRegistry`], the points, options, final values), and
//! [`sweep_main`], the front end a user's small binary calls to run shard `i` of `n` of such a
//! file under any job-array scheduler (Slurm, PBS, HyperQueue) and to merge the parts.
#![deny(clippy::indexing_slicing)]

use super::{Distribution, ParamPoints, Sweep, SweepError, SweepTable};
use serde::Deserialize;
use std::path::Path;

/// Models a sweep file may name: each a name and a template [`Sweep`] (constructor, options,
/// metrics, final values; its points come from the file).
#[derive(Clone, Debug, Default)]
pub struct SweepRegistry {
    entries: Vec<(String, Sweep)>,
}

impl SweepRegistry {
    /// An empty registry.
    pub fn new() -> Self {
        Self::default()
    }

    /// Registers `template` under `name` (replacing an earlier one of that name).
    pub fn add(mut self, name: impl Into<String>, template: Sweep) -> Self {
        let name = name.into();
        self.entries.retain(|(n, _)| *n != name);
        self.entries.push((name, template));
        self
    }

    /// The registered names, in the order added.
    pub fn names(&self) -> Vec<&str> {
        self.entries.iter().map(|(n, _)| n.as_str()).collect()
    }

    /// The template of `name`; [`SweepError::UnknownModel`] with a did-you-mean otherwise.
    pub fn get(&self, name: &str) -> Result<&Sweep, SweepError> {
        self.entries
            .iter()
            .find(|(n, _)| n == name)
            .map(|(_, s)| s)
            .ok_or_else(|| SweepError::UnknownModel {
                name: name.into(),
                hint: self
                    .entries
                    .iter()
                    .map(|(n, _)| n)
                    .filter(|n| strsim::levenshtein(n, name) <= 3)
                    .min_by_key(|n| strsim::levenshtein(n, name))
                    .cloned(),
                known: self.names().join(", "),
            })
    }
}

/// A sweep file (JSON). Every key but `model` and `points` is optional and overrides the
/// registered template's setting:
///
/// ```json
/// {
///   "model": "bouncing_sphere",
///   "stop_time": 1.0, "tolerance": 1e-6, "interval": 0.01, "seed": 0,
///   "points": {"grid": [{"name": "h0", "unit": "m", "linspace": [0.2, 1.0, 5]},
///                       {"name": "cor", "values": [0.5, 0.7, 0.9]}]},
///   "final_values": ["ball.r_abs[2]"]
/// }
/// ```
///
/// `points` is one of `{"grid": [axis, …]}` (an axis: `name`, optional `unit`, and `values`
/// or `linspace: [start, end, n]`; the first axis varies slowest), `{"list": {"params":
/// [{"name", "unit"}, …], "rows": [[…], …]}}`, `{"random": {"n", "seed", "params": [p, …]}}`
/// or `{"latin_hypercube": …}` alike (a `p`: `name`, optional `unit`, and one of `uniform:
/// [low, high]`, `log_uniform: [low, high]`, `normal: [mean, std_dev]`). Times are in s.
/// Unknown keys are errors (a typo does not pass silently).
#[derive(Clone, Debug, PartialEq, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SweepSpec {
    model: String,
    stop_time: Option<f64>,
    tolerance: Option<f64>,
    interval: Option<f64>,
    seed: Option<u64>,
    points: PointsSpec,
    #[serde(default)]
    final_values: Vec<String>,
}

#[derive(Clone, Debug, PartialEq, Deserialize)]
#[serde(rename_all = "snake_case", deny_unknown_fields)]
enum PointsSpec {
    Grid(Vec<AxisSpec>),
    List {
        params: Vec<NameSpec>,
        rows: Vec<Vec<f64>>,
    },
    Random(RandomSpec),
    LatinHypercube(RandomSpec),
}

#[derive(Clone, Debug, PartialEq, Deserialize)]
#[serde(deny_unknown_fields)]
struct AxisSpec {
    name: String,
    #[serde(default)]
    unit: String,
    values: Option<Vec<f64>>,
    linspace: Option<(f64, f64, usize)>,
}

#[derive(Clone, Debug, PartialEq, Deserialize)]
#[serde(deny_unknown_fields)]
struct NameSpec {
    name: String,
    #[serde(default)]
    unit: String,
}

#[derive(Clone, Debug, PartialEq, Deserialize)]
#[serde(deny_unknown_fields)]
struct RandomSpec {
    n: usize,
    #[serde(default)]
    seed: u64,
    params: Vec<RandomParamSpec>,
}

#[derive(Clone, Debug, PartialEq, Deserialize)]
#[serde(deny_unknown_fields)]
struct RandomParamSpec {
    name: String,
    #[serde(default)]
    unit: String,
    uniform: Option<(f64, f64)>,
    log_uniform: Option<(f64, f64)>,
    normal: Option<(f64, f64)>,
}

impl SweepSpec {
    /// Parses a sweep file's text; `path` names it in errors.
    pub fn from_json(text: &str, path: &str) -> Result<Self, SweepError> {
        serde_json::from_str(text).map_err(|e| SweepError::Spec {
            path: path.into(),
            reason: e.to_string(),
        })
    }

    /// Reads and parses a sweep file.
    pub fn read(path: impl AsRef<Path>) -> Result<Self, SweepError> {
        let path = path.as_ref();
        let text = std::fs::read_to_string(path).map_err(|source| SweepError::Io {
            path: path.display().to_string(),
            source,
        })?;
        Self::from_json(&text, &path.display().to_string())
    }

    /// The model name.
    pub fn model(&self) -> &str {
        &self.model
    }

    /// The parameter points the file describes.
    pub fn points(&self) -> Result<ParamPoints, SweepError> {
        match &self.points {
            PointsSpec::Grid(axes) => {
                let mut made = vec![];
                for a in axes {
                    let values = match (&a.values, a.linspace) {
                        (Some(v), None) => v.clone(),
                        (None, Some((start, end, n))) => super::linspace(start, end, n),
                        _ => return Err(SweepError::InvalidPoints {
                            reason: format!(
                                "grid axis `{}`: give either `values: [...]` or `linspace: [start, end, n]`",
                                a.name
                            ),
                        }),
                    };
                    made.push((a.name.as_str(), a.unit.as_str(), values));
                }
                ParamPoints::grid(&made)
            }
            PointsSpec::List { params, rows } => {
                let p: Vec<(&str, &str)> = params
                    .iter()
                    .map(|p| (p.name.as_str(), p.unit.as_str()))
                    .collect();
                ParamPoints::list(&p, rows.clone())
            }
            PointsSpec::Random(r) => ParamPoints::random(&r.params()?, r.n, r.seed),
            PointsSpec::LatinHypercube(r) => {
                ParamPoints::latin_hypercube(&r.params()?, r.n, r.seed)
            }
        }
    }

    /// The sweep: the registered template of [`Self::model`] with the file's points, options
    /// and final values (appended to the template's).
    pub fn sweep(&self, registry: &SweepRegistry) -> Result<Sweep, SweepError> {
        let mut sweep = registry.get(&self.model)?.clone().points(self.points()?);
        if let Some(t) = self.stop_time {
            sweep.options.stop_time = t;
        }
        if let Some(r) = self.tolerance {
            sweep.options.rtol = r;
        }
        if let Some(dt) = self.interval {
            sweep.options.interval = Some(dt);
        }
        if let Some(s) = self.seed {
            sweep.seed = s;
        }
        sweep.final_values.extend(self.final_values.iter().cloned());
        Ok(sweep)
    }
}

impl RandomSpec {
    fn params(&self) -> Result<Vec<(&str, &str, Distribution)>, SweepError> {
        self.params
            .iter()
            .map(|p| {
                let d = match (p.uniform, p.log_uniform, p.normal) {
                    (Some((low, high)), None, None) => Distribution::Uniform { low, high },
                    (None, Some((low, high)), None) => Distribution::LogUniform { low, high },
                    (None, None, Some((mean, std_dev))) => Distribution::Normal { mean, std_dev },
                    _ => {
                        return Err(SweepError::InvalidPoints {
                            reason: format!(
                                "parameter `{}`: give exactly one of `uniform: [low, high]`, `log_uniform: [low, high]`, `normal: [mean, std_dev]`",
                                p.name
                            ),
                        })
                    }
                };
                Ok((p.name.as_str(), p.unit.as_str(), d))
            })
            .collect()
    }
}

const USAGE: &str = "usage:
  <prog> run <sweep.json> [--shard I --of N] [--threads K] [--out PATH] [--arrow PATH]
      runs the sweep, or with --of N its shard I (0-based: the points I, I+N, I+2N, ...),
      and writes its table as CSV to PATH (default sweep.csv, or part-{shard}.csv for a
      shard; `{shard}` in PATH is replaced by I). Without --shard, I comes from the job
      array: HQ_TASK_ID, SLURM_ARRAY_TASK_ID, PBS_ARRAY_INDEX or PBS_ARRAYID; N may come from
      SLURM_ARRAY_TASK_COUNT. Threads: all cores, or RAYON_NUM_THREADS, or --threads.
  <prog> merge <sweep.json> --out PATH PART.csv...
      joins the parts in row order and checks that every point is there once.
  <prog> count <sweep.json>
      prints the number of points.";

/// Environment variables that job-array schedulers set to the task's index.
pub(super) const SHARD_INDEX_VARS: [&str; 4] = [
    "HQ_TASK_ID",
    "SLURM_ARRAY_TASK_ID",
    "PBS_ARRAY_INDEX",
    "PBS_ARRAYID",
];

/// The command-line front end of sharded sweeps over the models of `registry` (run, merge,
/// count; `--help` for the usage): what a user's small binary calls as its whole `main`, with
/// the process's arguments and environment. Prints a summary line on success, the error and
/// the usage on failure; the exit code says which.
pub fn sweep_main(registry: &SweepRegistry) -> std::process::ExitCode {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let env = |k: &str| std::env::var(k).ok();
    match run_cli(registry, &args, &env) {
        Ok(msg) => {
            println!("{msg}");
            std::process::ExitCode::SUCCESS
        }
        Err(e) => {
            eprintln!("error: {e}");
            std::process::ExitCode::FAILURE
        }
    }
}

fn usage(reason: impl Into<String>) -> SweepError {
    SweepError::Usage {
        reason: reason.into(),
        usage: USAGE,
    }
}

/// [`sweep_main`] on given arguments (without the program name) and environment.
pub(crate) fn run_cli(
    registry: &SweepRegistry,
    args: &[String],
    env: &dyn Fn(&str) -> Option<String>,
) -> Result<String, SweepError> {
    let mut opts = std::collections::HashMap::new();
    let mut positional = vec![];
    let mut it = args.iter();
    while let Some(a) = it.next() {
        match a.as_str() {
            "-h" | "--help" => return Ok(USAGE.to_string()),
            "--shard" | "--of" | "--threads" | "--out" | "--arrow" => {
                let v = it
                    .next()
                    .ok_or_else(|| usage(format!("`{a}` needs a value")))?;
                opts.insert(a.as_str(), v.clone());
            }
            s if s.starts_with("--") => return Err(usage(format!("unknown option `{s}`"))),
            _ => positional.push(a.clone()),
        }
    }
    let number = |key: &str, text: &str| {
        text.trim()
            .parse::<usize>()
            .map_err(|_| usage(format!("{key} `{text}` is not a non-negative integer")))
    };
    let (cmd, file, rest) = match positional.as_slice() {
        [cmd, file, rest @ ..] => (cmd.as_str(), file, rest),
        [cmd] => return Err(usage(format!("`{cmd}` needs a sweep file"))),
        [] => return Err(usage("no command given")),
    };
    let spec = SweepSpec::read(file)?;
    match cmd {
        "count" => Ok(spec.points()?.len().to_string()),
        "run" => {
            if let Some(extra) = rest.first() {
                return Err(usage(format!("unexpected argument `{extra}`")));
            }
            let mut sweep = spec.sweep(registry)?;
            if let Some(t) = opts.get("--threads") {
                sweep = sweep.threads(number("--threads", t)?);
            }
            let of = match opts.get("--of") {
                Some(v) => Some(number("--of", v)?),
                None => env("SLURM_ARRAY_TASK_COUNT")
                    .map(|v| number("SLURM_ARRAY_TASK_COUNT", &v))
                    .transpose()?,
            };
            let shard = match (opts.get("--shard"), of) {
                (Some(v), Some(_)) => Some(number("--shard", v)?),
                (Some(_), None) => {
                    return Err(usage("--shard needs --of N (the number of shards)"))
                }
                (None, Some(_)) => {
                    let (var, v) = SHARD_INDEX_VARS
                        .iter()
                        .find_map(|k| env(k).map(|v| (*k, v)))
                        .ok_or_else(|| {
                            usage(format!(
                                "--of is given but no shard index: pass --shard I or run in a job array ({})",
                                SHARD_INDEX_VARS.join(", ")
                            ))
                        })?;
                    Some(number(var, &v)?)
                }
                (None, None) => None,
            };
            let start = std::time::Instant::now();
            let (table, default_out) = match (shard, of) {
                (Some(i), Some(n)) => (sweep.run_shard(i, n)?, "part-{shard}.csv"),
                _ => (sweep.run()?, "sweep.csv"),
            };
            let secs = start.elapsed().as_secs_f64();
            let shard_text = shard.map_or(String::new(), |i| i.to_string());
            let out = opts
                .get("--out")
                .map_or(default_out, String::as_str)
                .replace("{shard}", &shard_text);
            write_table(&table, &out)?;
            if let Some(path) = opts.get("--arrow") {
                write_arrow(&table, &path.replace("{shard}", &shard_text))?;
            }
            let failed = table.failures().count();
            Ok(format!(
                "{}{} runs ({} ok, {failed} failed) in {secs:.2} s -> {out}",
                match (shard, of) {
                    (Some(i), Some(n)) => format!("shard {i} of {n}: "),
                    _ => String::new(),
                },
                table.rows.len(),
                table.rows.len() - failed,
            ))
        }
        "merge" => {
            let out = opts
                .get("--out")
                .ok_or_else(|| usage("merge needs --out PATH"))?;
            if rest.is_empty() {
                return Err(usage("merge needs the part files"));
            }
            let parts = rest
                .iter()
                .map(SweepTable::read_csv)
                .collect::<Result<Vec<_>, _>>()?;
            let n = spec.points()?.len();
            let table = SweepTable::merge(parts, Some(n))?;
            write_table(&table, out)?;
            if let Some(path) = opts.get("--arrow") {
                write_arrow(&table, path)?;
            }
            Ok(format!(
                "merged {} parts: {n} rows ({} failed) -> {out}",
                rest.len(),
                table.failures().count()
            ))
        }
        other => Err(usage(format!("unknown command `{other}`"))),
    }
}

/// Writes `table` as CSV to `path`, making its directory first (a job array's parts directory
/// need not exist).
fn write_table(table: &SweepTable, path: &str) -> Result<(), SweepError> {
    if let Some(dir) = Path::new(path)
        .parent()
        .filter(|d| !d.as_os_str().is_empty())
    {
        std::fs::create_dir_all(dir).map_err(|source| SweepError::Io {
            path: dir.display().to_string(),
            source,
        })?;
    }
    table.write_csv(path)
}

#[cfg(feature = "arrow")]
fn write_arrow(table: &SweepTable, path: &str) -> Result<(), SweepError> {
    table.write_arrow(path)
}

#[cfg(not(feature = "arrow"))]
fn write_arrow(_: &SweepTable, path: &str) -> Result<(), SweepError> {
    Err(SweepError::Export {
        path: path.into(),
        reason: "Arrow export needs the cargo feature `arrow` (`--features arrow`)".into(),
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn parse(json: &str) -> Result<SweepSpec, SweepError> {
        SweepSpec::from_json(json, "test.json")
    }

    #[test]
    fn spec_points_of_each_kind() {
        let s = parse(
            r#"{"model": "m", "points": {"grid": [{"name": "h", "unit": "m", "linspace": [0, 1, 3]},
                {"name": "c", "values": [5, 6]}]}}"#,
        )
        .unwrap();
        let p = s.points().unwrap();
        assert_eq!(p.len(), 6);
        assert_eq!(p.row(3), Some(&[0.5, 6.0][..]));
        assert_eq!(p.units(), ["m", ""]);
        let s = parse(
            r#"{"model": "m", "points": {"latin_hypercube": {"n": 5, "seed": 3,
                "params": [{"name": "v", "uniform": [1, 2]}, {"name": "a", "normal": [0, 1]}]}}}"#,
        )
        .unwrap();
        assert_eq!(s.points().unwrap().len(), 5);
        let s = parse(
            r#"{"model": "m", "points": {"list": {"params": [{"name": "a"}], "rows": [[1], [2]]}}}"#,
        )
        .unwrap();
        assert_eq!(s.points().unwrap().row(1), Some(&[2.0][..]));
    }

    #[test]
    fn spec_errors_name_the_key() {
        let e = parse(r#"{"model": "m", "pionts": {}}"#)
            .unwrap_err()
            .to_string();
        assert!(e.contains("pionts") && e.contains("test.json"), "{e}");
        let s = parse(
            r#"{"model": "m", "points": {"random": {"n": 2, "params": [{"name": "v", "uniform": [1, 2], "normal": [0, 1]}]}}}"#,
        )
        .unwrap();
        assert!(s.points().unwrap_err().to_string().contains("exactly one"));
        let r = SweepRegistry::new().add("bouncing", crate::Sweep::new(|_| Err("no".into())));
        let e = r.get("bounzing").unwrap_err().to_string();
        assert!(e.contains("did you mean `bouncing`"), "{e}");
    }

    #[test]
    fn cli_usage_errors() {
        let r = SweepRegistry::new();
        let none = |_: &str| None;
        let args = |a: &[&str]| a.iter().map(|s| s.to_string()).collect::<Vec<_>>();
        let e = run_cli(&r, &args(&[]), &none).unwrap_err().to_string();
        assert!(e.contains("no command") && e.contains("usage"), "{e}");
        let e = run_cli(&r, &args(&["run", "x.json", "--bogus"]), &none)
            .unwrap_err()
            .to_string();
        assert!(e.contains("unknown option `--bogus`"), "{e}");
        assert!(run_cli(&r, &args(&["--help"]), &none)
            .unwrap()
            .contains("merge"));
    }
}
