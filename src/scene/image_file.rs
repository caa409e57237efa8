//! Image files as textures (docs/scene-format.md): PNG and JPEG bytes from
//! a file, a glTF data URI or a glTF buffer view, measured from their
//! header and refused by the memory limit before anything is decoded, then
//! decoded from sRGB to a [`Texture`]'s linear texels.
//!
//! A scene's loader keeps one [`TextureStore`]: each image is decoded
//! once, and each (image, sampler, transform) becomes one
//! `Arc<ImageTexture>` that every material using it shares (the GPU's
//! texture table stores each `Arc` once). The bytes the textures take are
//! counted there and held to the [`LoadLimits`] with the geometry.
//!
//! What an image costs, counted from its header ([`image_cost`]):
//!
//! ```text
//! transient = encoded + decoded + rgba     while it is decoded
//! held      = 3 * texel_bytes(w, h)        while the scene lives
//! ```
//!
//! `encoded` is the file's bytes, `decoded` the decoder's own buffer (its
//! `total_bytes`: 3 or 4 bytes a pixel for 8-bit RGB or RGBA), `rgba` its
//! RGBA form (4 bytes a pixel, 8 for a 16-bit PNG), and
//! [`texel_bytes`] one copy of the linear `f32` RGB texels with the mip
//! chain (12 bytes a texel, about 4/3 of the image), held
//! [`TEXEL_COPIES`] times: in the scene, and on the GPU path in the texture
//! table on the host and in its device buffer. An 8-bit RGBA image costs
//! about `w h (4 + 4 + 4 * 16) = 72 w h` bytes and its file. The sum errs
//! high, as the rest of the estimate does: the decoder's buffer is freed
//! before the texels are made, and the CPU reference holds one copy.

use std::borrow::Cow;
use std::collections::HashMap;
use std::io::Cursor;
use std::path::PathBuf;
use std::sync::Arc;

use image::{DynamicImage, ImageDecoder, ImageFormat, ImageReader};

use crate::scene::error::SceneError;
use crate::scene::footprint::{format_bytes, texel_bytes, LoadLimits, TEXEL_COPIES};
use crate::scene::model::{ImageTexture, UvTransform};
use crate::scene::texture::{FilterPreset, Sampler, Texture, Wrap};

/// A TOML texture's `scale` when it gives none: `uv` as they are.
pub const TEXTURE_SCALE: f64 = 1.0;
/// A TOML texture's `wrap` when it gives none: "repeat".
pub const TEXTURE_WRAP: Wrap = Wrap::Repeat;
/// A TOML texture's `filter` when it gives none: "trilinear".
pub const TEXTURE_FILTER: FilterPreset = FilterPreset::Trilinear;

/// The longest side an image texture may have, in texels. Over it the
/// texel count of the mip chain would no longer fit the 32-bit offsets
/// the renderers index texels by; the memory limit normally refuses such
/// an image first.
pub const MAX_TEXTURE_SIDE: u32 = 32768;

/// Why an image cannot be a texture: the rest of a sentence that starts
/// with the image's name ("`floor.png` is ...").
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum ImageFailure {
    /// Not a PNG or JPEG, corrupt, truncated or of no size.
    Unreadable(String),
    /// Loading it would exceed the memory limit.
    TooLarge(String),
}

impl ImageFailure {
    pub fn message(&self) -> &str {
        match self {
            ImageFailure::Unreadable(m) | ImageFailure::TooLarge(m) => m,
        }
    }
}

/// An image decoded to a texture.
#[derive(Debug)]
pub struct Decoded {
    pub texture: Texture,
    /// Its alpha was not all opaque (which the texture ignores).
    pub translucent: bool,
}

/// What loading an image of `width` x `height` costs (module docs):
/// `(transient, held)` bytes, from its `encoded` size, the decoder's
/// `decoded` buffer and whether its samples are 16-bit (`wide`).
pub fn image_cost(width: u32, height: u32, encoded: u64, decoded: u64, wide: bool) -> (u64, u64) {
    let pixels = u64::from(width) * u64::from(height);
    let rgba = pixels.saturating_mul(if wide { 8 } else { 4 });
    let transient = encoded.saturating_add(decoded).saturating_add(rgba);
    let held = texel_bytes(width, height).saturating_mul(TEXEL_COPIES);
    (transient, held)
}

/// One line of an `image` crate error.
fn one_line(e: impl std::fmt::Display) -> String {
    e.to_string()
        .lines()
        .map(str::trim)
        .filter(|l| !l.is_empty())
        .collect::<Vec<_>>()
        .join("; ")
}

