//! Image textures as the renderers are to sample them
//! (docs/lighting-model.md, "Image textures"): linear RGB texels, a mip chain of
//! 2x2 box averages, and a sampler's wrap modes and filters. The f64
//! sampling itself is the CPU reference's (`cpu::sample`).
//!
//! The loaders fill them in: glTF base colour textures and TOML
//! `texture` tables (`image_file`, docs/scene-format.md).

use crate::srgb::{srgb16_to_linear, srgb8_to_linear};

/// What happens to texture coordinates outside `[0, 1]`, per axis.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Wrap {
    Repeat,
    ClampToEdge,
    MirroredRepeat,
}

/// Picking one texel, or blending the four nearest texel centres.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Filter {
    Nearest,
    Linear,
}

/// How a texture is read: glTF's sampler.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub struct Sampler {
    pub wrap_u: Wrap,
    pub wrap_v: Wrap,
    /// Where a texel covers more than a pixel (`lambda <= 0`).
    pub magnification: Filter,
    /// Within a level, where a texel covers less than a pixel.
    pub minification: Filter,
    /// Between mip levels: `None` reads level 0 alone (glTF's NEAREST and
    /// LINEAR minification filters), `Some` the nearest level or a blend of
    /// the two nearest.
    pub mipmap: Option<Filter>,
}

impl Sampler {
    /// glTF's default where a texture names no sampler: REPEAT, LINEAR
    /// magnification, LINEAR_MIPMAP_LINEAR minification.
    pub const GLTF_DEFAULT: Sampler = Sampler {
        wrap_u: Wrap::Repeat,
        wrap_v: Wrap::Repeat,
        magnification: Filter::Linear,
        minification: Filter::Linear,
        mipmap: Some(Filter::Linear),
    };
}

impl Wrap {
    /// The TOML spellings, in the order messages list them.
    pub const NAMES: [&'static str; 3] = ["repeat", "clamp", "mirror"];

    /// A TOML texture's `wrap` (both axes): "repeat", "clamp" (CLAMP_TO_EDGE)
    /// or "mirror" (MIRRORED_REPEAT).
    pub fn from_name(name: &str) -> Option<Wrap> {
        match name {
            "repeat" => Some(Wrap::Repeat),
            "clamp" => Some(Wrap::ClampToEdge),
            "mirror" => Some(Wrap::MirroredRepeat),
            _ => None,
        }
    }
}

/// The three filterings a TOML texture names (its `filter`), each a
/// magnification, minification and mipmap filter together; `compare`'s
/// `filter=` variants too.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum FilterPreset {
    /// NEAREST both ways, no mipmaps.
    Nearest,
    /// LINEAR both ways, no mipmaps.
    Bilinear,
    /// LINEAR magnification, LINEAR_MIPMAP_LINEAR minification.
    Trilinear,
}

impl FilterPreset {
    pub const ALL: [FilterPreset; 3] = [
        FilterPreset::Nearest,
        FilterPreset::Bilinear,
        FilterPreset::Trilinear,
    ];

    /// "nearest", "bilinear" or "trilinear".
    pub fn name(self) -> &'static str {
        match self {
            FilterPreset::Nearest => "nearest",
            FilterPreset::Bilinear => "bilinear",
            FilterPreset::Trilinear => "trilinear",
        }
    }

    /// The inverse of `name`.
    pub fn from_name(name: &str) -> Option<FilterPreset> {
        FilterPreset::ALL.into_iter().find(|f| f.name() == name)
    }

    /// A sampler wrapping both axes with `wrap`, filtering as this says.
    pub fn sampler(self, wrap: Wrap) -> Sampler {
        self.applied_to(Sampler {
            wrap_u: wrap,
            wrap_v: wrap,
            ..Sampler::GLTF_DEFAULT
        })
    }

    /// `sampler` filtering as this says, its wrap modes kept (`compare`'s
    /// `filter=` variants).
    pub fn applied_to(self, sampler: Sampler) -> Sampler {
        let (filter, mipmap) = match self {
            FilterPreset::Nearest => (Filter::Nearest, None),
            FilterPreset::Bilinear => (Filter::Linear, None),
            FilterPreset::Trilinear => (Filter::Linear, Some(Filter::Linear)),
        };
        Sampler {
            magnification: filter,
            minification: filter,
            mipmap,
            ..sampler
        }
    }
}

