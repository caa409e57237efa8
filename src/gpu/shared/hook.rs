//! The built-in shaders compiled again with a user's lighting hook in place
//! of `shaders/include/lighting_hook.glsl`, at run time: glslang compiles,
//! naga validates, and the module's interface must be the built-in one's
//! (the same bindings, push constants and specialization constants), so a
//! hook can change the formula and nothing else. Compiled modules are kept
//! on disk, keyed by every text that went in, the defines and the driver,
//! so a sweep over many variants compiles each once.

use crate::cache;
use crate::gpu::shared::shader_catalog::{reached_includes, ShaderBlob, ShaderStage, INCLUDES};
use crate::gpu::vk::context::DeviceInfo;
use crate::gpu::vk::error::GpuError;
use crate::scene::LightingHook;
use crate::shader_compile;

/// The cache folder's subfolder of compiled hooks.
const HOOK_CACHE: &str = "hooks";

/// The include a hook replaces.
const HOOK_INCLUDE: &str = "lighting_hook.glsl";

/// What a hook must define, in the words of error messages.
pub const HOOK_SIGNATURE: &str =
    "vec3 shade_light(vec3 N, vec3 V, vec3 L, float d, vec3 intensity, Surface m, float k)";

/// The SPIR-V words of `blob`, with `hook` compiled in when there is one
/// and the stage evaluates the formula at all.
pub fn module_words(
    blob: &ShaderBlob,
    hook: Option<&LightingHook>,
    device: &DeviceInfo,
) -> Result<Vec<u32>, GpuError> {
    let Some(hook) = hook.filter(|_| evaluates_formula(blob)) else {
        return Ok(blob.words());
    };
    let words = compiled(blob, hook, &device.driver)?;
    if declares_capability(&words, FLOAT16_CAPABILITY) && !device.shader_float16 {
        return Err(GpuError::LightingHook(format!(
            "{}: computes in half precision (float16), which the device `{}` lacks (shaderFloat16)",
            hook.path, device.name
        )));
    }
    Ok(words)
}

/// SPIR-V's `Float16` capability.
const FLOAT16_CAPABILITY: u32 = 9;

/// Whether the module declares `OpCapability capability` (the capabilities
/// open every module, right after the five-word header).
fn declares_capability(words: &[u32], capability: u32) -> bool {
    const OP_CAPABILITY: u32 = 17;
    shader_compile::instructions(words)
        .map_while(Result::ok)
        .take_while(|&(_, opcode, _)| opcode == OP_CAPABILITY)
        .any(|(at, _, _)| words.get(at + 1) == Some(&capability))
}

/// The module, from the cache or compiled (and then cached).
fn compiled(blob: &ShaderBlob, hook: &LightingHook, driver: &str) -> Result<Vec<u32>, GpuError> {
    let key = cache_key(blob, hook, driver);
    if let Some(words) = cache::read_module(HOOK_CACHE, &key) {
        return Ok(words);
    }
    let words = compile(blob, hook)?;
    cache::write_module(HOOK_CACHE, &key, &words);
    Ok(words)
}

/// Whether the stage includes the formula, itself or through another
/// include (the compute kernels' prelude); the others compile unchanged.
fn evaluates_formula(blob: &ShaderBlob) -> bool {
    reached_includes(blob.source, blob.defines).contains(&"lighting.glsl")
}

fn compile(blob: &ShaderBlob, hook: &LightingHook) -> Result<Vec<u32>, GpuError> {
    let stage = match blob.stage {
        ShaderStage::Vertex => shader_compile::Stage::Vertex,
        ShaderStage::Fragment => shader_compile::Stage::Fragment,
        ShaderStage::Compute => shader_compile::Stage::Compute,
    };
    let include = |name: &str| {
        if name == HOOK_INCLUDE {
            return Some((hook.path.clone(), hook.source.clone()));
        }
        INCLUDES
            .iter()
            .find(|(n, _)| *n == name)
            .map(|(n, text)| (format!("shaders/include/{n}"), text.to_string()))
    };
    let name = format!("shaders/{}", blob.name);
    let words = shader_compile::compile(blob.source, &name, stage, blob.defines, &include)
        .map_err(|log| compile_error(hook, &log))?;
    let bytes: Vec<u8> = words.iter().flat_map(|w| w.to_le_bytes()).collect();
    let reflection = shader_compile::reflect(&bytes).map_err(|e| {
        GpuError::LightingHook(format!(
            "{}: the shader compiled with this hook is not valid SPIR-V ({e})",
            hook.path
        ))
    })?;
    check_interface(blob, hook, &reflection)?;
    Ok(words)
}

/// glslang's log, or, when the hook's own lines are not what failed (the
/// call in `lighting.glsl` found no matching function), what the hook must
/// define.
fn compile_error(hook: &LightingHook, log: &str) -> GpuError {
    let log = log.trim();
    let in_hook = log.lines().any(|l| l.contains(&format!("{}:", hook.path)));
    if in_hook {
        return GpuError::LightingHook(format!("{}: does not compile:\n{log}", hook.path));
    }
    GpuError::LightingHook(format!(
        "{}: a lighting hook must define\n    {HOOK_SIGNATURE}\n(Surface has the fields color, ka, kd, ks, p); glslang says:\n{log}",
        hook.path
    ))
}

