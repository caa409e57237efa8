//! Links Debian's static shaderc, glslang and SPIRV-Tools libraries, in the
//! order a single-pass linker needs (each after what uses it), so that the
//! shaderc crate links to them instead of compiling them from source.
//! ci/install-deps.sh installs them (`libshaderc-dev`, `glslang-dev`,
//! `spirv-tools`).

use std::path::{Path, PathBuf};

/// Each library after the ones that use it.
const LIBRARIES: &[&str] = &[
    "shaderc_combined",
    "SPIRV",
    "glslang",
    "MachineIndependent",
    "OSDependent",
    "GenericCodeGen",
    "OGLCompiler",
    "HLSL",
    "SPIRV-Tools-opt",
    "SPIRV-Tools",
];

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
    for library in LIBRARIES {
        println!("cargo:rustc-link-lib=static={library}");
    }
}

/// The first folder that holds every library: SHADERC_LIB_DIR where set,
/// else Debian's multiarch folder, else /usr/lib.
fn library_dir() -> Option<PathBuf> {
    let arch = std::env::var("CARGO_CFG_TARGET_ARCH").unwrap_or_default();
    let candidates = [
        std::env::var_os("SHADERC_LIB_DIR").map(PathBuf::from),
        Some(PathBuf::from(format!("/usr/lib/{arch}-linux-gnu"))),
        Some(PathBuf::from("/usr/lib")),
    ];
    candidates
        .into_iter()
        .flatten()
        .find(|dir| LIBRARIES.iter().all(|l| has_library(dir, l)))
}

fn has_library(dir: &Path, name: &str) -> bool {
    dir.join(format!("lib{name}.a")).is_file()
}
