//! `railfem.Model`: a model file (or a dict with the same keys), checked and run exactly
//! as `railfem check` and `railfem run` do.
//!
//! A `Model` holds the model's *description*, not a built model: every `check()` and
//! `run()` reads and builds it afresh through the same library calls the command line
//! makes ([`railfem::load_model`] / [`railfem::model_from_value`], then
//! [`railfem::prepare`] and the driver's run), so messages and numbers are the command
//! line's. A run keeps every recorder's rows in memory (exact doubles) and, with `out`,
//! writes the same CSV files as `railfem run --out`.

use crate::{guarded, to_py_err, value};
use numpy::ndarray::Array2;
use numpy::IntoPyArray;
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyList};
use railfem::framework::recording::History;
use railfem::framework::FemError;
use railfem::solvers::driver::RunSummary;
use railfem::solvers::energy::EnergyRow;
use serde_json::Value;
use std::path::{Path, PathBuf};

/// Most problems `check()` lists, as `railfem check` does.
const MAX_LISTED: usize = 20;

/// Where a model's description comes from.
enum Source {
    /// A model file, named in messages as given.
    File(PathBuf),
    /// A dict converted to the file's JSON form; `name` stands for the file in messages,
    /// `base` resolves relative plugin paths.
    Value {
        value: Value,
        name: String,
        base: PathBuf,
    },
}

impl Source {
    fn name(&self) -> String {
        match self {
            Source::File(p) => p.display().to_string(),
            Source::Value { name, .. } => name.clone(),
        }
    }

    /// Builds the driver and runs the preflight checks, as `railfem check`/`run` do.
    fn prepare(
        &self,
        estimate_factor: bool,
    ) -> Result<
        (
            railfem::solvers::Driver,
            railfem::solvers::preflight::Preflight,
        ),
        FemError,
    > {
        let model = match self {
            Source::File(p) => railfem::load_model(p),
            Source::Value { value, name, base } => railfem::model_from_value(value, name, base),
        };
        railfem::prepare(model, &self.name(), estimate_factor)
    }
}

/// What a run hands back to Python, gathered with the GIL released.
struct Ran {
    summary: RunSummary,
    histories: Vec<History>,
    energy: Option<(Vec<EnergyRow>, String, f64)>,
    warnings: Vec<String>,
    size: String,
}

/// A railfem model: `Model.from_file(path)` or `Model.from_dict(dict)`.
#[pyclass(module = "railfem._railfem", frozen)]
pub struct Model {
    source: Source,
}

#[pymethods]
impl Model {
    /// The model file at `path` (TOML or JSON, by extension). It is read by `check()` and
    /// `run()`, each time, so a file that cannot be read is reported there.
    #[staticmethod]
    fn from_file(path: PathBuf) -> Model {
        Model {
            source: Source::File(path),
        }
    }

    /// A model from a dict with the same keys and structure as a model file (tables are
    /// dicts, arrays of tables lists of dicts). `name` stands for the file name in
    /// messages; `base` is the folder relative plugin paths start from (default: the
    /// current directory).
    #[staticmethod]
    #[pyo3(signature = (data, name = "model".to_string(), base = None))]
    fn from_dict(data: &Bound<'_, PyAny>, name: String, base: Option<PathBuf>) -> PyResult<Model> {
        let value = value::from_py(data, "", &name)?;
        Ok(Model {
            source: Source::Value {
                value,
                name,
                base: base.unwrap_or_default(),
            },
        })
    }

    /// The name messages use for the model (the path as given, or the dict's `name`).
    #[getter]
    fn name(&self) -> String {
        self.source.name()
    }

