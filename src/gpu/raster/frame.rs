//! One raster frame: its resources (the scene's vertices, indices, lights
//! and uniforms, the descriptors, the colour and depth images, the
//! read-back buffer; made by `frame_resources`) and the commands that draw
//! it (each pass: begin rendering, bind, the draws) and copy it back.
//! `raster::render` runs the phases in order: geometry, pipeline, this
//! frame's upload, its recording, the submission, the read-back.

use std::sync::Arc;

use ash::vk;

use crate::camera::View;
use crate::gpu::raster::flat::FlatMesh;
use crate::gpu::raster::frame_resources::{FrameImages, MeshBuffers, ShadingBuffers};
use crate::gpu::raster::layout::{DrawConstants, PatternDrawConstants};
use crate::gpu::raster::pipeline::{bindings_of, SurfaceFeatures};
use crate::gpu::raster::samples::{averaged, pass_viewport_origin, SampleDrawing};
use crate::gpu::raster::scene::RasterGeometry as Geometry;
use crate::gpu::raster::target::{ColorTarget, SCALED_UNORM16_RANGE};
use crate::gpu::shared::lights::PatternConstants;
use crate::gpu::vk::buffer::Buffer;
use crate::gpu::vk::context::GpuContext;
use crate::gpu::vk::descriptors::Descriptors;
use crate::gpu::vk::error::GpuError;
use crate::gpu::vk::image::image_barrier;
use crate::gpu::vk::image::Image;
use crate::gpu::vk::pipeline::PipelineObjects;
use crate::gpu::vk::timestamps::Timestamps;
use crate::linear_image::LinearImage;
use crate::scene::Scene;
use crate::shading::RasterMode;

/// What one frame draws from and into, alive until its submission ends.
pub(crate) struct Frame {
    vertex_buffer: Buffer,
    /// The second vertex stream, the vertex colours, where the scene has
    /// them (per flat vertex: its face's).
    color_buffer: Option<Buffer>,
    /// The third, the texture coordinates, where a material has a pattern
    /// (Gouraud and Phong).
    uv_buffer: Option<Buffer>,
    index_buffer: Buffer,
    descriptors: Descriptors,
    /// The resolved (or only) colour image, read back; with a pass per
    /// sample, the first pass's.
    color: Image,
    /// With a pass per sample, the other passes' images, read back after
    /// the first's and averaged with it on the host.
    pass_colors: Vec<Image>,
    /// Multisampled: the colour samples, averaged into `color` at the end
    /// of rendering.
    color_samples: Option<Image>,
    depth: Image,
    readback: Buffer,
    target: ColorTarget,
    extent: vk::Extent2D,
    drawing: SampleDrawing,
    // Read by the shaders through the descriptors.
    _light_buffer: Buffer,
    _frame_buffer: Buffer,
    _face_buffer: Option<Buffer>,
    _texture_buffers: Option<[Buffer; 2]>,
}

impl Frame {
    /// The scene's data uploaded and the images made, for `pipeline`.
    pub(crate) fn new(
        context: &Arc<GpuContext>,
        (scene, view, geometry): (&Scene, &View, &Geometry),
        (mode, features): (RasterMode, SurfaceFeatures),
        (target, drawing): (ColorTarget, SampleDrawing),
        pipeline: &PipelineObjects,
    ) -> Result<Self, GpuError> {
        let (width, height) = (scene.image.width, scene.image.height);
        let flat = mode == RasterMode::Flat;
        let flat_mesh = flat.then(|| FlatMesh::new(geometry));
        let MeshBuffers {
            vertices: vertex_buffer,
            colors: color_buffer,
            uvs: uv_buffer,
            indices: index_buffer,
        } = MeshBuffers::upload(context, geometry, flat_mesh.as_ref())?;
        let ShadingBuffers {
            lights: light_buffer,
            frame: frame_buffer,
            faces: face_buffer,
            textures: texture_buffers,
        } = ShadingBuffers::upload(
            context,
            (scene, view, geometry),
            flat_mesh.as_ref(),
            features,
        )?;
        let mut bound = vec![&light_buffer, &frame_buffer];
        bound.extend(&face_buffer);
        bound.extend(texture_buffers.iter().flatten());
        let descriptors = Descriptors::new(
            context,
            pipeline.set_layout,
            bindings_of(mode, features),
            &bound,
        )?;

        let extent = vk::Extent2D { width, height };
        let FrameImages {
            color,
            pass_colors,
            color_samples,
            depth,
            readback,
        } = FrameImages::new(context, extent, target, drawing)?;
        Ok(Self {
            vertex_buffer,
            color_buffer,
            uv_buffer,
            index_buffer,
            descriptors,
            color,
            pass_colors,
            color_samples,
            depth,
            readback,
            target,
            extent,
            drawing,
            _light_buffer: light_buffer,
            _frame_buffer: frame_buffer,
            _face_buffer: face_buffer,
            _texture_buffers: texture_buffers,
        })
    }

