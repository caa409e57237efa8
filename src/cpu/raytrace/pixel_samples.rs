//! Where in its pixel each sample of a path-traced render (the backward
//! tracer with `--bounces`) looks: a progressive sequence, so that any
//! prefix of a pixel's samples covers the whole pixel and is an unbiased
//! estimate of it, and so that a render cut short (`--time`, `--error`) or
//! split (`--shard`) is an honest image of what it traced
//! (docs/raytracing.md, "Samples of a pixel"). The GPU's twin is
//! `shaders/include/rt_pixel_samples.glsl`; both give the same bits.
//!
//! A pixel's samples are two interleaved streams (even samples, odd
//! samples), each the first two dimensions of the Sobol sequence (a
//! (0,2)-sequence: every aligned run of `2^k` points has one point in each
//! of the `2^k` elementary boxes of every shape), scrambled by a
//! hash-based Owen scramble (Burley 2020, "Practical hash-based Owen
//! scrambling", after Laine and Karras) whose seed comes from the pixel and
//! the stream. Owen scrambling keeps the net's strata and makes every point
//! uniform over the pixel (so every prefix is unbiased); the two streams'
//! scrambles are independent, so the even and the odd samples are two
//! independent estimates, which is what `--error`'s estimate of the error
//! needs (`error_budget`). Sample `i` is a function of `(pixel, i)` alone:
//! it keeps its point whatever range of samples a run traces, so shards
//! still add up to the whole render bit for bit.
//!
//! The Whitted tracer (no bounces) keeps its grid of cell centres
//! (`cpu::raytrace::sample_offsets`): its samples are all traced at once.

use crate::random_streams::Stream;

/// The point sample `i` of pixel `pixel` (`y * width + x`) looks through,
/// as an offset `(sx, sy)` in `(0, 1)` from the pixel's top-left corner.
/// Each coordinate is a multiple of `2^-24`, exact in `f32` (the GPU starts
/// from the same value), and the centre of a cell of `2^-23`, so that the
/// points' mean is the pixel's centre.
pub fn pixel_sample(pixel: u32, i: u32) -> (f64, f64) {
    let [x, y] = sample_words(pixel, i);
    (unit_centre(x), unit_centre(y))
}

/// The two scrambled words of sample `i` of `pixel`, before they become
/// numbers.
fn sample_words(pixel: u32, i: u32) -> [u32; 2] {
    let (stream, index) = (i & 1, i >> 1);
    // The scramble's first choices (the top bits of the point) take the
    // seed's low bits, where the hash's products mix least: reversed, they
    // are its best-mixed high bits (the streams' first points fell in one
    // cell of 16 x 16 half as often as independent points do, unreversed).
    let seeds = Stream::PixelScramble
        .words(pixel, stream, 0)
        .map(u32::reverse_bits);
    [
        owen_scramble(index.reverse_bits(), seeds[0]),
        owen_scramble(sobol_second(index), seeds[1]),
    ]
}

/// The Sobol sequence's second dimension (primitive polynomial `x + 1`):
/// the generator matrix's column `k` is the one before it XOR itself
/// shifted right by one, from `2^31`. Its first dimension is the index
/// with its bits reversed.
fn sobol_second(mut index: u32) -> u32 {
    let mut column = 1u32 << 31;
    let mut word = 0;
    while index != 0 {
        if index & 1 != 0 {
            word ^= column;
        }
        index >>= 1;
        column ^= column >> 1;
    }
    word
}

/// A hash-based Owen scramble of a fixed-point number in `[0, 1)` (its bits
/// from the most significant): each bit is flipped or not by a hash of the
/// seed and of the bits above it, so points in one elementary box stay in
/// one box. The hash works on the reversed word, where the bits above are
/// the lower ones, which an addition's carries and a multiplication by an
/// even number reach only upwards (Laine and Karras's permutation, Burley's
/// constants).
fn owen_scramble(word: u32, seed: u32) -> u32 {
    let mut x = word.reverse_bits().wrapping_add(seed);
    for c in [0x6c50_b47c, 0xb82f_1e52, 0xc7af_e638, 0x8d22_f6e6] {
        x ^= x.wrapping_mul(c);
    }
    x.reverse_bits()
}

