//! The raster renderer: flat, Gouraud and Phong through one Vulkan graphics
//! pipeline per (mode, interpolation, specialization), dynamic rendering into
//! a colour target (32-bit float, or 8-bit sRGB for PNG output) with a
//! reversed-Z depth buffer, then a copy back to the host.

use std::sync::Arc;
use std::time::Instant;

use ash::vk;

use super::commands::OneShot;
use super::context::GpuContext;
use super::descriptors::create_set_layout;
use super::error::{GpuError, VkContext};
use super::hook;
use super::image::subresource_range;
use super::pipeline::{single_pipeline, PipelineObjects};
use super::raster_frame::Frame;
use super::raster_layout::{
    DrawConstants, PatternDrawConstants, Specialization, Vertex, BINDINGS, SMOOTH_BINDINGS,
    TEXTURED_BINDINGS,
};
use super::raster_samples::{check_samples, SampleDrawing};
use super::raster_scene::{build_geometry, specialization};
use super::shader_catalog::{self as shaders, ShaderBlob};
use super::timestamps::{ms_since, GpuTimings, Timestamps};
use crate::camera::View;
use crate::linear_image::LinearImage;
use crate::scene::{Interpolation, LightingHook, Scene};
use crate::shading::RasterMode;

pub const DEPTH_FORMAT: vk::Format = vk::Format::D32_SFLOAT;

/// The largest value `ColorTarget::ScaledUnorm16` holds.
pub const SCALED_UNORM16_RANGE: f32 = 16.0;

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
    /// 16-bit unsigned-normalised RGBA holding linear values / 16: a
    /// multisampled render for a PNG. Its samples are averaged as linear
    /// values, which an 8-bit sRGB target does not do on lavapipe (5 to 8
    /// steps off at edges, measured); 16-bit floats would, drawn 1.2x
    /// slower there (the 40k sphere at 4 samples, 43 against 35 ms). No
    /// sample is below 0 (`AT_LEAST_ZERO`, raster_output.glsl). The
    /// fragment stages write colour / 16 (`OUTPUT_SCALE`), so every
    /// sample up to 16 keeps its value, and one at 16 or more already
    /// makes the average of up to 16 samples 1 or more, white in a PNG as
    /// it should be; steps of 16/65535 keep the PNG within 1 in 255 of the
    /// 32-bit path's (tests/msaa.rs).
    ScaledUnorm16,
}

impl ColorTarget {
    /// The target whose image `format` stores without loss: 8-bit for PNG.
    pub fn for_output(format: crate::output::ImageFormat) -> Self {
        match format {
            crate::output::ImageFormat::Png => ColorTarget::Srgb8,
            crate::output::ImageFormat::Exr => ColorTarget::Float32,
        }
    }

    /// The target drawn into when `self` is asked for at `msaa`: several
    /// samples are averaged as linear values.
    pub fn drawn_with(self, msaa: crate::msaa::Msaa) -> Self {
        SampleDrawing::of(msaa).target(self)
    }

    /// What the fragment stages multiply their colour by for it
    /// (`OUTPUT_SCALE`), undone on the host.
    pub fn output_scale(self) -> f32 {
        match self {
            ColorTarget::ScaledUnorm16 => 1.0 / SCALED_UNORM16_RANGE,
            _ => 1.0,
        }
    }

    pub fn format(self) -> vk::Format {
        match self {
            ColorTarget::Float32 => vk::Format::R32G32B32A32_SFLOAT,
            ColorTarget::Srgb8 => vk::Format::R8G8B8A8_SRGB,
            ColorTarget::ScaledUnorm16 => vk::Format::R16G16B16A16_UNORM,
        }
    }

    pub(crate) fn bytes_per_pixel(self) -> u64 {
        match self {
            ColorTarget::Float32 => 16,
            ColorTarget::Srgb8 => 4,
            ColorTarget::ScaledUnorm16 => 8,
        }
    }

    /// How reports name it.
    pub fn name(self) -> &'static str {
        match self {
            ColorTarget::Float32 => "rgba32f",
            ColorTarget::Srgb8 => "rgba8-srgb",
            ColorTarget::ScaledUnorm16 => "rgba16-unorm/16",
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

/// What a raster pipeline's shaders take beyond the mode: each a variant
/// of its own (build.rs), so a scene without them compiles none of it.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default)]
pub(crate) struct SurfaceFeatures {
    /// A colour per vertex (flat shading: per face) in a second vertex
    /// stream: vertex colours, and for flat shading the patterns too.
    pub colors: bool,
    /// Texture coordinates in a third vertex stream and a pattern per draw
    /// (Gouraud and Phong; flat shading's is in its face colours).
    pub pattern: bool,
    /// With `pattern`: some pattern is an image, sampled in the fragment
    /// stage from the texture buffers (`gpu::texture_table`).
    pub texture: bool,
}

/// The variant of `base` (`PHONG_FRAG`, ...) with the features it takes.
fn variant(base: &str, screen: bool, colors: bool, pattern: bool) -> &'static ShaderBlob {
    fragment_variant(base, (screen, colors, pattern), false)
}

/// `variant`, and for a fragment stage its `_TEXTURE` variant where it
/// samples images.
fn fragment_variant(
    base: &str,
    (screen, colors, pattern): (bool, bool, bool),
    texture: bool,
) -> &'static ShaderBlob {
    let mut name = base.to_string();
    for (on, suffix) in [
        (screen, "_SCREEN"),
        (colors, "_COLOR"),
        (pattern, "_PATTERN"),
        (texture, "_TEXTURE"),
    ] {
        if on {
            name.push_str(suffix);
        }
    }
    shaders::BY_NAME
        .iter()
        .find(|(n, _)| *n == name)
        .unwrap_or_else(|| panic!("build.rs compiles every raster variant, {name} too"))
        .1
}

