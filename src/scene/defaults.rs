//! The scene model's defaults: what a scene gets for every setting its file
//! leaves out, whichever format it came from.
//!
//! Both loaders ([`toml`](super::toml) and
//! [`gltf`](super::gltf)) read these, so a TOML scene and a
//! glTF scene that say nothing about, say, the ambient light are lit alike.
//! Defaults that only one format's syntax has (the tessellation of a TOML
//! sphere, a TOML camera's `up`) stay with that format.

use glam::DVec3;

use super::model::{
    CausticSettings, Falloff, ImageSettings, Interpolation, Lighting, Material, RenderSettings,
    Traversal,
};

/// Vertical field of view in degrees, for a camera that does not give one.
pub const DEFAULT_FOV_Y_DEG: f64 = 40.0;
/// Image width in pixels.
pub const DEFAULT_WIDTH: u32 = 640;
/// Image height in pixels.
pub const DEFAULT_HEIGHT: u32 = 480;
/// Ambient intensity Ia (each channel).
pub const DEFAULT_AMBIENT: f64 = 0.2;
/// Background colour (linear RGB): a dark blue-grey rather than black, so
/// that an unlit object's silhouette still shows.
pub const DEFAULT_BACKGROUND: DVec3 = DVec3::new(0.05, 0.05, 0.08);

/// A material's coefficients when a file gives none of them: white, mostly
/// diffuse, no highlight, mirror or glass. Loaders fill in the name.
pub const DEFAULT_MATERIAL: Material = Material {
    name: String::new(),
    color: DVec3::ONE,
    ka: 0.2,
    kd: 0.8,
    ks: 0.0,
    p: 32.0,
    kr: 0.0,
    kt: 0.0,
    ior: 1.0,
    pattern: None,
};

impl Default for ImageSettings {
    fn default() -> Self {
        Self {
            width: DEFAULT_WIDTH,
            height: DEFAULT_HEIGHT,
            background: DEFAULT_BACKGROUND,
        }
    }
}

impl Default for Lighting {
    fn default() -> Self {
        Self {
            ambient: DVec3::splat(DEFAULT_AMBIENT),
            k: 1.0,
            interpolation: Interpolation::Perspective,
            falloff: Falloff::Lecture,
        }
    }
}

impl Default for RenderSettings {
    fn default() -> Self {
        Self {
            depth: crate::scene::model::DEFAULT_DEPTH,
            depth_given: false,
            cutoff: 0.001,
            shadows: true,
            samples: 1,
            bounces: 0,
            photons: DEFAULT_PHOTONS,
            caustics: CausticSettings::default(),
            traversal: Traversal::Auto,
            msaa: crate::msaa::Msaa::default(),
            watchdog: Some(std::time::Duration::from_secs_f64(
                crate::scene::model::DEFAULT_WATCHDOG_S,
            )),
        }
    }
}

impl Default for CausticSettings {
    fn default() -> Self {
        Self {
            photons_per_pass: 0,
            passes: DEFAULT_CAUSTIC_PASSES,
            initial_radius: DEFAULT_CAUSTIC_RADIUS,
            alpha: CAUSTIC_ALPHA,
        }
    }
}

/// The photon map's passes when a scene or `--caustic-passes` does not
/// say.
pub const DEFAULT_CAUSTIC_PASSES: u32 = 16;

/// The photon map's first gathering radius, in pixel footprints, when a
/// scene or `--caustic-radius` does not say: a disc about four pixels
/// across.
pub const DEFAULT_CAUSTIC_RADIUS: f64 = 2.0;

/// SPPM's `alpha`, the share of a pass's photons a pixel's radius keeps:
/// Hachisuka and Jensen's 2/3, and pbrt's.
pub const CAUSTIC_ALPHA: f64 = 2.0 / 3.0;

/// Forward ray tracing's photons when a scene or `--photons` does not
/// say: 2^22, about 14 splats a pixel of a 640 x 480 image of a closed
/// scene.
pub const DEFAULT_PHOTONS: u32 = 1 << 22;

/// A checker pattern's cells per unit of `u` and `v` when its `scale` is
/// not given.
pub const CHECKER_SCALE: f64 = 8.0;

/// A checker pattern's two colours when its `colors` are not given: light
/// and dark grey.
pub const CHECKER_COLORS: [DVec3; 2] = [DVec3::splat(0.9), DVec3::splat(0.15)];
