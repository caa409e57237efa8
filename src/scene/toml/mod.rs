//! The TOML scene format of `docs/interface.md`, deserialised strictly and
//! converted into a validated [`Scene`](crate::scene::Scene).
//!
//! Every table denies unknown keys; every number must be finite (TOML's
//! `nan` and `inf` are rejected where they appear); values that parse but
//! make no sense are reported with the line of the offending key. Defaults
//! (those a glTF scene shares are in [`defaults`](super::defaults)):
//!
//! | key | default | constraint |
//! | --- | --- | --- |
//! | `camera.position`, `camera.look_at` | required | distinct |
//! | `camera.up` | `[0, 1, 0]` | non-zero, not parallel to the view direction |
//! | `camera.fov_y` | `40` | degrees, in (0, 180) |
//! | `image.width` / `image.height` | `640` / `480` | 1..=16384 |
//! | `image.background` | `[0.05, 0.05, 0.08]` | each >= 0 |
//! | `lighting.ambient` | `0.2` | number or `[r, g, b]`, each >= 0 |
//! | `lighting.k` | `1.0` | >= 0 |
//! | `lighting.interpolation` | `"perspective"` | or `"screen"` |
//! | `lighting.falloff` | `"lecture"` | Il / (d + k); `"inverse-square"`: Il / d^2; `"none"`: Il |
//! | `lighting.attenuation` | `true` | `false` is `falloff = "none"` (the older spelling) |
//! | `lights[].position`, `lights[].intensity` | required | intensity number or `[r, g, b]`, each >= 0 |
//! | `materials.NAME.color` | `[1, 1, 1]` | each >= 0 |
//! | `ka`, `kd`, `ks`, `p`, `kr`, `kt` | 0.2, 0.8, 0, 32, 0, 0 | >= 0 |
//! | `ior` | `1.0` | > 0 |
//! | `pattern` | none | `{ kind = "checker", scale = 8, colors = [[0.9, 0.9, 0.9], [0.15, 0.15, 0.15]] }`: scale > 0, two colours each >= 0 |
//! | `texture` | none | `{ file = "floor.png", scale = 1, rotation = 0, offset = [0, 0], wrap = "repeat", filter = "trilinear" }`: `file` required (PNG or JPEG, sRGB, relative to the scene file), scale > 0 (tiles across a face), rotation in degrees counter-clockwise as the face is seen, offset in image widths, wrap `"repeat"`, `"clamp"` or `"mirror"`, filter `"nearest"`, `"bilinear"` or `"trilinear"`; not with `pattern` |
//! | `render.depth` | `5` | 0..=64; left out, at least `render.bounces`; given, not below them |
//! | `render.cutoff` | `0.001` | >= 0 |
//! | `render.shadows` | `true` | |
//! | `render.samples` | `1` | 1..=1024 |
//! | `render.bounces` | `0` | 0..=64: diffuse bounces of the ray tracer's paths (secondary illumination; 0 is the Whitted tracer) |
//! | `render.photons` | `4194304` | 1..=4294967295: photons forward ray tracing traces from the lights |
//! | `render.caustics` | `0` | 0..=4294967295: photons per pass of the ray tracer's photon map (caustics) |
//! | `render.caustic_passes` | `16` | 1..=1048576: the photon map's passes |
//! | `render.caustic_radius` | `2` | > 0 and <= 16384: its first radius, in pixel footprints |
//! | `render.traversal` | `"auto"` | or `"bvh"`, `"query"`: the GPU ray tracer's engine |
//! | `render.watchdog` | `120` | 0..=86400 seconds one GPU submission may run before the render is given up as stuck (exit 3); 0 is no limit |
//! | `render.msaa` | `1` | the raster modes' samples per pixel, 1..=64 (the device's counts: `shadelab info`), or `"4,per-sample"` to shade every sample |
//!
//! Objects (`[[objects]]`, `shape` selects the kind; a key that belongs to
//! another shape is an error):
//!
//! - `sphere`: `center`, `radius` (> 0), `segments` (default 32, 3..=4096),
//!   `material` (required).
//! - `plane`: a finite square: `center`, `normal` (non-zero, normalised),
//!   `size` (edge length, > 0), `segments` (grid cells per edge, default 1,
//!   1..=1024), `material` (required).
//! - `box`: an oriented cuboid: `center`; `size` = its full edge lengths
//!   along its own x, y, z axes, a number (a cube) or `[x, y, z]`, each > 0;
//!   `rotate_deg` = `[x, y, z]` degrees (default 0), applied about world X,
//!   then world Y, then world Z (`R = Rz * Ry * Rx`); `material` (required).
//!   It becomes `Shape::Box { center, half_extents: size / 2, rotation: R }`.
//! - `mesh`: `file` (glTF/glb, relative to the scene file), `translate`
//!   (default 0), `rotate_deg` (default 0, same rule as `box`), `scale`
//!   (number or `[x, y, z]`, default 1, each non-zero), `material`
//!   (optional: overrides the file's materials). World transform
//!   `T * R * S * node_world`.
//!
//! Materials are referenced by name; they are stored in `Scene::materials`
//! in name order, followed by materials imported from mesh files.
//!
//! The parser reads in steps, one file each: `schema` is the file as serde
//! sees it; `located_errors` turns a TOML or serde error into a sentence
//! with its line and column, and `checks` gives the semantic checks the
//! line of their key; `parse` converts the tables in order, through
//! `camera_lights`, `render_settings`, `materials` and `shapes`.

mod camera_lights;
mod checks;
mod from_table;
mod located_errors;
mod materials;
mod parse;
mod render_settings;
mod schema;
mod shapes;
#[cfg(test)]
mod test_support;

pub use from_table::from_table;
pub use parse::{parse, parse_within};
pub use shapes::rotation_from_deg;
