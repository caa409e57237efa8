//! The ray tracer's buffers, built from the scene both tracers read
//! (`rt_scene::RtScene`) in the layouts of `layout`: f64 positions
//! rounded to f32, the BVH of `bvh`, and the triangles (and the objects
//! the BVH holds) in BVH leaf order, triangles split into what the
//! intersection test reads and what the nearest hit's shading reads.
//! `docs/raytracing.md` ("Why the shader is shaped this way") says why.

use bytemuck::Zeroable;
use glam::DVec3;

use crate::gpu::raytrace::bvh::{gpu_bvh, BvhKinds, GpuBvh, LeafBases};
use crate::gpu::raytrace::layout::*;
use crate::gpu::shared::texture_table::TextureTable;
use crate::gpu::vk::error::GpuError;
use crate::level_of_detail::uv_per_world_area;
use crate::rt_scene::RtScene;
use crate::scene::texcoords::box_face_codes;

/// The storage buffers' contents.
pub struct SceneRecords {
    pub spheres: Vec<GpuSphere>,
    pub planes: Vec<GpuPlane>,
    pub boxes: Vec<GpuBox>,
    pub triangles: Vec<GpuTriangleGeometry>,
    pub triangle_shading: Vec<GpuTriangleShading>,
    /// In the order of `triangle_shading`; empty when the scene has no
    /// vertex colours (`RtScene::triangle_colors`).
    pub triangle_colors: Vec<GpuTriangleColors>,
    /// Likewise, where some mesh's material has a pattern.
    pub triangle_uvs: Vec<GpuTriangleUvs>,
    /// One per material where some material has a pattern; else empty.
    pub patterns: Vec<GpuPattern>,
    /// The image textures (`gpu::shared::texture_table`); empty without any.
    pub texture_records: Vec<[u32; 4]>,
    pub texels: Vec<[f32; 4]>,
    pub bvh: GpuBvh,
    pub materials: Vec<GpuMaterial>,
}

impl SceneRecords {
    /// Makes the BVH one leaf of one triangle whose corners coincide (a
    /// zero determinant in the watertight test: never hit), for a scene
    /// with nothing in its BVH traced with the BVH walk compiled in.
    pub fn add_unhittable_triangle(&mut self) {
        debug_assert!(self.bvh.root.is_none() && self.triangles.is_empty());
        self.triangles.push(GpuTriangleGeometry::zeroed());
        self.triangle_shading.push(GpuTriangleShading::zeroed());
        self.bvh.root = Some(leaf_link(0, 1));
        self.bvh.bases = LeafBases {
            spheres: 1,
            planes: 1,
            boxes: 1,
            end: 1,
        };
    }
}

fn v3(v: DVec3) -> [f32; 3] {
    v.as_vec3().to_array()
}

/// A vector rounded to f32, with `w` as its fourth component.
pub(super) fn v4(v: DVec3, w: f32) -> [f32; 4] {
    let v = v.as_vec3();
    [v.x, v.y, v.z, w]
}

fn ids(material: u32, object: u32) -> [u32; 4] {
    [material, object, 0, 0]
}

/// `list` in the BVH's leaf order when it holds the kind (`order` not
/// empty), else as it is.
pub(super) fn in_order<T: Copy>(list: &[T], order: &[u32]) -> Vec<T> {
    if order.is_empty() {
        list.to_vec()
    } else {
        order.iter().map(|&i| list[i as usize]).collect()
    }
}

/// The plain spheres (in leaf order where the BVH holds them), then two
/// records for each huge sphere (`rt_scene::RtHugeSphere`): the first as
/// any sphere's (centre, radius, material, object: what its normal,
/// texture coordinates and tie rule read), the second its anchor and
/// `1 / r`, and the outward normal there as float bits. The huge ones
/// start at `RtScene::spheres.len()` (`TraceUniforms::grid[2]`).
fn sphere_records(rt: &RtScene, order: &[u32]) -> Vec<GpuSphere> {
    let plain = |s: &crate::rt_scene::RtSphere| GpuSphere {
        center_radius: v4(s.center, s.radius as f32),
        material_object: ids(s.material, s.object),
    };
    let mut records: Vec<GpuSphere> = in_order(&rt.spheres, order).iter().map(plain).collect();
    for huge in &rt.huge_spheres {
        records.push(plain(&huge.sphere));
        let [x, y, z] = v3(huge.anchor.normal);
        records.push(GpuSphere {
            center_radius: v4(huge.anchor.point, (1.0 / huge.sphere.radius) as f32),
            material_object: [x.to_bits(), y.to_bits(), z.to_bits(), 0],
        });
    }
    records
}

