//! `shadelab.Device`: the library's `render::Device` (the Vulkan context
//! and the pipelines it built, kept between renders) and `render`, which
//! runs the library's plan with the GIL released, polls for Ctrl-C and
//! progress meanwhile, and hands back an `Image`.

use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::{mpsc, Arc, Mutex};
use std::time::Duration;

use pyo3::prelude::*;
use shadelab::backend_choice::{self, Backend};
use shadelab::gpu::GpuOptions;
use shadelab::memory::MemoryLimit;
use shadelab::output::ImageFormat;
use shadelab::render::described::{color_target, effective_settings};
use shadelab::render::overrides::refuse_hook_on_cpu;
use shadelab::render::{Plan, RenderRequest, Rendered};
use shadelab::shading::Shading;
use shadelab::work_counter::WorkCounter;

use crate::errors::{device_error, internal, refusal, released, OrRaise};
use crate::image::Image;
use crate::interrupt::{main_thread_cancel, may_take_sigint, run_with_sigint};
use crate::options::{msaa_text, RenderOptions};
use crate::scene::Scene;

/// Where renders run: `gpu`, `cpu` (the f64 reference) or `auto`
/// (whichever should give the image first, as `render --backend auto`).
#[derive(Clone, Copy, PartialEq, Eq)]
enum Choice {
    Gpu,
    Cpu,
    Auto,
}

/// A device kept between renders: open one and render many images on it.
#[pyclass(module = "shadelab", frozen)]
pub struct Device {
    device: shadelab::render::Device,
    choice: Choice,
    /// One GPU render at a time: a Vulkan queue is used by one thread at
    /// a time. Two Python threads on one device take turns; CPU renders
    /// run side by side.
    gpu_turn: Mutex<()>,
}

impl Device {
    /// The backend one render takes.
    fn backend_for(&self, scene: &shadelab::scene::Scene, shading: Shading) -> Backend {
        match (self.choice, self.device.gpu()) {
            (Choice::Cpu, _) | (Choice::Auto, None) => Backend::Cpu,
            (Choice::Gpu, _) => Backend::Gpu,
            (Choice::Auto, Some(_)) => backend_choice::choose(scene, shading).backend,
        }
    }

    /// The device's name and driver for `backend`, as images record them.
    fn names(&self, backend: Backend) -> (String, Option<String>) {
        match (backend, self.device.gpu()) {
            (Backend::Gpu, Some(c)) => (c.info.name.clone(), Some(c.info.driver.clone())),
            _ => ("CPU reference (f64)".to_string(), None),
        }
    }

    pub(crate) fn library(&self) -> &shadelab::render::Device {
        &self.device
    }
}

/// The progress a render reports: a callable given `(done, total)`, or a
/// tqdm bar (`progress=True`).
struct Progress {
    callback: Option<Py<PyAny>>,
    bar: Option<Py<PyAny>>,
    tqdm: bool,
    shown: u64,
}

impl Progress {
    fn new(given: Option<&Bound<'_, PyAny>>) -> PyResult<Self> {
        let mut progress = Self {
            callback: None,
            bar: None,
            tqdm: false,
            shown: 0,
        };
        match given {
            None => {}
            Some(g) if g.is_callable() => progress.callback = Some(g.clone().unbind()),
            Some(g) => progress.tqdm = g.is_truthy()?,
        }
        Ok(progress)
    }

    /// Says the counter's figures where they moved.
    fn update(&mut self, py: Python<'_>, counter: &WorkCounter, unit: &str) -> PyResult<()> {
        let (_, done, total) = counter.read();
        if total == 0 || done == self.shown {
            return Ok(());
        }
        if let Some(callback) = &self.callback {
            callback.call1(py, (done, total))?;
        } else if self.tqdm {
            if self.bar.is_none() {
                let tqdm = py.import("tqdm")?.getattr("tqdm")?;
                let kwargs = pyo3::types::PyDict::new(py);
                kwargs.set_item("total", total)?;
                kwargs.set_item("unit", unit)?;
                self.bar = Some(tqdm.call((), Some(&kwargs))?.unbind());
            }
            if let Some(bar) = &self.bar {
                bar.call_method1(py, "update", (done.saturating_sub(self.shown),))?;
            }
        }
        self.shown = done;
        Ok(())
    }

    fn close(&self, py: Python<'_>) {
        if let Some(bar) = &self.bar {
            let _ = bar.call_method0(py, "close");
        }
    }
}

