//! Per-pixel error statistics between two images of the same size.
//!
//! Owns the pixel-wise figures (max, mean, RMSE, PSNR, percentiles). Works on
//! `LinearImage` values only: no files, no Vulkan, and no size check (the
//! caller, `metrics::compare`, checks sizes).

use serde::Serialize;

use crate::linear_image::LinearImage;

/// Error figures over a set of pixels (all of them, or those a mask selects).
///
/// "Pixel error" is the largest of the three channels' absolute differences,
/// `max_c |expected_c - actual_c|`, in linear intensity. RMSE and PSNR are
/// over every channel of the selected pixels.
///
/// A channel where either side is NaN or infinite has an infinite error,
/// unless both sides hold the same infinity (then it is 0). Such pixels are
/// counted in `non_finite`. Infinite figures (`psnr` of identical images,
/// `max_abs`/`rmse` with a NaN on one side) serialise to JSON as `null`.
///
/// Over an empty set of pixels (a mask that selects nothing) every figure is
/// 0, `psnr` is infinite and `pixels` is 0.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct ErrorStats {
    /// The largest pixel error.
    pub max_abs: f64,
    /// The mean pixel error.
    pub mean_abs: f64,
    /// Root mean square of the per-channel differences.
    pub rmse: f64,
    /// `10 log10(1 / MSE)` in dB, peak 1.0; infinite (JSON `null`) when the
    /// pixels are identical.
    pub psnr: f64,
    /// The fraction of pixels whose pixel error exceeds `pixel_threshold`.
    pub fraction_over: f64,
    /// The threshold `fraction_over` counts against.
    pub pixel_threshold: f64,
    /// The 99th percentile of the pixel error (nearest rank: the smallest
    /// value that at least 99% of the pixels are at or below).
    pub p99_abs: f64,
    /// Pixels with a NaN or infinite channel on either side.
    pub non_finite: usize,
    /// How many pixels the figures are over.
    pub pixels: usize,
}

/// The absolute difference of one channel, with the rule for non-finite
/// values above.
fn channel_error(a: f32, b: f32) -> f64 {
    if a == b {
        0.0
    } else if a.is_finite() && b.is_finite() {
        (f64::from(a) - f64::from(b)).abs()
    } else {
        f64::INFINITY
    }
}

/// The pixel error of every pixel: the largest channel difference.
pub fn pixel_errors(expected: &LinearImage, actual: &LinearImage) -> Vec<f64> {
    expected
        .pixels
        .iter()
        .zip(&actual.pixels)
        .map(|(e, a)| {
            (0..3)
                .map(|c| channel_error(e[c], a[c]))
                .fold(0.0, f64::max)
        })
        .collect()
}

/// The value at quantile `q` (0 < q <= 1) by nearest rank: the
/// `ceil(q n)`-th smallest. Sorts `values`; 0 for an empty slice.
pub fn nearest_rank(values: &mut [f64], q: f64) -> f64 {
    if values.is_empty() {
        return 0.0;
    }
    values.sort_by(f64::total_cmp);
    let rank = (q * values.len() as f64).ceil() as usize;
    values[rank.clamp(1, values.len()) - 1]
}

