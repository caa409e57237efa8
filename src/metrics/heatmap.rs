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
}
