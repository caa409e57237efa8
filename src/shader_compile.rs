//! GLSL to validated SPIR-V and its reflection: glslang compiles (through
//! shaderc, Google's front end to it, linked from the system's
//! `libshaderc-dev`), naga parses, validates and reflects. Shared by
//! build.rs (the built-in shaders, through `#[path]`) and
//! `gpu::shared::hook` (the built-in shaders with a user's lighting hook,
//! at run time), so both go through the same steps. Depends on shaderc and
//! naga alone.

pub use shaderc::ShaderKind as Stage;
// Debian's shaderc leaves glslang and SPIRV-Tools to its user to link.
use system_glslang as _;

/// Where `#include "name"` finds its text: `(name to report, text)`.
pub type Include<'a> = dyn Fn(&str) -> Option<(String, String)> + 'a;

/// Compiles `text` (reported as `name`) for `stage` with `defines`.
/// The error is glslang's log, which names the file and line of each
/// message.
pub fn compile(
    text: &str,
    name: &str,
    stage: Stage,
    defines: &[(&str, Option<&str>)],
    include: &Include<'_>,
) -> Result<Vec<u32>, String> {
    let compiler =
        shaderc::Compiler::new().map_err(|e| format!("glslang could not be initialised: {e}"))?;
    let mut options = shaderc::CompileOptions::new()
        .map_err(|e| format!("glslang's options could not be made: {e}"))?;
    options.set_source_language(shaderc::SourceLanguage::GLSL);
    options.set_target_env(
        shaderc::TargetEnv::Vulkan,
        shaderc::EnvVersion::Vulkan1_3 as u32,
    );
    options.set_target_spirv(shaderc::SpirvVersion::V1_6);
    for (define, value) in defines {
        options.add_macro_definition(define, *value);
    }
    options.set_include_callback(|requested, _kind, _from, _depth| {
        include(requested)
            .map(|(resolved_name, content)| shaderc::ResolvedInclude {
                resolved_name,
                content,
            })
            .ok_or_else(|| format!("no include file {requested:?}"))
    });
    let artifact = compiler
        .compile_into_spirv(text, stage, name, "main", Some(&options))
        .map_err(log_of)?;
    let mut words = artifact.as_binary().to_vec();
    local_size_by_value(&mut words);
    Ok(words)
}

/// A module's instructions after its five-word header, as `(index of the
/// first word, opcode, word count)`; an error, and then nothing, at the
/// first one whose word count is zero or runs past the end. The one walk
/// over SPIR-V words that build.rs, the lighting hook and the specialiser
/// all use.
pub fn instructions(
    words: &[u32],
) -> impl Iterator<Item = Result<(usize, u32, usize), String>> + '_ {
    let mut at = 5;
    std::iter::from_fn(move || {
        let word = *words.get(at)?;
        let (count, opcode) = ((word >> 16) as usize, word & 0xffff);
        if count == 0 || at + count > words.len() {
            let error = format!("a malformed instruction at word {at}");
            at = words.len();
            return Some(Err(error));
        }
        let instruction = (at, opcode, count);
        at += count;
        Some(Ok(instruction))
    })
}

/// Rewrites `OpExecutionModeId LocalSizeId` whose sizes are plain
/// constants into the `OpExecutionMode LocalSize` they mean, in place (both
/// are six words). glslang 12 (Debian 12's) writes the first for SPIR-V 1.6
/// and glslang 15 the second; naga reads only the second.
fn local_size_by_value(words: &mut [u32]) {
    const OP_CONSTANT: u32 = 43;
    const OP_EXECUTION_MODE: u32 = 16;
    const OP_EXECUTION_MODE_ID: u32 = 331;
    const LOCAL_SIZE: u32 = 17;
    const LOCAL_SIZE_ID: u32 = 38;
    let mut constants = std::collections::HashMap::new();
    let mut modes = Vec::new();
    // A malformed module is left as it is: naga will say what is wrong.
    for (at, opcode, count) in instructions(words).map_while(Result::ok) {
        if opcode == OP_CONSTANT && count == 4 {
            constants.insert(words[at + 2], words[at + 3]);
        }
        if opcode == OP_EXECUTION_MODE_ID && count == 6 && words[at + 2] == LOCAL_SIZE_ID {
            modes.push(at);
        }
    }
    for at in modes {
        let sizes: Option<Vec<u32>> = (3..6)
            .map(|i| constants.get(&words[at + i]).copied())
            .collect();
        if let Some(sizes) = sizes {
            words[at] = (6 << 16) | OP_EXECUTION_MODE;
            words[at + 2] = LOCAL_SIZE;
            words[at + 3..at + 6].copy_from_slice(&sizes);
        }
    }
}

