//! The forward tracer's film as the GPU sums it: each pixel's red, green
//! and blue splats in fixed point, `FILM_ONE` to 1.0, added as integers.
//! Integer sums do not depend on the order the splats arrive in, so a
//! render's film is the same bits at any thread count, and the films of
//! renders that split the photons between them (batches, shards on other
//! machines) add up to the film of one render of them all. `PhotonStats`
//! counts what the photons did, and `RenderPart` says which photons a
//! render traces, on either tracer.

use std::ops::Range;

use crate::linear_image::LinearImage;

/// 1.0 in the film's fixed point (the shader's `FILM_ONE`): 2^32, so a
/// splat keeps 2^-32 of absolute precision and a pixel holds sums up to
/// 2^31.
pub const FILM_ONE: f64 = 4_294_967_296.0;

/// The largest splat added, in fixed point (the shader's `FILM_MAX`): one
/// absurd splat cannot wrap a pixel's sum.
pub const FILM_MAX: f64 = 9.0e18;

/// A film: `3 * width * height` sums, rows from the top, red, green and
/// blue per pixel.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct FilmSums {
    pub width: u32,
    pub height: u32,
    pub sums: Vec<u64>,
}

impl FilmSums {
    /// A film of `width * height` pixels with nothing on it.
    pub fn zero(width: u32, height: u32) -> Self {
        FilmSums {
            width,
            height,
            sums: vec![0; 3 * width as usize * height as usize],
        }
    }

    /// A film of `width * height` pixels from its sums as the GPU wrote
    /// them (native-endian 64-bit words; the buffer may be longer).
    pub fn from_ne_bytes(width: u32, height: u32, bytes: &[u8]) -> Self {
        let count = 3 * width as usize * height as usize;
        let sums = bytes[..count * 8]
            .chunks_exact(8)
            .map(|w| u64::from_ne_bytes(w.try_into().expect("8 bytes")))
            .collect();
        FilmSums {
            width,
            height,
            sums,
        }
    }

    /// Adds another film of the same size, sum by sum (wrapping, as the
    /// GPU's atomics do, so that adding films in any order gives the
    /// bits one film of all their photons holds). `Err` for another size.
    pub fn add(&mut self, other: &FilmSums) -> Result<(), String> {
        if (self.width, self.height) != (other.width, other.height) {
            return Err(format!(
                "a {}x{} film cannot be added to a {}x{} one",
                other.width, other.height, self.width, self.height
            ));
        }
        for (a, b) in self.sums.iter_mut().zip(&other.sums) {
            *a = a.wrapping_add(*b);
        }
        Ok(())
    }

    /// The image the sums hold.
    pub fn image(&self) -> LinearImage {
        let value = |s: u64| (s as f64 / FILM_ONE) as f32;
        LinearImage {
            width: self.width,
            height: self.height,
            pixels: self
                .sums
                .chunks_exact(3)
                .map(|c| [value(c[0]), value(c[1]), value(c[2])])
                .collect(),
        }
    }
}

/// The image of `film`, which holds `traced` of the `asked` photons or
/// samples per pixel of a part: each term was divided by the render's
/// total, so a part that a time budget stopped short is scaled up by
/// asked over traced, the estimate of what was asked for.
pub fn scaled_image(film: &FilmSums, traced: u64, asked: u32) -> LinearImage {
    let image = film.image();
    let asked = u64::from(asked);
    if traced == 0 || traced >= asked {
        return image;
    }
    let scale = asked as f64 / traced as f64;
    LinearImage {
        pixels: image
            .pixels
            .iter()
            .map(|p| p.map(|v| (f64::from(v) * scale) as f32))
            .collect(),
        ..image
    }
}

/// The first line of a film file: what it is, and its format's version.
/// Version 2 added the sums' checksum to the header; a film of version 1
/// is refused with a word to render its shard again.
pub const FILM_FILE_MAGIC: &[u8] = b"shadelab film 2\n";

/// The first line of the films shadelab wrote before their sums had a
/// checksum.
const FILM_FILE_MAGIC_1: &[u8] = b"shadelab film 1\n";

/// The header key of the sums' checksum.
const SUMS_CHECKSUM: &str = "sums_fnv1a64";