    /// Everything `railfem check` checks. Returns `{"size": ..., "warnings": [...]}`;
    /// raises `ValueError` whose message is the lines `railfem check` prints after
    /// `error: `, one per problem (at most 20, then a count).
    fn check<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        let name = self.source.name();
        let r = guarded(py, || {
            self.source
                .prepare(true)
                .map(|(_, pre)| (pre.size.to_string(), pre.warnings))
        })?;
        match r {
            Ok((size, warnings)) => {
                let d = PyDict::new(py);
                d.set_item("size", size)?;
                d.set_item("warnings", warnings)?;
                Ok(d)
            }
            Err(e) => {
                let all = e.problems();
                let mut lines: Vec<String> = all
                    .iter()
                    .take(MAX_LISTED)
                    .map(|p| p.to_string().replace('\n', " "))
                    .collect();
                if all.len() > MAX_LISTED {
                    lines.push(format!(
                        "{name}: … and {} more problems; fix these first",
                        all.len() - MAX_LISTED
                    ));
                }
                match &e {
                    FemError::Many(_) => Err(PyValueError::new_err(lines.join("\n"))),
                    _ => Err(to_py_err(e)),
                }
            }
        }
    }

    /// Runs the model as `railfem run` does, with the GIL released. Returns a dict:
    /// `recorders` (per recorder `file`, `columns`, `time`, `values`), `energy`, `stats`,
    /// `size`, `warnings` — `railfem.Model.run` wraps it in a `Result`. With `out`, the
    /// CSV files `railfem run --out` writes are written too.
    #[pyo3(signature = (out = None))]
    fn run<'py>(&self, py: Python<'py>, out: Option<PathBuf>) -> PyResult<Bound<'py, PyDict>> {
        // With `out`, the directory gets the CLI's sidecar too (`run.json`: version,
        // what ran, start and end, status).
        let record = out.as_ref().map(|dir| railfem::sidecar::RunRecord {
            command: "python: railfem.Model.run".into(),
            argv: vec![self.source.name()],
            options: serde_json::json!({ "model": self.source.name(), "out": dir }),
            dir: dir.clone(),
            start: std::time::SystemTime::now(),
        });
        let ran = guarded(py, || -> Result<Ran, FemError> {
            let (mut driver, mut pre) = self.source.prepare(false)?;
            // The activity window (`[analysis.window]`), planned and moved as `railfem
            // run` does it; `auto` where it does not apply says why among the warnings.
            let name = self.source.name();
            let spec = driver.model.analysis.window;
            let mut window = railfem::run_window::plan(&driver, &spec, &name)?;
            let (summary, histories) = driver
                .run_preparing(
                    out.as_deref(),
                    true,
                    &mut |_| {},
                    &mut |_, _| {},
                    &mut |d| window.before_step(d),
                )
                .map_err(|e| e.in_file(&name))?;
            if let Some(why) = window.auto_off() {
                pre.warnings
                    .push(format!("activity window (auto): off here: {why}"));
            }
            let energy = driver
                .energy
                .as_ref()
                .filter(|e| e.started())
                .map(|e| (e.history.clone(), e.summary(), e.relative_error()));
            Ok(Ran {
                summary,
                histories,
                energy,
                warnings: pre.warnings,
                size: pre.size.to_string(),
            })
        })?;
        if let Some(r) = &record {
            let status = match &ran {
                Ok(_) => "completed".to_string(),
                Err(e) => format!("failed: {}", e.to_string().replace('\n', " ")),
            };
            // A sidecar that cannot be written does not hide the run's own result.
            let _ = r.write(&status);
        }
        let ran = ran.map_err(to_py_err)?;
        ran_to_py(py, ran, out.as_deref())
    }

    fn __repr__(&self) -> String {
        match &self.source {
            Source::File(p) => format!("railfem.Model.from_file({:?})", p.display().to_string()),
            Source::Value { name, .. } => format!("railfem.Model.from_dict(..., name={name:?})"),
        }
    }
}

/// One table of rows as a raw dict: `file`, `columns`, `time` (n,), `values` (n, columns).
pub(crate) fn table<'py>(
    py: Python<'py>,
    file: &str,
    columns: Vec<String>,
    time: Vec<f64>,
    values: Vec<f64>,
) -> PyResult<Bound<'py, PyDict>> {
    let rows = time.len();
    let cols = columns.len();
    let values = Array2::from_shape_vec((rows, cols), values)
        .map_err(|e| PyValueError::new_err(format!("{file}: ragged rows: {e}")))?;
    let d = PyDict::new(py);
    d.set_item("file", file)?;
    d.set_item("columns", columns)?;
    d.set_item("time", time.into_pyarray(py))?;
    d.set_item("values", values.into_pyarray(py))?;
    Ok(d)
}

fn ran_to_py<'py>(py: Python<'py>, ran: Ran, out: Option<&Path>) -> PyResult<Bound<'py, PyDict>> {
    let recorders = PyList::empty(py);
    for h in ran.histories {
        recorders.append(table(py, &h.file, h.columns, h.time, h.values)?)?;
    }
    let d = PyDict::new(py);
    d.set_item("recorders", recorders)?;
    match ran.energy {
        Some((rows, summary, rel)) => {
            let cols = railfem::solvers::energy::EnergyRow::COLUMNS;
            let time = rows.iter().map(|r| r.t).collect();
            let values = rows.iter().flat_map(|r| r.values()).collect();
            let e = table(
                py,
                railfem::framework::outputs::ENERGY_CSV,
                cols.iter().map(|c| c.to_string()).collect(),
                time,
                values,
            )?;
            e.set_item("summary", summary)?;
            e.set_item("relative_error", rel)?;
            d.set_item("energy", e)?;
        }
        None => d.set_item("energy", py.None())?,
    }
    let s = ran.summary;
    let stats = PyDict::new(py);
    stats.set_item("steps", s.steps)?;
    stats.set_item("iterations", s.iterations)?;
    stats.set_item("cuts", s.cuts)?;
    stats.set_item("factorizations", s.factorizations)?;
    stats.set_item("symbolic", s.symbolic)?;
    stats.set_item("equations", s.equations)?;
    stats.set_item("wall", s.wall)?;
    let t = PyDict::new(py);
    t.set_item("assembly", s.timings.assembly)?;
    t.set_item("factor", s.timings.factor)?;
    t.set_item("solve", s.timings.solve)?;
    t.set_item("loads", s.timings.loads)?;
    stats.set_item("timings", t)?;
    d.set_item("stats", stats)?;
    d.set_item("size", ran.size)?;
    d.set_item("warnings", ran.warnings)?;
    d.set_item("out", out.map(|p| p.display().to_string()))?;
    Ok(d)
}
