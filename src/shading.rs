//! The shading modes a user can ask for.

use std::fmt;
use std::str::FromStr;

#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum Shading {
    Flat,
    Gouraud,
    Phong,
    Raytrace,
    /// Forward ray tracing: photons from the lights (`render.photons`).
    /// Not in `BY_DEFAULT`, the modes every command runs by default: its image
    /// is an estimate with noise, and only of diffuse light.
    Forward,
}

impl Shading {
    /// The modes a command runs when none is named: every one but forward
    /// tracing (an estimate with noise, of diffuse light only).
    pub const BY_DEFAULT: [Shading; 4] = [
        Shading::Flat,
        Shading::Gouraud,
        Shading::Phong,
        Shading::Raytrace,
    ];

    /// Every mode there is, forward tracing included.
    pub const ALL: [Shading; 5] = [
        Shading::Flat,
        Shading::Gouraud,
        Shading::Phong,
        Shading::Raytrace,
        Shading::Forward,
    ];

    pub fn name(self) -> &'static str {
        match self {
            Shading::Flat => "flat",
            Shading::Gouraud => "gouraud",
            Shading::Phong => "phong",
            Shading::Raytrace => "raytrace",
            Shading::Forward => "forward",
        }
    }
}

impl fmt::Display for Shading {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

impl FromStr for Shading {
    type Err = String;

    fn from_str(s: &str) -> Result<Self, Self::Err> {
        Shading::ALL
            .into_iter()
            .find(|m| m.name() == s)
            .ok_or_else(|| {
                format!(
                    "unknown shading mode `{s}`; expected flat, gouraud, phong, raytrace or forward"
                )
            })
    }
}

/// The three modes a rasterizer (GPU or CPU) implements.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum RasterMode {
    Flat,
    Gouraud,
    Phong,
}

impl Shading {
    /// The raster mode for this shading, or `None` for ray tracing (either
    /// way).
    pub fn raster_mode(self) -> Option<RasterMode> {
        match self {
            Shading::Flat => Some(RasterMode::Flat),
            Shading::Gouraud => Some(RasterMode::Gouraud),
            Shading::Phong => Some(RasterMode::Phong),
            Shading::Raytrace | Shading::Forward => None,
        }
    }
}
