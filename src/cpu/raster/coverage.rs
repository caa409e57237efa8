//! Which samples a triangle covers (Vulkan's rules: snapped edges, the
//! top-left fill rule), where a pixel's samples lie, and the barycentrics
//! every later step interpolates with.

use glam::DVec2;

use super::triangle::{edge, Triangle};

/// The sample positions within a pixel (`crate::msaa::positions`).
pub(super) struct SamplePositions {
    offsets: &'static [(f64, f64)],
}

impl SamplePositions {
    pub(super) fn new(offsets: &'static [(f64, f64)]) -> Self {
        SamplePositions { offsets }
    }

    /// Samples per pixel.
    pub(super) fn count(&self) -> usize {
        self.offsets.len()
    }

    /// Sample `s` of pixel `(x, y)` in window coordinates.
    pub(super) fn at(&self, x: u32, y: u32, s: usize) -> DVec2 {
        let (ox, oy) = self.offsets[s];
        DVec2::new(f64::from(x) + ox, f64::from(y) + oy)
    }
}

/// Screen-space barycentrics of `p` if the sample is covered.
pub(super) fn coverage(t: &Triangle, p: DVec2) -> Option<[f64; 3]> {
    for i in 0..3 {
        let e = edge(t.edges.snapped[i], t.edges.snapped[(i + 1) % 3], p);
        if e < 0.0 || (e == 0.0 && !t.edges.top_left[i]) {
            return None;
        }
    }
    // Interpolation weights from the unsnapped positions.
    Some(barycentrics(t, p))
}

/// Barycentrics of `p` from the unsnapped window positions (extrapolated
/// outside the triangle).
pub(super) fn barycentrics(t: &Triangle, p: DVec2) -> [f64; 3] {
    let [a, b, c] = t.window;
    let area = t.edges.window_area;
    [
        edge(b, c, p) / area,
        edge(c, a, p) / area,
        edge(a, b, p) / area,
    ]
}

/// Signed distance in pixels from `p` to the triangle's boundary (positive
/// inside), and the barycentrics of `p` (extrapolated outside).
pub(super) fn boundary_distance(t: &Triangle, p: DVec2) -> (f64, [f64; 3]) {
    let sign = t.edges.window_area.signum();
    let distance = (0..3)
        .map(|i| sign * edge(t.window[i], t.window[(i + 1) % 3], p) / t.edges.lengths[i])
        .fold(f64::INFINITY, f64::min);
    (distance, barycentrics(t, p))
}

#[cfg(test)]
mod tests {
    use super::super::triangle::Edges;
    use super::*;
    use crate::cpu::clip::ClipVertex;
    use glam::{DVec3, DVec4};

    fn triangle(points: [DVec2; 3]) -> Triangle {
        let v = ClipVertex {
            clip: DVec4::ONE,
            position: DVec3::ZERO,
            normal: DVec3::Z,
            intensity: DVec3::ZERO,
            back_intensity: DVec3::ZERO,
            extra: None,
            weight: 1.0,
        };
        Triangle {
            object: 0,
            primitive: 0,
            window: points,
            edges: Edges::new(points).expect("a triangle with area"),
            depth: [1.0; 3],
            inv_w: [1.0; 3],
            vertices: [v.clone(), v.clone(), v],
            flat_color: DVec3::ZERO,
            coloured: false,
            min: (0, 0),
            max: (0, 0),
        }
    }

    /// A fan of triangles around a centre, and a grid of squares split along
    /// both diagonals, all with edges through pixel centres: the top-left
    /// rule must cover every sample inside exactly once (no cracks, no
    /// double hits), in either winding.
    #[test]
    fn shared_edges_cover_each_sample_exactly_once() {
        let mut tris = Vec::new();
        let centre = DVec2::new(8.5, 8.5);
        let ring: Vec<DVec2> = (0..12)
            .map(|k| {
                let a = f64::from(k) * std::f64::consts::TAU / 12.0;
                centre + DVec2::new(a.cos(), a.sin()) * 6.0
            })
            .collect();
        for k in 0..12 {
            let (a, b) = (ring[k], ring[(k + 1) % 12]);
            // Alternate windings: coverage must not depend on it.
            tris.push(if k % 2 == 0 {
                [centre, a, b]
            } else {
                [centre, b, a]
            });
        }
        for gx in 0..4 {
            for gy in 0..4 {
                let o = DVec2::new(20.5 + 2.0 * f64::from(gx), 0.5 + 2.0 * f64::from(gy));
                let (a, b, c, d) = (
                    o,
                    o + DVec2::X * 2.0,
                    o + DVec2::new(2.0, 2.0),
                    o + DVec2::Y * 2.0,
                );
                tris.extend([[a, b, c], [a, c, d]]);
            }
        }
        let tris: Vec<Triangle> = tris.into_iter().map(triangle).collect();
        for y in 0..10 {
            for x in 0..30 {
                let p = DVec2::new(f64::from(x) + 0.5, f64::from(y) + 0.5);
                let hits = tris.iter().filter(|t| coverage(t, p).is_some()).count();
                let in_fan = (p - centre).length() < 5.5;
                let in_grid = (20.5..28.5).contains(&p.x) && (0.5..8.5).contains(&p.y);
                if in_fan || in_grid {
                    assert_eq!(hits, 1, "sample ({x}, {y}) covered {hits} times");
                } else {
                    assert!(hits <= 1, "sample ({x}, {y}) covered {hits} times");
                }
            }
        }
    }

    #[test]
    fn top_left_rule_on_a_lone_square() {
        // A square with corners on pixel centres covers its top and left
        // edge samples but not its bottom and right ones: 4 x 4 of 5 x 5.
        let (a, b, c, d) = (
            DVec2::new(0.5, 0.5),
            DVec2::new(4.5, 0.5),
            DVec2::new(4.5, 4.5),
            DVec2::new(0.5, 4.5),
        );
        let tris = [triangle([a, b, c]), triangle([a, c, d])];
        let mut covered = 0;
        for y in 0..6 {
            for x in 0..6 {
                let p = DVec2::new(f64::from(x) + 0.5, f64::from(y) + 0.5);
                if tris.iter().any(|t| coverage(t, p).is_some()) {
                    assert!(x < 4 && y < 4, "({x}, {y}) is on the bottom or right edge");
                    covered += 1;
                }
            }
        }
        assert_eq!(covered, 16);
    }

    #[test]
    fn barycentrics_reproduce_the_sample() {
        let pts = [
            DVec2::new(1.0, 1.0),
            DVec2::new(9.0, 2.0),
            DVec2::new(3.0, 8.0),
        ];
        let t = triangle(pts);
        let p = DVec2::new(4.5, 3.5);
        let b = coverage(&t, p).unwrap();
        let back = pts[0] * b[0] + pts[1] * b[1] + pts[2] * b[2];
        assert!((back - p).length() < 1e-12);
        assert!((b[0] + b[1] + b[2] - 1.0).abs() < 1e-12);
    }
}
