//! Compiles `shaders/*.glsl` to SPIR-V with glslang, then parses and
//! validates every module with naga and records its reflection (descriptor
//! bindings, push-constant size, specialization constants). A shader that
//! glslang or naga rejects fails the build with the shader's own message.
//!
//! Output in OUT_DIR: one `.spv` per shader variant and `shaders.rs`, which
//! the crate includes (`src/gpu/shared/shader_catalog.rs`).

use std::fmt::Write as _;
use std::path::{Path, PathBuf};

/// Preprocessor defines: a name and its value, if any.
type Defines = &'static [(&'static str, Option<&'static str>)];

/// One compiled module: a source file, its stage, and preprocessor defines.
struct Variant {
    /// Rust constant name of the variant, e.g. `PHONG_FRAG_SCREEN`.
    name: String,
    source: &'static str,
    stage: shader_compile::Stage,
    defines: Defines,
}

/// The raster stages' features, each a define and a suffix of the
/// variant's name: `interpolation = "screen"`, vertex colours (for flat
/// shading, a colour per face), a pattern, and image textures (which come
/// with the pattern's texture coordinates and constants). Every subset a
/// stage takes is compiled, so that a scene gets the module for exactly
/// what it has.
const SCREEN_LINEAR: u8 = 1;
const VERTEX_COLOR: u8 = 2;
const PATTERN: u8 = 4;
const TEXTURE: u8 = 8;

/// The defines of a subset of the features.
fn feature_defines(features: u8) -> &'static [(&'static str, Option<&'static str>)] {
    let all = [
        (SCREEN_LINEAR, "SCREEN_LINEAR"),
        (VERTEX_COLOR, "VERTEX_COLOR"),
        (PATTERN, "PATTERN"),
        (TEXTURE, "TEXTURE"),
    ];
    let defines: Vec<(&'static str, Option<&'static str>)> = all
        .iter()
        .filter(|(bit, _)| features & bit != 0)
        .map(|&(_, name)| (name, None))
        .collect();
    Box::leak(defines.into_boxed_slice())
}

/// Each raster stage: its name, source, stage, and the features it takes
/// (the others do not change its code).
const RASTER_STAGES: &[(&str, &str, shader_compile::Stage, u8)] = &[
    (
        "FLAT_VERT",
        "flat.vert.glsl",
        shader_compile::Stage::Vertex,
        VERTEX_COLOR,
    ),
    (
        "FLAT_FRAG",
        "flat.frag.glsl",
        shader_compile::Stage::Fragment,
        0,
    ),
    (
        "GOURAUD_VERT",
        "gouraud.vert.glsl",
        shader_compile::Stage::Vertex,
        SCREEN_LINEAR | VERTEX_COLOR | PATTERN,
    ),
    (
        "GOURAUD_FRAG",
        "gouraud.frag.glsl",
        shader_compile::Stage::Fragment,
        SCREEN_LINEAR | PATTERN | TEXTURE,
    ),
    (
        "PHONG_VERT",
        "phong.vert.glsl",
        shader_compile::Stage::Vertex,
        SCREEN_LINEAR | VERTEX_COLOR | PATTERN,
    ),
    (
        "PHONG_FRAG",
        "phong.frag.glsl",
        shader_compile::Stage::Fragment,
        SCREEN_LINEAR | VERTEX_COLOR | PATTERN | TEXTURE,
    ),
];

/// The suffix the features add to a variant's name (`gpu::raster` looks
/// variants up by it): `_SCREEN`, `_COLOR`, `_PATTERN`, `_TEXTURE`, in
/// that order.
fn feature_suffix(features: u8) -> String {
    let mut suffix = String::new();
    for (bit, name) in [
        (SCREEN_LINEAR, "_SCREEN"),
        (VERTEX_COLOR, "_COLOR"),
        (PATTERN, "_PATTERN"),
        (TEXTURE, "_TEXTURE"),
    ] {
        if features & bit != 0 {
            suffix.push_str(name);
        }
    }
    suffix
}

