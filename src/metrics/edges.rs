//! Masks that split an image into silhouette pixels and interior pixels.
//!
//! Rasterisers disagree most at silhouettes (which pixel centres a triangle
//! edge covers), so error there says little about shading; error in the
//! interior says a lot. Two ways to find the silhouettes:
//!
//! - `silhouette_mask`, exact, from per-pixel object ids (the CPU reference
//!   renderer provides them);
//! - `gradient_mask`, approximate, from the expected image alone, for
//!   `shadelab diff` of two image files with no geometry at hand.
//!
//! In both, `true` means "silhouette". Masks are row-major, row 0 at the
//! top, one entry per pixel.

use crate::linear_image::LinearImage;

/// True where the 3x3 neighbourhood of a pixel (the pixel and its eight
/// neighbours that lie inside the image) holds more than one id. `None`,
/// the background, counts as an id of its own, so the pixels on both sides
/// of an object's outline are marked, and so are both sides of a boundary
/// between two objects. Outside the image is not background: an object that
/// fills the frame has no silhouette at the border.
///
/// # Panics
///
/// If `ids.len()` is not `width * height`.
pub fn silhouette_mask(ids: &[Option<u32>], width: u32, height: u32) -> Vec<bool> {
    let (w, h) = (width as usize, height as usize);
    assert_eq!(ids.len(), w * h, "one id per pixel");
    let mut mask = vec![false; w * h];
    for y in 0..h {
        for x in 0..w {
            let own = ids[y * w + x];
            let rows = y.saturating_sub(1)..=(y + 1).min(h - 1);
            mask[y * w + x] = rows.into_iter().any(|ny| {
                (x.saturating_sub(1)..=(x + 1).min(w - 1)).any(|nx| ids[ny * w + nx] != own)
            });
        }
    }
    mask
}

/// True where the largest channel difference between a pixel and one of its
/// four neighbours (left, right, up, down) exceeds `threshold`, in linear
/// intensity. Both pixels of such a step are marked.
///
/// This approximates `silhouette_mask` from the expected image: an outline
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
    fn silhouette_of_a_square_and_a_neighbour() {
        // 9x6: object 1 is a 4x4 square at x, y in 1..=4; object 2 is the
        // column x = 8 at the image's right border. The rest is background.
        let (w, h) = (9usize, 6usize);
        let mut ids = vec![None; w * h];
        for y in 1..=4 {
            for x in 1..=4 {
                ids[y * w + x] = Some(1);
            }
        }
        for y in 0..h {
            ids[y * w + 8] = Some(2);
        }
        let mask = silhouette_mask(&ids, w as u32, h as u32);
        assert_eq!(
            picture(&mask, w),
            [
                // x = 5 touches the square; x = 6 sees only background;
                // x = 7 and the column touch each other.
                "######.##",
                "######.##",
                "##..##.##", // (2, 2) and (3, 2) see only the square
                "##..##.##",
                "######.##",
                "######.##",
            ]
        );
    }

    #[test]
    fn one_id_everywhere_has_no_silhouette() {
        assert!(silhouette_mask(&[Some(3); 12], 4, 3).iter().all(|&m| !m));
        assert!(silhouette_mask(&[None; 12], 4, 3).iter().all(|&m| !m));
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
