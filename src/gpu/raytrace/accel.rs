//! The ray-query engine's acceleration structures, built by the driver from
//! the same records the compute tracer reads (`records`): one bottom
//! level per mesh (its triangles' corners taken from the triangle records,
//! which `group_by_mesh` has made contiguous per mesh),
//! one of bounding boxes per analytic kind that the scene has (spheres,
//! planes, boxes: procedural primitives the shader intersects with the
//! compute tracer's exact formulas), and a top level holding one instance
//! of each. A mesh's instance has as custom index its first record, so a
//! hit's record is that plus the primitive index; an analytic kind's names
//! the kind.

use std::sync::Arc;

use ash::vk;
use glam::DVec3;
use gpu_allocator::MemoryLocation;

use crate::gpu::raytrace::layout::GpuTriangleGeometry;
use crate::gpu::raytrace::records::{in_order, SceneRecords};
use crate::gpu::vk::buffer::Buffer;
use crate::gpu::vk::commands::OneShot;
use crate::gpu::vk::context::GpuContext;
use crate::gpu::vk::error::{GpuError, VkContext};
use crate::rt_scene::{RtBox, RtPlane, RtScene, RtSphere};

/// Instance custom indices of the analytic kinds: which records their
/// primitives index (the shader's `QUERY_*`). A mesh's instance has its
/// first triangle record instead (told apart by the hit's type).
pub const QUERY_SPHERES: u32 = 0;
pub const QUERY_PLANES: u32 = 1;
pub const QUERY_BOXES: u32 = 2;

/// A custom index has 24 bits: the first record of the last mesh must fit.
const MAX_CUSTOM_INDEX: usize = (1 << 24) - 1;

/// Reorders the triangle records (geometry and shading alike) so that each
/// mesh's are contiguous, in leaf order within a mesh (a stable sort by
/// object), and returns each mesh's run as (first record, count). The
/// compute BVH's leaves no longer match the records afterwards: for the
/// ray-query engine only, which does not walk them.
pub fn group_by_mesh(r: &mut SceneRecords) -> Vec<(u32, u32)> {
    let mut order: Vec<usize> = (0..r.triangles.len()).collect();
    order.sort_by_key(|&i| r.triangles[i].object);
    r.triangles = order.iter().map(|&i| r.triangles[i]).collect();
    r.triangle_shading = order.iter().map(|&i| r.triangle_shading[i]).collect();
    if !r.triangle_colors.is_empty() {
        r.triangle_colors = order.iter().map(|&i| r.triangle_colors[i]).collect();
    }
    if !r.triangle_uvs.is_empty() {
        r.triangle_uvs = order.iter().map(|&i| r.triangle_uvs[i]).collect();
    }
    let mut runs: Vec<(u32, u32)> = Vec::new();
    for (i, t) in r.triangles.iter().enumerate() {
        match runs.last_mut() {
            Some((first, count)) if r.triangles[*first as usize].object == t.object => *count += 1,
            _ => runs.push((i as u32, 1)),
        }
    }
    runs
}

/// The built structures, destroyed with their buffers when dropped.
pub struct SceneStructure {
    context: Arc<GpuContext>,
    structures: Vec<(vk::AccelerationStructureKHR, Buffer)>,
    /// The top level, which the shader's `scene_structure` binds.
    pub top: vk::AccelerationStructureKHR,
}

impl Drop for SceneStructure {
    fn drop(&mut self) {
        if crate::gpu::vk::watchdog::any_device_stuck() {
            // A shader may still be running: leaked, never freed under it.
            return;
        }
        let Some(support) = &self.context.ray_query else {
            return;
        };
        for (structure, _buffer) in self.structures.drain(..) {
            // SAFETY: the GPU work that read the structure has completed
            // (every submission waits on its fence); its buffer outlives it.
            unsafe {
                support
                    .structures
                    .destroy_acceleration_structure(structure, None)
            };
        }
    }
}

