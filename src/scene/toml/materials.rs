//! `[materials.NAME]`: the Phong coefficients with their defaults, and a
//! surface that is either a procedural `pattern` (a checkerboard) or an
//! image `texture`, placed on the face by its scale, rotation and offset
//! and sampled by its wrap and filter.

use std::borrow::Cow;
use std::collections::BTreeMap;

use toml::Spanned;

use super::checks::{spanned_map, Ctx};
use super::schema::{v3, Finite, MaterialRaw, PatternRaw, TextureRaw};
use crate::scene::defaults::{CHECKER_COLORS, CHECKER_SCALE, DEFAULT_MATERIAL};
use crate::scene::error::SceneError;
use crate::scene::image_file::{
    ImageFailure, ImageKey, TextureRequest, TextureStore, TEXTURE_FILTER, TEXTURE_SCALE,
    TEXTURE_WRAP,
};
use crate::scene::model::{Material, Pattern, UvTransform};
use crate::scene::texture::{FilterPreset, Wrap};

/// Every material in name order (the order `Scene::materials` keeps).
/// Textures are decoded into `textures`, once per file; an image with
/// alpha adds a warning.
pub(super) fn materials(
    cx: &Ctx,
    raw: &BTreeMap<String, Spanned<MaterialRaw>>,
    textures: &mut TextureStore,
    warnings: &mut Vec<String>,
) -> Result<Vec<Material>, SceneError> {
    let mut materials = Vec::with_capacity(raw.len());
    for (name, m) in raw {
        materials.push(material(cx, name, m.get_ref(), textures, warnings)?);
    }
    Ok(materials)
}

