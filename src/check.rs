//! `check`: a scene rendered on the GPU and with the CPU reference, the
//! difference measured, and a verdict against thresholds set from
//! measurement.
//!
//! Pixels are split by what the CPU reference knows of them: an edge pixel's
//! sample lies within `cpu::raster::EDGE_MARGIN` (1/64 px) of the boundary
//! of a visible triangle, where a conforming rasterizer working from f32
//! positions may cover it differently; every other pixel is interior and
//! must agree to float rounding, however small its triangle. Only the share
//! of edge pixels that differ is bounded.
//!
//! The limits are in units of display brightness. An image whose brightest
//! value lies outside `DISPLAY_RANGE` (a light of 1e30 or 1e-30, say) is
//! compared in units of that value instead, so that the same limits become
//! relative ones: against an absolute limit, f32 rounding at 1e30 would fail
//! every pixel and any error at 1e-30 would pass.

use std::borrow::Cow;

use crate::error::Error;
use crate::linear_image::LinearImage;
use crate::metrics::flip::{flip, FlipStats, PIXELS_PER_DEGREE};
use crate::metrics::stats::ErrorStats;
use crate::render::{render, Device, RenderRequest};
use crate::scene::Scene;
use crate::shading::Shading;
use crate::work_counter::WorkCounter;

/// The limits a GPU render must keep against the CPU reference.
///
/// Defaults from measurement (docs/cpu-reference.md and docs/check.md): over the default
/// scene and every scene in `assets/` at their own sizes, in every raster
/// mode, the largest interior error was 8.4e-5 (over 99.6% of the pixels),
/// at most 2 edge pixels of 307200 (0.00065% of the image) differed by more
/// than 0.01, and the largest FLIP mean was 1.0e-5.
#[derive(Debug, Clone, Copy, serde::Serialize)]
pub struct CheckThresholds {
    /// Largest error at an interior pixel. 1e-3: 12x the worst measured, and
    /// still 4x finer than one 8-bit output step.
    pub interior_max_abs: f64,
    /// Largest share of the image made of edge pixels whose error exceeds
    /// `edge_pixel_error`. 0.05%: 77x the worst measured (about 150 pixels
    /// at 640x480).
    pub edge_fraction: f64,
    /// What counts as a differing edge pixel: 0.01 (2.5 8-bit steps).
    pub edge_pixel_error: f64,
    /// Largest mean FLIP over the whole image. 1e-3: 100x the worst measured,
    /// and 20x below the 0.02 of `diff`'s default (a just visible change).
    pub flip_mean: f64,
    /// Forward tracing only: the largest relative difference between the
    /// two images' means (`FORWARD_MEAN_RELATIVE`). `None`: not judged.
    pub mean_relative: Option<f64>,
}

impl Default for CheckThresholds {
    fn default() -> Self {
        Self {
            interior_max_abs: 1e-3,
            edge_fraction: 5e-4,
            edge_pixel_error: 0.01,
            flip_mean: 1e-3,
            mean_relative: None,
        }
    }
}

/// The floor under the edge share and the FLIP mean: on any image,
/// `MIN_EDGE_PIXELS` edge pixels may differ. The limits are shares of the
/// image, and on a tiny one a single pixel on a silhouette that a
/// conforming rasterizer rounds the other way exceeds them (found by the
/// random scenes: one pixel of a 21 x 37 image is 0.13%, over the raster
/// modes' 0.05%). Four is what 0.05% allows at 96 x 72; from about 8000
/// pixels up (raster) or 800 (ray tracing) the shares are the larger.
pub const MIN_EDGE_PIXELS: u32 = 4;

/// Ray tracing's interior limit. Secondary rays carry f32 rounding of their
/// direction over their whole length, and curved mirrors and glass magnify
/// it: over the default scene and every scene in `assets/` the largest
/// interior error is 1.2e-3 (the default scene's glass and metal spheres),
/// and 1.6e-3 in `assets/hard/energy-gain.toml` (mirrors ten bounces deep).
/// 5e-3 is 4.2x and 3.1x those and still about one 8-bit step.
pub const RAYTRACE_INTERIOR_MAX_ABS: f64 = 5e-3;