fn shader_pair(
    mode: RasterMode,
    interpolation: Interpolation,
    features: SurfaceFeatures,
) -> (&'static ShaderBlob, &'static ShaderBlob) {
    let screen = interpolation == Interpolation::Screen;
    let SurfaceFeatures {
        colors,
        pattern,
        texture,
    } = features;
    match mode {
        RasterMode::Flat => (
            variant("FLAT_VERT", false, colors, false),
            variant("FLAT_FRAG", false, false, false),
        ),
        RasterMode::Gouraud => (
            variant("GOURAUD_VERT", screen, colors, pattern),
            fragment_variant("GOURAUD_FRAG", (screen, false, pattern), texture),
        ),
        RasterMode::Phong => (
            variant("PHONG_VERT", screen, colors, pattern),
            fragment_variant("PHONG_FRAG", (screen, colors, pattern), texture),
        ),
    }
}

/// The descriptor bindings a mode's pipeline uses: only flat shading reads
/// the per-face records, and only Gouraud and Phong the image textures
/// (flat shading's are in its face colours).
pub(crate) fn bindings_of(
    mode: RasterMode,
    features: SurfaceFeatures,
) -> &'static [(u32, vk::DescriptorType)] {
    match mode {
        RasterMode::Flat => BINDINGS,
        RasterMode::Gouraud | RasterMode::Phong if features.texture => TEXTURED_BINDINGS,
        RasterMode::Gouraud | RasterMode::Phong => SMOOTH_BINDINGS,
    }
}

