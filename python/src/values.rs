//! Python values to the library's (a dict to a TOML table) and back (JSON
//! to dicts), the key path of a value that has no TOML form named.

use pyo3::exceptions::PyTypeError;
use pyo3::prelude::*;
use pyo3::types::{PyBool, PyDict, PyFloat, PyInt, PyList, PyString, PyTuple};

/// `obj` as a TOML value; `path` names it in an error.
pub fn to_toml(obj: &Bound<'_, PyAny>, path: &str) -> Result<toml::Value, String> {
    if obj.is_instance_of::<PyBool>() {
        return Ok(toml::Value::Boolean(obj.extract().unwrap_or(false)));
    }
    if obj.is_instance_of::<PyInt>() {
        return obj
            .extract::<i64>()
            .map(toml::Value::Integer)
            .map_err(|_| format!("{path}: the integer does not fit 64 bits"));
    }
    if obj.is_instance_of::<PyFloat>() {
        return Ok(toml::Value::Float(obj.extract().unwrap_or(f64::NAN)));
    }
    if obj.is_instance_of::<PyString>() {
        return Ok(toml::Value::String(obj.extract().unwrap_or_default()));
    }
    if let Ok(dict) = obj.cast::<PyDict>() {
        return Ok(toml::Value::Table(to_table(dict, path)?));
    }
    if obj.is_instance_of::<PyList>() || obj.is_instance_of::<PyTuple>() {
        let items = obj
            .try_iter()
            .map_err(|e| format!("{path}: {e}"))?
            .enumerate()
            .map(|(i, item)| {
                let item = item.map_err(|e| format!("{path}[{i}]: {e}"))?;
                to_toml(&item, &format!("{path}[{i}]"))
            })
            .collect::<Result<Vec<_>, _>>()?;
        return Ok(toml::Value::Array(items));
    }
    // numpy arrays and scalars: their Python values.
    if let Ok(plain) = obj.call_method0("tolist") {
        if !plain.is(obj) {
            return to_toml(&plain, path);
        }
    }
    let type_name = obj
        .get_type()
        .name()
        .map(|n| n.to_string())
        .unwrap_or_default();
    Err(format!(
        "{path}: expected a number, a string, a bool, a list or a dict, not {type_name}"
    ))
}

/// A dict with string keys as a TOML table.
pub fn to_table(dict: &Bound<'_, PyDict>, path: &str) -> Result<toml::Table, String> {
    let mut table = toml::Table::new();
    for (key, value) in dict.iter() {
        let key: String = key
            .extract()
            .map_err(|_| format!("{path}: a key that is not a string"))?;
        let here = if path.is_empty() {
            key.clone()
        } else {
            format!("{path}.{key}")
        };
        if value.is_none() {
            // `None` leaves a key to its default, as leaving it out does.
            continue;
        }
        table.insert(key, to_toml(&value, &here)?);
    }
    Ok(table)
}

/// A TOML value as plain Python (dicts, lists, numbers, strings).
pub fn toml_to_py<'py>(py: Python<'py>, value: &toml::Value) -> PyResult<Bound<'py, PyAny>> {
    let json = serde_json::to_string(value).map_err(|e| PyTypeError::new_err(e.to_string()))?;
    py.import("json")?.call_method1("loads", (json,))
}

/// A JSON value as plain Python.
pub fn json_to_py<'py>(py: Python<'py>, value: &serde_json::Value) -> PyResult<Bound<'py, PyAny>> {
    py.import("json")?
        .call_method1("loads", (value.to_string(),))
}
