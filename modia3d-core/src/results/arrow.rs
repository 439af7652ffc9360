//! Results stage (export, feature `arrow`): signals as an Apache Arrow IPC file — one `Float64`
//! column per time and signal component, the unit in each field's metadata (`"unit"`). Python
//! reads it with `pyarrow.feather.read_table(path)` or `pandas.read_feather(path)`, Julia with
//! `Arrow.Table(path)`. Reads only the result.

use super::{ResultError, SimulationResult};
use arrow_array::{ArrayRef, Float64Array, RecordBatch};
use arrow_schema::{DataType, Field, Schema};
use std::collections::HashMap;
use std::sync::Arc;

impl SimulationResult {
    /// Writes time and the signals `names` (as [`Self::write_csv_signals`]: any name
    /// [`Self::signal`] accepts; columns `name` or `name[i]` per component, `time` first) as an
    /// Arrow IPC file (the Feather v2 format): `pandas.read_feather(path)`,
    /// `pyarrow.feather.read_table(path)`, Julia `Arrow.Table(path)`. Each column is `Float64`
    /// with its unit in the field metadata under `"unit"` (`"s"`, `"m"`, …). Pass
    /// [`Self::default_export_signals`] for the CSV's default set. Needs the cargo feature
    /// `arrow`.
    pub fn write_arrow<S: AsRef<str>>(
        &self,
        path: impl AsRef<std::path::Path>,
        names: &[S],
    ) -> Result<(), ResultError> {
        let path = path.as_ref();
        let cols = self.columns(names)?;
        let export = |reason: String| ResultError::Export {
            path: path.display().to_string(),
            reason,
        };
        let (fields, arrays) = cols
            .into_iter()
            .map(|c| {
                (
                    unit_field(&c.name, c.unit),
                    Arc::new(Float64Array::from(c.values)) as ArrayRef,
                )
            })
            .unzip();
        write_ipc(path, fields, arrays).map_err(|e| match e {
            IpcError::Io(source) => ResultError::Io {
                path: path.display().to_string(),
                source,
            },
            IpcError::Arrow(reason) => export(reason),
        })
    }
}

/// A non-nullable `Float64` field with its unit in the metadata under `"unit"`.
pub(crate) fn unit_field(name: &str, unit: &str) -> Field {
    Field::new(name, DataType::Float64, false)
        .with_metadata(HashMap::from([("unit".to_string(), unit.to_string())]))
}

/// Why an Arrow IPC file could not be written.
pub(crate) enum IpcError {
    /// The file could not be created.
    Io(std::io::Error),
    /// Arrow rejected the columns or failed to write.
    Arrow(String),
}

/// Writes one record batch of `fields` and their `arrays` (equal lengths) as an Arrow IPC
/// file at `path`.
pub(crate) fn write_ipc(
    path: &std::path::Path,
    fields: Vec<Field>,
    arrays: Vec<ArrayRef>,
) -> Result<(), IpcError> {
    let arrow = |e: arrow_schema::ArrowError| IpcError::Arrow(e.to_string());
    let schema = Arc::new(Schema::new(fields));
    let batch = RecordBatch::try_new(schema.clone(), arrays).map_err(arrow)?;
    let file = std::fs::File::create(path).map_err(IpcError::Io)?;
    let mut w = arrow_ipc::writer::FileWriter::try_new(std::io::BufWriter::new(file), &schema)
        .map_err(arrow)?;
    w.write(&batch).map_err(arrow)?;
    w.finish().map_err(arrow)
}

#[cfg(test)]
mod tests {
    use crate::scene::{Joint, JointKind, Object3D, SceneDesc, Solid};
    use crate::Shape;
    use crate::SimOptions;
    use arrow_array::cast::AsArray;
    use arrow_array::types::Float64Type;

