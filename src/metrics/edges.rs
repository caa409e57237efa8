//! A mask that splits an image into silhouette pixels and interior pixels
//! when no geometry is at hand.
//!
//! Rasterisers disagree most at silhouettes (which pixel centres a triangle
//! edge covers), so error there says little about shading; error in the
//! interior says a lot. `shadelab check` has the geometry and takes the
//! exact mask from the CPU reference (`render::Coverage::near_edge`);
//! `shadelab diff` of two image files estimates it with `gradient_mask`.
//!
//! `true` means "silhouette". Masks are row-major, row 0 at the top, one
//! entry per pixel.

use crate::linear_image::LinearImage;

/// True where the largest channel difference between a pixel and one of its
/// four neighbours (left, right, up, down) exceeds `threshold`, in linear
/// intensity. Both pixels of such a step are marked.
///
/// This approximates the silhouettes from the expected image: an outline
/// against a background of another brightness is a step, and smooth shading
/// inside an object changes little from one pixel to the next. It also marks
/// what is not a silhouette (a sharp highlight, a shadow edge, a texture-like
/// facet edge in flat shading) and misses an outline between two surfaces of
/// nearly the same colour. `shadelab diff` uses it with threshold 0.1.
pub fn gradient_mask(image: &LinearImage, threshold: f64) -> Vec<bool> {
    let (w, h) = (image.width as usize, image.height as usize);
    let mut mask = vec![false; w * h];
    let step = |a: [f32; 3], b: [f32; 3]| {
        (0..3)
            .map(|c| (f64::from(a[c]) - f64::from(b[c])).abs())
            .fold(0.0, f64::max)
    };
    for y in 0..h {
        for x in 0..w {
            let i = y * w + x;
            // Each step is looked at once, from its left or upper pixel.
            if x + 1 < w && step(image.pixels[i], image.pixels[i + 1]) > threshold {
                mask[i] = true;
                mask[i + 1] = true;
            }
            if y + 1 < h && step(image.pixels[i], image.pixels[i + w]) > threshold {
                mask[i] = true;
                mask[i + w] = true;
            }
        }
    }
    mask
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Renders a mask as rows of '#' (true) and '.' (false).
    fn picture(mask: &[bool], width: usize) -> Vec<String> {
        mask.chunks(width)
            .map(|row| row.iter().map(|&m| if m { '#' } else { '.' }).collect())
            .collect()
    }

    #[test]
    fn gradient_mask_marks_both_sides_of_a_step() {
        // 5x3, a bright column at x = 3, a faint ramp elsewhere.
        let mut image = LinearImage::new(5, 3, [0.0; 3]);
        for y in 0..3 {
            for x in 0..5 {
                image.set(x, y, [0.01 * x as f32, 0.0, 0.0]);
            }
            image.set(3, y, [0.0, 0.9, 0.0]);
        }
        assert_eq!(
            picture(&gradient_mask(&image, 0.1), 5),
            ["..###", "..###", "..###"]
        );
        assert!(gradient_mask(&image, 0.95).iter().all(|&m| !m));
    }
}