impl SceneStructure {
    /// Creates `level`'s structure, records its build into `cmd` and keeps
    /// it; its scratch memory goes to `scratches`, to be freed once the
    /// build has run.
    fn add(
        &mut self,
        context: &Arc<GpuContext>,
        cmd: vk::CommandBuffer,
        level: &Level,
        scratches: &mut Vec<Buffer>,
    ) -> Result<vk::AccelerationStructureKHR, GpuError> {
        let prepared = prepare(context, level)?;
        record_build(context, cmd, level, &prepared);
        self.structures.push((prepared.structure, prepared.buffer));
        scratches.push(prepared.scratch);
        Ok(prepared.structure)
    }
}

/// An object's bounds (`RtSphere::bounds` and its kin, in f64) as the
/// structure's f32 box, widened on every side by a margin relative to its
/// size and distance from the eye, so that neither this rounding nor the
/// records' (which the shader's exact test reads) cuts off a surface the
/// test would hit, and a plane's box is never flat.
fn widened((lo, hi): (DVec3, DVec3)) -> vk::AabbPositionsKHR {
    let reach = lo.abs().max(hi.abs()).max(hi - lo).max_element().max(1.0);
    let (lo, hi) = ((lo - 1e-4 * reach).as_vec3(), (hi + 1e-4 * reach).as_vec3());
    vk::AabbPositionsKHR {
        min_x: lo.x,
        min_y: lo.y,
        min_z: lo.z,
        max_x: hi.x,
        max_y: hi.y,
        max_z: hi.z,
    }
}

/// The boxes of each analytic kind the scene has, in the records' order
/// (the primitive index of a hit is its record), with the kind's custom
/// index.
fn object_boxes(rt: &RtScene, r: &SceneRecords) -> [(u32, Vec<vk::AabbPositionsKHR>); 3] {
    fn boxes<T: Copy>(
        list: &[T],
        order: &[u32],
        bounds: fn(&T) -> (DVec3, DVec3),
    ) -> Vec<vk::AabbPositionsKHR> {
        in_order(list, order)
            .iter()
            .map(|o| widened(bounds(o)))
            .collect()
    }
    let bvh = &r.bvh;
    [
        (
            QUERY_SPHERES,
            boxes(&rt.spheres, &bvh.sphere_order, RtSphere::bounds),
        ),
        (
            QUERY_PLANES,
            boxes(&rt.planes, &bvh.plane_order, RtPlane::bounds),
        ),
        (QUERY_BOXES, boxes(&rt.boxes, &bvh.box_order, RtBox::bounds)),
    ]
}

/// What a buffer the builds read needs: the triangle records' storage
/// buffer, made with it by `raytrace` for this engine, and the boxes and
/// instances here.
pub const INPUT: vk::BufferUsageFlags = vk::BufferUsageFlags::from_raw(
    vk::BufferUsageFlags::ACCELERATION_STRUCTURE_BUILD_INPUT_READ_ONLY_KHR.as_raw()
        | vk::BufferUsageFlags::SHADER_DEVICE_ADDRESS.as_raw(),
);

fn address(context: &GpuContext, buffer: &Buffer) -> vk::DeviceAddress {
    let info = vk::BufferDeviceAddressInfo::default().buffer(buffer.raw);
    // SAFETY: the buffer was created with SHADER_DEVICE_ADDRESS on a device
    // with bufferDeviceAddress enabled (the engine's requirement).
    unsafe { context.device.get_buffer_device_address(&info) }
}

/// One structure to build: its geometries and their primitive counts.
struct Level<'a> {
    ty: vk::AccelerationStructureTypeKHR,
    geometries: Vec<vk::AccelerationStructureGeometryKHR<'a>>,
    counts: Vec<u32>,
}

/// A structure created with room for `level`, and the scratch memory its
/// build needs (aligned as the device asks).
struct Prepared {
    structure: vk::AccelerationStructureKHR,
    buffer: Buffer,
    scratch: Buffer,
    scratch_address: vk::DeviceAddress,
}

impl<'a> Level<'a> {
    /// A bottom level of one geometry with `count` primitives.
    fn bottom(geometry: vk::AccelerationStructureGeometryKHR<'a>, count: u32) -> Self {
        Level {
            ty: vk::AccelerationStructureTypeKHR::BOTTOM_LEVEL,
            geometries: vec![geometry],
            counts: vec![count],
        }
    }

