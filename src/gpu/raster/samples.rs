//! How the GPU takes a raster render's samples (docs/lighting-model.md,
//! "Samples per pixel"): one at the pixel's centre; the device's
//! multisampling, shaded once per pixel; or, shaded at every sample, a pass
//! per sample.
//!
//! Per-sample shading is not the pipeline's sample-rate shading: lavapipe's
//! differs from the contract where a pixel's samples fall on different
//! triangles (up to 0.12 on `assets/vertex-colors.toml`, Mesa 25.0.7).
//! A pass per sample draws the scene shifted (the viewport's origin) so
//! that sample k of every pixel lies at that pixel's centre: the rasteriser
//! then covers,
//! depth-tests and shades exactly at sample k, with the same fill rule,
//! into an image of its own, and the host averages the N images. It needs
//! no multisampling at all, so it takes every standard count, where the
//! device places a viewport to a sixteenth of a pixel.

use crate::gpu::raster::target::ColorTarget;
use crate::gpu::vk::context::DeviceInfo;
use crate::gpu::vk::error::GpuError;
use crate::linear_image::LinearImage;
use crate::msaa::{self, Msaa};

/// How the samples of a pixel are drawn.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum SampleDrawing {
    /// One sample, at the pixel's centre.
    Single,
    /// The device's multisampling at N samples: coverage and depth per
    /// sample, the surface shaded once per pixel at its centre, the
    /// samples averaged at the end of rendering.
    Multisampled(u32),
    /// N passes of one sample each (per-sample shading), averaged on the
    /// host.
    Passes(u32),
}

impl SampleDrawing {
    pub(crate) fn of(msaa: Msaa) -> Self {
        match (msaa.samples, msaa.per_sample) {
            (1, _) => SampleDrawing::Single,
            (n, false) => SampleDrawing::Multisampled(n),
            (n, true) => SampleDrawing::Passes(n),
        }
    }

    /// The samples per pixel the rasteriser takes in one pass.
    pub(crate) fn rasterization_samples(self) -> u32 {
        match self {
            SampleDrawing::Multisampled(n) => n,
            SampleDrawing::Single | SampleDrawing::Passes(_) => 1,
        }
    }

    /// How many times the scene is drawn.
    pub(crate) fn passes(self) -> u32 {
        match self {
            SampleDrawing::Passes(n) => n,
            SampleDrawing::Single | SampleDrawing::Multisampled(_) => 1,
        }
    }

    /// The target drawn into for an image wanted in `wanted`. Samples are
    /// averaged as linear values: an 8-bit sRGB target is not averaged in
    /// linear light on lavapipe (5 to 8 steps off at edges, measured), so a
    /// multisampled PNG is drawn in scaled 16-bit unsigned values, and so
    /// are the passes.
    pub(crate) fn target(self, wanted: ColorTarget) -> ColorTarget {
        match (self, wanted) {
            (SampleDrawing::Single, wanted) => wanted,
            (_, ColorTarget::Srgb8) => ColorTarget::ScaledUnorm16,
            (_, wanted) => wanted,
        }
    }
}

/// Refuses a sample count the device does not render, naming what it
/// offers. A pass per sample takes every standard count on every device
/// that places a viewport finely enough.
pub(crate) fn check_samples(info: &DeviceInfo, msaa: Msaa) -> Result<(), GpuError> {
    let refuse = |why: String| {
        Err(GpuError::UnsupportedSamples {
            asked: msaa.to_string(),
            device: info.name.clone(),
            why,
        })
    };
    match SampleDrawing::of(msaa) {
        SampleDrawing::Passes(n) if msaa::positions(n).is_some() => {
            let needed = subpixel_bits_needed(n);
            if info.viewport_subpixel_bits >= needed {
                return Ok(());
            }
            refuse(format!(
                "places a viewport to 1/{} of a pixel, and shading per sample at {n} samples moves it by 1/{} (--msaa {n} shades per pixel; --backend cpu renders per sample)",
                1u64 << info.viewport_subpixel_bits.min(16),
                1u64 << needed
            ))
        }
        SampleDrawing::Single | SampleDrawing::Multisampled(_)
            if info.msaa_counts.contains(&msaa.samples) =>
        {
            Ok(())
        }
        _ => {
            let mut listed: Vec<String> = info.msaa_counts.iter().map(u32::to_string).collect();
            let last = listed.pop().unwrap_or_default();
            let listed = if listed.is_empty() {
                last
            } else {
                format!("{} or {last}", listed.join(", "))
            };
            refuse(format!("renders {listed} samples per pixel, and 1, 2, 4, 8 or 16 shaded per sample (`shadelab info` lists them; the CPU reference, --backend cpu, 1, 2, 4, 8 or 16)"))
        }
    }
}

/// The viewport's origin for pass `pass` of `drawing`, in pixels: shifted
/// so that the pass's sample lies at every pixel's centre (y down). The
/// viewport transform follows clipping, so the shift is exact where the
/// device keeps `subpixel_bits_needed` bits of it, where a shift of the
/// clip-space matrix is not: at a 179 degree field of view, vertices far
/// outside the image moved by rounding enough to flip samples on a silhouette.
pub(crate) fn pass_viewport_origin(drawing: SampleDrawing, pass: u32) -> (f32, f32) {
    let SampleDrawing::Passes(n) = drawing else {
        return (0.0, 0.0);
    };
    let (x, y) = msaa::positions(n).expect("check_samples passed the count")[pass as usize];
    ((0.5 - x) as f32, (0.5 - y) as f32)
}