#[allow(clippy::too_many_arguments)]
fn create_pipeline(
    context: &Arc<GpuContext>,
    mode: RasterMode,
    interpolation: Interpolation,
    spec: &Specialization,
    (target, drawing): (ColorTarget, SampleDrawing),
    lighting_hook: Option<&LightingHook>,
    features: SurfaceFeatures,
) -> Result<PipelineObjects, GpuError> {
    let device = &context.device;
    let mut p = PipelineObjects::new(context);
    let stages = vk::ShaderStageFlags::VERTEX | vk::ShaderStageFlags::FRAGMENT;
    p.set_layout = create_set_layout(context, bindings_of(mode, features), stages)?;
    let push_size = if features.pattern {
        std::mem::size_of::<PatternDrawConstants>()
    } else {
        std::mem::size_of::<DrawConstants>()
    };
    let ranges = [vk::PushConstantRange::default()
        .stage_flags(stages)
        .size(push_size as u32)];
    let set_layouts = [p.set_layout];
    let layout_info = vk::PipelineLayoutCreateInfo::default()
        .set_layouts(&set_layouts)
        .push_constant_ranges(&ranges);
    // SAFETY: as above.
    p.layout = unsafe { device.create_pipeline_layout(&layout_info, None) }
        .during("vkCreatePipelineLayout")?;

    let (vert, frag) = shader_pair(mode, interpolation, features);
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
    // Positions (and normals) in stream 0; the colours in stream 1 and the
    // texture coordinates in stream 2 where the variant reads them
    // (`raster_frame`), at the locations the shaders give them.
    let stream = |binding: u32, stride: usize| {
        vk::VertexInputBindingDescription::default()
            .binding(binding)
            .stride(stride as u32)
            .input_rate(vk::VertexInputRate::VERTEX)
    };
    let attribute = |location: u32, binding: u32, format: vk::Format, offset: u32| {
        vk::VertexInputAttributeDescription::default()
            .location(location)
            .binding(binding)
            .format(format)
            .offset(offset)
    };
    let vec3 = vk::Format::R32G32B32_SFLOAT;
    let mut bindings = vec![stream(0, stride)];
    // The flat vertex stage reads positions only (and its face's colour).
    let mut attributes = vec![attribute(0, 0, vec3, 0)];
    if mode != RasterMode::Flat {
        attributes.push(attribute(1, 0, vec3, 12));
    }
    if features.colors {
        bindings.push(stream(1, std::mem::size_of::<[f32; 3]>()));
        let location = if mode == RasterMode::Flat { 1 } else { 2 };
        attributes.push(attribute(location, 1, vec3, 0));
    }
    if features.pattern {
        bindings.push(stream(2, std::mem::size_of::<[f32; 2]>()));
        attributes.push(attribute(3, 2, vk::Format::R32G32_SFLOAT, 0));
    }
    let vertex_input = vk::PipelineVertexInputStateCreateInfo::default()
        .vertex_binding_descriptions(&bindings)
        .vertex_attribute_descriptions(&attributes);
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
    let multisample = vk::PipelineMultisampleStateCreateInfo::default().rasterization_samples(
        vk::SampleCountFlags::from_raw(drawing.rasterization_samples()),
    );
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

pub(crate) fn image_barrier(
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
    image_size_error(context.max_image_dimension(), width, height).map_or(Ok(()), Err)
}

/// Why a `width` x `height` image cannot be rendered on a device whose
/// images hold `side_limit` pixels per side at most, naming the limit it
/// passes: the device's side, or shadelab's cap on the pixel count.
fn image_size_error(side_limit: u32, width: u32, height: u32) -> Option<GpuError> {
    if width == 0 || height == 0 || width > side_limit || height > side_limit {
        return Some(GpuError::ImageTooLarge {
            width,
            height,
            why: format!("this device's limit of {side_limit} pixels per side"),
        });
    }
    let pixels = u64::from(width) * u64::from(height);
    (pixels > MAX_PIXELS).then(|| GpuError::ImageTooLarge {
        width,
        height,
        why: format!("the limit of {MAX_PIXELS} pixels (8192 x 8192) in all ({pixels} asked)"),
    })
}

/// Whether the device renders `msaa`: a count it multisamples, or shaded
/// per sample, a standard count its viewport can be shifted by.
pub fn renders_samples(info: &super::context::DeviceInfo, msaa: crate::msaa::Msaa) -> bool {
    check_samples(info, msaa).is_ok()
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
    let msaa = scene.render.msaa;
    check_samples(&context.info, msaa)?;
    let drawing = SampleDrawing::of(msaa);
    let target = target.drawn_with(msaa);
    let view = View::new(scene, width, height);
    let geometry = build_geometry(scene, &view, mode == RasterMode::Flat);
    let spec = Specialization {
        output_scale: target.output_scale(),
        at_least_zero: u32::from(matches!(drawing, SampleDrawing::Multisampled(_))),
        ..geometry.with_back_faces(specialization(scene))
    };
    let prepare_ms = ms_since(started);

    let pipeline_started = Instant::now();
    let hook = scene.lighting_hook.as_deref();
    let interpolation = scene.lighting.interpolation;
    let features = SurfaceFeatures {
        colors: !geometry.vertex_colors.is_empty() || !geometry.face_colors.is_empty(),
        pattern: !geometry.vertex_uvs.is_empty(),
        texture: !geometry.textures.is_empty(),
    };
    let key = format!(
        "raster {mode:?} {interpolation:?} {target:?} msaa {msaa} spec {:?} hook {:016x} {features:?}",
        bytemuck::bytes_of(&spec),
        crate::cache::digest(&hook.map(|h| &h.source)),
    );
    let pipeline = context.pipelines.get_or_create(key, || {
        create_pipeline(
            context,
            mode,
            interpolation,
            &spec,
            (target, drawing),
            hook,
            features,
        )
    })?;
    let pipeline_ms = ms_since(pipeline_started);

    let upload_started = Instant::now();
    let frame = Frame::new(
        context,
        (scene, &view, &geometry),
        (mode, features),
        (target, drawing),
        &pipeline,
    )?;
    let timestamps = Timestamps::new(context)?;
    let upload_ms = ms_since(upload_started);

    let commands = OneShot::begin(context)?;
    // SAFETY: the frame, the pipeline and the timestamps live until after
    // the submission completes (they are dropped at the end of this
    // function).
    unsafe {
        frame.record(
            &context.device,
            commands.cmd,
            &pipeline,
            (scene, &view, &geometry),
            &timestamps,
        );
    }
    let (submit_ms, gpu_ms) = timestamps.submit_and_measure(&commands)?;

    let readback_started = Instant::now();
    let image = frame.image();
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

#[cfg(test)]
mod size_tests {
    use super::*;

    /// The message names the limit that was passed (issue 30: 16384x4200
    /// was refused as over "8192 pixels per side" while 16384x2 renders).
    #[test]
    fn the_refusal_names_the_limit_passed() {
        let long = image_size_error(16384, 16384, 4200).unwrap().to_string();
        assert!(
            long.contains("67108864 pixels (8192 x 8192) in all"),
            "{long}"
        );
        assert!(!long.contains("per side"), "{long}");
        assert!(image_size_error(16384, 16384, 2).is_none());
        let wide = image_size_error(16384, 20000, 2).unwrap().to_string();
        assert!(wide.contains("16384 pixels per side"), "{wide}");
        assert!(image_size_error(16384, 8192, 8192).is_none());
    }
}
