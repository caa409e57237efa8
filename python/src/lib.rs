//! `shadelab._shadelab`: the library's front door (`shadelab::render`)
//! for Python, and nothing of its own. A scene from a file, TOML text or
//! a dict (`scene.rs`), a device kept between renders whose `render`
//! releases the GIL and stops at Ctrl-C (`device.rs`), the image as a
//! numpy array (`image.rs`), the comparisons (`tools.rs`), and the
//! library's errors as the package's exception classes (`errors.rs`).
//! The Python half of the package (`python/package/shadelab/`) holds the classes
//! Python code defines best: the exceptions and the pytest plugin.

mod device;
mod errors;
mod image;
mod interrupt;
mod options;
mod scene;
mod tools;
mod values;

use pyo3::prelude::*;

/// Panics inside the guard every library call runs in (`errors::released`):
/// for the test that shows a panic comes out as `InternalError`, not as
/// pyo3's `PanicException` (a `BaseException` that `except Exception`
/// misses). Not part of the API.
#[pyfunction]
#[pyo3(name = "_panic_at_the_border")]
fn panic_at_the_border(py: Python<'_>) -> PyResult<()> {
    errors::released(py, "a test of the border", || {
        std::panic::panic_any("a test of the border")
    })
}

#[pymodule]
fn _shadelab(m: &Bound<'_, PyModule>) -> PyResult<()> {
    // Before any device opens: the driver reads the cache folder's
    // variable when it loads (as the CLI's `main` does first).
    if let Err(warning) = shadelab::cache::use_for_mesa_shader_cache() {
        let warnings = m.py().import("warnings")?;
        warnings.call_method1("warn", (format!("shadelab: {warning}"),))?;
    }
    m.add("__version__", env!("CARGO_PKG_VERSION"))?;
    m.add_class::<scene::Scene>()?;
    m.add_class::<device::Device>()?;
    m.add_class::<image::Image>()?;
    m.add_function(wrap_pyfunction!(tools::diff, m)?)?;
    m.add_function(wrap_pyfunction!(tools::check, m)?)?;
    m.add_function(wrap_pyfunction!(tools::compare, m)?)?;
    m.add_function(wrap_pyfunction!(tools::golden_case, m)?)?;
    m.add_function(wrap_pyfunction!(tools::driver_key, m)?)?;
    m.add_function(wrap_pyfunction!(tools::read_image, m)?)?;
    m.add_function(wrap_pyfunction!(panic_at_the_border, m)?)?;
    Ok(())
}
