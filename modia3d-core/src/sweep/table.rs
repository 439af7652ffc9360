//! Sweep stage, the table: one row per run (its index, parameter values, status, outputs and
//! error message), written as CSV (and Arrow IPC with the `arrow` feature), read back exactly,
//! and merged from the parts that shards wrote.
#![deny(clippy::indexing_slicing)]

use super::SweepError;
use std::io::Write;
use std::path::Path;

/// Why a run of a sweep has no (or not all) outputs. The message is the typed error's text
/// (kept as text so that a table read back from CSV compares equal to the one written).
#[derive(thiserror::Error, Clone, Debug, PartialEq, Eq)]
pub enum RunError {
    /// The model constructor returned an error (e.g. a scene error: a negative mass).
    #[error("{0}")]
    Build(String),
    /// The simulation failed (a [`SimError`](crate::SimError); the row's `t_end` is how far it
    /// got).
    #[error("{0}")]
    Simulation(String),
    /// An output could not be computed: an unknown signal, a signal with several components,
    /// or a metric closure's error.
    #[error("{0}")]
    Output(String),
    /// A user closure (constructor, metric) or the simulation panicked; the panic was caught
    /// (its message still goes to standard error through the panic hook). A force law's panic
    /// is a [`Simulation`](RunError::Simulation) error: the solver catches it.
    #[error("{0}")]
    Panic(String),
}

impl RunError {
    /// The status word of a failed row: `build`, `simulation`, `output` or `panic`.
    pub fn status(&self) -> &'static str {
        match self {
            RunError::Build(_) => "build",
            RunError::Simulation(_) => "simulation",
            RunError::Output(_) => "output",
            RunError::Panic(_) => "panic",
        }
    }

    fn from_status(status: &str, message: String) -> Option<Self> {
        Some(match status {
            "build" => RunError::Build(message),
            "simulation" => RunError::Simulation(message),
            "output" => RunError::Output(message),
            "panic" => RunError::Panic(message),
            _ => return None,
        })
    }
}

/// One run of a sweep.
#[derive(Clone, Debug)]
pub struct SweepRow {
    /// The parameter point's index (row `i` of the whole sweep is point `i`).
    pub index: usize,
    /// Parameter values, in the order of [`SweepTable::params`].
    pub params: Vec<f64>,
    /// Outputs in the order of [`SweepTable::outputs`]: the final values, the metrics, and
    /// last `t_end` \[s\] (the time the run reached); NaN where not computed.
    pub outputs: Vec<f64>,
    /// `None` for a run that succeeded with every output, else why not.
    pub error: Option<RunError>,
}

impl SweepRow {
    /// `ok`, or the [`RunError::status`] word of the failure.
    pub fn status(&self) -> &'static str {
        self.error.as_ref().map_or("ok", RunError::status)
    }

    /// The error message; empty for a successful run.
    pub fn message(&self) -> String {
        self.error
            .as_ref()
            .map(|e| e.to_string())
            .unwrap_or_default()
    }
}

impl PartialEq for SweepRow {
    /// Equal bit for bit (so NaN equals NaN and 0.0 differs from −0.0).
    fn eq(&self, other: &Self) -> bool {
        let bits = |v: &[f64]| v.iter().map(|x| x.to_bits()).collect::<Vec<_>>();
        self.index == other.index
            && bits(&self.params) == bits(&other.params)
            && bits(&self.outputs) == bits(&other.outputs)
            && self.error == other.error
    }
}

/// A column of a sweep table: a name and its unit (`""` when it has none).
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct ColumnInfo {
    /// Column name: a parameter, a signal (`"ball.r_abs[2]"`) or a metric.
    pub name: String,
    /// Unit, e.g. `"m"`; `""` when unknown or none.
    pub unit: String,
}

/// The result of a sweep or of a shard of it: a row per run, in index order.
///
/// CSV layout (what [`Self::write_csv`] writes and [`Self::read_csv`] reads): a header
/// `index,<param> [unit],…,status,<output> [unit],…,message` (no ` [unit]` where the unit is
/// empty), then one line per run: values in Rust's shortest exact form (`1.5e0`, `NaN`; they
/// read back bit for bit), `status` `ok` or the [`RunError::status`] word, the error message
/// (quoted as CSV requires) or nothing.
#[derive(Clone, Debug, PartialEq)]
pub struct SweepTable {
    /// The parameter columns.
    pub params: Vec<ColumnInfo>,
    /// The output columns: final values, metrics, `t_end` \[s\].
    pub outputs: Vec<ColumnInfo>,
    /// One row per run, by increasing index.
    pub rows: Vec<SweepRow>,
}

