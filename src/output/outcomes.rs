//! The scalar outcomes of runs, for tools that compare many runs (`satflock campaign`, `satflock
//! compare`): every number of a `summary.json` by dotted name, and a table of runs (one row per run:
//! text columns such as the law and status, and number columns such as the outcomes) written as Parquet
//! or read back.
//!
//! Names: a number at `a.b.c` of the summary is the column `a.b.c`; an array of at most
//! [`MAX_VECTOR_LEN`] numbers (a vector such as `r_o_m` or a range such as `plane_theta_p_deg_range`)
//! gives `a.b.0`, `a.b.1`, …; longer arrays (per-satellite values) are left out, and so are `metadata`,
//! text and `null` (a value that does not exist). Booleans are 0 or 1.

use std::collections::BTreeMap;
use std::fs::File;
use std::path::Path;
use std::sync::Arc;

use arrow_array::{Array, ArrayRef, Float64Array, RecordBatch, StringArray, UInt64Array};
use arrow_schema::{DataType, Field, Schema};
use parquet::arrow::arrow_reader::ParquetRecordBatchReaderBuilder;
use parquet::arrow::ArrowWriter;
use parquet::basic::Compression;
use parquet::file::properties::WriterProperties;

use super::run_data::RunDataError;

/// Longest array of numbers kept as components (longer arrays are per-satellite values).
pub const MAX_VECTOR_LEN: usize = 6;

/// Keys of a summary that are not outcomes (`timing`, the engine's stage split, measures the machine and
/// differs between any two executions of one run).
const NOT_OUTCOMES: &[&str] = &["metadata", "seed", "threads", "timing"];

/// Every scalar outcome of a `summary.json`, by dotted name, sorted by name.
pub fn scalar_outcomes(summary: &serde_json::Value) -> Vec<(String, f64)> {
    let mut out = Vec::new();
    if let serde_json::Value::Object(map) = summary {
        for (key, value) in map {
            if !NOT_OUTCOMES.contains(&key.as_str()) {
                flatten(key, value, &mut out);
            }
        }
    }
    out
}

fn flatten(name: &str, value: &serde_json::Value, out: &mut Vec<(String, f64)>) {
    use serde_json::Value;
    match value {
        Value::Number(n) => {
            if let Some(v) = n.as_f64() {
                out.push((name.to_string(), v));
            }
        }
        Value::Bool(b) => out.push((name.to_string(), f64::from(u8::from(*b)))),
        Value::Array(items)
            if items.len() <= MAX_VECTOR_LEN && items.iter().all(Value::is_number) =>
        {
            for (k, item) in items.iter().enumerate() {
                flatten(&format!("{name}.{k}"), item, out);
            }
        }
        Value::Object(map) => {
            for (key, value) in map {
                flatten(&format!("{name}.{key}"), value, out);
            }
        }
        _ => {}
    }
}

/// A table of runs: text columns, integer columns, then number columns (NaN: no value, written as
/// null), one row each.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct RunTable {
    /// Text columns by name (e.g. `law`, `status`, `error`), in order.
    pub text: Vec<(String, Vec<String>)>,
    /// Integer columns by name (e.g. `seed`: exact, where a double rounds integers beyond 2^53), in
    /// order; [`RunTable::from_rows`] makes none, [`RunTable::push_integers`] adds one.
    pub integers: Vec<(String, Vec<u64>)>,
    /// Number columns by name (parameters, seed, outcomes), in order.
    pub numbers: Vec<(String, Vec<f64>)>,
}

impl RunTable {
    /// A table of `rows` runs from per-run maps: every name any run has becomes a column (a run without
    /// it has NaN / an empty text), columns in the order of first appearance.
    pub fn from_rows(
        text_rows: &[Vec<(String, String)>],
        number_rows: &[Vec<(String, f64)>],
    ) -> Self {
        fn columns<T: Clone>(rows: &[Vec<(String, T)>], missing: T) -> Vec<(String, Vec<T>)> {
            let mut order: Vec<String> = Vec::new();
            let mut seen = BTreeMap::new();
            for row in rows {
                for (name, _) in row {
                    if seen.insert(name.clone(), ()).is_none() {
                        order.push(name.clone());
                    }
                }
            }
            order
                .into_iter()
                .map(|name| {
                    let values = rows
                        .iter()
                        .map(|row| {
                            row.iter()
                                .find(|(n, _)| *n == name)
                                .map_or_else(|| missing.clone(), |(_, v)| v.clone())
                        })
                        .collect();
                    (name, values)
                })
                .collect()
        }
        Self {
            text: columns(text_rows, String::new()),
            integers: Vec::new(),
            numbers: columns(number_rows, f64::NAN),
        }
    }

