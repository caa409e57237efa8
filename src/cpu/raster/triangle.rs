//! A triangle in window coordinates, ready to rasterize: its corners
//! snapped to lavapipe's sub-pixel grid for the coverage test, with what
//! interpolation needs per vertex and the pixels it may cover.

use glam::{DVec2, DVec3, DVec4};

use crate::camera::View;
use crate::cpu::clip::ClipVertex;

/// Sub-pixel grid of the coverage test: 1/256 pixel.
const SUBPIXEL: f64 = 256.0;

/// What the coverage test and the edge distance need of a triangle,
/// computed once per triangle rather than per sample.
pub(super) struct Edges {
    /// Snapped to the sub-pixel grid and ordered so that the interior has
    /// positive edge functions (for coverage).
    pub(super) snapped: [DVec2; 3],
    /// Whether each snapped edge `snapped[i] -> snapped[i + 1]` is a top or
    /// a left edge.
    pub(super) top_left: [bool; 3],
    /// `edge(window[0], window[1], window[2])`, twice the signed area.
    pub(super) window_area: f64,
    /// Whether the triangle is seen from its front, as Vulkan decides it
    /// for `FrontFace::COUNTER_CLOCKWISE`: its snapped area, with the
    /// spec's sign `a = -edge / 2` in framebuffer coordinates (y down), is
    /// positive. The winding that makes `(b - a) x (c - a)` point at the
    /// eye.
    pub(super) front: bool,
    /// Lengths of the unsnapped edges `window[i] -> window[i + 1]`.
    pub(super) lengths: [f64; 3],
}

impl Edges {
    /// `None` when the snapped triangle has no area: it covers no sample.
    pub(super) fn new(window: [DVec2; 3]) -> Option<Self> {
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
pub(super) struct Triangle {
    pub(super) object: u32,
    /// Index of the unclipped triangle across the whole scene.
    pub(super) primitive: u32,
    /// Window coordinates in pixels, unsnapped (for interpolation).
    pub(super) window: [DVec2; 3],
    pub(super) edges: Edges,
    /// Reversed depth `near / w` per vertex.
    pub(super) depth: [f64; 3],
    /// `1 / w` per vertex, for perspective-correct interpolation.
    pub(super) inv_w: [f64; 3],
    pub(super) vertices: [ClipVertex; 3],
    /// Flat mode: the colour of the whole (unclipped) triangle.
    pub(super) flat_color: DVec3,
    /// Whether its mesh has vertex colours (Phong interpolates them).
    pub(super) coloured: bool,
    /// Pixel bounds (inclusive), clamped to the image.
    pub(super) min: (u32, u32),
    pub(super) max: (u32, u32),
}

impl Triangle {
    /// Seen from its front (`Edges::front`); else the back is lit.
    pub(super) fn front_facing(&self) -> bool {
        self.edges.front
    }

    /// The reversed depth at screen barycentrics `bary`.
    pub(super) fn depth_at(&self, bary: [f64; 3]) -> f64 {
        bary[0] * self.depth[0] + bary[1] * self.depth[1] + bary[2] * self.depth[2]
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
pub(super) fn edge(a: DVec2, b: DVec2, p: DVec2) -> f64 {
    (b.x - a.x) * (p.y - a.y) - (b.y - a.y) * (p.x - a.x)
}

/// Whether the edge a -> b of a triangle whose interior has positive edge
/// functions is a top or a left edge (y grows downward): a sample exactly on
/// such an edge is covered, on any other edge it is not.
fn is_top_left(a: DVec2, b: DVec2) -> bool {
    let d = b - a;
    (d.y == 0.0 && d.x > 0.0) || d.y < 0.0
}

/// The clipped triangle `vertices` of scene triangle `primitive` (of
/// object `object`) in window coordinates, with the pixels it may cover;
/// `None` when it covers no sample of the image.
pub(super) fn screen_triangle(
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
