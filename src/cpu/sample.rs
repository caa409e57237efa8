//! Texture sampling in f64 (docs/surface-colour.md, "Sampling"): the CPU
//! reference's, by the rules the GPU is to follow too.
//!
//! Texel `(i, j)` of a level of `w` x `h` has its centre at
//! `((i + 0.5) / w, (j + 0.5) / h)`. NEAREST takes the texel
//! `(floor(u w), floor(v h))`; LINEAR blends the four texels around
//! `(u w - 0.5, v h - 0.5)` by its fractions. Indices outside the level
//! wrap per axis. The level of detail `lambda` (log2 of texels per pixel)
//! picks the filter: magnification at `lambda <= 0`, else minification,
//! within level 0 or, with mip levels, in the level `nearest(lambda)`
//! (Vulkan's `ceil(lambda + 0.5) - 1`) or blended between `floor(lambda)`
//! and the next by its fraction, `lambda` clamped to the chain.

use glam::{DVec2, DVec3};

use crate::scene::texture::{Filter, MipLevel, Sampler, Texture, Wrap};

/// The texture's colour at `uv` with level of detail `lambda`.
pub fn sample(texture: &Texture, sampler: &Sampler, uv: DVec2, lambda: f64) -> DVec3 {
    if lambda <= 0.0 {
        return filtered(&texture.levels[0], sampler, sampler.magnification, uv);
    }
    let last = (texture.levels.len() - 1) as f64;
    let lambda = lambda.min(last);
    match sampler.mipmap {
        None => filtered(&texture.levels[0], sampler, sampler.minification, uv),
        Some(Filter::Nearest) => {
            let level = ((lambda + 0.5).ceil() - 1.0).clamp(0.0, last) as usize;
            filtered(&texture.levels[level], sampler, sampler.minification, uv)
        }
        Some(Filter::Linear) => {
            let lower = lambda.floor();
            let fraction = lambda - lower;
            let at = |level: f64| {
                let level = &texture.levels[level.min(last) as usize];
                filtered(level, sampler, sampler.minification, uv)
            };
            if fraction == 0.0 {
                at(lower)
            } else {
                at(lower) * (1.0 - fraction) + at(lower + 1.0) * fraction
            }
        }
    }
}

/// One level read with `filter`.
fn filtered(level: &MipLevel, sampler: &Sampler, filter: Filter, uv: DVec2) -> DVec3 {
    let (w, h) = (f64::from(level.width), f64::from(level.height));
    let texel = |i: f64, j: f64| {
        let i = wrap(i, level.width, sampler.wrap_u);
        let j = wrap(j, level.height, sampler.wrap_v);
        DVec3::from_array(level.texel(i, j).map(f64::from))
    };
    match filter {
        Filter::Nearest => texel((uv.x * w).floor(), (uv.y * h).floor()),
        Filter::Linear => {
            let (x, y) = (uv.x * w - 0.5, uv.y * h - 0.5);
            let (i, j) = (x.floor(), y.floor());
            let (a, b) = (x - i, y - j);
            let top = texel(i, j) * (1.0 - a) + texel(i + 1.0, j) * a;
            let bottom = texel(i, j + 1.0) * (1.0 - a) + texel(i + 1.0, j + 1.0) * a;
            top * (1.0 - b) + bottom * b
        }
    }
}

/// The index `i` (an integer, possibly outside `0..size`) wrapped into it.
fn wrap(i: f64, size: u32, mode: Wrap) -> u32 {
    let n = f64::from(size);
    let wrapped = match mode {
        Wrap::Repeat => i.rem_euclid(n),
        Wrap::ClampToEdge => i.clamp(0.0, n - 1.0),
        Wrap::MirroredRepeat => {
            let m = i.rem_euclid(2.0 * n);
            if m >= n {
                2.0 * n - 1.0 - m
            } else {
                m
            }
        }
    };
    wrapped as u32
}
