//! How forward tracing splits its photons over the lights: in proportion
//! to their power (the mean of the intensity's channels), as running
//! shares on a grid of 2^-24, so that the GPU's f32 and the CPU's f64 pick
//! the same light for the same number (a multiple of 2^-24, exact in both).

use super::scene::RtScene;

/// The grid the shares are held on: the resolution of a photon's number.
pub const SHARE_UNITS: u32 = 1 << 24;

/// Each light's running share of the power, in `SHARE_UNITS`: light `j`
/// takes the numbers `u` with `ends[j-1] <= u * SHARE_UNITS < ends[j]`,
/// and the last ends at `SHARE_UNITS`.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct LightShares {
    pub ends: Vec<u32>,
}

impl LightShares {
    /// `None` for a scene with no light that has power. A light with less
    /// than 2^-25 of the power may round to no share: it emits nothing.
    pub fn of(scene: &RtScene) -> Option<Self> {
        let power = |i: glam::DVec3| (i.x + i.y + i.z).max(0.0) / 3.0;
        let total: f64 = scene.lights.iter().map(|l| power(l.intensity)).sum();
        if total <= 0.0 || !total.is_finite() {
            return None;
        }
        let mut sum = 0.0;
        let mut ends: Vec<u32> = scene
            .lights
            .iter()
            .map(|l| {
                sum += power(l.intensity) / total;
                (sum * f64::from(SHARE_UNITS))
                    .round()
                    .min(f64::from(SHARE_UNITS)) as u32
            })
            .collect();
        *ends.last_mut().expect("a scene with power has a light") = SHARE_UNITS;
        Some(LightShares { ends })
    }

    /// The light number `u` (in [0, 1)) picks, and the chance it had.
    pub fn pick(&self, u: f64) -> (usize, f64) {
        let units = u * f64::from(SHARE_UNITS);
        let j = self
            .ends
            .iter()
            .position(|&end| units < f64::from(end))
            .unwrap_or(self.ends.len() - 1);
        (j, self.chance(j))
    }

    /// Light `j`'s chance.
    pub fn chance(&self, j: usize) -> f64 {
        let below = if j == 0 { 0 } else { self.ends[j - 1] };
        f64::from(self.ends[j] - below) / f64::from(SHARE_UNITS)
    }

    /// Light `j`'s running share as a fraction (exact in `f32`).
    pub fn end(&self, j: usize) -> f32 {
        self.ends[j] as f32 / SHARE_UNITS as f32
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene::{default_scene, PointLight};
    use glam::DVec3;

    fn shares(intensities: &[f64]) -> Option<LightShares> {
        let mut scene = default_scene();
        scene.lights = intensities
            .iter()
            .map(|&i| PointLight {
                position: DVec3::new(0.0, 5.0, 0.0),
                intensity: DVec3::splat(i),
            })
            .collect();
        LightShares::of(&RtScene::new(&scene))
    }

    /// Shares follow power; chances add to 1; every number picks the light
    /// whose share holds it, the boundaries included.
    #[test]
    fn lights_are_picked_in_proportion_to_power() {
        let s = shares(&[1.0, 3.0]).unwrap();
        assert_eq!(s.ends, vec![SHARE_UNITS / 4, SHARE_UNITS]);
        assert_eq!(s.chance(0) + s.chance(1), 1.0);
        assert_eq!(s.pick(0.0).0, 0);
        assert_eq!(s.pick(0.25 - 1.0 / 16777216.0).0, 0);
        assert_eq!(s.pick(0.25), (1, 0.75));
        assert_eq!(s.end(0), 0.25);
        assert!(shares(&[0.0, 0.0]).is_none());
        assert!(shares(&[]).is_none());
        // A dark light takes no numbers.
        let s = shares(&[0.0, 2.0]).unwrap();
        assert_eq!(s.pick(0.0), (1, 1.0));
    }
}