/// Runs `work` on a thread of its own with the GIL released; meanwhile,
/// every 20 ms, takes the GIL to run Python's signal handlers (Ctrl-C's
/// `KeyboardInterrupt` sets `cancel`, which the render reads between its
/// batches) and to report progress. A panic comes back as `InternalError`.
fn run_released<T: Send>(
    py: Python<'_>,
    cancel: &AtomicBool,
    counter: &WorkCounter,
    unit: &str,
    progress: &mut Progress,
    work: impl FnOnce() -> Result<T, shadelab::Error> + Send,
) -> PyResult<T> {
    let mut interrupted: Option<PyErr> = None;
    let outcome = py.detach(|| {
        std::thread::scope(|s| {
            let (done, finished) = mpsc::channel();
            s.spawn(move || {
                let outcome = std::panic::catch_unwind(std::panic::AssertUnwindSafe(work));
                let _ = done.send(outcome);
            });
            loop {
                match finished.recv_timeout(Duration::from_millis(20)) {
                    Ok(outcome) => return outcome,
                    // Once stopped, the render is only waited for.
                    Err(mpsc::RecvTimeoutError::Timeout) if interrupted.is_some() => {}
                    Err(mpsc::RecvTimeoutError::Timeout) => Python::attach(|py| {
                        let polled = py
                            .check_signals()
                            .and_then(|()| progress.update(py, counter, unit));
                        if let Err(e) = polled {
                            cancel.store(true, Ordering::Relaxed);
                            interrupted = Some(e);
                        }
                    }),
                    Err(mpsc::RecvTimeoutError::Disconnected) => {
                        return Err(Box::new("the render's thread ended without a result"))
                    }
                }
            }
        })
    });
    // The last count, which the render reached after the last poll.
    if interrupted.is_none() {
        if let Err(e) = progress.update(py, counter, unit) {
            interrupted = Some(e);
        }
    }
    progress.close(py);
    match (outcome, interrupted) {
        (_, Some(interrupt)) => Err(interrupt),
        (Ok(result), None) => result.or_raise(py),
        (Err(_), None) => Err(internal(py, "a render panicked")),
    }
}

#[pymethods]
impl Device {
    /// Opens a device: `name_or_index` picks a Vulkan device as
    /// `shadelab info` lists them (default: lavapipe, or `SHADELAB_DEVICE`);
    /// `backend` is `"gpu"`, `"cpu"` (the f64 reference only) or `"auto"`
    /// (each render where it should finish first; the CPU where no GPU
    /// opens).
    #[new]
    #[pyo3(signature = (name_or_index=None, backend="gpu"))]
    fn new(
        py: Python<'_>,
        name_or_index: Option<&Bound<'_, PyAny>>,
        backend: &str,
    ) -> PyResult<Self> {
        let choice = match backend {
            "gpu" => Choice::Gpu,
            "cpu" => Choice::Cpu,
            "auto" => Choice::Auto,
            other => {
                return Err(refusal(
                    py,
                    format!("backend {other:?}: expected \"gpu\", \"cpu\" or \"auto\""),
                ))
            }
        };
        let mut options = GpuOptions::from_env();
        if let Some(given) = name_or_index {
            options.device = Some(given.str()?.to_string());
        }
        let device = match choice {
            Choice::Cpu => shadelab::render::Device::cpu_only(),
            // Whatever stops a device opening (none there, none of that
            // name, no loader) is the device's error here.
            Choice::Gpu => released(py, "opening a device", || {
                shadelab::render::Device::open(&options)
            })?
            .map_err(|e| device_error(py, e.to_string()))?,
            Choice::Auto => released(py, "opening a device", || {
                shadelab::render::Device::open(&options)
            })?
            .unwrap_or_else(|_| shadelab::render::Device::cpu_only()),
        };
        Ok(Self {
            device,
            choice,
            gpu_turn: Mutex::new(()),
        })
    }

    /// The GPU's name (`"llvmpipe ..."` for lavapipe), or the CPU reference's.
    #[getter]
    fn name(&self) -> String {
        self.names(if self.device.gpu().is_some() {
            Backend::Gpu
        } else {
            Backend::Cpu
        })
        .0
    }

    /// The GPU driver's name and version; `None` without a GPU.
    #[getter]
    fn driver(&self) -> Option<String> {
        self.device.gpu().map(|c| c.info.driver.clone())
    }

