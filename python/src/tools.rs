//! The library's comparisons from Python: `diff` (two images' figures and
//! FLIP heat map), `check` (the GPU against the CPU reference), `compare`
//! (shader variants, speed against error) and one golden case (a render
//! judged against its stored reference, as `shadelab golden` judges it).

use std::path::PathBuf;

use pyo3::prelude::*;
use pyo3::types::PyDict;
use shadelab::check::CheckThresholds;
use shadelab::compare::report::{pareto_front, Metric, ReferenceChoice};
use shadelab::compare::run::{run, CompareOptions};
use shadelab::compare::variant::{default_variants, Variant};
use shadelab::diff::{compare_images, parse_thresholds, Judging, Preset};
use shadelab::golden::{keys, mark_settings, CaseRender, JudgeOptions};
use shadelab::metrics;
use shadelab::shading::Shading;
use shadelab::LinearImage;

use crate::device::Device;
use crate::errors::{refusal, released, to_py, OrRaise};
use crate::image::{array_of, linear_image_of, Image};
use crate::options::{msaa_text, RenderOptions};
use crate::scene::Scene;
use crate::values::json_to_py;

/// An image given to a comparison: an `Image`, an H x W x 3 array, or the
/// path of a PNG or EXR file.
fn image_of(py: Python<'_>, given: &Bound<'_, PyAny>) -> PyResult<LinearImage> {
    if let Ok(image) = given.cast::<Image>() {
        return image.get().linear(py);
    }
    if let Ok(path) = given.extract::<PathBuf>() {
        return shadelab::output::read_image(&path).map_err(|e| to_py(py, e.into()));
    }
    linear_image_of(py, given)
}

/// `stored-reference` or `gpu-vs-reference`, with `thresholds` on top
/// (`{"rmse": 0.01}`, as `--threshold rmse=0.01`).
fn judging(
    py: Python<'_>,
    preset: &str,
    thresholds: Option<&Bound<'_, PyDict>>,
) -> PyResult<(Judging, Preset)> {
    let preset = match preset {
        "stored-reference" => Preset::StoredReference,
        "gpu-vs-reference" => Preset::GpuVsReference,
        other => {
            return Err(refusal(
                py,
                format!("preset {other:?}: expected \"stored-reference\" or \"gpu-vs-reference\""),
            ))
        }
    };
    let entries = thresholds
        .map(|t| {
            t.iter()
                .map(|(k, v)| Ok(format!("{}={}", k.str()?, v.str()?)))
                .collect::<PyResult<Vec<String>>>()
        })
        .transpose()?
        .unwrap_or_default();
    let limits = parse_thresholds(preset.thresholds(), &entries).or_raise(py)?;
    Ok((Judging::new(limits), preset))
}

/// Compares `actual` with `expected` as `shadelab diff` does: every figure
/// (max, p99, RMSE, PSNR, FLIP; interior and silhouette apart), the
/// verdicts against the preset's limits with `thresholds` on top, and the
/// FLIP heat map as an H x W x 3 array.
#[pyfunction]
#[pyo3(signature = (expected, actual, *, preset="gpu-vs-reference", thresholds=None))]
pub fn diff<'py>(
    py: Python<'py>,
    expected: &Bound<'py, PyAny>,
    actual: &Bound<'py, PyAny>,
    preset: &str,
    thresholds: Option<&Bound<'py, PyDict>>,
) -> PyResult<Bound<'py, PyDict>> {
    let (judging, _) = judging(py, preset, thresholds)?;
    let (expected, actual) = (image_of(py, expected)?, image_of(py, actual)?);
    let pair = released(py, "comparing images", || {
        compare_images(&expected, &actual, &judging)
    })?
    .map_err(|e| refusal(py, format!("the images cannot be compared: {e}")))?;
    let out = PyDict::new(py);
    out.set_item("passed", pair.failures.is_empty())?;
    out.set_item("failures", pair.failures.clone())?;
    let figures = serde_json::to_value(&pair.comparison).unwrap_or_default();
    out.set_item("figures", json_to_py(py, &figures)?)?;
    let verdicts = serde_json::to_value(&pair.verdicts).unwrap_or_default();
    out.set_item("verdicts", json_to_py(py, &verdicts)?)?;
    out.set_item(
        "heatmap",
        array_of(py, metrics::flip_heatmap(&pair.comparison.flip))?,
    )?;
    Ok(out)
}

/// The device a call was given, or a new one on the GPU.
fn device_or_new(py: Python<'_>, device: Option<Py<Device>>) -> PyResult<Py<Device>> {
    match device {
        Some(d) => Ok(d),
        None => {
            let class = py.get_type::<Device>();
            Ok(class.call0()?.cast_into::<Device>()?.unbind())
        }
    }
}

