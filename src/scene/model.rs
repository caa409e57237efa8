//! The validated, renderer-independent description of a scene.
//!
//! Everything here is plain data in double precision and world space. Loaders
//! (`toml`, `gltf`) produce it; renderers only read it. Nothing
//! in this file touches a file, Vulkan, or an image. The values a loader uses
//! for what a file leaves out are in [`defaults`](super::defaults).

use std::sync::Arc;

use glam::DVec3;

pub use super::texture::{Filter, FilterPreset, Sampler, Texture, Wrap};

/// A whole scene, validated: every number finite, every material index valid,
/// every mesh with at least one non-degenerate triangle.
#[derive(Debug, Clone)]
pub struct Scene {
    pub camera: Camera,
    pub image: ImageSettings,
    pub lighting: Lighting,
    pub lights: Vec<PointLight>,
    pub materials: Vec<Material>,
    pub objects: Vec<Object>,
    pub render: RenderSettings,
    /// The user's GLSL for one light's contribution (`--lighting FILE`),
    /// compiled into every GPU mode in place of the built-in formula; the
    /// CPU reference always evaluates the built-in one, so errors are
    /// measured against the lecture's formula.
    pub lighting_hook: Option<Arc<LightingHook>>,
    /// Non-fatal findings of the loader (for example degenerate triangles that
    /// were dropped). The CLI prints them; the library never does.
    pub warnings: Vec<String>,
}

/// A lighting hook's source, as read from its file.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct LightingHook {
    /// The path as the user gave it: compiler messages name it.
    pub path: String,
    pub source: String,
}

#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Camera {
    pub position: DVec3,
    pub look_at: DVec3,
    pub up: DVec3,
    /// Vertical field of view in degrees, in (0, 180).
    pub fov_y_deg: f64,
}

#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ImageSettings {
    pub width: u32,
    pub height: u32,
    /// Linear RGB.
    pub background: DVec3,
}

#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum Interpolation {
    /// Perspective-correct interpolation (GLSL `smooth`).
    #[default]
    Perspective,
    /// Screen-space linear interpolation, the lecture's scanline rule
    /// (computed from perspective-correct varyings: `screen_linear.glsl`).
    Screen,
}

impl Interpolation {
    /// The spelling of scene files and variants.
    pub fn name(self) -> &'static str {
        match self {
            Interpolation::Perspective => "perspective",
            Interpolation::Screen => "screen",
        }
    }

    /// The inverse of `name`.
    pub fn from_name(name: &str) -> Option<Self> {
        [Interpolation::Perspective, Interpolation::Screen]
            .into_iter()
            .find(|i| i.name() == name)
    }
}

#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Lighting {
    /// Ia, per channel.
    pub ambient: DVec3,
    /// The constant k in Il / (d + k).
    pub k: f64,
    pub interpolation: Interpolation,
    /// How a point light's intensity falls with distance.
    pub falloff: Falloff,
}

/// How a point light's intensity `Il` falls with the distance `d` to the lit
/// point (docs/lighting-model.md, "Falloff").
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum Falloff {
    /// `Il / (d + k)`, the lecture's.
    #[default]
    Lecture,
    /// `Il / d^2`, physically based lights (`Il` a radiant intensity).
    InverseSquare,
    /// `Il`: the formula before attenuation is introduced.
    None,
}

impl Falloff {
    /// The spelling of scene files.
    pub fn name(self) -> &'static str {
        match self {
            Falloff::Lecture => "lecture",
            Falloff::InverseSquare => "inverse-square",
            Falloff::None => "none",
        }
    }

    /// What `Il` is divided by at distance `d`, with the constant `k`;
    /// none when it is not divided.
    pub fn divisor(self, d: f64, k: f64) -> Option<f64> {
        match self {
            Falloff::Lecture => Some(d + k),
            Falloff::InverseSquare => Some(d * d),
            Falloff::None => None,
        }
    }

    /// `intensity` as it arrives at distance `d`.
    pub fn attenuate(self, intensity: DVec3, d: f64, k: f64) -> DVec3 {
        match self.divisor(d, k) {
            Some(divisor) => intensity / divisor,
            None => intensity,
        }
    }
}

#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PointLight {
    pub position: DVec3,
    /// Il, per channel.
    pub intensity: DVec3,
}