/// The bits of a pixel's fraction the shifts of `samples` need: every
/// standard position is a multiple of 2^-bits.
pub(crate) fn subpixel_bits_needed(samples: u32) -> u32 {
    let positions = msaa::positions(samples).unwrap_or_default();
    (0..=8)
        .find(|&bits| {
            let scale = f64::from(1u32 << bits);
            positions
                .iter()
                .all(|&(x, y)| (x * scale).fract() == 0.0 && (y * scale).fract() == 0.0)
        })
        .unwrap_or(8)
}

/// The average of the passes' images, sample by sample: the resolve.
pub(crate) fn averaged(passes: &[LinearImage]) -> LinearImage {
    use rayon::prelude::*;
    let first = &passes[0];
    let weight = 1.0 / passes.len() as f32;
    let pixels = (0..first.pixels.len())
        .into_par_iter()
        .map(|i| {
            let mut sum = [0.0f32; 3];
            for pass in passes {
                for (s, v) in sum.iter_mut().zip(pass.pixels[i]) {
                    *s += v;
                }
            }
            sum.map(|s| s * weight)
        })
        .collect();
    LinearImage {
        width: first.width,
        height: first.height,
        pixels,
    }
}

impl ColorTarget {
    /// The target drawn into when `self` is asked for at `msaa`: several
    /// samples are averaged as linear values.
    pub fn drawn_with(self, msaa: crate::msaa::Msaa) -> Self {
        SampleDrawing::of(msaa).target(self)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A point at sample k's position of a pixel lands on that pixel's
    /// centre in pass k: the shift the passes rest on.
    #[test]
    fn each_pass_puts_its_sample_at_the_pixel_centres() {
        for n in [2, 4, 8, 16] {
            for (k, &(sx, sy)) in msaa::positions(n).unwrap().iter().enumerate() {
                let (ox, oy) = pass_viewport_origin(SampleDrawing::Passes(n), k as u32);
                let (px, py) = (10.0, 7.0);
                assert_eq!(px + sx + f64::from(ox), px + 0.5, "{n} {k}");
                assert_eq!(py + sy + f64::from(oy), py + 0.5, "{n} {k}");
            }
        }
        assert_eq!(
            pass_viewport_origin(SampleDrawing::Multisampled(4), 0),
            (0.0, 0.0)
        );
    }

    #[test]
    fn the_shifts_need_sixteenths_at_8_and_16_samples() {
        let needed: Vec<u32> = [1, 2, 4, 8, 16].map(subpixel_bits_needed).to_vec();
        assert_eq!(needed, [1, 2, 3, 4, 4]);
    }

    #[test]
    fn the_resolve_is_the_mean_of_the_passes() {
        let pass = |v: f32| LinearImage::new(2, 1, [v, 2.0 * v, 0.0]);
        let mean = averaged(&[pass(1.0), pass(0.0), pass(0.5), pass(0.5)]);
        assert_eq!(mean.pixels, vec![[0.5, 1.0, 0.0]; 2]);
    }

    /// A device takes the counts it multisamples, and per sample those
    /// whose shifts its viewport keeps: 2 bits hold 2 samples' quarters,
    /// not 8 samples' sixteenths.
    #[test]
    fn a_device_takes_what_it_multisamples_and_what_its_viewport_can_shift() {
        let device = DeviceInfo {
            index: 0,
            name: "test device".into(),
            driver: String::new(),
            device_type: String::new(),
            api_version: String::new(),
            is_lavapipe: false,
            shader_float16: false,
            msaa_counts: vec![1, 4],
            viewport_subpixel_bits: 2,
            unusable_because: None,
            no_ray_tracer_because: None,
            no_ray_query_because: None,
            no_forward_because: None,
        };
        let check = |text: &str| check_samples(&device, text.parse().unwrap());
        for fine in ["1", "4", "2,per-sample"] {
            assert!(check(fine).is_ok(), "{fine}");
        }
        let coarse = check("8,per-sample").unwrap_err().to_string();
        assert!(
            coarse.contains("1/4 of a pixel") && coarse.contains("1/16"),
            "{coarse}"
        );
        let absent = check("8").unwrap_err().to_string();
        assert!(
            absent.contains("renders 1 or 4 samples per pixel"),
            "{absent}"
        );
        assert!(check("3,per-sample").is_err());
    }

    #[test]
    fn every_standard_count_is_drawn_per_sample_on_any_device() {
        assert_eq!(
            SampleDrawing::of(Msaa {
                samples: 1,
                per_sample: true
            }),
            SampleDrawing::Single
        );
        assert_eq!(
            SampleDrawing::of(Msaa {
                samples: 8,
                per_sample: true
            })
            .passes(),
            8
        );
        assert_eq!(
            SampleDrawing::of(Msaa {
                samples: 4,
                per_sample: false
            })
            .rasterization_samples(),
            4
        );
    }
}
