//! One comparison of an actual image against an expected one: every
//! figure (`Comparison`), over the whole image and, with a silhouette
//! mask, over its interior and its silhouettes apart.

use serde::Serialize;

use super::flip::{self, FlipStats};
use super::stats::ErrorStats;
use crate::linear_image::LinearImage;

#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum MetricsError {
    #[error("the images differ in size: expected is {expected_width}x{expected_height}, actual is {actual_width}x{actual_height}")]
    SizeMismatch {
        expected_width: u32,
        expected_height: u32,
        actual_width: u32,
        actual_height: u32,
    },
    #[error("the images have no pixels ({width}x{height})")]
    Empty { width: u32, height: u32 },
    #[error("the mask has {mask} entries for {pixels} pixels")]
    MaskLength { mask: usize, pixels: usize },
}

/// How the figures are measured (not whether they pass: see `Thresholds`).
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct Settings {
    /// The pixel error `ErrorStats::fraction_over` counts against. Default
    /// 0.01 in linear intensity: more than an 8-bit sRGB round trip can cause
    /// (at most half a step, 0.0045 at white), so two renders that differ
    /// only by being saved as PNG count no pixel.
    pub pixel_threshold: f64,
    /// FLIP's observer. Default 67 (`flip::PIXELS_PER_DEGREE`).
    pub pixels_per_degree: f32,
}

impl Default for Settings {
    fn default() -> Self {
        Self {
            pixel_threshold: 0.01,
            pixels_per_degree: flip::PIXELS_PER_DEGREE,
        }
    }
}

/// Every figure of one comparison of an actual image against an expected one.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Comparison {
    pub width: u32,
    pub height: u32,
    /// Over every pixel.
    pub stats: ErrorStats,
    /// Over every pixel (FLIP looks at neighbourhoods, so it is not split).
    pub flip: FlipStats,
    /// Over the pixels outside the mask; `None` without a mask.
    pub interior: Option<ErrorStats>,
    /// Over the pixels inside the mask; `None` without a mask.
    pub silhouette: Option<ErrorStats>,
}

/// Compares `actual` against `expected` with the default `Settings`.
/// `mask` (true = silhouette, one entry per pixel, see `edges`) adds the
/// interior and silhouette figures.
pub fn compare(
    expected: &LinearImage,
    actual: &LinearImage,
    mask: Option<&[bool]>,
) -> Result<Comparison, MetricsError> {
    compare_with(expected, actual, mask, &Settings::default())
}

/// `compare` with explicit `Settings`.
pub fn compare_with(
    expected: &LinearImage,
    actual: &LinearImage,
    mask: Option<&[bool]>,
    settings: &Settings,
) -> Result<Comparison, MetricsError> {
    if (expected.width, expected.height) != (actual.width, actual.height) {
        return Err(MetricsError::SizeMismatch {
            expected_width: expected.width,
            expected_height: expected.height,
            actual_width: actual.width,
            actual_height: actual.height,
        });
    }
    if expected.pixels.is_empty() {
        return Err(MetricsError::Empty {
            width: expected.width,
            height: expected.height,
        });
    }
    if let Some(m) = mask {
        if m.len() != expected.pixels.len() {
            return Err(MetricsError::MaskLength {
                mask: m.len(),
                pixels: expected.pixels.len(),
            });
        }
    }
    let threshold = settings.pixel_threshold;
    let interior_mask: Option<Vec<bool>> = mask.map(|m| m.iter().map(|&s| !s).collect());
    Ok(Comparison {
        width: expected.width,
        height: expected.height,
        stats: ErrorStats::compute(expected, actual, None, threshold),
        flip: flip::flip(expected, actual, settings.pixels_per_degree),
        interior: interior_mask
            .as_deref()
            .map(|m| ErrorStats::compute(expected, actual, Some(m), threshold)),
        silhouette: mask.map(|m| ErrorStats::compute(expected, actual, Some(m), threshold)),
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::metrics::thresholds::Thresholds;

    #[test]
    fn size_mismatch_names_both_sizes() {
        let a = LinearImage::new(4, 3, [0.0; 3]);
        let b = LinearImage::new(3, 4, [0.0; 3]);
        let e = compare(&a, &b, None).unwrap_err();
        assert_eq!(
            e.to_string(),
            "the images differ in size: expected is 4x3, actual is 3x4"
        );
    }

    #[test]
    fn empty_images_and_wrong_masks_are_errors() {
        let empty = LinearImage::new(0, 5, [0.0; 3]);
        assert!(matches!(
            compare(&empty, &empty, None),
            Err(MetricsError::Empty { .. })
        ));
        let a = LinearImage::new(2, 2, [0.0; 3]);
        assert_eq!(
            compare(&a, &a, Some(&[true; 3])).unwrap_err(),
            MetricsError::MaskLength { mask: 3, pixels: 4 }
        );
    }

    #[test]
    fn identical_images_pass() {
        let mut a = LinearImage::new(8, 8, [0.1, 0.2, 0.3]);
        a.set(2, 2, [0.9, 0.9, 0.9]);
        let c = compare(&a, &a, None).unwrap();
        assert_eq!((c.stats.max_abs, c.flip.mean), (0.0, 0.0));
        assert!(c.interior.is_none() && c.silhouette.is_none());
        assert!(Thresholds::default().check(&c).is_empty());
    }

    #[test]
    fn mask_splits_interior_and_silhouette() {
        let expected = LinearImage::new(4, 1, [0.0; 3]);
        let mut actual = expected.clone();
        actual.set(0, 0, [0.2; 3]);
        actual.set(3, 0, [0.8; 3]);
        let mask = [false, false, false, true];
        let c = compare(&expected, &actual, Some(&mask)).unwrap();
        let (interior, silhouette) = (c.interior.unwrap(), c.silhouette.unwrap());
        assert_eq!((interior.pixels, silhouette.pixels), (3, 1));
        assert!((interior.max_abs - 0.2).abs() < 1e-7);
        assert!((silhouette.max_abs - 0.8).abs() < 1e-7);
        assert!((c.stats.max_abs - 0.8).abs() < 1e-7);
    }
}
