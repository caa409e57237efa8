//! The CPU reference rasterizer: flat, Gouraud and Phong in `f64`, following
//! Vulkan's rules so that it differs from the GPU only by float rounding and
//! the sub-pixel placement of silhouette edges.
//!
//! Conventions it shares with the GPU path: the same tessellation
//! (`scene::tessellate`), camera and projection (`camera.rs`), pixel centres
//! at half-integers, window coordinates snapped to 1/256 pixel (lavapipe's
//! `subPixelPrecisionBits = 8`) for the coverage test, the top-left fill
//! rule, near-plane clipping, a strict "nearer wins" reversed depth test with
//! scene order breaking ties, and no face culling. It shares no shading code
//! with the shaders: the formula is `cpu::lighting`.

use glam::{DVec2, DVec3, DVec4};
use rayon::prelude::*;

use super::clip::{clip_near, ClipVertex, Extras};
use super::lighting::{shade, Surface};
use super::surface::{pattern_color, AT_DISCONTINUITY};
use crate::camera::View;
use crate::level_of_detail::flat_lambda;
use crate::linear_image::LinearImage;
use crate::scene::{tessellate, tessellate_textured, ImageTexture, Interpolation, Material, Scene};
use crate::shading::RasterMode;
use crate::work_counter::WorkCounter;

/// Sub-pixel grid of the coverage test: 1/256 pixel.
const SUBPIXEL: f64 = 256.0;
/// Rows rasterized together by one task.
const BAND_ROWS: u32 = 8;
/// Samples closer than this (in pixels) to the boundary of a visible
/// triangle may be covered differently by the GPU: it snaps f32 window
/// coordinates to 1/256 pixel where this renderer snaps f64 ones, so a vertex
/// can land one grid step (0.0039 px) away, plus f32 rounding of positions
/// (under 0.001 px even at 16384 pixels). 1/64 px is three times their sum.
pub const EDGE_MARGIN: f64 = 1.0 / 64.0;

/// Phong samples whose interpolated normal is shorter than this (vertex
/// normals are unit) are counted with the edge samples: where opposite vertex
/// normals meet, the unit normal flips across a line, and f32 interpolation
/// (relative error ~1e-7) may put a sample within 1e-4 of it on the other
/// side (`assets/hard/bad-normals.toml`).
pub const VANISHING_NORMAL: f64 = 1e-4;

/// The reference image and, per pixel, what it shows.
pub struct CpuRender {
    pub image: LinearImage,
    /// `scene.objects` index per pixel, `None` for the background.
    pub object_ids: Vec<Option<u32>>,
    /// Triangle per pixel, numbered across all objects in scene order.
    pub triangle_ids: Vec<Option<u32>>,
    /// Pixels whose sample lies within `EDGE_MARGIN` of the boundary of a
    /// triangle that is not hidden there, or (Phong) whose interpolated
    /// normal is shorter than `VANISHING_NORMAL`: the only pixels where
    /// another conforming rasterizer may legitimately show something else.
    pub near_edge: Vec<bool>,
}

/// What the coverage test and the edge distance need of a triangle,
/// computed once per triangle rather than per sample.
struct Edges {
    /// Snapped to the sub-pixel grid and ordered so that the interior has
    /// positive edge functions (for coverage).
    snapped: [DVec2; 3],
    /// Whether each snapped edge `snapped[i] -> snapped[i + 1]` is a top or
    /// a left edge.
    top_left: [bool; 3],
    /// `edge(window[0], window[1], window[2])`, twice the signed area.
    window_area: f64,
    /// Whether the triangle is seen from its front, as Vulkan decides it
    /// for `FrontFace::COUNTER_CLOCKWISE`: its snapped area, with the
    /// spec's sign `a = -edge / 2` in framebuffer coordinates (y down), is
    /// positive. The winding that makes `(b - a) x (c - a)` point at the
    /// eye.
    front: bool,
    /// Lengths of the unsnapped edges `window[i] -> window[i + 1]`.
    lengths: [f64; 3],
}

