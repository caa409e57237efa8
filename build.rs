//! Compiles `shaders/*.glsl` to SPIR-V with glslang, then parses and
//! validates every module with naga and records its reflection (descriptor
//! bindings, push-constant size, specialization constants). A shader that
//! glslang or naga rejects fails the build with the shader's own message.
//!
//! Output in OUT_DIR: one `.spv` per shader variant and `shaders.rs`, which
//! the crate includes (`src/gpu/shader_catalog.rs`).

use std::fmt::Write as _;
use std::path::{Path, PathBuf};

/// One compiled module: a source file, its stage, and preprocessor defines.
struct Variant {
    /// Rust constant name of the variant, e.g. `PHONG_FRAG_SCREEN`.
    name: &'static str,
    source: &'static str,
    stage: glslang::ShaderStage,
    defines: &'static [(&'static str, Option<&'static str>)],
}

const SMOOTH: &[(&str, Option<&str>)] = &[];
const SCREEN_LINEAR: &[(&str, Option<&str>)] = &[("SCREEN_LINEAR", None)];
const VERTEX_COLOR: &[(&str, Option<&str>)] = &[("VERTEX_COLOR", None)];
const SCREEN_LINEAR_VERTEX_COLOR: &[(&str, Option<&str>)] =
    &[("SCREEN_LINEAR", None), ("VERTEX_COLOR", None)];
const RAY_QUERY: &[(&str, Option<&str>)] = &[("RAY_QUERY", None)];
const WIDE_BVH: &[(&str, Option<&str>)] = &[("WIDE_BVH", None)];

const VARIANTS: &[Variant] = &[
    Variant {
        name: "FLAT_VERT",
        source: "flat.vert.glsl",
        stage: glslang::ShaderStage::Vertex,
        defines: &[],
    },
    Variant {
        name: "FLAT_FRAG",
        source: "flat.frag.glsl",
        stage: glslang::ShaderStage::Fragment,
        defines: &[],
    },
    Variant {
        name: "GOURAUD_VERT",
        source: "gouraud.vert.glsl",
        stage: glslang::ShaderStage::Vertex,
        defines: SMOOTH,
    },
    Variant {
        name: "GOURAUD_FRAG",
        source: "gouraud.frag.glsl",
        stage: glslang::ShaderStage::Fragment,
        defines: SMOOTH,
    },
    Variant {
        name: "GOURAUD_VERT_SCREEN",
        source: "gouraud.vert.glsl",
        stage: glslang::ShaderStage::Vertex,
        defines: SCREEN_LINEAR,
    },
    Variant {
        name: "GOURAUD_FRAG_SCREEN",
        source: "gouraud.frag.glsl",
        stage: glslang::ShaderStage::Fragment,
        defines: SCREEN_LINEAR,
    },
    Variant {
        name: "PHONG_VERT",
        source: "phong.vert.glsl",
        stage: glslang::ShaderStage::Vertex,
        defines: SMOOTH,
    },
    Variant {
        name: "PHONG_FRAG",
        source: "phong.frag.glsl",
        stage: glslang::ShaderStage::Fragment,
        defines: SMOOTH,
    },
    Variant {
        name: "PHONG_VERT_SCREEN",
        source: "phong.vert.glsl",
        stage: glslang::ShaderStage::Vertex,
        defines: SCREEN_LINEAR,
    },
    Variant {
        name: "PHONG_FRAG_SCREEN",
        source: "phong.frag.glsl",
        stage: glslang::ShaderStage::Fragment,
        defines: SCREEN_LINEAR,
    },
    // With vertex colours: a second vertex stream, only for scenes that
    // have them (the fragment stages of flat and Gouraud do not change).
    Variant {
        name: "FLAT_VERT_COLOR",
        source: "flat.vert.glsl",
        stage: glslang::ShaderStage::Vertex,
        defines: VERTEX_COLOR,
    },
    Variant {
        name: "GOURAUD_VERT_COLOR",
        source: "gouraud.vert.glsl",
        stage: glslang::ShaderStage::Vertex,
        defines: VERTEX_COLOR,
    },
    Variant {
        name: "GOURAUD_VERT_SCREEN_COLOR",
        source: "gouraud.vert.glsl",
        stage: glslang::ShaderStage::Vertex,
        defines: SCREEN_LINEAR_VERTEX_COLOR,
    },
    Variant {
        name: "PHONG_VERT_COLOR",
        source: "phong.vert.glsl",
        stage: glslang::ShaderStage::Vertex,
        defines: VERTEX_COLOR,
    },
    Variant {
        name: "PHONG_FRAG_COLOR",
        source: "phong.frag.glsl",
        stage: glslang::ShaderStage::Fragment,
        defines: VERTEX_COLOR,
    },
    Variant {
        name: "PHONG_VERT_SCREEN_COLOR",
        source: "phong.vert.glsl",
        stage: glslang::ShaderStage::Vertex,
        defines: SCREEN_LINEAR_VERTEX_COLOR,
    },
    Variant {
        name: "PHONG_FRAG_SCREEN_COLOR",
        source: "phong.frag.glsl",
        stage: glslang::ShaderStage::Fragment,
        defines: SCREEN_LINEAR_VERTEX_COLOR,
    },
    Variant {
        name: "RAYTRACE_COMP",
        source: "raytrace.comp.glsl",
        stage: glslang::ShaderStage::Compute,
        defines: &[],
    },
    Variant {
        name: "RAYTRACE_WIDE_COMP",
        source: "raytrace.comp.glsl",
        stage: glslang::ShaderStage::Compute,
        defines: WIDE_BVH,
    },
    Variant {
        name: "RAYTRACE_QUERY_COMP",
        source: "raytrace.comp.glsl",
        stage: glslang::ShaderStage::Compute,
        defines: RAY_QUERY,
    },
];