impl FilmSums {
    /// A film file: the magic line, `header` (what made the film: a JSON
    /// object, to which the film's size and its sums' checksum are added)
    /// on one line, then the sums as little-endian 64-bit words.
    pub fn to_file_bytes(&self, header: &serde_json::Value) -> Vec<u8> {
        let words: Vec<u8> = self.sums.iter().flat_map(|s| s.to_le_bytes()).collect();
        let mut header = header.clone();
        header["width"] = self.width.into();
        header["height"] = self.height.into();
        header[SUMS_CHECKSUM] = crate::digest::fnv1a_hex(&words).into();
        let mut bytes = FILM_FILE_MAGIC.to_vec();
        bytes.extend_from_slice(header.to_string().as_bytes());
        bytes.push(b'\n');
        bytes.extend_from_slice(&words);
        bytes
    }

    /// The header and the film of a film file's bytes; `Err` says what is
    /// wrong with them.
    pub fn from_file_bytes(bytes: &[u8]) -> Result<(serde_json::Value, FilmSums), String> {
        if bytes.starts_with(FILM_FILE_MAGIC_1) {
            return Err("it is a film of an older shadelab (format 1, without a checksum of its sums): render its shard again".into());
        }
        let rest = bytes
            .strip_prefix(FILM_FILE_MAGIC)
            .ok_or("it is not a shadelab film (render --shard writes them)")?;
        let end = rest
            .iter()
            .position(|&b| b == b'\n')
            .ok_or("its header line is cut short")?;
        let header: serde_json::Value = serde_json::from_slice(&rest[..end])
            .map_err(|e| format!("its header is not JSON: {e}"))?;
        let size = |key: &str| {
            header[key]
                .as_u64()
                .and_then(|v| u32::try_from(v).ok())
                .filter(|&v| v > 0)
                .ok_or(format!("its header has no {key}"))
        };
        let (width, height) = (size("width")?, size("height")?);
        let words = &rest[end + 1..];
        let count = 3 * width as usize * height as usize;
        if words.len() != count * 8 {
            return Err(format!(
                "it holds {} bytes of sums where a {width}x{height} film has {}",
                words.len(),
                count * 8
            ));
        }
        let recorded = header[SUMS_CHECKSUM]
            .as_str()
            .ok_or(format!("its header has no {SUMS_CHECKSUM}"))?;
        let actual = crate::digest::fnv1a_hex(words);
        if recorded != actual {
            return Err(format!(
                "its sums are damaged (checksum {actual} where its header says {recorded}): copy or render this shard again"
            ));
        }
        let sums = words
            .chunks_exact(8)
            .map(|w| u64::from_le_bytes(w.try_into().expect("8 bytes")))
            .collect();
        Ok((
            header,
            FilmSums {
                width,
                height,
                sums,
            },
        ))
    }
}

/// The longest a render without a time budget (`--time`) is let run,
/// judged from its first batch: an hour, or the seconds that
/// `SHADELAB_LONGEST_RENDER_S` gives (a CI job may want to fail faster).
pub const UNBUDGETED_LIMIT_S: f64 = 3600.0;

/// `UNBUDGETED_LIMIT_S`, or `SHADELAB_LONGEST_RENDER_S` where that is a
/// number of seconds above 0.
pub fn unbudgeted_limit_s() -> f64 {
    std::env::var("SHADELAB_LONGEST_RENDER_S")
        .ok()
        .and_then(|v| v.trim().parse::<f64>().ok())
        .filter(|s| s.is_finite() && *s > 0.0)
        .unwrap_or(UNBUDGETED_LIMIT_S)
}

/// The fixed point of `value` (non-negative, rounded to nearest): 0 for a
/// value under half a unit, over `FILM_MAX`, or not finite, as the GPU's
/// `film_fixed.glsl` rule.
pub fn to_fixed(value: f64) -> u64 {
    let scaled = value * FILM_ONE;
    if (0.5..=FILM_MAX).contains(&scaled) {
        (scaled + 0.5) as u64
    } else {
        0
    }
}

/// Which of a render's photons (forward) or samples per pixel (backward,
/// with bounces) a run traces.
#[derive(Debug, Clone)]
pub struct RenderPart {
    /// The photons of the whole image, over which the lights' power is
    /// split (each photon's flux divides by it); or the samples each
    /// pixel has (each sample's value divides by it).
    pub total: u32,
    /// The photons or samples this run traces: `0..total`, or a shard's
    /// part.
    pub range: Range<u32>,
    /// A time budget: no batch (or task) starts after it, and the image
    /// is scaled to what was traced (`--time`).
    pub deadline: Option<std::time::Instant>,
    /// An error budget: the RMSE at which the GPU's batches stop, by the
    /// render's own estimate (`error_budget`, `--error`).
    pub error: Option<f64>,
    /// Set by the caller to stop between batches, passes or tasks (as a
    /// spent time budget does; the render then answers `Cancelled`).
    pub cancel: Option<std::sync::Arc<std::sync::atomic::AtomicBool>>,
}