/// Ray tracing's edge-pixel and FLIP limits. Reflections multiply edges: in
/// `assets/hard/energy-gain.toml` (two facing mirrors and a glass ball at
/// depth 10, weights growing as 1.3^n) box faces and corners seen several
/// bounces deep put up to 0.19% of the image on the other side of an edge,
/// with a FLIP mean of up to 2.0e-3, against at most 0.0007% and 1e-5 on the ordinary
/// scenes. 0.5% and 5e-3 are 2.7x and 2.5x that worst case; the interior
/// limit stays as strict as measured.
pub const RAYTRACE_EDGE_FRACTION: f64 = 5e-3;
pub const RAYTRACE_FLIP_MEAN: f64 = 5e-3;

/// Forward tracing's limits. The GPU and the f64 twin trace the same
/// photons, so their images differ only where f32 rounding sends a photon
/// another way (a splat in the next pixel, a bounce in another direction):
/// a scattering of single pixels, each about one splat, anywhere in the
/// image. Every pixel is judged as an edge pixel (`render::forward_cpu`
/// marks them all); bounded are the share that differs by more than 0.01,
/// FLIP, and the images' means, which a moved photon hardly changes (it
/// moves its splats, not their sum) where a splat factor, a light's share
/// or an event's choice that the two disagree on moves them by percents.
/// Measured over the default scene, `assets/` and the hard cases at their
/// own sizes and 2^22 photons (docs/check.md): on `assets/` at most 0.042%
/// of the pixels, a FLIP mean of 3.7e-4 and means 1e-5 apart; the chaotic
/// hard cases, where f32 rounding sends many photons another way, up to
/// 1.61% (`glass-ior-1e3`), 4.6e-3 (the same) and 1.7e-3 (`energy-gain`,
/// whose surfaces reflect more than they receive). The limits are 1.9x,
/// 2.2x and 2.9x those, FLIP still half of `diff`'s just-visible 0.02.
pub const FORWARD_EDGE_FRACTION: f64 = 3e-2;
pub const FORWARD_FLIP_MEAN: f64 = 1e-2;
pub const FORWARD_MEAN_RELATIVE: f64 = 5e-3;

/// The raster modes' edge-pixel and FLIP limits at more than one sample per
/// pixel. An f32 edge flips the samples within its rounding of the edge:
/// with N samples a pixel has N chances to hold one, and each flip moves
/// the pixel by 1/N of the contrast. Measured at 4 samples over the default
/// scene, `assets/` and the hard cases in the three raster modes: the share
/// of edge pixels off by more than 0.01 rose to 5.6e-4 (energy-gain, from
/// 3.7e-4 at one sample; the ordinary scenes 3.9e-5, from 9.8e-6), while
/// the largest edge error there fell from 0.16 to 0.042 and the largest
/// FLIP mean from 5.6e-4 to 3.0e-4. So the share rises to 1e-3 (1.8x the
/// worst) and the FLIP limit falls to 5e-4 (1.7x the worst); the interior
/// limit stays (6.2e-4 at most, light-on-surface). Per sample, and at 8
/// and 16 samples (lavapipe renders them per sample), the same limits hold
/// but at 16, whose pattern puts samples on the pixel's own boundary: a
/// boundary along a pixel row is a tie there (docs/check.md).
pub const MULTISAMPLED_EDGE_FRACTION: f64 = 1e-3;
pub const MULTISAMPLED_FLIP_MEAN: f64 = 5e-4;

impl CheckThresholds {
    /// The defaults for a mode at the scene's samples per pixel: more than
    /// one changes the raster modes' edge and FLIP limits
    /// (`MULTISAMPLED_EDGE_FRACTION`); the ray tracer takes no MSAA.
    pub fn for_render(shading: Shading, msaa: crate::msaa::Msaa) -> Self {
        let limits = Self::for_shading(shading);
        if msaa.is_multisampled() && shading.raster_mode().is_some() {
            Self {
                edge_fraction: MULTISAMPLED_EDGE_FRACTION,
                flip_mean: MULTISAMPLED_FLIP_MEAN,
                ..limits
            }
        } else {
            limits
        }
    }

