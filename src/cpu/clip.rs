//! Clipping a triangle against the near plane, in clip space, as Vulkan
//! does before rasterization.
//!
//! The projection (`camera.rs`) puts `z = near` and `w = distance along the
//! view direction`, so Vulkan's `0 <= z <= w` reduces to `w >= near`: only
//! the near plane clips what is seen. There is no far plane. The side
//! planes of a guard band `GUARD_BAND` times the view's width (Vulkan
//! implementations keep one for the same reason) clip too, which changes
//! no sample: they only keep window coordinates within a few image widths,
//! where a huge triangle near the eye (a facet of a planet of radius 1e20,
//! cut by a near plane 1e-3 away) would otherwise reach 1e21 pixels and
//! leave its edge functions no digits.

use glam::{DVec2, DVec3, DVec4};

/// A vertex with everything the rasterizer interpolates.
#[derive(Debug, Clone)]
pub struct ClipVertex {
    pub clip: DVec4,
    /// Camera-relative position.
    pub position: DVec3,
    pub normal: DVec3,
    /// Gouraud intensity (unused in the other modes).
    pub intensity: DVec3,
    /// Gouraud: the intensity of the back, lit with the normal negated,
    /// for a triangle seen from behind (`docs/lighting-model.md`, "Which
    /// side is lit").
    pub back_intensity: DVec3,
    /// What only a surface with vertex colours or a pattern carries, boxed
    /// so that the others' vertices stay small: the reference holds three
    /// per triangle.
    pub extra: Option<Box<Extras>>,
    /// What the attributes above are multiplied by: the clip-space `w` for
    /// screen-linear interpolation, 1 otherwise (see `cpu::raster`).
    pub weight: f64,
}

/// A vertex's colour attributes, multiplied by its `weight` like the others.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Extras {
    /// The vertex colour (one where the mesh has none): Phong interpolates
    /// it.
    pub color: DVec3,
    /// Gouraud under a pattern: the specular part of the intensity, apart
    /// from the rest (`intensity`), which the pattern multiplies per pixel.
    pub specular: DVec3,
    /// The same for the back.
    pub back_specular: DVec3,
    /// Texture coordinates (zero without a pattern).
    pub uv: DVec2,
}

impl ClipVertex {
    fn lerp(&self, other: &Self, t: f64) -> Self {
        Self {
            clip: self.clip.lerp(other.clip, t),
            position: self.position.lerp(other.position, t),
            normal: self.normal.lerp(other.normal, t),
            intensity: self.intensity.lerp(other.intensity, t),
            back_intensity: self.back_intensity.lerp(other.back_intensity, t),
            extra: match (&self.extra, &other.extra) {
                (Some(a), Some(b)) => Some(Box::new(Extras {
                    color: a.color.lerp(b.color, t),
                    specular: a.specular.lerp(b.specular, t),
                    back_specular: a.back_specular.lerp(b.back_specular, t),
                    uv: a.uv.lerp(b.uv, t),
                })),
                _ => None,
            },
            weight: self.weight + (other.weight - self.weight) * t,
        }
    }
}

/// The polygon (0, 3 or 4 vertices) of `tri` on the visible side of
/// `w >= near`, then within the guard band. New vertices interpolate every
/// attribute linearly in clip space (Sutherland-Hodgman), which is exact
/// for perspective-correct attributes.
pub fn clip_near(tri: [ClipVertex; 3], near: f64) -> Vec<ClipVertex> {
    let mut polygon = clip_against(tri.to_vec(), |c| c.w - near);
    // Exactly on the near plane despite rounding.
    for v in &mut polygon {
        if v.clip.w < near {
            v.clip.w = near;
        }
    }
    for (axis, sign) in [(0, 1.0), (0, -1.0), (1, 1.0), (1, -1.0)] {
        polygon = clip_against(polygon, |c| GUARD_BAND * c.w - sign * c[axis]);
    }
    polygon
}

/// Half the guard band's width in normalised device coordinates: window
/// coordinates stay within 32 image sizes of the image.
pub const GUARD_BAND: f64 = 64.0;

/// The part of a convex polygon where `distance(clip) >= 0`.
fn clip_against(polygon: Vec<ClipVertex>, distance: impl Fn(DVec4) -> f64) -> Vec<ClipVertex> {
    let d: Vec<f64> = polygon.iter().map(|v| distance(v.clip)).collect();
    if d.iter().all(|&x| x >= 0.0) {
        return polygon;
    }
    let n = polygon.len();
    let mut out = Vec::with_capacity(n + 1);
    for i in 0..n {
        let j = (i + 1) % n;
        if d[i] >= 0.0 {
            out.push(polygon[i].clone());
        }
        if (d[i] >= 0.0) != (d[j] >= 0.0) {
            // From the end nearer the plane, so that t <= 1/2: from the far
            // end t would round to 1 and the far end's rounding (a ring
            // vertex of a planet 1e18 away) would swamp the near one.
            let (from, to, d_from, d_to) = if d[i].abs() <= d[j].abs() {
                (i, j, d[i], d[j])
            } else {
                (j, i, d[j], d[i])
            };
            out.push(polygon[from].lerp(&polygon[to], d_from / (d_from - d_to)));
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    fn vertex(w: f64, tag: f64) -> ClipVertex {
        ClipVertex {
            clip: DVec4::new(tag, 0.0, 0.1, w),
            position: DVec3::splat(tag),
            normal: DVec3::Z,
            intensity: DVec3::splat(tag),
            back_intensity: DVec3::splat(tag),
            extra: None,
            weight: 1.0,
        }
    }

    #[test]
    fn keeps_visible_triangles_and_drops_hidden_ones() {
        let all_in = clip_near([vertex(1.0, 0.0), vertex(2.0, 1.0), vertex(3.0, 2.0)], 0.1);
        assert_eq!(all_in.len(), 3);
        let all_out = clip_near(
            [vertex(-1.0, 0.0), vertex(0.05, 1.0), vertex(-3.0, 2.0)],
            0.1,
        );
        assert!(all_out.is_empty());
    }

    #[test]
    fn one_vertex_behind_gives_a_quad_on_the_plane() {
        let poly = clip_near([vertex(-1.0, 0.0), vertex(1.0, 1.0), vertex(3.0, 2.0)], 0.5);
        assert_eq!(poly.len(), 4);
        assert!(poly.iter().all(|v| v.clip.w >= 0.5));
        // The new vertex on edge (w=-1 -> w=1) sits at t = 0.75: attributes
        // interpolate linearly in clip space.
        let on_plane: Vec<_> = poly.iter().filter(|v| v.clip.w == 0.5).collect();
        assert_eq!(on_plane.len(), 2);
        assert!(on_plane.iter().any(|v| (v.position.x - 0.75).abs() < 1e-12));
    }
}
