//! Which objects the raster modes may draw with back faces culled: those
//! whose back faces cannot show. Culling them halves the triangles lavapipe
//! rasterizes and depth-tests for a closed object (and the fragments it
//! shades before a nearer face overwrites them), and changes no pixel: the
//! CPU reference, which culls nothing, gives the same image.
//!
//! A back face cannot show when the object is a closed surface wound
//! counter-clockwise seen from outside (every edge shared by exactly two
//! triangles, in opposite directions, and a positive enclosed volume), and
//! its bounding box lies wholly beyond the near plane: then no part of it
//! is clipped (a clipped closed object shows its inside through the cut),
//! and the eye is outside it (an eye inside the box would have a corner of
//! it behind). Planes and open meshes fail the first test and keep both
//! sides, as in the ray tracer.

use glam::DVec3;
use rayon::slice::ParallelSliceMut;

use crate::camera::View;
use crate::scene::TriangleMesh;

/// Vertices this close, relative to the object's largest extent, are one.
/// A crack narrower than that (a thousandth of a pixel for an object
/// filling a 10000-pixel image) could let a pixel centre on a triangle edge
/// see a back face that culling removes: an edge pixel, where `check`
/// allows differences, and never seen in the scenes tried.
const WELD: f64 = 1e-7;

/// Whether `mesh` (world space) may be drawn with back faces culled, seen
/// from `view`.
pub fn back_faces_hidden(mesh: &TriangleMesh, view: &View) -> bool {
    let Some((lo, hi)) = bounds(mesh) else {
        return false;
    };
    let eye = view.eye;
    let corners = (0..8).map(|k| {
        DVec3::new(
            if k & 1 == 0 { lo.x } else { hi.x },
            if k & 2 == 0 { lo.y } else { hi.y },
            if k & 4 == 0 { lo.z } else { hi.z },
        )
    });
    let beyond_near = corners
        .map(|c| (c - eye).dot(view.forward))
        .all(|depth| depth > view.near);
    beyond_near && is_closed(mesh, lo, hi) && enclosed_volume(mesh, lo, hi) > 0.0
}

fn bounds(mesh: &TriangleMesh) -> Option<(DVec3, DVec3)> {
    let mut used = mesh
        .triangles
        .iter()
        .flatten()
        .map(|&i| mesh.positions[i as usize]);
    let first = used.next()?;
    Some(used.fold((first, first), |(lo, hi), p| (lo.min(p), hi.max(p))))
}

/// Every edge used by exactly two triangles, once in each direction, with
/// vertices closer than `WELD` of the object's size (`lo` to `hi`, its
/// bounds) taken as one (a UV
/// sphere's seam and poles repeat positions under other indices, often off
/// by a rounding error: sin(2 pi) is not 0).
fn is_closed(mesh: &TriangleMesh, lo: DVec3, hi: DVec3) -> bool {
    let cell = WELD * (hi - lo).max_element().max(f64::MIN_POSITIVE);
    // Welding by sorting the vertices' grid cells (faster than hashing
    // them: 400k triangles take tens of milliseconds, not hundreds).
    let mut cells: Vec<([i64; 3], u32)> = mesh
        .positions
        .iter()
        .enumerate()
        .map(|(i, p)| (((*p - lo) / cell).round().as_i64vec3().to_array(), i as u32))
        .collect();
    cells.par_sort_unstable();
    let mut id = vec![0u32; mesh.positions.len()];
    let mut next = 0u32;
    for (k, &(cell, index)) in cells.iter().enumerate() {
        if k > 0 && cells[k - 1].0 != cell {
            next += 1;
        }
        id[index as usize] = next;
    }
    // Each undirected edge once per triangle using it, as one number: the
    // lower vertex, the higher, and in the lowest bit the direction it is
    // used in. A closed, consistently wound surface has every edge exactly
    // twice, once each way. (Ids fit in 31 bits: a mesh has fewer than
    // 2^31 vertices.)
    let mut edges = Vec::with_capacity(mesh.triangles.len() * 3);
    for tri in &mesh.triangles {
        let [a, b, c] = tri.map(|i| id[i as usize]);
        if a == b || b == c || c == a {
            // Two corners at one position: no area, and its two other
            // edges are each other's reverse.
            continue;
        }
        for (u, v) in [(a, b), (b, c), (c, a)] {
            let (low, high) = (u64::from(u.min(v)), u64::from(u.max(v)));
            edges.push(low << 32 | high << 1 | u64::from(u < v));
        }
    }
    if edges.is_empty() || edges.len() % 2 != 0 {
        return false;
    }
    edges.par_sort_unstable();
    // Sorted, an edge used once each way is a pair `e & !1`, `e | 1`; a
    // third use would start the next pair with the same edge.
    let edge = |e: u64| e >> 1;
    edges
        .chunks_exact(2)
        .all(|pair| pair[0] & 1 == 0 && pair[1] == pair[0] | 1)
        && edges
            .chunks_exact(2)
            .zip(edges.chunks_exact(2).skip(1))
            .all(|(p, q)| edge(p[0]) != edge(q[0]))
}

