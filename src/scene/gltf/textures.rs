//! A material's base colour texture as its image pattern: the texture
//! coordinate set it reads, its `KHR_texture_transform`, its sampler, and
//! its image fetched from the scene's texture store (decoded once, within
//! the memory limit).

use super::document::GltfFile;
use super::images::{image_bytes, image_source, image_what, ImageSource};
use super::locations::material_label;
use crate::scene::error::SceneError;
use crate::scene::footprint::LoadLimits;
use crate::scene::image_file::{ImageFailure, ImageKey, TextureRequest, TextureStore};
use crate::scene::model::{Filter, Pattern, Sampler, UvTransform, Wrap};

/// The `KHR_texture_transform` object on a material's base colour texture.
fn base_colour_transform_json<'f>(
    file: &'f GltfFile,
    mat: &gltf::Material,
) -> Option<&'f serde_json::Value> {
    file.raw
        .materials
        .get(mat.index()?)?
        .get("pbrMetallicRoughness")?
        .get("baseColorTexture")?
        .get("extensions")?
        .get("KHR_texture_transform")
}

/// The texture coordinate set a material's base colour texture reads (its
/// `KHR_texture_transform`'s `texCoord`, else its own), if it has one.
pub(super) fn base_colour_set(file: &GltfFile, mat: &gltf::Material) -> Option<u32> {
    let info = mat.pbr_metallic_roughness().base_color_texture()?;
    let overridden = base_colour_transform_json(file, mat)
        .and_then(|t| t.get("texCoord")?.as_u64())
        .and_then(|set| u32::try_from(set).ok());
    Some(overridden.unwrap_or(info.tex_coord()))
}

/// `KHR_texture_transform` on a material's base colour texture as the map
/// of its texture coordinates, `uv' = T R S uv` (`gltf` module docs): with
/// offset `(ox, oy)`, rotation `r` and scale `(sx, sy)`,
/// `[cos r sx, sin r sy, ox; -sin r sx, cos r sy, oy]`. The identity
/// without it.
fn base_colour_uv_transform(
    file: &GltfFile,
    mat: &gltf::Material,
    who: &str,
) -> Result<UvTransform, SceneError> {
    let Some(t) = base_colour_transform_json(file, mat) else {
        return Ok(UvTransform::IDENTITY);
    };
    let bad = |key: &str, expected: &str| {
        SceneError::mesh(
            &file.label,
            format!(
                "material `{who}`: KHR_texture_transform `{key}` is {}; expected {expected}",
                t.get(key).map_or("missing".to_string(), |v| v.to_string())
            ),
        )
    };
    let pair = |key: &str, default: [f64; 2]| match t.get(key) {
        None => Ok(default),
        Some(v) => match v
            .as_array()
            .map(|a| a.iter().map(|x| x.as_f64()).collect::<Vec<_>>())
        {
            Some(xs) if xs.len() == 2 && xs.iter().all(Option::is_some) => {
                Ok([xs[0].unwrap_or(0.0), xs[1].unwrap_or(0.0)])
            }
            _ => Err(bad(key, "two numbers")),
        },
    };
    let offset = pair("offset", [0.0, 0.0])?;
    let scale = pair("scale", [1.0, 1.0])?;
    let rotation = match t.get("rotation") {
        None => 0.0,
        Some(v) => v
            .as_f64()
            .ok_or_else(|| bad("rotation", "a number (radians)"))?,
    };
    let (sin, cos) = rotation.sin_cos();
    let m = [
        cos * scale[0],
        sin * scale[1],
        offset[0],
        -sin * scale[0],
        cos * scale[1],
        offset[1],
    ];
    // The renderers' level of detail takes its area scale, `|det|`.
    if !m.iter().all(|x| x.is_finite()) || !UvTransform(m).area_scale().is_finite() {
        return Err(bad(
            "scale",
            "two numbers whose product is finite (the scale of the texture's area)",
        ));
    }
    // No -0 (sin 0 times a scale): equal transforms compare and share as
    // equal.
    Ok(UvTransform(m.map(|x| x + 0.0)))
}

/// A glTF sampler as the renderers sample (`gltf` module docs); glTF's defaults
/// where it says nothing: [`Sampler::GLTF_DEFAULT`].
fn sampler_of(texture: &gltf::Texture) -> Sampler {
    use gltf::texture::{MagFilter, MinFilter, WrappingMode};
    let s = texture.sampler();
    let wrap = |w: WrappingMode| match w {
        WrappingMode::Repeat => Wrap::Repeat,
        WrappingMode::ClampToEdge => Wrap::ClampToEdge,
        WrappingMode::MirroredRepeat => Wrap::MirroredRepeat,
    };
    let default = Sampler::GLTF_DEFAULT;
    let magnification = match s.mag_filter() {
        Some(MagFilter::Nearest) => Filter::Nearest,
        Some(MagFilter::Linear) => Filter::Linear,
        None => default.magnification,
    };
    let (minification, mipmap) = match s.min_filter() {
        None => (default.minification, default.mipmap),
        Some(MinFilter::Nearest) => (Filter::Nearest, None),
        Some(MinFilter::Linear) => (Filter::Linear, None),
        Some(MinFilter::NearestMipmapNearest) => (Filter::Nearest, Some(Filter::Nearest)),
        Some(MinFilter::LinearMipmapNearest) => (Filter::Linear, Some(Filter::Nearest)),
        Some(MinFilter::NearestMipmapLinear) => (Filter::Nearest, Some(Filter::Linear)),
        Some(MinFilter::LinearMipmapLinear) => (Filter::Linear, Some(Filter::Linear)),
    };
    Sampler {
        wrap_u: wrap(s.wrap_s()),
        wrap_v: wrap(s.wrap_t()),
        magnification,
        minification,
        mipmap,
    }
}

