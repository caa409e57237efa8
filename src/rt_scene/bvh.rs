//! The bounding volume hierarchy over the scene's triangles, and how both
//! tracers widen its `f32` boxes before testing rays against them.

use glam::{DVec3, Vec3A};
use obvhs::bvh2::Bvh2;
use obvhs::triangle::Triangle;

use super::primitives::RtTriangle;

/// The tree over `triangles`, built from their f32-rounded positions.
pub(super) fn build_bvh(triangles: &[RtTriangle]) -> Bvh2 {
    build_from(&f32_triangles(triangles))
}

/// The triangles' corners rounded to f32, as the tree is built over them.
pub(super) fn f32_triangles(triangles: &[RtTriangle]) -> Vec<Triangle> {
    triangles
        .iter()
        .map(|t| {
            let [v0, v1, v2] = t.positions.map(|p| Vec3A::from(p.as_vec3()));
            Triangle { v0, v1, v2 }
        })
        .collect()
}

/// The tree over f32 triangles (empty for none).
pub(super) fn build_from(tris: &[Triangle]) -> Bvh2 {
    if tris.is_empty() {
        return Bvh2::default();
    }
    let mut build_time = std::time::Duration::default();
    obvhs::bvh2::builder::build_bvh2_from_tris(
        tris,
        obvhs::BvhBuildParams::medium_build(),
        &mut build_time,
    )
}

/// Relative widening of the BVH's boxes: f32 rounding moves a coordinate by
/// at most 6e-8 of its magnitude, so 1e-5 leaves a factor of 100.
pub const BOX_WIDENING: f64 = 1e-5;

/// A BVH box moved outward by `BOX_WIDENING * max(1, |x|)` per coordinate.
/// The CPU needs it so that no f64 triangle pokes out of a box built from
/// its f32 rounding; the GPU so that a ray along an edge shared by two
/// boxes, which lies on both boxes' faces, is not rejected by both slab
/// tests' rounding (`tests/gpu/hard_cases.rs`, rays along shared edges).
pub fn widened_box(min: DVec3, max: DVec3) -> (DVec3, DVec3) {
    let margin = |x: DVec3| BOX_WIDENING * x.abs().max(DVec3::ONE);
    (min - margin(min), max + margin(max))
}
