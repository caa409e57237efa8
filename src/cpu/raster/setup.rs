//! Triangle setup: every object tessellated, its vertices lit (Gouraud)
//! and projected, each triangle's flat colour found (flat), clipped at the
//! near plane and turned into window-space `Triangle`s, in scene order.

use glam::{DVec2, DVec3};

use super::triangle::{screen_triangle, Triangle};
use crate::camera::View;
use crate::cpu::clip::{clip_near, ClipVertex, Extras};
use crate::cpu::lighting::{shade, Surface};
use crate::cpu::surface::pattern_color;
use crate::level_of_detail::flat_lambda;
use crate::scene::{
    tessellate, tessellate_textured, Interpolation, Material, Pattern, Scene, TriangleMesh,
};
use crate::shading::RasterMode;
use crate::work_counter::WorkCounter;

/// Every triangle of `scene` in window coordinates, counting the scene's
/// triangles into `counter` as they are set up.
pub(super) fn setup_triangles(
    scene: &Scene,
    view: &View,
    mode: RasterMode,
    counter: &WorkCounter,
) -> Vec<Triangle> {
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
        let vertices = clip_vertices(scene, view, mode, material, &mesh);
        for (k, tri) in mesh.triangles.iter().enumerate() {
            if k % 65536 == 65535 {
                counter.add(65536);
            }
            let primitive = next_primitive;
            next_primitive += 1;
            let corners = tri.map(|i| vertices[i as usize].clone());
            let flat_color = if mode == RasterMode::Flat {
                flat_color(scene, view, material, &mesh, tri.map(|i| i as usize))
            } else {
                DVec3::ZERO
            };
            let ids = (object_index as u32, primitive);
            let one_sample = !scene.render.msaa.is_multisampled();
            let coloured = !mesh.colors.is_empty();
            for mut t in clipped_triangles(view, ids, corners, flat_color, one_sample) {
                t.coloured = coloured;
                triangles.push(t);
            }
        }
        counter.add(mesh.triangles.len() as u64 % 65536);
    }
    triangles
}

/// `corners` clipped at the near plane, fanned into triangles, and those
/// that cover a sample of the image put in window coordinates.
fn clipped_triangles(
    view: &View,
    ids: (u32, u32),
    corners: [ClipVertex; 3],
    flat_color: DVec3,
    one_sample: bool,
) -> impl Iterator<Item = Triangle> + '_ {
    let polygon = clip_near(corners, view.near);
    (1..polygon.len().saturating_sub(1)).filter_map(move |k| {
        let verts = [
            polygon[0].clone(),
            polygon[k].clone(),
            polygon[k + 1].clone(),
        ];
        screen_triangle(view, ids, verts, flat_color, one_sample)
    })
}

/// The vertices of `mesh` in clip space, with the attributes the mode
/// interpolates (and Gouraud's intensities, front and back).
fn clip_vertices(
    scene: &Scene,
    view: &View,
    mode: RasterMode,
    material: &Material,
    mesh: &TriangleMesh,
) -> Vec<ClipVertex> {
    let clip_from_rel = view.clip_from_relative();
    let pattern = material.pattern.as_ref();
    let lit = VertexLighting::new(scene, view, mode, material);
    let uv_at = |i: usize| mesh.uvs.get(i).copied().unwrap_or_default();
    mesh.positions
        .iter()
        .zip(&mesh.normals)
        .enumerate()
        .map(|(i, (p, n))| {
            let rel = *p - view.eye;
            let tint = tint_at(mesh, i);
            let normal = n.normalize_or_zero();
            let (intensity, specular) = lit.gouraud(*p, tint, normal);
            let (back_intensity, back_specular) = lit.gouraud(*p, tint, -normal);
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
        .collect()
}

/// The vertex colour, one where the mesh has none.
fn tint_at(mesh: &TriangleMesh, i: usize) -> DVec3 {
    mesh.colors.get(i).copied().unwrap_or(DVec3::ONE)
}

/// What lighting a vertex needs: Gouraud runs the formula there.
struct VertexLighting<'a> {
    scene: &'a Scene,
    view: &'a View,
    mode: RasterMode,
    material: &'a Material,
    pattern: Option<&'a Pattern>,
    /// Gouraud under a pattern: the intensity without the specular term
    /// (`unlit_specular`, ks = 0) and the specular term alone (a black
    /// surface), which the pattern leaves untinted.
    unlit_specular: Material,
}

impl<'a> VertexLighting<'a> {
    fn new(scene: &'a Scene, view: &'a View, mode: RasterMode, material: &'a Material) -> Self {
        VertexLighting {
            scene,
            view,
            mode,
            material,
            pattern: material.pattern.as_ref(),
            unlit_specular: Material {
                ks: 0.0,
                ..material.clone()
            },
        }
    }

    /// The front lit with the normal, the back with it negated
    /// (`docs/lighting-model.md`, "Which side is lit").
    fn shade_side(&self, surface: Surface, p: DVec3, normal: DVec3) -> DVec3 {
        let scene = self.scene;
        shade(
            &scene.lighting,
            &scene.lights,
            surface,
            p,
            normal,
            self.view.eye,
        )
    }

    /// Gouraud's `(intensity, specular)` at vertex `p` of colour `tint`
    /// lit with `normal`: the specular apart only under a pattern; zeros in
    /// the other modes.
    fn gouraud(&self, p: DVec3, tint: DVec3, normal: DVec3) -> (DVec3, DVec3) {
        let material = self.material;
        match (self.mode, self.pattern) {
            // Gouraud runs the formula at the vertex, with the
            // vertex's own colour.
            (RasterMode::Gouraud, None) => (
                self.shade_side(Surface { material, tint }, p, normal),
                DVec3::ZERO,
            ),
            (RasterMode::Gouraud, Some(_)) => (
                self.shade_side(
                    Surface {
                        material: &self.unlit_specular,
                        tint,
                    },
                    p,
                    normal,
                ),
                self.shade_side(
                    Surface {
                        material,
                        tint: DVec3::ZERO,
                    },
                    p,
                    normal,
                ),
            ),
            _ => (DVec3::ZERO, DVec3::ZERO),
        }
    }
}

/// Flat mode's colour of the triangle `tri` of `mesh` (vertex indices).
fn flat_color(
    scene: &Scene,
    view: &View,
    material: &Material,
    mesh: &TriangleMesh,
    tri: [usize; 3],
) -> DVec3 {
    let [pa, pb, pc] = tri.map(|i| mesh.positions[i]);
    let centroid = (pa + pb + pc) / 3.0;
    let mut normal = (pb - pa).cross(pc - pa).normalize_or_zero();
    // A face seen from behind is lit as its back.
    if normal.dot(view.eye - centroid) < 0.0 {
        normal = -normal;
    }
    // Flat runs the formula at the centroid, whose colour is
    // the mean of the corners'.
    let [ta, tb, tc] = tri.map(|i| tint_at(mesh, i));
    let mut tint = (ta + tb + tc) / 3.0;
    if let Some(pattern) = &material.pattern {
        let uvs: [DVec2; 3] = tri.map(|i| mesh.uvs.get(i).copied().unwrap_or_default());
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
}
