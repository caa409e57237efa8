//! Python values to the library's (a dict to a TOML table) and back (JSON
//! to dicts), the key path of a value that has no TOML form named.

use pyo3::exceptions::PyTypeError;
use pyo3::prelude::*;
use pyo3::types::{PyBool, PyDict, PyFloat, PyInt, PyList, PyString, PyTuple};

/// Where in a dict a value has no TOML form, and why: the path is built
/// on the way back up, so a dict that converts allocates none.
pub struct BadValue {
    /// The path's parts, innermost first (`radius`, `[2]`, `objects`).
    parts: Vec<String>,
    message: String,
}

impl BadValue {
    fn new(message: String) -> Self {
        Self {
            parts: Vec::new(),
            message,
        }
    }

    fn under(mut self, part: String) -> Self {
        self.parts.push(part);
        self
    }

    /// `objects[2].radius`.
    pub fn key(&self) -> String {
        let mut key = String::new();
        for part in self.parts.iter().rev() {
            if !key.is_empty() && !part.starts_with('[') {
                key.push('.');
            }
            key.push_str(part);
        }
        key
    }

    pub fn message(&self) -> &str {
        &self.message
    }
}

/// `obj` as a TOML value.
pub fn to_toml(obj: &Bound<'_, PyAny>) -> Result<toml::Value, BadValue> {
    if obj.is_instance_of::<PyBool>() {
        return Ok(toml::Value::Boolean(obj.extract().unwrap_or(false)));
    }
    if obj.is_instance_of::<PyInt>() {
        return obj
            .extract::<i64>()
            .map(toml::Value::Integer)
            .map_err(|_| BadValue::new("the integer does not fit 64 bits".into()));
    }
    if obj.is_instance_of::<PyFloat>() {
        return Ok(toml::Value::Float(obj.extract().unwrap_or(f64::NAN)));
    }
    if obj.is_instance_of::<PyString>() {
        return Ok(toml::Value::String(obj.extract().unwrap_or_default()));
    }
    if let Ok(dict) = obj.cast::<PyDict>() {
        return Ok(toml::Value::Table(to_table(dict)?));
    }
    if let Ok(list) = obj.cast::<PyList>() {
        return items_to_toml(list.iter());
    }
    if let Ok(tuple) = obj.cast::<PyTuple>() {
        return items_to_toml(tuple.iter());
    }
    // numpy arrays and scalars: their Python values.
    if let Ok(plain) = obj.call_method0("tolist") {
        if !plain.is(obj) {
            return to_toml(&plain);
        }
    }
    let type_name = obj
        .get_type()
        .name()
        .map(|n| n.to_string())
        .unwrap_or_default();
    Err(BadValue::new(format!(
        "expected a number, a string, a bool, a list or a dict, not {type_name}"
    )))
}

/// A list's or tuple's items as a TOML array.
fn items_to_toml<'py>(
    items: impl Iterator<Item = Bound<'py, PyAny>>,
) -> Result<toml::Value, BadValue> {
    items
        .enumerate()
        .map(|(i, item)| to_toml(&item).map_err(|bad| bad.under(format!("[{i}]"))))
        .collect::<Result<Vec<_>, _>>()
        .map(toml::Value::Array)
}

/// A dict with string keys as a TOML table; a key set to `None` is left
/// out (its default, as in a file that leaves it out).
pub fn to_table(dict: &Bound<'_, PyDict>) -> Result<toml::Table, BadValue> {
    let mut table = toml::Table::new();
    for (key, value) in dict.iter() {
        let key: String = key
            .extract()
            .map_err(|_| BadValue::new("a key that is not a string".into()))?;
        if value.is_none() {
            continue;
        }
        let value = to_toml(&value).map_err(|bad| bad.under(key.clone()))?;
        table.insert(key, value);
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