    /// The defaults for one mode: the raster modes share `default()`; ray
    /// tracing allows `RAYTRACE_INTERIOR_MAX_ABS` inside surfaces.
    pub fn for_shading(shading: Shading) -> Self {
        match shading {
            Shading::Raytrace => Self {
                interior_max_abs: RAYTRACE_INTERIOR_MAX_ABS,
                edge_fraction: RAYTRACE_EDGE_FRACTION,
                flip_mean: RAYTRACE_FLIP_MEAN,
                ..Self::default()
            },
            Shading::Forward => Self {
                edge_fraction: FORWARD_EDGE_FRACTION,
                flip_mean: FORWARD_FLIP_MEAN,
                mean_relative: Some(FORWARD_MEAN_RELATIVE),
                ..Self::default()
            },
            _ => Self::default(),
        }
    }
}

/// Brightest values for which the limits are absolute. Inside it they keep
/// their measured meaning: the default scene, `assets/` and the hard cases
/// other than the 1e30 and 1e-30 ones peak between 0.08 and 11.
pub const DISPLAY_RANGE: (f64, f64) = (1e-3, 1e3);

/// The unit the images are compared in: 1, or the reference's brightest
/// finite value when that lies outside `DISPLAY_RANGE`.
pub fn comparison_scale(expected: &LinearImage) -> f64 {
    let brightest = expected
        .pixels
        .iter()
        .flatten()
        .filter(|v| v.is_finite())
        .fold(0.0f64, |m, &v| m.max(f64::from(v)));
    let (low, high) = DISPLAY_RANGE;
    if brightest > 0.0 && !(low..=high).contains(&brightest) {
        brightest
    } else {
        1.0
    }
}

/// `image` divided by `scale` (borrowed as it is when `scale` is 1).
pub fn scaled(image: &LinearImage, scale: f64) -> Cow<'_, LinearImage> {
    if scale == 1.0 {
        return Cow::Borrowed(image);
    }
    Cow::Owned(LinearImage {
        pixels: image
            .pixels
            .iter()
            .map(|p| p.map(|v| (f64::from(v) / scale) as f32))
            .collect(),
        width: image.width,
        height: image.height,
    })
}

/// The FLIP mean of `actual` against `expected` with the edge pixels that
/// differ by more than `tolerance` put back to `expected`'s, where they are
/// no more than the floor allows (`MIN_EDGE_PIXELS`); `None` where there
/// are none, or more. Asked only of an image whose whole FLIP is over its
/// limit, so that a passing image's FLIP is computed once. The floor lets those pixels differ whatever their
/// colour, and FLIP spreads one pixel's difference over its neighbours by
/// up to 25 pixels' worth (a saturated pixel on black or on another hue;
/// 2.2 for a grey one on grey): two silhouette pixels of a bright green box
/// on black put a random scene's FLIP mean (87 x 43) at 4.24e-3, over the
/// 3 grey pixels' worth the floor allowed for them before. The rest of the
/// image is held to the mode's own FLIP limit.
fn flip_without_floor_pixels(
    expected: &LinearImage,
    actual: &LinearImage,
    near_edge: &[bool],
    tolerance: f64,
) -> Option<f64> {
    let differing: Vec<usize> = (0..expected.pixels.len())
        .filter(|&i| near_edge[i])
        .filter(|&i| {
            let (e, a) = (expected.pixels[i], actual.pixels[i]);
            // NaN differs too.
            (0..3).any(|c| {
                let off = f64::from((e[c] - a[c]).abs());
                off.is_nan() || off > tolerance
            })
        })
        .collect();
    if differing.is_empty() || differing.len() > MIN_EDGE_PIXELS as usize {
        return None;
    }
    let mut rest = actual.clone();
    for i in differing {
        rest.pixels[i] = expected.pixels[i];
    }
    Some(flip(expected, &rest, PIXELS_PER_DEGREE).mean)
}

