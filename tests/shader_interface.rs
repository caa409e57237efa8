//! The host's descriptor layout, push-constant block and specialization
//! constants against naga's reflection of every compiled raster shader, so a
//! shader edit that the host does not follow (or the reverse) fails here
//! instead of as undefined behaviour on a device.

use ash::vk;
use shadelab::gpu::raster_layout::{self, DrawConstants, Specialization, BINDINGS, SPEC_CONSTANTS};
use shadelab::gpu::shader_catalog::{BindingKind, ShaderStage, ALL_SHADERS};

fn host_kind(ty: vk::DescriptorType) -> BindingKind {
    match ty {
        vk::DescriptorType::UNIFORM_BUFFER => BindingKind::UniformBuffer,
        vk::DescriptorType::STORAGE_BUFFER => BindingKind::StorageBuffer,
        _ => BindingKind::Other,
    }
}

#[test]
fn every_shader_binding_is_declared_by_the_host_with_the_same_type() {
    let mut used = std::collections::HashSet::new();
    for shader in ALL_SHADERS {
        for b in shader.bindings {
            assert_eq!(b.set, 0, "{}: only set 0 exists on the host", shader.name);
            let host = BINDINGS.iter().find(|(binding, _)| *binding == b.binding);
            let Some(&(_, ty)) = host else {
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
                raster_layout::record_size(b.binding),
                b.record_size as usize,
                "{}: binding {} record size (host struct vs shader std430 layout)",
                shader.name,
                b.binding
            );
            used.insert(b.binding);
        }
    }
    for (binding, _) in BINDINGS {
        assert!(
            used.contains(binding),
            "host binding {binding} is used by no shader"
        );
    }
}

#[test]
fn push_constant_block_has_the_hosts_size() {
    let host = std::mem::size_of::<DrawConstants>() as u32;
    let mut seen = 0;
    for shader in ALL_SHADERS.iter().filter(|s| s.push_constant_size > 0) {
        assert_eq!(shader.push_constant_size, host, "{}", shader.name);
        seen += 1;
    }
    assert!(seen >= 6, "the raster shaders declare push constants");
}

#[test]
fn specialization_constants_match_by_id_and_name() {
    for shader in ALL_SHADERS {
        for spec in shader.spec_constants {
            assert!(
                SPEC_CONSTANTS.contains(spec),
                "{}: specialization constant {spec:?} unknown to the host",
                shader.name
            );
        }
    }
    // One 4-byte value per constant, as the map entries say.
    assert_eq!(
        std::mem::size_of::<Specialization>(),
        4 * SPEC_CONSTANTS.len()
    );
    let entries = Specialization::map_entries();
    for (entry, (id, _)) in entries.iter().zip(SPEC_CONSTANTS) {
        assert_eq!(entry.constant_id, u32::from(*id));
    }
}

#[test]
fn every_stage_is_present() {
    let vertex = ALL_SHADERS
        .iter()
        .filter(|s| s.stage == ShaderStage::Vertex)
        .count();
    let fragment = ALL_SHADERS
        .iter()
        .filter(|s| s.stage == ShaderStage::Fragment)
        .count();
    assert_eq!((vertex, fragment), (5, 5));
    for s in ALL_SHADERS {
        assert_eq!(
            &s.spirv[..4],
            &0x0723_0203u32.to_le_bytes(),
            "{}: SPIR-V magic",
            s.name
        );
    }
}
