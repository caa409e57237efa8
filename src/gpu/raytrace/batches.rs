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
use crate::gpu::vk::watchdog::{self, watch, Guard, Watch};
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
/// film of a `width x height` image, what a unit of work is called, how
/// many units a batch takes without a budget, and how the units fall into
/// an error budget's two independent halves.
pub(super) struct FilmWork<'a> {
    pub buffers: &'a TraceBuffers,
    pub size: (u32, u32),
    pub unit: &'static str,
    pub batch: u32,
    pub halves: Halves,
}

/// Which units of a render are independent of which: what `--error`'s
/// estimate needs of its two halves.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(super) enum Halves {
    /// Every unit of its own (the forward tracer's photons, each drawn
    /// from its own hash): a batch goes to either half whole.
    ByBatch,
    /// Two interleaved streams, the even units and the odd ones (the ray
    /// tracer's samples of a pixel, `cpu::raytrace::pixel_sample`): units
    /// of one stream are stratified together, so each half is a stream,
    /// and a batch under an error budget is traced a stream at a time.
    ByStream,
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

/// Traces units `first, first + step, ...` below `end` in one submission:
/// its submit and GPU milliseconds.
pub(super) type Submit<'s> =
    dyn FnMut(&Timestamps, u32, u32, u32) -> Result<(f64, f64), GpuError> + 's;

/// Runs `part` a batch at a time through `submit`, counting units into
/// `counter` as batches finish: until the part is done, a time budget is
/// spent or an error budget reached. The first batch always runs, however
/// short the time budget: an image of no work would be black, not an
/// estimate.
pub(super) fn run(
    context: &Arc<GpuContext>,
    work: &FilmWork,
    part: &RenderPart,
    counter: &WorkCounter,
    submit: &mut Submit,
) -> Result<BatchesRun, GpuError> {
    counter.begin(work.unit, u64::from(part.count()));
    let timestamps = Timestamps::new(context)?;
    let size = batch_size(part, work.batch);
    let (width, height) = work.size;
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
    // Tightened after the first batch, which says how long one takes.
    let mut _tightened: Option<Guard> = None;
    // With a cancel flag, batches of about `CANCELLABLE_BATCH_S` each,
    // from what the last one took: a cancel waits for the batch running.
    let mut next = size;
    while first < part.range.end && part.may_start(first == part.range.start) {
        // Under a time budget or a cancel flag the first batch is one unit
        // of work for the samples (a sample per pixel), so that a budget
        // shorter than a batch overshoots it least and a cancel is heard
        // soon.
        let size =
            if first == part.range.start && (part.deadline.is_some() || part.cancel.is_some()) {
                first_batch_under_deadline(work, size)
            } else {
                next
            };
        let end = first.saturating_add(size).min(part.range.end);
        let count = end - first;
        let times = match (&mut budget, work.halves) {
            (Some(budget), Halves::ByStream) => {
                by_stream(&timestamps, work, budget, (first, end), submit)?
            }
            _ => submit(&timestamps, first, end, 1)?,
        };
        if first == part.range.start {
            part.refuse_if_too_long(count, times.0 / 1e3, work.unit)
                .map_err(GpuError::TooLong)?;
            _tightened = Some(tighten_watch(times.0, count, size));
        }
        if part.cancel.is_some() {
            next = cancellable_batch(count, times.0, size);
        }
        run.submit_ms += times.0;
        run.gpu_ms += times.1;
        run.traced += count;
        counter.add(u64::from(count));
        first = end;
        if let Some(budget) = &mut budget {
            if work.halves == Halves::ByBatch {
                budget.add_to_smaller(&film_now(work).sums, count);
            }
            run.estimate = budget.estimate;
            if budget.reached() {
                break;
            }
        }
    }
    Ok(run)
}

/// Holds the render's later submissions to what its first batch of
/// `count` units took (`submit_ms`), scaled to a batch of `size`: a hook
/// that hangs only in a later batch is found in seconds, not minutes
/// (`vk::watchdog::tightened`).
fn tighten_watch(submit_ms: f64, count: u32, size: u32) -> Guard {
    let per_unit = submit_ms.max(0.0) / 1e3 / f64::from(count.max(1));
    let expected = std::time::Duration::from_secs_f64(per_unit * f64::from(size));
    let now = watchdog::current();
    watch(Watch {
        limit: watchdog::tightened(now.limit, expected),
        cause: now.cause,
    })
}

/// How long a batch of a render that may be cancelled runs, about: what a
/// cancel waits for at most (the Python package's Ctrl-C, within half a
/// second).
const CANCELLABLE_BATCH_S: f64 = 0.2;

/// The next batch of a render that may be cancelled: as many units as
/// ran in `CANCELLABLE_BATCH_S` at the last batch's rate (`count` units
/// in `submit_ms`), at least 1, at most the usual `size`. The film's sums
/// do not depend on how the units are batched.
fn cancellable_batch(count: u32, submit_ms: f64, size: u32) -> u32 {
    let per_unit_s = submit_ms.max(1e-3) / 1e3 / f64::from(count.max(1));
    ((CANCELLABLE_BATCH_S / per_unit_s) as u32).clamp(1, size)
}

/// The size of a time budget's first batch.
fn first_batch_under_deadline(work: &FilmWork, size: u32) -> u32 {
    match work.halves {
        Halves::ByStream => 1,
        Halves::ByBatch => size,
    }
}

/// Batch `first..end` a stream at a time, each stream's part of the film
/// dealt to its half of `budget`: the summed times.
fn by_stream(
    timestamps: &Timestamps,
    work: &FilmWork,
    budget: &mut ErrorBudget,
    (first, end): (u32, u32),
    submit: &mut Submit,
) -> Result<(f64, f64), GpuError> {
    let mut times = (0.0, 0.0);
    for stream in 0..2u32 {
        let start = first + ((first ^ stream) & 1);
        if start >= end {
            continue;
        }
        let (submit_ms, gpu_ms) = submit(timestamps, start, end, 2)?;
        times = (times.0 + submit_ms, times.1 + gpu_ms);
        budget.add(
            stream as usize,
            &film_now(work).sums,
            (end - start).div_ceil(2),
        );
    }
    Ok(times)
}

/// The film as the GPU has summed it so far.
fn film_now(work: &FilmWork) -> FilmSums {
    let (width, height) = work.size;
    FilmSums::from_ne_bytes(width, height, work.buffers.output())
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