    /// A pendulum's file reads back with arrow's own reader: same column names, units and
    /// values, bit for bit (the format stores the f64s as they are).
    #[test]
    fn arrow_file_reads_back_equal() {
        let mut s = SceneDesc::new();
        s.add(Object3D::new("world").scene(Default::default()))
            .add(
                Object3D::new("bob")
                    .solid(Solid::new(Shape::Sphere { diameter: 0.1 }).material("Steel")),
            )
            .add_joint(Joint::new(
                "rev",
                "world",
                "bob",
                JointKind::Revolute {
                    axis: nalgebra::Vector3::y(),
                    phi: 0.5,
                    w: 0.0,
                },
            ));
        let res = s
            .build()
            .unwrap()
            .simulate(&SimOptions::new(0.5).interval(0.05).progress(false))
            .unwrap();
        let names = ["rev.phi", "bob.r_abs"];
        let path = std::env::temp_dir().join(format!("modia3d-{}.arrow", std::process::id()));
        res.write_arrow(&path, &names).unwrap();
        let file = std::fs::File::open(&path).unwrap();
        let reader = arrow_ipc::reader::FileReader::try_new(file, None).unwrap();
        let schema = reader.schema();
        let batches: Vec<_> = reader.map(|b| b.unwrap()).collect();
        std::fs::remove_file(&path).ok();
        assert_eq!(batches.len(), 1);
        let b = batches.first().unwrap();
        let col = |i: usize| b.column(i).as_primitive::<Float64Type>().values().to_vec();
        let expect_names = [
            "time",
            "rev.phi",
            "bob.r_abs[0]",
            "bob.r_abs[1]",
            "bob.r_abs[2]",
        ];
        let expect_units = ["s", "rad", "m", "m", "m"];
        for (i, (n, u)) in expect_names.iter().zip(expect_units).enumerate() {
            assert_eq!(schema.field(i).name(), n);
            assert_eq!(schema.field(i).metadata().get("unit").unwrap(), u);
        }
        assert_eq!(col(0), res.time());
        assert_eq!(col(1), res.signal("rev.phi").unwrap().values());
        let r = res.signal("bob.r_abs").unwrap();
        for k in 0..3 {
            assert_eq!(col(2 + k), r.component(k));
        }
    }

    /// A sweep table (`SweepTable::write_arrow`, which shares this module's writer) reads back
    /// with its index, parameters with units, status words, outputs (NaN kept) and messages.
    #[test]
    fn sweep_table_arrow_reads_back() {
        use crate::{ColumnInfo, RunError, SweepRow, SweepTable};
        use arrow_array::types::UInt64Type;
        let col = |n: &str, u: &str| ColumnInfo {
            name: n.into(),
            unit: u.into(),
        };
        let table = SweepTable {
            params: vec![col("h0", "m")],
            outputs: vec![col("t_end", "s")],
            rows: vec![
                SweepRow {
                    index: 0,
                    params: vec![0.25],
                    outputs: vec![1.5],
                    error: None,
                },
                SweepRow {
                    index: 1,
                    params: vec![-1.0],
                    outputs: vec![f64::NAN],
                    error: Some(RunError::Build("bad, \"very\" bad".into())),
                },
            ],
        };
        let path = std::env::temp_dir().join(format!("modia3d-sweep-{}.arrow", std::process::id()));
        table.write_arrow(&path).unwrap();
        let reader =
            arrow_ipc::reader::FileReader::try_new(std::fs::File::open(&path).unwrap(), None)
                .unwrap();
        let schema = reader.schema();
        let b = reader.map(|b| b.unwrap()).next().unwrap();
        std::fs::remove_file(&path).ok();
        let names: Vec<&str> = schema.fields().iter().map(|f| f.name().as_str()).collect();
        assert_eq!(names, ["index", "h0", "status", "t_end", "message"]);
        assert_eq!(schema.field(1).metadata().get("unit").unwrap(), "m");
        let idx = b.column(0).as_primitive::<UInt64Type>().values().to_vec();
        assert_eq!(idx, [0, 1]);
        let h0 = b.column(1).as_primitive::<Float64Type>().values().to_vec();
        assert_eq!(h0, [0.25, -1.0]);
        let status = b.column(2).as_string::<i32>();
        assert_eq!((status.value(0), status.value(1)), ("ok", "build"));
        let t = b.column(3).as_primitive::<Float64Type>().values().to_vec();
        assert_eq!(t.first(), Some(&1.5));
        assert!(t.get(1).is_some_and(|v| v.is_nan()));
        assert_eq!(b.column(4).as_string::<i32>().value(1), "bad, \"very\" bad");
    }
}
