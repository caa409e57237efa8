//! Diffuse bounces (secondary illumination): the counter-based random
//! numbers the GPU draws too (`shaders/include/rt_bounce.glsl`), and the
//! cosine-weighted direction they pick (docs/lighting-model.md,
//! "Backward: the eye's ray tree with diffuse bounces").

use glam::DVec3;

/// The bounce that a path takes past this many bounces is decided by
/// Russian roulette.
pub const ROULETTE_AFTER: u32 = 3;

/// Jarzynski and Olano's 4-D hash (2020), "Hash functions for GPU
/// rendering": one call turns a counter into four independent words, so a
/// pixel's paths need no state carried between threads or runs.
pub fn pcg4d(v: [u32; 4]) -> [u32; 4] {
    let mut v = v.map(|x| x.wrapping_mul(1_664_525).wrapping_add(1_013_904_223));
    let mix = |v: &mut [u32; 4]| {
        v[0] = v[0].wrapping_add(v[1].wrapping_mul(v[3]));
        v[1] = v[1].wrapping_add(v[2].wrapping_mul(v[0]));
        v[2] = v[2].wrapping_add(v[0].wrapping_mul(v[1]));
        v[3] = v[3].wrapping_add(v[1].wrapping_mul(v[2]));
    };
    mix(&mut v);
    v = v.map(|x| x ^ (x >> 16));
    mix(&mut v);
    v
}

/// The top 24 bits of `x` as a number in `[0, 1)`: exact in `f32`, so the
/// GPU and the CPU start from the same value.
pub fn unit(x: u32) -> f64 {
    f64::from(x >> 8) / 16_777_216.0
}

/// The three numbers a bounce from a hit at tree level `level` of sample
/// `sample` of pixel `pixel` (`y * width + x`) uses: two for its direction,
/// one for Russian roulette.
pub fn bounce_numbers(pixel: u32, sample: u32, level: u32) -> [f64; 3] {
    let x = pcg4d([pixel, sample, level, 0]);
    [unit(x[0]), unit(x[1]), unit(x[2])]
}

/// The four numbers photon `i` of a forward render uses at the `level`-th
/// surface of its path (0: its light, direction; the fourth word of the
/// key, 2, keeps them apart from the eye's bounces).
pub fn photon_numbers(i: u32, level: u32) -> [f64; 4] {
    pcg4d([i, level, 0, 2]).map(unit)
}

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

    /// The hash's words for a few counters, worked out by hand from its
    /// definition with Python's arbitrary-precision integers masked to 32
    /// bits (the GLSL twin is held to the same values through the images
    /// `tests/gpu/path_trace.rs` compares).
    #[test]
    fn pcg4d_matches_its_definition() {
        assert_eq!(
            pcg4d([0, 0, 0, 0]),
            [0x0f02_f829, 0x2d56_8769, 0x32b0_c43b, 0xd325_48ea]
        );
        assert_eq!(
            pcg4d([1, 2, 3, 4]),
            [0x3622_cd16, 0xf114_71d8, 0xe110_9b3f, 0x02b9_4c2f]
        );
    }

    #[test]
    fn units_lie_in_the_half_open_interval() {
        assert_eq!(unit(0), 0.0);
        assert_eq!(unit(u32::MAX), 1.0 - 1.0 / 16_777_216.0);
    }

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
                let [u0, u1, _] = bounce_numbers(i, 7, 1);
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