/// `image` with each pixel divided by the brightest channel of the same
/// pixel of `expected` where that is over 1: interior errors are absolute
/// up to 1 and relative above it, as f32's rounding is. A pixel of 99.7
/// (a light close to a surface, with the inverse-square falloff) was off
/// by 1.5e-3, two ulps, over the raster modes' absolute 1e-3 (found by the
/// random scenes); the image's brightest value (`comparison_scale`) alone
/// left it absolute, as the image stays inside `DISPLAY_RANGE`.
/// Borrowed where no pixel of `expected` is over 1 (most images): nothing
/// to divide.
fn relative_above_one<'a>(expected: &LinearImage, image: &'a LinearImage) -> Cow<'a, LinearImage> {
    let magnitude = |e: &[f32; 3]| e.iter().fold(1.0f32, |m, v| m.max(v.abs()));
    if expected.pixels.iter().all(|e| magnitude(e) == 1.0) {
        return Cow::Borrowed(image);
    }
    let pixels = expected
        .pixels
        .iter()
        .zip(&image.pixels)
        .map(|(e, p)| p.map(|v| v / magnitude(e)))
        .collect();
    Cow::Owned(LinearImage {
        pixels,
        width: image.width,
        height: image.height,
    })
}

/// One scene in one mode, checked.
pub struct CheckOutcome {
    pub shading: Shading,
    /// The CPU reference.
    pub expected: LinearImage,
    /// The GPU render.
    pub actual: LinearImage,
    /// The figures and the verdict (`judge`).
    pub judgement: Judgement,
    /// Each render's own time; the two run side by side, so they overlap.
    pub gpu_ms: f64,
    pub cpu_ms: f64,
    /// Both renders, side by side: what the case took.
    pub renders_ms: f64,
    /// The GPU ray tracer's engine; `None` for the raster modes.
    pub traversal: Option<crate::scene::Traversal>,
}

impl CheckOutcome {
    pub fn passed(&self) -> bool {
        self.judgement.failures.is_empty()
    }
}

/// A figure passes at or below its limit; NaN never passes.
fn within(value: f64, limit: f64) -> bool {
    value <= limit
}

/// The figures of one comparison and the thresholds they broke.
pub struct Judgement {
    pub interior: ErrorStats,
    pub edges: ErrorStats,
    /// Edge pixels differing by more than the edge tolerance, as a share of
    /// the whole image.
    pub edge_share: f64,
    pub flip: FlipStats,
    /// The unit of the figures above (`comparison_scale`): 1 for images in
    /// the display range.
    pub scale: f64,
    /// One line per threshold exceeded, with the figure and the limit.
    pub failures: Vec<String>,
}