    /// Adds an integer column (one value per row) after the integer columns the table has.
    pub fn push_integers(&mut self, name: &str, values: Vec<u64>) {
        self.integers.push((name.to_string(), values));
    }

    /// Number of rows.
    pub fn rows(&self) -> usize {
        self.text
            .first()
            .map(|c| c.1.len())
            .or_else(|| self.integers.first().map(|c| c.1.len()))
            .or_else(|| self.numbers.first().map(|c| c.1.len()))
            .unwrap_or(0)
    }

    /// A number column by name.
    pub fn numbers(&self, name: &str) -> Option<&[f64]> {
        self.numbers
            .iter()
            .find(|(n, _)| n == name)
            .map(|(_, v)| v.as_slice())
    }

    /// An integer column by name.
    pub fn integers(&self, name: &str) -> Option<&[u64]> {
        self.integers
            .iter()
            .find(|(n, _)| n == name)
            .map(|(_, v)| v.as_slice())
    }

    /// A text column by name.
    pub fn text(&self, name: &str) -> Option<&[String]> {
        self.text
            .iter()
            .find(|(n, _)| n == name)
            .map(|(_, v)| v.as_slice())
    }

    /// Writes the table as one Parquet file (text as `Utf8`, integers as `UInt64`, numbers as `Float64`,
    /// NaN as null), with
    /// `metadata` as the file's key-value metadata.
    pub fn write_parquet(&self, path: &Path, metadata: &[(&str, String)]) -> std::io::Result<()> {
        let io =
            |e: &dyn std::fmt::Display| std::io::Error::other(format!("{}: {e}", path.display()));
        let mut fields = Vec::new();
        let mut arrays: Vec<ArrayRef> = Vec::new();
        for (name, values) in &self.text {
            fields.push(Field::new(name, DataType::Utf8, false));
            arrays.push(Arc::new(StringArray::from(values.clone())));
        }
        for (name, values) in &self.integers {
            fields.push(Field::new(name, DataType::UInt64, false));
            arrays.push(Arc::new(UInt64Array::from(values.clone())));
        }
        for (name, values) in &self.numbers {
            fields.push(Field::new(name, DataType::Float64, true));
            arrays.push(Arc::new(Float64Array::from(
                values
                    .iter()
                    .map(|v| (!v.is_nan()).then_some(*v))
                    .collect::<Vec<_>>(),
            )));
        }
        let schema = Arc::new(Schema::new(fields));
        let batch = RecordBatch::try_new(schema.clone(), arrays).map_err(|e| io(&e))?;
        let properties = WriterProperties::builder()
            .set_compression(Compression::SNAPPY)
            .set_key_value_metadata(Some(
                metadata
                    .iter()
                    .map(|(k, v)| parquet::file::metadata::KeyValue::new(k.to_string(), v.clone()))
                    .collect(),
            ))
            .build();
        // Written beside and renamed: the file is whole or absent.
        let partial = path.with_extension("parquet.partial");
        let file = File::create(&partial)?;
        let mut writer =
            ArrowWriter::try_new(file, schema, Some(properties)).map_err(|e| io(&e))?;
        writer.write(&batch).map_err(|e| io(&e))?;
        writer.close().map_err(|e| io(&e))?;
        std::fs::rename(&partial, path)
    }

