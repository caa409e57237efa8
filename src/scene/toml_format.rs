//! The TOML scene format of `docs/interface.md`, deserialised strictly and
//! converted into a validated [`Scene`].
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
//! | `lighting.attenuation` | `true` | `false`: Il instead of Il / (d + k) |
//! | `lights[].position`, `lights[].intensity` | required | intensity number or `[r, g, b]`, each >= 0 |
//! | `materials.NAME.color` | `[1, 1, 1]` | each >= 0 |
//! | `ka`, `kd`, `ks`, `p`, `kr`, `kt` | 0.2, 0.8, 0, 32, 0, 0 | >= 0 |
//! | `ior` | `1.0` | > 0 |
//! | `pattern` | none | `{ kind = "checker", scale = 8, colors = [[0.9, 0.9, 0.9], [0.15, 0.15, 0.15]] }`: scale > 0, two colours each >= 0 |
//! | `texture` | none | `{ file = "floor.png", scale = 1, rotation = 0, offset = [0, 0], wrap = "repeat", filter = "trilinear" }`: `file` required (PNG or JPEG, sRGB, relative to the scene file), scale > 0 (tiles across a face), rotation in degrees counter-clockwise as the face is seen, offset in image widths, wrap `"repeat"`, `"clamp"` or `"mirror"`, filter `"nearest"`, `"bilinear"` or `"trilinear"`; not with `pattern` |
//! | `render.depth` | `5` | 0..=64 |
//! | `render.cutoff` | `0.001` | >= 0 |
//! | `render.shadows` | `true` | |
//! | `render.samples` | `1` | 1..=1024 |
//! | `render.traversal` | `"auto"` | or `"bvh"`, `"query"`: the GPU ray tracer's engine |
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

use std::borrow::Cow;
use std::collections::BTreeMap;
use std::fmt;
use std::path::Path;

use glam::{DMat3, DMat4, DVec3};
use serde::de::{self, Deserializer, IgnoredAny, SeqAccess, Visitor};
use serde::Deserialize;
use toml::Spanned;

use super::defaults::{CHECKER_COLORS, CHECKER_SCALE, DEFAULT_FOV_Y_DEG, DEFAULT_MATERIAL};
use super::error::SceneError;
use super::footprint::LoadLimits;
use super::gltf;
use super::image_file::{
    ImageFailure, ImageKey, TextureRequest, TextureStore, TEXTURE_FILTER, TEXTURE_SCALE,
    TEXTURE_WRAP,
};
use super::model::{
    Camera, ImageSettings, Interpolation, Lighting, Material, Object, Pattern, PointLight,
    RenderSettings, Scene, Shape, Traversal, UvTransform, MAX_DEPTH, MAX_RESOLUTION,
};
use super::texture::{FilterPreset, Wrap};

// ---------------------------------------------------------------------------
// Value types with their own checks (so the TOML parser attaches the line).

/// A finite number; TOML integers are accepted too.
#[derive(Debug, Clone, Copy)]
struct Finite(f64);

struct FiniteVisitor;

impl Visitor<'_> for FiniteVisitor {
    type Value = Finite;
    fn expecting(&self, f: &mut fmt::Formatter) -> fmt::Result {
        f.write_str("a finite number")
    }
    fn visit_f64<E: de::Error>(self, v: f64) -> Result<Finite, E> {
        if v.is_finite() {
            Ok(Finite(v))
        } else {
            Err(E::custom(format!(
                "non-finite number {v}; expected a finite number"
            )))
        }
    }
    fn visit_i64<E: de::Error>(self, v: i64) -> Result<Finite, E> {
        Ok(Finite(v as f64))
    }
    fn visit_u64<E: de::Error>(self, v: u64) -> Result<Finite, E> {
        Ok(Finite(v as f64))
    }
}

impl<'de> Deserialize<'de> for Finite {
    fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        d.deserialize_any(FiniteVisitor)
    }
}

/// `[x, y, z]` of finite numbers.
type V3 = [Finite; 3];

fn v3(v: &V3) -> DVec3 {
    DVec3::new(v[0].0, v[1].0, v[2].0)
}

/// A number or `[x, y, z]`, all finite.
#[derive(Debug, Clone, Copy)]
enum NumOr3 {
    Num(f64),
    Vec(DVec3),
}

impl NumOr3 {
    fn splat(self) -> DVec3 {
        match self {
            NumOr3::Num(x) => DVec3::splat(x),
            NumOr3::Vec(v) => v,
        }
    }
}

struct NumOr3Visitor;

impl<'de> Visitor<'de> for NumOr3Visitor {
    type Value = NumOr3;
    fn expecting(&self, f: &mut fmt::Formatter) -> fmt::Result {
        f.write_str("a finite number or an array of 3 finite numbers")
    }
    fn visit_f64<E: de::Error>(self, v: f64) -> Result<NumOr3, E> {
        FiniteVisitor.visit_f64(v).map(|x| NumOr3::Num(x.0))
    }
    fn visit_i64<E: de::Error>(self, v: i64) -> Result<NumOr3, E> {
        Ok(NumOr3::Num(v as f64))
    }
    fn visit_u64<E: de::Error>(self, v: u64) -> Result<NumOr3, E> {
        Ok(NumOr3::Num(v as f64))
    }
    fn visit_seq<A: SeqAccess<'de>>(self, mut seq: A) -> Result<NumOr3, A::Error> {
        let mut out = [0.0; 3];
        for (i, slot) in out.iter_mut().enumerate() {
            *slot = seq
                .next_element::<Finite>()?
                .ok_or_else(|| de::Error::invalid_length(i, &self))?
                .0;
        }
        if seq.next_element::<IgnoredAny>()?.is_some() {
            return Err(de::Error::invalid_length(4, &self));
        }
        Ok(NumOr3::Vec(DVec3::from_array(out)))
    }
}

impl<'de> Deserialize<'de> for NumOr3 {
    fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        d.deserialize_any(NumOr3Visitor)
    }
}

