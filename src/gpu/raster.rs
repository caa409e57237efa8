//! The raster renderer: flat, Gouraud and Phong through one Vulkan graphics
//! pipeline per (mode, interpolation, specialization), dynamic rendering into
//! a colour target (32-bit float, or 8-bit sRGB for PNG output) with a
//! reversed-Z depth buffer, then a copy back to the host.

use std::sync::Arc;
use std::time::Instant;

use ash::vk;
use gpu_allocator::MemoryLocation;

use super::buffer::Buffer;
use super::commands::OneShot;
use super::context::GpuContext;
use super::descriptors::{create_set_layout, Descriptors};
use super::error::{GpuError, VkContext};
use super::hook;
use super::image::{subresource_range, Image};
use super::pipeline::{single_pipeline, PipelineObjects};
use super::raster_flat::FlatMesh;
use super::raster_layout::{
    DrawConstants, FrameUniforms, Specialization, Vertex, BINDINGS, SMOOTH_BINDINGS,
};
use super::raster_scene::{build_geometry, lights, specialization};
use super::shader_catalog::{self as shaders, ShaderBlob};
use super::timestamps::{ms_since, GpuTimings, Timestamps};
use crate::camera::View;
use crate::linear_image::LinearImage;
use crate::scene::{Interpolation, LightingHook, Scene};
use crate::shading::RasterMode;

pub const DEPTH_FORMAT: vk::Format = vk::Format::D32_SFLOAT;

/// The colour target a raster render writes.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum ColorTarget {
    /// 32-bit float RGBA, linear and unclamped: EXR output, `check`,
    /// `diff`, `compare`.
    #[default]
    Float32,
    /// 8-bit sRGB RGBA: the hardware encodes `clamp(I, 0, 1)` as a PNG
    /// holds it. A quarter of the bytes to write and read back; the same
    /// PNG as the float target within 1 in 255 (tests/raster_modes.rs).
    Srgb8,
}

impl ColorTarget {
    /// The target whose image `format` stores without loss: 8-bit for PNG.
    pub fn for_output(format: crate::output::ImageFormat) -> Self {
        match format {
            crate::output::ImageFormat::Png => ColorTarget::Srgb8,
            crate::output::ImageFormat::Exr => ColorTarget::Float32,
        }
    }

    pub fn format(self) -> vk::Format {
        match self {
            ColorTarget::Float32 => vk::Format::R32G32B32A32_SFLOAT,
            ColorTarget::Srgb8 => vk::Format::R8G8B8A8_SRGB,
        }
    }

    fn bytes_per_pixel(self) -> u64 {
        match self {
            ColorTarget::Float32 => 16,
            ColorTarget::Srgb8 => 4,
        }
    }

    /// How reports name it.
    pub fn name(self) -> &'static str {
        match self {
            ColorTarget::Float32 => "rgba32f",
            ColorTarget::Srgb8 => "rgba8-srgb",
        }
    }
}
/// A cap on pixels per image (8192 x 8192): the float target and its
/// read-back copy take 16 bytes per pixel each.
pub const MAX_PIXELS: u64 = 8192 * 8192;

pub struct RasterOutput {
    pub image: LinearImage,
    pub timings: GpuTimings,
}

fn shader_pair(
    mode: RasterMode,
    interpolation: Interpolation,
) -> (&'static ShaderBlob, &'static ShaderBlob) {
    use Interpolation::{Perspective, Screen};
    match (mode, interpolation) {
        (RasterMode::Flat, _) => (&shaders::FLAT_VERT, &shaders::FLAT_FRAG),
        (RasterMode::Gouraud, Perspective) => (&shaders::GOURAUD_VERT, &shaders::GOURAUD_FRAG),
        (RasterMode::Gouraud, Screen) => {
            (&shaders::GOURAUD_VERT_SCREEN, &shaders::GOURAUD_FRAG_SCREEN)
        }
        (RasterMode::Phong, Perspective) => (&shaders::PHONG_VERT, &shaders::PHONG_FRAG),
        (RasterMode::Phong, Screen) => (&shaders::PHONG_VERT_SCREEN, &shaders::PHONG_FRAG_SCREEN),
    }
}

