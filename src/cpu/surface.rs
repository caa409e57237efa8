//! What a surface point adds to its material's colour: the vertex colour
//! and the pattern or image texture at the point (docs/lighting-model.md,
//! "Surface colour"). The ray tracer's twin of `hit_tint` and
//! `hit_pattern` in `shaders/raytrace.comp.glsl`.

use std::f64::consts::PI;

use glam::{DVec2, DVec3};

use super::intersect::Hit;
use super::sample::sample;
use crate::level_of_detail::{cone_lambda, texel_area, triangle_density};
use crate::rt_scene::{Primitive, RtScene};
use crate::scene::texcoords::{box_face_axes, box_uv, plane_uv, sphere_uv};
use crate::scene::{Filter, ImageTexture, Pattern};

/// The cell of a sample that lies on a jump of an image's colour: within
/// `DISCONTINUITY_MARGIN` of a texel edge where the texture is read
/// unfiltered, or of a switch of level or filter. There another renderer's
/// rounding may read the other side; `check` measures such samples apart.
pub const AT_DISCONTINUITY: i64 = i64::MIN;

/// How near (in texels, or in levels of detail) a sample must be to a jump
/// of colour to count as on it: the GPU's f32 texture coordinates are off
/// by about 1e-7 of their value, some 1e-5 texel for a texture of 1024
/// repeated 100 times, and its level by as much again; 1e-3 is 100 times
/// that.
pub const DISCONTINUITY_MARGIN: f64 = 1e-3;

/// A pattern's colour at `uv`, and the cell `check` compares neighbouring
/// pixels by where the colour jumps: a checker's cell; for an image,
/// `AT_DISCONTINUITY` where the sample lies on a jump (`on_a_jump`), else
/// none. An image is read at the level `lambda` gives it.
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
            let cell = on_a_jump(image, u, v, lambda).then_some(AT_DISCONTINUITY);
            (color, cell)
        }
    }
}

/// Whether an image's colour jumps within `DISCONTINUITY_MARGIN` of the
/// sample: at a texel edge of a level read with NEAREST, where the level
/// read with NEAREST between levels switches, or at `lambda = 0` where
/// magnification and minification filter differently.
fn on_a_jump(image: &ImageTexture, u: f64, v: f64, lambda: f64) -> bool {
    let sampler = &image.sampler;
    let near_integer = |x: f64| (x - x.round()).abs() < DISCONTINUITY_MARGIN;
    let last = (image.texture.levels.len() - 1) as f64;
    let (filter, level) = if lambda <= 0.0 {
        (sampler.magnification, 0.0)
    } else {
        let lambda = lambda.min(last);
        match sampler.mipmap {
            None => (sampler.minification, 0.0),
            Some(Filter::Nearest) => {
                if near_integer(lambda + 0.5) && lambda < last {
                    return true;
                }
                (
                    sampler.minification,
                    ((lambda + 0.5).ceil() - 1.0).clamp(0.0, last),
                )
            }
            // Blended levels are continuous in lambda, but a NEAREST read
            // of either jumps at that level's texel edges.
            Some(Filter::Linear) => (sampler.minification, lambda.floor()),
        }
    };
    if sampler.magnification != sampler.minification && lambda.abs() < DISCONTINUITY_MARGIN {
        return true;
    }
    if filter == Filter::Linear {
        return false;
    }
    let blended = sampler.mipmap == Some(Filter::Linear) && lambda > 0.0;
    let next = if blended {
        (level + 1.0).min(last)
    } else {
        level
    };
    [level, next].into_iter().any(|level| {
        let size = &image.texture.levels[level as usize];
        near_integer(u * f64::from(size.width)) || near_integer(v * f64::from(size.height))
    })
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
        Primitive::Sphere(_) | Primitive::HugeSphere(_) => sphere_uv(hit.normal),
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
        Primitive::Sphere(_) | Primitive::HugeSphere(_) => {
            let r = rt.sphere_radius(hit.primitive);
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