    /// The build of this level, as sized and as recorded alike.
    fn build_info(&self) -> vk::AccelerationStructureBuildGeometryInfoKHR<'_> {
        vk::AccelerationStructureBuildGeometryInfoKHR::default()
            .ty(self.ty)
            .flags(vk::BuildAccelerationStructureFlagsKHR::PREFER_FAST_TRACE)
            .mode(vk::BuildAccelerationStructureModeKHR::BUILD)
            .geometries(&self.geometries)
    }
}

fn prepare(context: &Arc<GpuContext>, level: &Level) -> Result<Prepared, GpuError> {
    let support = context.ray_query.as_ref().expect("checked by build");
    let info = level.build_info();
    let mut sizes = vk::AccelerationStructureBuildSizesInfoKHR::default();
    // SAFETY: the build info and counts describe the same geometries.
    unsafe {
        support.structures.get_acceleration_structure_build_sizes(
            vk::AccelerationStructureBuildTypeKHR::DEVICE,
            &info,
            &level.counts,
            &mut sizes,
        )
    };
    let buffer = Buffer::new(
        context,
        "acceleration structure",
        sizes.acceleration_structure_size,
        vk::BufferUsageFlags::ACCELERATION_STRUCTURE_STORAGE_KHR
            | vk::BufferUsageFlags::SHADER_DEVICE_ADDRESS,
        MemoryLocation::GpuOnly,
    )?;
    let create = vk::AccelerationStructureCreateInfoKHR::default()
        .buffer(buffer.raw)
        .size(sizes.acceleration_structure_size)
        .ty(level.ty);
    // SAFETY: the buffer is at least `size` bytes and made for structures.
    let structure = unsafe {
        support
            .structures
            .create_acceleration_structure(&create, None)
    }
    .during("vkCreateAccelerationStructureKHR")?;
    let align = support.scratch_alignment;
    let scratch = Buffer::new(
        context,
        "acceleration structure scratch",
        sizes.build_scratch_size + align,
        vk::BufferUsageFlags::STORAGE_BUFFER | vk::BufferUsageFlags::SHADER_DEVICE_ADDRESS,
        MemoryLocation::GpuOnly,
    );
    let scratch = match scratch {
        Ok(s) => s,
        Err(e) => {
            // SAFETY: the structure is unused.
            unsafe {
                support
                    .structures
                    .destroy_acceleration_structure(structure, None)
            };
            return Err(e);
        }
    };
    let scratch_address = address(context, &scratch).next_multiple_of(align);
    Ok(Prepared {
        structure,
        buffer,
        scratch,
        scratch_address,
    })
}

/// Records the build of `level` into `prepared`.
fn record_build(context: &GpuContext, cmd: vk::CommandBuffer, level: &Level, prepared: &Prepared) {
    let support = context.ray_query.as_ref().expect("checked by build");
    let info = level
        .build_info()
        .dst_acceleration_structure(prepared.structure)
        .scratch_data(vk::DeviceOrHostAddressKHR {
            device_address: prepared.scratch_address,
        });
    let ranges: Vec<vk::AccelerationStructureBuildRangeInfoKHR> = level
        .counts
        .iter()
        .map(|&n| vk::AccelerationStructureBuildRangeInfoKHR::default().primitive_count(n))
        .collect();
    // SAFETY: every address in `info` is a live buffer of this device made
    // for its use; the command buffer is recording.
    unsafe {
        support
            .structures
            .cmd_build_acceleration_structures(cmd, &[info], &[&ranges])
    };
}