/// The storage buffers' contents for `rt`; refuses what they cannot hold
/// (`gpu_bvh`).
pub fn records(rt: &RtScene) -> Result<SceneRecords, GpuError> {
    let bvh = gpu_bvh(rt, BvhKinds::of(rt))?;
    let textures = TextureTable::new(&rt.materials);
    // Leaf order: a leaf's triangles are the run its link names.
    let order = if rt.triangles.is_empty() {
        &[][..]
    } else {
        &rt.bvh.primitive_indices[..]
    };
    Ok(SceneRecords {
        spheres: sphere_records(rt, &bvh.sphere_order),
        planes: plane_records(rt, &bvh.plane_order),
        boxes: box_records(rt, &bvh.box_order),
        triangles: triangle_geometry(rt, order),
        triangle_shading: triangle_shading(rt, order),
        triangle_colors: triangle_colors(rt, order),
        triangle_uvs: triangle_uvs(rt, order),
        patterns: pattern_records(rt, &textures.material_texture),
        texture_records: textures.records,
        texels: textures.texels,
        bvh,
        materials: material_records(rt),
    })
}

/// The planes, in leaf order where the BVH holds them.
fn plane_records(rt: &RtScene, order: &[u32]) -> Vec<GpuPlane> {
    in_order(&rt.planes, order)
        .iter()
        .map(|p| GpuPlane {
            center_half: v4(p.center, p.half_size as f32),
            normal: v4(p.normal, 0.0),
            u: v4(p.u, 0.0),
            v: v4(p.v, 0.0),
            material_object: ids(p.material, p.object),
        })
        .collect()
}

/// The boxes, in leaf order where the BVH holds them, each with the codes
/// of its faces' texture axes beside its ids.
fn box_records(rt: &RtScene, order: &[u32]) -> Vec<GpuBox> {
    in_order(&rt.boxes, order)
        .iter()
        .map(|b| GpuBox {
            center: v4(b.center, 0.0),
            half_extents: v4(b.half_extents, 0.0),
            axis_x: v4(b.rotation.x_axis, 0.0),
            axis_y: v4(b.rotation.y_axis, 0.0),
            axis_z: v4(b.rotation.z_axis, 0.0),
            material_object: {
                let [u, v] = box_face_codes(&b.rotation);
                let [material, object, ..] = ids(b.material, b.object);
                [material, object, u, v]
            },
        })
        .collect()
}

/// What the intersection test reads of each triangle, in leaf `order`.
fn triangle_geometry(rt: &RtScene, order: &[u32]) -> Vec<GpuTriangleGeometry> {
    order
        .iter()
        .map(|&i| {
            let t = &rt.triangles[i as usize];
            GpuTriangleGeometry::new(t.positions.map(v3), i, t.object)
        })
        .collect()
}

/// What the nearest hit's shading reads of each triangle, in leaf `order`.
fn triangle_shading(rt: &RtScene, order: &[u32]) -> Vec<GpuTriangleShading> {
    order
        .iter()
        .map(|&i| {
            let t = &rt.triangles[i as usize];
            GpuTriangleShading {
                n0: v3(t.normals[0]),
                material: t.material,
                n1: v3(t.normals[1]),
                unused1: 0,
                n2: v3(t.normals[2]),
                unused2: 0,
                geometric: v3(t.geometric_normal()),
                unused3: 0,
            }
        })
        .collect()
}

fn triangle_colors(rt: &RtScene, order: &[u32]) -> Vec<GpuTriangleColors> {
    if rt.triangle_colors.is_empty() {
        Vec::new()
    } else {
        order
            .iter()
            .map(|&i| {
                let [c0, c1, c2] = rt.triangle_colors[i as usize].map(|c| v4(c, 1.0));
                GpuTriangleColors { c0, c1, c2 }
            })
            .collect()
    }
}

fn triangle_uvs(rt: &RtScene, order: &[u32]) -> Vec<GpuTriangleUvs> {
    order
        .iter()
        .filter_map(|&i| Some((rt.triangle_uvs.get(i as usize)?, i)))
        .map(|(uvs, i)| {
            let density = uv_per_world_area(rt.triangles[i as usize].positions, *uvs);
            let [a, b, c] = uvs.map(|uv| uv.as_vec2());
            GpuTriangleUvs {
                uv01: [a.x, a.y, b.x, b.y],
                uv2: [c.x, c.y, density as f32, 0.0],
            }
        })
        .collect()
}

/// One per material (with its image texture's index in
/// `material_texture`) where some material has a pattern; else none.
fn pattern_records(rt: &RtScene, material_texture: &[Option<u32>]) -> Vec<GpuPattern> {
    if rt.materials.iter().any(|m| m.pattern.is_some()) {
        rt.materials
            .iter()
            .zip(material_texture)
            .map(|(m, &texture)| GpuPattern::of(m.pattern.as_ref(), texture))
            .collect()
    } else {
        Vec::new()
    }
}

fn material_records(rt: &RtScene) -> Vec<GpuMaterial> {
    rt.materials
        .iter()
        .map(|m| GpuMaterial {
            color_ka: v4(m.color, m.ka as f32),
            kd_ks_p_kr: [m.kd as f32, m.ks as f32, m.p as f32, m.kr as f32],
            kt_ior: [m.kt as f32, m.ior as f32, 0.0, 0.0],
        })
        .collect()
}