fn modes_of(py: Python<'_>, shading: Option<Vec<String>>) -> PyResult<Vec<Shading>> {
    match shading {
        None => Ok(Shading::BY_DEFAULT.to_vec()),
        Some(names) => names
            .iter()
            .map(|n| {
                n.parse()
                    .map_err(|e: String| refusal(py, format!("shading: {e}")))
            })
            .collect(),
    }
}

/// The GPU against the CPU reference on `scene`, mode by mode, judged by
/// `shadelab check`'s limits: a record per mode (`passed`, `failures`, the
/// figures, each render's time).
#[pyfunction]
#[pyo3(signature = (scene=None, shading=None, *, device=None, width=None, height=None))]
pub fn check<'py>(
    py: Python<'py>,
    scene: Option<&Bound<'py, PyAny>>,
    shading: Option<Vec<String>>,
    device: Option<Py<Device>>,
    width: Option<i64>,
    height: Option<i64>,
) -> PyResult<Vec<Bound<'py, PyDict>>> {
    let given = Scene::coerce(py, scene)?;
    let mut scene = (*given.get().inner).clone();
    let size = shadelab::render::overrides::Overrides {
        width,
        height,
        ..Default::default()
    };
    size.apply_size(&mut scene).or_raise(py)?;
    let device = device_or_new(py, device)?;
    let mut records = Vec::new();
    for shading in modes_of(py, shading)? {
        let limits = CheckThresholds::for_render(shading, scene.render.msaa);
        let library = device.get().library();
        let outcome = released(py, "a check", || {
            shadelab::check::check(library, &scene, &scene, shading, &limits)
        })?
        .or_raise(py)?;
        let judgement = &outcome.judgement;
        let record = PyDict::new(py);
        record.set_item("shading", shading.to_string())?;
        record.set_item("passed", outcome.passed())?;
        record.set_item("failures", judgement.failures.clone())?;
        let figures = serde_json::json!({
            "interior": judgement.interior,
            "edges": judgement.edges,
            "edge_share": judgement.edge_share,
            "flip": judgement.flip,
            "scale": judgement.scale,
        });
        record.set_item("figures", json_to_py(py, &figures)?)?;
        record.set_item("gpu_ms", outcome.gpu_ms)?;
        record.set_item("cpu_ms", outcome.cpu_ms)?;
        records.push(record);
    }
    Ok(records)
}

/// A JSON object's leaves as one flat record: `{"timing": {"gpu_ms": 3}}`
/// gives `{"timing.gpu_ms": 3}`, the shape a DataFrame takes.
fn flatten(
    prefix: &str,
    value: &serde_json::Value,
    out: &mut serde_json::Map<String, serde_json::Value>,
) {
    match value {
        serde_json::Value::Object(fields) => {
            for (k, v) in fields {
                let key = if prefix.is_empty() {
                    k.clone()
                } else {
                    format!("{prefix}.{k}")
                };
                flatten(&key, v, out);
            }
        }
        other => {
            out.insert(prefix.to_string(), other.clone());
        }
    }
}

/// Shader variants of one scene, speed against error, as `shadelab
/// compare` measures them (its images, heat maps and report in `out`): a
/// flat record per variant (a DataFrame takes the list), `pareto` true on
/// the front of time against error.
#[pyfunction]
#[pyo3(signature = (scene=None, variants=None, *, out=None, runs=3, device=None))]
pub fn compare<'py>(
    py: Python<'py>,
    scene: Option<&Bound<'py, PyAny>>,
    variants: Option<Vec<String>>,
    out: Option<PathBuf>,
    runs: usize,
    device: Option<Py<Device>>,
) -> PyResult<Vec<Bound<'py, PyAny>>> {
    let given = Scene::coerce(py, scene)?;
    let scene = &given.get().inner;
    let variants: Vec<Variant> = match variants {
        None => default_variants(scene),
        Some(names) => names
            .iter()
            .map(|v| v.parse::<Variant>().map_err(|e| refusal(py, e)))
            .collect::<PyResult<_>>()?,
    };
    if !(1..=1000).contains(&runs) {
        return Err(refusal(
            py,
            format!("runs {runs} is out of range; expected 1 to 1000"),
        ));
    }
    let out = out.unwrap_or_else(|| PathBuf::from("compare-out"));
    shadelab::output::prepare_output_folder(&out).map_err(|e| to_py(py, e.into()))?;
    let device = device_or_new(py, device)?;
    let options = CompareOptions {
        runs,
        shard: None,
        reference: ReferenceChoice::Global,
        metric: Metric::Rmse,
        budget: None,
        skip: Default::default(),
    };
    let library = device.get().library();
    let report = released(py, "a comparison", || {
        run(
            library,
            scene,
            &given.get().name,
            &variants,
            &options,
            &out,
            |_, _, _| {},
        )
    })?
    .or_raise(py)?;
    let points: Vec<(f64, f64)> = report
        .variants
        .iter()
        .map(|v| (v.timing.gpu_ms, v.model_error.rmse))
        .collect();
    let front = pareto_front(&points);
    report
        .variants
        .iter()
        .zip(front)
        .map(|(variant, on_front)| {
            let mut record = serde_json::Map::new();
            flatten(
                "",
                &serde_json::to_value(variant).unwrap_or_default(),
                &mut record,
            );
            record.insert("pareto".into(), on_front.into());
            json_to_py(py, &serde_json::Value::Object(record))
        })
        .collect()
}