impl Edges {
    /// `None` when the snapped triangle has no area: it covers no sample.
    fn new(window: [DVec2; 3]) -> Option<Self> {
        let [a, b, c] = window.map(snap);
        let snapped_area = edge(a, b, c);
        if snapped_area == 0.0 {
            return None;
        }
        // Orient so the interior has positive edge functions.
        let snapped = if snapped_area > 0.0 {
            [a, b, c]
        } else {
            [a, c, b]
        };
        Some(Edges {
            snapped,
            top_left: [0, 1, 2].map(|i| is_top_left(snapped[i], snapped[(i + 1) % 3])),
            window_area: edge(window[0], window[1], window[2]),
            front: snapped_area < 0.0,
            lengths: [0, 1, 2].map(|i| (window[(i + 1) % 3] - window[i]).length()),
        })
    }
}

/// One screen-space triangle ready to rasterize.
struct Triangle {
    object: u32,
    /// Index of the unclipped triangle across the whole scene.
    primitive: u32,
    /// Window coordinates in pixels, unsnapped (for interpolation).
    window: [DVec2; 3],
    edges: Edges,
    /// Reversed depth `near / w` per vertex.
    depth: [f64; 3],
    /// `1 / w` per vertex, for perspective-correct interpolation.
    inv_w: [f64; 3],
    vertices: [ClipVertex; 3],
    /// Flat mode: the colour of the whole (unclipped) triangle.
    flat_color: DVec3,
    /// Whether its mesh has vertex colours (Phong interpolates them).
    coloured: bool,
    /// Pixel bounds (inclusive), clamped to the image.
    min: (u32, u32),
    max: (u32, u32),
}

impl Triangle {
    /// Seen from its front (`Edges::front`); else the back is lit.
    fn front_facing(&self) -> bool {
        self.edges.front
    }
}

fn window_of(view: &View, clip: DVec4) -> DVec2 {
    let ndc = DVec2::new(clip.x / clip.w, clip.y / clip.w);
    DVec2::new(
        (ndc.x + 1.0) * 0.5 * f64::from(view.width),
        (ndc.y + 1.0) * 0.5 * f64::from(view.height),
    )
}

fn snap(p: DVec2) -> DVec2 {
    (p * SUBPIXEL).round() / SUBPIXEL
}

/// Edge function of (a, b) at p: positive on one side, zero on the line.
fn edge(a: DVec2, b: DVec2, p: DVec2) -> f64 {
    (b.x - a.x) * (p.y - a.y) - (b.y - a.y) * (p.x - a.x)
}

/// Whether the edge a -> b of a triangle whose interior has positive edge
/// functions is a top or a left edge (y grows downward): a sample exactly on
/// such an edge is covered, on any other edge it is not.
fn is_top_left(a: DVec2, b: DVec2) -> bool {
    let d = b - a;
    (d.y == 0.0 && d.x > 0.0) || d.y < 0.0
}

