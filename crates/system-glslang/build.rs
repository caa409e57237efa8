//! Links Debian's static shaderc, glslang and SPIRV-Tools libraries, in the
//! order a single-pass linker needs (each after what uses it), so that the
//! shaderc crate links to them instead of compiling them from source.
//! ci/install-deps.sh installs them (`libshaderc-dev`, `glslang-dev`,
//! `spirv-tools`).

use std::path::{Path, PathBuf};

/// Each library after the ones that use it. Debian 12's glslang (12.0)
/// splits itself into more libraries than newer ones do (glslang 14 has no
/// OGLCompiler or HLSL library): those are linked where they exist.
const LIBRARIES: &[(&str, Need)] = &[
    ("shaderc_combined", Need::Required),
    ("SPIRV", Need::WhereItExists),
    ("glslang", Need::Required),
    ("MachineIndependent", Need::WhereItExists),
    ("OSDependent", Need::WhereItExists),
    ("GenericCodeGen", Need::WhereItExists),
    ("OGLCompiler", Need::WhereItExists),
    ("HLSL", Need::WhereItExists),
    ("SPIRV-Tools-opt", Need::Required),
    ("SPIRV-Tools", Need::Required),
];

#[derive(PartialEq)]
enum Need {
    Required,
    WhereItExists,
}

fn main() {
    println!("cargo:rerun-if-env-changed=SHADERC_LIB_DIR");
    let dir = library_dir().unwrap_or_else(|| {
        panic!(
            "\n\nshaderc, glslang and SPIRV-Tools' static libraries were not found \
             (libshaderc_combined.a, libglslang.a, libSPIRV-Tools.a in /usr/lib/<triple>, \
             or in SHADERC_LIB_DIR): install Debian's libshaderc-dev, glslang-dev and \
             spirv-tools, as ci/install-deps.sh does\n"
        )
    });
    println!("cargo:rustc-link-search=native={}", dir.display());
    for (library, _) in LIBRARIES.iter().filter(|(l, _)| has_library(&dir, l)) {
        println!("cargo:rustc-link-lib=static={library}");
    }
}

/// The first folder that holds every required library: SHADERC_LIB_DIR where set,
/// else Debian's multiarch folder, else /usr/lib.
fn library_dir() -> Option<PathBuf> {
    let arch = std::env::var("CARGO_CFG_TARGET_ARCH").unwrap_or_default();
    let candidates = [
        std::env::var_os("SHADERC_LIB_DIR").map(PathBuf::from),
        Some(PathBuf::from(format!("/usr/lib/{arch}-linux-gnu"))),
        Some(PathBuf::from("/usr/lib")),
    ];
    candidates.into_iter().flatten().find(|dir| {
        LIBRARIES
            .iter()
            .all(|(l, need)| *need == Need::WhereItExists || has_library(dir, l))
    })
}

fn has_library(dir: &Path, name: &str) -> bool {
    dir.join(format!("lib{name}.a")).is_file()
}
