//! Each pipeline's host-side interface (descriptor bindings, record sizes,
//! push constants, specialization constants) against naga's reflection of
//! its compiled shaders, so a shader edit that the host does not follow (or
//! the reverse) fails here instead of as undefined behaviour on a device.
//! The raster stages answer to `raster::layout`, the ray-tracing compute
//! shader to `raytrace::layout`.

use ash::vk;
use rt_layout::TraceSpecialization;
use shadelab::gpu::raster::layout as raster_layout;
use shadelab::gpu::raytrace::caustics;
use shadelab::gpu::raytrace::forward::{PhotonBatch, PHOTONS_PER_LANE};
use shadelab::gpu::raytrace::layout as rt_layout;
use shadelab::gpu::shared::shader_catalog::{
    BindingKind, ShaderBlob, ShaderStage, ALL_SHADERS, INCLUDES,
};
use std::mem::offset_of;

/// What the host declares for one pipeline family.
struct HostInterface {
    bindings: &'static [(u32, vk::DescriptorType)],
    record_size: fn(u32) -> usize,
    spec_constants: &'static [(u16, &'static str)],
    push_constant_size: u32,
}

/// Flat shading's stages bind all of the raster set; Gouraud's and
/// Phong's the part without the faces, and with image textures
/// (`TEXTURE`) the texture buffers too. The variants with a pattern push
/// its constants after the draw's.
fn host_for(shader: &ShaderBlob) -> HostInterface {
    let patterned = shader.defines.iter().any(|(d, _)| *d == "PATTERN");
    let textured = shader.defines.iter().any(|(d, _)| *d == "TEXTURE");
    let push_constant_size = if patterned {
        std::mem::size_of::<raster_layout::PatternDrawConstants>()
    } else {
        std::mem::size_of::<raster_layout::DrawConstants>()
    } as u32;
    let raster = |bindings| HostInterface {
        bindings,
        record_size: raster_layout::record_size,
        spec_constants: raster_layout::SPEC_CONSTANTS,
        push_constant_size,
    };
    let forward = shader.defines.iter().any(|(d, _)| *d == "FORWARD");
    let paths = shader.defines.iter().any(|(d, _)| *d == "PATHS");
    match shader.stage {
        ShaderStage::Compute if shader.name.starts_with("caustics.") => HostInterface {
            bindings: rt_layout::BINDINGS,
            record_size: rt_layout::forward_record_size,
            spec_constants: rt_layout::SPEC_CONSTANTS,
            push_constant_size: std::mem::size_of::<caustics::CausticPass>() as u32,
        },
        ShaderStage::Compute if forward => HostInterface {
            bindings: rt_layout::BINDINGS,
            record_size: rt_layout::forward_record_size,
            spec_constants: rt_layout::SPEC_CONSTANTS,
            push_constant_size: std::mem::size_of::<PhotonBatch>() as u32,
        },
        ShaderStage::Compute if paths => HostInterface {
            bindings: rt_layout::BINDINGS,
            record_size: rt_layout::paths_record_size,
            spec_constants: rt_layout::SPEC_CONSTANTS,
            push_constant_size: std::mem::size_of::<rt_layout::SampleRange>() as u32,
        },
        ShaderStage::Compute => HostInterface {
            bindings: rt_layout::BINDINGS,
            record_size: rt_layout::record_size,
            spec_constants: rt_layout::SPEC_CONSTANTS,
            push_constant_size: 0,
        },
        _ if shader.name.starts_with("flat.") => raster(raster_layout::BINDINGS),
        ShaderStage::Fragment if textured => raster(raster_layout::TEXTURED_BINDINGS),
        ShaderStage::Vertex | ShaderStage::Fragment => raster(raster_layout::SMOOTH_BINDINGS),
    }
}

fn host_kind(ty: vk::DescriptorType) -> BindingKind {
    match ty {
        vk::DescriptorType::UNIFORM_BUFFER => BindingKind::UniformBuffer,
        vk::DescriptorType::STORAGE_BUFFER => BindingKind::StorageBuffer,
        _ => BindingKind::Other,
    }
}

