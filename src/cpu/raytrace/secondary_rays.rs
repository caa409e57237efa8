//! Where a hit's secondary rays start and go: off the surface by an
//! epsilon that scales with the scene, reflected about the normal or
//! refracted through it; and the side of a surface the local model lights.

use glam::DVec3;

use super::path_signature::RayKind;
use crate::scene::Material;

/// `eps = 1e-4 * max(|p|_max, |o|_max)`: the offset of a secondary ray's
/// origin from `p`, found by a ray from `o`. The hit's rounding grows with
/// both (`p = o + t d`, and each test subtracts `o`), and with nothing
/// else: a scene a millionth of a unit across gets offsets a millionth as
/// large (`assets/hard/mesh-scale-1e-6.toml`).
pub fn offset_epsilon(p: DVec3, o: DVec3) -> f64 {
    1e-4 * p.abs().max_element().max(o.abs().max_element())
}

/// The normal the local model lights a hit with: the side the ray arrives
/// on. Seen from behind its geometric normal (`Ng·d > 0`: the inside of a
/// sphere or a box, the underside of a plane, the back of a triangle) a
/// surface is lit as its back, with the shading normal negated
/// (`docs/lighting-model.md`, "Which side is lit"). Reflection and
/// refraction keep the outward normal, which says whether a ray enters.
pub fn facing_normal(normal: DVec3, geometric_normal: DVec3, d: DVec3) -> DVec3 {
    if geometric_normal.dot(d) > 0.0 {
        -normal
    } else {
        normal
    }
}

/// The origin of a secondary ray leaving `p` (found by a ray from `o`) in
/// direction `dir`: pushed by `eps` along the geometric normal to the side
/// `dir` goes (`Ng·dir = 0` counts as the front side).
pub fn offset_origin(p: DVec3, o: DVec3, geometric_normal: DVec3, dir: DVec3) -> DVec3 {
    let s = if geometric_normal.dot(dir) < 0.0 {
        -1.0
    } else {
        1.0
    };
    p + s * offset_epsilon(p, o) * geometric_normal
}

/// The children of a hit at normal `n` (outward, nonzero) of a ray along
/// `d` whose weight is `weight` (RGB): reflected, then refracted (so the
/// refracted one is traced first), each `(direction, weight, kind)`.
pub(crate) fn children(
    d: DVec3,
    n: DVec3,
    material: &Material,
    weight: DVec3,
) -> [Option<(DVec3, DVec3, RayKind)>; 2] {
    let (kr, kt) = (material.kr, material.kt);
    let mut reflected_weight = (kr > 0.0).then_some(weight * kr);
    let mut refracted = None;
    if kt > 0.0 {
        let (normal, eta) = if n.dot(d) < 0.0 {
            (n, 1.0 / material.ior)
        } else {
            (-n, material.ior)
        };
        let cos_i = -normal.dot(d);
        // sin²(i) from the direction's part along the surface, not as
        // 1 - cos²(i), which near normal incidence is a rounding
        // error that an index of 1e3 multiplies by 1e6
        // (assets/hard/glass-ior-1e3.toml).
        let along = d + cos_i * normal;
        let k = 1.0 - eta * eta * along.length_squared();
        if k < 0.0 {
            reflected_weight = Some(weight * (kr + kt));
        } else {
            let dir = (eta * along - k.sqrt() * normal).normalize();
            refracted = Some((dir, weight * kt));
        }
    }
    [
        reflected_weight.map(|w| (d - 2.0 * d.dot(n) * n, w, RayKind::Reflected)),
        refracted.map(|(dir, w)| (dir, w, RayKind::Refracted)),
    ]
}