/// Builds the scene's structures on `context` (which must offer the
/// engine) and waits for the build to finish; `meshes` are the runs of
/// `group_by_mesh`.
pub fn build(
    context: &Arc<GpuContext>,
    rt: &RtScene,
    r: &SceneRecords,
    meshes: &[(u32, u32)],
) -> Result<SceneStructure, GpuError> {
    let Some(support) = &context.ray_query else {
        return Err(GpuError::NoRayQuery {
            device: context.info.name.clone(),
            why: context
                .info
                .no_ray_query_because
                .clone()
                .unwrap_or_default(),
        });
    };
    let mut inputs: Vec<Buffer> = Vec::new();
    check_custom_index(meshes)?;
    let mut bottoms = mesh_levels(context, r, meshes, &mut inputs)?;
    bottoms.extend(box_levels(context, rt, r, &mut inputs)?);

    let mut structure = SceneStructure {
        context: context.clone(),
        structures: Vec::new(),
        top: vk::AccelerationStructureKHR::null(),
    };
    let mut scratches = Vec::new();
    let mut instances = Vec::new();
    let commands = OneShot::begin(context)?;
    for (kind, level) in &bottoms {
        let bottom = structure.add(context, commands.cmd, level, &mut scratches)?;
        let info =
            vk::AccelerationStructureDeviceAddressInfoKHR::default().acceleration_structure(bottom);
        // SAFETY: the structure was just created on this device.
        let reference = unsafe {
            support
                .structures
                .get_acceleration_structure_device_address(&info)
        };
        instances.push(instance(*kind, reference));
    }
    // The top level reads the bottom levels the builds above write.
    let built = [vk::MemoryBarrier2::default()
        .src_stage_mask(vk::PipelineStageFlags2::ACCELERATION_STRUCTURE_BUILD_KHR)
        .src_access_mask(vk::AccessFlags2::ACCELERATION_STRUCTURE_WRITE_KHR)
        .dst_stage_mask(vk::PipelineStageFlags2::ACCELERATION_STRUCTURE_BUILD_KHR)
        .dst_access_mask(vk::AccessFlags2::ACCELERATION_STRUCTURE_READ_KHR)];
    // SAFETY: the command buffer is recording.
    unsafe {
        context.device.cmd_pipeline_barrier2(
            commands.cmd,
            &vk::DependencyInfo::default().memory_barriers(&built),
        )
    };
    let instance_data = Buffer::with_data(
        context,
        "query instances",
        instance_bytes(&instances),
        INPUT,
    )?;
    let top = top_level(context, &instance_data, instances.len() as u32);
    structure.top = structure.add(context, commands.cmd, &top, &mut scratches)?;
    commands.submit_and_wait()?;
    drop((scratches, inputs, instance_data));
    Ok(structure)
}

/// Refuses meshes whose first record the 24 bits of a custom index
/// cannot hold.
fn check_custom_index(meshes: &[(u32, u32)]) -> Result<(), GpuError> {
    if let Some(&(last, _)) = meshes.last() {
        if last as usize > MAX_CUSTOM_INDEX {
            return Err(GpuError::SceneTooLarge(format!(
                "{} triangles, more than the ray-query engine's {MAX_CUSTOM_INDEX} before the last mesh; \
                 use --traversal bvh",
                last
            )));
        }
    }
    Ok(())
}

/// A bottom level of triangles per mesh, with its first record as custom
/// index; the corners they read are uploaded into `inputs`.
fn mesh_levels(
    context: &Arc<GpuContext>,
    r: &SceneRecords,
    meshes: &[(u32, u32)],
    inputs: &mut Vec<Buffer>,
) -> Result<Vec<(u32, Level<'static>)>, GpuError> {
    // Three corners per triangle, in record order, not indexed: the records
    // hold them by axis, for the compute tracer's shuffles.
    let corners: Vec<[f32; 3]> = r
        .triangles
        .iter()
        .flat_map(GpuTriangleGeometry::corners)
        .collect();
    let mut base = 0;
    if !corners.is_empty() {
        let vertices = Buffer::with_data(
            context,
            "query vertices",
            bytemuck::cast_slice(&corners),
            INPUT,
        )?;
        base = address(context, &vertices);
        inputs.push(vertices);
    }
    let corner_size = std::mem::size_of::<[f32; 3]>() as u64;
    let mut bottoms = Vec::new();
    for &(first, count) in meshes {
        let triangles = vk::AccelerationStructureGeometryTrianglesDataKHR::default()
            .vertex_format(vk::Format::R32G32B32_SFLOAT)
            .vertex_data(vk::DeviceOrHostAddressConstKHR {
                device_address: base + 3 * u64::from(first) * corner_size,
            })
            .vertex_stride(corner_size)
            .max_vertex(3 * count - 1)
            .index_type(vk::IndexType::NONE_KHR);
        // Opaque: the driver commits the nearest triangle itself, without a
        // trip back to the shader for every candidate (on lavapipe within
        // the noise of the trips; on hardware the trips are what costs).
        let geometry = vk::AccelerationStructureGeometryKHR::default()
            .geometry_type(vk::GeometryTypeKHR::TRIANGLES)
            .flags(vk::GeometryFlagsKHR::OPAQUE)
            .geometry(vk::AccelerationStructureGeometryDataKHR { triangles });
        bottoms.push((first, Level::bottom(geometry, count)));
    }
    Ok(bottoms)
}

