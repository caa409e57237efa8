//! The forward tracer's film as the GPU sums it: each pixel's red, green
//! and blue splats in fixed point, `FILM_ONE` to 1.0, added as integers.
//! Integer sums do not depend on the order the splats arrive in, so a
//! render's film is the same bits at any thread count, and the films of
//! renders that split the photons between them (batches, shards on other
//! machines) add up to the film of one render of them all. `PhotonStats`
//! counts what the photons did, and `PhotonJob` says which photons a
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

/// Which photons a render traces.
#[derive(Debug, Clone)]
pub struct PhotonJob {
    /// The photons of the whole image, over which the lights' power is
    /// split (each photon's flux divides by it).
    pub total: u32,
    /// The photons this render traces: `0..total`, or a shard's part.
    pub range: Range<u32>,
}

impl PhotonJob {
    /// All `total` photons.
    pub fn all(total: u32) -> Self {
        PhotonJob {
            total,
            range: 0..total,
        }
    }
}

/// What the photons of a render did.
#[derive(Debug, Default, Clone, Copy, PartialEq, Eq, serde::Serialize)]
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
}
