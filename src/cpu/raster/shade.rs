//! Shading one sample of a triangle: the mode's formula at the sample's
//! interpolated attributes, with the pattern at its texture coordinates
//! (at the level of detail the fragment shader's quad derivatives give).

use glam::{DVec2, DVec3};

use super::coverage::barycentrics;
use super::triangle::Triangle;
use crate::camera::View;
use crate::cpu::clip::{ClipVertex, Extras};
use crate::cpu::lighting::{shade, Surface};
use crate::cpu::surface::pattern_color;
use crate::scene::{ImageTexture, Material, Scene};
use crate::shading::RasterMode;

/// Phong samples whose interpolated normal is shorter than this (vertex
/// normals are unit) are counted with the edge samples: where opposite vertex
/// normals meet, the unit normal flips across a line, and f32 interpolation
/// (relative error ~1e-7) may put a sample within 1e-4 of it on the other
/// side (`assets/hard/bad-normals.toml`).
pub const VANISHING_NORMAL: f64 = 1e-4;

/// What one sample shows.
#[derive(Clone)]
pub(super) struct Sample {
    pub(super) color: DVec3,
    /// Phong: the interpolated normal is shorter than `VANISHING_NORMAL`.
    pub(super) vanishing_normal: bool,
    /// The pattern cell the sample lies in, if its surface has a pattern.
    pub(super) cell: Option<i64>,
}

/// The interpolation weights of the sample with screen barycentrics
/// `bary`: perspective-correct, and the factor that divides screen-linear
/// interpolation's `w` back out (1 otherwise).
fn interpolation_weights(t: &Triangle, bary: [f64; 3]) -> ([f64; 3], f64) {
    let w = [
        bary[0] * t.inv_w[0],
        bary[1] * t.inv_w[1],
        bary[2] * t.inv_w[2],
    ];
    let sum = w[0] + w[1] + w[2];
    let weights = [w[0] / sum, w[1] / sum, w[2] / sum];
    let scale = 1.0
        / (t.vertices[0].weight * weights[0]
            + t.vertices[1].weight * weights[1]
            + t.vertices[2].weight * weights[2]);
    (weights, scale)
}

/// The texture coordinates interpolated at window point `p` (extrapolated
/// outside the triangle, as a helper invocation of the GPU's quad does).
fn uv_at_point(t: &Triangle, p: DVec2) -> DVec2 {
    let (weights, scale) = interpolation_weights(t, barycentrics(t, p));
    let at = |k: usize| t.vertices[k].extra.as_deref().map_or(DVec2::ZERO, |e| e.uv);
    (at(0) * weights[0] + at(1) * weights[1] + at(2) * weights[2]) * scale
}

/// The level of detail of `image` at the sample `p` as the fragment shader
/// takes it (`shaders/include/texture.glsl`, `raster_lambda`): fine
/// derivatives over the sample's 2 x 2 quad (the difference along its row
/// and along its column between the quad's two pixel centres), scaled by
/// the transform and level 0's size; `lambda = log2` of the longer.
fn raster_lambda(t: &Triangle, p: DVec2, image: &ImageTexture) -> f64 {
    // The quad's first pixel, and where in its pixel the sample lies: a
    // sample shaded on its own (per-sample MSAA) differs from the same
    // sample of the quad's other pixels.
    let (x, y) = (p.x.floor(), p.y.floor());
    let (fx, fy) = (p.x - x, p.y - y);
    let (qx, qy) = (x - x.rem_euclid(2.0) + fx, y - y.rem_euclid(2.0) + fy);
    let dx = uv_at_point(t, DVec2::new(qx + 1.0, p.y)) - uv_at_point(t, DVec2::new(qx, p.y));
    let dy = uv_at_point(t, DVec2::new(p.x, qy + 1.0)) - uv_at_point(t, DVec2::new(p.x, qy));
    let m = &image.transform.0;
    let level = &image.texture.levels[0];
    let size = DVec2::new(f64::from(level.width), f64::from(level.height));
    let texels = |d: DVec2| DVec2::new(m[0] * d.x + m[1] * d.y, m[3] * d.x + m[4] * d.y) * size;
    let rho = texels(dx).length().max(texels(dy).length());
    rho.log2()
}

/// A sample's interpolation weights over its triangle's vertices.
struct Weights<'a> {
    t: &'a Triangle,
    weights: [f64; 3],
    scale: f64,
}

impl<'a> Weights<'a> {
    fn new(t: &'a Triangle, bary: [f64; 3]) -> Self {
        // Perspective-correct weights; with screen-linear interpolation the
        // attributes carry a factor w that `weight` divides back out.
        let (weights, scale) = interpolation_weights(t, bary);
        Weights { t, weights, scale }
    }

