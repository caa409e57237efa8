//! The level of detail of an image texture where a renderer has no screen
//! derivatives (docs/lighting-model.md, "Level of detail"): the ray
//! tracer's ray cones, and flat shading's one lookup per face, which is a
//! primary ray's cone at the face's centroid. Both ray tracers and both
//! flat-shading hosts take it from here or compute the same in GLSL
//! (`shaders/include/texture.glsl`, `cone_lambda`).
//!
//! A cone of width `w` meeting a surface at `cos = |n . d|` leaves a
//! footprint `w` wide across and `w / cos` long; the surface holds
//! `density` texels per unit of area, so its longer axis spans
//! `sqrt(density) w / cos` texels, and the level is that length's log2:
//! `lambda = 0.5 log2(density) + log2(w / cos)` (Akenine-Moller et al.,
//! "Texture Level of Detail Strategies for Real-Time Ray Tracing", 2019).

use glam::{DVec2, DVec3};

use crate::camera::View;
use crate::scene::ImageTexture;

/// How fast a primary ray's cone widens: one pixel's height per unit of
/// distance at the image centre, `2 tan(fov_y / 2) / height`.
pub fn pixel_spread(view: &View) -> f64 {
    2.0 / (view.focal * f64::from(view.height))
}

/// The level of detail of a cone of `width` meeting a surface of `density`
/// texels per unit area at `cos`. NaN (a zero-width cone meeting the
/// surface edge-on, or a surface with no texels) is 0.
pub fn cone_lambda(density: f64, width: f64, cos: f64) -> f64 {
    let lambda = 0.5 * density.log2() + width.log2() - cos.abs().log2();
    if lambda.is_nan() {
        0.0
    } else {
        lambda
    }
}

/// Texels per unit of area of a triangle with corners `positions` and
/// texture coordinates `uvs` (before the texture's transform): its area in
/// texels (level 0) over its area in the world.
pub fn triangle_density(image: &ImageTexture, positions: [DVec3; 3], uvs: [DVec2; 3]) -> f64 {
    uv_per_world_area(positions, uvs) * texel_area(image)
}

/// A triangle's uv area per unit of its world area: its texel density
/// before the texture's size and transform (the GPU ray tracer keeps it
/// per triangle and multiplies those in: `gpu::raytrace::records`).
pub fn uv_per_world_area(positions: [DVec3; 3], uvs: [DVec2; 3]) -> f64 {
    let [a, b, c] = positions;
    let world = 0.5 * (b - a).cross(c - a).length();
    let (e1, e2) = (uvs[1] - uvs[0], uvs[2] - uvs[0]);
    0.5 * e1.perp_dot(e2).abs() / world
}

/// Texels per unit of uv area: level 0's width times its height, times how
/// much the texture's transform scales areas.
pub fn texel_area(image: &ImageTexture) -> f64 {
    let level = &image.texture.levels[0];
    f64::from(level.width) * f64::from(level.height) * image.transform.area_scale()
}

/// Flat shading's level for a triangle: a primary ray's cone at its
/// centroid (distance `t` from the eye, width `pixel_spread * t`, meeting
/// the face at the angle between the face normal and the ray).
pub fn flat_lambda(
    image: &ImageTexture,
    view: &View,
    positions: [DVec3; 3],
    uvs: [DVec2; 3],
) -> f64 {
    let [a, b, c] = positions;
    let centroid = (a + b + c) / 3.0;
    let to_centroid = centroid - view.eye;
    let t = to_centroid.length();
    let normal = (b - a).cross(c - a).normalize_or_zero();
    let cos = normal.dot(to_centroid / t);
    cone_lambda(
        triangle_density(image, positions, uvs),
        pixel_spread(view) * t,
        cos,
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A face seen head-on whose texels are exactly one pixel each is at
    /// level 0; four times the texels per pixel (twice per side) is level 1.
    #[test]
    fn a_cone_level_counts_texels_per_pixel_side() {
        // Width 0.01 at the surface, 100 x 100 texels per unit area: one
        // texel per cone width.
        assert!((cone_lambda(1e4, 0.01, 1.0)).abs() < 1e-12);
        assert!((cone_lambda(4e4, 0.01, 1.0) - 1.0).abs() < 1e-12);
        // Seen at 60 degrees the footprint stretches twice along one axis:
        // one level, the longer axis deciding (as Vulkan's rho does).
        assert!((cone_lambda(1e4, 0.01, 0.5) - 1.0).abs() < 1e-12);
        assert_eq!(cone_lambda(1e4, 0.0, 0.0), 0.0);
    }

    /// A right triangle of legs 2 and 3 in the world (area 3) whose uv
    /// legs are 0.5 and 0.25 (area 1/16).
    #[test]
    fn a_triangle_density_is_its_uv_area_over_its_world_area() {
        let positions = [
            DVec3::ZERO,
            DVec3::new(2.0, 0.0, 0.0),
            DVec3::new(0.0, 3.0, 0.0),
        ];
        let uvs = [DVec2::ZERO, DVec2::new(0.5, 0.0), DVec2::new(0.0, 0.25)];
        assert!((uv_per_world_area(positions, uvs) - 1.0 / 48.0).abs() < 1e-15);
    }
}