// ---------------------------------------------------------------------------
// The raw file, one struct per table.

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct FileRaw {
    camera: Spanned<CameraRaw>,
    image: Option<ImageRaw>,
    lighting: Option<LightingRaw>,
    #[serde(default)]
    lights: Vec<Spanned<LightRaw>>,
    #[serde(default)]
    materials: BTreeMap<String, Spanned<MaterialRaw>>,
    #[serde(default)]
    objects: Vec<Spanned<ObjectRaw>>,
    render: Option<RenderRaw>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct CameraRaw {
    position: Spanned<V3>,
    look_at: Spanned<V3>,
    up: Option<Spanned<V3>>,
    fov_y: Option<Spanned<Finite>>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct ImageRaw {
    width: Option<Spanned<i64>>,
    height: Option<Spanned<i64>>,
    background: Option<Spanned<V3>>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct LightingRaw {
    ambient: Option<Spanned<NumOr3>>,
    k: Option<Spanned<Finite>>,
    interpolation: Option<Interpolation>,
    attenuation: Option<bool>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct LightRaw {
    position: V3,
    intensity: Spanned<NumOr3>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct MaterialRaw {
    color: Option<Spanned<V3>>,
    ka: Option<Spanned<Finite>>,
    kd: Option<Spanned<Finite>>,
    ks: Option<Spanned<Finite>>,
    p: Option<Spanned<Finite>>,
    kr: Option<Spanned<Finite>>,
    kt: Option<Spanned<Finite>>,
    ior: Option<Spanned<Finite>>,
    pattern: Option<Spanned<PatternRaw>>,
    texture: Option<Spanned<TextureRaw>>,
}

/// `texture = { file = "floor.png", scale = 1, wrap = "repeat", filter =
/// "trilinear" }`.
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct TextureRaw {
    file: Spanned<String>,
    scale: Option<Spanned<Finite>>,
    rotation: Option<Spanned<Finite>>,
    offset: Option<Spanned<[Finite; 2]>>,
    wrap: Option<Spanned<String>>,
    filter: Option<Spanned<String>>,
}

/// `pattern = { kind = "checker", scale = 8, colors = [[...], [...]] }`.
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct PatternRaw {
    kind: Spanned<String>,
    scale: Option<Spanned<Finite>>,
    colors: Option<Spanned<Vec<V3>>>,
}

/// The union of every shape's keys; which ones are allowed is checked per
/// shape after parsing, so that every key keeps its line.
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct ObjectRaw {
    shape: Spanned<String>,
    center: Option<Spanned<V3>>,
    radius: Option<Spanned<Finite>>,
    segments: Option<Spanned<i64>>,
    normal: Option<Spanned<V3>>,
    size: Option<Spanned<NumOr3>>,
    rotate_deg: Option<Spanned<V3>>,
    material: Option<Spanned<String>>,
    file: Option<Spanned<String>>,
    translate: Option<Spanned<V3>>,
    scale: Option<Spanned<NumOr3>>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct RenderRaw {
    depth: Option<Spanned<i64>>,
    cutoff: Option<Spanned<Finite>>,
    shadows: Option<bool>,
    samples: Option<Spanned<i64>>,
    traversal: Option<Traversal>,
    msaa: Option<Spanned<MsaaRaw>>,
}

/// `msaa = 4` or `msaa = "4,per-sample"`.
#[derive(Deserialize)]
#[serde(untagged)]
enum MsaaRaw {
    Count(i64),
    Text(String),
}

// ---------------------------------------------------------------------------
// Positions and messages.

/// 1-based line and column of byte `offset` in `text`.
fn line_col(text: &str, offset: usize) -> (usize, usize) {
    let offset = offset.min(text.len());
    let before = text.get(..offset).unwrap_or(text);
    let line = before.matches('\n').count() + 1;
    let col = before
        .rsplit('\n')
        .next()
        .map_or(1, |l| l.chars().count() + 1);
    (line, col)
}

/// The table header on a line (`[camera]`, `[[objects]]`), if it is one.
fn header_of(line: &str) -> Option<&str> {
    let t = line.split('#').next().unwrap_or("").trim();
    if t.starts_with('[') && t.ends_with(']') && !t.contains('=') {
        Some(t)
    } else {
        None
    }
}

/// The table a 0-based line belongs to, as `[name]` or `[[objects]] #N`.
/// The key of the inline table that column `column` (1-based) of `line`
/// lies in, for a line `key = { ... }`.
fn inline_table_key(line: &str, column: usize) -> Option<&str> {
    let (key, rest) = line.split_once('=')?;
    let key = key.trim();
    let brace = line.len() - rest.len() + rest.find('{')?;
    let bare = !key.is_empty()
        && key
            .chars()
            .all(|c| c.is_ascii_alphanumeric() || c == '_' || c == '-');
    (bare && rest.trim_start().starts_with('{') && column > brace + 1).then_some(key)
}

fn table_context(text: &str, line0: usize) -> Option<String> {
    let lines: Vec<&str> = text.lines().collect();
    let upto = lines.get(..=line0.min(lines.len().saturating_sub(1)))?;
    let (idx, header) = upto
        .iter()
        .enumerate()
        .rev()
        .find_map(|(i, l)| header_of(l).map(|h| (i, h)))?;
    if header.starts_with("[[") {
        let n = upto[..=idx]
            .iter()
            .filter(|l| header_of(l) == Some(header))
            .count();
        Some(format!("{header} #{n}"))
    } else {
        Some(header.to_string())
    }
}

/// The key assigned on the line of `offset` (`key = ...`), if any.
fn key_before(text: &str, offset: usize) -> Option<String> {
    let before = text.get(..offset.min(text.len()))?;
    let line = before.rsplit('\n').next()?;
    let eq = line.find('=')?;
    let key = line[..eq].trim();
    let ok = !key.is_empty()
        && key
            .chars()
            .all(|c| c.is_alphanumeric() || "_-.\"' ".contains(c));
    ok.then(|| key.to_string())
}

/// Turns serde's `a`, `b` list into `a, b`.
fn unquote_list(s: &str) -> String {
    s.replace('`', "")
}

/// One readable sentence from a TOML parser error.
fn toml_error(label: &str, text: &str, err: &toml::de::Error) -> SceneError {
    let raw = err
        .message()
        .lines()
        .map(str::trim)
        .filter(|l| !l.is_empty())
        .collect::<Vec<_>>()
        .join("; ");
    let Some(span) = err.span() else {
        let message = if let Some(rest) = raw.strip_prefix("missing field `") {
            let key = rest.split('`').next().unwrap_or(rest);
            format!("missing required table [{key}]")
        } else {
            raw
        };
        return SceneError::Toml {
            file: label.to_string(),
            message,
        };
    };
    let (line, column) = line_col(text, span.start);
    let line_text = text.lines().nth(line - 1).unwrap_or("");
    let on_header = header_of(line_text).is_some();
    let own_context = table_context(text, line - 1);
    let context = if on_header { None } else { own_context.clone() };
    // A key inside an inline table (`pattern = { ... }`) belongs to it.
    let context = match (inline_table_key(line_text, column), context) {
        (Some(key), Some(table)) => Some(format!("the `{key}` table of {table}")),
        (Some(key), None) => Some(format!("the `{key}` table")),
        (None, context) => context,
    };
    let in_ctx = |c: &Option<String>| c.as_ref().map(|c| format!(" in {c}")).unwrap_or_default();
    let message = if let Some(rest) = raw.strip_prefix("unknown field `") {
        let (key, tail) = rest.split_once('`').unwrap_or((rest, ""));
        let expected = tail
            .trim_start_matches(',')
            .trim()
            .strip_prefix("expected one of ")
            .or_else(|| {
                tail.trim_start_matches(',')
                    .trim()
                    .strip_prefix("expected ")
            })
            .map(unquote_list);
        match expected {
            Some(e) => format!(
                "unknown key `{key}`{}; expected one of {e}",
                in_ctx(&context)
            ),
            None => format!(
                "unknown key `{key}`{}; {}",
                in_ctx(&context),
                tail.trim_start_matches(',').trim()
            ),
        }
    } else if let Some(rest) = raw.strip_prefix("missing field `") {
        let key = rest.split('`').next().unwrap_or(rest);
        if key == "camera" {
            "missing required table [camera]; expected at least [camera] with position and look_at"
                .to_string()
        } else {
            format!("missing required key `{key}`{}", in_ctx(&own_context))
        }
    } else if let Some(rest) = raw.strip_prefix("unknown variant `") {
        let (value, tail) = rest.split_once('`').unwrap_or((rest, ""));
        let key = key_before(text, span.start)
            .map(|k| format!(" for key `{k}`"))
            .unwrap_or_default();
        format!(
            "unknown value `{value}`{key}{}; {}",
            in_ctx(&context),
            unquote_list(tail.trim_start_matches(',').trim())
        )
    } else {
        let key = key_before(text, span.start)
            .map(|k| format!("key `{k}`{}: ", in_ctx(&context)))
            .unwrap_or_default();
        let fixed = raw
            .replace("invalid type:", "wrong type:")
            .replace("expected i64", "expected an integer")
            .replace(
                "expected struct PatternRaw",
                "expected a table such as { kind = \"checker\" }",
            )
            .replace(
                "expected struct TextureRaw",
                "expected a table such as { file = \"floor.png\" }",
            );
        format!("{key}{fixed}")
    };
    SceneError::Syntax {
        file: label.to_string(),
        line,
        column,
        message,
    }
}

/// Semantic checks after parsing: errors carry the line of a `Spanned`.
struct Ctx<'a> {
    label: &'a str,
    text: &'a str,
    limits: &'a LoadLimits,
}

impl Ctx<'_> {
    fn line<T>(&self, s: &Spanned<T>) -> usize {
        line_col(self.text, s.span().start).0
    }

    fn err<T>(&self, at: &Spanned<T>, message: impl Into<String>) -> SceneError {
        SceneError::invalid(self.label, self.line(at), message)
    }

    fn non_negative(&self, s: &Spanned<Finite>, what: &str) -> Result<f64, SceneError> {
        let v = s.get_ref().0;
        if v >= 0.0 {
            Ok(v)
        } else {
            Err(self.err(s, format!("`{what}` is {v}; expected a number >= 0")))
        }
    }

    fn positive(&self, s: &Spanned<Finite>, what: &str) -> Result<f64, SceneError> {
        let v = s.get_ref().0;
        if v > 0.0 {
            Ok(v)
        } else {
            Err(self.err(s, format!("`{what}` is {v}; expected a number > 0")))
        }
    }

    fn non_negative3(&self, s: &Spanned<DVec3>, what: &str) -> Result<DVec3, SceneError> {
        let v = *s.get_ref();
        if v.min_element() >= 0.0 {
            Ok(v)
        } else {
            Err(self.err(
                s,
                format!(
                    "`{what}` is [{}, {}, {}]; expected values >= 0",
                    v.x, v.y, v.z
                ),
            ))
        }
    }

    /// A material's `pattern`, its defaults filled in: a checkerboard of
    /// `CHECKER_SCALE` cells per unit of `u` and `v`, in `CHECKER_COLORS`.
    fn pattern(&self, s: &Spanned<PatternRaw>, what: &str) -> Result<Pattern, SceneError> {
        let raw = s.get_ref();
        if raw.kind.get_ref() != "checker" {
            return Err(self.err(
                &raw.kind,
                format!(
                    "`{what}.kind` is {:?}; expected \"checker\"",
                    raw.kind.get_ref()
                ),
            ));
        }
        let scale = match &raw.scale {
            Some(v) => self.positive(v, &format!("{what}.scale"))?,
            None => CHECKER_SCALE,
        };
        let colors = match &raw.colors {
            Some(list) => {
                let [a, b] = list.get_ref()[..] else {
                    return Err(self.err(
                        list,
                        format!(
                            "`{what}.colors` has {} colours; expected two, [[r, g, b], [r, g, b]]",
                            list.get_ref().len()
                        ),
                    ));
                };
                let key = format!("{what}.colors");
                [
                    self.non_negative3(&spanned_map(list, |_| v3(&a)), &key)?,
                    self.non_negative3(&spanned_map(list, |_| v3(&b)), &key)?,
                ]
            }
            None => CHECKER_COLORS,
        };
        Ok(Pattern::Checker { scale, colors })
    }

    /// A material's `texture` (`what` its key), its defaults filled in
    /// (`image_file`'s consts): the image from `store`, which decodes each
    /// file once per scene and holds it to the memory limit. Also whether
    /// the image was decoded now and its alpha is not all opaque.
    fn texture(
        &self,
        s: &Spanned<TextureRaw>,
        what: &str,
        base_dir: &Path,
        store: &mut TextureStore,
    ) -> Result<(Pattern, bool), SceneError> {
        let raw = s.get_ref();
        let scale = match &raw.scale {
            Some(v) => {
                let scale = self.positive(v, &format!("{what}.scale"))?;
                // The renderers' level of detail takes the area's scale.
                if !(scale * scale).is_finite() {
                    return Err(self.err(
                        v,
                        format!("`{what}.scale` is {scale:e}; expected a number > 0 whose square is finite"),
                    ));
                }
                scale
            }
            None => TEXTURE_SCALE,
        };
        let quoted = |names: &[&str]| {
            names
                .iter()
                .map(|n| format!("\"{n}\""))
                .collect::<Vec<_>>()
                .join(", ")
        };
        let wrap = match &raw.wrap {
            Some(w) => Wrap::from_name(w.get_ref()).ok_or_else(|| {
                self.err(
                    w,
                    format!(
                        "`{what}.wrap` is {:?}; expected one of {}",
                        w.get_ref(),
                        quoted(&Wrap::NAMES)
                    ),
                )
            })?,
            None => TEXTURE_WRAP,
        };
        let filter = match &raw.filter {
            Some(f) => FilterPreset::from_name(f.get_ref()).ok_or_else(|| {
                let names = FilterPreset::ALL.map(FilterPreset::name);
                self.err(
                    f,
                    format!(
                        "`{what}.filter` is {:?}; expected one of {}",
                        f.get_ref(),
                        quoted(&names)
                    ),
                )
            })?,
            None => TEXTURE_FILTER,
        };
        let file = raw.file.get_ref();
        let path = base_dir.join(file);
        let key = ImageKey::File(std::fs::canonicalize(&path).unwrap_or_else(|_| path.clone()));
        let request = TextureRequest {
            key,
            name: file.clone(),
            sampler: filter.sampler(wrap),
            transform: UvTransform::placed(
                scale,
                raw.rotation.as_ref().map_or(0.0, |r| r.get_ref().0),
                raw.offset
                    .as_ref()
                    .map_or([0.0; 2], |o| o.get_ref().map(|x| x.0)),
            ),
        };
        let read = || {
            std::fs::read(&path).map(Cow::Owned).map_err(|e| {
                self.err(
                    &raw.file,
                    format!(
                        "`{what}.file`: cannot read `{file}` ({}: {e}); expected a PNG or JPEG file, relative to the scene file",
                        path.display()
                    ),
                )
            })
        };
        let fail = |failure: ImageFailure| {
            let message = format!("`{what}.file`: `{file}` {}", failure.message());
            match failure {
                ImageFailure::TooLarge(_) => SceneError::TooLarge {
                    file: self.label.to_string(),
                    message: format!("line {}: {message}", self.line(&raw.file)),
                },
                ImageFailure::Unreadable(_) => self.err(&raw.file, message),
            }
        };
        let fetched = store.texture(request, self.limits, 0, read, fail)?;
        Ok((Pattern::Image(fetched.texture), fetched.newly_translucent))
    }

    fn int_in(
        &self,
        s: &Spanned<i64>,
        what: &str,
        lo: i64,
        hi: i64,
        why: &str,
    ) -> Result<u32, SceneError> {
        let v = *s.get_ref();
        if (lo..=hi).contains(&v) {
            u32::try_from(v).map_err(|_| self.err(s, format!("`{what}` is {v}; out of range")))
        } else {
            Err(self.err(
                s,
                format!("`{what}` is {v}{why}; expected an integer from {lo} to {hi}"),
            ))
        }
    }
}

fn spanned_map<T, U>(s: &Spanned<T>, f: impl FnOnce(&T) -> U) -> Spanned<U> {
    Spanned::new(s.span(), f(s.get_ref()))
}

/// `R = Rz * Ry * Rx` for `[x, y, z]` in degrees.
pub fn rotation_from_deg(deg: DVec3) -> DMat3 {
    DMat3::from_rotation_z(deg.z.to_radians())
        * DMat3::from_rotation_y(deg.y.to_radians())
        * DMat3::from_rotation_x(deg.x.to_radians())
}

// ---------------------------------------------------------------------------
// Conversion.

/// Parses and validates a TOML scene. `base_dir` resolves mesh paths;
/// `label` names the file in messages.
pub fn parse(text: &str, base_dir: &Path, label: &str) -> Result<Scene, SceneError> {
    parse_within(text, base_dir, label, &LoadLimits::default())
}

/// As [`parse`], each mesh file held to `limits` (`footprint`).
pub fn parse_within(
    text: &str,
    base_dir: &Path,
    label: &str,
    limits: &LoadLimits,
) -> Result<Scene, SceneError> {
    let raw: FileRaw = toml::from_str(text).map_err(|e| toml_error(label, text, &e))?;
    let cx = Ctx {
        label,
        text,
        limits,
    };

    // camera
    let cam = raw.camera.get_ref();
    let position = v3(cam.position.get_ref());
    let look_at = v3(cam.look_at.get_ref());
    let up = cam.up.as_ref().map_or(DVec3::Y, |u| v3(u.get_ref()));
    let dir = look_at - position;
    let scale = position.abs().max(look_at.abs()).max_element().max(1.0);
    if dir.length() <= 1e-12 * scale {
        return Err(cx.err(
            &cam.look_at,
            "`look_at` equals the camera `position`; expected a point the camera looks toward",
        ));
    }
    if let Some(u) = &cam.up {
        if up.length() == 0.0 {
            return Err(cx.err(
                u,
                "`up` is the zero vector; expected a direction such as [0, 1, 0]",
            ));
        }
    }
    if up.normalize().cross(dir.normalize()).length() < 1e-9 {
        let at = cam
            .up
            .as_ref()
            .map_or_else(|| cx.line(&cam.look_at), |u| cx.line(u));
        return Err(SceneError::invalid(
            label,
            at,
            "camera `up` is parallel to the view direction (look_at - position); expected an up vector that is not",
        ));
    }
    let fov_y_deg = match &cam.fov_y {
        Some(f) => {
            let v = f.get_ref().0;
            if !(v > 0.0 && v < 180.0) {
                return Err(cx.err(
                    f,
                    format!("`fov_y` is {v}; expected degrees strictly between 0 and 180"),
                ));
            }
            v
        }
        None => DEFAULT_FOV_Y_DEG,
    };
    let camera = Camera {
        position,
        look_at,
        up: up.normalize(),
        fov_y_deg,
    };

    // image
    let mut image = ImageSettings::default();
    if let Some(img) = &raw.image {
        let why = " (an absurd resolution)";
        if let Some(w) = &img.width {
            image.width = cx.int_in(w, "image.width", 1, MAX_RESOLUTION, why)?;
        }
        if let Some(h) = &img.height {
            image.height = cx.int_in(h, "image.height", 1, MAX_RESOLUTION, why)?;
        }
        if let Some(b) = &img.background {
            image.background = cx.non_negative3(&spanned_map(b, v3), "image.background")?;
        }
    }

    // A view too narrow for f32 at this height (camera::MIN_PIXEL_ANGLE).
    if let Some(why) = crate::camera::narrow_view_refusal(camera.fov_y_deg, image.height) {
        let at = cam
            .fov_y
            .as_ref()
            .map_or_else(|| cx.line(&cam.position), |f| cx.line(f));
        return Err(SceneError::invalid(label, at, why));
    }

    // lighting
    let mut lighting = Lighting::default();
    if let Some(l) = &raw.lighting {
        if let Some(a) = &l.ambient {
            lighting.ambient =
                cx.non_negative3(&spanned_map(a, |x| x.splat()), "lighting.ambient")?;
        }
        if let Some(k) = &l.k {
            lighting.k = cx.non_negative(k, "lighting.k")?;
        }
        if let Some(i) = l.interpolation {
            lighting.interpolation = i;
        }
        if let Some(a) = l.attenuation {
            lighting.attenuation = a;
        }
    }

    // lights
    let mut lights = Vec::with_capacity(raw.lights.len());
    for light in &raw.lights {
        let l = light.get_ref();
        let intensity = cx.non_negative3(&spanned_map(&l.intensity, |x| x.splat()), "intensity")?;
        lights.push(PointLight {
            position: v3(&l.position),
            intensity,
        });
    }

    // materials
    let mut materials = Vec::with_capacity(raw.materials.len());
    let mut warnings = Vec::new();
    let mut textures = TextureStore::default();
    for (name, m) in &raw.materials {
        let r = m.get_ref();
        let get =
            |v: &Option<Spanned<Finite>>, key: &str, default: f64| -> Result<f64, SceneError> {
                v.as_ref().map_or(Ok(default), |s| {
                    cx.non_negative(s, &format!("materials.{name}.{key}"))
                })
            };
        let d = &DEFAULT_MATERIAL;
        let color = match &r.color {
            Some(c) => cx.non_negative3(&spanned_map(c, v3), &format!("materials.{name}.color"))?,
            None => d.color,
        };
        let ior = match &r.ior {
            Some(s) => cx.positive(s, &format!("materials.{name}.ior"))?,
            None => d.ior,
        };
        let pattern = match (&r.pattern, &r.texture) {
            (Some(_), Some(t)) => {
                return Err(cx.err(
                    t,
                    format!(
                    "[materials.{name}] has both a `pattern` and a `texture`; expected one of them"
                ),
                ))
            }
            (Some(raw), None) => Some(cx.pattern(raw, &format!("materials.{name}.pattern"))?),
            (None, Some(t)) => {
                let what = format!("materials.{name}.texture");
                let (texture, translucent) = cx.texture(t, &what, base_dir, &mut textures)?;
                if translucent {
                    warnings.push(format!(
                        "{label}: the image `{}` of [materials.{name}] has alpha below 1 (not all opaque); shadelab uses its RGB and ignores the alpha",
                        t.get_ref().file.get_ref()
                    ));
                }
                Some(texture)
            }
            (None, None) => None,
        };
        materials.push(Material {
            name: name.clone(),
            color,
            ka: get(&r.ka, "ka", d.ka)?,
            kd: get(&r.kd, "kd", d.kd)?,
            ks: get(&r.ks, "ks", d.ks)?,
            p: get(&r.p, "p", d.p)?,
            kr: get(&r.kr, "kr", d.kr)?,
            kt: get(&r.kt, "kt", d.kt)?,
            ior,
            pattern,
        });
    }
    let names: Vec<String> = raw.materials.keys().cloned().collect();

    // objects
    let mut objects = Vec::new();
    for (i, obj) in raw.objects.iter().enumerate() {
        let before = objects.len();
        convert_object(
            &cx,
            base_dir,
            i + 1,
            obj,
            &names,
            &mut materials,
            &mut objects,
            &mut warnings,
            &mut textures,
        )?;
        // A sphere that f32 cannot trace from this eye (huge_sphere).
        if let (Some(Shape::Sphere { center, radius, .. }), Some(r)) = (
            objects.get(before).map(|o: &Object| o.shape.clone()),
            &obj.get_ref().radius,
        ) {
            if let Some(why) = crate::huge_sphere::refusal(camera.position, center, radius) {
                return Err(cx.err(r, format!("object {} (sphere): {why}", i + 1)));
            }
        }
    }

    // render
    let mut render = RenderSettings::default();
    if let Some(r) = &raw.render {
        if let Some(d) = &r.depth {
            render.depth = cx.int_in(d, "render.depth", 0, i64::from(MAX_DEPTH), "")?;
        }
        if let Some(c) = &r.cutoff {
            render.cutoff = cx.non_negative(c, "render.cutoff")?;
        }
        if let Some(s) = r.shadows {
            render.shadows = s;
        }
        if let Some(s) = &r.samples {
            render.samples = cx.int_in(s, "render.samples", 1, 1024, "")?;
        }
        if let Some(t) = r.traversal {
            render.traversal = t;
        }
        if let Some(m) = &r.msaa {
            let text = match m.get_ref() {
                MsaaRaw::Count(n) => n.to_string(),
                MsaaRaw::Text(t) => t.clone(),
            };
            render.msaa = text
                .parse()
                .map_err(|e: String| cx.err(m, format!("render.msaa {e}")))?;
        }
    }

    Ok(Scene {
        camera,
        image,
        lighting,
        lights,
        materials,
        objects,
        render,
        lighting_hook: None,
        warnings,
    })
}

/// The keys each shape accepts (besides `shape`).
fn allowed_keys(shape: &str) -> Option<&'static [&'static str]> {
    Some(match shape {
        "sphere" => &["center", "radius", "segments", "material"],
        "plane" => &["center", "normal", "size", "segments", "material"],
        "box" => &["center", "size", "rotate_deg", "material"],
        "mesh" => &["file", "translate", "rotate_deg", "scale", "material"],
        _ => return None,
    })
}

#[allow(clippy::too_many_arguments)]
fn convert_object(
    cx: &Ctx,
    base_dir: &Path,
    index: usize,
    obj: &Spanned<ObjectRaw>,
    names: &[String],
    materials: &mut Vec<Material>,
    objects: &mut Vec<Object>,
    warnings: &mut Vec<String>,
    textures: &mut TextureStore,
) -> Result<(), SceneError> {
    let o = obj.get_ref();
    let shape = o.shape.get_ref().as_str();
    let allowed = allowed_keys(shape).ok_or_else(|| {
        cx.err(
            &o.shape,
            format!(
                "object {index}: unknown shape `{shape}`; expected one of sphere, plane, box, mesh"
            ),
        )
    })?;
    // Which keys are present, with their lines.
    let present: [(&str, Option<usize>); 10] = [
        ("center", o.center.as_ref().map(|s| cx.line(s))),
        ("radius", o.radius.as_ref().map(|s| cx.line(s))),
        ("segments", o.segments.as_ref().map(|s| cx.line(s))),
        ("normal", o.normal.as_ref().map(|s| cx.line(s))),
        ("size", o.size.as_ref().map(|s| cx.line(s))),
        ("rotate_deg", o.rotate_deg.as_ref().map(|s| cx.line(s))),
        ("material", o.material.as_ref().map(|s| cx.line(s))),
        ("file", o.file.as_ref().map(|s| cx.line(s))),
        ("translate", o.translate.as_ref().map(|s| cx.line(s))),
        ("scale", o.scale.as_ref().map(|s| cx.line(s))),
    ];
    for (key, line) in present {
        if let Some(line) = line {
            if !allowed.contains(&key) {
                return Err(SceneError::invalid(
                    cx.label,
                    line,
                    format!(
                        "object {index}: key `{key}` does not apply to a {shape}; expected one of shape, {}",
                        allowed.join(", ")
                    ),
                ));
            }
        }
    }
    let obj_line = cx.line(&o.shape);
    let missing = |key: &str| {
        SceneError::invalid(
            cx.label,
            obj_line,
            format!("object {index} ({shape}): missing required key `{key}`"),
        )
    };
    let lookup = |m: &Spanned<String>| -> Result<usize, SceneError> {
        let name = m.get_ref();
        names.iter().position(|n| n == name).ok_or_else(|| {
            let known = if names.is_empty() {
                "no materials are defined; add a [materials.NAME] table".to_string()
            } else {
                format!("expected one of {}", names.join(", "))
            };
            cx.err(
                m,
                format!("object {index} ({shape}): unknown material `{name}`; {known}"),
            )
        })
    };
    let center = || {
        o.center
            .as_ref()
            .map(|c| v3(c.get_ref()))
            .ok_or_else(|| missing("center"))
    };
    let segments = |default: i64, lo: i64, hi: i64| -> Result<u32, SceneError> {
        match &o.segments {
            Some(s) => cx.int_in(s, &format!("object {index}: segments"), lo, hi, ""),
            None => Ok(default as u32),
        }
    };

    if shape == "mesh" {
        let file = o.file.as_ref().ok_or_else(|| missing("file"))?;
        let material = o.material.as_ref().map(lookup).transpose()?;
        let translate = o
            .translate
            .as_ref()
            .map_or(DVec3::ZERO, |t| v3(t.get_ref()));
        let rotation = rotation_from_deg(
            o.rotate_deg
                .as_ref()
                .map_or(DVec3::ZERO, |r| v3(r.get_ref())),
        );
        let scale = match &o.scale {
            Some(s) => {
                let v = s.get_ref().splat();
                if v.x == 0.0 || v.y == 0.0 || v.z == 0.0 {
                    return Err(cx.err(
                        s,
                        format!("object {index} (mesh): `scale` has a zero component; expected non-zero values"),
                    ));
                }
                v
            }
            None => DVec3::ONE,
        };
        let post = DMat4::from_translation(translate)
            * DMat4::from_mat3(rotation)
            * DMat4::from_scale(scale);
        let path = base_dir.join(file.get_ref());
        let mut loading = gltf::Loading {
            limits: cx.limits,
            textures,
        };
        let loaded = gltf::load_meshes(&path, post, material, materials, warnings, &mut loading)
            .map_err(|e| SceneError::InObject {
                file: cx.label.to_string(),
                line: cx.line(file),
                object: index,
                source: Box::new(e),
            })?;
        objects.extend(loaded);
        return Ok(());
    }

    let material = lookup(o.material.as_ref().ok_or_else(|| missing("material"))?)?;
    let shape = match shape {
        "sphere" => {
            let center = center()?;
            let r = o.radius.as_ref().ok_or_else(|| missing("radius"))?;
            let radius = cx.positive(r, &format!("object {index}: radius"))?;
            Shape::Sphere {
                center,
                radius,
                segments: segments(32, 3, 4096)?,
            }
        }
        "plane" => {
            let center = center()?;
            let n = o.normal.as_ref().ok_or_else(|| missing("normal"))?;
            let normal = v3(n.get_ref()).normalize_or_zero();
            if normal == DVec3::ZERO || !normal.is_finite() {
                return Err(cx.err(
                    n,
                    format!(
                        "object {index} (plane): `normal` is the zero vector; expected a direction"
                    ),
                ));
            }
            let s = o.size.as_ref().ok_or_else(|| missing("size"))?;
            let size = match s.get_ref() {
                NumOr3::Num(x) if *x > 0.0 => *x,
                NumOr3::Num(x) => {
                    return Err(cx.err(
                        s,
                        format!("object {index} (plane): `size` is {x}; expected a number > 0"),
                    ))
                }
                NumOr3::Vec(_) => {
                    return Err(cx.err(
                        s,
                        format!("object {index} (plane): `size` is an array; expected one number (the edge length of the square)"),
                    ))
                }
            };
            Shape::Plane {
                center,
                normal,
                size,
                segments: segments(1, 1, 1024)?,
            }
        }
        _ => {
            // box
            let center = center()?;
            let s = o.size.as_ref().ok_or_else(|| missing("size"))?;
            let size = s.get_ref().splat();
            if size.min_element() <= 0.0 {
                return Err(cx.err(
                    s,
                    format!("object {index} (box): `size` must be > 0 along every axis; expected edge lengths > 0"),
                ));
            }
            let rotation = rotation_from_deg(
                o.rotate_deg
                    .as_ref()
                    .map_or(DVec3::ZERO, |r| v3(r.get_ref())),
            );
            Shape::Box {
                center,
                half_extents: size * 0.5,
                rotation,
            }
        }
    };
    objects.push(Object { shape, material });
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::path::PathBuf;

    /// The example of `docs/interface.md`, verbatim.
    const INTERFACE_EXAMPLE: &str = r#"[camera]
position = [0.0, 1.5, 6.0]
look_at  = [0.0, 0.0, 0.0]
up       = [0.0, 1.0, 0.0]   # optional, this default
fov_y    = 40.0              # degrees, vertical

[image]
width      = 640
height     = 480
background = [0.05, 0.05, 0.08]   # linear RGB

[lighting]
ambient = 0.2          # Ia: a number or [r, g, b]
k       = 1.0          # the constant in Il / (d + k)
interpolation = "perspective"   # or "screen" (the lecture's scanline rule)

[[lights]]
position  = [4.0, 6.0, 5.0]
intensity = 8.0        # Il: a number or [r, g, b]

[materials.plaster]
color = [0.9, 0.85, 0.8]
ka = 0.3
kd = 0.7
ks = 0.2
p  = 20
kr = 0.0               # reflectance   (ray tracing)
kt = 0.0               # transmittance (ray tracing)
ior = 1.0

[materials.glass]
color = [1.0, 1.0, 1.0]
ka = 0.0
kd = 0.05
ks = 0.8
p  = 300
kr = 0.1
kt = 0.85
ior = 1.5

[[objects]]
shape    = "sphere"
center   = [0.0, 0.0, 0.0]
radius   = 1.0
segments = 48          # tessellation for the raster modes; the ray tracer
                       # intersects the exact sphere
material = "glass"

[[objects]]
shape    = "plane"     # a finite square, the same in every mode
center   = [0.0, -1.0, 0.0]
normal   = [0.0, 1.0, 0.0]
size     = 12.0
material = "plaster"

[[objects]]
shape    = "mesh"
file     = "models/teapot.glb"
translate = [2.0, -1.0, 0.0]
rotate_deg = [0.0, 30.0, 0.0]    # XYZ Euler angles
scale    = 0.5                   # a number or [x, y, z]
material = "plaster"             # optional: overrides the file's materials

[render]                          # optional defaults, each also a CLI flag
depth   = 5                       # ray tracing: maximum recursion depth
cutoff  = 0.001                   # ray tracing: adaptive depth cut-off
shadows = true
samples = 1                       # ray tracing: samples per pixel
msaa    = 1                       # raster modes: samples per pixel ("4,per-sample": shade each)
"#;

    fn fixture(name: &str) -> PathBuf {
        PathBuf::from(env!("CARGO_MANIFEST_DIR"))
            .join("tests/data")
            .join(name)
    }

    fn parse_ok(text: &str) -> Scene {
        parse(text, Path::new("."), "scene.toml").unwrap_or_else(|e| panic!("{e}"))
    }

    fn parse_err(text: &str) -> String {
        match parse(text, Path::new("."), "scene.toml") {
            Ok(_) => panic!("expected an error for:\n{text}"),
            Err(e) => e.to_string(),
        }
    }

    fn assert_has(msg: &str, parts: &[&str]) {
        for p in parts {
            assert!(msg.contains(p), "`{p}` missing from: {msg}");
        }
        assert!(!msg.contains('\n'), "not one line: {msg}");
    }

    const CAMERA: &str = "[camera]\nposition = [0, 0, 5]\nlook_at = [0, 0, 0]\n";

    fn with_camera(rest: &str) -> String {
        format!("{CAMERA}{rest}")
    }

    #[test]
    fn interface_example_parses_verbatim() {
        let dir = tempfile::tempdir().unwrap();
        std::fs::create_dir(dir.path().join("models")).unwrap();
        std::fs::copy(fixture("cube.glb"), dir.path().join("models/teapot.glb")).unwrap();
        let s = parse(INTERFACE_EXAMPLE, dir.path(), "interface.toml")
            .unwrap_or_else(|e| panic!("{e}"));
        assert_eq!(s.camera.position, DVec3::new(0.0, 1.5, 6.0));
        assert_eq!(s.camera.look_at, DVec3::ZERO);
        assert_eq!(s.camera.up, DVec3::Y);
        assert_eq!(s.camera.fov_y_deg, 40.0);
        assert_eq!((s.image.width, s.image.height), (640, 480));
        assert_eq!(s.image.background, DVec3::new(0.05, 0.05, 0.08));
        assert_eq!(s.lighting.ambient, DVec3::splat(0.2));
        assert_eq!(s.lighting.k, 1.0);
        assert_eq!(s.lighting.interpolation, Interpolation::Perspective);
        assert!(s.lighting.attenuation);
        assert_eq!(s.lights.len(), 1);
        assert_eq!(s.lights[0].position, DVec3::new(4.0, 6.0, 5.0));
        assert_eq!(s.lights[0].intensity, DVec3::splat(8.0));
        let plaster = s
            .materials
            .iter()
            .position(|m| m.name == "plaster")
            .unwrap();
        let glass = s.materials.iter().position(|m| m.name == "glass").unwrap();
        let p = &s.materials[plaster];
        assert_eq!(p.color, DVec3::new(0.9, 0.85, 0.8));
        assert_eq!(
            (p.ka, p.kd, p.ks, p.p, p.kr, p.kt, p.ior),
            (0.3, 0.7, 0.2, 20.0, 0.0, 0.0, 1.0)
        );
        let g = &s.materials[glass];
        assert_eq!(
            (g.ka, g.kd, g.ks, g.p, g.kr, g.kt, g.ior),
            (0.0, 0.05, 0.8, 300.0, 0.1, 0.85, 1.5)
        );
        assert_eq!(s.objects.len(), 3);
        assert!(
            matches!(s.objects[0].shape, Shape::Sphere { radius, segments: 48, .. } if radius == 1.0)
        );
        assert_eq!(s.objects[0].material, glass);
        match s.objects[1].shape {
            Shape::Plane {
                center,
                normal,
                size,
                segments,
            } => {
                assert_eq!(
                    (center, normal, size, segments),
                    (DVec3::new(0.0, -1.0, 0.0), DVec3::Y, 12.0, 1)
                );
            }
            ref other => panic!("{other:?}"),
        }
        assert_eq!(s.objects[1].material, plaster);
        // The mesh: T * R * S applied to the cube's corner (0.5, 0.5, 0.5).
        assert_eq!(s.objects[2].material, plaster, "material override");
        assert_eq!(
            s.materials.len(),
            2,
            "overridden file materials are not added"
        );
        let Shape::Mesh(m) = &s.objects[2].shape else {
            panic!()
        };
        assert_eq!(m.triangles.len(), 12);
        let expected = DVec3::new(2.0, -1.0, 0.0)
            + DMat3::from_rotation_y(30f64.to_radians()) * DVec3::splat(0.25);
        assert!(m.positions.iter().any(|p| (*p - expected).length() < 1e-9));
        assert_eq!(
            s.render,
            RenderSettings {
                depth: 5,
                cutoff: 0.001,
                shadows: true,
                samples: 1,
                traversal: Traversal::Auto,
                msaa: crate::msaa::Msaa::default(),
            }
        );
        assert!(s.warnings.is_empty());
    }

    #[test]
    fn every_default() {
        let s = parse_ok(&with_camera(
            "[materials.m]\n[[objects]]\nshape = \"sphere\"\ncenter = [0, 0, 0]\nradius = 1\nmaterial = \"m\"\n\
             [[objects]]\nshape = \"plane\"\ncenter = [0, -1, 0]\nnormal = [0, 3, 0]\nsize = 4\nmaterial = \"m\"\n\
             [[objects]]\nshape = \"box\"\ncenter = [1, 2, 3]\nsize = 2\nmaterial = \"m\"\n",
        ));
        assert_eq!(s.camera.up, DVec3::Y);
        assert_eq!(s.camera.fov_y_deg, 40.0);
        assert_eq!(
            s.image,
            ImageSettings {
                width: 640,
                height: 480,
                background: DVec3::new(0.05, 0.05, 0.08)
            }
        );
        assert_eq!(
            s.lighting,
            Lighting {
                ambient: DVec3::splat(0.2),
                k: 1.0,
                interpolation: Interpolation::Perspective,
                attenuation: true
            }
        );
        assert!(s.lights.is_empty());
        assert_eq!(
            s.materials[0],
            Material {
                name: "m".into(),
                color: DVec3::ONE,
                ka: 0.2,
                kd: 0.8,
                ks: 0.0,
                p: 32.0,
                kr: 0.0,
                kt: 0.0,
                ior: 1.0,
                pattern: None,
            }
        );
        assert!(matches!(
            s.objects[0].shape,
            Shape::Sphere { segments: 32, .. }
        ));
        match s.objects[1].shape {
            Shape::Plane {
                normal, segments, ..
            } => assert_eq!((normal, segments), (DVec3::Y, 1)),
            ref o => panic!("{o:?}"),
        }
        match s.objects[2].shape {
            Shape::Box {
                center,
                half_extents,
                rotation,
            } => {
                assert_eq!(center, DVec3::new(1.0, 2.0, 3.0));
                assert_eq!(half_extents, DVec3::ONE);
                assert_eq!(rotation, DMat3::IDENTITY);
            }
            ref o => panic!("{o:?}"),
        }
        assert_eq!(s.render, RenderSettings::default());
    }

    #[test]
    fn extensions_and_alternative_forms() {
        let s = parse_ok(&with_camera(
            "[lighting]\nambient = [0.1, 0.2, 0.3]\nk = 0\ninterpolation = \"screen\"\nattenuation = false\n\
             [[lights]]\nposition = [1, 2, 3]\nintensity = [1, 0.5, 0]\n\
             [materials.m]\n[[objects]]\nshape = \"box\"\ncenter = [0, 0, 0]\nsize = [2, 4, 6]\nrotate_deg = [0, 90, 0]\nmaterial = \"m\"\n\
             [render]\ndepth = 0\ncutoff = 0\nshadows = false\nsamples = 16\ntraversal = \"query\"\nmsaa = \"4,per-sample\"\n",
        ));
        assert_eq!(s.lighting.ambient, DVec3::new(0.1, 0.2, 0.3));
        assert_eq!(s.lighting.k, 0.0);
        assert_eq!(s.lighting.interpolation, Interpolation::Screen);
        assert!(!s.lighting.attenuation);
        assert_eq!(s.lights[0].intensity, DVec3::new(1.0, 0.5, 0.0));
        let Shape::Box {
            half_extents,
            rotation,
            ..
        } = s.objects[0].shape
        else {
            panic!()
        };
        assert_eq!(half_extents, DVec3::new(1.0, 2.0, 3.0));
        // 90 degrees about Y maps +X to -Z.
        assert!((rotation * DVec3::X - DVec3::NEG_Z).length() < 1e-12);
        assert_eq!(
            s.render,
            RenderSettings {
                depth: 0,
                cutoff: 0.0,
                shadows: false,
                samples: 16,
                traversal: Traversal::Query,
                msaa: crate::msaa::Msaa {
                    samples: 4,
                    per_sample: true,
                },
            }
        );
    }

    #[test]
    fn rotation_order_is_x_then_y_then_z() {
        let r = rotation_from_deg(DVec3::new(90.0, 90.0, 0.0));
        // X first: +Y -> +Z; then Y: +Z -> +X.
        assert!((r * DVec3::Y - DVec3::X).length() < 1e-12);
        let r = rotation_from_deg(DVec3::new(0.0, 90.0, 90.0));
        // Y first: +X -> -Z; then Z leaves -Z alone.
        assert!((r * DVec3::X - DVec3::NEG_Z).length() < 1e-12);
    }

    #[test]
    fn unknown_key_names_key_line_and_table() {
        let text = with_camera("[materials.plaster]\ncolour = [1, 1, 1]\n");
        let e = parse_err(&text);
        assert_has(
            &e,
            &[
                "scene.toml",
                "line 5",
                "`colour`",
                "[materials.plaster]",
                "color",
                "ior",
            ],
        );
        let e = parse_err(&with_camera(
            "[materials.m]\n[[objects]]\nshape = \"sphere\"\ncentre = [0, 0, 0]\n",
        ));
        assert_has(&e, &["line 7", "`centre`", "[[objects]] #1", "center"]);
        let e = parse_err(&with_camera("[imgae]\nwidth = 3\n"));
        assert_has(&e, &["line 4", "`imgae`", "image"]);
        let e = parse_err("[camera]\nposition = [0, 0, 5]\nlook_at = [0, 0, 0]\nzoom = 2\n");
        assert_has(&e, &["line 4", "`zoom`", "[camera]", "fov_y"]);
    }

    #[test]
    fn key_of_another_shape_is_rejected() {
        let e = parse_err(&with_camera(
            "[materials.m]\n[[objects]]\nshape = \"plane\"\ncenter = [0, 0, 0]\nnormal = [0, 1, 0]\nsize = 1\nradius = 2\nmaterial = \"m\"\n",
        ));
        assert_has(&e, &["line 10", "object 1", "`radius`", "plane", "normal"]);
        let e = parse_err(&with_camera("[[objects]]\nshape = \"cone\"\n"));
        assert_has(&e, &["line 5", "`cone`", "sphere, plane, box, mesh"]);
    }

    #[test]
    fn missing_required_keys() {
        let e = parse_err("[camera]\nposition = [0, 0, 5]\n");
        assert_has(&e, &["scene.toml", "`look_at`", "[camera]"]);
        let e = parse_err("[image]\nwidth = 3\n");
        assert_has(&e, &["scene.toml", "[camera]"]);
        let e = parse_err(&with_camera("[materials.m]\n[[objects]]\nshape = \"sphere\"\ncenter = [0, 0, 0]\nmaterial = \"m\"\n"));
        assert_has(&e, &["line 6", "object 1 (sphere)", "`radius`"]);
        let e = parse_err(&with_camera(
            "[materials.m]\n[[objects]]\nshape = \"sphere\"\ncenter = [0, 0, 0]\nradius = 1\n",
        ));
        assert_has(&e, &["line 6", "object 1 (sphere)", "`material`"]);
        let e = parse_err(&with_camera("[[objects]]\nshape = \"mesh\"\n"));
        assert_has(&e, &["line 5", "`file`"]);
        let e = parse_err(&with_camera("[[lights]]\nposition = [0, 0, 0]\n"));
        assert_has(&e, &["`intensity`", "[[lights]] #1"]);
        let e = parse_err(&with_camera("[[objects]]\ncenter = [0, 0, 0]\n"));
        assert_has(&e, &["`shape`"]);
    }

    #[test]
    fn wrong_types() {
        let e = parse_err(&with_camera("[materials.m]\nka = \"high\"\n"));
        assert_has(&e, &["line 5", "`ka`", "wrong type", "finite number"]);
        let e = parse_err("[camera]\nposition = [0, 0]\nlook_at = [0, 0, 0]\n");
        assert_has(&e, &["line 2", "`position`", "3"]);
        let e = parse_err(&with_camera("[image]\nwidth = 640.5\n"));
        assert_has(&e, &["line 5", "`width`", "integer"]);
        let e = parse_err(&with_camera("[lighting]\ninterpolation = \"linear\"\n"));
        assert_has(&e, &["line 5", "`linear`", "perspective", "screen"]);
        let e = parse_err(&with_camera("[render]\nshadows = 1\n"));
        assert_has(&e, &["line 5", "`shadows`", "bool"]);
        let e = parse_err(&with_camera(
            "[[lights]]\nposition = [0, 0, 0]\nintensity = [1, 2]\n",
        ));
        assert_has(&e, &["line 6", "`intensity`", "3"]);
        let e = parse_err(&with_camera("lights = 3\n"));
        assert_has(&e, &["line 4", "`lights`"]);
        let e = parse_err("[camera\nposition = [0, 0, 5]\n");
        assert_has(&e, &["scene.toml line 1"]);
    }

    #[test]
    fn non_finite_numbers_are_rejected_with_their_line() {
        for (text, line) in [
            (with_camera("[lighting]\nk = nan\n"), "line 5"),
            (with_camera("[lighting]\nambient = inf\n"), "line 5"),
            (
                with_camera("[[lights]]\nposition = [0, -inf, 0]\nintensity = 1\n"),
                "line 5",
            ),
            (
                "[camera]\nposition = [0, 0, nan]\nlook_at = [0, 0, 0]\n".to_string(),
                "line 2",
            ),
            (with_camera("[materials.m]\np = -inf\n"), "line 5"),
        ] {
            let e = parse_err(&text);
            assert_has(&e, &[line, "non-finite", "finite number"]);
        }
    }

    #[test]
    fn unknown_material_names_object_line_and_choices() {
        let e = parse_err(&with_camera(
            "[materials.plaster]\n[materials.glass]\n[[objects]]\nshape = \"sphere\"\ncenter = [0, 0, 0]\nradius = 1\nmaterial = \"marble\"\n",
        ));
        assert_has(&e, &["line 10", "object 1", "`marble`", "glass, plaster"]);
        let e = parse_err(&with_camera(
            "[[objects]]\nshape = \"box\"\ncenter = [0, 0, 0]\nsize = 1\nmaterial = \"x\"\n",
        ));
        assert_has(&e, &["line 8", "no materials are defined"]);
    }

    #[test]
    fn a_checker_pattern_takes_its_defaults_and_its_values() {
        let s = parse(
            &with_camera(
                "[materials.plain]\npattern = { kind = \"checker\" }\n[materials.set]\npattern = { kind = \"checker\", scale = 3, colors = [[1, 0, 0], [0, 0, 1]] }\n",
            ),
            Path::new("."),
            "t.toml",
        )
        .unwrap();
        let [plain, set] = [&s.materials[0], &s.materials[1]];
        assert_eq!(
            plain.pattern,
            Some(Pattern::Checker {
                scale: CHECKER_SCALE,
                colors: CHECKER_COLORS
            })
        );
        assert_eq!(
            set.pattern,
            Some(Pattern::Checker {
                scale: 3.0,
                colors: [DVec3::X, DVec3::Z]
            })
        );
    }

    /// A mesh under a patterned material needs texture coordinates; the
    /// test cube has none, and the message names the primitive and the
    /// material.
    #[test]
    fn a_pattern_on_a_mesh_without_texture_coordinates_is_refused() {
        let dir = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("tests/data");
        let text = with_camera(
            "[materials.m]\npattern = { kind = \"checker\" }\n[[objects]]\nshape = \"mesh\"\nfile = \"cube.glb\"\nmaterial = \"m\"\n",
        );
        let e = parse(&text, &dir, "t.toml").unwrap_err().to_string();
        assert_has(
            &e,
            &[
                "cube.glb",
                "has no texture coordinates (TEXCOORD_0)",
                "material `m`",
            ],
        );
    }

    #[test]
    fn absurd_and_invalid_values() {
        for (rest, parts) in [
            ("[image]\nwidth = 0\n", &["line 5", "image.width", "0", "absurd", "16384"][..]),
            ("[image]\nheight = 100000\n", &["line 5", "image.height", "100000", "absurd"]),
            ("[image]\nwidth = -3\n", &["line 5", "image.width"]),
            ("[lighting]\nk = -1\n", &["line 5", "lighting.k", ">= 0"]),
            ("[materials.m]\nior = 0\n", &["line 5", "ior", "> 0"]),
            ("[materials.m]\nkd = -0.5\n", &["line 5", "materials.m.kd", ">= 0"]),
            ("[materials.m]\ncolor = [1, -1, 1]\n", &["line 5", "color"]),
            ("[[lights]]\nposition = [0, 0, 0]\nintensity = -2\n", &["line 6", "intensity", ">= 0"]),
            ("[render]\ndepth = 65\n", &["line 5", "render.depth", "64"]),
            ("[render]\nsamples = 0\n", &["line 5", "render.samples", "1024"]),
            ("[render]\nmsaa = 0\n", &["line 5", "render.msaa", "sample count"]),
            ("[render]\nmsaa = \"4,sometimes\"\n", &["line 5", "render.msaa", "per-sample"]),
            ("[render]\ncutoff = -0.1\n", &["line 5", "render.cutoff"]),
            (
                "[materials.m]\n[[objects]]\nshape = \"sphere\"\ncenter = [0, 0, 0]\nradius = 0\nmaterial = \"m\"\n",
                &["line 8", "object 1: radius", "> 0"],
            ),
            (
                "[materials.m]\n[[objects]]\nshape = \"sphere\"\ncenter = [0, 0, 0]\nradius = 1\nsegments = 2\nmaterial = \"m\"\n",
                &["line 9", "segments", "3 to 4096"],
            ),
            (
                "[materials.m]\n[[objects]]\nshape = \"plane\"\ncenter = [0, 0, 0]\nnormal = [0, 0, 0]\nsize = 1\nmaterial = \"m\"\n",
                &["line 8", "`normal`", "zero"],
            ),
            (
                "[materials.m]\n[[objects]]\nshape = \"plane\"\ncenter = [0, 0, 0]\nnormal = [0, 1, 0]\nsize = [1, 2, 3]\nmaterial = \"m\"\n",
                &["line 9", "`size`", "one number"],
            ),
            (
                "[materials.m]\n[[objects]]\nshape = \"box\"\ncenter = [0, 0, 0]\nsize = [1, 0, 1]\nmaterial = \"m\"\n",
                &["line 8", "`size`", "> 0"],
            ),
            ("[[objects]]\nshape = \"mesh\"\nfile = \"x.glb\"\nscale = [1, 0, 1]\n", &["line 7", "`scale`", "non-zero"]),
            (
                "[materials.m]\npattern = { kind = \"stripes\" }\n",
                &["line 5", "materials.m.pattern.kind", "\"stripes\"", "expected \"checker\""],
            ),
            (
                "[materials.m]\npattern = { kind = \"checker\", scale = 0 }\n",
                &["line 5", "materials.m.pattern.scale", "> 0"],
            ),
            (
                "[materials.m]\npattern = { kind = \"checker\", colors = [[1, 1, 1]] }\n",
                &["line 5", "materials.m.pattern.colors", "has 1 colours; expected two"],
            ),
            (
                "[materials.m]\npattern = { kind = \"checker\", colors = [[1, 1, 1], [0, -1, 0]] }\n",
                &["line 5", "materials.m.pattern.colors", ">= 0"],
            ),
            (
                "[materials.m]\npattern = { kind = \"checker\", size = 2 }\n",
                &[
                    "line 5",
                    "unknown key `size` in the `pattern` table of [materials.m]",
                    "kind, scale, colors",
                ],
            ),
        ] {
            let e = parse_err(&with_camera(rest));
            assert_has(&e, parts);
        }
    }

    /// A texture or pattern given as a bare string is named as the table
    /// it should be, not as the loader's own type.
    #[test]
    fn a_texture_or_pattern_that_is_not_a_table_says_what_is_expected() {
        for (rest, parts) in [
            (
                "[materials.m]\ntexture = \"floor.png\"\n",
                &["line 5", "key `texture` in [materials.m]", "wrong type: string \"floor.png\", expected a table such as { file = \"floor.png\" }"][..],
            ),
            (
                "[materials.m]\npattern = \"checker\"\n",
                &["line 5", "expected a table such as { kind = \"checker\" }"],
            ),
        ] {
            let e = parse_err(&with_camera(rest));
            assert_has(&e, parts);
            assert!(!e.contains("Raw"), "{e}");
        }
    }

    /// A TOML texture's defaults are glTF's sampler defaults and no
    /// transform; a glTF file resolves in the scene's folder.
    #[test]
    fn a_texture_table_defaults_to_repeat_trilinear_scale_1() {
        assert_eq!(
            TEXTURE_FILTER.sampler(TEXTURE_WRAP),
            crate::scene::Sampler::GLTF_DEFAULT
        );
        assert_eq!(TEXTURE_SCALE, 1.0);
        let dir = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("tests/data");
        let s = parse(
            &with_camera("[materials.m]\ntexture = { file = \"checker-2x2.png\" }\n"),
            &dir,
            "t.toml",
        )
        .unwrap();
        let Some(Pattern::Image(image)) = &s.materials[0].pattern else {
            panic!("{:?}", s.materials[0].pattern)
        };
        assert_eq!(image.sampler, crate::scene::Sampler::GLTF_DEFAULT);
        assert_eq!(image.transform, UvTransform::IDENTITY);
        assert_eq!(image.name, "checker-2x2.png");
        assert_eq!(image.texture.levels[0].texels[0], [1.0, 0.0, 0.0]);
    }

    #[test]
    fn camera_must_be_usable() {
        let e = parse_err("[camera]\nposition = [1, 2, 3]\nlook_at = [1, 2, 3]\n");
        assert_has(&e, &["line 3", "`look_at`", "position"]);
        let e = parse_err("[camera]\nposition = [0, 5, 0]\nlook_at = [0, 0, 0]\n");
        assert_has(&e, &["parallel", "up"]);
        let e = parse_err("[camera]\nposition = [0, 0, 5]\nlook_at = [0, 0, 0]\nup = [0, 0, 0]\n");
        assert_has(&e, &["line 4", "`up`", "zero"]);
        for fov in ["0", "180", "-5", "200"] {
            let e = parse_err(&format!("{CAMERA}fov_y = {fov}\n"));
            assert_has(&e, &["line 4", "`fov_y`", "0 and 180"]);
        }
    }

    #[test]
    fn mesh_errors_name_scene_and_mesh_file() {
        let dir = tempfile::tempdir().unwrap();
        let e = parse(
            &with_camera("[[objects]]\nshape = \"mesh\"\nfile = \"models/missing.glb\"\n"),
            dir.path(),
            "scene.toml",
        )
        .unwrap_err()
        .to_string();
        assert_has(
            &e,
            &[
                "scene.toml line 6",
                "object 1 (mesh)",
                "missing.glb",
                "cannot read",
            ],
        );
        let corrupt = fixture("corrupt.glb");
        let text = with_camera(&format!(
            "[[objects]]\nshape = \"mesh\"\nfile = {:?}\n",
            corrupt.display().to_string()
        ));
        let e = parse_err(&text);
        assert_has(&e, &["scene.toml line 6", "corrupt.glb", "not a valid"]);
        let nan = fixture("nan_position.gltf");
        let text = with_camera(&format!(
            "[[objects]]\nshape = \"mesh\"\nfile = {:?}\n",
            nan.display().to_string()
        ));
        let e = parse_err(&text);
        assert_has(
            &e,
            &["nan_position.gltf", "POSITION", "accessor 0", "finite"],
        );
    }

    #[test]
    fn mesh_object_uses_file_materials_and_transform() {
        let cube = fixture("cube.glb");
        let text = with_camera(&format!(
            "[[objects]]\nshape = \"mesh\"\nfile = {:?}\nscale = [-2, 1, 1]\ntranslate = [0, 3, 0]\n\
             [[objects]]\nshape = \"mesh\"\nfile = {:?}\n",
            cube.display().to_string(),
            cube.display().to_string()
        ));
        let s = parse_ok(&text);
        assert_eq!(s.objects.len(), 2);
        assert_eq!(
            s.materials.len(),
            1,
            "the same file's material is added once"
        );
        assert_eq!(s.materials[0].name, "cube/ochre");
        assert_eq!(s.objects[0].material, 0);
        assert_eq!(s.objects[1].material, 0);
        let Shape::Mesh(m) = &s.objects[0].shape else {
            panic!()
        };
        assert!(m
            .positions
            .iter()
            .all(|p| (p.x.abs() - 1.0).abs() < 1e-12 && (p.y - 3.0).abs() <= 0.5 + 1e-12));
        // Mirrored by the negative scale: the winding still agrees with the normals.
        for t in &m.triangles {
            let [a, b, c] = t.map(|i| m.positions[i as usize]);
            let g = (b - a).cross(c - a);
            for &i in t {
                assert!(g.dot(m.normals[i as usize]) > 0.0);
            }
        }
    }

    #[test]
    fn messages_are_one_line_for_syntax_errors() {
        let e = parse_err("[camera]\nposition = [0, 0, 5\nlook_at = [0, 0, 0]\n");
        assert_has(&e, &["scene.toml line"]);
    }
}
