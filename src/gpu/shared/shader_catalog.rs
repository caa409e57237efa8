//! Every compiled shader variant: SPIR-V produced by build.rs, with naga's
//! reflection of its descriptor bindings, push constants and specialization
//! constants. The host declares its side in `raster::layout`;
//! tests/cpu/shader_interface.rs holds the two together.

#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ShaderStage {
    Vertex,
    Fragment,
    Compute,
}

#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum BindingKind {
    UniformBuffer,
    StorageBuffer,
    Other,
}

#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct ReflectedBinding {
    pub set: u32,
    pub binding: u32,
    pub kind: BindingKind,
    /// Byte stride of a runtime-array buffer's records, else the block size.
    pub record_size: u32,
}

#[derive(Debug)]
pub struct ShaderBlob {
    /// Source file under `shaders/`.
    pub name: &'static str,
    pub stage: ShaderStage,
    /// Little-endian SPIR-V words.
    pub spirv: &'static [u8],
    /// The GLSL it was compiled from (its includes are in `INCLUDES`) and
    /// the defines it was compiled with: what `gpu::hook` compiles again
    /// with a user's lighting hook.
    pub source: &'static str,
    pub defines: &'static [(&'static str, Option<&'static str>)],
    pub bindings: &'static [ReflectedBinding],
    /// Size in bytes of the push-constant block, 0 when there is none.
    pub push_constant_size: u32,
    /// Specialization constant ids and names.
    pub spec_constants: &'static [(u16, &'static str)],
}

impl ShaderBlob {
    pub fn words(&self) -> Vec<u32> {
        self.spirv
            .chunks_exact(4)
            .map(|c| u32::from_le_bytes([c[0], c[1], c[2], c[3]]))
            .collect()
    }
}

include!(concat!(env!("OUT_DIR"), "/shaders.rs"));

/// The files under `shaders/include/` (and the generated `kernel_sizes.glsl`)
/// that `text` reaches when compiled with `defines`, directly or through
/// one another, each once, in the order first reached. Conditions are
/// followed as far as `#ifdef NAME` and `#ifndef NAME` name a define (an
/// include guard, `*_GLSL`, counts as not yet defined); any other `#if` is
/// taken as true.
pub fn reached_includes(text: &str, defines: &[(&str, Option<&str>)]) -> Vec<&'static str> {
    let mut reached = Vec::new();
    walk_includes(text, defines, &mut reached);
    reached
}

fn walk_includes(text: &str, defines: &[(&str, Option<&str>)], reached: &mut Vec<&'static str>) {
    let defined = |name: &str| defines.iter().any(|(d, _)| *d == name);
    // Whether each open conditional's branch is taken.
    let mut taken: Vec<bool> = Vec::new();
    for line in text.lines().map(str::trim) {
        let words: Vec<&str> = line.split_whitespace().collect();
        match words.as_slice() {
            ["#ifdef", name, ..] => taken.push(defined(name)),
            ["#ifndef", name, ..] => taken.push(name.ends_with("_GLSL") || !defined(name)),
            [if_, ..] if if_.starts_with("#if") => taken.push(true),
            ["#else", ..] | ["#elif", ..] => {
                if let Some(last) = taken.last_mut() {
                    *last = !*last;
                }
            }
            ["#endif", ..] => {
                taken.pop();
            }
            ["#include", quoted, ..] if taken.iter().all(|&t| t) => {
                let name = quoted.trim_matches('"');
                if let Some(&(name, included)) = INCLUDES.iter().find(|(n, _)| *n == name) {
                    if !reached.contains(&name) {
                        reached.push(name);
                        walk_includes(included, defines, reached);
                    }
                }
            }
            _ => {}
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Every header a compute kernel reaches compiles when included alone
    /// after the kernels' prelude (`rt_kernel.glsl`), with that kernel's
    /// defines: each includes what it needs.
    #[test]
    fn kernel_headers_compile_alone_after_the_prelude() {
        let include = |name: &str| {
            let (_, text) = INCLUDES.iter().find(|(n, _)| *n == name)?;
            Some((name.to_string(), text.to_string()))
        };
        let kernels = [
            &RAYTRACE_COMP,
            &RAYTRACE_QUERY_COMP,
            &RAYTRACE_WIDE_PATHS_COMP,
            &FORWARD_COMP,
            &CAUSTICS_WIDE_COMP,
        ];
        for kernel in kernels {
            let headers = reached_includes(kernel.source, kernel.defines);
            assert!(headers.contains(&"rt_kernel.glsl"), "{}", kernel.name);
            // The lighting hook is a part of lighting.glsl, compiled inside
            // it (and a user's replaces it): not a header of its own.
            for header in headers.into_iter().filter(|&h| h != "lighting_hook.glsl") {
                let text = format!(
                    "#version 460\n#extension GL_GOOGLE_include_directive : require\n\
                     #include \"rt_kernel.glsl\"\n#include \"{header}\"\nvoid main() {{}}\n"
                );
                crate::shader_compile::compile(
                    &text,
                    header,
                    crate::shader_compile::Stage::Compute,
                    kernel.defines,
                    &include,
                )
                .unwrap_or_else(|log| panic!("{header} alone, as in {}: {log}", kernel.name));
            }
        }
    }

    /// The walk follows the kernels' conditions: the ray-query engine only
    /// with RAY_QUERY, the bounces only with PATHS.
    #[test]
    fn reached_includes_follow_the_defines() {
        let whitted = reached_includes(RAYTRACE_COMP.source, RAYTRACE_COMP.defines);
        assert!(whitted.contains(&"rt_bvh.glsl") && whitted.contains(&"lighting.glsl"));
        assert!(!whitted.contains(&"rt_query.glsl") && !whitted.contains(&"rt_bounce.glsl"));
        let query = reached_includes(RAYTRACE_QUERY_COMP.source, RAYTRACE_QUERY_COMP.defines);
        assert!(query.contains(&"rt_query.glsl"));
        let paths = reached_includes(RAYTRACE_PATHS_COMP.source, RAYTRACE_PATHS_COMP.defines);
        assert!(paths.contains(&"random_streams.glsl") && paths.contains(&"rt_sample_sums.glsl"));
        assert!(!reached_includes(FLAT_FRAG.source, FLAT_FRAG.defines).contains(&"lighting.glsl"));
    }
}