/// The hook may change the formula, not the interface: every binding, the
/// push constants and the specialization constants as the built-in module
/// has them.
fn check_interface(
    blob: &ShaderBlob,
    hook: &LightingHook,
    got: &shader_compile::Reflection,
) -> Result<(), GpuError> {
    let bindings: Vec<(u32, u32, String, u32)> = got
        .bindings
        .iter()
        .map(|b| (b.set, b.binding, b.kind.to_string(), b.record_size))
        .collect();
    let expected: Vec<(u32, u32, String, u32)> = blob
        .bindings
        .iter()
        .map(|b| (b.set, b.binding, format!("{:?}", b.kind), b.record_size))
        .collect();
    if let Some(extra) = bindings.iter().find(|b| !expected.contains(b)) {
        return Err(GpuError::LightingHook(format!(
            "{}: declares a resource of its own (set {}, binding {}); a hook may use only what shadelab supplies (its arguments, the Surface fields, USE_SPECULAR, USE_ATTENUATION, INVERSE_SQUARE)",
            hook.path, extra.0, extra.1
        )));
    }
    let specs: Vec<(u16, &str)> = got
        .spec_constants
        .iter()
        .map(|(id, name)| (*id, name.as_str()))
        .collect();
    let expected_specs: Vec<(u16, &str)> = blob.spec_constants.to_vec();
    if got.push_constant_size != blob.push_constant_size || specs != expected_specs {
        return Err(GpuError::LightingHook(format!(
            "{}: declares push constants or specialization constants of its own; a hook may use only what shadelab supplies",
            hook.path
        )));
    }
    Ok(())
}

/// Everything the module depends on: the shader's text and defines, every
/// include (the hook among them), the compiler's version, the driver.
fn cache_key(blob: &ShaderBlob, hook: &LightingHook, driver: &str) -> String {
    let digest = cache::digest(&(blob.source, INCLUDES, &hook.source));
    format!(
        "shadelab {} glslang (shaderc 0.10) {} {:?} {driver} {:016x}",
        env!("CARGO_PKG_VERSION"),
        blob.name,
        blob.defines,
        digest
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_key_changes_with_the_hook_the_defines_and_the_driver() {
        use crate::gpu::shared::shader_catalog::{GOURAUD_VERT, GOURAUD_VERT_SCREEN};
        let hook = |text: &str| LightingHook {
            path: "h.glsl".into(),
            source: text.into(),
        };
        let base = cache_key(&GOURAUD_VERT, &hook("a"), "llvmpipe");
        assert_ne!(base, cache_key(&GOURAUD_VERT, &hook("b"), "llvmpipe"));
        assert_ne!(
            base,
            cache_key(&GOURAUD_VERT_SCREEN, &hook("a"), "llvmpipe")
        );
        assert_ne!(base, cache_key(&GOURAUD_VERT, &hook("a"), "nvidia"));
        assert_eq!(base, cache_key(&GOURAUD_VERT, &hook("a"), "llvmpipe"));
    }

    /// The compute kernels reach the formula through their prelude.
    #[test]
    fn every_stage_that_lights_takes_the_hook() {
        use crate::gpu::shared::shader_catalog::{
            CAUSTICS_COMP, FLAT_FRAG, FLAT_VERT, FORWARD_COMP, PHONG_FRAG, RAYTRACE_COMP,
            RAYTRACE_QUERY_PATHS_COMP,
        };
        for blob in [
            &RAYTRACE_COMP,
            &RAYTRACE_QUERY_PATHS_COMP,
            &FORWARD_COMP,
            &CAUSTICS_COMP,
        ] {
            assert!(evaluates_formula(blob), "{}", blob.name);
        }
        assert!(evaluates_formula(&FLAT_VERT) && evaluates_formula(&PHONG_FRAG));
        assert!(!evaluates_formula(&FLAT_FRAG));
    }

    #[test]
    fn a_float16_capability_is_found_among_the_capabilities() {
        use crate::gpu::shared::shader_catalog::PHONG_FRAG;
        let header = [0x0723_0203, 0x0001_0600, 0, 10, 0];
        let capability = |c: u32| [(2 << 16) | 17, c];
        let mut module = header.to_vec();
        module.extend(capability(1)); // Shader
        module.extend(capability(FLOAT16_CAPABILITY));
        module.push((1 << 16) | 0xffff); // not a capability: the scan stops
        assert!(declares_capability(&module, FLOAT16_CAPABILITY));
        assert!(!declares_capability(&module, 22));
        assert!(!declares_capability(
            &PHONG_FRAG.words(),
            FLOAT16_CAPABILITY
        ));
        assert!(declares_capability(&PHONG_FRAG.words(), 1));
    }

    #[test]
    fn a_half_precision_hook_is_refused_where_the_device_lacks_float16() {
        use crate::gpu::shared::shader_catalog::PHONG_FRAG;
        let path = concat!(
            env!("CARGO_MANIFEST_DIR"),
            "/examples/lighting/half-precision.glsl"
        );
        let hook = LightingHook::load(std::path::Path::new(path)).unwrap();
        let mut device = DeviceInfo {
            index: 0,
            name: "test device".into(),
            driver: format!("test {}", std::process::id()),
            device_type: String::new(),
            api_version: String::new(),
            is_lavapipe: false,
            shader_float16: true,
            msaa_counts: vec![1],
            viewport_subpixel_bits: 8,
            unusable_because: None,
            no_ray_tracer_because: None,
            no_ray_query_because: None,
            no_forward_because: None,
        };
        let words = module_words(&PHONG_FRAG, Some(&hook), &device).unwrap();
        assert!(declares_capability(&words, FLOAT16_CAPABILITY));
        device.shader_float16 = false;
        let refused = module_words(&PHONG_FRAG, Some(&hook), &device).unwrap_err();
        assert!(refused.to_string().contains("shaderFloat16"), "{refused}");
    }
}
