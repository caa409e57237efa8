//! Turns a `Scene` into what the raster pipelines consume: camera-relative
//! vertices (subtracted in `f64`, then rounded to `f32`), indices, one
//! record per triangle for flat shading, one draw per object (with its back
//! faces culled where they cannot show, `raster_cull`), and the
//! specialization constants that switch off what the scene does not use.

use glam::DVec3;

use super::raster_cull::back_faces_hidden;
use super::raster_layout::{GpuFace, GpuLight, Specialization, Vertex};
use crate::camera::View;
use crate::scene::{tessellate, Scene};

pub struct Draw {
    pub first_index: u32,
    pub index_count: u32,
    pub vertex_offset: i32,
    pub material: usize,
    /// Draw with back faces culled: they cannot show (`raster_cull`).
    pub cull_back: bool,
}

pub struct RasterGeometry {
    pub vertices: Vec<Vertex>,
    pub indices: Vec<u32>,
    pub faces: Vec<GpuFace>,
    pub draws: Vec<Draw>,
}

fn f32x3(v: DVec3) -> [f32; 3] {
    v.as_vec3().to_array()
}

fn f32x4(v: DVec3) -> [f32; 4] {
    let [x, y, z] = f32x3(v);
    [x, y, z, 0.0]
}

/// `with_faces`: also the per-triangle records, which only flat shading
/// reads (`faces` stays empty otherwise).
pub fn build_geometry(scene: &Scene, view: &View, with_faces: bool) -> RasterGeometry {
    let eye = view.eye;
    let mut geometry = RasterGeometry {
        vertices: Vec::new(),
        indices: Vec::new(),
        faces: Vec::new(),
        draws: Vec::new(),
    };
    for object in &scene.objects {
        let mesh = tessellate(&object.shape);
        let draw = Draw {
            first_index: geometry.indices.len() as u32,
            index_count: (mesh.triangles.len() * 3) as u32,
            vertex_offset: geometry.vertices.len() as i32,
            material: object.material,
            cull_back: back_faces_hidden(&mesh, view),
        };
        geometry.vertices.extend(
            mesh.positions
                .iter()
                .zip(&mesh.normals)
                .map(|(p, n)| Vertex {
                    position: f32x3(*p - eye),
                    normal: f32x3(*n),
                }),
        );
        for tri in &mesh.triangles {
            geometry.indices.extend_from_slice(tri);
            if !with_faces {
                continue;
            }
            let [a, b, c] = tri.map(|i| mesh.positions[i as usize]);
            let normal = (b - a).cross(c - a).normalize_or_zero();
            let center = (a + b + c) / 3.0;
            geometry.faces.push(GpuFace {
                center: f32x4(center - eye),
                normal: f32x4(normal),
            });
        }
        geometry.draws.push(draw);
    }
    geometry
}

pub fn lights(scene: &Scene, eye: DVec3) -> Vec<GpuLight> {
    scene
        .lights
        .iter()
        .map(|l| GpuLight {
            position: f32x4(l.position - eye),
            intensity: f32x4(l.intensity),
        })
        .collect()
}

/// Only what the scene uses: the loop over exactly its lights, specular only
/// if some drawn material has `ks > 0`, attenuation only if enabled.
pub fn specialization(scene: &Scene) -> Specialization {
    let use_specular = scene
        .objects
        .iter()
        .any(|o| scene.materials[o.material].ks > 0.0);
    Specialization {
        light_count: scene.lights.len() as i32,
        use_specular: u32::from(use_specular),
        use_attenuation: u32::from(scene.lighting.attenuation),
    }
}
