//! The library's errors as the package's exception classes (defined in
//! `shadelab/_errors.py`), each with the CLI's one-line message: a scene's
//! as `SceneError` (a `ValueError`, with the file, line or key), a device
//! that cannot be opened or fails as `DeviceError` (a `RuntimeError`), a
//! render over the memory limit as `MemoryLimitError` (a `MemoryError`),
//! any other refusal of the input as `RefusalError` (a `ValueError`).

use pyo3::exceptions::{PyKeyboardInterrupt, PyRuntimeError};
use pyo3::prelude::*;
use shadelab::scene::SceneError;

/// An instance of `shadelab._errors.NAME(message)` with `attributes` set.
fn raise(py: Python<'_>, name: &str, message: String, attributes: &[(&str, Py<PyAny>)]) -> PyErr {
    let made = (|| -> PyResult<PyErr> {
        let class = py.import("shadelab._errors")?.getattr(name)?;
        let exception = class.call1((message.clone(),))?;
        for (key, value) in attributes {
            exception.setattr(*key, value)?;
        }
        Ok(PyErr::from_value(exception))
    })();
    made.unwrap_or_else(|e| PyRuntimeError::new_err(format!("{message} ({e})")))
}

/// `SceneError` with the file, line and key the scene's error names.
pub fn scene_error(py: Python<'_>, e: &SceneError) -> PyErr {
    let (file, line, key) = match e {
        SceneError::Read { file, .. }
        | SceneError::UnsupportedFile { file }
        | SceneError::Toml { file, .. }
        | SceneError::Mesh { file, .. }
        | SceneError::TooLarge { file, .. } => (Some(file.clone()), None, None),
        SceneError::Syntax { file, line, .. }
        | SceneError::Invalid { file, line, .. }
        | SceneError::InObject { file, line, .. } => (Some(file.clone()), Some(*line), None),
        SceneError::AtKey { key, .. } => (None, None, Some(key.clone())),
    };
    if matches!(e, SceneError::TooLarge { .. }) {
        return raise(py, "MemoryLimitError", e.to_string(), &[]);
    }
    raise(
        py,
        "SceneError",
        e.to_string(),
        &[
            ("path", optional(py, file)),
            ("line", optional(py, line)),
            ("key", optional(py, key)),
        ],
    )
}

/// `value` as Python, `None` where there is none.
fn optional<'py, T: pyo3::IntoPyObjectExt<'py>>(py: Python<'py>, value: Option<T>) -> Py<PyAny> {
    value
        .and_then(|v| v.into_py_any(py).ok())
        .unwrap_or_else(|| py.None())
}

/// The exception for any error of the library.
pub fn to_py(py: Python<'_>, e: shadelab::Error) -> PyErr {
    use shadelab::Error;
    match e {
        Error::Scene(scene) => scene_error(py, &scene),
        Error::OverMemory(message) => raise(py, "MemoryLimitError", message, &[]),
        Error::Gpu(gpu) if gpu.is_bad_input() => raise(py, "RefusalError", gpu.to_string(), &[]),
        Error::Gpu(gpu) => raise(py, "DeviceError", gpu.to_string(), &[]),
        Error::Output(output) => raise(py, "OutputError", output.to_string(), &[]),
        Error::Metrics(_) | Error::Usage(_) => raise(py, "RefusalError", e.to_string(), &[]),
        Error::Cancelled => PyKeyboardInterrupt::new_err("the render was cancelled"),
    }
}

/// A panic caught at the border: a bug in shadelab, said as one.
pub fn internal(py: Python<'_>, what: &str) -> PyErr {
    raise(
        py,
        "InternalError",
        format!("shadelab failed inside ({what}); this is a bug, please report it with the scene"),
        &[],
    )
}

/// A device that cannot be opened.
pub fn device_error(py: Python<'_>, message: String) -> PyErr {
    raise(py, "DeviceError", message, &[])
}

/// A usage error of the Python call itself.
pub fn refusal(py: Python<'_>, message: impl Into<String>) -> PyErr {
    raise(py, "RefusalError", message.into(), &[])
}

/// Runs library work with the GIL released: other Python threads run
/// meanwhile, and a panic (a bug) comes back as `InternalError`, never
/// across into Python.
pub fn released<T: Send>(
    py: Python<'_>,
    what: &str,
    work: impl FnOnce() -> T + Send,
) -> PyResult<T> {
    py.detach(|| std::panic::catch_unwind(std::panic::AssertUnwindSafe(work)))
        .map_err(|_| internal(py, what))
}

/// A library result as a Python one.
pub trait OrRaise<T> {
    fn or_raise(self, py: Python<'_>) -> PyResult<T>;
}

impl<T> OrRaise<T> for Result<T, shadelab::Error> {
    fn or_raise(self, py: Python<'_>) -> PyResult<T> {
        self.map_err(|e| to_py(py, e))
    }
}