fn variants() -> Vec<Variant> {
    let mut out = Vec::new();
    for &(name, source, stage, takes) in RASTER_STAGES {
        for features in 0..16u8 {
            // Images are read at the pattern's texture coordinates.
            if features & !takes != 0 || (features & TEXTURE != 0 && features & PATTERN == 0) {
                continue;
            }
            out.push(Variant {
                name: format!("{name}{}", feature_suffix(features)),
                source,
                stage,
                defines: feature_defines(features),
            });
        }
    }
    let compute = |name: &str, defines: Defines| Variant {
        name: name.to_string(),
        source: "raytrace.comp.glsl",
        stage: shader_compile::Stage::Compute,
        defines: with_kernel_sizes(defines),
    };
    out.push(compute("RAYTRACE_COMP", &[]));
    out.push(compute("RAYTRACE_WIDE_COMP", &[("WIDE_BVH", None)]));
    // Two eye rays a lane over the 4-wide walk, for the devices where it
    // pays (gpu::raytrace::pairing).
    out.push(compute(
        "RAYTRACE_WIDE_PAIRED_COMP",
        &[("WIDE_BVH", None), ("PAIRED", None)],
    ));
    out.push(compute("RAYTRACE_QUERY_COMP", &[("RAY_QUERY", None)]));
    // Diffuse bounces (secondary illumination): modules of their own, so
    // that a Whitted render neither compiles nor carries them.
    out.push(compute("RAYTRACE_PATHS_COMP", &[("PATHS", None)]));
    out.push(compute(
        "RAYTRACE_WIDE_PATHS_COMP",
        &[("WIDE_BVH", None), ("PATHS", None)],
    ));
    out.push(compute(
        "RAYTRACE_QUERY_PATHS_COMP",
        &[("RAY_QUERY", None), ("PATHS", None)],
    ));
    // Forward ray tracing (photons from the lights): its own shader over
    // the ray tracer's parts, on the compute BVH, binary or 4-wide.
    let forward = |name: &str, defines: Defines| Variant {
        name: name.to_string(),
        source: "forward.comp.glsl",
        stage: shader_compile::Stage::Compute,
        defines: with_kernel_sizes(defines),
    };
    out.push(forward("FORWARD_COMP", &[("FORWARD", None)]));
    out.push(forward(
        "FORWARD_WIDE_COMP",
        &[("FORWARD", None), ("WIDE_BVH", None)],
    ));
    // Caustics from a photon map: the forward tracer's photons and film,
    // gathered at the eye's visible points (its own module, so that a
    // render without caustics neither compiles nor carries it).
    let caustics = |name: &str, defines: Defines| Variant {
        name: name.to_string(),
        source: "caustics.comp.glsl",
        stage: shader_compile::Stage::Compute,
        defines: with_kernel_sizes(defines),
    };
    out.push(caustics("CAUSTICS_COMP", &[("FORWARD", None)]));
    out.push(caustics(
        "CAUSTICS_WIDE_COMP",
        &[("FORWARD", None), ("WIDE_BVH", None)],
    ));
    out
}

#[path = "src/shader_compile.rs"]
mod shader_compile;

/// A compute kernel's defines: its variant's, then the sizes that
/// `kernel_sizes` passes as defines (the rest are in `kernel_sizes.glsl`).
fn with_kernel_sizes(defines: Defines) -> Defines {
    let mut all = defines.to_vec();
    for (name, value) in kernel_sizes::glsl_defines() {
        all.push((name, Some(Box::leak(value.into_boxed_str()))));
    }
    Box::leak(all.into_boxed_slice())
}

// The compute kernels' sizes, shared with the crate: written into
// `kernel_sizes.glsl` here, so the shaders and the host hold one value each.
#[path = "src/gpu/raytrace/kernel_sizes.rs"]
mod kernel_sizes;

/// The generated header's name, as the kernels include it.
const KERNEL_SIZES: &str = "kernel_sizes.glsl";

