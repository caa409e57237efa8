//! The sRGB transfer function and its inverse, for 8-bit values: what PNG
//! files hold, and what the raster modes' 8-bit colour target stores.

/// The sRGB transfer function applied to a linear value clamped to [0, 1].
///
/// The same byte as `linear_to_srgb8_exact` for every input, found from 255
/// thresholds instead of through `powf`, which was a sixth of `check`'s
/// time (every PNG written, every FLIP input): each threshold is the least
/// value whose byte is one more, found by bisecting the exact function
/// once per process. The value's top 16 bits pick where to start among them
/// (within one or two of the answer), so a value costs a table read and a
/// comparison or two, not a search.
pub fn linear_to_srgb8(v: f32) -> u8 {
    // NaN, negatives and both zeros (whose bits would index past the table).
    if v.is_nan() || v <= 0.0 {
        return 0;
    }
    let c = v.min(1.0);
    let table = table();
    let mut byte = table.start[(c.to_bits() >> 16) as usize];
    while byte < 255 && table.thresholds[usize::from(byte)] <= c {
        byte += 1;
    }
    byte
}

struct Table {
    /// `thresholds[k]`: the least value in [0, 1] whose byte is `k + 1`.
    thresholds: [f32; 255],
    /// `start[b]`: the byte of the least value whose top 16 bits are `b`.
    start: Vec<u8>,
}

fn table() -> &'static Table {
    static TABLE: std::sync::OnceLock<Table> = std::sync::OnceLock::new();
    TABLE.get_or_init(|| {
        let thresholds: [f32; 255] = std::array::from_fn(|k| {
            let byte = k as u8 + 1;
            // Non-negative floats order as their bit patterns do.
            let (mut low, mut high) = (0u32, 1.0f32.to_bits());
            while low < high {
                let mid = low + (high - low) / 2;
                if linear_to_srgb8_exact(f32::from_bits(mid)) >= byte {
                    high = mid;
                } else {
                    low = mid + 1;
                }
            }
            f32::from_bits(low)
        });
        let start = (0..=(1.0f32.to_bits() >> 16))
            .map(|top| {
                let least = f32::from_bits(top << 16);
                thresholds.partition_point(|&t| t <= least) as u8
            })
            .collect();
        Table { thresholds, start }
    })
}

/// The transfer function as the formula gives it (`linear_to_srgb8` is
/// its fast form).
pub fn linear_to_srgb8_exact(v: f32) -> u8 {
    let c = if v.is_nan() { 0.0 } else { v.clamp(0.0, 1.0) };
    let s = if c <= 0.003_130_8 {
        12.92 * c
    } else {
        1.055 * c.powf(1.0 / 2.4) - 0.055
    };
    (s * 255.0 + 0.5) as u8
}

/// The linear value of an 8-bit sRGB value; `linear_to_srgb8` maps it back
/// to the same byte (tested in `metrics::flip`).
pub fn srgb8_to_linear(v: u8) -> f32 {
    srgb_to_linear(f32::from(v) / 255.0)
}

/// The linear value of a 16-bit sRGB value (a 16-bit PNG's samples).
pub fn srgb16_to_linear(v: u16) -> f32 {
    srgb_to_linear(f32::from(v) / 65535.0)
}

/// The sRGB decoding of `s` in [0, 1].
fn srgb_to_linear(s: f32) -> f32 {
    if s <= 0.040_45 {
        s / 12.92
    } else {
        ((s + 0.055) / 1.055).powf(2.4)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The fast form gives the formula's byte: on every 97th float in
    /// [0, 1], on every float within 4096 of each threshold (where a wrong
    /// threshold or a formula that is not monotonic would show), and on
    /// the values outside [0, 1] and NaN.
    #[test]
    fn the_thresholds_give_the_formulas_byte() {
        let one = 1.0f32.to_bits();
        let mut checked = 0u64;
        let mut check = |bits: u32| {
            let v = f32::from_bits(bits);
            assert_eq!(linear_to_srgb8(v), linear_to_srgb8_exact(v), "{v:e}");
            checked += 1;
        };
        for bits in (0..=one).step_by(97) {
            check(bits);
        }
        for &t in &table().thresholds {
            let b = t.to_bits();
            for bits in b.saturating_sub(4096)..=(b + 4096).min(one) {
                check(bits);
            }
        }
        assert!(checked > 10_000_000);
        for v in [
            -1.0,
            -0.0,
            1.0,
            1.5,
            f32::INFINITY,
            f32::NEG_INFINITY,
            f32::NAN,
        ] {
            assert_eq!(linear_to_srgb8(v), linear_to_srgb8_exact(v), "{v}");
        }
        assert_eq!(linear_to_srgb8(1.0), 255);
        assert_eq!(linear_to_srgb8(0.0), 0);
    }
}
