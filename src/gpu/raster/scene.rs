//! Turns a `Scene` into what the raster pipelines consume: camera-relative
//! vertices (subtracted in `f64`, then rounded to `f32`), indices, one
//! record per triangle for flat shading, the draws (with back faces culled
//! where they cannot show, `cull`), and the specialization constants
//! that switch off what the scene does not use.
//!
//! Consecutive objects with the same material and culling share one draw:
//! lavapipe keeps tens of kilobytes of binning state per draw until the
//! frame ends, so a glTF instancing one triangle 20 000 times took 650 MB as
//! 20 000 draws. Merging keeps the objects' order, and so the order in which
//! triangles reach the depth test: the image is the same.

use glam::{DVec2, DVec3};

use crate::camera::View;
use crate::cpu::surface::pattern_color;
use crate::gpu::raster::cull::back_faces_hidden;
use crate::gpu::raster::layout::{GpuFace, Specialization, Vertex};
use crate::gpu::shared::lights::SceneLighting;
use crate::gpu::shared::texture_table::TextureTable;
use crate::level_of_detail::flat_lambda;
use crate::scene::{tessellate, tessellate_textured, Object, Pattern, Scene, Shape, TriangleMesh};

pub struct Draw {
    pub first_index: u32,
    pub index_count: u32,
    pub material: usize,
    /// Draw with back faces culled: they cannot show (`cull`).
    pub cull_back: bool,
}

pub struct RasterGeometry {
    pub vertices: Vec<Vertex>,
    /// One per vertex, a second vertex stream, only when a mesh of the
    /// scene has vertex colours (ones for the others' vertices); empty
    /// otherwise, and the pipeline reads none (`has_vertex_colors`).
    pub vertex_colors: Vec<[f32; 3]>,
    /// Into `vertices` (global, not per draw: merged draws span objects).
    pub indices: Vec<u32>,
    pub faces: Vec<GpuFace>,
    /// With `faces`, where the scene has vertex colours or a pattern: each
    /// face's colour at its centroid, where flat shading runs the formula:
    /// the mean of its corners' vertex colours times its pattern at the
    /// mean of their texture coordinates.
    pub face_colors: Vec<[f32; 3]>,
    /// Without `faces` (Gouraud and Phong), where some material has a
    /// pattern: texture coordinates per vertex, a third vertex stream
    /// (zeros for the objects without one).
    pub vertex_uvs: Vec<[f32; 2]>,
    /// Without `faces`, where some drawn material has an image texture:
    /// the images as the fragment stage reads them (empty otherwise).
    pub textures: TextureTable,
    pub draws: Vec<Draw>,
}

/// Whether some object of the scene has a material with a pattern.
pub fn has_patterns(scene: &Scene) -> bool {
    scene
        .objects
        .iter()
        .any(|o| scene.materials[o.material].pattern.is_some())
}

/// Whether some object of the scene has a material with an image texture.
pub fn has_textures(scene: &Scene) -> bool {
    scene.objects.iter().any(|o| {
        matches!(
            scene.materials[o.material].pattern,
            Some(crate::scene::Pattern::Image(_))
        )
    })
}

/// Whether some mesh of the scene has vertex colours: the raster
/// pipelines then read a colour per vertex, and only then.
pub fn has_vertex_colors(scene: &Scene) -> bool {
    scene
        .objects
        .iter()
        .any(|o| matches!(&o.shape, Shape::Mesh(m) if !m.colors.is_empty()))
}

fn f32x3(v: DVec3) -> [f32; 3] {
    v.as_vec3().to_array()
}

fn f32x4(v: DVec3) -> [f32; 4] {
    let [x, y, z] = f32x3(v);
    [x, y, z, 0.0]
}

/// Which streams and records a scene's geometry holds.
#[derive(Clone, Copy)]
struct Streams {
    /// A vertex colour per vertex (some mesh has them).
    coloured: bool,
    /// Some object's material has a pattern.
    patterned: bool,
    /// The per-triangle records of flat shading.
    with_faces: bool,
    /// With the faces, a colour per face (`RasterGeometry::face_colors`).
    face_colors: bool,
}

/// `with_faces`: also the per-triangle records, which only flat shading
/// reads (`faces` stays empty otherwise).
pub fn build_geometry(scene: &Scene, view: &View, with_faces: bool) -> RasterGeometry {
    let coloured = has_vertex_colors(scene);
    let patterned = has_patterns(scene);
    let streams = Streams {
        coloured,
        patterned,
        with_faces,
        face_colors: with_faces && (coloured || patterned),
    };
    let mut geometry = RasterGeometry::reserved(scene, streams);
    for object in &scene.objects {
        geometry.add_object(scene, view, object, streams);
    }
    geometry
}