impl SweepTable {
    /// The rows whose run failed.
    pub fn failures(&self) -> impl Iterator<Item = &SweepRow> {
        self.rows.iter().filter(|r| r.error.is_some())
    }

    /// The values of the output or parameter column `name`, one per row (NaN where a run did
    /// not produce it); `None` without such a column.
    pub fn column(&self, name: &str) -> Option<Vec<f64>> {
        if let Some(k) = self.params.iter().position(|c| c.name == name) {
            return Some(self.rows.iter().map(|r| at(&r.params, k)).collect());
        }
        let k = self.outputs.iter().position(|c| c.name == name)?;
        Some(self.rows.iter().map(|r| at(&r.outputs, k)).collect())
    }

    /// The table as CSV text (see the type's docs for the layout).
    pub fn to_csv(&self) -> String {
        let head = |c: &ColumnInfo| {
            if c.unit.is_empty() {
                c.name.clone()
            } else {
                format!("{} [{}]", c.name, c.unit)
            }
        };
        let mut header = vec!["index".to_string()];
        header.extend(self.params.iter().map(head));
        header.push("status".into());
        header.extend(self.outputs.iter().map(head));
        header.push("message".into());
        let mut out = header.join(",");
        out.push('\n');
        for r in &self.rows {
            let mut fields = vec![r.index.to_string()];
            fields.extend(r.params.iter().map(|v| format!("{v:e}")));
            fields.push(r.status().into());
            fields.extend(r.outputs.iter().map(|v| format!("{v:e}")));
            fields.push(csv_quote(&r.message()));
            out.push_str(&fields.join(","));
            out.push('\n');
        }
        out
    }

    /// Writes the table as CSV to `path`.
    pub fn write_csv(&self, path: impl AsRef<Path>) -> Result<(), SweepError> {
        let path = path.as_ref();
        let io = |source| SweepError::Io {
            path: path.display().to_string(),
            source,
        };
        let mut f = std::fs::File::create(path).map_err(io)?;
        f.write_all(self.to_csv().as_bytes()).map_err(io)
    }

    /// Reads a table [`Self::write_csv`] wrote.
    pub fn read_csv(path: impl AsRef<Path>) -> Result<Self, SweepError> {
        let path = path.as_ref();
        let text = std::fs::read_to_string(path).map_err(|source| SweepError::Io {
            path: path.display().to_string(),
            source,
        })?;
        Self::from_csv(&text).map_err(|(line, reason)| SweepError::Table {
            path: path.display().to_string(),
            line,
            reason,
        })
    }

    /// Parses CSV text in the layout of [`Self::to_csv`]; `Err((line, reason))`.
    fn from_csv(text: &str) -> Result<Self, (usize, String)> {
        let records = csv_records(text)?;
        let mut it = records.into_iter();
        let (_, header) = it.next().ok_or((1, "the file is empty".to_string()))?;
        let status_at = header.iter().position(|h| h == "status");
        let (Some(status_at), Some("index"), Some("message")) = (
            status_at,
            header.first().map(String::as_str),
            header.last().map(String::as_str),
        ) else {
            return Err((
                1,
                "not a sweep table: the header must be `index,<params>,status,<outputs>,message`"
                    .into(),
            ));
        };
        let column = |h: &String| match h.strip_suffix(']').and_then(|s| s.rsplit_once(" [")) {
            Some((name, unit)) => ColumnInfo {
                name: name.into(),
                unit: unit.into(),
            },
            None => ColumnInfo {
                name: h.clone(),
                unit: String::new(),
            },
        };
        let params: Vec<ColumnInfo> = header
            .get(1..status_at)
            .unwrap_or_default()
            .iter()
            .map(column)
            .collect();
        let outputs: Vec<ColumnInfo> = header
            .get(status_at + 1..header.len() - 1)
            .unwrap_or_default()
            .iter()
            .map(column)
            .collect();
        let mut rows = vec![];
        for (line, rec) in it {
            if rec.len() != header.len() {
                return Err((
                    line,
                    format!("{} fields for {} columns", rec.len(), header.len()),
                ));
            }
            let num = |s: &str| {
                s.parse::<f64>()
                    .map_err(|_| (line, format!("`{s}` is not a number")))
            };
            let nums = |range: std::ops::Range<usize>| {
                rec.get(range)
                    .unwrap_or_default()
                    .iter()
                    .map(|s| num(s))
                    .collect::<Result<Vec<f64>, _>>()
            };
            let index = rec
                .first()
                .and_then(|s| s.parse::<usize>().ok())
                .ok_or((line, "the index is not a non-negative integer".to_string()))?;
            let status = rec.get(status_at).map(String::as_str).unwrap_or_default();
            let message = rec.last().cloned().unwrap_or_default();
            let error = match status {
                "ok" => None,
                s => Some(RunError::from_status(s, message).ok_or((
                    line,
                    format!(
                        "unknown status `{s}`: expected ok, build, simulation, output or panic"
                    ),
                ))?),
            };
            rows.push(SweepRow {
                index,
                params: nums(1..status_at)?,
                outputs: nums(status_at + 1..header.len() - 1)?,
                error,
            });
        }
        Ok(SweepTable {
            params,
            outputs,
            rows,
        })
    }

