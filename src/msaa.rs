//! Multisampling of the raster modes: how many samples a pixel has, where
//! they lie (Vulkan's standard sample locations), and whether the surface is
//! shaded once per pixel or at every sample. The contract is
//! `docs/lighting-model.md`, "Samples per pixel"; the GPU takes its sample
//! positions from the driver (which must offer the standard ones), the CPU
//! reference from [`positions`].

use std::fmt;

/// Samples per pixel and where the shading is evaluated.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, serde::Serialize, serde::Deserialize)]
pub struct Msaa {
    /// Samples per pixel: 1 is one sample at the pixel's centre.
    pub samples: u32,
    /// Shade every covered sample at its own position (sample-rate
    /// shading), rather than once per pixel at the pixel's centre.
    pub per_sample: bool,
}

impl Default for Msaa {
    /// One sample at the centre: the images of before multisampling.
    fn default() -> Self {
        Msaa {
            samples: 1,
            per_sample: false,
        }
    }
}

/// The counts that have standard sample locations (and that the CPU
/// reference renders).
pub const STANDARD_COUNTS: [u32; 5] = [1, 2, 4, 8, 16];

impl Msaa {
    /// More than one sample: a multisampled target and a resolve.
    pub fn is_multisampled(self) -> bool {
        self.samples > 1
    }

    /// Where each of a pixel's samples lies, from the pixel's top-left
    /// corner in pixels (y down): Vulkan's standard sample locations.
    pub fn positions(self) -> Option<&'static [(f64, f64)]> {
        positions(self.samples)
    }
}

/// Vulkan's standard sample locations for `samples` per pixel
/// (`VkPhysicalDeviceLimits::standardSampleLocations`), in the order of the
/// sample indices; `None` for a count without them.
pub fn positions(samples: u32) -> Option<&'static [(f64, f64)]> {
    const ONE: [(f64, f64); 1] = [(0.5, 0.5)];
    const TWO: [(f64, f64); 2] = [(0.75, 0.75), (0.25, 0.25)];
    const FOUR: [(f64, f64); 4] = [
        (0.375, 0.125),
        (0.875, 0.375),
        (0.125, 0.625),
        (0.625, 0.875),
    ];
    const EIGHT: [(f64, f64); 8] = [
        (0.5625, 0.3125),
        (0.4375, 0.6875),
        (0.8125, 0.5625),
        (0.3125, 0.1875),
        (0.1875, 0.8125),
        (0.0625, 0.4375),
        (0.6875, 0.9375),
        (0.9375, 0.0625),
    ];
    const SIXTEEN: [(f64, f64); 16] = [
        (0.5625, 0.5625),
        (0.4375, 0.3125),
        (0.3125, 0.625),
        (0.75, 0.4375),
        (0.1875, 0.375),
        (0.625, 0.8125),
        (0.8125, 0.6875),
        (0.6875, 0.1875),
        (0.375, 0.875),
        (0.5, 0.0625),
        (0.25, 0.125),
        (0.125, 0.75),
        (0.0, 0.5),
        (0.9375, 0.25),
        (0.875, 0.9375),
        (0.0625, 0.0),
    ];
    match samples {
        1 => Some(&ONE),
        2 => Some(&TWO),
        4 => Some(&FOUR),
        8 => Some(&EIGHT),
        16 => Some(&SIXTEEN),
        _ => None,
    }
}

impl fmt::Display for Msaa {
    /// `4`, or `4,per-sample`: what `--msaa` and the scene's `msaa` take.
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}", self.samples)?;
        if self.per_sample {
            write!(f, ",per-sample")?;
        }
        Ok(())
    }
}

impl std::str::FromStr for Msaa {
    type Err = String;

    /// `N`, `N,per-sample` or `N,per-pixel`, N from 1 to 64; whether the
    /// device renders N is for the renderer to say.
    fn from_str(text: &str) -> Result<Self, String> {
        let (count, rate) = match text.split_once(',') {
            Some((count, rate)) => (count.trim(), Some(rate.trim())),
            None => (text.trim(), None),
        };
        let samples = count
            .parse::<u32>()
            .ok()
            .filter(|n| (1..=64).contains(n))
            .ok_or_else(|| {
                format!(
                    "`{text}`: expected a sample count (1, 2, 4, 8 or 16 where the device has them; `shadelab info` lists its counts), optionally followed by `,per-sample`"
                )
            })?;
        let per_sample = match rate {
            None | Some("per-pixel") => false,
            Some("per-sample") => true,
            Some(other) => {
                return Err(format!(
                    "`{text}`: unknown shading rate `{other}`; expected per-pixel or per-sample"
                ))
            }
        };
        Ok(Msaa {
            samples,
            per_sample,
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn counts_and_rates_read_and_print_alike() {
        for text in ["1", "4", "8,per-sample", "16"] {
            let msaa: Msaa = text.parse().unwrap();
            assert_eq!(msaa.to_string(), text);
        }
        assert_eq!("4,per-pixel".parse::<Msaa>().unwrap().to_string(), "4");
        for bad in ["0", "65", "-1", "four", "4,sometimes", ""] {
            assert!(bad.parse::<Msaa>().is_err(), "{bad}");
        }
    }

    /// Every standard pattern lies inside the pixel and has as many
    /// distinct positions as samples; up to 8 they average to the pixel's
    /// centre, so a resolve is centred where one sample was (16's, taken
    /// from Direct3D's as Vulkan's is, averages 1/32 pixel up and left).
    #[test]
    fn the_standard_locations_are_distinct_inside_and_centred() {
        for n in STANDARD_COUNTS {
            let p = positions(n).unwrap();
            assert_eq!(p.len(), n as usize);
            let mean = p.iter().fold((0.0, 0.0), |a, q| (a.0 + q.0, a.1 + q.1));
            let centre = if n == 16 { 0.5 - 1.0 / 32.0 } else { 0.5 };
            assert_eq!(
                (mean.0 / f64::from(n), mean.1 / f64::from(n)),
                (centre, centre),
                "{n}"
            );
            for (i, a) in p.iter().enumerate() {
                assert!((0.0..1.0).contains(&a.0) && (0.0..1.0).contains(&a.1));
                assert!(p[..i].iter().all(|b| b != a), "{n}: {a:?} twice");
            }
        }
        assert!(positions(3).is_none() && positions(32).is_none());
    }
}
