//! Diffuse bounces (secondary illumination): the cosine-weighted direction
//! a bounce's numbers (`random_streams`) pick and Russian roulette, as the
//! GPU's `shaders/include/rt_bounce.glsl` (docs/lighting-model.md,
//! "Backward: the eye's ray tree with diffuse bounces"). The forward
//! tracer's photons bounce by the same direction.

use glam::DVec3;

/// The bounce that a path takes past this many bounces is decided by
/// Russian roulette.
pub const ROULETTE_AFTER: u32 = 3;

/// A direction about the unit normal `n`, distributed as `(n·w) / pi`
/// when `u0, u1` are uniform: azimuth `2 pi u0`, `sin^2` of the polar
/// angle `u1`, in the frame Duff et al. (2017) complete `n` to.
pub fn cosine_direction(n: DVec3, u0: f64, u1: f64) -> DVec3 {
    let s = if n.z >= 0.0 { 1.0 } else { -1.0 };
    let a = -1.0 / (s + n.z);
    let b = n.x * n.y * a;
    let t = DVec3::new(1.0 + s * n.x * n.x * a, s * b, -s * n.x);
    let bitangent = DVec3::new(b, s + n.y * n.y * a, -n.y);
    let phi = 2.0 * std::f64::consts::PI * u0;
    let r = u1.sqrt();
    r * phi.cos() * t + r * phi.sin() * bitangent + (1.0 - u1).max(0.0).sqrt() * n
}

/// Russian roulette for a bounce of weight `weight`: `None` where the path
/// ends, else the weight divided by the chance it had to go on,
/// `q = min(1, max channel)`, decided by `u < q`.
pub fn roulette(weight: DVec3, u: f64) -> Option<DVec3> {
    let q = weight.max_element().min(1.0);
    (u < q).then(|| weight / q)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::random_streams::Sampler;

    /// Directions are unit, on the normal's side, and their mean cosine is
    /// 2/3 (the mean of cos under a cosine-weighted hemisphere), their
    /// mean along the tangents 0, for normals of every sign.
    #[test]
    fn cosine_directions_are_cosine_distributed() {
        for n in [
            DVec3::Z,
            DVec3::NEG_Z,
            DVec3::new(0.48, -0.6, 0.64),
            DVec3::new(-0.6, 0.0, -0.8),
        ] {
            let (mut cos, mut mean) = (0.0, DVec3::ZERO);
            let count = 20_000;
            for i in 0..count {
                let [u0, u1] = Sampler::start_pixel_sample(i, 7).at_level(1).get_2d();
                let w = cosine_direction(n, u0, u1);
                assert!((w.length() - 1.0).abs() < 1e-12, "{w}");
                assert!(w.dot(n) >= 0.0);
                cos += w.dot(n);
                mean += w - w.dot(n) * n;
            }
            let count = f64::from(count);
            // Standard deviation of cos is sqrt(1/2 - 4/9) = 0.236, of the
            // mean of 20000 0.0017: 0.01 is six of them.
            assert!(
                (cos / count - 2.0 / 3.0).abs() < 0.01,
                "{n}: {}",
                cos / count
            );
            assert!((mean / count).length() < 0.01, "{n}: {mean}");
        }
    }

    #[test]
    fn roulette_keeps_the_expectation() {
        let w = DVec3::new(0.25, 0.5, 0.1);
        assert_eq!(roulette(w, 0.49), Some(w / 0.5));
        assert_eq!(roulette(w, 0.5), None);
        assert_eq!(roulette(DVec3::splat(2.0), 0.999), Some(DVec3::splat(2.0)));
    }
}