/// The descriptor bindings a mode's pipeline uses: only flat shading reads
/// the per-face records.
fn bindings_of(mode: RasterMode) -> &'static [(u32, vk::DescriptorType)] {
    match mode {
        RasterMode::Flat => BINDINGS,
        RasterMode::Gouraud | RasterMode::Phong => SMOOTH_BINDINGS,
    }
}

fn create_pipeline(
    context: &Arc<GpuContext>,
    mode: RasterMode,
    interpolation: Interpolation,
    spec: &Specialization,
    target: ColorTarget,
    lighting_hook: Option<&LightingHook>,
) -> Result<PipelineObjects, GpuError> {
    let device = &context.device;
    let mut p = PipelineObjects::new(context);
    let stages = vk::ShaderStageFlags::VERTEX | vk::ShaderStageFlags::FRAGMENT;
    p.set_layout = create_set_layout(context, bindings_of(mode), stages)?;
    let ranges = [vk::PushConstantRange::default()
        .stage_flags(stages)
        .size(std::mem::size_of::<DrawConstants>() as u32)];
    let set_layouts = [p.set_layout];
    let layout_info = vk::PipelineLayoutCreateInfo::default()
        .set_layouts(&set_layouts)
        .push_constant_ranges(&ranges);
    // SAFETY: as above.
    p.layout = unsafe { device.create_pipeline_layout(&layout_info, None) }
        .during("vkCreatePipelineLayout")?;

    let (vert, frag) = shader_pair(mode, interpolation);
    for blob in [vert, frag] {
        let words = hook::module_words(blob, lighting_hook, &context.info)?;
        let info = vk::ShaderModuleCreateInfo::default().code(&words);
        // SAFETY: the words are SPIR-V validated by naga (at build time, or
        // with the hook by `hook::module_words`).
        let module =
            unsafe { device.create_shader_module(&info, None) }.during("vkCreateShaderModule")?;
        p.modules.push(module);
    }
    let entries = Specialization::map_entries();
    let spec_info = vk::SpecializationInfo::default()
        .map_entries(&entries)
        .data(bytemuck::bytes_of(spec));
    let stage_infos = [
        vk::PipelineShaderStageCreateInfo::default()
            .stage(vk::ShaderStageFlags::VERTEX)
            .module(p.modules[0])
            .name(c"main")
            .specialization_info(&spec_info),
        vk::PipelineShaderStageCreateInfo::default()
            .stage(vk::ShaderStageFlags::FRAGMENT)
            .module(p.modules[1])
            .name(c"main")
            .specialization_info(&spec_info),
    ];
    // Flat draws read positions alone, one vertex of its own per triangle
    // (`raster_flat`).
    let stride = if mode == RasterMode::Flat {
        std::mem::size_of::<[f32; 3]>()
    } else {
        std::mem::size_of::<Vertex>()
    };
    let vertex_bindings = [vk::VertexInputBindingDescription::default()
        .binding(0)
        .stride(stride as u32)
        .input_rate(vk::VertexInputRate::VERTEX)];
    let all_attributes = [
        vk::VertexInputAttributeDescription::default()
            .location(0)
            .format(vk::Format::R32G32B32_SFLOAT)
            .offset(0),
        vk::VertexInputAttributeDescription::default()
            .location(1)
            .format(vk::Format::R32G32B32_SFLOAT)
            .offset(12),
    ];
    // The flat vertex stage reads positions only.
    let attributes = if mode == RasterMode::Flat {
        &all_attributes[..1]
    } else {
        &all_attributes[..]
    };
    let vertex_input = vk::PipelineVertexInputStateCreateInfo::default()
        .vertex_binding_descriptions(&vertex_bindings)
        .vertex_attribute_descriptions(attributes);
    let assembly = vk::PipelineInputAssemblyStateCreateInfo::default()
        .topology(vk::PrimitiveTopology::TRIANGLE_LIST);
    let viewport = vk::PipelineViewportStateCreateInfo::default()
        .viewport_count(1)
        .scissor_count(1);
    // Culling is set per draw (dynamic state): only where back faces cannot
    // show (raster_cull); planes and open meshes keep both sides, as in the
    // ray tracer.
    let raster = vk::PipelineRasterizationStateCreateInfo::default()
        .polygon_mode(vk::PolygonMode::FILL)
        .cull_mode(vk::CullModeFlags::NONE)
        .front_face(vk::FrontFace::COUNTER_CLOCKWISE)
        .line_width(1.0);
    let multisample = vk::PipelineMultisampleStateCreateInfo::default()
        .rasterization_samples(vk::SampleCountFlags::TYPE_1);
    // Reversed Z: nearer is greater. Strict comparison makes the first-drawn
    // of two coincident surfaces win, deterministically.
    let depth = vk::PipelineDepthStencilStateCreateInfo::default()
        .depth_test_enable(true)
        .depth_write_enable(true)
        .depth_compare_op(vk::CompareOp::GREATER);
    let blend_attachments = [vk::PipelineColorBlendAttachmentState::default()
        .color_write_mask(vk::ColorComponentFlags::RGBA)];
    let blend = vk::PipelineColorBlendStateCreateInfo::default().attachments(&blend_attachments);
    let dynamic_states = [
        vk::DynamicState::VIEWPORT,
        vk::DynamicState::SCISSOR,
        vk::DynamicState::CULL_MODE,
    ];
    let dynamic = vk::PipelineDynamicStateCreateInfo::default().dynamic_states(&dynamic_states);
    let color_formats = [target.format()];
    let mut rendering = vk::PipelineRenderingCreateInfo::default()
        .color_attachment_formats(&color_formats)
        .depth_attachment_format(DEPTH_FORMAT);
    let info = vk::GraphicsPipelineCreateInfo::default()
        .stages(&stage_infos)
        .vertex_input_state(&vertex_input)
        .input_assembly_state(&assembly)
        .viewport_state(&viewport)
        .rasterization_state(&raster)
        .multisample_state(&multisample)
        .depth_stencil_state(&depth)
        .color_blend_state(&blend)
        .dynamic_state(&dynamic)
        .layout(p.layout)
        .push_next(&mut rendering);
    // SAFETY: every pointer in `info` refers to locals alive for the call.
    let created =
        unsafe { device.create_graphics_pipelines(vk::PipelineCache::null(), &[info], None) };
    p.pipeline = single_pipeline(created, "vkCreateGraphicsPipelines")?;
    Ok(p)
}

