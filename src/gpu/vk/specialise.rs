//! A module specialised to a scene before the driver sees it: the values of
//! its specialization constants written in as plain constants, then the
//! code they rule out removed by SPIRV-Tools' optimizer, `spirv-opt` (the
//! Debian/Ubuntu package `spirv-tools`, which `ci/install-deps.sh`
//! installs).
//!
//! Why: lavapipe translates and optimises the whole module at pipeline
//! creation, the code that the constants switch off included, on every
//! render (nothing in Mesa caches that step). The ray tracer specialised
//! here is half the size, and its pipeline is made in a quarter of the time
//! (docs/performance.md, "Time to image"); the driver computes the same,
//! so the image is bit-identical. Then, as `Lowering` says, the
//! calls are inlined and the locals forwarded, which lavapipe would
//! otherwise do on every render: the 4-wide walk's pipeline in a third of
//! the time, for 0.05 to 0.1 s more in the optimizer once per scene.
//!
//! The result is kept in the cache folder (`spirv/`), keyed by the module,
//! the values and which `spirv-opt` made it, so a scene seen before pays
//! neither step.
//!
//! Why a program and not the library: SPIRV-Tools compiled from source
//! was nine of the twelve minutes of a fresh `cargo build --release`
//! (issue 44); a process per specialisation costs a few milliseconds on a
//! cache miss. Where `spirv-opt` is missing, the driver specialises
//! instead (`specialise` returns `None`): the same image, the pipeline
//! made slower.

use std::sync::OnceLock;

use ash::vk;
use spirv_tools::opt::{Optimizer, Passes};

use crate::cache;
use crate::gpu::vk::error::GpuError;
use crate::shader_compile;

/// The cache folder's subfolder of specialised modules.
const SPECIALISED_CACHE: &str = "spirv";

/// The dead-code passes, in order: freeze the constants, fold what they
/// decide, drop the branches and code that can no longer run.
const DEAD_CODE: [Passes; 8] = [
    Passes::FreezeSpecConstantValue,
    Passes::FoldSpecConstantOpAndComposite,
    Passes::ConditionalConstantPropagation,
    Passes::DeadBranchElim,
    Passes::AggressiveDCE,
    Passes::BlockMerge,
    Passes::EliminateDeadFunctions,
    Passes::EliminateDeadConstant,
];

/// Then every call inlined (a function that returns before its end stays
/// a call: `MergeReturn`'s rewrite of those made the driver slower) and
/// each local stored once, or loaded in the block that stored it, replaced
/// by its value.
const INLINED: [Passes; 4] = [
    Passes::InlineExhaustive,
    Passes::EliminateDeadFunctions,
    Passes::LocalSingleBlockLoadStoreElim,
    Passes::LocalSingleStoreElim,
];

/// How much of the driver's front end is done here, past the dead code
/// (docs/performance.md, "Issue 58", "The module inlined before the
/// driver"). Lavapipe inlines and builds SSA form on every pipeline it
/// makes; done once here and cached, the 4-wide walk's pipeline takes a
/// half to a third of the time. The images are the same either way, but
/// the driver's code is not laid out the same, and the trace's speed moves
/// with it, so each module takes what was measured not to slow it.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Lowering {
    /// Calls inlined and the simplest locals forwarded: the pipeline a
    /// third faster on the default scene, the trace as fast.
    Inlined,
    /// Every local made an SSA value too: the 4-wide walk's pipeline 15 to
    /// 30 ms faster again, its trace as fast; but the binary walk's (the
    /// default scene) traced 1.17x slower after it.
    InlinedSsa,
}

impl Lowering {
    fn passes(self) -> Vec<Passes> {
        let mut passes = [DEAD_CODE.as_slice(), &INLINED].concat();
        match self {
            Lowering::Inlined => passes.push(Passes::AggressiveDCE),
            Lowering::InlinedSsa => passes.extend([
                Passes::SSARewrite,
                Passes::ConditionalConstantPropagation,
                Passes::DeadBranchElim,
                Passes::BlockMerge,
                Passes::AggressiveDCE,
            ]),
        }
        passes
    }
}

