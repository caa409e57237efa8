//! The buffers a trace binds (`layout::BINDINGS`): the scene's records,
//! its lights and the uniforms uploaded from the host, and what the shader
//! writes (the pixels, the ray counters, its work queue), read back after.

use std::sync::Arc;

use ash::vk;
use gpu_allocator::MemoryLocation;

use crate::camera::View;
use crate::gpu::raytrace::layout::{TraceUniforms, BINDINGS};
use crate::gpu::raytrace::records::{v4, SceneRecords};
use crate::gpu::shared::lights::GpuLight;
use crate::gpu::vk::buffer::Buffer;
use crate::gpu::vk::context::GpuContext;
use crate::gpu::vk::descriptors::Descriptors;
use crate::gpu::vk::error::GpuError;
use crate::linear_image::LinearImage;
use crate::rt_scene::{sample_grid, RayStats, RtScene};

/// Every buffer of a trace. Fields drop in the order they are declared,
/// so they are listed newest first: the buffers are freed in the reverse
/// of their creation in `upload`.
pub(super) struct TraceBuffers {
    stats: Buffer,
    output: Buffer,
    uniforms: Buffer,
    materials: Buffer,
    pub work_queue: Buffer,
    texels: Buffer,
    texture_records: Buffer,
    patterns: Buffer,
    triangle_uvs: Buffer,
    triangle_colors: Buffer,
    triangle_shading: Buffer,
    nodes: Buffer,
    triangles: Buffer,
    boxes: Buffer,
    planes: Buffer,
    spheres: Buffer,
    lights: Buffer,
}

impl TraceBuffers {
    /// Uploads the records `r` of `rt`, the `lights` and the uniforms as
    /// seen through `view`, and makes the buffers the shader writes: its
    /// output `output_bytes` long, its counters (zeroed).
    pub fn upload(
        context: &Arc<GpuContext>,
        lights: &[GpuLight],
        view: &View,
        rt: &RtScene,
        r: &SceneRecords,
        output_bytes: u64,
    ) -> Result<Self, GpuError> {
        let uniforms = uniforms(view, rt, r);
        let storage = vk::BufferUsageFlags::STORAGE_BUFFER;
        let upload = |name: &str, bytes: &[u8]| Buffer::with_data(context, name, bytes, storage);
        let lights = upload("lights", bytemuck::cast_slice(lights))?;
        let spheres = upload("spheres", bytemuck::cast_slice(&r.spheres))?;
        let planes = upload("planes", bytemuck::cast_slice(&r.planes))?;
        let boxes = upload("boxes", bytemuck::cast_slice(&r.boxes))?;
        let triangles = upload("triangles", bytemuck::cast_slice(&r.triangles))?;
        let nodes = upload("bvh nodes", r.bvh.walk_nodes())?;
        let triangle_shading = upload(
            "triangle shading",
            bytemuck::cast_slice(&r.triangle_shading),
        )?;
        // Bound whether or not the scene has vertex colours, patterns or
        // images: the bindings are in the module either way, read only where
        // VERTEX_COLORS, PATTERNS or TEXTURES is on.
        let triangle_colors = upload("triangle colours", bytemuck::cast_slice(&r.triangle_colors))?;
        let triangle_uvs = upload(
            "triangle texture coordinates",
            bytemuck::cast_slice(&r.triangle_uvs),
        )?;
        let patterns = upload("patterns", bytemuck::cast_slice(&r.patterns))?;
        let texture_records = upload("texture records", bytemuck::cast_slice(&r.texture_records))?;
        let texels = upload("texels", bytemuck::cast_slice(&r.texels))?;
        // Zeroed on the device before the dispatch (`BoundTrace::record`),
        // whatever memory the allocator hands out.
        let work_queue = Buffer::new(
            context,
            "work queue",
            4,
            storage | vk::BufferUsageFlags::TRANSFER_DST,
            MemoryLocation::GpuOnly,
        )?;
        let materials = upload("materials", bytemuck::cast_slice(&r.materials))?;
        let uniforms = Buffer::with_data(
            context,
            "trace uniforms",
            bytemuck::bytes_of(&uniforms),
            vk::BufferUsageFlags::UNIFORM_BUFFER,
        )?;
        let output = Buffer::new(
            context,
            "output",
            output_bytes,
            storage,
            MemoryLocation::GpuToCpu,
        )?;

        let mut stats = Buffer::new(context, "ray stats", 32, storage, MemoryLocation::GpuToCpu)?;
        stats.mapped_mut()[..32].fill(0);
        Ok(Self {
            stats,
            output,
            uniforms,
            materials,
            work_queue,
            texels,
            texture_records,
            patterns,
            triangle_uvs,
            triangle_colors,
            triangle_shading,
            nodes,
            triangles,
            boxes,
            planes,
            spheres,
            lights,
        })
    }

