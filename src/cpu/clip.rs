//! Clipping a triangle against the near plane, in clip space, as Vulkan
//! does before rasterization.
//!
//! The projection (`camera.rs`) puts `z = near` and `w = distance along the
//! view direction`, so Vulkan's `0 <= z <= w` reduces to `w >= near`: only
//! the near plane clips. The side planes need no clipping, because
//! rasterization is bounded by the image (Vulkan implementations use a guard
//! band for the same reason); there is no far plane.

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
            extra: match (&self.extra, &other.extra) {
                (Some(a), Some(b)) => Some(Box::new(Extras {
                    color: a.color.lerp(b.color, t),
                    specular: a.specular.lerp(b.specular, t),
                    uv: a.uv.lerp(b.uv, t),
                })),
                _ => None,
            },
            weight: self.weight + (other.weight - self.weight) * t,
        }
    }
}

/// The polygon (0, 3 or 4 vertices) of `tri` on the visible side of
/// `w >= near`. New vertices interpolate every attribute linearly in clip
/// space (Sutherland-Hodgman), which is exact for perspective-correct
/// attributes.
pub fn clip_near(tri: [ClipVertex; 3], near: f64) -> Vec<ClipVertex> {
    let inside = |v: &ClipVertex| v.clip.w >= near;
    if tri.iter().all(inside) {
        return tri.to_vec();
    }
    let mut out = Vec::with_capacity(4);
    for i in 0..3 {
        let (a, b) = (&tri[i], &tri[(i + 1) % 3]);
        if inside(a) {
            out.push(a.clone());
        }
        if inside(a) != inside(b) {
            let t = (near - a.clip.w) / (b.clip.w - a.clip.w);
            let mut v = a.lerp(b, t);
            v.clip.w = near; // exactly on the plane despite rounding
            out.push(v);
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