#[path = "src/shader_compile.rs"]
mod shader_compile;

fn main() {
    let root = PathBuf::from(std::env::var("CARGO_MANIFEST_DIR").unwrap());
    let shader_dir = root.join("shaders");
    let out_dir = PathBuf::from(std::env::var("OUT_DIR").unwrap());
    println!("cargo:rerun-if-changed=shaders");
    println!("cargo:rerun-if-changed=src/shader_compile.rs");

    let compiler = glslang::Compiler::acquire().expect("glslang could not be initialised");
    let mut catalog =
        String::from("// Generated by build.rs: SPIR-V and naga reflection of every shader.\n\n");
    let mut reflections: Vec<(&str, shader_compile::Reflection)> = Vec::new();
    for variant in VARIANTS {
        let spirv = compile(compiler, &shader_dir, variant);
        let bytes: Vec<u8> = spirv.iter().flat_map(|w| w.to_le_bytes()).collect();
        let spv_path = out_dir.join(format!("{}.spv", variant.name.to_lowercase()));
        std::fs::write(&spv_path, &bytes).unwrap();
        let reflection = if uses_ray_queries(variant) {
            // naga's SPIR-V reader does not know SPV_KHR_ray_query: this
            // module is validated by spirv-val instead, and its interface is
            // the same source's without RAY_QUERY plus what its own
            // decorations add (the acceleration structure).
            spirv_val(variant, &spv_path);
            let (_, base) = reflections
                .iter()
                .find(|(name, _)| *name == "RAYTRACE_COMP")
                .expect("RAYTRACE_COMP is compiled before its ray-query variant");
            shader_compile::extend_by_decorations(base, &spirv)
                .unwrap_or_else(|e| fail(variant, "its interface does not extend the base's", &e))
        } else {
            shader_compile::reflect(&bytes)
                .unwrap_or_else(|e| fail(variant, "naga rejected the SPIR-V", &e))
        };
        write_entry(&mut catalog, variant, &shader_dir, &spv_path, &reflection);
        reflections.push((variant.name, reflection));
    }
    let all: String = VARIANTS.iter().map(|v| format!("&{}, ", v.name)).collect();
    writeln!(catalog, "pub const ALL_SHADERS: &[&ShaderBlob] = &[{all}];").unwrap();
    write_includes(&mut catalog, &shader_dir.join("include"));
    std::fs::write(out_dir.join("shaders.rs"), catalog).unwrap();
}

