//! What both tracers agree on about a pixel's rays: where its samples lie
//! and how the rays they spawn are counted.

/// Rays traced by kind (`docs/raytracing.md`, "Counting").
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, serde::Serialize)]
pub struct RayStats {
    pub primary: u64,
    pub shadow: u64,
    pub reflected: u64,
    pub refracted: u64,
    /// Children not traced because their weight fell below the cut-off.
    pub pruned: u64,
    /// The largest depth of any traced ray (0: primary rays only).
    pub max_depth_reached: u32,
}

impl RayStats {
    pub fn total(&self) -> u64 {
        self.primary + self.shadow + self.reflected + self.refracted
    }
}

/// The sample grid of docs/raytracing.md for `samples` per pixel:
/// `kx = ceil(sqrt(samples))` columns and `ky = ceil(samples / kx)` rows.
/// Both tracers place their samples from it.
pub fn sample_grid(samples: u32) -> (u32, u32) {
    let samples = samples.max(1);
    // The least kx with kx^2 >= samples, in integers.
    let kx = (1..).find(|k: &u32| k * k >= samples).unwrap_or(1);
    (kx, samples.div_ceil(kx))
}