/// `words` with the constants of `entries`/`data` (a `VkSpecializationInfo`'s
/// map and data, 4-byte values) fixed and the code they rule out removed.
/// The result has no specialization constants left for those ids: create
/// its pipeline without a `VkSpecializationInfo`. `None` where `spirv-opt`
/// is not installed: give the driver the constants instead.
pub fn specialise(
    words: &[u32],
    entries: &[vk::SpecializationMapEntry],
    data: &[u8],
    lowering: Lowering,
) -> Result<Option<Vec<u32>>, GpuError> {
    let values = spec_values(entries, data)?;
    let Some(version) = optimizer_version() else {
        return Ok(None);
    };
    let passes = lowering.passes();
    let key = format!(
        "shadelab {} {version} passes {passes:?} module {:016x} values {values:?}",
        env!("CARGO_PKG_VERSION"),
        cache::digest(&words),
    );
    if let Some(cached) = cache::read_module(SPECIALISED_CACHE, &key) {
        return Ok(Some(cached));
    }
    let mut module = words.to_vec();
    set_defaults(&mut module, &values)?;
    let mut optimizer = spirv_tools::opt::create(Some(spirv_tools::TargetEnv::Vulkan_1_3));
    for pass in passes {
        optimizer.register_pass(pass);
    }
    let mut messages = String::new();
    let optimized = optimizer
        .optimize(
            &module,
            &mut |m: spirv_tools::error::Message| {
                messages.push_str(&m.message);
                messages.push('\n');
            },
            None,
        )
        .map_err(|e| {
            GpuError::Specialise(format!("SPIRV-Tools' optimizer failed: {e} {messages}"))
        })?;
    let out = optimized.as_words().to_vec();
    cache::write_module(SPECIALISED_CACHE, &key, &out);
    Ok(Some(out))
}

/// Which `spirv-opt` would run, as the cache key needs it: its path, size
/// and modification time, since another build may write other modules.
/// Found on `PATH` once a process, by looking and not by running it, so a
/// render whose module is cached starts no process at all; `None` where
/// there is none.
fn optimizer_version() -> Option<&'static str> {
    static VERSION: OnceLock<Option<String>> = OnceLock::new();
    VERSION
        .get_or_init(|| {
            let path = std::env::var_os("PATH")?;
            std::env::split_paths(&path).find_map(|dir| {
                let program = dir.join("spirv-opt");
                let meta = std::fs::metadata(&program).ok().filter(|m| m.is_file())?;
                let modified = meta
                    .modified()
                    .ok()
                    .and_then(|t| t.duration_since(std::time::UNIX_EPOCH).ok())
                    .map_or(0, |d| d.as_secs());
                Some(format!(
                    "spirv-opt {} {} bytes {modified}",
                    program.display(),
                    meta.len()
                ))
            })
        })
        .as_deref()
}

/// `(constant id, value)` for each map entry, in the map's order.
fn spec_values(
    entries: &[vk::SpecializationMapEntry],
    data: &[u8],
) -> Result<Vec<(u32, u32)>, GpuError> {
    entries
        .iter()
        .map(|e| {
            let at = e.offset as usize;
            let bytes = data
                .get(at..at + 4)
                .filter(|_| e.size == 4)
                .ok_or_else(|| {
                    GpuError::Specialise(format!(
                        "constant {} is not a 4-byte value within the data",
                        e.constant_id
                    ))
                })?;
            Ok((
                e.constant_id,
                u32::from_ne_bytes([bytes[0], bytes[1], bytes[2], bytes[3]]),
            ))
        })
        .collect()
}

const OP_DECORATE: u32 = 71;
const DECORATION_SPEC_ID: u32 = 1;
const OP_SPEC_CONSTANT_TRUE: u32 = 48;
const OP_SPEC_CONSTANT_FALSE: u32 = 49;
const OP_SPEC_CONSTANT: u32 = 50;