    /// Reads a table written by [`RunTable::write_parquet`].
    pub fn read_parquet(path: &Path) -> Result<Self, RunDataError> {
        let fail = |message: String| RunDataError {
            path: path.display().to_string(),
            message,
        };
        let file = crate::input_file::open_parquet(path, crate::input_file::MAX_TABLE_BYTES)
            .map_err(|e| fail(e.to_string()))?;
        let reader = ParquetRecordBatchReaderBuilder::try_new(file)
            .and_then(|b| b.build())
            .map_err(|e| fail(e.to_string()))?;
        let mut table = Self::default();
        for batch in reader {
            let batch = batch.map_err(|e| fail(e.to_string()))?;
            for (field, column) in batch.schema().fields().iter().zip(batch.columns()) {
                let name = field.name().clone();
                if let Some(text) = column.as_any().downcast_ref::<StringArray>() {
                    let values = text.iter().map(|v| v.unwrap_or("").to_string());
                    match table.text.iter_mut().find(|(n, _)| *n == name) {
                        Some((_, column)) => column.extend(values),
                        None => table.text.push((name, values.collect())),
                    }
                } else if let Some(integers) = column.as_any().downcast_ref::<UInt64Array>() {
                    let values = integers.values().iter().copied();
                    match table.integers.iter_mut().find(|(n, _)| *n == name) {
                        Some((_, column)) => column.extend(values),
                        None => table.integers.push((name, values.collect())),
                    }
                } else if let Some(numbers) = column.as_any().downcast_ref::<Float64Array>() {
                    let values = (0..numbers.len()).map(|k| {
                        if numbers.is_null(k) {
                            f64::NAN
                        } else {
                            numbers.value(k)
                        }
                    });
                    match table.numbers.iter_mut().find(|(n, _)| *n == name) {
                        Some((_, column)) => column.extend(values),
                        None => table.numbers.push((name, values.collect())),
                    }
                } else {
                    return Err(fail(format!(
                        "column `{name}` is {} (a run table holds Utf8, UInt64 and Float64 columns)",
                        field.data_type()
                    )));
                }
            }
        }
        Ok(table)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn integer_columns_round_trip_exactly_beyond_2_to_the_53() {
        let seeds = vec![u64::MAX, (1 << 53) + 1, 0];
        let mut table = RunTable::from_rows(
            &vec![vec![("law".to_string(), "a".to_string())]; 3],
            &vec![vec![("x".to_string(), 1.5)]; 3],
        );
        table.push_integers("seed", seeds.clone());
        let dir = std::env::temp_dir().join(format!("satflock-run-table-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let path = dir.join("t.parquet");
        table.write_parquet(&path, &[]).unwrap();
        let back = RunTable::read_parquet(&path).unwrap();
        std::fs::remove_dir_all(&dir).unwrap();
        assert_eq!(back.integers("seed"), Some(seeds.as_slice()));
        assert_eq!(back, table);
        assert_eq!(back.rows(), 3);
    }

    #[test]
    fn flattens_numbers_vectors_and_objects_and_leaves_out_the_rest() {
        let summary = serde_json::json!({
            "scenario": "x", "seed": 3, "status": "completed", "wall_time_s": 1.5,
            "timing": {"sensing_s": 0.5, "law_s": 0.25},
            "delta_v_mps": {"per_satellite": [1.0, 2.0, 3.0, 4.0, 5.0, 6.0, 7.0], "max": 7.0,
                            "mean_per_axis_hill": [0.1, 0.2, 0.3]},
            "final": {"five_elements": null},
            "law": {"reached": true, "range": [1.0, 2.0]},
            "metadata": {"satflock_version": "0.1.0"}
        });
        let out = scalar_outcomes(&summary);
        let names: Vec<&str> = out.iter().map(|(n, _)| n.as_str()).collect();
        assert_eq!(
            names,
            [
                "delta_v_mps.max",
                "delta_v_mps.mean_per_axis_hill.0",
                "delta_v_mps.mean_per_axis_hill.1",
                "delta_v_mps.mean_per_axis_hill.2",
                "law.range.0",
                "law.range.1",
                "law.reached",
                "wall_time_s",
            ]
        );
        assert_eq!(out[6], ("law.reached".to_string(), 1.0));
    }

    #[test]
    fn a_run_table_round_trips_through_parquet_with_missing_values() {
        let text = vec![
            vec![("law".to_string(), "hold".to_string())],
            vec![("law".to_string(), "none".to_string())],
        ];
        let numbers = vec![
            vec![("seed".to_string(), 1.0), ("a".to_string(), 2.5)],
            vec![("seed".to_string(), 2.0), ("b".to_string(), -1.0)],
        ];
        let table = RunTable::from_rows(&text, &numbers);
        assert_eq!(table.rows(), 2);
        assert!(table.numbers("a").unwrap()[1].is_nan());
        let dir = std::env::temp_dir().join(format!("satflock-runtable-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let path = dir.join("t.parquet");
        table
            .write_parquet(&path, &[("tool", "test".into())])
            .unwrap();
        let back = RunTable::read_parquet(&path).unwrap();
        std::fs::remove_dir_all(&dir).unwrap();
        assert_eq!(back.text, table.text);
        assert_eq!(back.numbers.len(), 3);
        for ((n1, v1), (n2, v2)) in back.numbers.iter().zip(&table.numbers) {
            assert_eq!(n1, n2);
            assert!(v1.iter().zip(v2).all(|(a, b)| a.to_bits() == b.to_bits()));
        }
    }
}