    /// Records the frame: the attachments cleared, every draw, the colour
    /// image copied to the read-back buffer, `timestamps` around the draws.
    ///
    /// # Safety
    /// `cmd` is recording, and `self`, `pipeline` and `timestamps` live
    /// until the submission that runs it has completed; the barriers order
    /// every access.
    pub(crate) unsafe fn record(
        &self,
        device: &ash::Device,
        cmd: vk::CommandBuffer,
        pipeline: &PipelineObjects,
        (scene, view, geometry): (&Scene, &View, &Geometry),
        timestamps: &Timestamps,
    ) {
        self.to_attachments(device, cmd);
        timestamps.start(cmd);
        for pass in 0..self.drawing.passes() {
            if pass > 0 {
                Self::between_passes(device, cmd);
            }
            self.draw(device, cmd, pipeline, (scene, view, geometry), pass);
        }
        timestamps.stop(cmd);
        self.copy_back(device, cmd);
    }

    /// The attachments' layouts for drawing, nothing before them to wait on.
    ///
    /// # Safety
    /// As `record`.
    unsafe fn to_attachments(&self, device: &ash::Device, cmd: vk::CommandBuffer) {
        let (color, depth) = (&self.color, &self.depth);
        let to_color_attachment = |image: vk::Image| {
            image_barrier(
                image,
                vk::ImageAspectFlags::COLOR,
                (
                    vk::ImageLayout::UNDEFINED,
                    vk::ImageLayout::COLOR_ATTACHMENT_OPTIMAL,
                ),
                (vk::PipelineStageFlags2::NONE, vk::AccessFlags2::NONE),
                (
                    vk::PipelineStageFlags2::COLOR_ATTACHMENT_OUTPUT,
                    vk::AccessFlags2::COLOR_ATTACHMENT_WRITE,
                ),
            )
        };
        let mut to_attachment = vec![
            to_color_attachment(color.raw),
            image_barrier(
                depth.raw,
                vk::ImageAspectFlags::DEPTH,
                (
                    vk::ImageLayout::UNDEFINED,
                    vk::ImageLayout::DEPTH_ATTACHMENT_OPTIMAL,
                ),
                (vk::PipelineStageFlags2::NONE, vk::AccessFlags2::NONE),
                (
                    vk::PipelineStageFlags2::EARLY_FRAGMENT_TESTS
                        | vk::PipelineStageFlags2::LATE_FRAGMENT_TESTS,
                    vk::AccessFlags2::DEPTH_STENCIL_ATTACHMENT_READ
                        | vk::AccessFlags2::DEPTH_STENCIL_ATTACHMENT_WRITE,
                ),
            ),
        ];
        if let Some(samples) = &self.color_samples {
            to_attachment.push(to_color_attachment(samples.raw));
        }
        to_attachment.extend(self.pass_colors.iter().map(|c| to_color_attachment(c.raw)));
        device.cmd_pipeline_barrier2(
            cmd,
            &vk::DependencyInfo::default().image_memory_barriers(&to_attachment),
        );
    }

