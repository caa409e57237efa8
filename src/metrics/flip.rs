//! FLIP, NVIDIA's perceptual image difference, through the `nv-flip` crate
//! (which builds NVIDIA's C++ implementation).
//!
//! Owns the conversion of our linear images to what FLIP reads and the
//! pooling of its per-pixel map. LDR-FLIP compares sRGB images: both sides
//! are clamped to [0, 1] and sRGB-encoded to 8 bits first, exactly as a PNG
//! of them would be, so `diff` of two PNGs sees the files' own bytes.

use serde::Serialize;

use crate::linear_image::LinearImage;
use crate::output::linear_to_srgb8;

use super::stats::nearest_rank;

/// FLIP's default observer: 0.7 m from a 0.7 m wide 3840-pixel display.
pub const PIXELS_PER_DEGREE: f32 = nv_flip::DEFAULT_PIXELS_PER_DEGREE;

/// The FLIP error map and its pooled figures. Each map value is in [0, 1];
/// 0 is no visible difference.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct FlipStats {
    /// The mean of the map: the single number FLIP's authors recommend.
    pub mean: f64,
    /// The median of the map (nearest rank, unweighted).
    pub median: f64,
    /// The 99th percentile of the map (nearest rank, unweighted).
    pub p99: f64,
    /// The largest map value.
    pub max: f64,
    pub pixels_per_degree: f64,
    pub width: u32,
    pub height: u32,
    /// The per-pixel error, row-major from the top left. Not serialised.
    #[serde(skip)]
    pub map: Vec<f32>,
}

fn to_flip_image(image: &LinearImage) -> nv_flip::FlipImageRgb8 {
    let bytes: Vec<u8> = image
        .pixels
        .iter()
        .flat_map(|p| p.map(linear_to_srgb8))
        .collect();
    nv_flip::FlipImageRgb8::with_data(image.width, image.height, &bytes)
}

/// LDR-FLIP of `actual` against `expected` (FLIP's reference and test).
///
/// # Panics
///
/// If the sizes differ or either image has no pixels (`metrics::compare`
/// checks both first).
pub fn flip(expected: &LinearImage, actual: &LinearImage, pixels_per_degree: f32) -> FlipStats {
    assert_eq!(
        (expected.width, expected.height),
        (actual.width, actual.height),
        "images of different sizes"
    );
    assert!(!expected.pixels.is_empty(), "an empty image");
    let map = nv_flip::flip(
        to_flip_image(expected),
        to_flip_image(actual),
        pixels_per_degree,
    )
    .to_vec();
    let mut sorted: Vec<f64> = map.iter().map(|&v| f64::from(v)).collect();
    let mean = sorted.iter().sum::<f64>() / sorted.len() as f64;
    let median = nearest_rank(&mut sorted, 0.5);
    let p99 = nearest_rank(&mut sorted, 0.99);
    FlipStats {
        mean,
        median,
        p99,
        max: *sorted.last().expect("a non-empty map"),
        pixels_per_degree: f64::from(pixels_per_degree),
        width: expected.width,
        height: expected.height,
        map,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::output::srgb8_to_linear;

    #[test]
    fn every_8_bit_value_survives_decoding_and_encoding() {
        // FLIP of two PNGs must see the files' bytes: decoding to linear and
        // encoding back has to be exact.
        for v in 0..=255u8 {
            assert_eq!(linear_to_srgb8(srgb8_to_linear(v)), v);
        }
    }

    #[test]
    fn identical_images_have_zero_flip() {
        let mut a = LinearImage::new(16, 16, [0.2, 0.4, 0.6]);
        a.set(3, 4, [1.0, 0.0, 0.0]);
        let f = flip(&a, &a.clone(), PIXELS_PER_DEGREE);
        assert_eq!((f.mean, f.max), (0.0, 0.0));
        assert_eq!(f.map.len(), 256);
    }

    #[test]
    fn a_visible_change_is_local_and_ordered() {
        let expected = LinearImage::new(32, 32, [0.0; 3]);
        let mut actual = expected.clone();
        for y in 14..18 {
            for x in 14..18 {
                actual.set(x, y, [1.0; 3]);
            }
        }
        let f = flip(&expected, &actual, PIXELS_PER_DEGREE);
        let at = |x: usize, y: usize| f.map[y * 32 + x];
        assert!(at(15, 15) > 0.5, "a white square on black is obvious");
        assert_eq!(at(0, 0), 0.0, "far corners see nothing");
        assert!(f.mean > 0.0 && f.mean < f.p99 && f.p99 <= f.max);
        assert!(f.median <= f.p99);
        // Values above 1 clamp to white, as in a PNG.
        let mut brighter = actual.clone();
        brighter.set(15, 15, [7.0; 3]);
        assert_eq!(flip(&expected, &brighter, PIXELS_PER_DEGREE).map, f.map);
    }
}