/// Decodes PNG or JPEG `bytes` to a texture, refusing it first when its
/// cost (module docs) on top of the `already` bytes the scene holds would
/// exceed `limits`. The `image` crate's own allocation limit is set to what
/// is left, as a second guard.
pub fn decode(bytes: &[u8], limits: &LoadLimits, already: u64) -> Result<Decoded, ImageFailure> {
    use ImageFailure::{TooLarge, Unreadable};
    let budget = limits.max_bytes.saturating_sub(already);
    let reader = ImageReader::new(Cursor::new(bytes))
        .with_guessed_format()
        .map_err(|e| Unreadable(format!("cannot be read ({})", one_line(e))))?;
    match reader.format() {
        Some(ImageFormat::Png | ImageFormat::Jpeg) => {}
        Some(other) => {
            return Err(Unreadable(format!(
                "is a {other:?} image; expected a PNG or JPEG image"
            )))
        }
        None => {
            return Err(Unreadable(
                "is not a PNG or JPEG image (its first bytes are neither's signature); expected a PNG or JPEG image"
                    .into(),
            ))
        }
    }
    let mut io_limits = image::Limits::no_limits();
    io_limits.max_alloc = Some(budget);
    let mut reader = reader;
    reader.limits(io_limits.clone());
    let mut decoder = reader
        .into_decoder()
        .map_err(|e| Unreadable(format!("cannot be decoded ({})", one_line(e))))?;
    let (width, height) = decoder.dimensions();
    if width == 0 || height == 0 {
        return Err(Unreadable(format!(
            "is {width} x {height} pixels; expected an image of at least one pixel"
        )));
    }
    let color = decoder.color_type();
    let wide = color.bytes_per_pixel() > color.channel_count();
    let (transient, held) = image_cost(
        width,
        height,
        bytes.len() as u64,
        decoder.total_bytes(),
        wide,
    );
    if transient.saturating_add(held) > budget {
        let beside = if already > 0 {
            format!(
                " with the {} the scene holds already",
                format_bytes(already)
            )
        } else {
            String::new()
        };
        return Err(TooLarge(format!(
            "is {width} x {height} pixels; decoding it would take about {} and holding its texels with their mip levels about {} more ({} a copy, {TEXEL_COPIES} copies for the renderers), over the memory limit of {} ({}){beside}; raise the limit with --max-memory or SHADELAB_MAX_MEMORY, or use a smaller image",
            format_bytes(transient),
            format_bytes(held),
            format_bytes(held / TEXEL_COPIES),
            format_bytes(limits.max_bytes),
            limits.source,
        )));
    }
    if width > MAX_TEXTURE_SIDE || height > MAX_TEXTURE_SIDE {
        return Err(Unreadable(format!(
            "is {width} x {height} pixels; expected at most {MAX_TEXTURE_SIDE} along each side"
        )));
    }
    let mut guard = io_limits.clone();
    guard
        .reserve(decoder.total_bytes())
        .and_then(|()| decoder.set_limits(io_limits))
        .map_err(|e| {
            TooLarge(format!(
                "cannot be decoded within the memory limit ({})",
                one_line(e)
            ))
        })?;
    let image = DynamicImage::from_decoder(decoder)
        .map_err(|e| Unreadable(format!("cannot be decoded ({})", one_line(e))))?;
    let has_alpha = color.has_alpha();
    Ok(if wide {
        let rgba = image.into_rgba16();
        Decoded {
            translucent: has_alpha && rgba.pixels().any(|p| p[3] != u16::MAX),
            texture: Texture::from_srgb16_rgba(width, height, rgba.as_raw()),
        }
    } else {
        let rgba = image.into_rgba8();
        Decoded {
            translucent: has_alpha && rgba.pixels().any(|p| p[3] != u8::MAX),
            texture: Texture::from_srgb8_rgba(width, height, rgba.as_raw()),
        }
    })
}

/// Which image: a file (by its path, canonical where it can be made so),
/// or the `index`th image held inside the glTF file `label` (a buffer view
/// or a data URI).
#[derive(Debug, Clone, PartialEq, Eq, Hash)]
pub enum ImageKey {
    File(PathBuf),
    Embedded { label: String, index: usize },
}

/// One texture a material asks for.
pub struct TextureRequest {
    pub key: ImageKey,
    /// What messages and [`ImageTexture::name`] call it.
    pub name: String,
    pub sampler: Sampler,
    pub transform: UvTransform,
}

/// A texture the store gave.
pub struct Fetched {
    pub texture: Arc<ImageTexture>,
    /// Its image was decoded for this request and its alpha is not all
    /// opaque: the caller warns, once per image.
    pub newly_translucent: bool,
}

