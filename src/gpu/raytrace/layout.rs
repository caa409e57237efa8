//! The host's side of the ray-tracing shader interface
//! (`shaders/include/rt_interface.glsl`): bindings, record layouts, the
//! uniform block and the specialization constants. tests/cpu/shader_interface.rs
//! checks each against naga's reflection of `raytrace.comp.glsl`.

use ash::vk;
use bytemuck::{Pod, Zeroable};

use crate::gpu::shared::lights::GpuLight;

pub const LIGHTS: u32 = 0;
pub const UNIFORMS: u32 = 1;
pub const SPHERES: u32 = 2;
pub const PLANES: u32 = 3;
pub const BOXES: u32 = 4;
pub const TRIANGLES: u32 = 5;
pub const BVH_NODES: u32 = 6;
pub const TRIANGLE_SHADING: u32 = 7;
pub const MATERIALS: u32 = 8;
pub const OUTPUT: u32 = 9;
pub const STATS: u32 = 10;
pub const WORK_QUEUE: u32 = 11;
pub const TRIANGLE_COLORS: u32 = 12;
pub const TRIANGLE_UVS: u32 = 13;
pub const PATTERNS: u32 = 14;
pub const TEXTURE_RECORDS: u32 = 15;
pub const TEXELS: u32 = 16;

const STORAGE: vk::DescriptorType = vk::DescriptorType::STORAGE_BUFFER;

/// Set 0 of the ray-tracing pipeline: (binding, type), in binding order.
pub const BINDINGS: &[(u32, vk::DescriptorType)] = &[
    (LIGHTS, STORAGE),
    (UNIFORMS, vk::DescriptorType::UNIFORM_BUFFER),
    (SPHERES, STORAGE),
    (PLANES, STORAGE),
    (BOXES, STORAGE),
    (TRIANGLES, STORAGE),
    (BVH_NODES, STORAGE),
    (TRIANGLE_SHADING, STORAGE),
    (MATERIALS, STORAGE),
    (OUTPUT, STORAGE),
    (STATS, STORAGE),
    (WORK_QUEUE, STORAGE),
    (TRIANGLE_COLORS, STORAGE),
    (TRIANGLE_UVS, STORAGE),
    (PATTERNS, STORAGE),
    (TEXTURE_RECORDS, STORAGE),
    (TEXELS, STORAGE),
];

/// The ray-query engine's second set (`--traversal query`): the top-level
/// acceleration structure alone (`shaders/include/rt_query.glsl`).
pub const QUERY_SET: u32 = 1;
pub const QUERY_BINDINGS: &[(u32, vk::DescriptorType)] =
    &[(0, vk::DescriptorType::ACCELERATION_STRUCTURE_KHR)];

// The kernels' sizes: the shaders are built with the same constants,
// through build.rs (`kernel_sizes` says what each is).
pub use super::kernel_sizes::{
    BVH_STACK_SIZE, ITEM_PACKETS, UNROLLED_BOXES, UNROLLED_MATERIALS, UNROLLED_PLANES,
    UNROLLED_SPHERES, WORKGROUP_SIZE,
};

/// Whether the shader reads a scene of `count` materials once per
/// invocation and picks by selects (its `MATERIALS_LISTED`): 1 to
/// `UNROLLED_MATERIALS` of them. With none there is nothing to read, and
/// the pick would start from an element never written.
pub fn lists_materials(count: usize) -> bool {
    (1..=UNROLLED_MATERIALS).contains(&count)
}