/// A material's base colour texture as its pattern (`gltf` module docs), from
/// `store`, which decodes each image once and holds the bytes of all to
/// `limits` together with `geometry` (the file's). A warning per image
/// whose alpha is not all opaque.
pub(super) fn base_colour_texture(
    file: &GltfFile,
    mat: &gltf::Material,
    store: &mut TextureStore,
    limits: &LoadLimits,
    geometry: u64,
    warnings: &mut Vec<String>,
) -> Result<Option<Pattern>, SceneError> {
    let Some(info) = mat.pbr_metallic_roughness().base_color_texture() else {
        return Ok(None);
    };
    let who = material_label(mat);
    let texture = info.texture();
    let image = texture.source();
    let source = image_source(file, &image)?;
    let what = image_what(&image, &source);
    let key = match &source {
        ImageSource::File(path, _) => {
            ImageKey::File(std::fs::canonicalize(path).unwrap_or_else(|_| path.clone()))
        }
        _ => ImageKey::Embedded {
            label: file.label.clone(),
            index: image.index(),
        },
    };
    let request = TextureRequest {
        key,
        name: format!("{} {what}", file.label),
        sampler: sampler_of(&texture),
        transform: base_colour_uv_transform(file, mat, &who)?,
    };
    let fail = |failure: ImageFailure| {
        let message = format!(
            "{what} (the base colour texture of material `{who}`) {}",
            failure.message()
        );
        match failure {
            ImageFailure::TooLarge(_) => SceneError::TooLarge {
                file: file.label.clone(),
                message,
            },
            ImageFailure::Unreadable(_) => SceneError::mesh(&file.label, message),
        }
    };
    let fetched = store.texture(
        request,
        limits,
        geometry,
        || image_bytes(file, &source, &what),
        fail,
    )?;
    if fetched.newly_translucent {
        warnings.push(format!(
            "{}: {what} has alpha below 1 (not all opaque); shadelab uses its RGB and ignores the alpha",
            file.label
        ));
    }
    Ok(Some(Pattern::Image(fetched.texture)))
}

#[cfg(test)]
mod tests {
    use crate::scene::gltf::test_support::load_patched_fixture;
    use crate::scene::model::Pattern;

    /// Extensions on the base colour texture other than the transform are
    /// named (their PNG source is drawn); the transform is not.
    #[test]
    fn other_extensions_on_the_base_colour_texture_are_announced() {
        let l = load_patched_fixture("textured_datauri.gltf", |d| {
            d["textures"][0]["extensions"] = serde_json::json!({"EXT_texture_webp": {"source": 0}});
            d["materials"][0]["pbrMetallicRoughness"]["baseColorTexture"]["extensions"]
                ["MSFT_lod"] = serde_json::json!({});
        })
        .unwrap();
        assert_eq!(l.warnings.len(), 1, "{:?}", l.warnings);
        let w = &l.warnings[0];
        for part in [
            "patched.gltf: material `painted` has ",
            "the extension MSFT_lod on its base colour texture (its PNG or JPEG source is drawn)",
            "the extension EXT_texture_webp on its base colour texture",
        ] {
            assert!(w.contains(part), "{w}\nshould say: {part}");
        }
        assert!(!w.contains("KHR_texture_transform"), "{w}");
        assert!(matches!(&l.materials[0].pattern, Some(Pattern::Image(_))));
    }

    /// An image's buffer view must lie inside its buffer; a texture's
    /// transform must be numbers.
    #[test]
    fn an_image_past_its_buffer_or_a_bad_transform_is_refused() {
        let e = load_patched_fixture("textured_datauri.gltf", |d| {
            let views = d["bufferViews"].as_array_mut().unwrap();
            views.push(serde_json::json!({"buffer": 0, "byteOffset": 16, "byteLength": 1_000_000}));
            let view = views.len() - 1;
            d["images"][0] = serde_json::json!({"bufferView": view, "mimeType": "image/png"});
        })
        .err()
        .expect("an error");
        assert!(
            e.ends_with(
                "patched.gltf: image 0 is in buffer view 4, which runs past the end of buffer 0"
            ),
            "{e}"
        );
        // A number past f32's range in a glTF file (which the gltf crate
        // reads into f32) is refused where the JSON is read, in one line
        // naming the file: the exact float parser that keeps shard records'
        // figures to the digit (serde_json's `float_roundtrip`) refuses
        // what the default one turned into infinity.
        for scale in [1e150, 1e200] {
            let e = load_patched_fixture("textured_datauri.gltf", |d| {
                d["materials"][0]["pbrMetallicRoughness"]["baseColorTexture"]["extensions"]
                    ["KHR_texture_transform"]["scale"] = serde_json::json!([scale, scale]);
            })
            .err()
            .expect("an error");
            assert!(
                e.contains("patched.gltf: not a valid glTF 2.0 file (number out of range"),
                "{e}"
            );
        }
    }
}