/// The signed volume the triangles enclose: positive when they are wound
/// counter-clockwise seen from outside (the pipeline's front faces).
/// `lo`, `hi`: the mesh's bounds.
fn enclosed_volume(mesh: &TriangleMesh, lo: DVec3, hi: DVec3) -> f64 {
    // Relative to the box's centre, so far-away objects keep precision.
    let origin = (lo + hi) * 0.5;
    mesh.triangles
        .iter()
        .map(|tri| {
            let [a, b, c] = tri.map(|i| mesh.positions[i as usize] - origin);
            a.dot(b.cross(c))
        })
        .sum::<f64>()
        / 6.0
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene::{default_scene, tessellate, Shape};

    fn view_from(eye: DVec3, look_at: DVec3) -> View {
        let mut scene = default_scene();
        scene.camera.position = eye;
        scene.camera.look_at = look_at;
        View::new(&scene, 64, 48)
    }

    fn sphere() -> TriangleMesh {
        tessellate(&Shape::Sphere {
            center: DVec3::ZERO,
            radius: 1.0,
            segments: 16,
        })
    }

    #[test]
    fn closed_objects_seen_from_outside_are_culled() {
        let outside = view_from(DVec3::new(0.0, 1.0, 5.0), DVec3::ZERO);
        assert!(back_faces_hidden(&sphere(), &outside));
        let cube = tessellate(&Shape::Box {
            center: DVec3::ZERO,
            half_extents: DVec3::new(1.0, 0.5, 2.0),
            rotation: glam::DMat3::from_rotation_y(0.3),
        });
        assert!(back_faces_hidden(&cube, &outside));
    }

    /// Each condition alone keeps both sides: the eye inside, a surface
    /// with a hole, one wound inside out, one cut by the near plane, a
    /// plane.
    #[test]
    fn every_condition_is_needed() {
        let inside = view_from(DVec3::new(0.1, 0.2, 0.3), DVec3::new(0.0, 0.0, -1.0));
        assert!(!back_faces_hidden(&sphere(), &inside));

        let outside = view_from(DVec3::new(0.0, 1.0, 5.0), DVec3::ZERO);
        let mut open = sphere();
        open.triangles.pop();
        assert!(!back_faces_hidden(&open, &outside));

        let mut inverted = sphere();
        for t in &mut inverted.triangles {
            t.swap(1, 2);
        }
        assert!(!back_faces_hidden(&inverted, &outside));

        // The eye just outside, looking along the surface: the box reaches
        // behind the eye, so part of it is in front of the near plane.
        let grazing = view_from(DVec3::new(0.0, 0.0, 1.5), DVec3::new(5.0, 0.0, 1.5));
        assert!(!back_faces_hidden(&sphere(), &grazing));

        let plane = tessellate(&Shape::Plane {
            center: DVec3::ZERO,
            normal: DVec3::Y,
            size: 2.0,
            segments: 2,
        });
        assert!(!back_faces_hidden(&plane, &outside));
    }
}