/// Measures `actual` against `expected` (interior and edge pixels apart,
/// `near_edge` marking the edge ones) and judges the figures by `limits`.
/// Pure: what `check` decides from two images, testable on made-up ones.
pub fn judge(
    expected: &LinearImage,
    actual: &LinearImage,
    near_edge: &[bool],
    limits: &CheckThresholds,
) -> Judgement {
    let interior_mask: Vec<bool> = near_edge.iter().map(|e| !e).collect();
    let pixel = limits.edge_pixel_error;
    let scale = comparison_scale(expected);
    let (e, a) = (scaled(expected, scale), scaled(actual, scale));
    // FLIP (single-threaded, the costliest figure) beside the statistics.
    let (flip, (interior, edges)) = rayon::join(
        || flip(&e, &a, PIXELS_PER_DEGREE),
        || {
            (
                ErrorStats::compute(
                    &relative_above_one(&e, &e),
                    &relative_above_one(&e, &a),
                    Some(&interior_mask),
                    pixel,
                ),
                ErrorStats::compute(&e, &a, Some(near_edge), pixel),
            )
        },
    );

    let mut failures = Vec::new();
    if !within(interior.max_abs, limits.interior_max_abs) {
        failures.push(format!(
            "interior max error {:.3e} > {:.1e} ({} interior pixels)",
            interior.max_abs, limits.interior_max_abs, interior.pixels
        ));
    }
    let differing_edges = edges.fraction_over * edges.pixels as f64;
    let image_pixels = (interior.pixels + edges.pixels).max(1) as f64;
    let edge_share = differing_edges / image_pixels;
    // The floor (`MIN_EDGE_PIXELS`) as a share of this image.
    let floor = f64::from(MIN_EDGE_PIXELS) / image_pixels;
    let edge_limit = limits.edge_fraction.max(floor);
    if !within(edge_share, edge_limit) {
        failures.push(format!(
            "{differing_edges:.0} edge pixels ({:.4}% of the image) differ by more than {pixel} > {:.3}%",
            edge_share * 100.0,
            edge_limit * 100.0
        ));
    }
    let judged_flip = if within(flip.mean, limits.flip_mean) {
        flip.mean
    } else {
        flip_without_floor_pixels(&e, &a, near_edge, pixel).unwrap_or(flip.mean)
    };
    if !within(judged_flip, limits.flip_mean) {
        failures.push(format!(
            "FLIP mean {judged_flip:.2e} > {:.1e}",
            limits.flip_mean
        ));
    }
    if let Some(limit) = limits.mean_relative {
        let apart = relative_mean_difference(&e, &a);
        if !within(apart, limit) {
            failures.push(format!(
                "the images' means are {apart:.2e} apart (relative) > {limit:.1e}"
            ));
        }
    }
    let non_finite = interior.non_finite + edges.non_finite;
    if non_finite > 0 {
        failures.push(format!("{non_finite} pixels are NaN or infinite"));
    }
    Judgement {
        interior,
        edges,
        edge_share,
        flip,
        scale,
        failures,
    }
}

/// `|mean(actual) - mean(expected)| / mean(expected)` over every channel
/// of every pixel (0 for two black images, infinity for a black expected
/// one against another).
fn relative_mean_difference(expected: &LinearImage, actual: &LinearImage) -> f64 {
    let mean = |i: &LinearImage| {
        i.pixels
            .iter()
            .flatten()
            .map(|&v| f64::from(v))
            .sum::<f64>()
            / i.pixels.len().max(1) as f64
    };
    let (e, a) = (mean(expected), mean(actual));
    if e == a {
        0.0
    } else {
        (a - e).abs() / e.abs()
    }
}

/// Renders `scene` on the GPU and `reference` (normally the same scene) with
/// the CPU reference, and compares. A different `reference` is how the tests
/// show that perturbing the reference is caught.
pub fn check(
    device: &Device,
    scene: &Scene,
    reference: &Scene,
    shading: Shading,
    limits: &CheckThresholds,
) -> Result<CheckOutcome, Error> {
    check_counted(
        device,
        scene,
        reference,
        shading,
        limits,
        &WorkCounter::default(),
    )
}

/// [`check`], the CPU reference counting its phases into `counter` (for a
/// caller to show progress).
pub fn check_counted(
    device: &Device,
    scene: &Scene,
    reference: &Scene,
    shading: Shading,
    limits: &CheckThresholds,
    counter: &WorkCounter,
) -> Result<CheckOutcome, Error> {
    // Side by side: the GPU render leaves a core idle for much of its time
    // (pipeline creation and code generation run on one thread), which the
    // CPU reference fills.
    let started = std::time::Instant::now();
    let (actual, reference_render) = rayon::join(
        || render(device, scene, &RenderRequest::gpu(shading)),
        || {
            let request = RenderRequest {
                progress: Some(counter),
                ..RenderRequest::cpu(shading)
            };
            render(device, reference, &request)
        },
    );
    let renders_ms = started.elapsed().as_secs_f64() * 1e3;
    let actual = actual?;
    let expected = reference_render?;
    let coverage = (expected.coverage.as_ref()).expect("the CPU reference knows its pixels");
    let judgement = judge(&expected.image, &actual.image, &coverage.near_edge, limits);
    Ok(CheckOutcome {
        shading,
        gpu_ms: actual.timings.total_ms,
        cpu_ms: expected.timings.total_ms,
        renders_ms,
        traversal: actual.traversal,
        expected: expected.image,
        actual: actual.image,
        judgement,
    })
}