impl RenderPart {
    /// The photons or samples the part asks for.
    pub fn count(&self) -> u32 {
        self.range.end.saturating_sub(self.range.start)
    }

    /// After `done` of the part's photons or samples (`what`) took
    /// `elapsed_s` seconds, the rest's time projected: `Err` says the
    /// figure where, with no time budget, the part would run past
    /// `unbudgeted_limit_s` (a count that is absurd on this machine, found
    /// after its first batch rather than hours later).
    pub fn refuse_if_too_long(&self, done: u32, elapsed_s: f64, what: &str) -> Result<(), String> {
        self.refuse_past(unbudgeted_limit_s(), done, elapsed_s, what)
    }

    fn refuse_past(
        &self,
        limit_s: f64,
        done: u32,
        elapsed_s: f64,
        what: &str,
    ) -> Result<(), String> {
        let budgeted = self.deadline.is_some() || self.error.is_some();
        if budgeted || done == 0 || done >= self.count() {
            return Ok(());
        }
        let rate = f64::from(done) / elapsed_s.max(1e-9);
        let projected = f64::from(self.count()) / rate;
        if projected <= limit_s {
            return Ok(());
        }
        let (figure, unit) = if projected >= 3600.0 {
            (projected / 3600.0, "hours")
        } else {
            (projected, "s")
        };
        Err(format!(
            "{} {what} would take about {figure:.1} {unit} here (the first {done} took {elapsed_s:.2} s), past the {limit_s:.0} s a render may run without a budget; give --time SECONDS to stop at a budget with the estimate of those traced, fewer {what}, or --shard I/N to split them over machines",
            self.count(),
        ))
    }

    /// Whether the next batch, pass or task may start (`first`: none has
    /// yet): never once the caller cancelled (a cancelled render gives no
    /// image, so none of its work is wanted); the first always under a
    /// time budget (an image of no work would be black, not an estimate);
    /// a later one only while the budget lasts. The GPU's batches and
    /// passes and the CPU twin's tasks ask this one rule.
    pub fn may_start(&self, first: bool) -> bool {
        let cancelled =
            (self.cancel.as_ref()).is_some_and(|c| c.load(std::sync::atomic::Ordering::Relaxed));
        let spent = || {
            self.deadline
                .is_some_and(|d| std::time::Instant::now() >= d)
        };
        !cancelled && (first || !spent())
    }

    /// Shard `i` of `n` (1-based) of `total` photons or samples: the
    /// `i`-th of `n` runs of consecutive ones, as even as they go. The
    /// shards of one `total` cover `0..total` once.
    pub fn shard(total: u32, (i, n): (u32, u32)) -> Self {
        let at = |k: u32| (u64::from(total) * u64::from(k) / u64::from(n)) as u32;
        RenderPart {
            total,
            range: at(i - 1)..at(i),
            deadline: None,
            error: None,
            cancel: None,
        }
    }

    /// All `total` photons or samples.
    pub fn all(total: u32) -> Self {
        RenderPart {
            total,
            range: 0..total,
            deadline: None,
            error: None,
            cancel: None,
        }
    }
}

/// What the photons of a render did.
#[derive(Debug, Default, Clone, Copy, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
pub struct PhotonStats {
    /// Photons that left a light.
    pub emitted: u64,
    /// Splats that reached the eye (shadow ray clear, on the image).
    pub splats: u64,
    /// Photons with at least one splat: light that reached the eye.
    pub seen: u64,
    /// Surfaces hit.
    pub hits: u64,
}

