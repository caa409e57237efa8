//! The scene's image textures as the shaders read them
//! (`shaders/include/texture.glsl`): every level of every texture in one
//! buffer of linear RGB floats, and a table of records saying where each
//! level lies and how each texture is sampled. The shaders filter these
//! texels themselves, by the rules the CPU reference follows
//! (`cpu::sample`), so no driver's sampler approximations enter the image.

use std::sync::Arc;

use crate::scene::{Filter, ImageTexture, Material, Pattern, Wrap};

/// The texel buffer and the record table, and which material reads which
/// texture.
#[derive(Debug, Default)]
pub struct TextureTable {
    /// First one record per texture: `(first level record, level count,
    /// sampler bits, 0)`; then one per level: `(first texel, width,
    /// height, 0)`.
    pub records: Vec<[u32; 4]>,
    /// Three floats per texel, level after level, row after row.
    pub texels: Vec<f32>,
    /// Per material, its texture's index in `records`, if it has one.
    pub material_texture: Vec<Option<u32>>,
}

/// The sampler as `texture.glsl` reads it: wrap `u` in bits 0-1 and `v` in
/// 2-3 (0 repeat, 1 clamp to edge, 2 mirrored repeat), magnification
/// LINEAR in bit 4, minification LINEAR in bit 5, the mipmap filter in
/// bits 6-7 (0 none, 1 nearest, 2 linear).
pub fn sampler_bits(image: &ImageTexture) -> u32 {
    let wrap = |w: Wrap| match w {
        Wrap::Repeat => 0,
        Wrap::ClampToEdge => 1,
        Wrap::MirroredRepeat => 2,
    };
    let linear = |f: Filter| u32::from(f == Filter::Linear);
    let s = &image.sampler;
    let mip = match s.mipmap {
        None => 0,
        Some(Filter::Nearest) => 1,
        Some(Filter::Linear) => 2,
    };
    wrap(s.wrap_u)
        | wrap(s.wrap_v) << 2
        | linear(s.magnification) << 4
        | linear(s.minification) << 5
        | mip << 6
}

impl TextureTable {
    /// The textures of `materials`, each stored once however many
    /// materials share it.
    pub fn new(materials: &[Material]) -> Self {
        let mut images: Vec<&Arc<ImageTexture>> = Vec::new();
        let mut material_texture = Vec::with_capacity(materials.len());
        for material in materials {
            let index = match &material.pattern {
                Some(Pattern::Image(image)) => Some(match images
                    .iter()
                    .position(|known| Arc::ptr_eq(known, image))
                {
                    Some(i) => i,
                    None => {
                        images.push(image);
                        images.len() - 1
                    }
                } as u32),
                _ => None,
            };
            material_texture.push(index);
        }
        let mut table = TextureTable {
            records: Vec::new(),
            texels: Vec::new(),
            material_texture,
        };
        let mut next_level = images.len() as u32;
        for image in &images {
            let count = image.texture.levels.len() as u32;
            table
                .records
                .push([next_level, count, sampler_bits(image), 0]);
            next_level += count;
        }
        for image in &images {
            for level in &image.texture.levels {
                let first = (table.texels.len() / 3) as u32;
                table.records.push([first, level.width, level.height, 0]);
                table.texels.extend(level.texels.iter().flatten());
            }
        }
        table
    }

    pub fn is_empty(&self) -> bool {
        self.records.is_empty()
    }
}