/// The vertex colour of `mesh`'s vertex `i`, one where the mesh has none.
fn tint_at(mesh: &TriangleMesh, i: u32) -> DVec3 {
    mesh.colors.get(i as usize).copied().unwrap_or(DVec3::ONE)
}

/// The texture coordinates of `mesh`'s vertex `i`, zero where it has none.
fn uv_at(mesh: &TriangleMesh, i: u32) -> DVec2 {
    mesh.uvs.get(i as usize).copied().unwrap_or_default()
}

impl RasterGeometry {
    /// No geometry yet, with room for all of `scene`'s, and the image
    /// textures where the fragment stage samples them.
    fn reserved(scene: &Scene, streams: Streams) -> Self {
        let mut geometry = RasterGeometry {
            vertices: Vec::new(),
            vertex_colors: Vec::new(),
            indices: Vec::new(),
            faces: Vec::new(),
            face_colors: Vec::new(),
            vertex_uvs: Vec::new(),
            textures: TextureTable::default(),
            draws: Vec::new(),
        };
        if !streams.with_faces && has_textures(scene) {
            geometry.textures = TextureTable::new(&scene.materials);
        }
        // Reserved exactly: growth by doubling left up to half of each list
        // unused (`docs/memory.md`).
        let (vertex_count, triangle_count) = scene
            .objects
            .iter()
            .map(|o| tessellate::counts(&o.shape))
            .fold((0, 0), |(v, t), (ov, ot)| (v + ov, t + ot));
        geometry.vertices.reserve_exact(vertex_count as usize);
        geometry.indices.reserve_exact(3 * triangle_count as usize);
        if streams.with_faces {
            geometry.faces.reserve_exact(triangle_count as usize);
        }
        if streams.coloured {
            geometry.vertex_colors.reserve_exact(vertex_count as usize);
        }
        if streams.face_colors {
            geometry.face_colors.reserve_exact(triangle_count as usize);
        }
        geometry
    }

    /// `object` tessellated: its vertices (camera-relative) and their
    /// streams, its triangles, and its draw, merged into the last where
    /// the material and culling match.
    fn add_object(&mut self, scene: &Scene, view: &View, object: &Object, streams: Streams) {
        let eye = view.eye;
        let pattern = scene.materials[object.material].pattern.as_ref();
        let mesh = if pattern.is_some() {
            tessellate_textured(&object.shape)
        } else {
            tessellate(&object.shape)
        };
        let draw = Draw {
            first_index: self.indices.len() as u32,
            index_count: (mesh.triangles.len() * 3) as u32,
            material: object.material,
            cull_back: back_faces_hidden(&mesh, view),
        };
        let base = self.vertices.len() as u32;
        self.vertices.extend(
            mesh.positions
                .iter()
                .zip(&mesh.normals)
                .map(|(p, n)| Vertex {
                    position: f32x3(*p - eye),
                    normal: f32x3(*n),
                }),
        );
        if streams.coloured {
            self.vertex_colors
                .extend((0..mesh.positions.len() as u32).map(|i| f32x3(tint_at(&mesh, i))));
        }
        if streams.patterned && !streams.with_faces {
            self.vertex_uvs.extend(
                (0..mesh.positions.len() as u32).map(|i| uv_at(&mesh, i).as_vec2().to_array()),
            );
        }
        self.add_triangles(view, &mesh, (base, pattern), streams);
        match self.draws.last_mut() {
            Some(last) if last.material == draw.material && last.cull_back == draw.cull_back => {
                last.index_count += draw.index_count;
            }
            _ => self.draws.push(draw),
        }
    }

    /// `mesh`'s triangles as indices past `base`, and for flat shading
    /// each one's record and colour (its corners' mean tint times its
    /// `pattern` at their mean coordinates).
    fn add_triangles(
        &mut self,
        view: &View,
        mesh: &TriangleMesh,
        (base, pattern): (u32, Option<&Pattern>),
        streams: Streams,
    ) {
        let eye = view.eye;
        for tri in &mesh.triangles {
            self.indices.extend(tri.map(|i| base + i));
            if !streams.with_faces {
                continue;
            }
            if streams.face_colors {
                let [ta, tb, tc] = tri.map(|i| tint_at(mesh, i));
                let mut color = (ta + tb + tc) / 3.0;
                if let Some(pattern) = pattern {
                    let uvs = tri.map(|i| uv_at(mesh, i));
                    let uv = (uvs[0] + uvs[1] + uvs[2]) / 3.0;
                    let positions = tri.map(|i| mesh.positions[i as usize]);
                    let lambda = |image: &_| flat_lambda(image, view, positions, uvs);
                    color *= pattern_color(pattern, uv, lambda).0;
                }
                self.face_colors.push(f32x3(color));
            }
            let [a, b, c] = tri.map(|i| mesh.positions[i as usize]);
            let normal = (b - a).cross(c - a).normalize_or_zero();
            let center = (a + b + c) / 3.0;
            self.faces.push(GpuFace {
                center: f32x4(center - eye),
                normal: f32x4(normal),
            });
        }
    }
}

