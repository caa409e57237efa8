//! Nothing to call: this crate exists for its build script, which tells the
//! linker where glslang and SPIRV-Tools are. Debian's `libshaderc-dev` ships
//! shaderc alone (`libshaderc_combined.a` holds shaderc's own objects, and
//! `libshaderc.so.1` leaves glslang's and SPIRV-Tools' symbols undefined);
//! their static libraries come from `glslang-dev` and `spirv-tools`. A crate
//! that names this one (`use system_glslang as _;`) links them.