fn setup_triangles(
    scene: &Scene,
    view: &View,
    mode: RasterMode,
    counter: &WorkCounter,
) -> Vec<Triangle> {
    let clip_from_rel = view.clip_from_relative();
    let total: u64 = scene
        .objects
        .iter()
        .map(|o| crate::scene::tessellate::counts(&o.shape).1)
        .sum();
    counter.begin("triangles set up", total);
    let mut triangles = Vec::new();
    let mut next_primitive = 0u32;
    for (object_index, object) in scene.objects.iter().enumerate() {
        let material = &scene.materials[object.material];
        let pattern = material.pattern.as_ref();
        let mesh = if pattern.is_some() {
            tessellate_textured(&object.shape)
        } else {
            tessellate(&object.shape)
        };
        // Gouraud under a pattern: the intensity without the specular term
        // (`unlit_specular`, ks = 0) and the specular term alone (a black
        // surface), which the pattern leaves untinted.
        let unlit_specular = Material {
            ks: 0.0,
            ..material.clone()
        };
        let uv_at = |i: usize| mesh.uvs.get(i).copied().unwrap_or_default();
        // The vertex colour, one where the mesh has none.
        let tint_at = |i: usize| mesh.colors.get(i).copied().unwrap_or(DVec3::ONE);
        let vertices: Vec<ClipVertex> = mesh
            .positions
            .iter()
            .zip(&mesh.normals)
            .enumerate()
            .map(|(i, (p, n))| {
                let rel = *p - view.eye;
                let tint = tint_at(i);
                let normal = n.normalize_or_zero();
                // The front lit with the normal, the back with it negated
                // (`docs/lighting-model.md`, "Which side is lit").
                let shade_side = |surface, normal| {
                    shade(
                        &scene.lighting,
                        &scene.lights,
                        surface,
                        *p,
                        normal,
                        view.eye,
                    )
                };
                let gouraud = |normal: DVec3| match (mode, pattern) {
                    // Gouraud runs the formula at the vertex, with the
                    // vertex's own colour.
                    (RasterMode::Gouraud, None) => {
                        (shade_side(Surface { material, tint }, normal), DVec3::ZERO)
                    }
                    (RasterMode::Gouraud, Some(_)) => (
                        shade_side(
                            Surface {
                                material: &unlit_specular,
                                tint,
                            },
                            normal,
                        ),
                        shade_side(
                            Surface {
                                material,
                                tint: DVec3::ZERO,
                            },
                            normal,
                        ),
                    ),
                    _ => (DVec3::ZERO, DVec3::ZERO),
                };
                let (intensity, specular) = gouraud(normal);
                let (back_intensity, back_specular) = gouraud(-normal);
                let clip = clip_from_rel * rel.extend(1.0);
                // Screen-linear interpolation as the shaders make it
                // (shaders/include/screen_linear.glsl): attributes times w,
                // interpolated perspective-correctly, divided by the same
                // interpolation of w.
                let weight = match scene.lighting.interpolation {
                    Interpolation::Screen => clip.w,
                    Interpolation::Perspective => 1.0,
                };
                ClipVertex {
                    clip,
                    position: rel * weight,
                    normal: *n * weight,
                    intensity: intensity * weight,
                    back_intensity: back_intensity * weight,
                    extra: (!mesh.colors.is_empty() || pattern.is_some()).then(|| {
                        Box::new(Extras {
                            color: tint * weight,
                            specular: specular * weight,
                            back_specular: back_specular * weight,
                            uv: uv_at(i) * weight,
                        })
                    }),
                    weight,
                }
            })
            .collect();
        for (k, tri) in mesh.triangles.iter().enumerate() {
            if k % 65536 == 65535 {
                counter.add(65536);
            }
            let primitive = next_primitive;
            next_primitive += 1;
            let [a, b, c] = tri.map(|i| vertices[i as usize].clone());
            let flat_color = if mode == RasterMode::Flat {
                let [pa, pb, pc] = tri.map(|i| mesh.positions[i as usize]);
                let centroid = (pa + pb + pc) / 3.0;
                let mut normal = (pb - pa).cross(pc - pa).normalize_or_zero();
                // A face seen from behind is lit as its back.
                if normal.dot(view.eye - centroid) < 0.0 {
                    normal = -normal;
                }
                // Flat runs the formula at the centroid, whose colour is
                // the mean of the corners'.
                let [ta, tb, tc] = tri.map(|i| tint_at(i as usize));
                let mut tint = (ta + tb + tc) / 3.0;
                if let Some(pattern) = pattern {
                    let uvs = tri.map(|i| uv_at(i as usize));
                    let uv = (uvs[0] + uvs[1] + uvs[2]) / 3.0;
                    let positions = [pa, pb, pc];
                    let lambda = |image: &_| flat_lambda(image, view, positions, uvs);
                    tint *= pattern_color(pattern, uv, lambda).0;
                }
                shade(
                    &scene.lighting,
                    &scene.lights,
                    Surface { material, tint },
                    centroid,
                    normal,
                    view.eye,
                )
            } else {
                DVec3::ZERO
            };
            let polygon = clip_near([a, b, c], view.near);
            for k in 1..polygon.len().saturating_sub(1) {
                let verts = [
                    polygon[0].clone(),
                    polygon[k].clone(),
                    polygon[k + 1].clone(),
                ];
                let ids = (object_index as u32, primitive);
                let one_sample = !scene.render.msaa.is_multisampled();
                if let Some(mut t) = screen_triangle(view, ids, verts, flat_color, one_sample) {
                    t.coloured = !mesh.colors.is_empty();
                    triangles.push(t);
                }
            }
        }
        counter.add(mesh.triangles.len() as u64 % 65536);
    }
    triangles
}

