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
