//! Which pixels another conforming rasterizer may legitimately show
//! differently (`CpuRender::near_edge`): samples near a visible triangle's
//! boundary, pixels across a pattern's cell boundary, and Gouraud's steep
//! steps of intensity.

use super::coverage::{boundary_distance, SamplePositions};
use super::triangle::Triangle;
use crate::cpu::surface::AT_DISCONTINUITY;
use crate::linear_image::LinearImage;

/// Samples closer than this (in pixels) to the boundary of a visible
/// triangle may be covered differently by the GPU: it snaps f32 window
/// coordinates to 1/256 pixel where this renderer snaps f64 ones, so a vertex
/// can land one grid step (0.0039 px) away, plus f32 rounding of positions
/// (under 0.001 px even at 16384 pixels). 1/64 px is three times their sum.
pub const EDGE_MARGIN: f64 = 1.0 / 64.0;

/// The second pass over a band of rows `y0..y1`, against its final depth
/// (`depth`, pixel i's sample s at i * n + s): marks pixels with a sample
/// within `EDGE_MARGIN` of the boundary of a triangle not behind it there.
pub(super) fn mark_near_boundaries(
    triangles: &[Triangle],
    samples: &SamplePositions,
    (y0, y1): (u32, u32),
    width: u32,
    depth: &[f64],
    near_edge: &mut [bool],
) {
    let n = samples.count();
    for t in triangles {
        if t.max.1 + 1 < y0 || t.min.1 > y1 {
            continue;
        }
        let ys = t.min.1.saturating_sub(1).max(y0)..=(t.max.1 + 1).min(y1 - 1);
        for y in ys {
            for x in t.min.0.saturating_sub(1)..=(t.max.0 + 1).min(width - 1) {
                let i = ((y - y0) * width + x) as usize;
                if near_edge[i] {
                    continue;
                }
                near_edge[i] = (0..n).any(|s| {
                    let (distance, bary) = boundary_distance(t, samples.at(x, y, s));
                    let z = t.depth_at(bary);
                    distance.abs() <= EDGE_MARGIN && z >= depth[i * n + s] * (1.0 - 1e-9)
                });
            }
        }
    }
}

/// A step between neighbouring pixels of a Gouraud image, inside one
/// triangle, that only extreme perspective makes: 0.1 (25 8-bit steps).
const STEEP_STEP: f32 = 0.1;

/// Gouraud: marks every pixel whose value differs from a 4-neighbour's by
/// more than `STEEP_STEP`. Its intensities are linear over each triangle in
/// 3D, so such a step inside a triangle means the interpolation runs over a
/// huge range of depth there: the horizon of a planet's facets, whose
/// corners are 1e18 away. The GPU interpolates `1 / w` in f32, and its
/// rounding moves such a pixel as a silhouette's sub-pixel rounding does
/// (planet-1e20.toml: 1.8e-3 at a pixel the steps of 0.2 surround, 3e-5 on
/// the rest of its floor), so the pixel is judged as an edge.
pub(super) fn mark_steep_intensities(image: &LinearImage, near_edge: &mut [bool]) {
    let (width, height) = (image.width as usize, image.height as usize);
    let step = |a: [f32; 3], b: [f32; 3]| (0..3).any(|k| (a[k] - b[k]).abs() > STEEP_STEP);
    for y in 0..height {
        for x in 0..width {
            let here = image.pixels[y * width + x];
            let steep = (x + 1 < width && step(here, image.pixels[y * width + x + 1]))
                || (y + 1 < height && step(here, image.pixels[(y + 1) * width + x]));
            if steep {
                near_edge[y * width + x] = true;
                if x + 1 < width {
                    near_edge[y * width + x + 1] = true;
                }
                if y + 1 < height {
                    near_edge[(y + 1) * width + x] = true;
                }
            }
        }
    }
}

/// Marks every pixel whose 3x3 neighbourhood holds another pattern cell
/// than its own, and every pixel on a jump of an image's colour
/// (`AT_DISCONTINUITY`): the pattern's colour changes there, and a sample of
/// the GPU's, whose texture coordinates are f32, may land on either side.
pub(super) fn mark_cell_edges(
    width: usize,
    height: usize,
    cells: &[Option<i64>],
    near_edge: &mut [bool],
) {
    for y in 0..height {
        for x in 0..width {
            let Some(own) = cells[y * width + x] else {
                continue;
            };
            if own == AT_DISCONTINUITY {
                near_edge[y * width + x] = true;
                continue;
            }
            let differs = (y.saturating_sub(1)..(y + 2).min(height)).any(|ny| {
                (x.saturating_sub(1)..(x + 2).min(width))
                    .any(|nx| cells[ny * width + nx].is_some_and(|c| c != own))
            });
            if differs {
                near_edge[y * width + x] = true;
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A pattern's cell boundary is an edge for `check`, like a
    /// silhouette: the pixels on both sides of it, and only those.
    #[test]
    fn pixels_beside_a_pattern_cell_change_are_edges() {
        // 4 x 3 pixels: cells 1 | 2 between columns 1 and 2, background
        // (no cell) in the last row.
        let cells = [
            Some(1),
            Some(1),
            Some(2),
            Some(2),
            Some(1),
            Some(1),
            Some(2),
            Some(2),
            None,
            None,
            None,
            None,
        ];
        let mut near_edge = [false; 12];
        mark_cell_edges(4, 3, &cells, &mut near_edge);
        let want = [
            false, true, true, false, false, true, true, false, false, false, false, false,
        ];
        assert_eq!(near_edge, want);
    }
}
