//! The images a device renders: its side limit, and shadelab's cap on the
//! pixel count, both renderers alike.

use crate::gpu::vk::context::GpuContext;
use crate::gpu::vk::error::GpuError;

/// A cap on pixels per image (8192 x 8192): the float target and its
/// read-back copy take 16 bytes per pixel each.
pub const MAX_PIXELS: u64 = 8192 * 8192;

/// Refuses an image the device cannot hold or that exceeds `MAX_PIXELS`.
pub(crate) fn check_image_size(
    context: &GpuContext,
    width: u32,
    height: u32,
) -> Result<(), GpuError> {
    image_size_error(context.max_image_dimension(), width, height).map_or(Ok(()), Err)
}

/// Why a `width` x `height` image cannot be rendered on a device whose
/// images hold `side_limit` pixels per side at most, naming the limit it
/// passes: the device's side, or shadelab's cap on the pixel count.
fn image_size_error(side_limit: u32, width: u32, height: u32) -> Option<GpuError> {
    if width == 0 || height == 0 || width > side_limit || height > side_limit {
        return Some(GpuError::ImageTooLarge {
            width,
            height,
            why: format!("this device's limit of {side_limit} pixels per side"),
        });
    }
    let pixels = u64::from(width) * u64::from(height);
    (pixels > MAX_PIXELS).then(|| GpuError::ImageTooLarge {
        width,
        height,
        why: format!("the limit of {MAX_PIXELS} pixels (8192 x 8192) in all ({pixels} asked)"),
    })
}

#[cfg(test)]
mod size_tests {
    use super::*;

    /// The message names the limit that was passed (issue 30: 16384x4200
    /// was refused as over "8192 pixels per side" while 16384x2 renders).
    #[test]
    fn the_refusal_names_the_limit_passed() {
        let long = image_size_error(16384, 16384, 4200).unwrap().to_string();
        assert!(
            long.contains("67108864 pixels (8192 x 8192) in all"),
            "{long}"
        );
        assert!(!long.contains("per side"), "{long}");
        assert!(image_size_error(16384, 16384, 2).is_none());
        let wide = image_size_error(16384, 20000, 2).unwrap().to_string();
        assert!(wide.contains("16384 pixels per side"), "{wide}");
        assert!(image_size_error(16384, 8192, 8192).is_none());
    }
}