/// The image textures of one scene being loaded: each image decoded once,
/// one `Arc<ImageTexture>` per (image, sampler, transform), and the bytes
/// they hold (module docs), counted against the memory limit.
#[derive(Debug, Default)]
pub struct TextureStore {
    held: u64,
    images: HashMap<ImageKey, Arc<ImageTexture>>,
    textures: HashMap<(ImageKey, Sampler, [u64; 6]), Arc<ImageTexture>>,
}

impl TextureStore {
    /// The bytes the textures loaded so far hold ([`TEXEL_COPIES`] copies
    /// of their texels).
    pub fn held(&self) -> u64 {
        self.held
    }

    /// The texture `request` asks for. Its image's bytes come from `read`,
    /// called only when the image is not decoded yet; `already` is what the
    /// caller holds besides the textures (a glTF file's geometry), and
    /// `fail` turns an image's failure into the caller's error.
    pub fn texture<'b>(
        &mut self,
        request: TextureRequest,
        limits: &LoadLimits,
        already: u64,
        read: impl FnOnce() -> Result<Cow<'b, [u8]>, SceneError>,
        fail: impl FnOnce(ImageFailure) -> SceneError,
    ) -> Result<Fetched, SceneError> {
        let TextureRequest {
            key,
            name,
            sampler,
            transform,
        } = request;
        // `+ 0.0`: -0 and 0 are one key.
        let full = (
            key.clone(),
            sampler,
            transform.0.map(|x| (x + 0.0).to_bits()),
        );
        if let Some(t) = self.textures.get(&full) {
            return Ok(Fetched {
                texture: Arc::clone(t),
                newly_translucent: false,
            });
        }
        let already = already.saturating_add(self.held);
        let (texture, newly_translucent) = match self.images.get(&key) {
            Some(first) => {
                let held = first
                    .texture
                    .texel_count()
                    .saturating_mul(12 * TEXEL_COPIES);
                if already.saturating_add(held) > limits.max_bytes {
                    return Err(fail(ImageFailure::TooLarge(format!(
                        "is used with another sampler or texture transform, whose copy of its texels would take about {} more, over the memory limit of {} ({}) with the {} the scene holds already; raise the limit with --max-memory or SHADELAB_MAX_MEMORY",
                        format_bytes(held),
                        format_bytes(limits.max_bytes),
                        limits.source,
                        format_bytes(already)
                    ))));
                }
                (first.texture.clone(), false)
            }
            None => {
                let bytes = read()?;
                let decoded = decode(&bytes, limits, already).map_err(fail)?;
                (decoded.texture, decoded.translucent)
            }
        };
        self.held = self
            .held
            .saturating_add(texture.texel_count().saturating_mul(12 * TEXEL_COPIES));
        let image = Arc::new(ImageTexture {
            name,
            texture,
            sampler,
            transform,
        });
        self.images.entry(key).or_insert_with(|| Arc::clone(&image));
        self.textures.insert(full, Arc::clone(&image));
        Ok(Fetched {
            texture: image,
            newly_translucent,
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene::texture::Filter;

    /// A PNG of `rgba` pixels (`width` x `height`), made with the `png`
    /// crate (no code shared with the decoder's path here).
    pub(crate) fn png(width: u32, height: u32, rgba: &[u8]) -> Vec<u8> {
        let mut out = Vec::new();
        let mut encoder = png::Encoder::new(&mut out, width, height);
        encoder.set_color(png::ColorType::Rgba);
        encoder.set_depth(png::BitDepth::Eight);
        let mut writer = encoder.write_header().unwrap();
        writer.write_image_data(rgba).unwrap();
        writer.finish().unwrap();
        out
    }

    /// The linear value of an 8-bit sRGB value, by the sRGB formula in f64.
    fn linear(v: u8) -> f64 {
        let s = f64::from(v) / 255.0;
        if s <= 0.04045 {
            s / 12.92
        } else {
            ((s + 0.055) / 1.055).powf(2.4)
        }
    }

    #[test]
    fn a_png_decodes_to_linear_texels_and_its_mip_chain() {
        // Top left red, top right green (half alpha), bottom left blue,
        // bottom right sRGB 128 grey.
        let rgba = [
            255, 0, 0, 255, 0, 255, 0, 128, 0, 0, 255, 255, 128, 128, 128, 255,
        ];
        let d = decode(&png(2, 2, &rgba), &LoadLimits::default(), 0).unwrap();
        assert!(d.translucent);
        let level0 = &d.texture.levels[0];
        assert_eq!((level0.width, level0.height), (2, 2));
        let g = linear(128);
        assert!((g - 0.2158605).abs() < 1e-6, "{g}");
        let want = [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0], [g, g, g]];
        for (got, want) in level0.texels.iter().zip(want) {
            for c in 0..3 {
                assert!(
                    (f64::from(got[c]) - want[c]).abs() < 1e-6,
                    "{got:?} {want:?}"
                );
            }
        }
        assert_eq!(d.texture.levels.len(), 2);
        let mean = d.texture.levels[1].texels[0];
        assert!((f64::from(mean[0]) - (1.0 + g) / 4.0).abs() < 1e-6);
        // Opaque: no warning due.
        let opaque = decode(&png(1, 1, &[9, 9, 9, 255]), &LoadLimits::default(), 0).unwrap();
        assert!(!opaque.translucent);
    }

    #[test]
    fn what_is_not_a_png_or_jpeg_is_refused() {
        let limits = LoadLimits::default();
        let e = decode(b"hello, world, not an image", &limits, 0).unwrap_err();
        assert!(e.message().contains("is not a PNG or JPEG image"), "{e:?}");
        // A GIF's signature: known to the crate, not a texture format here.
        let e = decode(b"GIF89a\x01\x00\x01\x00\x00\x00\x00;", &limits, 0).unwrap_err();
        assert!(
            e.message()
                .contains("is a Gif image; expected a PNG or JPEG"),
            "{e:?}"
        );
        // A PNG cut short after its signature.
        let whole = png(2, 2, &[0; 16]);
        let e = decode(&whole[..20], &limits, 0).unwrap_err();
        assert!(
            matches!(&e, ImageFailure::Unreadable(m) if m.starts_with("cannot be decoded (")),
            "{e:?}"
        );
        // Its data cut short: the header reads, the pixels do not.
        let e = decode(&whole[..whole.len() - 20], &limits, 0).unwrap_err();
        assert!(e.message().starts_with("cannot be decoded ("), "{e:?}");
    }

    #[test]
    fn the_cost_is_counted_from_the_header_and_held_to_the_limit() {
        let bytes = png(4, 4, &[200; 64]);
        let (transient, held) = image_cost(4, 4, bytes.len() as u64, 64, false);
        assert_eq!(held, TEXEL_COPIES * 12 * (16 + 4 + 1));
        assert_eq!(transient, bytes.len() as u64 + 64 + 64);
        let at = LoadLimits {
            max_bytes: 1000 + transient + held,
            source: "--max-memory 1k".into(),
        };
        assert!(decode(&bytes, &at, 1000).is_ok());
        let e = decode(&bytes, &at, 1001).unwrap_err();
        let ImageFailure::TooLarge(m) = e else {
            panic!("{e:?}")
        };
        assert!(
            m.starts_with("is 4 x 4 pixels; decoding it would take about"),
            "{m}"
        );
        assert!(
            m.contains("(--max-memory 1k)") && m.contains("1001 B the scene holds"),
            "{m}"
        );
    }

    #[test]
    fn each_image_is_decoded_once_and_each_variant_shared() {
        let mut store = TextureStore::default();
        let limits = LoadLimits::default();
        let bytes = png(2, 1, &[255, 255, 255, 255, 0, 0, 0, 10]);
        let request = |sampler, scale: f64| TextureRequest {
            key: ImageKey::File("/x/a.png".into()),
            name: "a.png".into(),
            sampler,
            transform: UvTransform([scale, 0.0, 0.0, 0.0, scale, 0.0]),
        };
        let mut reads = 0;
        let mut get = |store: &mut TextureStore, sampler, scale| {
            store
                .texture(
                    request(sampler, scale),
                    &limits,
                    0,
                    || {
                        reads += 1;
                        Ok(Cow::Borrowed(&bytes[..]))
                    },
                    |f| SceneError::mesh("t", f.message()),
                )
                .unwrap()
        };
        let a = get(&mut store, Sampler::GLTF_DEFAULT, 1.0);
        assert!(a.newly_translucent);
        let b = get(&mut store, Sampler::GLTF_DEFAULT, 1.0);
        assert!(Arc::ptr_eq(&a.texture, &b.texture) && !b.newly_translucent);
        let nearest = FilterPreset::Nearest.sampler(Wrap::ClampToEdge);
        assert_eq!(nearest.minification, Filter::Nearest);
        let c = get(&mut store, nearest, 1.0);
        let d = get(&mut store, Sampler::GLTF_DEFAULT, 2.0);
        assert!(!Arc::ptr_eq(&a.texture, &c.texture) && !Arc::ptr_eq(&a.texture, &d.texture));
        assert_eq!(c.texture.texture, a.texture.texture);
        assert_eq!(c.texture.sampler, nearest);
        assert_eq!(d.texture.transform.0[4], 2.0);
        assert_eq!(reads, 1, "decoded once");
        // 2x1 and 1x1: three texels, TEXEL_COPIES copies each of 12
        // bytes, for each of the three textures.
        assert_eq!(store.held(), 3 * 3 * 12 * TEXEL_COPIES);
    }
}