#[test]
fn every_shader_binding_is_declared_by_the_host_with_the_same_type_and_record() {
    let mut used: Vec<(*const (u32, vk::DescriptorType), u32)> = Vec::new();
    for shader in ALL_SHADERS {
        let host = host_for(shader);
        for b in shader.bindings {
            let ray_query = shader.defines.iter().any(|(d, _)| *d == "RAY_QUERY");
            if shader.name.starts_with("caustics.") && b.set == 1 {
                // The photon map's set (gpu::raytrace::caustics::map).
                let (binding, ty) = caustics::MAP_BINDINGS[b.binding as usize];
                assert_eq!(b.binding, binding, "{}", shader.name);
                assert_eq!(host_kind(ty), b.kind, "{}", shader.name);
                assert_eq!(
                    caustics::MAP_RECORD_SIZES[b.binding as usize],
                    b.record_size as usize,
                    "{}: map binding {} record size",
                    shader.name,
                    b.binding
                );
                continue;
            }
            if b.set == rt_layout::QUERY_SET && ray_query {
                // The ray-query engine's second set: its structure alone.
                let (binding, ty) = rt_layout::QUERY_BINDINGS[0];
                assert_eq!(b.binding, binding, "{}", shader.name);
                assert_eq!(host_kind(ty), b.kind, "{}", shader.name);
                assert_eq!(rt_layout::QUERY_BINDINGS.len(), 1);
                continue;
            }
            assert_eq!(b.set, 0, "{}: only set 0 exists on the host", shader.name);
            let Some(&(_, ty)) = host
                .bindings
                .iter()
                .find(|(binding, _)| *binding == b.binding)
            else {
                panic!(
                    "{}: binding {} is not in the host layout",
                    shader.name, b.binding
                );
            };
            assert_eq!(
                host_kind(ty),
                b.kind,
                "{}: binding {} type",
                shader.name,
                b.binding
            );
            assert_eq!(
                (host.record_size)(b.binding),
                b.record_size as usize,
                "{}: binding {} record size (host struct vs shader std430 layout)",
                shader.name,
                b.binding
            );
            used.push((host.bindings.as_ptr(), b.binding));
        }
    }
    for family in [raster_layout::BINDINGS, rt_layout::BINDINGS] {
        for (binding, _) in family {
            assert!(
                used.contains(&(family.as_ptr(), *binding)),
                "host binding {binding} is used by no shader of its pipeline"
            );
        }
    }
}

#[test]
fn push_constant_blocks_have_the_hosts_size() {
    // A stage that declares no push-constant block is skipped; every stage
    // that declares one must match. The raster stages all declare theirs.
    let mut compared = 0;
    for shader in ALL_SHADERS {
        let host = host_for(shader);
        if shader.push_constant_size > 0 || host.push_constant_size == 0 {
            assert_eq!(
                shader.push_constant_size, host.push_constant_size,
                "{}",
                shader.name
            );
            compared += 1;
        }
    }
    assert!(compared >= 6, "only {compared} stages compared");
}

/// Each ray-tracing specialization constant's name and the offset of the
/// `TraceSpecialization` field that holds it.
fn trace_specialization_fields() -> Vec<(&'static str, usize)> {
    vec![
        ("LIGHT_COUNT", offset_of!(TraceSpecialization, light_count)),
        (
            "USE_SPECULAR",
            offset_of!(TraceSpecialization, use_specular),
        ),
        (
            "USE_ATTENUATION",
            offset_of!(TraceSpecialization, use_attenuation),
        ),
        ("SHADOWS", offset_of!(TraceSpecialization, shadows)),
        (
            "HAS_REFLECTION",
            offset_of!(TraceSpecialization, has_reflection),
        ),
        (
            "HAS_TRANSMISSION",
            offset_of!(TraceSpecialization, has_transmission),
        ),
        (
            "SPHERE_COUNT",
            offset_of!(TraceSpecialization, sphere_count),
        ),
        ("PLANE_COUNT", offset_of!(TraceSpecialization, plane_count)),
        ("BOX_COUNT", offset_of!(TraceSpecialization, box_count)),
        ("HAS_BVH", offset_of!(TraceSpecialization, has_bvh)),
        ("COUNT_RAYS", offset_of!(TraceSpecialization, count_rays)),
        ("BVH_SPHERES", offset_of!(TraceSpecialization, bvh_spheres)),
        ("BVH_PLANES", offset_of!(TraceSpecialization, bvh_planes)),
        ("BVH_BOXES", offset_of!(TraceSpecialization, bvh_boxes)),
        (
            "MATERIALS_LISTED",
            offset_of!(TraceSpecialization, materials_listed),
        ),
        (
            "MATERIAL_COUNT",
            offset_of!(TraceSpecialization, material_count),
        ),
        (
            "VERTEX_COLORS",
            offset_of!(TraceSpecialization, vertex_colors),
        ),
        ("PATTERNS", offset_of!(TraceSpecialization, patterns)),
        ("TEXTURES", offset_of!(TraceSpecialization, textures)),
        (
            "SAMPLER_FIXED",
            offset_of!(TraceSpecialization, sampler_fixed),
        ),
        (
            "FIXED_SAMPLER",
            offset_of!(TraceSpecialization, fixed_sampler),
        ),
        (
            "HUGE_SPHERE_COUNT",
            offset_of!(TraceSpecialization, huge_sphere_count),
        ),
        (
            "INVERSE_SQUARE",
            offset_of!(TraceSpecialization, inverse_square),
        ),
    ]
}