/// A bottom level of bounding boxes per analytic kind the scene has, with
/// the kind as custom index; the boxes are uploaded into `inputs`.
fn box_levels(
    context: &Arc<GpuContext>,
    rt: &RtScene,
    r: &SceneRecords,
    inputs: &mut Vec<Buffer>,
) -> Result<Vec<(u32, Level<'static>)>, GpuError> {
    let mut bottoms = Vec::new();
    for (kind, boxes) in object_boxes(rt, r) {
        if boxes.is_empty() {
            continue;
        }
        let data = Buffer::with_data(context, "query boxes", aabb_bytes(&boxes), INPUT)?;
        let aabbs = vk::AccelerationStructureGeometryAabbsDataKHR::default()
            .data(vk::DeviceOrHostAddressConstKHR {
                device_address: address(context, &data),
            })
            .stride(std::mem::size_of::<vk::AabbPositionsKHR>() as u64);
        inputs.push(data);
        let geometry = vk::AccelerationStructureGeometryKHR::default()
            .geometry_type(vk::GeometryTypeKHR::AABBS)
            .geometry(vk::AccelerationStructureGeometryDataKHR { aabbs });
        bottoms.push((kind, Level::bottom(geometry, boxes.len() as u32)));
    }
    Ok(bottoms)
}

/// The top level: `count` instances, one per bottom level, read from
/// `instance_data`.
fn top_level(context: &GpuContext, instance_data: &Buffer, count: u32) -> Level<'static> {
    Level {
        ty: vk::AccelerationStructureTypeKHR::TOP_LEVEL,
        geometries: vec![vk::AccelerationStructureGeometryKHR::default()
            .geometry_type(vk::GeometryTypeKHR::INSTANCES)
            .geometry(vk::AccelerationStructureGeometryDataKHR {
                instances: vk::AccelerationStructureGeometryInstancesDataKHR::default().data(
                    vk::DeviceOrHostAddressConstKHR {
                        device_address: address(context, instance_data),
                    },
                ),
            })],
        counts: vec![count],
    }
}

/// An instance of a bottom level at its place (identity transform: the
/// records are in the scene's camera-relative coordinates already), both
/// faces of its triangles visible, with its custom index (a kind, or a
/// mesh's first record).
fn instance(custom: u32, reference: vk::DeviceAddress) -> vk::AccelerationStructureInstanceKHR {
    vk::AccelerationStructureInstanceKHR {
        transform: vk::TransformMatrixKHR {
            matrix: [1.0, 0.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 0.0, 1.0, 0.0],
        },
        instance_custom_index_and_mask: vk::Packed24_8::new(custom, 0xff),
        instance_shader_binding_table_record_offset_and_flags: vk::Packed24_8::new(
            0,
            vk::GeometryInstanceFlagsKHR::TRIANGLE_FACING_CULL_DISABLE.as_raw() as u8,
        ),
        acceleration_structure_reference: vk::AccelerationStructureReferenceKHR {
            device_handle: reference,
        },
    }
}

fn aabb_bytes(boxes: &[vk::AabbPositionsKHR]) -> &[u8] {
    // SAFETY: AabbPositionsKHR is six f32s, repr(C), with no padding.
    unsafe { std::slice::from_raw_parts(boxes.as_ptr().cast(), std::mem::size_of_val(boxes)) }
}