/// Makes each listed constant's default value the given one, as a
/// pipeline's specialization would: a boolean is true for any nonzero value
/// (a `VkBool32`), a scalar takes the 32 bits as they are. The freeze pass
/// then turns the defaults into constants.
fn set_defaults(module: &mut [u32], values: &[(u32, u32)]) -> Result<(), GpuError> {
    let listed: Vec<(usize, u32, usize)> = shader_compile::instructions(module)
        .collect::<Result<_, _>>()
        .map_err(|e| GpuError::Specialise(format!("the module is not well-formed SPIR-V: {e}")))?;
    // Result id -> constant id, from the SpecId decorations.
    let spec_ids: std::collections::HashMap<u32, u32> = listed
        .iter()
        .filter(|&&(at, op, count)| {
            op == OP_DECORATE && count == 4 && module[at + 2] == DECORATION_SPEC_ID
        })
        .map(|&(at, _, _)| (module[at + 1], module[at + 3]))
        .collect();
    let value_of = |result: u32| {
        let id = spec_ids.get(&result)?;
        values.iter().find(|(c, _)| c == id).map(|&(_, v)| v)
    };
    for (at, opcode, count) in listed {
        match opcode {
            OP_SPEC_CONSTANT_TRUE | OP_SPEC_CONSTANT_FALSE if count == 3 => {
                if let Some(v) = value_of(module[at + 2]) {
                    let op = if v != 0 {
                        OP_SPEC_CONSTANT_TRUE
                    } else {
                        OP_SPEC_CONSTANT_FALSE
                    };
                    module[at] = (module[at] & 0xffff_0000) | op;
                }
            }
            OP_SPEC_CONSTANT => {
                if let Some(v) = value_of(module[at + 2]) {
                    if count != 4 {
                        return Err(GpuError::Specialise(format!(
                            "constant %{} is wider than 32 bits",
                            module[at + 2]
                        )));
                    }
                    module[at + 3] = v;
                }
            }
            _ => {}
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A module of two spec constants: `%2 = OpSpecConstantTrue %1` (SpecId
    /// 3) and `%4 = OpSpecConstant %5 7` (SpecId 9), with their decorations.
    fn module() -> Vec<u32> {
        vec![
            0x0723_0203,
            0x0001_0600,
            0,
            10,
            0,
            (4 << 16) | OP_DECORATE,
            2,
            DECORATION_SPEC_ID,
            3,
            (4 << 16) | OP_DECORATE,
            4,
            DECORATION_SPEC_ID,
            9,
            (3 << 16) | OP_SPEC_CONSTANT_TRUE,
            1,
            2,
            (4 << 16) | OP_SPEC_CONSTANT,
            5,
            4,
            7,
        ]
    }

    #[test]
    fn defaults_take_the_values_by_constant_id() {
        let mut m = module();
        set_defaults(&mut m, &[(3, 0), (9, 42)]).unwrap();
        assert_eq!(m[13], (3 << 16) | OP_SPEC_CONSTANT_FALSE, "bool 0: false");
        assert_eq!(m[19], 42);
        // Any nonzero VkBool32 is true; an id not in the map stays as it is.
        let mut m = module();
        set_defaults(&mut m, &[(3, 2)]).unwrap();
        assert_eq!(m[13], (3 << 16) | OP_SPEC_CONSTANT_TRUE);
        assert_eq!(m[19], 7);
    }

    #[test]
    fn a_truncated_module_is_an_error_not_a_panic() {
        let mut m = module();
        m.pop();
        assert!(set_defaults(&mut m, &[(9, 1)]).is_err());
    }

    #[test]
    fn values_are_read_where_the_map_says() {
        let entries = [
            vk::SpecializationMapEntry {
                constant_id: 5,
                offset: 4,
                size: 4,
            },
            vk::SpecializationMapEntry {
                constant_id: 1,
                offset: 0,
                size: 4,
            },
        ];
        let data: Vec<u8> = [11u32, 22].iter().flat_map(|v| v.to_ne_bytes()).collect();
        assert_eq!(
            spec_values(&entries, &data).unwrap(),
            vec![(5, 22), (1, 11)]
        );
        let beyond = [vk::SpecializationMapEntry {
            constant_id: 0,
            offset: 8,
            size: 4,
        }];
        assert!(spec_values(&beyond, &data).is_err());
    }
}