/// The top 23 bits of `word` as the centre of one of `2^23` cells of
/// `[0, 1)`: `(2k + 1) / 2^24`, exact in `f32`.
fn unit_centre(word: u32) -> f64 {
    f64::from(((word >> 9) << 1) | 1) / 16_777_216.0
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The first points of the unscrambled sequence, worked out by hand:
    /// the second dimension's columns are 0x8, 0xc, 0xa, 0xf (top nibble).
    #[test]
    fn sobol_second_dimension_by_hand() {
        let top = |i| sobol_second(i) >> 28;
        assert_eq!([0, 1, 2, 3, 4, 5].map(top), [0x0, 0x8, 0xc, 0x4, 0xa, 0x2]);
    }

    /// The scramble keeps strata: two words that share their top `k` bits
    /// still share them after it, and words that differ in them still differ.
    #[test]
    fn owen_scramble_keeps_elementary_intervals() {
        let seed = 0x1234_5678;
        for a in (0u32..4096).map(|k| k.wrapping_mul(0x9e37_79b9)) {
            for k in [1, 3, 8] {
                let b = (a & !(u32::MAX >> k)) | (a.wrapping_mul(7) & (u32::MAX >> k));
                let (sa, sb) = (owen_scramble(a, seed), owen_scramble(b, seed));
                assert_eq!(sa >> (32 - k), sb >> (32 - k), "{a:x} {b:x} top {k}");
            }
        }
    }

    /// Every aligned run of 2^k samples of one stream is a (0,k,2)-net:
    /// one point in each of the 2^k boxes of every shape `2^-a x 2^-(k-a)`.
    /// So any prefix of a pixel's samples is spread over the whole pixel
    /// (the grid of cell centres put the first quarter in the top rows).
    #[test]
    fn each_stream_is_a_net_in_every_aligned_run() {
        for pixel in [0, 7, 123_456] {
            for stream in 0..2 {
                for k in [2u32, 4, 6] {
                    let n = 1u32 << k;
                    for run in 0..3 {
                        let points: Vec<(f64, f64)> = (run * n..(run + 1) * n)
                            .map(|j| pixel_sample(pixel, 2 * j + stream))
                            .collect();
                        for a in 0..=k {
                            let (cols, rows) = (1u32 << a, 1u32 << (k - a));
                            let mut seen = vec![false; n as usize];
                            for &(x, y) in &points {
                                let cell = (y * f64::from(rows)) as u32 * cols
                                    + (x * f64::from(cols)) as u32;
                                assert!(!seen[cell as usize], "pixel {pixel} k {k} a {a}");
                                seen[cell as usize] = true;
                            }
                        }
                    }
                }
            }
        }
    }

    /// Every point is uniform over the pixel: over many pixels, a sample's
    /// points fall in each of 16 x 16 cells as often as a uniform draw
    /// would (chi-square, 255 degrees of freedom: its 99.9% point is 330),
    /// for the first sample and a later one of each stream.
    #[test]
    fn every_sample_is_uniform_over_its_pixel() {
        for i in [0, 1, 6, 37] {
            let mut counts = [0u32; 256];
            let pixels = 256 * 64;
            for pixel in 0..pixels {
                let (x, y) = pixel_sample(pixel, i);
                counts[(y * 16.0) as usize * 16 + (x * 16.0) as usize] += 1;
            }
            let expected = f64::from(pixels) / 256.0;
            let chi2: f64 = counts
                .iter()
                .map(|&c| (f64::from(c) - expected).powi(2) / expected)
                .sum();
            assert!(chi2 < 330.0, "sample {i}: chi-square {chi2}");
        }
    }

    /// The two streams of a pixel, and the streams of neighbouring pixels,
    /// are scrambled apart: their first points fall in one cell of 16 x 16
    /// about 1 time in 256 over many pixels, as independent points do (the
    /// seeds' low bits unreversed gave 1 in 508 between the streams).
    #[test]
    fn streams_and_neighbours_are_scrambled_independently() {
        let pixels = 65_536u32;
        let cell = |(x, y): (f64, f64)| ((x * 16.0) as u32, (y * 16.0) as u32);
        // (pixel, sample) against (pixel, sample): the streams of a pixel,
        // neighbours along a row, neighbours down a column of 80.
        let pairs: [[u32; 4]; 3] = [[0, 0, 0, 1], [0, 0, 1, 0], [0, 1, 80, 1]];
        for (k, [da, ia, db, ib]) in pairs.into_iter().enumerate() {
            let same = (0..pixels)
                .filter(|&p| cell(pixel_sample(p + da, ia)) == cell(pixel_sample(p + db, ib)))
                .count() as f64;
            let rate = same / f64::from(pixels);
            // 65536 pairs at 1/256: 256 expected, standard deviation 16.
            assert!((rate * 256.0 - 1.0).abs() < 0.25, "pair {k}: {rate}");
        }
    }

    /// Coordinates are exact in f32 and strictly inside the pixel.
    #[test]
    fn coordinates_are_exact_in_f32() {
        for i in 0..64 {
            let (x, y) = pixel_sample(99, i);
            for v in [x, y] {
                assert_eq!(f64::from(v as f32), v);
                assert!(v > 0.0 && v < 1.0);
            }
        }
    }
}
