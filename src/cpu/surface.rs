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
    let (color, cell) = pattern.at(uv.x, uv.y);
    (tint * color, Some(cell))
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