fn image_barrier(
    image: vk::Image,
    aspect: vk::ImageAspectFlags,
    (old, new): (vk::ImageLayout, vk::ImageLayout),
    (src_stage, src_access): (vk::PipelineStageFlags2, vk::AccessFlags2),
    (dst_stage, dst_access): (vk::PipelineStageFlags2, vk::AccessFlags2),
) -> vk::ImageMemoryBarrier2<'static> {
    vk::ImageMemoryBarrier2::default()
        .image(image)
        .subresource_range(subresource_range(aspect))
        .old_layout(old)
        .new_layout(new)
        .src_stage_mask(src_stage)
        .src_access_mask(src_access)
        .dst_stage_mask(dst_stage)
        .dst_access_mask(dst_access)
}

/// Refuses an image the device cannot hold or that exceeds `MAX_PIXELS`.
pub(crate) fn check_image_size(
    context: &GpuContext,
    width: u32,
    height: u32,
) -> Result<(), GpuError> {
    let limit = context.max_image_dimension();
    if width == 0
        || height == 0
        || width > limit
        || height > limit
        || u64::from(width) * u64::from(height) > MAX_PIXELS
    {
        return Err(GpuError::ImageTooLarge {
            width,
            height,
            limit: limit.min(8192),
        });
    }
    Ok(())
}

/// Renders `scene` at its `image` size in `mode`, into the float target.
pub fn render(
    context: &Arc<GpuContext>,
    scene: &Scene,
    mode: RasterMode,
) -> Result<RasterOutput, GpuError> {
    render_to(context, scene, mode, ColorTarget::Float32)
}

