//! The ray tracer with diffuse bounces, a range of each pixel's samples per
//! submission: the shader adds each sample's value, over the samples a
//! pixel has, to the pixel's fixed-point sums (`film_sums`), so the sums
//! are the same bits however the samples are split, between batches here
//! or between machines (`render --shard`). Batches let a long render show
//! its progress, stop at a time budget, and be refused after its first
//! batch where it would take hours.

use std::sync::Arc;

use crate::error_budget::ErrorBudget;
use crate::film_sums::{FilmSums, RenderPart};
use crate::gpu::raytrace::buffers::TraceBuffers;
use crate::gpu::raytrace::dispatch::{submit_batch, BoundTrace};
use crate::gpu::raytrace::layout::SampleRange;
use crate::gpu::vk::context::GpuContext;
use crate::gpu::vk::error::GpuError;
use crate::gpu::vk::timestamps::Timestamps;
use crate::work_counter::WorkCounter;

/// Path vertices (a sample's eye ray and its bounces) per submission:
/// about a quarter of a second of lavapipe's time on the diffuse box,
/// so that progress moves. The sums do not depend on it.
const BATCH_VERTICES: u64 = 1 << 24;

/// What the batches did: the samples per pixel traced (fewer than asked
/// where a budget stopped them), the summed submit and GPU milliseconds,
/// and under an error budget the last estimate of the RMSE.
pub(super) struct BatchesRun {
    pub traced: u32,
    pub submit_ms: f64,
    pub gpu_ms: f64,
    pub estimate: Option<f64>,
}

/// A trace with bounces, ready to run: its pipeline and buffers bound, the
/// image's size, the bounces its paths take and the workgroups of a
/// dispatch.
pub(super) struct SampleWork<'a> {
    pub bound: &'a BoundTrace<'a>,
    pub buffers: &'a TraceBuffers,
    pub size: (u32, u32),
    pub bounces: u32,
    pub groups: (u32, u32),
}

/// Samples per batch for `part`: about the same work each, smaller under
/// a time budget (a quarter: it overshoots less) or an error budget (a
/// sixteenth, and no more than a 64th of the samples asked for: the
/// estimate needs a few batches, and stops at a finer count).
fn batch_size(part: &RenderPart, pixels: u64, bounces: u32) -> u32 {
    let size = batch_samples(pixels, bounces);
    if part.error.is_some() {
        size.div_ceil(16).min(part.total.div_ceil(64))
    } else if part.deadline.is_some() {
        size.div_ceil(4)
    } else {
        size
    }
}

/// Samples per pixel in one batch of an image of `pixels` pixels whose
/// paths take up to `bounces` diffuse bounces: at least 1.
fn batch_samples(pixels: u64, bounces: u32) -> u32 {
    let per_sample = pixels.max(1) * (1 + u64::from(bounces));
    u32::try_from((BATCH_VERTICES / per_sample).max(1)).unwrap_or(u32::MAX)
}

/// Traces `part`'s samples of every pixel, a batch per submission,
/// counting samples into `counter` as batches finish; under a time
/// budget, the batches that start before it; under an error budget, until
/// the estimate is within it.
pub(super) fn run(
    context: &Arc<GpuContext>,
    work: &SampleWork,
    part: &RenderPart,
    counter: &WorkCounter,
) -> Result<BatchesRun, GpuError> {
    counter.begin("samples per pixel", u64::from(part.count()));
    let timestamps = Timestamps::new(context)?;
    let (width, height) = work.size;
    let pixels = u64::from(width) * u64::from(height);
    let size = batch_size(part, pixels, work.bounces);
    let sums = 3 * pixels as usize;
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
        let range = SampleRange {
            first,
            end,
            unused: [0; 2],
        };
        let push = bytemuck::bytes_of(&range);
        let batch = (0, work.groups);
        let (submit, gpu) = submit_batch(context, work.bound, Some(&timestamps), push, batch)?;
        if first == part.range.start {
            part.refuse_if_too_long(end - first, submit / 1e3, "samples per pixel")
                .map_err(GpuError::TooLong)?;
        }
        run.submit_ms += submit;
        run.gpu_ms += gpu;
        run.traced += end - first;
        let count = end - first;
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