/// Workgroups to dispatch for a `width` x `height` image. The shader's
/// subgroups take work from a queue until it is empty, so any count
/// covers the image; this one decides only how many can work at once. On
/// a GPU: enough for one work item per subgroup. On a CPU device
/// (lavapipe), whose threads each run a fixed share of the workgroups one
/// after another, a subgroup that starts drains the queue with the
/// others running beside it, and every further workgroup only pays its
/// start-up to find the queue empty: a few per CPU thread (`cpus`) are
/// enough.
pub fn workgroups(width: u32, height: u32, on_cpu: bool, cpus: usize) -> (u32, u32) {
    // A workgroup's lanes trace WORKGROUP_SIZE * ITEM_PACKETS = 1024
    // pixels per round of items: a 32 x 32 square's worth.
    const EDGE: u32 = 32;
    const _: () = assert!(EDGE * EDGE == WORKGROUP_SIZE * ITEM_PACKETS);
    let (across, down) = (width.div_ceil(EDGE).max(1), height.div_ceil(EDGE).max(1));
    if !on_cpu {
        return (across, down);
    }
    let enough = u32::try_from(cpus.max(1) * 8).unwrap_or(u32::MAX);
    (across.saturating_mul(down).min(enough), 1)
}

/// Specialization constants: (constant_id, name in GLSL). Ids 0 to 2 mean
/// the same as in the raster pipelines.
pub const SPEC_CONSTANTS: &[(u16, &str)] = &[
    (0, "LIGHT_COUNT"),
    (1, "USE_SPECULAR"),
    (2, "USE_ATTENUATION"),
    (3, "SHADOWS"),
    (4, "HAS_REFLECTION"),
    (5, "HAS_TRANSMISSION"),
    (6, "SPHERE_COUNT"),
    (7, "PLANE_COUNT"),
    (8, "BOX_COUNT"),
    (9, "HAS_BVH"),
    (10, "COUNT_RAYS"),
    (11, "BVH_SPHERES"),
    (12, "BVH_PLANES"),
    (13, "BVH_BOXES"),
    (14, "MATERIALS_LISTED"),
    (15, "MATERIAL_COUNT"),
    (16, "VERTEX_COLORS"),
    (17, "PATTERNS"),
    (18, "TEXTURES"),
    (19, "SAMPLER_FIXED"),
    (20, "FIXED_SAMPLER"),
    (21, "HUGE_SPHERE_COUNT"),
    (32, "INVERSE_SQUARE"),
];

#[repr(C)]
#[derive(Debug, Clone, Copy, Pod, Zeroable)]
pub struct TraceUniforms {
    pub ambient_k: [f32; 4],
    pub background: [f32; 4],
    pub right_focal: [f32; 4],
    pub up_aspect: [f32; 4],
    pub forward_cutoff: [f32; 4],
    /// width, height, samples, maximum depth.
    pub image: [u32; 4],
    /// The sample grid kx, ky; the first huge sphere's record
    /// (`records::sphere_records`); the BVH's root link (`GpuBvhNode`).
    pub grid: [u32; 4],
    /// Where the BVH's spheres, planes and boxes start in its leaf index
    /// space (`bvh::LeafBases`); the diffuse bounces a path may take.
    pub leaf_bases: [u32; 4],
    /// A sphere around the whole BVH (`GpuBvh::bounding_sphere`): centre,
    /// radius (negative for an empty tree).
    pub bvh_sphere: [f32; 4],
}

#[repr(C)]
#[derive(Debug, Clone, Copy, Pod, Zeroable)]
pub struct GpuSphere {
    pub center_radius: [f32; 4],
    pub material_object: [u32; 4],
}

#[repr(C)]
#[derive(Debug, Clone, Copy, Pod, Zeroable)]
pub struct GpuPlane {
    pub center_half: [f32; 4],
    pub normal: [f32; 4],
    pub u: [f32; 4],
    pub v: [f32; 4],
    pub material_object: [u32; 4],
}

#[repr(C)]
#[derive(Debug, Clone, Copy, Pod, Zeroable)]
pub struct GpuBox {
    pub center: [f32; 4],
    pub half_extents: [f32; 4],
    pub axis_x: [f32; 4],
    pub axis_y: [f32; 4],
    pub axis_z: [f32; 4],
    /// Material, object, and each face's texture axes
    /// (`texcoords::box_face_codes`).
    pub material_object: [u32; 4],
}

