//! Heat maps of the per-pixel error, as images to write next to a failed
//! comparison.
//!
//! Owns colouring only: the FLIP map through the magma colour map that
//! `nv-flip` ships (black for no difference, through purple and orange, to
//! pale yellow for FLIP 1). The result is a `LinearImage` whose 8-bit sRGB
//! encoding (a PNG) is exactly the magma colours.

use crate::linear_image::LinearImage;
use crate::output::srgb8_to_linear;

use super::flip::FlipStats;

/// The magma colour of each pixel of `flip.map`.
pub fn flip_heatmap(flip: &FlipStats) -> LinearImage {
    let map = nv_flip::FlipImageFloat::with_data(flip.width, flip.height, &flip.map);
    let bytes = map.apply_color_lut(&nv_flip::magma_lut()).to_vec();
    LinearImage {
        width: flip.width,
        height: flip.height,
        pixels: bytes
            .chunks_exact(3)
            .map(|c| [c[0], c[1], c[2]].map(srgb8_to_linear))
            .collect(),
    }
}

/// The per-pixel error (the largest channel difference) of two images of
/// one size, scaled so that the largest is 1, in magma: where they differ,
/// however little (FLIP's map of a change under one 8-bit step is black
/// to the eye). A non-finite difference counts as the largest. Returns
/// the image and the scale (the largest finite error; 0 where they are
/// equal, and the image black).
pub fn scaled_error_heatmap(expected: &LinearImage, actual: &LinearImage) -> (LinearImage, f64) {
    let errors: Vec<f64> = expected
        .pixels
        .iter()
        .zip(&actual.pixels)
        .map(|(e, a)| {
            (0..3)
                .map(|c| (f64::from(e[c]) - f64::from(a[c])).abs())
                .fold(
                    0.0,
                    |m: f64, d| if d.is_nan() { f64::INFINITY } else { m.max(d) },
                )
        })
        .collect();
    let largest = errors
        .iter()
        .copied()
        .filter(|d| d.is_finite())
        .fold(0.0, f64::max);
    let map: Vec<f32> = errors
        .iter()
        .map(|&d| match (d.is_finite(), largest > 0.0) {
            (false, _) => 1.0,
            (true, true) => (d / largest) as f32,
            (true, false) => 0.0,
        })
        .collect();
    let stats = FlipStats {
        mean: 0.0,
        median: 0.0,
        p99: 0.0,
        max: 0.0,
        pixels_per_degree: 0.0,
        width: expected.width,
        height: expected.height,
        map,
    };
    (flip_heatmap(&stats), largest)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::output::linear_to_srgb8;

    fn stats(map: Vec<f32>, width: u32, height: u32) -> FlipStats {
        FlipStats {
            mean: 0.0,
            median: 0.0,
            p99: 0.0,
            max: 0.0,
            pixels_per_degree: 67.0,
            width,
            height,
            map,
        }
    }

    #[test]
    fn magma_runs_from_black_to_pale_yellow() {
        let heat = flip_heatmap(&stats(vec![0.0, 0.5, 1.0], 3, 1));
        let srgb = |x| heat.get(x, 0).map(linear_to_srgb8);
        // Magma's ends: (0, 0, 4) and (252, 253, 191).
        assert_eq!(srgb(0), [0, 0, 4]);
        assert_eq!(srgb(2), [252, 253, 191]);
        let [r, g, b] = srgb(1);
        assert!(
            r > g && r > b,
            "the middle of magma is a red-pink: {r} {g} {b}"
        );
    }

    #[test]
    fn keeps_the_layout() {
        let mut map = vec![0.0; 6];
        map[5] = 1.0; // (2, 1): bottom right of a 3x2 map
        let heat = flip_heatmap(&stats(map, 3, 2));
        assert_eq!((heat.width, heat.height), (3, 2));
        assert_eq!(linear_to_srgb8(heat.get(2, 1)[0]), 252);
        assert_eq!(linear_to_srgb8(heat.get(0, 0)[0]), 0);
    }

    /// The largest error is magma's top, half of it magma's middle, none
    /// black, whatever the scale.
    #[test]
    fn the_scaled_error_map_spans_magma_from_no_error_to_the_largest() {
        let image = |values: [f32; 3]| LinearImage {
            width: 3,
            height: 1,
            pixels: values.iter().map(|&v| [v, 0.0, 0.0]).collect(),
        };
        let (heat, scale) =
            scaled_error_heatmap(&image([0.1, 0.1, 0.1]), &image([0.1, 0.102, 0.104]));
        assert!((scale - 0.004).abs() < 1e-6, "{scale}");
        let reference = flip_heatmap(&stats(vec![0.0, 0.5, 1.0], 3, 1));
        for x in 0..3 {
            let a = heat.get(x, 0).map(linear_to_srgb8);
            let b = reference.get(x, 0).map(linear_to_srgb8);
            let close = a.iter().zip(&b).all(|(p, q)| p.abs_diff(*q) <= 2);
            assert!(close, "pixel {x}: {a:?} against {b:?}");
        }
        let (black, zero) = scaled_error_heatmap(&image([0.5; 3]), &image([0.5; 3]));
        assert_eq!(zero, 0.0);
        assert_eq!(
            black.get(2, 0).map(linear_to_srgb8),
            reference.get(0, 0).map(linear_to_srgb8)
        );
    }
}