/// glslang's own messages, without shaderc's framing.
fn log_of(e: shaderc::Error) -> String {
    match e {
        shaderc::Error::CompilationError(_, log) => log,
        other => other.to_string(),
    }
}

#[derive(Clone, Copy)]
pub struct Binding {
    pub set: u32,
    pub binding: u32,
    /// `UniformBuffer`, `StorageBuffer` or `Other`.
    pub kind: &'static str,
    /// Byte stride of a runtime-array buffer's records, else the block size.
    pub record_size: u32,
}

pub struct Reflection {
    /// By (set, binding).
    pub bindings: Vec<Binding>,
    /// 0 when there is no push-constant block.
    pub push_constant_size: u32,
    /// By id.
    pub spec_constants: Vec<(u16, String)>,
}

/// The stride of a block's trailing runtime array, or the block's size.
fn record_size(module: &naga::Module, ty: naga::Handle<naga::Type>) -> u32 {
    if let naga::TypeInner::Struct { members, .. } = &module.types[ty].inner {
        if let Some(last) = members.last() {
            if let naga::TypeInner::Array {
                size: naga::ArraySize::Dynamic,
                stride,
                ..
            } = module.types[last.ty].inner
            {
                return stride;
            }
        }
    }
    module.types[ty].inner.size(module.to_ctx())
}

/// Parses and validates `spirv` with naga and reflects its interface.
pub fn reflect(spirv: &[u8]) -> Result<Reflection, String> {
    let options = naga::front::spv::Options {
        adjust_coordinate_space: false,
        strict_capabilities: false,
        block_ctx_dump_prefix: None,
    };
    let module = naga::front::spv::parse_u8_slice(spirv, &options)
        .map_err(|e| format!("naga could not parse the SPIR-V: {e}"))?;
    naga::valid::Validator::new(
        naga::valid::ValidationFlags::all(),
        naga::valid::Capabilities::all(),
    )
    .validate(&module)
    .map_err(|e| format!("naga validation failed: {e:?}"))?;

    let mut reflection = Reflection {
        bindings: Vec::new(),
        push_constant_size: 0,
        spec_constants: Vec::new(),
    };
    for (_, global) in module.global_variables.iter() {
        let kind = match global.space {
            naga::AddressSpace::Immediate => {
                reflection.push_constant_size = module.types[global.ty].inner.size(module.to_ctx());
                continue;
            }
            naga::AddressSpace::Uniform => "UniformBuffer",
            naga::AddressSpace::Storage { .. } => "StorageBuffer",
            naga::AddressSpace::Handle => "Other",
            _ => continue,
        };
        if let Some(b) = &global.binding {
            reflection.bindings.push(Binding {
                set: b.group,
                binding: b.binding,
                kind,
                record_size: record_size(&module, global.ty),
            });
        }
    }
    reflection.bindings.sort_by_key(|b| (b.set, b.binding));
    for (_, o) in module.overrides.iter() {
        if let Some(id) = o.id {
            reflection
                .spec_constants
                .push((id, o.name.clone().unwrap_or_default()));
        }
    }
    reflection.spec_constants.sort();
    Ok(reflection)
}