/// What the intersection test reads of a triangle, in BVH leaf order: its
/// corners by axis (`x` holds the three corners' x), so that the shader
/// takes each coordinate its ray's shear asks for with one shuffle (see
/// `triangle_t` in shaders/include/rt_primitives.glsl).
#[repr(C)]
#[derive(Debug, Clone, Copy, Pod, Zeroable)]
pub struct GpuTriangleGeometry {
    pub x: [f32; 3],
    /// The triangle's index in `RtScene::triangles` (the tie rule's order).
    pub index: u32,
    pub y: [f32; 3],
    pub object: u32,
    pub z: [f32; 3],
    pub unused: u32,
}

impl GpuTriangleGeometry {
    /// The record of the triangle with these corners (p0, p1, p2).
    pub fn new(corners: [[f32; 3]; 3], index: u32, object: u32) -> Self {
        let axis = |k: usize| [corners[0][k], corners[1][k], corners[2][k]];
        GpuTriangleGeometry {
            x: axis(0),
            index,
            y: axis(1),
            object,
            z: axis(2),
            unused: 0,
        }
    }

    /// Its corners p0, p1, p2 again, as vertices (the ray-query engine's
    /// builds take them so).
    pub fn corners(&self) -> [[f32; 3]; 3] {
        let corner = |v: usize| [self.x[v], self.y[v], self.z[v]];
        [corner(0), corner(1), corner(2)]
    }
}

/// What shading reads of the nearest hit's triangle, in BVH leaf order.
#[repr(C)]
#[derive(Debug, Clone, Copy, Pod, Zeroable)]
pub struct GpuTriangleShading {
    pub n0: [f32; 3],
    pub material: u32,
    pub n1: [f32; 3],
    pub unused1: u32,
    pub n2: [f32; 3],
    pub unused2: u32,
    pub geometric: [f32; 3],
    pub unused3: u32,
}

/// One child of an inner BVH node: its box and its link (a node index, a
/// leaf (`leaf_link`), or in a 4-wide node `NO_CHILD` for an empty slot).
#[repr(C)]
#[derive(Debug, Clone, Copy, PartialEq, Pod, Zeroable)]
pub struct GpuBvhChild {
    pub lo: [f32; 3],
    pub link: u32,
    pub hi: [f32; 3],
    pub unused: u32,
}

impl GpuBvhChild {
    pub fn new(lo: [f32; 3], link: u32, hi: [f32; 3]) -> Self {
        GpuBvhChild {
            lo,
            link,
            hi,
            unused: 0,
        }
    }
}

/// An inner node of the binary BVH, holding both children's boxes.
#[repr(C)]
#[derive(Debug, Clone, Copy, PartialEq, Pod, Zeroable)]
pub struct GpuBvhNode {
    pub children: [GpuBvhChild; 2],
}

/// An inner node of the 4-wide BVH (`raytrace::wide_bvh`): up to four children, the
/// used slots first.
#[repr(C)]
#[derive(Debug, Clone, Copy, PartialEq, Pod, Zeroable)]
pub struct GpuWideNode {
    pub children: [GpuBvhChild; 4],
}

/// The link of an empty child slot (the shader's `NO_SHAPE`: a leaf link
/// never has every bit set, since a leaf's first index is below
/// `MAX_BVH_PRIMITIVES`).
pub const NO_CHILD: u32 = u32::MAX;

/// A link's leaf flag (the shader's `LEAF_BIT`).
pub const LEAF_BIT: u32 = 1 << 31;
/// Primitives a leaf may hold: its count less one fills bits 26 to 30.
pub const MAX_LEAF_PRIMITIVES: u32 = 32;
/// Primitives the BVH may hold (triangles and the objects it takes, in the
/// leaf index space of `bvh::LeafBases`): a leaf's first index fills
/// bits 0 to 25.
pub const MAX_BVH_PRIMITIVES: usize = (1 << 26) - 1;