/// Renders `scene` at its `image` size in `mode`, into `target`.
pub fn render_to(
    context: &Arc<GpuContext>,
    scene: &Scene,
    mode: RasterMode,
    target: ColorTarget,
) -> Result<RasterOutput, GpuError> {
    let started = Instant::now();
    let (width, height) = (scene.image.width, scene.image.height);
    check_image_size(context, width, height)?;
    let device = &context.device;
    let view = View::new(scene, width, height);
    let geometry = build_geometry(scene, &view, mode == RasterMode::Flat);
    let spec = specialization(scene);
    let prepare_ms = ms_since(started);

    let pipeline_started = Instant::now();
    let hook = scene.lighting_hook.as_deref();
    let interpolation = scene.lighting.interpolation;
    let key = format!(
        "raster {mode:?} {interpolation:?} {target:?} spec {:?} hook {:016x}",
        bytemuck::bytes_of(&spec),
        crate::cache::digest(&hook.map(|h| &h.source)),
    );
    let pipeline = context.pipelines.get_or_create(key, || {
        create_pipeline(context, mode, interpolation, &spec, target, hook)
    })?;
    let pipeline_ms = ms_since(pipeline_started);

    let upload_started = Instant::now();
    let flat = mode == RasterMode::Flat;
    let flat_mesh = flat.then(|| FlatMesh::new(&geometry));
    let (vertex_bytes, index_data): (&[u8], &[u32]) = match &flat_mesh {
        Some(m) => (bytemuck::cast_slice(&m.positions), &m.indices),
        None => (bytemuck::cast_slice(&geometry.vertices), &geometry.indices),
    };
    let vertex_buffer = Buffer::with_data(
        context,
        "vertices",
        vertex_bytes,
        vk::BufferUsageFlags::VERTEX_BUFFER,
    )?;
    let index_buffer = Buffer::with_data(
        context,
        "indices",
        bytemuck::cast_slice(index_data),
        vk::BufferUsageFlags::INDEX_BUFFER,
    )?;
    let light_buffer = Buffer::with_data(
        context,
        "lights",
        bytemuck::cast_slice(&lights(scene, view.eye)),
        vk::BufferUsageFlags::STORAGE_BUFFER,
    )?;
    let ambient = scene.lighting.ambient.as_vec3();
    let frame = FrameUniforms {
        ambient_k: [ambient.x, ambient.y, ambient.z, scene.lighting.k as f32],
    };
    let frame_buffer = Buffer::with_data(
        context,
        "frame",
        bytemuck::bytes_of(&frame),
        vk::BufferUsageFlags::UNIFORM_BUFFER,
    )?;
    let face_buffer = match &flat_mesh {
        Some(m) => Some(Buffer::with_data(
            context,
            "faces",
            bytemuck::cast_slice(&m.faces),
            vk::BufferUsageFlags::STORAGE_BUFFER,
        )?),
        None => None,
    };
    let mut bound = vec![&light_buffer, &frame_buffer];
    bound.extend(&face_buffer);
    let descriptors = Descriptors::new(context, pipeline.set_layout, bindings_of(mode), &bound)?;

    let extent = vk::Extent2D { width, height };
    let color = Image::new(
        context,
        "color",
        extent,
        target.format(),
        vk::ImageUsageFlags::COLOR_ATTACHMENT | vk::ImageUsageFlags::TRANSFER_SRC,
        vk::ImageAspectFlags::COLOR,
    )?;
    let depth = Image::new(
        context,
        "depth",
        extent,
        DEPTH_FORMAT,
        vk::ImageUsageFlags::DEPTH_STENCIL_ATTACHMENT,
        vk::ImageAspectFlags::DEPTH,
    )?;
    let pixel_bytes = target.bytes_per_pixel();
    let readback = Buffer::new(
        context,
        "readback",
        u64::from(width) * u64::from(height) * pixel_bytes,
        vk::BufferUsageFlags::TRANSFER_DST,
        MemoryLocation::GpuToCpu,
    )?;
    let timestamps = Timestamps::new(context)?;
    let upload_ms = ms_since(upload_started);

    let commands = OneShot::begin(context)?;
    let cmd = commands.cmd;
    let background = scene.image.background.as_vec3();
    // SAFETY: all handles recorded below are alive until after the submission
    // completes (they are dropped at the end of this function), and the
    // barriers order every access.
    unsafe {
        let to_attachment = [
            image_barrier(
                color.raw,
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
            ),
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
        device.cmd_pipeline_barrier2(
            cmd,
            &vk::DependencyInfo::default().image_memory_barriers(&to_attachment),
        );
        timestamps.start(cmd);

        let color_attachments = [vk::RenderingAttachmentInfo::default()
            .image_view(color.view)
            .image_layout(vk::ImageLayout::COLOR_ATTACHMENT_OPTIMAL)
            .load_op(vk::AttachmentLoadOp::CLEAR)
            .store_op(vk::AttachmentStoreOp::STORE)
            .clear_value(vk::ClearValue {
                color: vk::ClearColorValue {
                    float32: [background.x, background.y, background.z, 1.0],
                },
            })];
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
        let area = vk::Rect2D {
            offset: vk::Offset2D { x: 0, y: 0 },
            extent,
        };
        let rendering = vk::RenderingInfo::default()
            .render_area(area)
            .layer_count(1)
            .color_attachments(&color_attachments)
            .depth_attachment(&depth_attachment);
        device.cmd_begin_rendering(cmd, &rendering);
        device.cmd_bind_pipeline(cmd, vk::PipelineBindPoint::GRAPHICS, pipeline.pipeline);
        device.cmd_set_viewport(
            cmd,
            0,
            &[vk::Viewport {
                x: 0.0,
                y: 0.0,
                width: width as f32,
                height: height as f32,
                min_depth: 0.0,
                max_depth: 1.0,
            }],
        );
        device.cmd_set_scissor(cmd, 0, &[area]);
        device.cmd_bind_descriptor_sets(
            cmd,
            vk::PipelineBindPoint::GRAPHICS,
            pipeline.layout,
            0,
            &[descriptors.set],
            &[],
        );
        device.cmd_bind_vertex_buffers(cmd, 0, &[vertex_buffer.raw], &[0]);
        device.cmd_bind_index_buffer(cmd, index_buffer.raw, 0, vk::IndexType::UINT32);
        let clip = view.clip_from_relative().as_mat4().to_cols_array_2d();
        for draw in &geometry.draws {
            let m = &scene.materials[draw.material];
            let color = m.color.as_vec3();
            let constants = DrawConstants {
                clip_from_relative: clip,
                color_ka: [color.x, color.y, color.z, m.ka as f32],
                kd_ks_p: [m.kd as f32, m.ks as f32, m.p as f32, 0.0],
            };
            device.cmd_push_constants(
                cmd,
                pipeline.layout,
                vk::ShaderStageFlags::VERTEX | vk::ShaderStageFlags::FRAGMENT,
                0,
                bytemuck::bytes_of(&constants),
            );
            let cull = if draw.cull_back {
                vk::CullModeFlags::BACK
            } else {
                vk::CullModeFlags::NONE
            };
            device.cmd_set_cull_mode(cmd, cull);
            device.cmd_draw_indexed(cmd, draw.index_count, 1, draw.first_index, 0, 0);
        }
        device.cmd_end_rendering(cmd);
        timestamps.stop(cmd);

        let to_transfer = [image_barrier(
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
        )];
        device.cmd_pipeline_barrier2(
            cmd,
            &vk::DependencyInfo::default().image_memory_barriers(&to_transfer),
        );
        let region = vk::BufferImageCopy::default()
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
    let (submit_ms, gpu_ms) = timestamps.submit_and_measure(&commands)?;

    let readback_started = Instant::now();
    let image = match target {
        ColorTarget::Float32 => LinearImage::from_rgba32f_bytes(width, height, readback.mapped()),
        ColorTarget::Srgb8 => LinearImage::from_srgba8_bytes(width, height, readback.mapped()),
    };
    Ok(RasterOutput {
        image,
        timings: GpuTimings {
            prepare_ms,
            pipeline_ms,
            upload_ms,
            codegen_ms: None,
            gpu_ms,
            submit_ms,
            readback_ms: ms_since(readback_started),
            total_ms: ms_since(started),
        },
    })
}
