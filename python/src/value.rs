//! Python values to and from the model file's in-memory form (a `serde_json::Value`).
//!
//! `Model.from_dict` takes the same keys a model file has: dicts for tables, lists for
//! arrays of tables and vectors, str, bool, int and float. A value the file formats cannot
//! hold is refused with its key path: `None` (TOML has no null) and NaN or infinity (the
//! same message the TOML reader gives). numpy arrays and scalars are read through their
//! `tolist()`. The other way, JSON values become Python objects through `json.loads`.

use pyo3::exceptions::{PyTypeError, PyValueError};
use pyo3::prelude::*;
use pyo3::types::{PyBool, PyDict, PyFloat, PyInt, PyList, PyString, PyTuple};
use serde_json::{Map, Number, Value};

/// `o` as a JSON value; `path` is the key path so far (`node[0].xyz`), `name` the model's
/// name for messages.
pub fn from_py(o: &Bound<'_, PyAny>, path: &str, name: &str) -> PyResult<Value> {
    let at = || {
        if path.is_empty() {
            "the model".to_string()
        } else {
            format!("`{path}`")
        }
    };
    if o.is_none() {
        return Err(PyValueError::new_err(format!(
            "{name}: {} is None; give a value or leave the key out (model files have no null)",
            at()
        )));
    }
    if o.is_instance_of::<PyBool>() {
        return Ok(Value::Bool(o.extract()?));
    }
    if o.is_instance_of::<PyInt>() {
        if let Ok(i) = o.extract::<i64>() {
            return Ok(Value::Number(i.into()));
        }
        let u: u64 = o.extract().map_err(|_| {
            PyValueError::new_err(format!("{name}: {} does not fit in 64 bits", at()))
        })?;
        return Ok(Value::Number(u.into()));
    }
    if o.is_instance_of::<PyFloat>() {
        let f: f64 = o.extract()?;
        return Number::from_f64(f).map(Value::Number).ok_or_else(|| {
            PyValueError::new_err(format!(
                "{name}: {} is not a finite number; give a finite value in SI units",
                at()
            ))
        });
    }
    if o.is_instance_of::<PyString>() {
        return Ok(Value::String(o.extract()?));
    }
    if let Ok(d) = o.cast::<PyDict>() {
        let mut map = Map::new();
        for (k, v) in d.iter() {
            let key: String = k.extract().map_err(|_| {
                PyTypeError::new_err(format!(
                    "{name}: a key of {} is not a str: {}",
                    at(),
                    k.repr().map(|r| r.to_string()).unwrap_or_default()
                ))
            })?;
            let sub = if path.is_empty() {
                key.clone()
            } else {
                format!("{path}.{key}")
            };
            map.insert(key, from_py(&v, &sub, name)?);
        }
        return Ok(Value::Object(map));
    }
    if o.is_instance_of::<PyList>() || o.is_instance_of::<PyTuple>() {
        let mut list = Vec::new();
        for (i, v) in o.try_iter()?.enumerate() {
            list.push(from_py(&v?, &format!("{path}[{i}]"), name)?);
        }
        return Ok(Value::Array(list));
    }
    if o.hasattr("tolist")? {
        // numpy arrays and scalars.
        return from_py(&o.call_method0("tolist")?, path, name);
    }
    Err(PyTypeError::new_err(format!(
        "{name}: {} is a {}; give a dict, list, str, bool, int or float",
        at(),
        o.get_type().name()?
    )))
}

/// A JSON value (or `None`) as a Python object.
pub fn to_py<'py>(py: Python<'py>, v: Option<&Value>) -> PyResult<Bound<'py, PyAny>> {
    match v {
        None => Ok(py.None().into_bound(py)),
        Some(v) => {
            let text = serde_json::to_string(v)
                .map_err(|e| PyValueError::new_err(format!("unrepresentable value: {e}")))?;
            py.import("json")?.call_method1("loads", (text,))
        }
    }
}

/// A serializable Rust value (a case, a result) as a Python object.
pub fn serialize_to_py<'py, T: serde::Serialize>(
    py: Python<'py>,
    v: &T,
) -> PyResult<Bound<'py, PyAny>> {
    let value = serde_json::to_value(v)
        .map_err(|e| PyValueError::new_err(format!("unrepresentable value: {e}")))?;
    to_py(py, Some(&value))
}