/// Only what the scene uses (`SceneLighting`), and image textures through
/// one sampler where they all share it.
pub fn specialization(scene: &Scene) -> Specialization {
    let lighting = SceneLighting::of(scene);
    let fixed_sampler = TextureTable::common_sampler(&scene.materials);
    Specialization {
        light_count: lighting.light_count,
        use_specular: u32::from(lighting.use_specular),
        use_attenuation: u32::from(lighting.use_attenuation),
        sampler_fixed: u32::from(fixed_sampler.is_some()),
        fixed_sampler: fixed_sampler.unwrap_or(0),
        // Until the draws are known (`with_back_faces`): on.
        back_faces: 1,
        output_scale: 1.0,
        at_least_zero: 0,
        inverse_square: u32::from(lighting.inverse_square),
    }
}

impl RasterGeometry {
    /// `spec` with `BACK_FACES` off where every draw culls its back faces
    /// (closed objects seen from outside): Gouraud then lights no backs.
    pub fn with_back_faces(&self, spec: Specialization) -> Specialization {
        Specialization {
            back_faces: u32::from(self.draws.iter().any(|d| !d.cull_back)),
            ..spec
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene::{default_scene, Object, Shape};

    #[test]
    fn consecutive_objects_of_one_material_share_a_draw_in_order() {
        let mut scene = default_scene();
        let sphere = |x: f64, material| Object {
            shape: Shape::Sphere {
                center: DVec3::new(x, 0.0, 0.0),
                radius: 0.4,
                segments: 8,
            },
            material,
        };
        scene.objects = vec![
            sphere(-2.0, 0),
            sphere(-1.0, 0),
            sphere(0.0, 1),
            sphere(1.0, 0),
        ];
        let view = View::new(&scene, 64, 64);
        let g = build_geometry(&scene, &view, false);
        let materials: Vec<usize> = g.draws.iter().map(|d| d.material).collect();
        assert_eq!(materials, [0, 1, 0]);
        // The draws tile the index buffer in the objects' order.
        let mut next = 0;
        for d in &g.draws {
            assert_eq!(d.first_index, next);
            next += d.index_count;
        }
        assert_eq!(next as usize, g.indices.len());
        let per_sphere = tessellate(&scene.objects[0].shape).triangles.len() as u32 * 3;
        assert_eq!(g.draws[0].index_count, 2 * per_sphere);
        // Indices are global: the second sphere's point at the first's
        // vertices shifted by one sphere's vertex count.
        let shift = tessellate(&scene.objects[0].shape).positions.len() as u32;
        let first = &g.indices[..per_sphere as usize];
        let second = &g.indices[per_sphere as usize..2 * per_sphere as usize];
        assert!(first.iter().zip(second).all(|(a, b)| a + shift == *b));
        assert!(g.indices.iter().all(|&i| (i as usize) < g.vertices.len()));
    }

    /// Features a scene does not use cost nothing: no colour or coordinate
    /// stream unless some surface has vertex colours or a pattern, and then
    /// only what its mode reads (flat: a colour per face; Gouraud and
    /// Phong: coordinates per vertex).
    #[test]
    fn colour_streams_only_for_the_scenes_that_have_them() {
        let mut scene = default_scene();
        let view = View::new(&scene, 64, 64);
        for with_faces in [true, false] {
            let g = build_geometry(&scene, &view, with_faces);
            assert!(g.vertex_colors.is_empty() && g.face_colors.is_empty());
            assert!(g.vertex_uvs.is_empty());
        }
        scene.materials[0].pattern = Some(crate::scene::Pattern::Checker {
            scale: 2.0,
            colors: [DVec3::ONE, DVec3::ZERO],
        });
        let flat = build_geometry(&scene, &view, true);
        assert_eq!(flat.face_colors.len(), flat.faces.len());
        assert!(flat.vertex_uvs.is_empty() && flat.vertex_colors.is_empty());
        let smooth = build_geometry(&scene, &view, false);
        assert_eq!(smooth.vertex_uvs.len(), smooth.vertices.len());
        assert!(smooth.face_colors.is_empty() && smooth.vertex_colors.is_empty());
    }
}