    /// Joins the tables of shards into one, rows by index. The parts must have the same
    /// columns, no index twice, and together the indices `0..n` without a gap (`expected`:
    /// also `n` itself, when known, e.g. from the sweep file).
    pub fn merge(
        parts: Vec<SweepTable>,
        expected: Option<usize>,
    ) -> Result<SweepTable, SweepError> {
        let merge_err = |reason: String| SweepError::Merge { reason };
        let mut parts = parts.into_iter();
        let mut all = parts
            .next()
            .ok_or_else(|| merge_err("no parts given".into()))?;
        for (k, p) in parts.enumerate() {
            if p.params != all.params || p.outputs.len() != all.outputs.len() {
                return Err(merge_err(format!(
                    "part {} has other columns than part 0: were they made from the same sweep file?",
                    k + 1
                )));
            }
            for (mine, theirs) in all.outputs.iter_mut().zip(&p.outputs) {
                if mine.name != theirs.name {
                    return Err(merge_err(format!(
                        "part {} has output `{}` where part 0 has `{}`",
                        k + 1,
                        theirs.name,
                        mine.name
                    )));
                }
                // A unit is known from the first successful run of a part.
                if mine.unit.is_empty() {
                    mine.unit.clone_from(&theirs.unit);
                }
            }
            all.rows.extend(p.rows);
        }
        all.rows.sort_by_key(|r| r.index);
        for (i, r) in all.rows.iter().enumerate() {
            if r.index != i {
                return Err(merge_err(if r.index < i {
                    format!("row {} is in two parts", r.index)
                } else {
                    format!("row {i} is missing: did a shard fail or was its part left out?")
                }));
            }
        }
        if let Some(n) = expected.filter(|&n| n != all.rows.len()) {
            return Err(merge_err(format!(
                "the parts hold {} rows of the sweep's {n}: rows {}..{n} are missing",
                all.rows.len(),
                all.rows.len()
            )));
        }
        Ok(all)
    }

    /// Writes the table as an Arrow IPC file (the Feather v2 format; `pandas.read_feather`):
    /// `index` (UInt64), parameter and output columns (Float64, the unit in the field
    /// metadata under `"unit"`), `status` and `message` (Utf8). Needs the cargo feature `arrow`.
    #[cfg(feature = "arrow")]
    pub fn write_arrow(&self, path: impl AsRef<Path>) -> Result<(), SweepError> {
        use crate::results::arrow::{unit_field, write_ipc, IpcError};
        use arrow_array::{ArrayRef, Float64Array, StringArray, UInt64Array};
        use arrow_schema::{DataType, Field};
        use std::sync::Arc;
        let path = path.as_ref();
        let float = |c: &ColumnInfo, values: Vec<f64>| {
            (
                unit_field(&c.name, &c.unit),
                Arc::new(Float64Array::from(values)) as ArrayRef,
            )
        };
        let text = |name: &str, values: Vec<String>| {
            (
                Field::new(name, DataType::Utf8, false),
                Arc::new(StringArray::from(values)) as ArrayRef,
            )
        };
        let mut cols = vec![(
            Field::new("index", DataType::UInt64, false),
            Arc::new(UInt64Array::from(
                self.rows.iter().map(|r| r.index as u64).collect::<Vec<_>>(),
            )) as ArrayRef,
        )];
        for (k, c) in self.params.iter().enumerate() {
            cols.push(float(
                c,
                self.rows.iter().map(|r| at(&r.params, k)).collect(),
            ));
        }
        cols.push(text(
            "status",
            self.rows.iter().map(|r| r.status().to_string()).collect(),
        ));
        for (k, c) in self.outputs.iter().enumerate() {
            cols.push(float(
                c,
                self.rows.iter().map(|r| at(&r.outputs, k)).collect(),
            ));
        }
        cols.push(text(
            "message",
            self.rows.iter().map(SweepRow::message).collect(),
        ));
        let (fields, arrays) = cols.into_iter().unzip();
        write_ipc(path, fields, arrays).map_err(|e| match e {
            IpcError::Io(source) => SweepError::Io {
                path: path.display().to_string(),
                source,
            },
            IpcError::Arrow(reason) => SweepError::Export {
                path: path.display().to_string(),
                reason,
            },
        })
    }
}