fn screen_triangle(
    view: &View,
    (object, primitive): (u32, u32),
    vertices: [ClipVertex; 3],
    flat_color: DVec3,
    one_sample: bool,
) -> Option<Triangle> {
    let window = [0, 1, 2].map(|k| window_of(view, vertices[k].clip));
    let edges = Edges::new(window)?;
    let snapped = edges.snapped;
    let lo = snapped[0].min(snapped[1]).min(snapped[2]);
    let hi = snapped[0].max(snapped[1]).max(snapped[2]);
    let (w, h) = (f64::from(view.width), f64::from(view.height));
    if hi.x < 0.0 || hi.y < 0.0 || lo.x > w || lo.y > h {
        return None;
    }
    // Pixels whose centre (x + 0.5) can fall inside [lo, hi]; with several
    // samples, those whose area [x, x + 1) meets it, as any sample may.
    let (before, after) = if one_sample { (0.5, 0.5) } else { (1.0, 0.0) };
    let first = |v: f64| (v - before).ceil().max(0.0) as u32;
    let last = |v: f64, n: u32| ((v - after).floor().max(-1.0) as i64).min(i64::from(n) - 1);
    let (x1, y1) = (last(hi.x, view.width), last(hi.y, view.height));
    if x1 < 0 || y1 < 0 {
        return None;
    }
    Some(Triangle {
        object,
        primitive,
        window,
        edges,
        depth: [0, 1, 2].map(|k| vertices[k].clip.z / vertices[k].clip.w),
        inv_w: [0, 1, 2].map(|k| 1.0 / vertices[k].clip.w),
        vertices,
        flat_color,
        coloured: false,
        min: (first(lo.x), first(lo.y)),
        max: (x1 as u32, y1 as u32),
    })
}

