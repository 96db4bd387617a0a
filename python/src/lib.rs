//! The compiled half of the `railfem` Python package (`railfem._railfem`).
//!
//! What lives here: the module's definition, the two rules every call follows — errors
//! become Python exceptions carrying the command line's one-line message
//! ([`to_py_err`]), and a Rust panic becomes a `RuntimeError` instead of taking the
//! interpreter down ([`guarded`]) — and the small functions `elements` and `load_plugin`.
//! The model class is in [`model`], the built-in cases in [`cases`], Python values to the
//! model file's JSON form in [`value`]. The Python half (`railfem/__init__.py`) wraps the
//! raw dictionaries returned here in result classes.

use pyo3::exceptions::{PyOSError, PyRuntimeError, PyValueError};
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyList};
use railfem::framework::FemError;
use std::panic::{catch_unwind, AssertUnwindSafe};
use std::path::PathBuf;

mod cases;
mod model;
mod value;

pyo3::create_exception!(
    _railfem,
    SolverError,
    PyRuntimeError,
    "A run that could not go on: no convergence, or a NaN or infinity appeared."
);

/// The exception for a [`FemError`], with the text `railfem` prints after `error: `.
/// Bad input (model, plugin, singular model, element) is a `ValueError`, a failed step a
/// [`SolverError`] (a `RuntimeError`), an output that cannot be written an `OSError`.
pub(crate) fn to_py_err(e: FemError) -> PyErr {
    let msg = e.to_string().replace('\n', " ");
    match e {
        FemError::Convergence(_) | FemError::NonFinite(_) => SolverError::new_err(msg),
        FemError::Output { .. } => PyOSError::new_err(msg),
        _ => PyValueError::new_err(msg),
    }
}

/// Runs `f` with the GIL released and any panic caught: a panic becomes a
/// `RuntimeError` with the panic's message, so the interpreter lives on. Everything `f`
/// touches is owned by Rust (it captures no Python object).
pub(crate) fn guarded<T: Send>(py: Python<'_>, f: impl FnOnce() -> T + Send) -> PyResult<T> {
    py.detach(|| catch_unwind(AssertUnwindSafe(f)))
        .map_err(|p| {
            let msg = p
                .downcast_ref::<&str>()
                .map(|s| s.to_string())
                .or_else(|| p.downcast_ref::<String>().cloned())
                .unwrap_or_else(|| "(no message)".to_string());
            PyRuntimeError::new_err(format!(
                "railfem: internal error: {msg} — please report this with the model"
            ))
        })
}

/// Every registered element kind: a list of dicts `{name, description, params}`, each
/// param `{key, unit, default, doc}` (`default` is `None` for a required key), the same
/// table `railfem elements` prints.
#[pyfunction]
fn elements(py: Python<'_>) -> PyResult<Bound<'_, PyList>> {
    let kinds = guarded(py, railfem::framework::registry::kinds)?;
    let out = PyList::empty(py);
    for k in kinds {
        let d = PyDict::new(py);
        d.set_item("name", k.name)?;
        d.set_item("description", k.description)?;
        let params = PyList::empty(py);
        for p in (k.params)() {
            let q = PyDict::new(py);
            q.set_item("key", p.key)?;
            q.set_item("unit", p.unit)?;
            q.set_item("default", value::to_py(py, p.default.as_ref())?)?;
            q.set_item("doc", p.doc)?;
            params.append(q)?;
        }
        d.set_item("params", params)?;
        out.append(d)?;
    }
    Ok(out)
}

/// Loads an element plugin (a shared library built with `export_plugin!`) and returns
/// the names of the element kinds it registered (its load and recorder kinds, if any, are
/// registered too and read by model files). Loading the same file again does nothing. A
/// library that cannot be loaded raises `ValueError` with the loader's message.
#[pyfunction]
fn load_plugin(py: Python<'_>, path: PathBuf) -> PyResult<Vec<String>> {
    let p = path.clone();
    guarded(py, move || railfem::framework::plugin::load(&p))?.map_err(to_py_err)?;
    let canon = std::fs::canonicalize(&path).unwrap_or(path);
    Ok(railfem::framework::plugin::loaded()
        .into_iter()
        .find(|(p, _)| *p == canon)
        .map(|(_, kinds)| {
            kinds
                .into_iter()
                .filter(|k| railfem::framework::registry::find(k).is_some())
                .map(String::from)
                .collect()
        })
        .unwrap_or_default())
}

/// Panics inside [`guarded`], exactly as a failing run would; it exists so that the tests
/// can check that a panic becomes a `RuntimeError` and the interpreter lives on.
#[pyfunction]
fn _panic_inside(py: Python<'_>, message: String) -> PyResult<()> {
    guarded(py, move || -> () { panic!("{message}") })
}

#[pymodule]
fn _railfem(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add("SolverError", m.py().get_type::<SolverError>())?;
    m.add_class::<model::Model>()?;
    m.add_function(wrap_pyfunction!(elements, m)?)?;
    m.add_function(wrap_pyfunction!(load_plugin, m)?)?;
    m.add_function(wrap_pyfunction!(_panic_inside, m)?)?;
    m.add_function(wrap_pyfunction!(cases::curve, m)?)?;
    m.add_function(wrap_pyfunction!(cases::critical_radius, m)?)?;
    m.add_function(wrap_pyfunction!(cases::train_bridge, m)?)?;
    Ok(())
}