impl ErrorStats {
    /// The figures over every pixel, or over the pixels where `mask` is true.
    ///
    /// # Panics
    ///
    /// If the images' pixel counts differ, or `mask` has another length.
    pub fn compute(
        expected: &LinearImage,
        actual: &LinearImage,
        mask: Option<&[bool]>,
        pixel_threshold: f64,
    ) -> Self {
        let n = expected.pixels.len();
        assert_eq!(n, actual.pixels.len(), "images of different sizes");
        if let Some(m) = mask {
            assert_eq!(m.len(), n, "a mask of the wrong length");
        }
        let selected = |i: usize| mask.is_none_or(|m| m[i]);

        let mut errors = Vec::with_capacity(n);
        let mut sum_sq = 0.0;
        let mut non_finite = 0;
        for (i, (e, a)) in expected.pixels.iter().zip(&actual.pixels).enumerate() {
            if !selected(i) {
                continue;
            }
            let mut pixel = 0.0f64;
            for c in 0..3 {
                let d = channel_error(e[c], a[c]);
                pixel = pixel.max(d);
                sum_sq += d * d;
            }
            if !(e.iter().chain(a).all(|v| v.is_finite())) {
                non_finite += 1;
            }
            errors.push(pixel);
        }

        let pixels = errors.len();
        if pixels == 0 {
            return Self {
                max_abs: 0.0,
                mean_abs: 0.0,
                rmse: 0.0,
                psnr: f64::INFINITY,
                fraction_over: 0.0,
                pixel_threshold,
                p99_abs: 0.0,
                non_finite: 0,
                pixels: 0,
            };
        }
        let count = pixels as f64;
        let mse = sum_sq / (3.0 * count);
        let over = errors.iter().filter(|&&d| d > pixel_threshold).count();
        Self {
            max_abs: errors.iter().copied().fold(0.0, f64::max),
            mean_abs: errors.iter().sum::<f64>() / count,
            rmse: mse.sqrt(),
            // An infinite error (NaN against a number) gives -inf, never
            // the +inf of identical images.
            psnr: if mse == 0.0 {
                f64::INFINITY
            } else if mse.is_finite() {
                -10.0 * mse.log10()
            } else {
                f64::NEG_INFINITY
            },
            fraction_over: over as f64 / count,
            pixel_threshold,
            p99_abs: nearest_rank(&mut errors, 0.99),
            non_finite,
            pixels,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn grey(width: u32, height: u32, v: f32) -> LinearImage {
        LinearImage::new(width, height, [v; 3])
    }

    #[test]
    fn identical_images_have_no_error() {
        let a = grey(5, 3, 0.3);
        let s = ErrorStats::compute(&a, &a.clone(), None, 0.01);
        assert_eq!(s.max_abs, 0.0);
        assert_eq!(s.mean_abs, 0.0);
        assert_eq!(s.rmse, 0.0);
        assert_eq!(s.p99_abs, 0.0);
        assert_eq!(s.fraction_over, 0.0);
        assert_eq!(s.psnr, f64::INFINITY);
        assert_eq!(s.pixels, 15);
        // JSON has no infinity: it becomes null.
        let json = serde_json::to_value(&s).unwrap();
        assert!(json["psnr"].is_null());
    }

    #[test]
    fn known_differences_by_hand() {
        // 4x2 of 0.25 grey; two pixels changed by values exact in binary.
        let expected = grey(4, 2, 0.25);
        let mut actual = expected.clone();
        actual.set(0, 0, [0.75, 0.25, 0.25]); // +0.5 in red
        actual.set(3, 1, [0.25, 0.125, 0.5]); // -0.125 green, +0.25 blue
        let s = ErrorStats::compute(&expected, &actual, None, 0.3);
        // Squares: 0.25 + 0.015625 + 0.0625 = 0.328125 over 8 x 3 channels.
        let mse = 0.328125 / 24.0;
        assert!((s.rmse - 0.116_926_793_336_686).abs() < 1e-12);
        assert!((s.rmse - f64::sqrt(mse)).abs() < 1e-12);
        assert!((s.psnr - 18.641_719_209_616).abs() < 1e-9, "{}", s.psnr);
        assert_eq!(s.max_abs, 0.5);
        // Pixel errors: 0.5, 0.25 and six zeros.
        assert!((s.mean_abs - 0.75 / 8.0).abs() < 1e-12);
        assert_eq!(s.fraction_over, 1.0 / 8.0, "only 0.5 exceeds 0.3");
        // Nearest rank: ceil(0.99 * 8) = 8th smallest = the largest.
        assert_eq!(s.p99_abs, 0.5);
    }

    #[test]
    fn p99_is_the_nearest_rank() {
        // 200 pixels, errors 0.001 * i for i in 0..200: the 198th smallest
        // (ceil(0.99 * 200)) is 0.197.
        let expected = grey(200, 1, 0.0);
        let mut actual = expected.clone();
        for x in 0..200 {
            actual.set(x, 0, [0.0, x as f32 * 0.001, 0.0]);
        }
        let s = ErrorStats::compute(&expected, &actual, None, 0.1005);
        assert!((s.p99_abs - 0.197).abs() < 1e-6, "{}", s.p99_abs);
        assert!((s.max_abs - 0.199).abs() < 1e-6);
        // 0.101 ..= 0.199 exceed 0.1005: 99 pixels.
        assert_eq!(s.fraction_over, 99.0 / 200.0);
    }

    #[test]
    fn mask_restricts_the_pixels() {
        let expected = grey(2, 2, 0.0);
        let mut actual = expected.clone();
        actual.set(1, 1, [0.5, 0.0, 0.0]);
        let mask = [false, false, false, true];
        let inside = ErrorStats::compute(&expected, &actual, Some(&mask), 0.01);
        assert_eq!(
            (inside.pixels, inside.max_abs, inside.mean_abs),
            (1, 0.5, 0.5)
        );
        let not_mask: Vec<bool> = mask.iter().map(|m| !m).collect();
        let outside = ErrorStats::compute(&expected, &actual, Some(&not_mask), 0.01);
        assert_eq!((outside.pixels, outside.max_abs), (3, 0.0));
        let none = ErrorStats::compute(&expected, &actual, Some(&[false; 4]), 0.01);
        assert_eq!((none.pixels, none.max_abs, none.rmse), (0, 0.0, 0.0));
    }

    #[test]
    fn non_finite_values_are_infinite_error() {
        let expected = grey(3, 1, 0.5);
        let mut actual = expected.clone();
        actual.set(0, 0, [f32::NAN, 0.5, 0.5]);
        let s = ErrorStats::compute(&expected, &actual, None, 0.01);
        assert_eq!(s.max_abs, f64::INFINITY);
        assert_eq!(s.non_finite, 1);
        assert_eq!(
            s.psnr,
            f64::NEG_INFINITY,
            "a NaN is no match, not a perfect one"
        );
        // NaN on both sides is no match either.
        let s = ErrorStats::compute(&actual, &actual.clone(), None, 0.01);
        assert_eq!((s.psnr, s.non_finite), (f64::NEG_INFINITY, 1));
        // The same infinity on both sides is no error.
        let inf = grey(1, 1, f32::INFINITY);
        let s = ErrorStats::compute(&inf, &inf.clone(), None, 0.01);
        assert_eq!((s.max_abs, s.non_finite), (0.0, 1));
    }
}
