//! A run's tables as numpy arrays: [`MemoryRecorder`], the in-memory recorder of `Simulation` (the
//! rows of [`Record::fill`], exactly as the CLI's CSV and Parquet recorders write them), and the
//! conversion of a metrics or trajectory [`Table`] (read back from a run directory by `RunData`, or held
//! by the recorder) into numpy arrays: the metrics by column, the trajectory as (records, satellites, …)
//! arrays with a NaN row where a satellite is not alive.

use numpy::{PyArray1, PyArrayMethods};
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyList};

use satflock::output::columns::{ColumnKind, OutputColumns, Record, TRAJECTORY_HEADER};
use satflock::output::Table;
use satflock::swarm::{Recorder, Snapshot};
use satflock::time::{self, Epoch};

/// Marks a numpy array read-only (`flags.writeable = False`) and returns it.
pub fn readonly(array: Bound<'_, PyAny>) -> PyResult<Bound<'_, PyAny>> {
    array.getattr("flags")?.setattr("writeable", false)?;
    Ok(array)
}

/// Keeps every snapshot's rows in memory, column by column: the columns of the CLI's tables but
/// `time_utc` (the epoch plus `t_s`).
pub struct MemoryRecorder {
    columns: OutputColumns,
    epoch: Epoch,
    record: Record,
    metrics: Vec<Vec<f64>>,
    /// `None`: the scenario writes no trajectory (`[output] trajectory = false`).
    trajectory: Option<Vec<Vec<f64>>>,
}

/// The names of `columns` without `time_utc`.
fn numeric_names(columns: &[satflock::output::columns::Column]) -> Vec<String> {
    columns
        .iter()
        .filter(|c| c.kind != ColumnKind::Text)
        .map(|c| c.name.to_string())
        .collect()
}

impl MemoryRecorder {
    /// An empty recorder of the tables with `columns`; `epoch` is the instant of t = 0.
    pub fn new(columns: OutputColumns, epoch: Epoch, with_trajectory: bool) -> Self {
        let metrics = vec![Vec::new(); numeric_names(&columns.metrics()).len()];
        let trajectory =
            with_trajectory.then(|| vec![Vec::new(); numeric_names(&columns.trajectory()).len()]);
        Self {
            columns,
            epoch,
            record: Record::default(),
            metrics,
            trajectory,
        }
    }

    /// The metrics recorded so far.
    pub fn metrics(&self) -> Table {
        Table::new(numeric_names(&self.columns.metrics()), self.metrics.clone())
    }

    /// The trajectory recorded so far (`None` when the scenario writes none).
    pub fn trajectory(&self) -> Option<Table> {
        self.trajectory
            .as_ref()
            .map(|columns| Table::new(numeric_names(&self.columns.trajectory()), columns.clone()))
    }
}

/// Appends `t_s` and the row's values to the columns.
fn push_row(columns: &mut [Vec<f64>], time_s: f64, values: &[f64]) {
    columns[0].push(time_s);
    for (column, value) in columns[1..].iter_mut().zip(values) {
        column.push(*value);
    }
}

impl Recorder for MemoryRecorder {
    fn record(&mut self, snapshot: &Snapshot<'_>) -> std::io::Result<()> {
        let record = &mut self.record;
        record.fill(
            &self.columns,
            self.epoch,
            snapshot,
            self.trajectory.is_some(),
        );
        push_row(&mut self.metrics, record.time_s, &record.metrics);
        if let Some(trajectory) = &mut self.trajectory {
            for row in record.trajectory_rows() {
                push_row(trajectory, record.time_s, row);
            }
        }
        Ok(())
    }
}

/// The metrics table as a dict of numpy arrays by column, in file order: `t_s`, `time_utc` (a list of
/// ISO 8601 UTC strings: `epoch` plus `t_s`, as the CLI writes them), then every numeric column (counts
/// as int64, the rest float64 with NaN where a value does not exist).
pub fn metrics_columns<'py>(
    py: Python<'py>,
    table: &Table,
    epoch: Epoch,
) -> PyResult<Bound<'py, PyDict>> {
    let dict = PyDict::new(py);
    let t_s = table.column("t_s").unwrap_or_default();
    for name in table.names() {
        let Some(values) = table.column(name) else {
            continue;
        };
        let array = if ColumnKind::of(name) == ColumnKind::Count {
            PyArray1::from_vec(py, values.iter().map(|v| *v as i64).collect()).into_any()
        } else {
            PyArray1::from_slice(py, values).into_any()
        };
        dict.set_item(name, readonly(array)?)?;
        if name == "t_s" {
            let utc: Vec<String> = t_s
                .iter()
                .map(|t| time::utc_iso(time::at(epoch, *t)))
                .collect();
            dict.set_item("time_utc", PyList::new(py, utc)?)?;
        }
    }
    Ok(dict)
}

