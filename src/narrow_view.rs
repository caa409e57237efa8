//! The narrowest view `f32` renderers can place: a camera whose pixels span
//! less than [`MIN_PIXEL_ANGLE`] is refused, by the TOML loader with the
//! line of `fov_y` and by `render` at the size a render gets.
//!
//! It stands apart from `camera` so that the loader, which `camera` reads
//! through `scene`, can ask it without reading `camera` back.

/// The smallest angle one pixel may span, in radians: 8e-6, about 67
/// steps of an `f32` unit vector (2^-23 = 1.2e-7). Below it `f32` positions
/// and ray directions cannot place a pixel: a camera 1.5e5 from its subject
/// with `fov_y = 0.01` over 120 rows (1.5e-6 per pixel) is off by up to
/// 0.03 in flat and 0.02 in Phong shading, with 4e-6 still 3.6e-3 off in
/// Phong; 5.8e-6 and 8e-6 pass `check` in every mode
/// (`assets/hard/refused/fov-0.001.toml` is refused by this rule).
pub const MIN_PIXEL_ANGLE: f64 = 8e-6;

/// The angle one of `height` rows spans at the centre of the image.
pub fn pixel_angle(fov_y_deg: f64, height: u32) -> f64 {
    2.0 * (fov_y_deg.to_radians() * 0.5).tan() / f64::from(height.max(1))
}

/// Why `f32` cannot render this field of view at this height, if it
/// cannot ([`MIN_PIXEL_ANGLE`]).
pub fn refusal(fov_y_deg: f64, height: u32) -> Option<String> {
    let angle = pixel_angle(fov_y_deg, height);
    (angle < MIN_PIXEL_ANGLE).then(|| {
        let smallest = 2.0
            * (MIN_PIXEL_ANGLE * f64::from(height) * 0.5)
                .atan()
                .to_degrees();
        format!(
            "`fov_y` {fov_y_deg} over {height} rows gives each pixel {angle:.2e} radians, under \
             the {MIN_PIXEL_ANGLE:e} that 32-bit float positions and ray directions can place \
             (pixels would move by a sizeable part of themselves); expected fov_y >= \
             {smallest:.3e} at this height, or fewer rows"
        )
    })
}