#[derive(Debug, Clone, PartialEq)]
pub struct Material {
    pub name: String,
    /// Tints the ambient and diffuse terms (linear RGB).
    pub color: DVec3,
    pub ka: f64,
    pub kd: f64,
    pub ks: f64,
    /// Glossiness (Phong exponent).
    pub p: f64,
    pub kr: f64,
    pub kt: f64,
    pub ior: f64,
    /// A procedural texture whose colour multiplies `color`, or none.
    pub pattern: Option<Pattern>,
}

/// What multiplies a material's colour over its surface: a procedural
/// pattern or an image, at the surface's texture coordinates `(u, v)`
/// (docs/lighting-model.md, "Surface colour").
#[derive(Debug, Clone, PartialEq)]
pub enum Pattern {
    /// Two colours alternating on the `uv` grid scaled by `scale`:
    /// `floor(scale u) + floor(scale v)` even gives `colors[0]`. Evaluated
    /// exactly at the point, with no filtering.
    Checker { scale: f64, colors: [DVec3; 2] },
    /// An image, filtered by its sampler at a level of detail each renderer
    /// chooses by the contract's rules.
    Image(Arc<ImageTexture>),
}

/// An image texture as a material uses it.
#[derive(Debug, Clone, PartialEq)]
pub struct ImageTexture {
    /// What messages call it: the file, or the glTF image's name or index.
    pub name: String,
    pub texture: Texture,
    pub sampler: Sampler,
    /// Applied to the surface's `(u, v)` before the lookup:
    /// `(u', v') = (m[0] u + m[1] v + m[2], m[3] u + m[4] v + m[5])`
    /// (glTF's `KHR_texture_transform`, a TOML texture's placement:
    /// [`UvTransform::placed`]).
    pub transform: UvTransform,
}

/// An affine map of texture coordinates, row-major 2 x 3.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct UvTransform(pub [f64; 6]);

impl UvTransform {
    pub const IDENTITY: UvTransform = UvTransform([1.0, 0.0, 0.0, 0.0, 1.0, 0.0]);

    pub fn apply(&self, u: f64, v: f64) -> (f64, f64) {
        let m = &self.0;
        (m[0] * u + m[1] * v + m[2], m[3] * u + m[4] * v + m[5])
    }

    /// An image placed on a surface (a TOML texture's `scale`, `rotation`
    /// and `offset`), as the map from the surface's `(u, v)` to the
    /// image's: turned `rotation_deg` counter-clockwise about the image's
    /// centre as the face is seen (`v` runs down the image), then tiled
    /// `scale` times across, then moved by `offset` image widths:
    /// `uv' = scale (R (uv - 1/2) + 1/2) + offset`. Quarter turns are exact.
    pub fn placed(scale: f64, rotation_deg: f64, offset: [f64; 2]) -> UvTransform {
        let degrees = rotation_deg.rem_euclid(360.0);
        let turns = degrees / 90.0;
        let (sin, cos) = if turns == turns.round() {
            match turns as u32 % 4 {
                0 => (0.0, 1.0),
                1 => (1.0, 0.0),
                2 => (0.0, -1.0),
                _ => (-1.0, 0.0),
            }
        } else {
            degrees.to_radians().sin_cos()
        };
        // Seen with v down, turning the image counter-clockwise by a turns the
        // lookup by it: its top edge comes to the face's left at a quarter turn.
        let (a, b, c, d) = (cos, -sin, sin, cos);
        let tx = 0.5 - a * 0.5 - b * 0.5;
        let ty = 0.5 - c * 0.5 - d * 0.5;
        UvTransform([
            scale * a,
            scale * b,
            scale * tx + offset[0],
            scale * c,
            scale * d,
            scale * ty + offset[1],
        ])
    }

    /// How much it scales areas: `|det|` of its linear part.
    pub fn area_scale(&self) -> f64 {
        let m = &self.0;
        (m[0] * m[4] - m[1] * m[3]).abs()
    }
}