/// Screen-space barycentrics of `p` if the sample is covered.
fn coverage(t: &Triangle, p: DVec2) -> Option<[f64; 3]> {
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
fn barycentrics(t: &Triangle, p: DVec2) -> [f64; 3] {
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
fn boundary_distance(t: &Triangle, p: DVec2) -> (f64, [f64; 3]) {
    let sign = t.edges.window_area.signum();
    let distance = (0..3)
        .map(|i| sign * edge(t.window[i], t.window[(i + 1) % 3], p) / t.edges.lengths[i])
        .fold(f64::INFINITY, f64::min);
    (distance, barycentrics(t, p))
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

fn shade_sample(
    scene: &Scene,
    view: &View,
    mode: RasterMode,
    t: &Triangle,
    (p, bary): (DVec2, [f64; 3]),
) -> Sample {
    // Perspective-correct weights; with screen-linear interpolation the
    // attributes carry a factor w that `weight` divides back out.
    let (weights, scale) = interpolation_weights(t, bary);
    let mix = |f: fn(&ClipVertex) -> DVec3| {
        (f(&t.vertices[0]) * weights[0]
            + f(&t.vertices[1]) * weights[1]
            + f(&t.vertices[2]) * weights[2])
            * scale
    };
    // The colour attributes, where the vertices carry them.
    let mix_extra = |f: fn(&Extras) -> DVec3| {
        let at = |k: usize| t.vertices[k].extra.as_deref().map_or(DVec3::ZERO, f);
        (at(0) * weights[0] + at(1) * weights[1] + at(2) * weights[2]) * scale
    };
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
            color: match (patterned, t.front_facing()) {
                (None, true) => mix(|v| v.intensity),
                (None, false) => mix(|v| v.back_intensity),
                (Some((texel, _)), true) => {
                    texel * mix(|v| v.intensity) + mix_extra(|e| e.specular)
                }
                (Some((texel, _)), false) => {
                    texel * mix(|v| v.back_intensity) + mix_extra(|e| e.back_specular)
                }
            },
            vanishing_normal: false,
            cell,
        },
        RasterMode::Phong => {
            let position = mix(|v| v.position) + view.eye;
            // Seen from behind, the back: the normal negated.
            let side = if t.front_facing() { 1.0 } else { -1.0 };
            let interpolated = side * mix(|v| v.normal);
            let normal = interpolated.normalize_or_zero();
            // Not interpolated where there are none: weights that sum to 1
            // only up to rounding would move an uncoloured surface's colour.
            let mut tint = if t.coloured {
                mix_extra(|e| e.color)
            } else {
                DVec3::ONE
            };
            if let Some((texel, _)) = patterned {
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
            Sample {
                color,
                vanishing_normal: interpolated.length() < VANISHING_NORMAL,
                cell,
            }
        }
    }
}

/// `color` with every channel below 0 made 0 (NaN kept, to be counted):
/// shaded once per pixel, a centre outside the triangle extrapolates the
/// inputs, and light below 0 there counts as none (docs/lighting-model.md,
/// "Samples per pixel"; the GPU's `AT_LEAST_ZERO`).
fn at_least_zero(color: DVec3) -> DVec3 {
    let clamp = |c: f64| if c < 0.0 { 0.0 } else { c };
    DVec3::new(clamp(color.x), clamp(color.y), clamp(color.z))
}

/// What one sample shows.
#[derive(Clone)]
struct Sample {
    color: DVec3,
    /// Phong: the interpolated normal is shorter than `VANISHING_NORMAL`.
    vanishing_normal: bool,
    /// The pattern cell the sample lies in, if its surface has a pattern.
    cell: Option<i64>,
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
fn mark_steep_intensities(image: &LinearImage, near_edge: &mut [bool]) {
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
fn mark_cell_edges(width: usize, height: usize, cells: &[Option<i64>], near_edge: &mut [bool]) {
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

/// The rows one task rasterizes.
struct Band {
    pixels: Vec<[f32; 3]>,
    object_ids: Vec<Option<u32>>,
    triangle_ids: Vec<Option<u32>>,
    near_edge: Vec<bool>,
    cells: Vec<Option<i64>>,
}

/// Renders `scene` at its image size in `mode`, with its samples per
/// pixel (`scene.render.msaa`, a count with standard locations:
/// [`crate::msaa::positions`]): each sample covered and depth tested on its
/// own, shaded once per pixel at its centre (or, per sample, at its own
/// position), and the samples' linear values averaged.
pub fn render(scene: &Scene, mode: RasterMode) -> CpuRender {
    render_counted(scene, mode, &WorkCounter::default())
}

/// [`render`], counting its bands of rows into `counter` as they finish.
pub fn render_counted(scene: &Scene, mode: RasterMode, counter: &WorkCounter) -> CpuRender {
    let (width, height) = (scene.image.width, scene.image.height);
    let view = View::new(scene, width, height);
    let triangles = setup_triangles(scene, &view, mode, counter);
    let background = scene.image.background;
    let msaa = scene.render.msaa;
    let offsets = msaa
        .positions()
        .expect("render::render_cpu refuses counts without standard locations");
    let n = offsets.len();
    let at = |x: u32, y: u32, s: usize| {
        let (ox, oy) = offsets[s];
        DVec2::new(f64::from(x) + ox, f64::from(y) + oy)
    };
    let per_sample = msaa.per_sample && n > 1;
    counter.begin("bands of rows", u64::from(height.div_ceil(BAND_ROWS)));
    let bands: Vec<Band> = (0..height.div_ceil(BAND_ROWS))
        .into_par_iter()
        .map(|band| {
            let y0 = band * BAND_ROWS;
            let y1 = (y0 + BAND_ROWS).min(height);
            let count = ((y1 - y0) * width) as usize;
            // Per sample: pixel i's sample s at i * n + s.
            let mut color = vec![background; count * n];
            let mut ids = vec![None; count * n];
            let mut tri_ids = vec![None; count * n];
            let mut vanishing = vec![false; count * n];
            let mut cells = vec![None; count * n];
            // Reversed depth: cleared to 0, nearer is greater.
            let mut depth = vec![0.0f64; count * n];
            for t in &triangles {
                if t.max.1 < y0 || t.min.1 >= y1 {
                    continue;
                }
                for y in t.min.1.max(y0)..=t.max.1.min(y1 - 1) {
                    for x in t.min.0..=t.max.0 {
                        let i = ((y - y0) * width + x) as usize;
                        // Once per pixel: shaded at the centre (extrapolated
                        // where the triangle misses it), when it wins a sample.
                        let mut pixel_shade: Option<Sample> = None;
                        for s in 0..n {
                            let p = at(x, y, s);
                            let Some(bary) = coverage(t, p) else { continue };
                            let z =
                                bary[0] * t.depth[0] + bary[1] * t.depth[1] + bary[2] * t.depth[2];
                            let k = i * n + s;
                            if z <= depth[k] {
                                continue;
                            }
                            depth[k] = z;
                            ids[k] = Some(t.object);
                            tri_ids[k] = Some(t.primitive);
                            let sample = if per_sample || n == 1 {
                                shade_sample(scene, &view, mode, t, (p, bary))
                            } else {
                                pixel_shade
                                    .get_or_insert_with(|| {
                                        let centre =
                                            DVec2::new(f64::from(x) + 0.5, f64::from(y) + 0.5);
                                        let mut shaded = shade_sample(
                                            scene,
                                            &view,
                                            mode,
                                            t,
                                            (centre, barycentrics(t, centre)),
                                        );
                                        shaded.color = at_least_zero(shaded.color);
                                        shaded
                                    })
                                    .clone()
                            };
                            (color[k], vanishing[k]) = (sample.color, sample.vanishing_normal);
                            cells[k] = sample.cell;
                        }
                    }
                }
            }
            // Second pass, against the final depth: mark pixels with a
            // sample near the boundary of a triangle not behind it there.
            let mut near_edge: Vec<bool> = (0..count)
                .map(|i| vanishing[i * n..(i + 1) * n].iter().any(|&v| v))
                .collect();
            for t in &triangles {
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
                            let (distance, bary) = boundary_distance(t, at(x, y, s));
                            let z =
                                bary[0] * t.depth[0] + bary[1] * t.depth[1] + bary[2] * t.depth[2];
                            distance.abs() <= EDGE_MARGIN && z >= depth[i * n + s] * (1.0 - 1e-9)
                        });
                    }
                }
            }
            // The resolve: the mean of the samples' linear values. A pixel
            // whose samples show different pattern cells is an edge too.
            let mut pixel_cells = Vec::with_capacity(count);
            for i in 0..count {
                let own = &cells[i * n..(i + 1) * n];
                if own.iter().any(|c| *c != own[0]) {
                    near_edge[i] = true;
                }
                pixel_cells.push(own[0]);
            }
            let pixels = (0..count)
                .map(|i| {
                    let sum = color[i * n..(i + 1) * n]
                        .iter()
                        .fold(DVec3::ZERO, |a, c| a + *c);
                    (sum / n as f64).as_vec3().to_array()
                })
                .collect();
            counter.add(1);
            Band {
                pixels,
                object_ids: (0..count).map(|i| ids[i * n]).collect(),
                triangle_ids: (0..count).map(|i| tri_ids[i * n]).collect(),
                near_edge,
                cells: pixel_cells,
            }
        })
        .collect();
    let mut image = LinearImage {
        width,
        height,
        pixels: Vec::with_capacity((width * height) as usize),
    };
    let mut object_ids = Vec::with_capacity((width * height) as usize);
    let mut triangle_ids = Vec::with_capacity((width * height) as usize);
    let mut near_edge = Vec::with_capacity((width * height) as usize);
    let mut cells = Vec::with_capacity((width * height) as usize);
    for band in bands {
        image.pixels.extend(band.pixels);
        object_ids.extend(band.object_ids);
        triangle_ids.extend(band.triangle_ids);
        near_edge.extend(band.near_edge);
        cells.extend(band.cells);
    }
    mark_cell_edges(width as usize, height as usize, &cells, &mut near_edge);
    if mode == RasterMode::Gouraud {
        mark_steep_intensities(&image, &mut near_edge);
    }
    CpuRender {
        image,
        object_ids,
        triangle_ids,
        near_edge,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

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
