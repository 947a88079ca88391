//! `corps.run`: a scenario's closed-loop run in memory, as `corps run` does it (same
//! scenario files, same overrides, same errors), returning its time series as numpy arrays.

use crate::errors::{scenario_error, CorpsError, PlantError};
use crate::plant::{PythonPlant, Raised};
use corps_scenario::estimation::EstimatorKind;
use corps_scenario::overrides::{read_file, Overrides};
use corps_scenario::run::{RowSink, RunOptions, ScenarioRun};
use corps_scenario::scenario::Scenario;
use corps_scenario::sensor_profile::SensorProfile;
use corps_scenario::ScenarioError;
use numpy::{PyArray1, PyArray2, PyArrayMethods, PyUntypedArrayMethods};
use pyo3::exceptions::{PyImportError, PyKeyError};
use pyo3::prelude::*;
use pyo3::types::PyDict;
use std::path::{Path, PathBuf};

/// Rows between two checks for Ctrl-C.
const SIGNAL_CHECK_ROWS: usize = 200;

/// Keeps every row (flattened) and polls Python's signal handlers now and then.
struct Rows {
    values: Vec<f64>,
    interrupt: Option<PyErr>,
}

impl RowSink for Rows {
    fn row(&mut self, index: usize, row: &[f64]) -> Result<(), ScenarioError> {
        self.values.extend_from_slice(row);
        if index.is_multiple_of(SIGNAL_CHECK_ROWS) {
            if let Err(e) = Python::attach(|py| py.check_signals()) {
                self.interrupt = Some(e);
                return Err(ScenarioError::Output("interrupted".into()));
            }
        }
        Ok(())
    }
}

/// The result of a run: the time series (one row per control tick), the metrics and the
/// verdict.
#[pyclass(name = "RunResult", module = "corps", frozen)]
pub struct PyRunResult {
    /// Column names, in column order (`t` first, seconds of controlled time).
    #[pyo3(get)]
    columns: Vec<String>,
    /// The rows (ticks × columns).
    #[pyo3(get)]
    data: Py<PyArray2<f64>>,
    /// `completed`, `fell`, `diverged` or `controller_failed`.
    #[pyo3(get)]
    verdict: String,
    /// The verdict the scenario expects.
    #[pyo3(get)]
    expected: String,
    /// Everything `metrics.json` holds, as a dict.
    #[pyo3(get)]
    metrics: Py<PyAny>,
    /// The metrics as `corps run` prints them.
    #[pyo3(get)]
    report: String,
}

#[pymethods]
impl PyRunResult {
    /// Column `name` as a 1-D array (a view of `data`).
    fn __getitem__<'py>(&self, py: Python<'py>, name: &str) -> PyResult<Bound<'py, PyAny>> {
        let Some(k) = self.columns.iter().position(|c| c == name) else {
            return Err(PyKeyError::new_err(format!(
                "no column '{name}' (columns: {})",
                self.columns.join(", ")
            )));
        };
        let data = self.data.bind(py);
        data.as_any().get_item((pyo3::types::PySlice::full(py), k))
    }
    /// The time column (s).
    #[getter]
    fn time<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        self.__getitem__(py, "t")
    }
    /// The time series as a pandas DataFrame (needs pandas).
    fn dataframe<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        let pandas = py.import("pandas").map_err(|_| {
            PyImportError::new_err("RunResult.dataframe() needs pandas (pip install pandas)")
        })?;
        let kwargs = PyDict::new(py);
        kwargs.set_item("columns", self.columns.clone())?;
        pandas.call_method("DataFrame", (self.data.bind(py),), Some(&kwargs))
    }
    fn __len__(&self, py: Python<'_>) -> usize {
        self.data.bind(py).shape()[0]
    }
    fn __repr__(&self, py: Python<'_>) -> String {
        let shape = self.data.bind(py).shape().to_vec();
        format!(
            "corps.RunResult(verdict='{}', ticks={}, columns={})",
            self.verdict, shape[0], shape[1]
        )
    }
}