#[test]
fn specialization_constants_match_by_id_and_name() {
    for shader in ALL_SHADERS {
        let host = host_for(shader);
        for spec in shader.spec_constants {
            assert!(
                host.spec_constants.contains(spec),
                "{}: specialization constant {spec:?} unknown to the host",
                shader.name
            );
        }
    }
    // One 4-byte value per constant, in order, as the map entries say.
    assert_eq!(
        std::mem::size_of::<raster_layout::Specialization>(),
        4 * raster_layout::SPEC_CONSTANTS.len()
    );
    assert_eq!(
        std::mem::size_of::<rt_layout::TraceSpecialization>(),
        4 * rt_layout::SPEC_CONSTANTS.len()
    );
    let raster = raster_layout::Specialization::map_entries();
    assert_eq!(raster.len(), raster_layout::SPEC_CONSTANTS.len());
    assert_eq!(
        std::mem::size_of::<raster_layout::Specialization>(),
        4 * raster.len()
    );
    for (entry, (id, _)) in raster.iter().zip(raster_layout::SPEC_CONSTANTS) {
        assert_eq!(entry.constant_id, u32::from(*id));
    }
    // Each field sits where its constant's map entry says: the field named
    // like the constant is at 4 x the constant's place in the list.
    let traced = rt_layout::TraceSpecialization::map_entries();
    let fields = trace_specialization_fields();
    assert_eq!(fields.len(), rt_layout::SPEC_CONSTANTS.len());
    for (name, offset) in fields {
        let index = rt_layout::SPEC_CONSTANTS
            .iter()
            .position(|(_, n)| *n == name)
            .unwrap_or_else(|| panic!("{name} is not a ray-tracing constant"));
        assert_eq!(traced[index].offset as usize, offset, "{name}");
    }
    // The shared constants mean the same in both pipelines.
    assert_eq!(
        &rt_layout::SPEC_CONSTANTS[..3],
        &raster_layout::SPEC_CONSTANTS[..3]
    );
    assert_eq!(
        rt_layout::SPEC_CONSTANTS.last(),
        raster_layout::SPEC_CONSTANTS.last(),
        "lights.glsl's INVERSE_SQUARE, last in both"
    );
}

#[test]
fn every_stage_is_present() {
    let count = |stage| ALL_SHADERS.iter().filter(|s| s.stage == stage).count();
    assert_eq!(
        (
            count(ShaderStage::Vertex),
            count(ShaderStage::Fragment),
            count(ShaderStage::Compute)
        ),
        // Every subset of the features each stage takes (build.rs): flat's
        // vertex stage with and without face colours, Gouraud's and Phong's
        // with each of screen-linear, vertex colours and a pattern; flat's
        // fragment stage alone, Gouraud's with screen-linear and a pattern,
        // Phong's with all three; and the two smooth fragment stages'
        // pattern variants again with image textures (2 and 4 of them).
        // (Per-sample MSAA is a pass per sample: no variant of its own.)
        // The ray tracer: the binary and the 4-wide BVH walk and ray
        // queries, and the three again with diffuse bounces (PATHS); the
        // 4-wide walk with two eye rays a lane (PAIRED); the forward tracer
        // and the photon map's caustics on the binary and the 4-wide walk.
        (2 + 8 + 8, 1 + (4 + 2) + (8 + 4), 3 + 3 + 1 + 2 + 2)
    );
    // The second ray tracer is the ray-query engine, and it has its set.
    assert!(ALL_SHADERS.iter().any(|s| {
        s.defines.iter().any(|(d, _)| *d == "RAY_QUERY")
            && s.bindings.iter().any(|b| b.set == rt_layout::QUERY_SET)
    }));
    for s in ALL_SHADERS {
        assert_eq!(
            &s.spirv[..4],
            &0x0723_0203u32.to_le_bytes(),
            "{}: SPIR-V magic",
            s.name
        );
    }
}