    /// A vertex attribute at the sample.
    fn mix(&self, f: fn(&ClipVertex) -> DVec3) -> DVec3 {
        let (v, w) = (&self.t.vertices, self.weights);
        (f(&v[0]) * w[0] + f(&v[1]) * w[1] + f(&v[2]) * w[2]) * self.scale
    }

    /// A colour attribute at the sample, where the vertices carry them.
    fn mix_extra(&self, f: fn(&Extras) -> DVec3) -> DVec3 {
        let at = |k: usize| self.t.vertices[k].extra.as_deref().map_or(DVec3::ZERO, f);
        let w = self.weights;
        (at(0) * w[0] + at(1) * w[1] + at(2) * w[2]) * self.scale
    }
}

/// What sample `p` (screen barycentrics `bary`) of `t` shows in `mode`.
pub(super) fn shade_sample(
    scene: &Scene,
    view: &View,
    mode: RasterMode,
    t: &Triangle,
    (p, bary): (DVec2, [f64; 3]),
) -> Sample {
    let weights = Weights::new(t, bary);
    let material = &scene.materials[scene.objects[t.object as usize].material];
    // The pattern at the sample's interpolated texture coordinates (flat
    // shading's is in its triangle's colour).
    let per_sample = mode != RasterMode::Flat;
    let patterned = material
        .pattern
        .as_ref()
        .filter(|_| per_sample)
        .map(|pattern| {
            pattern_color(pattern, uv_at_point(t, p), |image| {
                raster_lambda(t, p, image)
            })
        });
    let cell = patterned.and_then(|(_, cell)| cell);
    match mode {
        RasterMode::Flat => Sample {
            color: t.flat_color,
            vanishing_normal: false,
            cell: None,
        },
        RasterMode::Gouraud => Sample {
            color: gouraud_color(&weights, patterned.map(|(texel, _)| texel)),
            vanishing_normal: false,
            cell,
        },
        RasterMode::Phong => {
            let texel = patterned.map(|(texel, _)| texel);
            let (color, vanishing_normal) = phong_color(scene, view, material, &weights, texel);
            Sample {
                color,
                vanishing_normal,
                cell,
            }
        }
    }
}

/// Gouraud: the vertices' intensities of the side seen, tinted by the
/// pattern's `texel` (the specular term untinted).
fn gouraud_color(weights: &Weights, texel: Option<DVec3>) -> DVec3 {
    match (texel, weights.t.front_facing()) {
        (None, true) => weights.mix(|v| v.intensity),
        (None, false) => weights.mix(|v| v.back_intensity),
        (Some(texel), true) => {
            texel * weights.mix(|v| v.intensity) + weights.mix_extra(|e| e.specular)
        }
        (Some(texel), false) => {
            texel * weights.mix(|v| v.back_intensity) + weights.mix_extra(|e| e.back_specular)
        }
    }
}

/// Phong: the formula at the interpolated position and normal, and
/// whether that normal vanishes (`VANISHING_NORMAL`).
fn phong_color(
    scene: &Scene,
    view: &View,
    material: &Material,
    weights: &Weights,
    texel: Option<DVec3>,
) -> (DVec3, bool) {
    let t = weights.t;
    let position = weights.mix(|v| v.position) + view.eye;
    // Seen from behind, the back: the normal negated.
    let side = if t.front_facing() { 1.0 } else { -1.0 };
    let interpolated = side * weights.mix(|v| v.normal);
    let normal = interpolated.normalize_or_zero();
    // Not interpolated where there are none: weights that sum to 1
    // only up to rounding would move an uncoloured surface's colour.
    let mut tint = if t.coloured {
        weights.mix_extra(|e| e.color)
    } else {
        DVec3::ONE
    };
    if let Some(texel) = texel {
        tint *= texel;
    }
    let color = shade(
        &scene.lighting,
        &scene.lights,
        Surface { material, tint },
        position,
        normal,
        view.eye,
    );
    (color, interpolated.length() < VANISHING_NORMAL)
}

/// `color` with every channel below 0 made 0 (NaN kept, to be counted):
/// shaded once per pixel, a centre outside the triangle extrapolates the
/// inputs, and light below 0 there counts as none (docs/lighting-model.md,
pub(super) fn at_least_zero(color: DVec3) -> DVec3 {
    let clamp = |c: f64| if c < 0.0 { 0.0 } else { c };
    DVec3::new(clamp(color.x), clamp(color.y), clamp(color.z))
}