/// This device's folder of golden references: `shadelab golden`'s key,
/// from the device's and the driver's names.
#[pyfunction]
pub fn driver_key(device: &Device) -> String {
    match device.library().gpu() {
        Some(c) => keys::driver_key(&c.info.name, &c.info.driver),
        None => keys::driver_key("no device", ""),
    }
}

/// One golden case, judged as `shadelab golden` judges it: `scene` rendered
/// in `shading` on `device`, compared with `references/KEY/FILE` (this
/// driver's) or `references/FILE` (shared), `FILE` being `{name}-{mode}.png`.
/// `create` makes a missing reference, `bless` rewrites one over its
/// limits; a case that fails leaves its render and heat map in `out`. The
/// case's record (`status`, `failures`, figures, the files), as
/// `golden.json` holds it.
// The keyword arguments are `shadelab golden`'s flags, one each.
#[allow(clippy::too_many_arguments)]
#[pyfunction]
#[pyo3(signature = (device, scene, shading, references, *, name=None, preset="stored-reference",
    thresholds=None, create=false, bless=false, per_driver=false, out=None, width=None,
    height=None, msaa=None, lighting=None))]
pub fn golden_case<'py>(
    py: Python<'py>,
    device: &Device,
    scene: &Bound<'py, PyAny>,
    shading: &str,
    references: PathBuf,
    name: Option<String>,
    preset: &str,
    thresholds: Option<&Bound<'py, PyDict>>,
    create: bool,
    bless: bool,
    per_driver: bool,
    out: Option<PathBuf>,
    width: Option<i64>,
    height: Option<i64>,
    msaa: Option<&Bound<'py, PyAny>>,
    lighting: Option<String>,
) -> PyResult<Bound<'py, PyAny>> {
    let (judging, preset) = judging(py, preset, thresholds)?;
    let given = Scene::coerce(py, Some(scene))?;
    let options = RenderOptions {
        width,
        height,
        msaa: msaa_text(py, msaa)?,
        lighting,
        ..RenderOptions::default()
    };
    let image = device.render_scene(py, given.get(), shading, &options, false, None)?;
    let key = name.unwrap_or_else(|| given.get().name.clone());
    let file = format!("{key}-{shading}.png");
    let mut settings = image.settings_json().clone();
    let hook = options.overrides(py)?.lighting;
    mark_settings(
        &mut settings,
        &key,
        hook.as_ref().map(|h| h.source.as_str()),
    );
    let (device_name, driver) = (
        image.device().to_string(),
        device.library().gpu().map(|c| c.info.driver.clone()),
    );
    let metadata = shadelab::render::described::image_metadata(&key, &device_name, &settings);
    let out = out.unwrap_or_else(|| PathBuf::from("golden-out"));
    let options = JudgeOptions {
        references,
        key: driver_key(device),
        judging,
        create,
        bless,
        per_driver,
        out: out.clone(),
    };
    let linear = image.linear(py)?;
    if linear.non_finite_pixels() > 0 {
        return Err(refusal(
            py,
            format!("{file}: the render has pixels that are not finite (NaN or infinity); an image with them is never a reference"),
        ));
    }
    shadelab::output::prepare_output_folder(&out).map_err(|e| to_py(py, e.into()))?;
    shadelab::golden::clear_pictures(&out, &file);
    let render = CaseRender {
        file: &file,
        image: &linear,
        metadata: &metadata,
        settings: &settings,
        device: &device_name,
        driver: driver.as_deref(),
    };
    let judged = released(py, "judging a golden case", || options.judge(&render))?.or_raise(py)?;
    let case = shadelab::golden::report::ReportCase {
        scene: key.clone(),
        shading: shading
            .parse()
            .map_err(|e: String| refusal(py, format!("shading: {e}")))?,
        file: file.clone(),
        judged,
    };
    let mut record = shadelab::golden::report::case_json(&case);
    record["preset"] = preset.name().into();
    record["key"] = options.key.clone().into();
    json_to_py(py, &record)
}

/// A PNG (8-bit sRGB, decoded to linear) or EXR (linear float) file as an
/// H x W x 3 float32 array, as `diff` and `golden` read images.
#[pyfunction]
pub fn read_image<'py>(
    py: Python<'py>,
    path: PathBuf,
) -> PyResult<Bound<'py, numpy::PyArray3<f32>>> {
    let image = released(py, "reading an image", || {
        shadelab::output::read_image(&path)
    })?
    .map_err(|e| to_py(py, e.into()))?;
    array_of(py, image)
}
