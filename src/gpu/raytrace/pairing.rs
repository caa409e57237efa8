//! Two eye rays a lane (`shaders/include/rt_paired.glsl`): each lane of a
//! packet walks the 4-wide tree for two pixels at once, sharing every
//! node's and triangle's read and every vote. The walk pays only where the
//! driver's vector registers hold the second ray's state: on lavapipe with
//! AVX-512, whose 32 registers LLVM uses at lavapipe's 256-bit width too
//! (with AVX2's 16 the second ray spills). And its module takes lavapipe
//! about 100 ms longer to build, so a render pairs only where its trace is
//! long enough to win that back (docs/performance.md, "Two rays a lane").
//! `SHADELAB_PAIRED_RAYS=1` or `0` overrides the choice.

use crate::gpu::vk::context::DeviceInfo;

/// Eye rays (pixels times samples) from which a render pairs them: at 2048
/// x 2048 the 40k sphere's whole command took 0.97x the time paired, the
/// ogre's 1.14x; at 4096 x 4096 0.90x and 1.12x.
pub const PAIRED_MIN_EYE_RAYS: u64 = 16 << 20;

/// Whether the ray tracer on this device walks a render's `eye_rays` two a
/// lane.
pub fn pairs_eye_rays(info: &DeviceInfo, eye_rays: u64) -> bool {
    match std::env::var("SHADELAB_PAIRED_RAYS").as_deref() {
        Ok("1") => true,
        Ok("0") => false,
        _ => info.is_lavapipe && cpu_has_avx512() && eye_rays >= PAIRED_MIN_EYE_RAYS,
    }
}

fn cpu_has_avx512() -> bool {
    #[cfg(target_arch = "x86_64")]
    {
        std::arch::is_x86_feature_detected!("avx512f")
    }
    #[cfg(not(target_arch = "x86_64"))]
    {
        false
    }
}
