//! A render that sums into a film, a batch per submission: the forward
//! tracer's photons, or the ray tracer's samples of every pixel with
//! diffuse bounces. The shaders add to fixed-point sums (`film_sums`), so
//! the film is the same bits however the work is split, between batches
//! here or between machines (`render --shard`). Batches let a long render
//! show its progress, stop at a time or error budget, and be refused
//! after its first batch where it would take hours; this one loop does
//! that for both tracers.

use std::sync::Arc;

use crate::error_budget::ErrorBudget;
use crate::film_sums::{FilmSums, RenderPart};
use crate::gpu::raytrace::buffers::TraceBuffers;
use crate::gpu::vk::context::GpuContext;
use crate::gpu::vk::error::GpuError;
use crate::gpu::vk::timestamps::Timestamps;
use crate::work_counter::WorkCounter;

/// Path vertices (a sample's eye ray and its bounces) per submission of
/// the ray tracer: about a quarter of a second of lavapipe's time on the
/// diffuse box, so that progress moves. The sums do not depend on it.
const BATCH_VERTICES: u64 = 1 << 24;

/// What the batches did: the photons or samples per pixel traced (fewer
/// than asked where a budget stopped them), the summed submit and GPU
/// milliseconds, and under an error budget the last estimate of the RMSE.
pub(super) struct BatchesRun {
    pub traced: u32,
    pub submit_ms: f64,
    pub gpu_ms: f64,
    pub estimate: Option<f64>,
}

/// A render's film and how it is cut: the buffers whose output is the
/// film of a `width x height` image, what a unit of work is called, and
/// how many units a batch takes without a budget.
pub(super) struct FilmWork<'a> {
    pub buffers: &'a TraceBuffers,
    pub size: (u32, u32),
    pub unit: &'static str,
    pub batch: u32,
}

/// Samples per pixel in one batch of an image of `pixels` pixels whose
/// paths take up to `bounces` diffuse bounces: at least 1.
pub(super) fn batch_samples(pixels: u64, bounces: u32) -> u32 {
    let per_sample = pixels.max(1) * (1 + u64::from(bounces));
    u32::try_from((BATCH_VERTICES / per_sample).max(1)).unwrap_or(u32::MAX)
}

/// Units per batch for `part`, from `batch` without a budget: a quarter
/// under a time budget (it overshoots less), a sixteenth and no more than
/// a 64th of the part's total under an error budget (the estimate needs a
/// few batches, and stops at a finer count).
fn batch_size(part: &RenderPart, batch: u32) -> u32 {
    let size = if part.error.is_some() {
        batch.div_ceil(16).min(part.total.div_ceil(64))
    } else if part.deadline.is_some() {
        batch.div_ceil(4)
    } else {
        batch
    };
    size.max(1)
}

/// Runs `part` a batch at a time, `submit(timestamps, first, end)` tracing
/// units `first..end` in one submission (its submit and GPU milliseconds),
/// counting units into `counter` as batches finish: until the part is
/// done, a time budget is spent or an error budget reached.
pub(super) fn run(
    context: &Arc<GpuContext>,
    work: &FilmWork,
    part: &RenderPart,
    counter: &WorkCounter,
    mut submit: impl FnMut(&Timestamps, u32, u32) -> Result<(f64, f64), GpuError>,
) -> Result<BatchesRun, GpuError> {
    counter.begin(work.unit, u64::from(part.count()));
    let timestamps = Timestamps::new(context)?;
    let (width, height) = work.size;
    let size = batch_size(part, work.batch);
    let sums = 3 * width as usize * height as usize;
    let mut budget = part
        .error
        .map(|target| ErrorBudget::new(target, part.total, sums));
    let mut run = BatchesRun {
        traced: 0,
        submit_ms: 0.0,
        gpu_ms: 0.0,
        estimate: None,
    };
    let mut first = part.range.start;
    while first < part.range.end && !part.past_deadline() {
        let end = first.saturating_add(size).min(part.range.end);
        let count = end - first;
        let (submit_ms, gpu_ms) = submit(&timestamps, first, end)?;
        if first == part.range.start {
            part.refuse_if_too_long(count, submit_ms / 1e3, work.unit)
                .map_err(GpuError::TooLong)?;
        }
        run.submit_ms += submit_ms;
        run.gpu_ms += gpu_ms;
        run.traced += count;
        counter.add(u64::from(count));
        first = end;
        if let Some(budget) = &mut budget {
            let film = FilmSums::from_ne_bytes(width, height, work.buffers.output());
            let reached = budget.after_batch(&film.sums, count);
            run.estimate = budget.estimate;
            if reached {
                break;
            }
        }
    }
    Ok(run)
}

#[cfg(test)]
mod tests {
    use super::batch_samples;

    /// A small image takes its samples in one batch, a big one one
    /// sample at a time, and bounces shrink the batch.
    #[test]
    fn batches_hold_about_the_same_work() {
        assert_eq!(batch_samples(160 * 120, 2), 291);
        assert_eq!(batch_samples(640 * 480, 2), 18);
        assert_eq!(batch_samples(8192 * 8192, 64), 1);
        assert_eq!(batch_samples(0, 0), 1 << 24);
    }
}
