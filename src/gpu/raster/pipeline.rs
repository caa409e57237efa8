//! The raster pipelines, one per (mode, interpolation, features,
//! specialization, target): which compiled shader variants a mode takes,
//! the descriptor bindings it reads, and the fixed-function state it draws
//! with.

use std::sync::Arc;

use ash::vk;

use crate::gpu::raster::layout::{
    DrawConstants, PatternDrawConstants, Specialization, Vertex, BINDINGS, SMOOTH_BINDINGS,
    TEXTURED_BINDINGS,
};
use crate::gpu::raster::samples::SampleDrawing;
use crate::gpu::raster::target::{ColorTarget, DEPTH_FORMAT};
use crate::gpu::shared::hook;
use crate::gpu::shared::shader_catalog::{self as shaders, ShaderBlob};
use crate::gpu::vk::context::GpuContext;
use crate::gpu::vk::descriptors::create_set_layout;
use crate::gpu::vk::error::{GpuError, VkContext};
use crate::gpu::vk::pipeline::{single_pipeline, PipelineObjects};
use crate::scene::{Interpolation, LightingHook};
use crate::shading::RasterMode;

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
    /// stage from the texture buffers (`gpu::shared::texture_table`).
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

/// The pipeline that draws `mode` with `features` into `target`: its
/// layout, its two shader stages specialised with `spec` (and the
/// lighting hook compiled in), its vertex streams and the fixed-function
/// state.
#[allow(clippy::too_many_arguments)]
pub(crate) fn create_pipeline(
    context: &Arc<GpuContext>,
    mode: RasterMode,
    interpolation: Interpolation,
    spec: &Specialization,
    (target, drawing): (ColorTarget, SampleDrawing),
    lighting_hook: Option<&LightingHook>,
    features: SurfaceFeatures,
) -> Result<PipelineObjects, GpuError> {
    let mut p = PipelineObjects::new(&context.device);
    create_layout(context, &mut p, mode, features)?;
    let shaders = shader_pair(mode, interpolation, features);
    create_modules(context, &mut p, shaders, lighting_hook)?;
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
    let (bindings, attributes) = vertex_streams(mode, features);
    let vertex_input = vk::PipelineVertexInputStateCreateInfo::default()
        .vertex_binding_descriptions(&bindings)
        .vertex_attribute_descriptions(&attributes);
    p.pipeline = create_graphics_pipeline(
        &context.device,
        (&stage_infos, &vertex_input),
        p.layout,
        (target, drawing),
    )?;
    Ok(p)
}

/// `p`'s descriptor set layout (the bindings `mode` reads) and its
/// pipeline layout, with room for the draw constants `features` push.
fn create_layout(
    context: &Arc<GpuContext>,
    p: &mut PipelineObjects,
    mode: RasterMode,
    features: SurfaceFeatures,
) -> Result<(), GpuError> {
    let device = &context.device;
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
    // SAFETY: valid device and create info.
    p.layout = unsafe { device.create_pipeline_layout(&layout_info, None) }
        .during("vkCreatePipelineLayout")?;
    Ok(())
}

/// The vertex and fragment modules of `(vert, frag)`, with the lighting
/// hook where there is one, kept in `p.modules` in that order.
fn create_modules(
    context: &Arc<GpuContext>,
    p: &mut PipelineObjects,
    (vert, frag): (&ShaderBlob, &ShaderBlob),
    lighting_hook: Option<&LightingHook>,
) -> Result<(), GpuError> {
    for blob in [vert, frag] {
        let words = hook::module_words(blob, lighting_hook, &context.info)?;
        let info = vk::ShaderModuleCreateInfo::default().code(&words);
        // SAFETY: the words are SPIR-V validated by naga (at build time, or
        // with the hook by `hook::module_words`).
        let module = unsafe { context.device.create_shader_module(&info, None) }
            .during("vkCreateShaderModule")?;
        p.modules.push(module);
    }
    Ok(())
}

/// The vertex streams (bindings) and attributes `mode`'s vertex stage
/// reads with `features`.
fn vertex_streams(
    mode: RasterMode,
    features: SurfaceFeatures,
) -> (
    Vec<vk::VertexInputBindingDescription>,
    Vec<vk::VertexInputAttributeDescription>,
) {
    // Flat draws read positions alone, one vertex of its own per triangle
    // (`flat`).
    let stride = if mode == RasterMode::Flat {
        std::mem::size_of::<[f32; 3]>()
    } else {
        std::mem::size_of::<Vertex>()
    };
    // Positions (and normals) in stream 0; the colours in stream 1 and the
    // texture coordinates in stream 2 where the variant reads them
    // (`frame`), at the locations the shaders give them.
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
    (bindings, attributes)
}

/// The graphics pipeline of `stages` reading `vertex_input`, in `layout`,
/// with the fixed-function state every raster mode draws with: triangle
/// lists, a dynamic viewport and scissor, culling set per draw, reversed
/// Z, no blending, into `target` at `drawing`'s samples and the depth
/// format.
fn create_graphics_pipeline(
    device: &ash::Device,
    (stages, vertex_input): (
        &[vk::PipelineShaderStageCreateInfo],
        &vk::PipelineVertexInputStateCreateInfo,
    ),
    layout: vk::PipelineLayout,
    (target, drawing): (ColorTarget, SampleDrawing),
) -> Result<vk::Pipeline, GpuError> {
    let assembly = vk::PipelineInputAssemblyStateCreateInfo::default()
        .topology(vk::PrimitiveTopology::TRIANGLE_LIST);
    let viewport = vk::PipelineViewportStateCreateInfo::default()
        .viewport_count(1)
        .scissor_count(1);
    // Culling is set per draw (dynamic state): only where back faces cannot
    // show (`cull`); planes and open meshes keep both sides, as in the
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
        .stages(stages)
        .vertex_input_state(vertex_input)
        .input_assembly_state(&assembly)
        .viewport_state(&viewport)
        .rasterization_state(&raster)
        .multisample_state(&multisample)
        .depth_stencil_state(&depth)
        .color_blend_state(&blend)
        .dynamic_state(&dynamic)
        .layout(layout)
        .push_next(&mut rendering);
    // SAFETY: every pointer in `info` refers to locals alive for the call.
    let created =
        unsafe { device.create_graphics_pipelines(vk::PipelineCache::null(), &[info], None) };
    single_pipeline(created, "vkCreateGraphicsPipelines")
}
