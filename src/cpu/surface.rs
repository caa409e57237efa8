//! What a ray hit adds to its material's colour: the vertex colour and the
//! pattern at the hit point (docs/lighting-model.md, "Surface colour").
//! The ray tracer's twin of `hit_tint` in `shaders/raytrace.comp.glsl`.

use glam::{DVec2, DVec3};

use super::intersect::{Hit, Primitive};
use crate::rt_scene::RtScene;
use crate::scene::texcoords::{box_uv, plane_uv, sphere_uv};

/// The tint at `hit` (whose point is `p`), and the pattern cell it lies in
/// where its material has a pattern (what `check` compares neighbouring
/// pixels by).
pub fn hit_tint(rt: &RtScene, hit: &Hit, p: DVec3) -> (DVec3, Option<i64>) {
    let mut tint = DVec3::ONE;
    let at = |corners: &[DVec2; 3]| {
        let DVec2 { x: u, y: v } = hit.barycentrics;
        (1.0 - u - v) * corners[0] + u * corners[1] + v * corners[2]
    };
    if let Primitive::Triangle(k) = hit.primitive {
        if let Some(c) = rt.triangle_colors.get(k as usize) {
            let DVec2 { x: u, y: v } = hit.barycentrics;
            tint = (1.0 - u - v) * c[0] + u * c[1] + v * c[2];
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
        Primitive::Triangle(k) => rt.triangle_uvs.get(k as usize).map_or(DVec2::ZERO, at),
    };
    let (color, cell) = pattern.at(uv.x, uv.y);
    (tint * color, Some(cell))
}
