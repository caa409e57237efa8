//! The sRGB transfer function and its inverse, for 8-bit values: what PNG
//! files hold, and what the raster modes' 8-bit colour target stores.

/// The sRGB transfer function applied to a linear value clamped to [0, 1].
pub fn linear_to_srgb8(v: f32) -> u8 {
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
    let s = f32::from(v) / 255.0;
    if s <= 0.040_45 {
        s / 12.92
    } else {
        ((s + 0.055) / 1.055).powf(2.4)
    }
}