fn main() {
    let root = PathBuf::from(std::env::var("CARGO_MANIFEST_DIR").unwrap());
    let shader_dir = root.join("shaders");
    let out_dir = PathBuf::from(std::env::var("OUT_DIR").unwrap());
    println!("cargo:rerun-if-changed=shaders");
    println!("cargo:rerun-if-changed=src/shader_compile.rs");
    println!("cargo:rerun-if-changed=src/gpu/raytrace/kernel_sizes.rs");
    std::fs::write(out_dir.join(KERNEL_SIZES), kernel_sizes::glsl_header()).unwrap();

    let mut catalog =
        String::from("// Generated by build.rs: SPIR-V and naga reflection of every shader.\n\n");
    let mut reflections: Vec<(String, shader_compile::Reflection)> = Vec::new();
    let variants = variants();
    for variant in &variants {
        let spirv = compile(&shader_dir, &out_dir, variant);
        let bytes: Vec<u8> = spirv.iter().flat_map(|w| w.to_le_bytes()).collect();
        let spv_path = out_dir.join(format!("{}.spv", variant.name.to_lowercase()));
        std::fs::write(&spv_path, &bytes).unwrap();
        let reflection = if uses_ray_queries(variant) {
            // naga's SPIR-V reader does not know SPV_KHR_ray_query: this
            // module is validated by spirv-val instead, and its interface is
            // the same source's without RAY_QUERY plus what its own
            // decorations add (the acceleration structure).
            spirv_val(variant, &spv_path);
            // RAYTRACE_QUERY_PATHS_COMP's is RAYTRACE_PATHS_COMP's.
            let base_name = variant.name.replace("_QUERY", "");
            let (_, base) = reflections
                .iter()
                .find(|(name, _)| *name == base_name)
                .expect("the base is compiled before its ray-query variant");
            shader_compile::extend_by_decorations(base, &spirv)
                .unwrap_or_else(|e| fail(variant, "its interface does not extend the base's", &e))
        } else {
            shader_compile::reflect(&bytes)
                .unwrap_or_else(|e| fail(variant, "naga rejected the SPIR-V", &e))
        };
        write_entry(&mut catalog, variant, &shader_dir, &spv_path, &reflection);
        reflections.push((variant.name.clone(), reflection));
    }
    let all: String = variants.iter().map(|v| format!("&{}, ", v.name)).collect();
    writeln!(catalog, "pub const ALL_SHADERS: &[&ShaderBlob] = &[{all}];").unwrap();
    let by_name: String = variants
        .iter()
        .map(|v| format!("({:?}, &{}), ", v.name, v.name))
        .collect();
    writeln!(
        catalog,
        "/// Every variant by its constant's name.\npub const BY_NAME: &[(&str, &ShaderBlob)] = &[{by_name}];"
    )
    .unwrap();
    write_includes(&mut catalog, &shader_dir.join("include"), &out_dir);
    std::fs::write(out_dir.join("shaders.rs"), catalog).unwrap();
}

/// The text of every file under `shaders/include/`, and of the generated
/// `kernel_sizes.glsl`, by name, so the binary can compile the shaders
/// again with a user's lighting hook.
fn write_includes(out: &mut String, dir: &Path, out_dir: &Path) {
    let mut paths: Vec<PathBuf> = std::fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|e| e == "glsl"))
        .collect();
    paths.push(out_dir.join(KERNEL_SIZES));
    paths.sort_by_key(|p| p.file_name().map(|n| n.to_os_string()));
    let entries: String = paths
        .iter()
        .map(|p| {
            let name = p.file_name().unwrap().to_string_lossy();
            format!("({name:?}, include_str!({:?})), ", p.display().to_string())
        })
        .collect();
    writeln!(out, "pub const INCLUDES: &[(&str, &str)] = &[{entries}];").unwrap();
}

fn compile(dir: &Path, out_dir: &Path, variant: &Variant) -> Vec<u32> {
    let path = dir.join(variant.source);
    println!("cargo:rerun-if-changed={}", path.display());
    let text = std::fs::read_to_string(&path)
        .unwrap_or_else(|e| panic!("cannot read {}: {e}", path.display()));
    let include_dir = dir.join("include");
    let include = |name: &str| {
        let path = if name == KERNEL_SIZES {
            out_dir.join(name)
        } else {
            include_dir.join(name)
        };
        let data = std::fs::read_to_string(&path).ok()?;
        Some((path.display().to_string(), data))
    };
    shader_compile::compile(
        &text,
        &path.display().to_string(),
        variant.stage,
        variant.defines,
        &include,
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
        shader_compile::Stage::Vertex => "Vertex",
        shader_compile::Stage::Fragment => "Fragment",
        shader_compile::Stage::Compute => "Compute",
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