/// One level of a texture: `width` x `height` linear RGB texels, row by
/// row from the top of the image (`v = 0`, glTF's convention).
#[derive(Debug, Clone, PartialEq)]
pub struct MipLevel {
    pub width: u32,
    pub height: u32,
    pub texels: Vec<[f32; 3]>,
}

impl MipLevel {
    /// The texel at column `i`, row `j`, both in range.
    pub fn texel(&self, i: u32, j: u32) -> [f32; 3] {
        self.texels[(j * self.width + i) as usize]
    }
}

/// A texture and its mip chain, level 0 the image, down to 1 x 1.
#[derive(Debug, Clone, PartialEq)]
pub struct Texture {
    pub levels: Vec<MipLevel>,
}

impl Texture {
    /// A texture of `texels` (linear RGB, `width * height` of them, both
    /// at least 1), with its mip chain: each level halves each side of the
    /// one above (rounding down, at least 1), each texel the mean of the
    /// 2 x 2 above it (an odd last row or column is left out; a side of 1
    /// is averaged with itself), in f64, stored as f32.
    pub fn new(width: u32, height: u32, texels: Vec<[f32; 3]>) -> Self {
        assert!(width >= 1 && height >= 1 && texels.len() == (width * height) as usize);
        let mut levels = vec![MipLevel {
            width,
            height,
            texels,
        }];
        loop {
            let above = levels.last().expect("level 0 is there");
            if above.width == 1 && above.height == 1 {
                break;
            }
            let (w, h) = ((above.width / 2).max(1), (above.height / 2).max(1));
            let at = |i: u32, j: u32| {
                let t = above.texel(i.min(above.width - 1), j.min(above.height - 1));
                t.map(f64::from)
            };
            let mut texels = Vec::with_capacity((w * h) as usize);
            for j in 0..h {
                for i in 0..w {
                    let quad = [
                        at(2 * i, 2 * j),
                        at(2 * i + 1, 2 * j),
                        at(2 * i, 2 * j + 1),
                        at(2 * i + 1, 2 * j + 1),
                    ];
                    texels.push(
                        [0, 1, 2].map(|c| (quad.iter().map(|t| t[c]).sum::<f64>() / 4.0) as f32),
                    );
                }
            }
            levels.push(MipLevel {
                width: w,
                height: h,
                texels,
            });
        }
        Texture { levels }
    }

    /// A texture from 8-bit sRGB RGBA pixels (as the `image` crate decodes
    /// a PNG or JPEG), decoded to linear; alpha is not a colour and is
    /// left out.
    pub fn from_srgb8_rgba(width: u32, height: u32, rgba: &[u8]) -> Self {
        let texels = rgba
            .chunks_exact(4)
            .map(|p| [p[0], p[1], p[2]].map(srgb8_to_linear))
            .collect();
        Texture::new(width, height, texels)
    }

    /// As [`Texture::from_srgb8_rgba`], from 16-bit sRGB RGBA pixels (a
    /// 16-bit PNG), each channel decoded at its full precision.
    pub fn from_srgb16_rgba(width: u32, height: u32, rgba: &[u16]) -> Self {
        let texels = rgba
            .chunks_exact(4)
            .map(|p| [p[0], p[1], p[2]].map(srgb16_to_linear))
            .collect();
        Texture::new(width, height, texels)
    }

    /// The texels of every level, each counted once.
    pub fn texel_count(&self) -> u64 {
        self.levels
            .iter()
            .map(|l| u64::from(l.width) * u64::from(l.height))
            .sum()
    }
}
