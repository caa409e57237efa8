//! `bench --time-to-image`: what a user waits for, the whole `render`
//! command, timed from outside as fresh processes of this same binary.
//!
//! Cold: a new, empty cache folder per run (`SHADELAB_CACHE_DIR`, which also
//! holds Mesa's shader cache), as on a fresh CI runner. Warm: one folder that
//! a first, untimed run has filled. The CPU twin's command (`--backend cpu`)
//! has no cache to fill. Medians over the runs.

use std::ffi::OsString;
use std::path::Path;
use std::process::{Command, Stdio};
use std::time::Instant;

use shadelab::compare::run::median_and_spread;
use shadelab::shading::Shading;

use crate::cli::common::failure::Failure;

/// The whole command's wall clock, in milliseconds, medians.
#[derive(Debug, Clone, Copy, serde::Serialize)]
pub struct TimeToImage {
    /// GPU, empty caches.
    pub cold_ms: f64,
    /// GPU, the caches filled by an earlier run.
    pub warm_ms: f64,
    /// The CPU twin's command (`--backend cpu`).
    pub cpu_ms: f64,
}

/// Times `render ARGS --shading SHADING` (`args` the scene and its
/// overrides; `gpu_args` more for the GPU alone, as a lighting hook, which
/// the CPU twin refuses) `runs` times each way.
pub fn measure(
    args: &[OsString],
    gpu_args: &[OsString],
    shading: Shading,
    runs: usize,
) -> Result<TimeToImage, Failure> {
    let work = tempfile::tempdir()
        .map_err(|e| Failure::usage(format!("cannot make a scratch folder: {e}")))?;
    let out = work.path().join("image.png");
    let render = |backend: &str, cache: &Path| -> Result<f64, Failure> {
        let exe = std::env::current_exe()
            .map_err(|e| Failure::usage(format!("cannot find this program's path: {e}")))?;
        let mut command = Command::new(exe);
        command
            .arg("render")
            .args(args)
            .args(if backend == "gpu" { gpu_args } else { &[] })
            .args(["--shading", &shading.to_string(), "--backend", backend])
            .arg("--out")
            .arg(&out)
            .env("SHADELAB_CACHE_DIR", cache)
            .env_remove("MESA_SHADER_CACHE_DIR")
            .env_remove("MESA_SHADER_CACHE_DISABLE")
            .stdout(Stdio::null())
            .stderr(Stdio::piped());
        let started = Instant::now();
        let finished = command
            .output()
            .map_err(|e| Failure::usage(format!("cannot run `shadelab render`: {e}")))?;
        let ms = started.elapsed().as_secs_f64() * 1e3;
        if !finished.status.success() {
            return Err(Failure {
                code: finished.status.code().map_or(3, |c| c.clamp(1, 255) as u8),
                message: format!(
                    "the timed render failed: {}",
                    String::from_utf8_lossy(&finished.stderr).trim()
                ),
            });
        }
        Ok(ms)
    };
    let fresh = |i: usize| work.path().join(format!("cold-{i}"));
    let warm_cache = work.path().join("warm");
    render("gpu", &warm_cache)?; // fills the warm caches
    let mut cold = Vec::new();
    let mut warm = Vec::new();
    let mut cpu = Vec::new();
    // Interleaved, so that drift on a shared machine touches all three.
    for i in 0..runs {
        cold.push(render("gpu", &fresh(i))?);
        warm.push(render("gpu", &warm_cache)?);
        cpu.push(render("cpu", &warm_cache)?);
    }
    Ok(TimeToImage {
        cold_ms: median_and_spread(cold).0,
        warm_ms: median_and_spread(warm).0,
        cpu_ms: median_and_spread(cpu).0,
    })
}