/// The host refuses a BVH deeper than the shader's traversal stack, tests
/// one by one no more of a kind's objects than the shader's arrays of them
/// hold (the rest go into the BVH), and sizes its dispatch by the shader's
/// workgroup and work item; the constants must agree (the shader's are
/// plain `const`s and a layout qualifier, not reflected). build.rs writes
/// them from the host's (`gpu::raytrace::kernel_sizes`) into the kernels'
/// `kernel_sizes.glsl` and their defines: this holds it to having done so.
#[test]
fn the_bvh_stack_size_listed_objects_and_work_item_are_the_shaders() {
    let sizes = INCLUDES
        .iter()
        .find(|(name, _)| *name == "kernel_sizes.glsl")
        .expect("build.rs writes kernel_sizes.glsl")
        .1;
    let prelude = INCLUDES
        .iter()
        .find(|(name, _)| *name == "rt_kernel.glsl")
        .expect("the kernels' prelude")
        .1;
    assert!(prelude.contains("layout(local_size_x = WORKGROUP_SIZE,"));
    let workgroup = rt_layout::WORKGROUP_SIZE.to_string();
    for kernel in ALL_SHADERS
        .iter()
        .filter(|s| s.stage == ShaderStage::Compute)
    {
        assert!(
            kernel.source.contains("#include \"rt_kernel.glsl\""),
            "{} does not start with the prelude",
            kernel.name
        );
        assert!(
            kernel
                .defines
                .contains(&("WORKGROUP_SIZE", Some(workgroup.as_str()))),
            "{} is not compiled with WORKGROUP_SIZE {workgroup}",
            kernel.name
        );
    }
    for declared in [
        format!("const uint PHOTONS_PER_LANE = {PHOTONS_PER_LANE}u;"),
        format!("const uint CAUSTIC_PER_LANE = {}u;", caustics::PER_LANE),
        format!("const int BVH_STACK_SIZE = {};", rt_layout::BVH_STACK_SIZE),
        format!("const uint ITEM_PACKETS = {}u;", rt_layout::ITEM_PACKETS),
        format!(
            "const int UNROLLED_SPHERES = {};",
            rt_layout::UNROLLED_SPHERES
        ),
        format!(
            "const int UNROLLED_PLANES = {};",
            rt_layout::UNROLLED_PLANES
        ),
        format!("const int UNROLLED_BOXES = {};", rt_layout::UNROLLED_BOXES),
        format!(
            "const int UNROLLED_MATERIALS = {};",
            rt_layout::UNROLLED_MATERIALS
        ),
    ] {
        assert!(
            sizes.contains(&declared),
            "kernel_sizes.glsl lacks `{declared}`"
        );
    }
}