    /// A pass after the one before: its depth clear follows the last
    /// pass's depth tests (each pass has a colour image of its own).
    ///
    /// # Safety
    /// As `record`.
    unsafe fn between_passes(device: &ash::Device, cmd: vk::CommandBuffer) {
        let tests = vk::PipelineStageFlags2::EARLY_FRAGMENT_TESTS
            | vk::PipelineStageFlags2::LATE_FRAGMENT_TESTS;
        let barriers = [vk::MemoryBarrier2::default()
            .src_stage_mask(tests)
            .src_access_mask(vk::AccessFlags2::DEPTH_STENCIL_ATTACHMENT_WRITE)
            .dst_stage_mask(tests)
            .dst_access_mask(
                vk::AccessFlags2::DEPTH_STENCIL_ATTACHMENT_READ
                    | vk::AccessFlags2::DEPTH_STENCIL_ATTACHMENT_WRITE,
            )];
        device.cmd_pipeline_barrier2(
            cmd,
            &vk::DependencyInfo::default().memory_barriers(&barriers),
        );
    }

    /// The attachments cleared and every draw of the scene, in pass `pass`.
    ///
    /// # Safety
    /// As `record`.
    unsafe fn draw(
        &self,
        device: &ash::Device,
        cmd: vk::CommandBuffer,
        pipeline: &PipelineObjects,
        (scene, view, geometry): (&Scene, &View, &Geometry),
        pass: u32,
    ) {
        self.begin_rendering(device, cmd, scene, pass);
        self.bind(device, cmd, pipeline, pass);
        self.record_draws(device, cmd, pipeline, (scene, view, geometry));
        device.cmd_end_rendering(cmd);
    }

    /// The whole frame's area, which every pass renders and draws.
    fn area(&self) -> vk::Rect2D {
        vk::Rect2D {
            offset: vk::Offset2D { x: 0, y: 0 },
            extent: self.extent,
        }
    }

    /// Begins rendering pass `pass` into its colour image (through the
    /// samples where multisampled) and the depth image, both cleared.
    ///
    /// # Safety
    /// As `record`.
    unsafe fn begin_rendering(
        &self,
        device: &ash::Device,
        cmd: vk::CommandBuffer,
        scene: &Scene,
        pass: u32,
    ) {
        let (color, depth) = (&self.color, &self.depth);
        // In the target's scale, as the fragment stages write.
        let background = scene.image.background.as_vec3() * self.target.output_scale();
        let clear = vk::ClearValue {
            color: vk::ClearColorValue {
                float32: [background.x, background.y, background.z, 1.0],
            },
        };
        let color = match pass {
            0 => color,
            _ => &self.pass_colors[pass as usize - 1],
        };
        // Multisampled: the samples are drawn, averaged into `color` at the
        // end (their own values are not kept).
        let color_attachments = [match &self.color_samples {
            None => vk::RenderingAttachmentInfo::default()
                .image_view(color.view)
                .image_layout(vk::ImageLayout::COLOR_ATTACHMENT_OPTIMAL)
                .load_op(vk::AttachmentLoadOp::CLEAR)
                .store_op(vk::AttachmentStoreOp::STORE)
                .clear_value(clear),
            Some(samples) => vk::RenderingAttachmentInfo::default()
                .image_view(samples.view)
                .image_layout(vk::ImageLayout::COLOR_ATTACHMENT_OPTIMAL)
                .load_op(vk::AttachmentLoadOp::CLEAR)
                .store_op(vk::AttachmentStoreOp::DONT_CARE)
                .clear_value(clear)
                .resolve_mode(vk::ResolveModeFlags::AVERAGE)
                .resolve_image_view(color.view)
                .resolve_image_layout(vk::ImageLayout::COLOR_ATTACHMENT_OPTIMAL),
        }];
        let depth_attachment = vk::RenderingAttachmentInfo::default()
            .image_view(depth.view)
            .image_layout(vk::ImageLayout::DEPTH_ATTACHMENT_OPTIMAL)
            .load_op(vk::AttachmentLoadOp::CLEAR)
            .store_op(vk::AttachmentStoreOp::DONT_CARE)
            .clear_value(vk::ClearValue {
                depth_stencil: vk::ClearDepthStencilValue {
                    depth: 0.0,
                    stencil: 0,
                },
            });
        let rendering = vk::RenderingInfo::default()
            .render_area(self.area())
            .layer_count(1)
            .color_attachments(&color_attachments)
            .depth_attachment(&depth_attachment);
        device.cmd_begin_rendering(cmd, &rendering);
    }