    /// `"gpu"`, `"cpu"` or `"auto"`, as opened.
    #[getter]
    fn backend(&self) -> &'static str {
        match self.choice {
            Choice::Gpu => "gpu",
            Choice::Cpu => "cpu",
            Choice::Auto => "auto",
        }
    }

    /// Renders `scene` (a `Scene`, a scene file's path or a dict; the
    /// built-in default scene if left out) in `shading`, the keyword
    /// arguments overriding the scene's settings as the CLI's flags of the
    /// same names do. The GIL is released while it renders; Ctrl-C stops it
    /// (`KeyboardInterrupt`) and leaves the device usable. `progress`: a
    /// callable given `(done, total)`, or `True` for a tqdm bar.
    // The keyword arguments are the CLI's flags, one each.
    #[allow(clippy::too_many_arguments)]
    #[pyo3(signature = (scene=None, shading="phong", *, width=None, height=None, msaa=None,
        samples=None, depth=None, bounces=None, photons=None, caustics=None, caustic_passes=None,
        lighting=None, traversal=None, watchdog=None, shadows=None, time=None, error=None,
        stats=false, progress=None))]
    fn render(
        &self,
        py: Python<'_>,
        scene: Option<&Bound<'_, PyAny>>,
        shading: &str,
        width: Option<i64>,
        height: Option<i64>,
        msaa: Option<&Bound<'_, PyAny>>,
        samples: Option<i64>,
        depth: Option<i64>,
        bounces: Option<i64>,
        photons: Option<i64>,
        caustics: Option<i64>,
        caustic_passes: Option<i64>,
        lighting: Option<String>,
        traversal: Option<String>,
        watchdog: Option<f64>,
        shadows: Option<bool>,
        time: Option<f64>,
        error: Option<f64>,
        stats: bool,
        progress: Option<&Bound<'_, PyAny>>,
    ) -> PyResult<Image> {
        let options = RenderOptions {
            width,
            height,
            msaa: msaa_text(py, msaa)?,
            samples,
            depth,
            bounces,
            photons,
            caustics,
            caustic_passes,
            lighting,
            traversal,
            watchdog,
            shadows,
            time,
            error,
        };
        let given = Scene::coerce(py, scene)?;
        self.render_scene(py, given.get(), shading, &options, stats, progress)
    }

    fn __repr__(&self) -> String {
        format!("Device({:?}, backend={:?})", self.name(), self.backend())
    }
}

impl Device {
    /// `render`, its arguments gathered.
    pub(crate) fn render_scene(
        &self,
        py: Python<'_>,
        given: &Scene,
        shading: &str,
        options: &RenderOptions,
        stats: bool,
        progress: Option<&Bound<'_, PyAny>>,
    ) -> PyResult<Image> {
        let shading: Shading = shading
            .parse()
            .map_err(|e: String| refusal(py, format!("shading: {e}")))?;
        let overrides = options.overrides(py)?;
        let mut scene = (*given.inner).clone();
        overrides.apply(&mut scene).or_raise(py)?;
        let backend = self.backend_for(&scene, shading);
        refuse_hook_on_cpu(overrides.lighting.is_some(), backend).or_raise(py)?;
        let budgets = options.budgets();
        budgets
            .check(&scene, Some(shading), backend == Backend::Gpu)
            .or_raise(py)?;
        let (gpu, cpu) = match backend {
            Backend::Gpu => (vec![shading], vec![]),
            Backend::Cpu => (vec![], vec![shading]),
        };
        MemoryLimit::resolve(None)
            .and_then(|limit| limit.check(&given.name, &scene, &gpu, &cpu))
            .or_raise(py)?;
        let counter = WorkCounter::default();
        // The main thread's renders share one flag its SIGINT handler sets
        // (`interrupt.rs`); the others' are their own.
        let sigint = progress.is_none() && may_take_sigint(py)?;
        let cancel = if sigint {
            main_thread_cancel()
        } else {
            Arc::new(AtomicBool::new(false))
        };
        let request = RenderRequest {
            target: color_target(&scene, ImageFormat::Exr),
            count_rays: stats,
            deadline: budgets.deadline(),
            error: budgets.error,
            progress: Some(&counter),
            cancel: Some(cancel.clone()),
            ..RenderRequest::new(shading, backend)
        };
        let plan = Plan::new(&scene, &request).or_raise(py)?;
        if !plan.warnings.is_empty() {
            let warnings = py.import("warnings")?;
            for warning in &plan.warnings {
                warnings.call_method1("warn", (format!("shadelab: {warning}"),))?;
            }
        }
        let render = || {
            let _turn = (backend == Backend::Gpu)
                .then(|| self.gpu_turn.lock().unwrap_or_else(|e| e.into_inner()));
            plan.render(&self.device, &scene)
        };
        let rendered: Rendered = match (progress, sigint) {
            // On this thread: Ctrl-C heard by our own handler on the main
            // thread; on another, no signal comes.
            (None, true) => run_with_sigint(py, render)?.or_raise(py)?,
            (None, false) => released(py, "a render", render)?.or_raise(py)?,
            // On a thread of its own, this one reporting progress (and
            // running Python's signal handlers) meanwhile.
            (Some(given), _) => {
                let mut progress = Progress::new(Some(given))?;
                let unit = plan.technique.work_unit();
                run_released(py, &cancel, &counter, unit, &mut progress, render)?
            }
        };
        let (device, driver) = self.names(backend);
        let settings = effective_settings(
            given.origin.as_deref(),
            shading,
            &scene,
            backend,
            &rendered,
            &device,
            driver.as_deref(),
        );
        Image::new(py, rendered, settings, given.name.clone(), device)
    }
}