/// The trajectory table as arrays over (records, satellites): `t_s` (R,) the recording times (the
/// metrics table's, so a record with no live satellite is there too), `ids` (N,), `hill` and `eci`
/// (R, N, 6) positions then velocities, `delta_v_mps` (R, N), `law_outputs` a dict of (R, N) arrays; a
/// satellite not alive at a record is a row of NaN.
pub fn trajectory_arrays<'py>(
    py: Python<'py>,
    table: &Table,
    record_times_s: &[f64],
    n: usize,
) -> PyResult<Bound<'py, PyDict>> {
    let column = |name: &str| {
        table.column(name).ok_or_else(|| {
            PyValueError::new_err(format!("the trajectory table has no column `{name}`"))
        })
    };
    let r = record_times_s.len();
    let mut hill = vec![f64::NAN; r * n * 6];
    let mut eci = vec![f64::NAN; r * n * 6];
    let mut delta_v = vec![f64::NAN; r * n];
    let law_names: Vec<&String> = table
        .names()
        .iter()
        .filter(|name| !TRAJECTORY_HEADER.contains(&name.as_str()))
        .collect();
    let mut law_outputs = vec![vec![f64::NAN; r * n]; law_names.len()];
    let hill_columns = TRAJECTORY_HEADER[3..9]
        .iter()
        .map(|c| column(c))
        .collect::<PyResult<Vec<_>>>()?;
    let eci_columns = TRAJECTORY_HEADER[9..15]
        .iter()
        .map(|c| column(c))
        .collect::<PyResult<Vec<_>>>()?;
    let delta_v_column = column("delta_v_mps")?;
    let law_columns = law_names
        .iter()
        .map(|c| column(c))
        .collect::<PyResult<Vec<_>>>()?;
    let (t_column, ids) = (column("t_s")?, column("id")?);
    // Rows come record after record, in time order: walk the recording times along them.
    let mut record = 0;
    for (row, (&t, &id)) in t_column.iter().zip(ids).enumerate() {
        while record < r && record_times_s[record] != t {
            record += 1;
        }
        let i = id as usize;
        if record == r || id < 0.0 || i >= n || id.fract() != 0.0 {
            return Err(PyValueError::new_err(format!(
                "trajectory row {row} (t_s = {t}, id = {id}) matches no record and satellite of the \
                 run ({r} records, {n} satellites)"
            )));
        }
        let at = record * n + i;
        for k in 0..6 {
            hill[at * 6 + k] = hill_columns[k][row];
            eci[at * 6 + k] = eci_columns[k][row];
        }
        delta_v[at] = delta_v_column[row];
        for (values, column) in law_outputs.iter_mut().zip(&law_columns) {
            values[at] = column[row];
        }
    }
    let states = |values: Vec<f64>| -> PyResult<Bound<'py, PyAny>> {
        readonly(
            PyArray1::from_vec(py, values)
                .reshape([r, n, 6])?
                .into_any(),
        )
    };
    let per_satellite = |values: Vec<f64>| -> PyResult<Bound<'py, PyAny>> {
        readonly(PyArray1::from_vec(py, values).reshape([r, n])?.into_any())
    };
    let dict = PyDict::new(py);
    dict.set_item(
        "t_s",
        readonly(PyArray1::from_slice(py, record_times_s).into_any())?,
    )?;
    dict.set_item(
        "ids",
        readonly(PyArray1::from_vec(py, (0..n as i64).collect()).into_any())?,
    )?;
    dict.set_item("hill", states(hill)?)?;
    dict.set_item("eci", states(eci)?)?;
    dict.set_item("delta_v_mps", per_satellite(delta_v)?)?;
    let outputs = PyDict::new(py);
    for (name, values) in law_names.into_iter().zip(law_outputs) {
        outputs.set_item(name, per_satellite(values)?)?;
    }
    dict.set_item("law_outputs", outputs)?;
    Ok(dict)
}
