//! `shadelab.Image`: a render's pixels as a numpy array (H x W x 3,
//! float32, linear, row 0 at the top: the library's own buffer handed to
//! numpy, not copied), with what made it and where the time went, saved
//! as the CLI saves it.

use numpy::{PyArray1, PyArray3, PyArrayMethods, PyUntypedArrayMethods};
use pyo3::prelude::*;
use pyo3::types::PyBytes;
use shadelab::output::{self, ImageMetadata};
use shadelab::render::described::image_metadata;
use shadelab::render::Rendered;
use shadelab::LinearImage;

use crate::errors::{refusal, released, to_py};
use crate::values::json_to_py;

#[pyclass(module = "shadelab", frozen)]
pub struct Image {
    array: Py<PyArray3<f32>>,
    settings: serde_json::Value,
    timings: serde_json::Value,
    stats: Option<serde_json::Value>,
    name: String,
    device: String,
}

/// `image`'s pixels as an H x W x 3 array, its buffer handed over.
pub fn array_of<'py>(py: Python<'py>, image: LinearImage) -> PyResult<Bound<'py, PyArray3<f32>>> {
    let (h, w) = (image.height as usize, image.width as usize);
    let flat: Vec<f32> = bytemuck::cast_vec(image.pixels);
    PyArray1::from_vec(py, flat).reshape([h, w, 3])
}

/// An H x W x 3 array (any float type) as a `LinearImage`, copied.
pub fn linear_image_of(py: Python<'_>, array: &Bound<'_, PyAny>) -> PyResult<LinearImage> {
    let numpy = py.import("numpy")?;
    let array = numpy.call_method1("ascontiguousarray", (array, "float32"))?;
    let array = array
        .cast::<PyArray3<f32>>()
        .map_err(|_| refusal(py, "an image array is H x W x 3"))?;
    let shape = array.shape().to_vec();
    if shape[2] != 3 {
        return Err(refusal(
            py,
            format!("an image array is H x W x 3, not {shape:?}"),
        ));
    }
    let readonly = array.readonly();
    let values = readonly
        .as_slice()
        .map_err(|e| refusal(py, e.to_string()))?;
    Ok(LinearImage {
        width: shape[1] as u32,
        height: shape[0] as u32,
        pixels: values.chunks_exact(3).map(|p| [p[0], p[1], p[2]]).collect(),
    })
}

/// What `render --json` says of a render beside its timings: the rays by
/// kind, the photons or samples traced, the estimated error, the photon
/// map's figures.
fn stats_of(rendered: &Rendered) -> Option<serde_json::Value> {
    let mut stats = serde_json::Map::new();
    if let Some(rays) = &rendered.ray_stats {
        stats.insert("rays".into(), serde_json::to_value(rays).ok()?);
    }
    if let Some(film) = &rendered.film {
        stats.insert("traced".into(), film.traced.into());
        stats.insert("estimated_rmse".into(), film.estimated_rmse.into());
        if let Some(photons) = &film.photons {
            stats.insert("photons".into(), serde_json::to_value(photons).ok()?);
        }
    }
    if let Some(caustics) = &rendered.caustics {
        stats.insert("caustics".into(), serde_json::to_value(caustics).ok()?);
    }
    (!stats.is_empty()).then_some(serde_json::Value::Object(stats))
}

impl Image {
    pub fn new(
        py: Python<'_>,
        rendered: Rendered,
        settings: serde_json::Value,
        name: String,
        device: String,
    ) -> PyResult<Self> {
        let timings = serde_json::to_value(rendered.timings).unwrap_or_default();
        let stats = stats_of(&rendered);
        let array = array_of(py, rendered.image)?.unbind();
        Ok(Self {
            array,
            settings,
            timings,
            stats,
            name,
            device,
        })
    }

    /// What made it, as JSON.
    pub fn settings_json(&self) -> &serde_json::Value {
        &self.settings
    }

    /// The device's name, as the image records it.
    pub fn device(&self) -> &str {
        &self.device
    }

    fn metadata(&self) -> ImageMetadata {
        image_metadata(&self.name, &self.device, &self.settings)
    }

    /// The pixels as they are now, copied.
    pub fn linear(&self, py: Python<'_>) -> PyResult<LinearImage> {
        linear_image_of(py, self.array.bind(py).as_any())
    }
}

#[pymethods]
impl Image {
    /// The pixels: float32, H x W x 3, linear RGB, row 0 at the top.
    #[getter]
    fn array<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray3<f32>> {
        self.array.bind(py).clone()
    }

    /// What made the image (`render --json`'s `settings`).
    #[getter]
    fn settings<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        json_to_py(py, &self.settings)
    }

    /// Where the time went, in milliseconds (`render --json`'s `timings_ms`).
    #[getter]
    fn timings<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        json_to_py(py, &self.timings)
    }

    /// Rays by kind (with `stats=True`), photons or samples traced and the
    /// estimated RMSE (Monte Carlo modes), the photon map's figures; `None`
    /// where the render has none.
    #[getter]
    fn stats<'py>(&self, py: Python<'py>) -> PyResult<Option<Bound<'py, PyAny>>> {
        self.stats.as_ref().map(|s| json_to_py(py, s)).transpose()
    }

    #[getter]
    fn width(&self, py: Python<'_>) -> usize {
        self.array.bind(py).shape()[1]
    }

    #[getter]
    fn height(&self, py: Python<'_>) -> usize {
        self.array.bind(py).shape()[0]
    }

    /// Writes the image as `shadelab render --out PATH` does: `.png` (8-bit
    /// sRGB, the settings in its text) or `.exr` (linear 32-bit float).
    fn save(&self, py: Python<'_>, path: std::path::PathBuf) -> PyResult<()> {
        let image = self.linear(py)?;
        let metadata = self.metadata();
        released(py, "writing an image", || {
            output::write_image_with(&image, &path, &metadata)
        })?
        .map_err(|e| to_py(py, e.into()))
    }

    /// The image as a PNG (8-bit sRGB), for a notebook to show.
    fn _repr_png_<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyBytes>> {
        let image = self.linear(py)?;
        let bytes =
            output::encode_with(&image, std::path::Path::new("image.png"), &self.metadata())
                .map_err(|e| to_py(py, e.into()))?;
        Ok(PyBytes::new(py, &bytes))
    }

    /// `numpy.asarray(image)`: the pixels.
    #[pyo3(signature = (dtype=None, copy=None))]
    fn __array__<'py>(
        &self,
        py: Python<'py>,
        dtype: Option<&Bound<'py, PyAny>>,
        copy: Option<bool>,
    ) -> PyResult<Bound<'py, PyAny>> {
        let array = self.array.bind(py).clone().into_any();
        match (dtype, copy) {
            (Some(dtype), _) => array.call_method1("astype", (dtype,)),
            (None, Some(true)) => array.call_method0("copy"),
            _ => Ok(array),
        }
    }

    fn __repr__(&self, py: Python<'_>) -> String {
        let shading = self.settings["shading"].as_str().unwrap_or("?");
        format!(
            "Image({:?}, {}, {}x{}, on {})",
            self.name,
            shading,
            self.width(py),
            self.height(py),
            self.device
        )
    }
}
