//! What a raster render draws into and returns: the colour target's
//! format (and what each is for), the depth format, and the output.

use ash::vk;

use crate::gpu::vk::timestamps::GpuTimings;
use crate::linear_image::LinearImage;

pub const DEPTH_FORMAT: vk::Format = vk::Format::D32_SFLOAT;

/// The largest value `ColorTarget::ScaledUnorm16` holds.
pub const SCALED_UNORM16_RANGE: f32 = 16.0;

/// The colour target a raster render writes.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum ColorTarget {
    /// 32-bit float RGBA, linear and unclamped: EXR output, `check`,
    /// `diff`, `compare`.
    #[default]
    Float32,
    /// 8-bit sRGB RGBA: the hardware encodes `clamp(I, 0, 1)` as a PNG
    /// holds it. A quarter of the bytes to write and read back; the same
    /// PNG as the float target within 1 in 255 (tests/gpu/raster_modes.rs).
    Srgb8,
    /// 16-bit unsigned-normalised RGBA holding linear values / 16: a
    /// multisampled render for a PNG. Its samples are averaged as linear
    /// values, which an 8-bit sRGB target does not do on lavapipe (5 to 8
    /// steps off at edges, measured); 16-bit floats would, drawn 1.2x
    /// slower there (the 40k sphere at 4 samples, 43 against 35 ms). No
    /// sample is below 0 (`AT_LEAST_ZERO`, raster_output.glsl). The
    /// fragment stages write colour / 16 (`OUTPUT_SCALE`), so every
    /// sample up to 16 keeps its value, and one at 16 or more already
    /// makes the average of up to 16 samples 1 or more, white in a PNG as
    /// it should be; steps of 16/65535 keep the PNG within 1 in 255 of the
    /// 32-bit path's (tests/gpu/msaa.rs).
    ScaledUnorm16,
}

impl ColorTarget {
    /// The target whose image `format` stores without loss: 8-bit for PNG.
    pub fn for_output(format: crate::output::ImageFormat) -> Self {
        match format {
            crate::output::ImageFormat::Png => ColorTarget::Srgb8,
            crate::output::ImageFormat::Exr => ColorTarget::Float32,
        }
    }

    /// What the fragment stages multiply their colour by for it
    /// (`OUTPUT_SCALE`), undone on the host.
    pub fn output_scale(self) -> f32 {
        match self {
            ColorTarget::ScaledUnorm16 => 1.0 / SCALED_UNORM16_RANGE,
            _ => 1.0,
        }
    }

    pub fn format(self) -> vk::Format {
        match self {
            ColorTarget::Float32 => vk::Format::R32G32B32A32_SFLOAT,
            ColorTarget::Srgb8 => vk::Format::R8G8B8A8_SRGB,
            ColorTarget::ScaledUnorm16 => vk::Format::R16G16B16A16_UNORM,
        }
    }

    pub(crate) fn bytes_per_pixel(self) -> u64 {
        match self {
            ColorTarget::Float32 => 16,
            ColorTarget::Srgb8 => 4,
            ColorTarget::ScaledUnorm16 => 8,
        }
    }

    /// How reports name it.
    pub fn name(self) -> &'static str {
        match self {
            ColorTarget::Float32 => "rgba32f",
            ColorTarget::Srgb8 => "rgba8-srgb",
            ColorTarget::ScaledUnorm16 => "rgba16-unorm/16",
        }
    }
}

pub struct RasterOutput {
    pub image: LinearImage,
    pub timings: GpuTimings,
}