    /// Binds the pipeline, pass `pass`'s viewport (shifted to its sample
    /// position), the descriptors, the vertex streams and the indices.
    ///
    /// # Safety
    /// As `record`.
    unsafe fn bind(
        &self,
        device: &ash::Device,
        cmd: vk::CommandBuffer,
        pipeline: &PipelineObjects,
        pass: u32,
    ) {
        let (vertex_buffer, index_buffer, descriptors) =
            (&self.vertex_buffer, &self.index_buffer, &self.descriptors);
        let (width, height) = (self.extent.width, self.extent.height);
        device.cmd_bind_pipeline(cmd, vk::PipelineBindPoint::GRAPHICS, pipeline.pipeline);
        let shift = pass_viewport_origin(self.drawing, pass);
        device.cmd_set_viewport(
            cmd,
            0,
            &[vk::Viewport {
                x: shift.0,
                y: shift.1,
                width: width as f32,
                height: height as f32,
                min_depth: 0.0,
                max_depth: 1.0,
            }],
        );
        device.cmd_set_scissor(cmd, 0, &[self.area()]);
        device.cmd_bind_descriptor_sets(
            cmd,
            vk::PipelineBindPoint::GRAPHICS,
            pipeline.layout,
            0,
            &[descriptors.set],
            &[],
        );
        device.cmd_bind_vertex_buffers(cmd, 0, &[vertex_buffer.raw], &[0]);
        if let Some(colors) = &self.color_buffer {
            device.cmd_bind_vertex_buffers(cmd, 1, &[colors.raw], &[0]);
        }
        if let Some(uvs) = &self.uv_buffer {
            device.cmd_bind_vertex_buffers(cmd, 2, &[uvs.raw], &[0]);
        }
        device.cmd_bind_index_buffer(cmd, index_buffer.raw, 0, vk::IndexType::UINT32);
    }

    /// Every draw of `geometry`: its material's constants pushed (with the
    /// pattern's where the frame has texture coordinates), its culling
    /// set, its indices drawn.
    ///
    /// # Safety
    /// As `record`.
    unsafe fn record_draws(
        &self,
        device: &ash::Device,
        cmd: vk::CommandBuffer,
        pipeline: &PipelineObjects,
        (scene, view, geometry): (&Scene, &View, &Geometry),
    ) {
        let clip = view.clip_from_relative().as_mat4().to_cols_array_2d();
        for draw in &geometry.draws {
            let m = &scene.materials[draw.material];
            let color = m.color.as_vec3();
            let constants = DrawConstants {
                clip_from_relative: clip,
                color_ka: [color.x, color.y, color.z, m.ka as f32],
                kd_ks_p: [m.kd as f32, m.ks as f32, m.p as f32, 0.0],
            };
            let patterned;
            let bytes = if self.uv_buffer.is_some() {
                let texture = geometry.textures.material_texture.get(draw.material);
                patterned = PatternDrawConstants {
                    draw: constants,
                    pattern: PatternConstants::of(m.pattern.as_ref(), texture.copied().flatten()),
                };
                bytemuck::bytes_of(&patterned)
            } else {
                bytemuck::bytes_of(&constants)
            };
            device.cmd_push_constants(
                cmd,
                pipeline.layout,
                vk::ShaderStageFlags::VERTEX | vk::ShaderStageFlags::FRAGMENT,
                0,
                bytes,
            );
            let cull = if draw.cull_back {
                vk::CullModeFlags::BACK
            } else {
                vk::CullModeFlags::NONE
            };
            device.cmd_set_cull_mode(cmd, cull);
            device.cmd_draw_indexed(cmd, draw.index_count, 1, draw.first_index, 0, 0);
        }
    }