/// Runs scenario file `scenario` as `corps run` does (one thread) and returns its time
/// series in memory; writes no file. `robot`, `duration` (s), `estimator`
/// (`leg-odometry` or `ground-truth`) and `noise` (a sensor profile file) replace the
/// scenario's, as the command's options do. A run that ends otherwise than the scenario
/// expects is returned, not raised: compare `result.verdict` with `result.expected`.
/// `plant` (an object with `reset`, `step` and `state`, see `corps.Plant`) replaces corps'
/// simulator once the robot has settled.
#[pyfunction]
#[pyo3(signature = (scenario, robot = None, duration = None, estimator = None, noise = None, plant = None))]
pub fn run(
    py: Python<'_>,
    scenario: PathBuf,
    robot: Option<String>,
    duration: Option<f64>,
    estimator: Option<&str>,
    noise: Option<PathBuf>,
    plant: Option<Py<PyAny>>,
) -> PyResult<PyRunResult> {
    let estimator = match estimator {
        None => None,
        Some("leg-odometry") => Some(EstimatorKind::LegOdometry),
        Some("ground-truth") => Some(EstimatorKind::GroundTruth),
        Some(other) => {
            return Err(scenario_error(format!(
                "estimator: '{other}' is not one of leg-odometry, ground-truth"
            )))
        }
    };
    let noise = match noise {
        Some(p) => Some(SensorProfile::read(&p).map_err(|e| scenario_error(format!("{e:#}")))?),
        None => None,
    };
    let overrides = Overrides {
        duration,
        robot,
        estimator,
        noise,
        max_log_mb: None,
    };
    if let Some(p) = &plant {
        for method in ["reset", "step", "state"] {
            if !p.bind(py).hasattr(method)? {
                return Err(PlantError::new_err(format!(
                    "plant: the object has no method '{method}' (see corps.Plant)"
                )));
            }
        }
    }
    let shown = scenario.display().to_string();
    let text = read_file(&scenario).map_err(scenario_error)?;
    let parsed = Scenario::parse_with(&text, &scenario, &overrides).map_err(scenario_error)?;
    let name = parsed.run_name(&scenario);
    let base_dir = scenario.parent().unwrap_or(Path::new(".")).to_path_buf();
    let mut rows = Rows {
        values: Vec::new(),
        interrupt: None,
    };
    let raised = Raised::default();
    let plant = plant.map(|p| Box::new(PythonPlant::new(p, raised.clone())));
    let outcome = py.detach(|| {
        std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| {
            let mut run = ScenarioRun::new(&parsed, &name, &base_dir, RunOptions::default())?;
            if let Some(plant) = plant {
                run = run.with_plant(plant)?;
            }
            // The time series in memory: 8 bytes a value, under the scenario's log cap.
            let values = run.ticks().saturating_mul(run.columns().len());
            let bytes = values.saturating_mul(8) as u64;
            let cap = parsed.output.max_log_bytes();
            if bytes > cap {
                return Err(ScenarioError::Invalid(format!(
                    "the time series would take {:.0} MB in memory, over the log cap of {:.0} MB ([output] max_log_mb; shorten the run with duration=)",
                    bytes as f64 / 1e6,
                    cap as f64 / 1e6
                )));
            }
            rows.values.try_reserve_exact(values).map_err(|_| {
                ScenarioError::Invalid(format!(
                    "cannot hold the time series in memory ({:.0} MB)",
                    bytes as f64 / 1e6
                ))
            })?;
            run.run(&mut [&mut rows])
        }))
    });
    let result = match outcome {
        Ok(Ok(r)) => r,
        Ok(Err(e)) => {
            let from_plant = raised.lock().ok().and_then(|mut r| r.take());
            return Err(match (rows.interrupt.take(), from_plant) {
                (Some(interrupt), _) => interrupt,
                (None, Some(raised)) => raised,
                (None, None) => scenario_error(format!("{shown}: {e}")),
            });
        }
        Err(panic) => return Err(internal_error(panic)),
    };
    let m = result.metrics;
    let json = serde_json::to_string(&m).map_err(|e| CorpsError::new_err(e.to_string()))?;
    let metrics = py.import("json")?.call_method1("loads", (json,))?.unbind();
    let columns = result.columns;
    let width = columns.len().max(1);
    let ticks = rows.values.len() / width;
    let data = PyArray1::from_vec(py, rows.values).reshape([ticks, columns.len()])?;
    Ok(PyRunResult {
        columns,
        data: data.unbind(),
        verdict: m.verdict.verdict.to_string(),
        expected: parsed.expect.to_string(),
        report: m.to_string(),
        metrics,
    })
}

/// A panic inside corps as a Python exception (a bug in corps, reported, not a crash).
pub fn internal_error(panic: Box<dyn std::any::Any + Send>) -> PyErr {
    let what = panic
        .downcast_ref::<String>()
        .cloned()
        .or_else(|| panic.downcast_ref::<&str>().map(|s| s.to_string()))
        .unwrap_or_else(|| "unknown panic".into());
    CorpsError::new_err(format!(
        "internal error in corps (please report it): {what}"
    ))
}

/// Panics inside Rust on purpose, to test that a panic becomes a Python exception.
#[pyfunction]
pub fn _panic_for_test() -> PyResult<()> {
    std::panic::catch_unwind(|| panic!("a test panic")).map_err(internal_error)
}