impl PhotonStats {
    pub fn add(&mut self, other: &PhotonStats) {
        self.emitted += other.emitted;
        self.splats += other.splats;
        self.seen += other.seen;
        self.hits += other.hits;
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Films add sum by sum whatever the order, and the image reads the
    /// fixed point back.
    #[test]
    fn films_add_in_any_order_to_the_same_bits() {
        let film = |sums: Vec<u64>| FilmSums {
            width: 2,
            height: 1,
            sums,
        };
        let a = film(vec![1 << 32, 0, 3, u64::MAX, 5, 6]);
        let b = film(vec![1 << 31, 7, 0, 2, 0, 1]);
        let mut ab = a.clone();
        ab.add(&b).unwrap();
        let mut ba = b.clone();
        ba.add(&a).unwrap();
        assert_eq!(ab, ba);
        assert_eq!(ab.sums[0], 3 << 31);
        assert_eq!(ab.sums[3], 1, "wraps as the GPU's atomics do");
        assert_eq!(ab.image().pixels[0][0], 1.5);
        let other = FilmSums {
            width: 1,
            height: 2,
            sums: vec![0; 6],
        };
        assert!(ab.add(&other).is_err());
        let bytes: Vec<u8> = a.sums.iter().flat_map(|s| s.to_ne_bytes()).collect();
        assert_eq!(FilmSums::from_ne_bytes(2, 1, &bytes), a);
    }

    /// A film file reads back as written; a cut or foreign one is refused
    /// with the reason.
    #[test]
    fn film_files_round_trip_and_refuse_what_is_not_one() {
        let film = FilmSums {
            width: 2,
            height: 1,
            sums: vec![1, 2, 3, u64::MAX, 5, 6],
        };
        let bytes = film.to_file_bytes(&serde_json::json!({"photons": 7}));
        let (header, back) = FilmSums::from_file_bytes(&bytes).unwrap();
        assert_eq!(back, film);
        assert_eq!(header["photons"], 7);
        let cut = FilmSums::from_file_bytes(&bytes[..bytes.len() - 1]).unwrap_err();
        assert!(cut.contains("bytes of sums"), "{cut}");
        let png = FilmSums::from_file_bytes(b"\x89PNG").unwrap_err();
        assert!(png.contains("not a shadelab film"), "{png}");
        let mut damaged = bytes.clone();
        let at = damaged.len() - 20;
        damaged[at..at + 4].copy_from_slice(&[0x5a; 4]);
        let why = FilmSums::from_file_bytes(&damaged).unwrap_err();
        assert!(why.contains("damaged"), "{why}");
        let mut old = b"shadelab film 1\n".to_vec();
        old.extend_from_slice(&bytes[FILM_FILE_MAGIC.len()..]);
        let why = FilmSums::from_file_bytes(&old).unwrap_err();
        assert!(why.contains("render its shard again"), "{why}");
    }

    /// A part whose first batch says it would run past the limit is
    /// refused with the figure; one within it, one with a time budget,
    /// and a finished one are not.
    #[test]
    fn a_part_projected_past_the_limit_is_refused_with_the_figure() {
        let part = RenderPart::all(4_000_000_000);
        // 2^20 in a second: 3815 s, over the hour.
        let hour = UNBUDGETED_LIMIT_S;
        let refused = part.refuse_past(hour, 1 << 20, 1.0, "photons").unwrap_err();
        assert!(refused.contains("about 1.1 hours"), "{refused}");
        assert!(refused.contains("--time"), "{refused}");
        assert!(part.refuse_past(hour, 1 << 20, 0.9, "photons").is_ok());
        let budgeted = RenderPart {
            deadline: Some(std::time::Instant::now()),
            ..part.clone()
        };
        assert!(budgeted.refuse_past(hour, 1, 10.0, "photons").is_ok());
        assert!(part
            .refuse_past(hour, 4_000_000_000, 1e6, "photons")
            .is_ok());
        let minute = part.refuse_past(60.0, 1 << 20, 0.1, "photons").unwrap_err();
        assert!(minute.contains("about 381.5 s"), "{minute}");
    }

    /// The fixed point rounds to nearest and drops what it cannot hold.
    #[test]
    fn fixed_point_rounds_and_drops_what_it_cannot_hold() {
        assert_eq!(to_fixed(1.0), 1 << 32);
        assert_eq!(to_fixed(0.75 / FILM_ONE), 1);
        assert_eq!(to_fixed(0.25 / FILM_ONE), 0);
        assert_eq!(to_fixed(-1.0), 0);
        assert_eq!(to_fixed(f64::NAN), 0);
        assert_eq!(to_fixed(f64::INFINITY), 0);
    }

    /// Shards cover the photons once, in runs as even as they go.
    #[test]
    fn shards_cover_every_photon_once() {
        for (total, n) in [(10, 3), (7, 7), (1, 4), (u32::MAX, 5)] {
            let mut next = 0;
            for i in 1..=n {
                let job = RenderPart::shard(total, (i, n));
                assert_eq!(job.range.start, next, "{total} in {n}");
                assert!(job.range.end - job.range.start <= total / n + 1);
                next = job.range.end;
            }
            assert_eq!(next, total);
        }
    }
}