/// The link to a leaf of `count` primitives (1 to `MAX_LEAF_PRIMITIVES`)
/// starting at leaf index `first` (at most `MAX_BVH_PRIMITIVES`).
pub fn leaf_link(first: u32, count: u32) -> u32 {
    debug_assert!((1..=MAX_LEAF_PRIMITIVES).contains(&count));
    debug_assert!((first as usize) < MAX_BVH_PRIMITIVES);
    LEAF_BIT | (count - 1) << 26 | first
}

#[repr(C)]
#[derive(Debug, Clone, Copy, Pod, Zeroable)]
pub struct GpuMaterial {
    pub color_ka: [f32; 4],
    pub kd_ks_p_kr: [f32; 4],
    pub kt_ior: [f32; 4],
}

/// A triangle's vertex colours (rgb, w unused), in the order of its
/// shading record; only for scenes with vertex colours.
#[repr(C)]
#[derive(Debug, Clone, Copy, Pod, Zeroable)]
pub struct GpuTriangleColors {
    pub c0: [f32; 4],
    pub c1: [f32; 4],
    pub c2: [f32; 4],
}

/// A triangle's texture coordinates, in the order of its shading record;
/// only for scenes with a patterned mesh.
#[repr(C)]
#[derive(Debug, Clone, Copy, Pod, Zeroable)]
pub struct GpuTriangleUvs {
    /// Corner 0's `(u, v)`, then corner 1's.
    pub uv01: [f32; 4],
    /// Corner 2's `(u, v)`, the triangle's uv area per unit of its world
    /// area (for the ray cones' level of detail), and one unused.
    pub uv2: [f32; 4],
}

/// A material's pattern, one per material; only for scenes with one. The
/// raster pipelines push the same values (`shared::lights::PatternConstants`).
pub type GpuPattern = crate::gpu::shared::lights::PatternConstants;

/// Values for `SPEC_CONSTANTS`, in order, 4 bytes each (bools as VkBool32).
#[repr(C)]
#[derive(Debug, Clone, Copy, PartialEq, Eq, Pod, Zeroable)]
pub struct TraceSpecialization {
    pub light_count: i32,
    pub use_specular: u32,
    pub use_attenuation: u32,
    pub shadows: u32,
    pub has_reflection: u32,
    pub has_transmission: u32,
    pub sphere_count: i32,
    pub plane_count: i32,
    pub box_count: i32,
    pub has_bvh: u32,
    pub count_rays: u32,
    pub bvh_spheres: u32,
    pub bvh_planes: u32,
    pub bvh_boxes: u32,
    pub materials_listed: u32,
    pub material_count: i32,
    pub vertex_colors: u32,
    pub patterns: u32,
    pub textures: u32,
    pub sampler_fixed: u32,
    pub fixed_sampler: u32,
    pub huge_sphere_count: i32,
    pub inverse_square: u32,
}

impl TraceSpecialization {
    pub fn map_entries() -> Vec<vk::SpecializationMapEntry> {
        SPEC_CONSTANTS
            .iter()
            .enumerate()
            .map(|(index, &(id, _))| vk::SpecializationMapEntry {
                constant_id: u32::from(id),
                offset: index as u32 * 4,
                size: 4,
            })
            .collect()
    }
}

/// The size of the record the host writes to each binding: one element of
/// a runtime array, or the whole uniform block.
pub fn record_size(binding: u32) -> usize {
    match binding {
        LIGHTS => std::mem::size_of::<GpuLight>(),
        UNIFORMS => std::mem::size_of::<TraceUniforms>(),
        // Read as quads of words, a subgroup at a time; the records' word
        // offsets are checked against the shader's constants by
        // tests/cpu/shader_interface.rs.
        SPHERES | PLANES | BOXES | TRIANGLES | BVH_NODES => 16,
        TRIANGLE_SHADING => std::mem::size_of::<GpuTriangleShading>(),
        TRIANGLE_COLORS => std::mem::size_of::<GpuTriangleColors>(),
        TRIANGLE_UVS => std::mem::size_of::<GpuTriangleUvs>(),
        PATTERNS => std::mem::size_of::<GpuPattern>(),
        TEXTURE_RECORDS | TEXELS => 16,
        MATERIALS => std::mem::size_of::<GpuMaterial>(),
        OUTPUT => 16,
        // A fixed array of 8 counters and one counter, not runtime arrays:
        // their blocks' sizes.
        STATS => 32,
        WORK_QUEUE => 4,
        _ => 0,
    }
}