impl Pattern {
    /// A checker's colour at `(u, v)`, and the cell it lies in (what
    /// `check` compares neighbours by: a colour edge lies between cells);
    /// `None` for an image, which is sampled at a level of detail
    /// (`cpu::sample`).
    pub fn checker_at(&self, u: f64, v: f64) -> Option<(DVec3, i64)> {
        match self {
            Pattern::Checker { scale, colors } => {
                let (i, j) = ((scale * u).floor(), (scale * v).floor());
                let parity = (i + j).rem_euclid(2.0);
                let cell = ((i as i64) << 32) ^ ((j as i64) & 0xffff_ffff);
                Some((colors[usize::from(parity != 0.0)], cell))
            }
            Pattern::Image(_) => None,
        }
    }

    /// The image texture, if this is one.
    pub fn image(&self) -> Option<&ImageTexture> {
        match self {
            Pattern::Image(image) => Some(image),
            Pattern::Checker { .. } => None,
        }
    }
}

#[derive(Debug, Clone)]
pub struct Object {
    pub shape: Shape,
    /// Index into `Scene::materials`.
    pub material: usize,
}

#[derive(Debug, Clone)]
pub enum Shape {
    Sphere {
        center: DVec3,
        radius: f64,
        /// Tessellation for the raster modes: `segments` around the equator,
        /// `segments / 2` (at least 2) from pole to pole.
        segments: u32,
    },
    /// A finite square of edge `size` centred on `center`, facing `normal`
    /// (unit length). Its edges follow `plane_axes(normal)`.
    Plane {
        center: DVec3,
        normal: DVec3,
        size: f64,
        /// Grid cells per edge for the raster modes (1 = two triangles).
        segments: u32,
    },
    /// An oriented box: `half_extents` along the columns of `rotation`.
    Box {
        center: DVec3,
        half_extents: DVec3,
        rotation: glam::DMat3,
    },
    /// A triangle mesh, already in world space.
    Mesh(TriangleMesh),
}

/// Indexed triangles in world space with one unit normal per vertex.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct TriangleMesh {
    pub positions: Vec<DVec3>,
    pub normals: Vec<DVec3>,
    /// Linear RGB per vertex (glTF `COLOR_0`), each channel finite and at
    /// least 0; empty when the mesh has none. Multiplies the material's
    /// colour (docs/lighting-model.md, "Surface colour").
    pub colors: Vec<DVec3>,
    /// Texture coordinates per vertex (glTF `TEXCOORD_0`, `v` down the
    /// image); empty when the mesh has none or its material has no use for
    /// them.
    pub uvs: Vec<glam::DVec2>,
    /// Counter-clockwise seen from the side the geometric normal points to.
    pub triangles: Vec<[u32; 3]>,
}

impl TriangleMesh {
    /// A mesh of positions, normals and triangles alone: no vertex colours,
    /// no texture coordinates.
    pub fn new(positions: Vec<DVec3>, normals: Vec<DVec3>, triangles: Vec<[u32; 3]>) -> Self {
        TriangleMesh {
            positions,
            normals,
            triangles,
            colors: Vec::new(),
            uvs: Vec::new(),
        }
    }
}

/// The deepest ray tree a scene or `--depth` may ask for.
pub const MAX_DEPTH: u32 = 64;

/// How long one GPU submission may run where a scene or `--watchdog` does
/// not say: no honest submission comes near it (long work is batched into
/// short submissions), while an endless lighting hook ends in minutes.
pub const DEFAULT_WATCHDOG_S: f64 = 120.0;

/// The longest watchdog a scene or `--watchdog` may ask for: a day. (0 is
/// none.)
pub const MAX_WATCHDOG_S: f64 = 86_400.0;

/// `render.watchdog` or `--watchdog` in seconds as the renderers take it:
/// `None` (0 s) waits for ever; the range error's text where out of range.
pub fn watchdog_limit(seconds: f64) -> Result<Option<std::time::Duration>, String> {
    if !(0.0..=MAX_WATCHDOG_S).contains(&seconds) {
        return Err(format!(
            "{seconds} is out of range; expected 0 (no limit) to {MAX_WATCHDOG_S} seconds"
        ));
    }
    Ok((seconds > 0.0).then(|| std::time::Duration::from_secs_f64(seconds)))
}