/// The text of every file under `shaders/include/`, by name, so the binary
/// can compile the shaders again with a user's lighting hook.
fn write_includes(out: &mut String, dir: &Path) {
    let mut names: Vec<String> = std::fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .filter(|n| n.ends_with(".glsl"))
        .collect();
    names.sort();
    let entries: String = names
        .iter()
        .map(|n| {
            format!(
                "({n:?}, include_str!({:?})), ",
                dir.join(n).display().to_string()
            )
        })
        .collect();
    writeln!(out, "pub const INCLUDES: &[(&str, &str)] = &[{entries}];").unwrap();
}

fn compile(compiler: &glslang::Compiler, dir: &Path, variant: &Variant) -> Vec<u32> {
    let path = dir.join(variant.source);
    println!("cargo:rerun-if-changed={}", path.display());
    let text = std::fs::read_to_string(&path)
        .unwrap_or_else(|e| panic!("cannot read {}: {e}", path.display()));
    let include_dir = dir.join("include");
    let mut include = |name: &str| {
        let path = include_dir.join(name);
        let data = std::fs::read_to_string(&path).ok()?;
        Some((path.display().to_string(), data))
    };
    shader_compile::compile(
        compiler,
        &text,
        variant.stage,
        variant.defines,
        &mut include,
    )
    .unwrap_or_else(|e| fail(variant, "glslang failed to compile it", &e))
}

fn uses_ray_queries(variant: &Variant) -> bool {
    variant.defines.iter().any(|(name, _)| *name == "RAY_QUERY")
}

/// Validates a module naga cannot read with the Khronos validator
/// (`spirv-val`, Debian's `spirv-tools`, which ci/install-deps.sh installs).
fn spirv_val(variant: &Variant, spv: &Path) {
    let run = std::process::Command::new("spirv-val")
        .args(["--target-env", "vulkan1.3"])
        .arg(spv)
        .output();
    match run {
        Ok(out) if out.status.success() => {}
        Ok(out) => fail(
            variant,
            "spirv-val rejected the SPIR-V",
            &String::from_utf8_lossy(&out.stderr),
        ),
        Err(e) => fail(
            variant,
            "spirv-val, which validates the modules naga cannot read, did not run (install \
             Debian's spirv-tools, as ci/install-deps.sh does)",
            &e,
        ),
    }
}

fn fail(variant: &Variant, what: &str, err: &dyn std::fmt::Display) -> ! {
    panic!(
        "\n\nshader {} ({}): {what}:\n{err}\n",
        variant.source, variant.name
    )
}

fn write_entry(
    out: &mut String,
    variant: &Variant,
    dir: &Path,
    spv: &Path,
    r: &shader_compile::Reflection,
) {
    let stage = match variant.stage {
        glslang::ShaderStage::Vertex => "Vertex",
        glslang::ShaderStage::Fragment => "Fragment",
        glslang::ShaderStage::Compute => "Compute",
        _ => panic!("unsupported stage in {}", variant.source),
    };
    let bindings: String = r
        .bindings
        .iter()
        .map(|b| {
            format!(
                "ReflectedBinding {{ set: {}, binding: {}, kind: BindingKind::{}, record_size: {} }}, ",
                b.set, b.binding, b.kind, b.record_size
            )
        })
        .collect();
    let specs: String = r
        .spec_constants
        .iter()
        .map(|(id, name)| format!("({id}, {name:?}), "))
        .collect();
    let defines: String = variant
        .defines
        .iter()
        .map(|(k, v)| format!("({k:?}, {v:?}), "))
        .collect();
    writeln!(
        out,
        "pub const {}: ShaderBlob = ShaderBlob {{\n    name: {:?},\n    stage: ShaderStage::{stage},\n    spirv: include_bytes!({:?}),\n    source: include_str!({:?}),\n    defines: &[{defines}],\n    bindings: &[{bindings}],\n    push_constant_size: {},\n    spec_constants: &[{specs}],\n}};\n",
        variant.name,
        variant.source,
        spv.display().to_string(),
        dir.join(variant.source).display().to_string(),
        r.push_constant_size,
    )
    .unwrap();
}