    /// The colour image copied into the read-back buffer, for the host.
    ///
    /// # Safety
    /// As `record`.
    unsafe fn copy_back(&self, device: &ash::Device, cmd: vk::CommandBuffer) {
        let readback = &self.readback;
        let (width, height) = (self.extent.width, self.extent.height);
        // One image, or each pass's one after another.
        let colors: Vec<&Image> = std::iter::once(&self.color)
            .chain(&self.pass_colors)
            .collect();
        let to_transfer: Vec<_> = colors
            .iter()
            .map(|color| {
                image_barrier(
                    color.raw,
                    vk::ImageAspectFlags::COLOR,
                    (
                        vk::ImageLayout::COLOR_ATTACHMENT_OPTIMAL,
                        vk::ImageLayout::TRANSFER_SRC_OPTIMAL,
                    ),
                    (
                        vk::PipelineStageFlags2::COLOR_ATTACHMENT_OUTPUT,
                        vk::AccessFlags2::COLOR_ATTACHMENT_WRITE,
                    ),
                    (
                        vk::PipelineStageFlags2::COPY,
                        vk::AccessFlags2::TRANSFER_READ,
                    ),
                )
            })
            .collect();
        device.cmd_pipeline_barrier2(
            cmd,
            &vk::DependencyInfo::default().image_memory_barriers(&to_transfer),
        );
        let image_bytes = u64::from(width) * u64::from(height) * self.target.bytes_per_pixel();
        for (pass, color) in colors.iter().enumerate() {
            let region = vk::BufferImageCopy::default()
                .buffer_offset(pass as u64 * image_bytes)
                .image_subresource(
                    vk::ImageSubresourceLayers::default()
                        .aspect_mask(vk::ImageAspectFlags::COLOR)
                        .layer_count(1),
                )
                .image_extent(vk::Extent3D {
                    width,
                    height,
                    depth: 1,
                });
            device.cmd_copy_image_to_buffer(
                cmd,
                color.raw,
                vk::ImageLayout::TRANSFER_SRC_OPTIMAL,
                readback.raw,
                &[region],
            );
        }
        let to_host = [vk::BufferMemoryBarrier2::default()
            .buffer(readback.raw)
            .size(vk::WHOLE_SIZE)
            .src_stage_mask(vk::PipelineStageFlags2::COPY)
            .src_access_mask(vk::AccessFlags2::TRANSFER_WRITE)
            .dst_stage_mask(vk::PipelineStageFlags2::HOST)
            .dst_access_mask(vk::AccessFlags2::HOST_READ)];
        device.cmd_pipeline_barrier2(
            cmd,
            &vk::DependencyInfo::default().buffer_memory_barriers(&to_host),
        );
    }

    /// The image read back, in linear values.
    /// With a pass per sample, the passes' images averaged.
    pub(crate) fn image(&self) -> LinearImage {
        let (width, height) = (self.extent.width, self.extent.height);
        let image_bytes =
            (u64::from(width) * u64::from(height) * self.target.bytes_per_pixel()) as usize;
        let pass_image = |bytes: &[u8]| match self.target {
            ColorTarget::Float32 => LinearImage::from_rgba32f_bytes(width, height, bytes),
            ColorTarget::Srgb8 => LinearImage::from_srgba8_bytes(width, height, bytes),
            ColorTarget::ScaledUnorm16 => LinearImage::from_scaled_rgba16_unorm_bytes(
                width,
                height,
                bytes,
                SCALED_UNORM16_RANGE,
            ),
        };
        let mapped = self.readback.mapped();
        if self.drawing.passes() == 1 {
            return pass_image(mapped);
        }
        // Decoded and averaged on every core: 8 passes of 1024 x 1024 took
        // 75 ms on one.
        use rayon::prelude::*;
        let passes: Vec<LinearImage> = mapped
            .par_chunks_exact(image_bytes)
            .take(self.drawing.passes() as usize)
            .map(pass_image)
            .collect();
        averaged(&passes)
    }
}