/// `render.caustic_radius` or `--caustic-radius` (pixel footprints): above
/// 0, and no wider than the largest image (`MAX_RESOLUTION` pixels), past
/// which every pixel would gather every photon and the estimate is no
/// longer local; the range error's text where out of range.
pub fn check_caustic_radius(radius: f64) -> Result<f64, String> {
    if radius.is_finite() && radius > 0.0 && radius <= MAX_RESOLUTION as f64 {
        Ok(radius)
    } else {
        // As the number was written: `0`, `1e30`, `0.5`.
        let shown = if radius.fract() == 0.0 && radius.abs() < 1e16 {
            format!("{radius:.0}")
        } else {
            format!("{radius:?}")
        };
        Err(format!(
            "{shown} is out of range; expected a number above 0 and at most {MAX_RESOLUTION} (pixel footprints: a wider disc than the largest image gathers every photon into every pixel)"
        ))
    }
}

/// The largest image width or height a scene or `--width`/`--height` may ask
/// for.
pub const MAX_RESOLUTION: i64 = 16384;

/// Which engine finds the ray tracer's hits on the GPU (`--traversal`,
/// `render.traversal`); the CPU reference has one.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum Traversal {
    /// The device decides, by the measured rule of `gpu::raytrace::engine_for`.
    #[default]
    Auto,
    /// The compute shader's own BVH walk, in packets of a subgroup.
    Bvh,
    /// `VK_KHR_ray_query` through an acceleration structure the driver builds.
    Query,
}

impl Traversal {
    /// The spelling of scene files, flags and variants.
    pub fn name(self) -> &'static str {
        match self {
            Traversal::Auto => "auto",
            Traversal::Bvh => "bvh",
            Traversal::Query => "query",
        }
    }
}

impl std::str::FromStr for Traversal {
    type Err = String;
    fn from_str(s: &str) -> Result<Self, String> {
        match s {
            "auto" => Ok(Traversal::Auto),
            "bvh" => Ok(Traversal::Bvh),
            "query" => Ok(Traversal::Query),
            _ => Err(format!(
                "unknown traversal `{s}`; expected auto, bvh or query"
            )),
        }
    }
}

#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RenderSettings {
    /// Ray tracing: maximum recursion depth.
    pub depth: u32,
    /// Whether `depth` was asked for (`render.depth`, `--depth`, a
    /// variant's `depth=`); if not, it follows `bounces` up
    /// ([`RenderSettings::settle_depth`]).
    pub depth_given: bool,
    /// Ray tracing: adaptive depth cut-off on the ray weight.
    pub cutoff: f64,
    pub shadows: bool,
    /// Ray tracing: samples per pixel.
    pub samples: u32,
    /// Ray tracing: diffuse bounces a path may take (secondary
    /// illumination, docs/lighting-model.md); 0 is the Whitted tracer.
    pub bounces: u32,
    /// Forward ray tracing: photons traced from the lights, split over
    /// them by power.
    pub photons: u32,
    /// Ray tracing: caustics from a photon map, added to the backward
    /// tracer's image (none where its photons per pass are 0).
    pub caustics: CausticSettings,
    /// Ray tracing on the GPU: the engine that finds hits.
    pub traversal: Traversal,
    /// The raster modes: samples per pixel and where they are shaded.
    pub msaa: crate::msaa::Msaa,
    /// The GPU: how long one submission may run before the render is
    /// given up as stuck (`None`: for ever).
    pub watchdog: Option<std::time::Duration>,
}

/// The ray tracer's depth where nothing asks for another (and the bounces
/// need no more).
pub const DEFAULT_DEPTH: u32 = 5;

impl RenderSettings {
    /// The one rule of depth and bounces (docs/lighting-model.md, "Depth
    /// and bounces"): each diffuse bounce is a level of the ray tree, which
    /// `depth` bounds, so `bounces` N needs a depth of N or more. A depth
    /// nobody asked for is the default raised to the bounces; one asked
    /// for below them is refused, with `(depth, bounces)`, rather than
    /// rendering fewer bounces than asked.
    pub fn settle_depth(&mut self) -> Result<(), (u32, u32)> {
        if !self.depth_given {
            self.depth = DEFAULT_DEPTH.max(self.bounces);
        } else if self.depth < self.bounces {
            return Err((self.depth, self.bounces));
        }
        Ok(())
    }
}