fn instance_bytes(instances: &[vk::AccelerationStructureInstanceKHR]) -> &[u8] {
    // SAFETY: the instance record is repr(C), 64 bytes with no padding, as
    // Vulkan defines VkAccelerationStructureInstanceKHR.
    unsafe {
        std::slice::from_raw_parts(instances.as_ptr().cast(), std::mem::size_of_val(instances))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Each mesh's records become one run, leaf order kept within it, and a
    /// triangle's shading record moves with its geometry.
    #[test]
    fn group_by_mesh_makes_each_mesh_one_run() {
        use crate::gpu::raytrace::bvh::GpuBvh;
        use crate::gpu::raytrace::layout::GpuTriangleShading;
        use bytemuck::Zeroable;
        let objects = [1u32, 0, 1, 2, 0];
        let mut r = SceneRecords {
            spheres: Vec::new(),
            planes: Vec::new(),
            boxes: Vec::new(),
            triangles: objects
                .iter()
                .enumerate()
                .map(|(i, &object)| GpuTriangleGeometry {
                    index: i as u32,
                    object,
                    ..GpuTriangleGeometry::zeroed()
                })
                .collect(),
            triangle_shading: (0..objects.len())
                .map(|i| GpuTriangleShading {
                    material: 100 + i as u32,
                    ..GpuTriangleShading::zeroed()
                })
                .collect(),
            triangle_colors: Vec::new(),
            triangle_uvs: Vec::new(),
            patterns: Vec::new(),
            texture_records: Vec::new(),
            texels: Vec::new(),
            bvh: GpuBvh::default(),
            materials: Vec::new(),
        };
        let runs = group_by_mesh(&mut r);
        assert_eq!(runs, [(0, 2), (2, 2), (4, 1)]);
        let index: Vec<u32> = r.triangles.iter().map(|t| t.index).collect();
        assert_eq!(index, [1, 4, 0, 2, 3]);
        let shading: Vec<u32> = r
            .triangle_shading
            .iter()
            .map(|s| s.material - 100)
            .collect();
        assert_eq!(shading, index);
    }

    /// A structure's box holds its object's bounds, with room, and is never
    /// flat; the bounds are the objects' own (`RtSphere::bounds` and kin,
    /// which the compute BVH uses too).
    #[test]
    fn boxes_hold_their_objects_with_room() {
        use glam::DMat3;
        let s = RtSphere {
            center: DVec3::new(1.0, -2.0, 3.0),
            radius: 0.5,
            material: 0,
            object: 0,
        };
        let b = widened(s.bounds());
        assert!(b.min_x < 0.5 && b.max_x > 1.5 && b.min_y < -2.5 && b.max_z > 3.5);
        // The margin is small: a ten-thousandth of the reach, here 3.5.
        assert!(b.max_x < 1.5 + 1e-3 && b.min_y > -2.5 - 1e-3);
        // A floor facing +Y: flat in Y, but its box is not.
        let p = RtPlane {
            center: DVec3::new(0.0, -1.0, 0.0),
            normal: DVec3::Y,
            u: DVec3::X,
            v: DVec3::Z,
            half_size: 5.0,
            material: 0,
            object: 0,
        };
        let b = widened(p.bounds());
        assert!(b.min_y < -1.0 && b.max_y > -1.0);
        assert!(b.min_x <= -5.0 && b.max_z >= 5.0);
        // A unit cube turned 45 degrees about Y reaches sqrt(2)/2 along X.
        let c = std::f32::consts::FRAC_1_SQRT_2;
        let cube = RtBox {
            center: DVec3::ZERO,
            half_extents: DVec3::splat(0.5),
            rotation: DMat3::from_rotation_y(std::f64::consts::FRAC_PI_4),
            material: 0,
            object: 0,
        };
        let b = widened(cube.bounds());
        assert!(b.max_x >= c && b.max_x < c + 0.01, "{}", b.max_x);
        assert!(b.max_y >= 0.5 && b.max_y < 0.51);
    }
}
