//! The ray tracer with diffuse bounces, a range of each pixel's samples per
//! submission: the shader adds each sample's value, over the samples a
//! pixel has, to the pixel's fixed-point sums (`film_sums`), so the sums
//! are the same bits however the samples are split, between batches here
//! or between machines (`render --shard`). Batches let a long render show
//! its progress, stop at a time budget, and be refused after its first
//! batch where it would take hours.

use std::sync::Arc;

use crate::film_sums::RenderPart;
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
/// where a time budget stopped them), and the summed submit and GPU
/// milliseconds.
pub(super) struct BatchesRun {
    pub traced: u32,
    pub submit_ms: f64,
    pub gpu_ms: f64,
}

/// Samples per pixel in one batch of an image of `pixels` pixels whose
/// paths take up to `bounces` diffuse bounces: at least 1.
fn batch_samples(pixels: u64, bounces: u32) -> u32 {
    let per_sample = pixels.max(1) * (1 + u64::from(bounces));
    u32::try_from((BATCH_VERTICES / per_sample).max(1)).unwrap_or(u32::MAX)
}

/// Traces `part`'s samples of every pixel of a `width x height` image, a
/// batch per submission of `groups` workgroups, counting samples into
/// `counter` as batches finish; under a time budget, the batches that
/// start before it.
pub(super) fn run(
    context: &Arc<GpuContext>,
    bound: &BoundTrace,
    part: &RenderPart,
    (pixels, bounces): (u64, u32),
    groups: (u32, u32),
    counter: &WorkCounter,
) -> Result<BatchesRun, GpuError> {
    counter.begin("samples per pixel", u64::from(part.count()));
    let timestamps = Timestamps::new(context)?;
    let mut size = batch_samples(pixels, bounces);
    if part.deadline.is_some() {
        // Smaller batches overshoot a budget less.
        size = size.div_ceil(4);
    }
    let mut run = BatchesRun {
        traced: 0,
        submit_ms: 0.0,
        gpu_ms: 0.0,
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
        let (submit, gpu) = submit_batch(context, bound, Some(&timestamps), push, (0, groups))?;
        if first == part.range.start {
            part.refuse_if_too_long(end - first, submit / 1e3, "samples per pixel")
                .map_err(GpuError::TooLong)?;
        }
        run.submit_ms += submit;
        run.gpu_ms += gpu;
        run.traced += end - first;
        counter.add(u64::from(end - first));
        first = end;
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