/// How the ray tracer's caustics are gathered from a progressive photon
/// map (docs/lighting-model.md, "Caustics").
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CausticSettings {
    /// Photons emitted each pass (each carries `1 / photons_per_pass` of
    /// the lights' power); 0: no caustics.
    pub photons_per_pass: u32,
    pub passes: u32,
    /// Every pixel's gathering radius where its eye path first finds a
    /// diffuse surface, in pixel footprints there: the path's length
    /// times the angle a pixel spans (`2 / (focal height)`), so that the
    /// first radius covers about as many pixels anywhere in the image.
    pub initial_radius: f64,
    /// The share of a pass's photons the radius keeps (SPPM's `alpha`).
    pub alpha: f64,
}

impl CausticSettings {
    /// Whether the ray tracer gathers caustics at all.
    pub fn on(&self) -> bool {
        self.photons_per_pass > 0 && self.passes > 0
    }

    /// Every photon the passes emit; `None` past 2^32 - 1 (a photon's
    /// number is 32 bits).
    pub fn total_photons(&self) -> Option<u32> {
        u32::try_from(u64::from(self.photons_per_pass) * u64::from(self.passes)).ok()
    }
}

/// Two unit vectors `(u, v)` spanning the plane with unit normal `n`, with
/// `u x v = n`: the right and up of an image on the plane as a viewer on
/// the side `n` points to sees it, so that a texture reads as in an image
/// viewer (docs/scene-format.md, "Which way an image reads").
///
/// A face nearer vertical than horizontal (`|n.y| <= sqrt(1/2)`) keeps world
/// up: `u = normalize(Y x n)`, horizontal. A floor or a ceiling (nearer
/// horizontal) reads as a viewer looking along -Z sees it when they look
/// down or up: `u = normalize(z x n)` with `z = -Z` on a floor, `+Z` on a
/// ceiling, which is `+X` on a level face, the image's top toward -Z on a
/// floor and +Z on a ceiling. Either way `v = n x u`. The plane's square
/// has its edges along these axes.
pub fn plane_axes(n: DVec3) -> (DVec3, DVec3) {
    let reference = if n.y.abs() <= std::f64::consts::FRAC_1_SQRT_2 {
        DVec3::Y
    } else {
        DVec3::new(0.0, 0.0, -n.y.signum())
    };
    let u = reference.cross(n).normalize();
    let v = n.cross(u);
    (u, v)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn checker_at(p: &Pattern, u: f64, v: f64) -> (DVec3, i64) {
        p.checker_at(u, v).expect("a checker")
    }

    /// A quarter turn counter-clockwise, worked out by hand: the face's top
    /// left corner `(0, 0)` shows the image's top right `(1, 0)`, its top
    /// right `(1, 0)` the image's bottom right `(1, 1)`; exactly.
    #[test]
    fn a_quarter_turn_maps_the_corners_exactly() {
        let t = UvTransform::placed(1.0, 90.0, [0.0, 0.0]);
        assert_eq!(t.apply(0.0, 0.0), (1.0, 0.0));
        assert_eq!(t.apply(1.0, 0.0), (1.0, 1.0));
        assert_eq!(UvTransform::placed(1.0, -270.0, [0.0, 0.0]), t);
        assert_eq!(
            UvTransform::placed(2.0, 0.0, [0.25, 0.0]).apply(0.5, 0.5),
            (1.25, 1.0)
        );
    }

    #[test]
    fn a_checker_alternates_by_cell_also_below_zero() {
        let a = DVec3::X;
        let b = DVec3::Y;
        let checker = Pattern::Checker {
            scale: 2.0,
            colors: [a, b],
        };
        // Cells half a unit wide: (0, 0) even, (1, 0) odd, (-1, 0) odd,
        // (-1, -1) even.
        assert_eq!(checker_at(&checker, 0.1, 0.2).0, a);
        assert_eq!(checker_at(&checker, 0.6, 0.2).0, b);
        assert_eq!(checker_at(&checker, -0.1, 0.2).0, b);
        assert_eq!(checker_at(&checker, -0.1, -0.2).0, a);
        assert_ne!(
            checker_at(&checker, 0.1, 0.2).1,
            checker_at(&checker, 0.6, 0.2).1
        );
        assert_ne!(
            checker_at(&checker, 0.1, 0.6).1,
            checker_at(&checker, 0.6, 0.1).1
        );
        assert_eq!(
            checker_at(&checker, 0.1, 0.2).1,
            checker_at(&checker, 0.4, 0.4).1
        );
    }
}
