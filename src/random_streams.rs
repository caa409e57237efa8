//! The random numbers of every tracer that draws any (the backward tracer
//! with diffuse bounces, the forward tracer, the photon map's photons and
//! eye paths), on the CPU and, through its GLSL twin
//! `shaders/include/random_streams.glsl`, on the GPU: the same names and
//! the same bits.
//!
//! Numbers are counter-based: each draw hashes a key of four words with
//! [`pcg4d`], so a path's numbers are a function of what the path is (a
//! pixel's sample, a photon) and not of the thread, lane, dispatch or
//! machine that traces it; a render split into shards or batches draws
//! what one render of the whole does. The key's last word names the
//! [`Stream`], which keeps the tracers' numbers apart. A [`Sampler`],
//! started for one path, draws its numbers level by level (a level is a
//! surface along the path), in the spirit of pbrt's samplers.

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

/// The streams: the last word of every key, one per kind of path. The
/// values are the keys' words since the tracers first drew them (1 and 4
/// were never used); the GLSL twin names them `STREAM_*`.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[repr(u32)]
pub enum Stream {
    /// The backward tracer's diffuse bounces (`--bounces`): key `(pixel,
    /// sample, level)`, the bounce from the hit at tree level `level`;
    /// words 0 and 1 its direction, word 2 its Russian roulette.
    Bounce = 0,
    /// Photons, of the forward tracer and of the photon map alike: key
    /// `(photon, level, 0)`; at level 0 the light (word 0) and the
    /// direction (words 1, 2), at level `n` the event at the `n`-th
    /// surface (word 0 picks it, words 1 and 2 a diffuse direction).
    Photon = 2,
    /// The photon map's eye paths: key `(pixel, pass, level)`; at level 0
    /// the point of the pixel (words 0, 1), at level `n` the event at the
    /// `n`-th surface (word 0).
    CausticEye = 3,
    /// The scramble seeds of a path-traced pixel's samples
    /// (`cpu::raytrace::pixel_sample`): key `(pixel, i & 1, 0)`, one seed
    /// pair per stream of samples (even, odd).
    PixelScramble = 5,
}

impl Stream {
    /// Every stream, for the test that ties them to the GLSL twin.
    pub const ALL: [Stream; 4] = [
        Stream::Bounce,
        Stream::Photon,
        Stream::CausticEye,
        Stream::PixelScramble,
    ];

    /// The constant that names the stream in `random_streams.glsl`.
    pub fn glsl_name(self) -> &'static str {
        match self {
            Stream::Bounce => "STREAM_BOUNCE",
            Stream::Photon => "STREAM_PHOTON",
            Stream::CausticEye => "STREAM_CAUSTIC_EYE",
            Stream::PixelScramble => "STREAM_PIXEL_SCRAMBLE",
        }
    }

    /// The four words of this stream at key `(a, b, c)`.
    pub fn words(self, a: u32, b: u32, c: u32) -> [u32; 4] {
        pcg4d([a, b, c, self as u32])
    }
}

/// One path's numbers: started for a pixel's sample, a photon or an eye
/// path of the photon map, then drawn level by level ([`Sampler::at_level`]).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Sampler {
    stream: Stream,
    /// The key's first two words: `(pixel, sample)`, `(photon, 0)` or
    /// `(pixel, pass)`.
    path: [u32; 2],
}

impl Sampler {
    /// Sample `sample` of pixel `pixel` (`y * width + x`): its bounces'
    /// numbers.
    pub fn start_pixel_sample(pixel: u32, sample: u32) -> Self {
        Sampler {
            stream: Stream::Bounce,
            path: [pixel, sample],
        }
    }

    /// Photon `photon` of a forward render or of a pass of the photon map.
    pub fn start_photon(photon: u32) -> Self {
        Sampler {
            stream: Stream::Photon,
            path: [photon, 0],
        }
    }

    /// The photon map's eye path through pixel `pixel` in pass `pass`.
    pub fn start_eye_path(pixel: u32, pass: u32) -> Self {
        Sampler {
            stream: Stream::CausticEye,
            path: [pixel, pass],
        }
    }

    /// The four numbers the path draws at `level`, to be taken in order.
    /// The photons' keys put the level second, the others' third.
    pub fn at_level(self, level: u32) -> Draw {
        let [a, b] = self.path;
        let words = match self.stream {
            Stream::Photon => self.stream.words(a, level, b),
            _ => self.stream.words(a, b, level),
        };
        Draw { words, next: 0 }
    }
}

/// The four numbers of one level of a path, taken in order by
/// [`Draw::get_1d`] and [`Draw::get_2d`] (or all at once, [`Draw::all`]).
#[derive(Clone, Copy, Debug)]
pub struct Draw {
    words: [u32; 4],
    next: usize,
}

impl Draw {
    /// The next number. Panics past the fourth: a level has four.
    pub fn get_1d(&mut self) -> f64 {
        let u = unit(self.words[self.next]);
        self.next += 1;
        u
    }

    /// The next two numbers.
    pub fn get_2d(&mut self) -> [f64; 2] {
        [self.get_1d(), self.get_1d()]
    }

    /// All four numbers, in order, whatever was taken.
    pub fn all(self) -> [f64; 4] {
        self.words.map(unit)
    }
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

    /// The samplers draw the keys the tracers drew before they were named:
    /// `(pixel, sample, level, 0)`, `(photon, level, 0, 2)`, `(pixel,
    /// pass, level, 3)`.
    #[test]
    fn samplers_hash_their_streams_keys() {
        let numbers = |key| pcg4d(key).map(unit);
        assert_eq!(
            Sampler::start_pixel_sample(7, 9).at_level(2).all(),
            numbers([7, 9, 2, 0])
        );
        assert_eq!(
            Sampler::start_photon(7).at_level(2).all(),
            numbers([7, 2, 0, 2])
        );
        assert_eq!(
            Sampler::start_eye_path(7, 9).at_level(2).all(),
            numbers([7, 9, 2, 3])
        );
        let mut draw = Sampler::start_photon(7).at_level(0);
        let [u0, u1, u2, _] = draw.all();
        assert_eq!((draw.get_1d(), draw.get_2d()), (u0, [u1, u2]));
    }

    /// The GLSL twin names each stream with the same value: its
    /// `const uint STREAM_* = Nu;` lines, read from the header, are the
    /// streams here, no more and no fewer.
    #[test]
    fn the_glsl_streams_are_these() {
        let header = include_str!("../shaders/include/random_streams.glsl");
        let mut declared: Vec<(String, u32)> = header
            .lines()
            .filter_map(|line| {
                let rest = line.trim().strip_prefix("const uint STREAM_")?;
                let (name, value) = rest.split_once(" = ")?;
                let value = value.strip_suffix("u;")?.parse().ok()?;
                Some((format!("STREAM_{name}"), value))
            })
            .collect();
        declared.sort();
        let mut ours: Vec<(String, u32)> = Stream::ALL
            .iter()
            .map(|&s| (s.glsl_name().to_string(), s as u32))
            .collect();
        ours.sort();
        assert_eq!(declared, ours);
    }
}