fn at(v: &[f64], k: usize) -> f64 {
    v.get(k).copied().unwrap_or(f64::NAN)
}

/// A CSV field: quoted (quotes doubled) when it holds a comma, quote or line break.
fn csv_quote(s: &str) -> String {
    if s.contains([',', '"', '\n', '\r']) {
        format!("\"{}\"", s.replace('"', "\"\""))
    } else {
        s.to_string()
    }
}

/// CSV records, each with the line it starts on.
type Records = Vec<(usize, Vec<String>)>;

/// The records of CSV text (RFC 4180: quoted fields may hold commas, doubled quotes and line
/// breaks), each with the line it starts on; `Err((line, reason))` for an unclosed quote.
fn csv_records(text: &str) -> Result<Records, (usize, String)> {
    let mut records = vec![];
    let mut fields = vec![];
    let mut field = String::new();
    let (mut line, mut start_line) = (1, 1);
    let mut quoted = false;
    let mut chars = text.chars().peekable();
    while let Some(c) = chars.next() {
        match (quoted, c) {
            (true, '"') if chars.peek() == Some(&'"') => {
                chars.next();
                field.push('"');
            }
            (true, '"') => quoted = false,
            (false, '"') if field.is_empty() => quoted = true,
            (false, ',') => fields.push(std::mem::take(&mut field)),
            (false, '\r') => {}
            (false, '\n') => {
                fields.push(std::mem::take(&mut field));
                records.push((start_line, std::mem::take(&mut fields)));
                line += 1;
                start_line = line;
            }
            (_, c) => {
                if c == '\n' {
                    line += 1;
                }
                field.push(c);
            }
        }
    }
    if quoted {
        return Err((start_line, "a quoted field is not closed".into()));
    }
    if !field.is_empty() || !fields.is_empty() {
        fields.push(field);
        records.push((start_line, fields));
    }
    Ok(records)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn table() -> SweepTable {
        let col = |n: &str, u: &str| ColumnInfo {
            name: n.into(),
            unit: u.into(),
        };
        SweepTable {
            params: vec![col("h0", "m"), col("cor", "")],
            outputs: vec![col("ball.r_abs[2]", "m"), col("t_end", "s")],
            rows: vec![
                SweepRow {
                    index: 0,
                    params: vec![0.1, -0.0],
                    outputs: vec![1.0 / 3.0, 1.5],
                    error: None,
                },
                SweepRow {
                    index: 1,
                    params: vec![1e-300, 7.0],
                    outputs: vec![f64::NAN, f64::INFINITY],
                    error: Some(RunError::Build(
                        "scene error:\n  object `ball`: mass -1 kg, \"must\" be > 0".into(),
                    )),
                },
            ],
        }
    }

    /// Written and read back, a table is equal bit for bit (NaN, −0.0, 1e-300, a message with
    /// commas, quotes and a line break included).
    #[test]
    fn csv_round_trip_is_exact() {
        let t = table();
        let back = SweepTable::from_csv(&t.to_csv()).unwrap();
        assert_eq!(back, t);
        assert!(t.to_csv().starts_with(
            "index,h0 [m],cor,status,ball.r_abs[2] [m],t_end [s],message\n0,1e-1,-0e0,ok,"
        ));
    }

    #[test]
    fn merge_checks_gaps_duplicates_and_columns() {
        let t = table();
        let mut a = t.clone();
        let mut b = t.clone();
        b.rows = a.rows.split_off(1);
        assert_eq!(
            SweepTable::merge(vec![b.clone(), a.clone()], Some(2)).unwrap(),
            t
        );
        let e = SweepTable::merge(vec![b.clone()], None)
            .unwrap_err()
            .to_string();
        assert!(e.contains("row 0 is missing"), "{e}");
        let e = SweepTable::merge(vec![a.clone(), a.clone(), b.clone()], None)
            .unwrap_err()
            .to_string();
        assert!(e.contains("row 0 is in two parts"), "{e}");
        let e = SweepTable::merge(vec![a.clone(), b.clone()], Some(3))
            .unwrap_err()
            .to_string();
        assert!(e.contains("rows 2..3 are missing"), "{e}");
        let mut c = b;
        c.params.pop();
        assert!(SweepTable::merge(vec![a, c], None).is_err());
        let e = SweepTable::from_csv("index,a,status,message\n0,x,ok,\n").unwrap_err();
        assert_eq!(e.0, 2);
    }
}