/// The record size at `binding` in the forward tracer's module
/// (`shaders/forward.comp.glsl`): the ray tracer's, but for its output, a
/// film of 64-bit sums (`film_sums`), and its four 64-bit photon counts.
pub fn forward_record_size(binding: u32) -> usize {
    match binding {
        OUTPUT => 8,
        STATS => 32,
        _ => record_size(binding),
    }
}

/// The record size at `binding` in the ray tracer's module with diffuse
/// bounces (`PATHS`): the ray tracer's, but for its output, each pixel's
/// fixed-point sums of its samples (`film_sums`) as pairs of words.
pub fn paths_record_size(binding: u32) -> usize {
    match binding {
        OUTPUT => 8,
        _ => record_size(binding),
    }
}

/// The samples of each pixel a dispatch of the ray tracer with diffuse
/// bounces traces (the shader's `SampleRange` push constants).
#[repr(C)]
#[derive(Debug, Clone, Copy, bytemuck::Pod, bytemuck::Zeroable)]
pub struct SampleRange {
    /// The first sample.
    pub first: u32,
    /// One past the last; more than `first`.
    pub end: u32,
    /// 1 for every sample of the range, 2 for one of its two streams
    /// (`cpu::raytrace::pixel_sample`'s even or odd samples).
    pub step: u32,
    pub unused: u32,
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The record holds each axis's three coordinates in corner order, and
    /// gives the corners back as they came (the ray-query engine's
    /// vertices; the compute tracer's reading of it is held to the CPU twin
    /// by the twin tests).
    #[test]
    fn a_triangle_record_holds_its_corners_by_axis() {
        let corners = [[1.0, 2.0, 3.0], [4.0, 5.0, 6.0], [7.0, 8.0, 9.0]];
        let t = GpuTriangleGeometry::new(corners, 11, 12);
        assert_eq!(
            (t.x, t.y, t.z),
            ([1.0, 4.0, 7.0], [2.0, 5.0, 8.0], [3.0, 6.0, 9.0])
        );
        assert_eq!((t.index, t.object), (11, 12));
        assert_eq!(t.corners(), corners);
    }

    /// On a GPU every subgroup gets an item (the dispatch holds a lane
    /// for every 16 pixels); on a CPU a few workgroups per thread, never
    /// none, never more than a GPU's count.
    #[test]
    fn the_dispatch_fits_the_device() {
        for (width, height) in [(1, 1), (33, 31), (640, 480), (1024, 1024), (4097, 3)] {
            let (x, y) = workgroups(width, height, false, 2);
            let lanes = u64::from(x) * u64::from(y) * u64::from(WORKGROUP_SIZE);
            let pixels = u64::from(width) * u64::from(height);
            assert!(
                lanes * u64::from(ITEM_PACKETS) >= pixels,
                "{width}x{height}"
            );
            assert!(lanes * u64::from(ITEM_PACKETS) < pixels + 64 * 1024 * u64::from(x + y));
            for cpus in [1, 2, 16] {
                let (cx, cy) = workgroups(width, height, true, cpus);
                assert_eq!(cy, 1);
                assert!(
                    cx >= 1 && cx <= (8 * cpus) as u32 && cx <= x * y,
                    "{width}x{height}, {cpus}"
                );
            }
        }
        assert_eq!(workgroups(1024, 1024, true, 2), (16, 1));
    }
}
