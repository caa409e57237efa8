//! What a surface point adds to its material's colour: the vertex colour
//! and the pattern or image texture at the point (docs/lighting-model.md,
//! "Surface colour"). The ray tracer's twin of `hit_tint` and
//! `hit_pattern` in `shaders/raytrace.comp.glsl`.

use std::f64::consts::PI;

use glam::{DVec2, DVec3};

use super::intersect::{Hit, Primitive};
use super::sample::sample;
use crate::level_of_detail::{cone_lambda, texel_area, triangle_density};
use crate::rt_scene::RtScene;
use crate::scene::texcoords::{box_face_axes, box_uv, plane_uv, sphere_uv};
use crate::scene::{Filter, ImageTexture, Pattern};

/// A pattern's colour at `uv`, and the cell `check` compares neighbouring
/// pixels by where the colour jumps (a checker's cell; an image's texel
/// where it is read unfiltered, NEAREST). An image is read at the level
/// `lambda` gives it.
pub fn pattern_color(
    pattern: &Pattern,
    uv: DVec2,
    lambda: impl FnOnce(&ImageTexture) -> f64,
) -> (DVec3, Option<i64>) {
    match pattern {
        Pattern::Checker { .. } => {
            let (color, cell) = pattern.checker_at(uv.x, uv.y).expect("a checker");
            (color, Some(cell))
        }
        Pattern::Image(image) => {
            let lambda = lambda(image);
            let (u, v) = image.transform.apply(uv.x, uv.y);
            let color = sample(&image.texture, &image.sampler, DVec2::new(u, v), lambda);
            (color, texel_cell(image, u, v, lambda))
        }
    }
}

/// The texel of level 0 that an unfiltered read takes, for an image read
/// with NEAREST where `lambda` puts it; `None` where the read is filtered
/// (its colour continuous in `uv`).
fn texel_cell(image: &ImageTexture, u: f64, v: f64, lambda: f64) -> Option<i64> {
    let sampler = &image.sampler;
    let filter = if lambda <= 0.0 {
        sampler.magnification
    } else {
        sampler.minification
    };
    if filter == Filter::Linear && sampler.mipmap != Some(Filter::Nearest) {
        return None;
    }
    let level = &image.texture.levels[0];
    let i = (u * f64::from(level.width)).floor() as i64;
    let j = (v * f64::from(level.height)).floor() as i64;
    Some((i << 32) ^ (j & 0xffff_ffff))
}

/// The tint at `hit` (whose point is `p`, reached along the unit direction
/// `dir` by a ray cone `cone_width` wide there), and the pattern cell it
/// lies in where that matters (`pattern_color`).
pub fn hit_tint(
    rt: &RtScene,
    hit: &Hit,
    p: DVec3,
    dir: DVec3,
    cone_width: f64,
) -> (DVec3, Option<i64>) {
    let mut tint = DVec3::ONE;
    if let Primitive::Triangle(k) = hit.primitive {
        if let Some(corners) = rt.triangle_colors.get(k as usize) {
            tint = at_barycentrics(corners, hit.barycentrics);
        }
    }
    let Some(pattern) = &rt.materials[hit.material as usize].pattern else {
        return (tint, None);
    };
    let uv = match hit.primitive {
        Primitive::Sphere(_) => sphere_uv(hit.normal),
        Primitive::Plane(i) => {
            let pl = &rt.planes[i as usize];
            plane_uv(p - pl.center, pl.u, pl.v, 2.0 * pl.half_size)
        }
        Primitive::Box { index, face } => {
            let b = &rt.boxes[index as usize];
            box_uv(p - b.center, &b.rotation, b.half_extents, face)
        }
        Primitive::Triangle(k) => rt
            .triangle_uvs
            .get(k as usize)
            .map_or(DVec2::ZERO, |corners| {
                at_barycentrics(corners, hit.barycentrics)
            }),
    };
    let lambda = |image: &ImageTexture| {
        let density = surface_density(rt, hit, image);
        cone_lambda(density, cone_width, hit.normal.dot(dir))
    };
    let (color, cell) = pattern_color(pattern, uv, lambda);
    (tint * color, cell)
}

/// Texels per unit of area of `image` on the surface at `hit`: from the
/// triangle's own area in each space, or from the analytic shape's
/// parameterisation (`scene::texcoords`): a plane of edge `s` spans
/// `1 / s^2` of uv per unit area, a box face `1 / (4 h_u h_v)`, a sphere
/// `1 / (2 pi^2 r^2 sin(theta))` at colatitude `theta` (unbounded at the
/// poles, where the level is then the last).
fn surface_density(rt: &RtScene, hit: &Hit, image: &ImageTexture) -> f64 {
    let texels = texel_area(image);
    match hit.primitive {
        Primitive::Triangle(k) => {
            let uvs = rt.triangle_uvs.get(k as usize).copied().unwrap_or_default();
            triangle_density(image, rt.triangles[k as usize].positions, uvs)
        }
        Primitive::Sphere(i) => {
            let r = rt.spheres[i as usize].radius;
            let sin_theta = (1.0 - hit.normal.y * hit.normal.y).max(0.0).sqrt();
            texels / (2.0 * PI * PI * r * r * sin_theta)
        }
        Primitive::Plane(i) => {
            let size = 2.0 * rt.planes[i as usize].half_size;
            texels / (size * size)
        }
        Primitive::Box { index, face } => {
            let b = &rt.boxes[index as usize];
            let ((_, hu), (_, hv)) = box_face_axes(&b.rotation, b.half_extents, face);
            texels / (4.0 * hu * hv)
        }
    }
}

/// A value given at a triangle's corners, at barycentrics `(u, v)` (the
/// weights of the second and third corners), as the normal is
/// interpolated (`intersect::triangle_normal`).
fn at_barycentrics<T>(corners: &[T; 3], barycentrics: DVec2) -> T
where
    T: Copy + std::ops::Mul<f64, Output = T> + std::ops::Add<Output = T>,
{
    let DVec2 { x: u, y: v } = barycentrics;
    corners[0] * (1.0 - u - v) + corners[1] * u + corners[2] * v
}