/// Spheres, planes, boxes, triangles and BVH nodes are read as quads of words
/// (so that a subgroup can share a record), which naga's reflection cannot
/// see into: the shader names each field's word offset in a constant, held
/// here to the host's record layout.
#[test]
fn quad_records_have_the_hosts_word_offsets() {
    use rt_layout::{
        GpuBox, GpuBvhChild, GpuBvhNode, GpuPlane, GpuSphere, GpuTriangleGeometry, GpuWideNode,
    };
    use std::mem::size_of;
    let source = include_str!("../../shaders/include/rt_interface.glsl");
    let constant = |name: &str| -> usize {
        let prefix = format!("const uint {name} = ");
        let line = source
            .lines()
            .find_map(|l| l.trim().strip_prefix(prefix.as_str()))
            .unwrap_or_else(|| panic!("rt_interface.glsl lacks `{prefix}`"));
        let digits: String = line.chars().take_while(char::is_ascii_digit).collect();
        digits.parse().unwrap()
    };
    let word = |byte_offset: usize| byte_offset / 4;
    // A shared record is held in two quads a lane, and the host allows
    // subgroups of 4 lanes: no record may have more than 8 quads.
    let quads = |name: &str, size: usize| {
        assert_eq!(constant(name) * 16, size, "{name}");
        assert!(constant(name) <= 8, "{name}: more quads than 4 lanes hold");
    };
    quads("SPHERE_QUADS", size_of::<GpuSphere>());
    quads("PLANE_QUADS", size_of::<GpuPlane>());
    quads("BOX_QUADS", size_of::<GpuBox>());
    quads("TRI_QUADS", size_of::<GpuTriangleGeometry>());
    quads("NODE_QUADS", size_of::<GpuBvhNode>());
    quads("WIDE_NODE_QUADS", size_of::<GpuWideNode>());
    assert_eq!(constant("CHILD_WORDS") * 4, size_of::<GpuBvhChild>());
    assert_eq!(size_of::<GpuBvhNode>(), 2 * size_of::<GpuBvhChild>());
    assert_eq!(size_of::<GpuWideNode>(), 4 * size_of::<GpuBvhChild>());
    let checks = [
        ("SPHERE_CENTER", word(offset_of!(GpuSphere, center_radius))),
        (
            "SPHERE_RADIUS",
            word(offset_of!(GpuSphere, center_radius)) + 3,
        ),
        (
            "SPHERE_MATERIAL",
            word(offset_of!(GpuSphere, material_object)),
        ),
        (
            "SPHERE_OBJECT",
            word(offset_of!(GpuSphere, material_object)) + 1,
        ),
        ("PLANE_CENTER", word(offset_of!(GpuPlane, center_half))),
        ("PLANE_HALF", word(offset_of!(GpuPlane, center_half)) + 3),
        ("PLANE_NORMAL", word(offset_of!(GpuPlane, normal))),
        ("PLANE_U", word(offset_of!(GpuPlane, u))),
        ("PLANE_V", word(offset_of!(GpuPlane, v))),
        (
            "PLANE_MATERIAL",
            word(offset_of!(GpuPlane, material_object)),
        ),
        (
            "PLANE_OBJECT",
            word(offset_of!(GpuPlane, material_object)) + 1,
        ),
        ("BOX_CENTER", word(offset_of!(GpuBox, center))),
        ("BOX_HALF", word(offset_of!(GpuBox, half_extents))),
        ("BOX_AXIS_X", word(offset_of!(GpuBox, axis_x))),
        ("BOX_AXIS_Y", word(offset_of!(GpuBox, axis_y))),
        ("BOX_AXIS_Z", word(offset_of!(GpuBox, axis_z))),
        ("BOX_MATERIAL", word(offset_of!(GpuBox, material_object))),
        ("BOX_OBJECT", word(offset_of!(GpuBox, material_object)) + 1),
        ("BOX_FACE_U", word(offset_of!(GpuBox, material_object)) + 2),
        ("BOX_FACE_V", word(offset_of!(GpuBox, material_object)) + 3),
        ("TRI_X", word(offset_of!(GpuTriangleGeometry, x))),
        ("TRI_INDEX", word(offset_of!(GpuTriangleGeometry, index))),
        ("TRI_Y", word(offset_of!(GpuTriangleGeometry, y))),
        ("TRI_OBJECT", word(offset_of!(GpuTriangleGeometry, object))),
        ("TRI_Z", word(offset_of!(GpuTriangleGeometry, z))),
        ("CHILD_LO", word(offset_of!(GpuBvhChild, lo))),
        ("CHILD_LINK", word(offset_of!(GpuBvhChild, link))),
        ("CHILD_HI", word(offset_of!(GpuBvhChild, hi))),
    ];
    // The triangle test shuffles axis k's coordinates from lane
    // TRI_X / 4 + k (`sheared_corner`): the axes must be whole, consecutive
    // quads, their corners in words 0 to 2.
    assert_eq!(constant("TRI_X") % 4, 0);
    assert_eq!(constant("TRI_Y"), constant("TRI_X") + 4);
    assert_eq!(constant("TRI_Z"), constant("TRI_Y") + 4);
    for (name, expected) in checks {
        assert_eq!(constant(name), expected, "{name}");
    }
    // A leaf link packs its count less one and its first triangle.
    let link = rt_layout::leaf_link(12345, 7);
    assert_eq!(link & rt_layout::LEAF_BIT, rt_layout::LEAF_BIT);
    assert_eq!((link >> 26) & 31, 6);
    assert_eq!(link & 0x03ff_ffff, 12345);
}