/// One material, its keys checked in the order colour, `ior`, surface,
/// then the coefficients.
fn material(
    cx: &Ctx,
    name: &str,
    r: &MaterialRaw,
    textures: &mut TextureStore,
    warnings: &mut Vec<String>,
) -> Result<Material, SceneError> {
    let get = |v: &Option<Spanned<Finite>>, key: &str, default: f64| -> Result<f64, SceneError> {
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
    let pattern = surface(cx, name, r, textures, warnings)?;
    Ok(Material {
        name: name.to_string(),
        color,
        ka: get(&r.ka, "ka", d.ka)?,
        kd: get(&r.kd, "kd", d.kd)?,
        ks: get(&r.ks, "ks", d.ks)?,
        p: get(&r.p, "p", d.p)?,
        kr: get(&r.kr, "kr", d.kr)?,
        kt: get(&r.kt, "kt", d.kt)?,
        ior,
        pattern,
    })
}

/// A material's `pattern` or `texture` (not both), if it has one.
fn surface(
    cx: &Ctx,
    name: &str,
    r: &MaterialRaw,
    textures: &mut TextureStore,
    warnings: &mut Vec<String>,
) -> Result<Option<Pattern>, SceneError> {
    Ok(match (&r.pattern, &r.texture) {
        (Some(_), Some(t)) => {
            return Err(cx.err(
                t,
                format!(
                    "[materials.{name}] has both a `pattern` and a `texture`; expected one of them"
                ),
            ))
        }
        (Some(raw), None) => Some(pattern(cx, raw, &format!("materials.{name}.pattern"))?),
        (None, Some(t)) => {
            let what = format!("materials.{name}.texture");
            let (texture, translucent) = texture(cx, t, &what, textures)?;
            if translucent {
                warnings.push(format!(
                    "{}: the image `{}` of [materials.{name}] has alpha below 1 (not all opaque); shadelab uses its RGB and ignores the alpha",
                    cx.label,
                    t.get_ref().file.get_ref()
                ));
            }
            Some(texture)
        }
        (None, None) => None,
    })
}

/// A material's `pattern`, its defaults filled in: a checkerboard of
/// `CHECKER_SCALE` cells per unit of `u` and `v`, in `CHECKER_COLORS`.
fn pattern(cx: &Ctx, s: &Spanned<PatternRaw>, what: &str) -> Result<Pattern, SceneError> {
    let raw = s.get_ref();
    if raw.kind.get_ref() != "checker" {
        return Err(cx.err(
            &raw.kind,
            format!(
                "`{what}.kind` is {:?}; expected \"checker\"",
                raw.kind.get_ref()
            ),
        ));
    }
    let scale = match &raw.scale {
        Some(v) => cx.positive(v, &format!("{what}.scale"))?,
        None => CHECKER_SCALE,
    };
    let colors = match &raw.colors {
        Some(list) => {
            let [a, b] = list.get_ref()[..] else {
                return Err(cx.err(
                    list,
                    format!(
                        "`{what}.colors` has {} colours; expected two, [[r, g, b], [r, g, b]]",
                        list.get_ref().len()
                    ),
                ));
            };
            let key = format!("{what}.colors");
            [
                cx.non_negative3(&spanned_map(list, |_| v3(&a)), &key)?,
                cx.non_negative3(&spanned_map(list, |_| v3(&b)), &key)?,
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
    cx: &Ctx,
    s: &Spanned<TextureRaw>,
    what: &str,
    store: &mut TextureStore,
) -> Result<(Pattern, bool), SceneError> {
    let raw = s.get_ref();
    let scale = texture_scale(cx, raw, what)?;
    let wrap = wrap(cx, raw, what)?;
    let filter = filter(cx, raw, what)?;
    let file = raw.file.get_ref();
    let path = cx.base_dir.join(file);
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
            cx.err(
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
                file: cx.label.to_string(),
                message: format!("line {}: {message}", cx.line(&raw.file)),
            },
            ImageFailure::Unreadable(_) => cx.err(&raw.file, message),
        }
    };
    let fetched = store.texture(request, cx.limits, 0, read, fail)?;
    Ok((Pattern::Image(fetched.texture), fetched.newly_translucent))
}

/// A texture's `scale` (tiles across a face), > 0 and with a finite
/// square.
fn texture_scale(cx: &Ctx, raw: &TextureRaw, what: &str) -> Result<f64, SceneError> {
    Ok(match &raw.scale {
        Some(v) => {
            let scale = cx.positive(v, &format!("{what}.scale"))?;
            // The renderers' level of detail takes the area's scale.
            if !(scale * scale).is_finite() {
                return Err(cx.err(
                    v,
                    format!(
                        "`{what}.scale` is {scale:e}; expected a number > 0 whose square is finite"
                    ),
                ));
            }
            scale
        }
        None => TEXTURE_SCALE,
    })
}

/// A texture's `wrap`, by name.
fn wrap(cx: &Ctx, raw: &TextureRaw, what: &str) -> Result<Wrap, SceneError> {
    Ok(match &raw.wrap {
        Some(w) => Wrap::from_name(w.get_ref()).ok_or_else(|| {
            cx.err(
                w,
                format!(
                    "`{what}.wrap` is {:?}; expected one of {}",
                    w.get_ref(),
                    quoted(&Wrap::NAMES)
                ),
            )
        })?,
        None => TEXTURE_WRAP,
    })
}

/// A texture's `filter`, by name.
fn filter(cx: &Ctx, raw: &TextureRaw, what: &str) -> Result<FilterPreset, SceneError> {
    Ok(match &raw.filter {
        Some(f) => FilterPreset::from_name(f.get_ref()).ok_or_else(|| {
            let names = FilterPreset::ALL.map(FilterPreset::name);
            cx.err(
                f,
                format!(
                    "`{what}.filter` is {:?}; expected one of {}",
                    f.get_ref(),
                    quoted(&names)
                ),
            )
        })?,
        None => TEXTURE_FILTER,
    })
}

/// `"a", "b"`: the names a key accepts, as the file writes them.
fn quoted(names: &[&str]) -> String {
    names
        .iter()
        .map(|n| format!("\"{n}\""))
        .collect::<Vec<_>>()
        .join(", ")
}

#[cfg(test)]
mod tests {
    use std::path::{Path, PathBuf};

    use glam::DVec3;

    use super::super::parse;
    use super::super::test_support::*;
    use super::*;

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
    fn absurd_and_invalid_values() {
        for (rest, parts) in [
            ("[materials.m]\nior = 0\n", &["line 5", "ior", "> 0"][..]),
            ("[materials.m]\nkd = -0.5\n", &["line 5", "materials.m.kd", ">= 0"]),
            ("[materials.m]\ncolor = [1, -1, 1]\n", &["line 5", "color"]),
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
}