/// The (set, binding) of every variable `spirv` decorates with both: read
/// from its OpDecorate instructions, for a module naga cannot parse.
// (Here, and in `extend_by_decorations`, for build.rs: the library never
// reflects a module naga cannot read.)
#[allow(dead_code)]
pub fn decorated_bindings(spirv: &[u32]) -> Result<Vec<(u32, u32)>, String> {
    const OP_DECORATE: u32 = 71;
    const BINDING: u32 = 33;
    const DESCRIPTOR_SET: u32 = 34;
    let mut sets = std::collections::BTreeMap::new();
    let mut bindings = std::collections::BTreeMap::new();
    for instruction in instructions(spirv) {
        let (at, opcode, count) = instruction?;
        if opcode == OP_DECORATE && count == 4 {
            let (target, decoration, value) = (spirv[at + 1], spirv[at + 2], spirv[at + 3]);
            match decoration {
                DESCRIPTOR_SET => {
                    sets.insert(target, value);
                }
                BINDING => {
                    bindings.insert(target, value);
                }
                _ => {}
            }
        }
    }
    let mut out: Vec<(u32, u32)> = sets
        .iter()
        .filter_map(|(id, set)| bindings.get(id).map(|b| (*set, *b)))
        .collect();
    out.sort();
    Ok(out)
}

/// The interface of a module compiled from `base`'s source with more in it
/// (the ray-query engine): `base`'s bindings, push constants and
/// specialization constants, plus every binding the module's decorations
/// add (of a kind naga would call `Other`). Fails if the module lacks one
/// of `base`'s bindings.
#[allow(dead_code)]
pub fn extend_by_decorations(base: &Reflection, spirv: &[u32]) -> Result<Reflection, String> {
    let decorated = decorated_bindings(spirv)?;
    let mut bindings = Vec::new();
    for b in &base.bindings {
        if !decorated.contains(&(b.set, b.binding)) {
            return Err(format!("it lacks set {} binding {}", b.set, b.binding));
        }
        bindings.push(*b);
    }
    for &(set, binding) in &decorated {
        if !base
            .bindings
            .iter()
            .any(|b| (b.set, b.binding) == (set, binding))
        {
            bindings.push(Binding {
                set,
                binding,
                kind: "Other",
                record_size: 0,
            });
        }
    }
    bindings.sort_by_key(|b| (b.set, b.binding));
    Ok(Reflection {
        bindings,
        push_constant_size: base.push_constant_size,
        spec_constants: base.spec_constants.clone(),
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::gpu::shared::shader_catalog::{RAYTRACE_COMP, RAYTRACE_QUERY_COMP};

    /// glslang 12's `LocalSizeId` of three constants becomes the
    /// `LocalSize` naga reads, with their values; one whose size is not a
    /// plain constant (a specialization constant) is left as it is.
    #[test]
    fn local_size_ids_of_constants_become_local_sizes() {
        const HEADER: [u32; 5] = [0x0723_0203, 0x0001_0600, 0, 20, 0];
        let mode_id = |x: u32| [(6 << 16) | 331, 1, 38, x, 11, 11];
        let constants = [[(4 << 16) | 43, 2, 10, 64], [(4 << 16) | 43, 2, 11, 1]];
        let mut words: Vec<u32> = HEADER.to_vec();
        words.extend(mode_id(10));
        constants.iter().for_each(|c| words.extend(c));
        local_size_by_value(&mut words);
        assert_eq!(words[5..11], [(6 << 16) | 16, 1, 17, 64, 1, 1]);
        assert_eq!(words[11..], constants.concat()[..]);

        // %12 is a specialization constant (OpSpecConstant, 50).
        let mut words: Vec<u32> = HEADER.to_vec();
        words.extend(mode_id(12));
        constants.iter().for_each(|c| words.extend(c));
        words.extend([(4 << 16) | 50, 2, 12, 64]);
        let before = words.clone();
        local_size_by_value(&mut words);
        assert_eq!(words, before);
    }

    /// The decorations of the built ray tracers: the compute one's set 0,
    /// and the ray-query one's set 0 plus its acceleration structure.
    #[test]
    fn decorated_bindings_are_the_modules_bindings() {
        let base = decorated_bindings(&RAYTRACE_COMP.words()).unwrap();
        let reflected: Vec<(u32, u32)> = RAYTRACE_COMP
            .bindings
            .iter()
            .map(|b| (b.set, b.binding))
            .collect();
        assert_eq!(base, reflected);
        let query = decorated_bindings(&RAYTRACE_QUERY_COMP.words()).unwrap();
        let mut expected = reflected.clone();
        expected.push((1, 0));
        assert_eq!(query, expected);
        assert!(decorated_bindings(&[0x0723_0203, 0, 0, 0, 0, 0x0004_0047]).is_err());
    }
}