    /// The descriptor set of `set_layout` with each buffer at its binding
    /// (`BINDINGS`' order).
    pub fn bind(
        &self,
        context: &Arc<GpuContext>,
        set_layout: vk::DescriptorSetLayout,
    ) -> Result<Descriptors, GpuError> {
        Descriptors::new(
            context,
            set_layout,
            BINDINGS,
            &[
                &self.lights,
                &self.uniforms,
                &self.spheres,
                &self.planes,
                &self.boxes,
                &self.triangles,
                &self.nodes,
                &self.triangle_shading,
                &self.materials,
                &self.output,
                &self.stats,
                &self.work_queue,
                &self.triangle_colors,
                &self.triangle_uvs,
                &self.patterns,
                &self.texture_records,
                &self.texels,
            ],
        )
    }

    /// The traced pixels, after the submission has completed.
    pub fn image(&self, width: u32, height: u32) -> LinearImage {
        LinearImage::from_rgba32f_bytes(width, height, self.output.mapped())
    }

    /// Zeroes the output, before a shader that adds to it (the forward
    /// tracer's film; the ray tracer writes every pixel).
    pub fn zero_output(&mut self) {
        self.output.mapped_mut().fill(0);
    }

    /// The output's bytes, after the submission has completed.
    pub fn output(&self) -> &[u8] {
        self.output.mapped()
    }

    /// The counters' bytes, after the submission has completed.
    pub fn counters(&self) -> &[u8] {
        &self.stats.mapped()[..32]
    }

    /// The shader's ray counters, after the submission has completed.
    pub fn ray_stats(&self) -> RayStats {
        let counter = |i: usize| {
            let b = &self.stats.mapped()[i * 4..i * 4 + 4];
            u32::from_ne_bytes([b[0], b[1], b[2], b[3]])
        };
        RayStats {
            primary: u64::from(counter(0)),
            shadow: u64::from(counter(1)),
            reflected: u64::from(counter(2)),
            refracted: u64::from(counter(3)),
            pruned: u64::from(counter(4)),
            max_depth_reached: counter(5),
        }
    }
}

/// The uniforms: the lighting's ambient term, the background, the camera
/// of `view`, the image and its sample grid, and where the BVH walk
/// starts.
fn uniforms(view: &View, rt: &RtScene, r: &SceneRecords) -> TraceUniforms {
    let (kx, ky) = sample_grid(rt.render.samples);
    TraceUniforms {
        ambient_k: v4(rt.lighting.ambient, rt.lighting.k as f32),
        background: v4(rt.background, 0.0),
        right_focal: v4(view.right, view.focal as f32),
        up_aspect: v4(view.up, view.aspect as f32),
        forward_cutoff: v4(view.forward, rt.render.cutoff as f32),
        image: [view.width, view.height, rt.render.samples, rt.render.depth],
        grid: [
            kx,
            ky,
            rt.spheres.len() as u32,
            r.bvh.walk_root().unwrap_or(0),
        ],
        leaf_bases: [
            r.bvh.bases.spheres,
            r.bvh.bases.planes,
            r.bvh.bases.boxes,
            rt.render.bounces,
        ],
        bvh_sphere: r.bvh.bounding_sphere(),
    }
}
