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
    /// Linear RGB and a pad per texel, level after level, row after row:
    /// one load a texel where three floats took three.
    pub texels: Vec<[f32; 4]>,
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
                let first = table.texels.len() as u32;
                table.records.push([first, level.width, level.height, 0]);
                table
                    .texels
                    .extend(level.texels.iter().map(|&[r, g, b]| [r, g, b, 0.0]));
            }
        }
        table
    }

    /// The sampler bits every image of `materials` shares, if they share
    /// one: the shaders are then specialised to it (`SAMPLER_FIXED`), and
    /// the branches on wrap modes and filters fold away when the pipeline
    /// is built (lavapipe's code generation for a textured ray tracer:
    /// 2.0 s with one sampler, 4.8 s reading each image's at run time).
    pub fn common_sampler(materials: &[Material]) -> Option<u32> {
        let mut bits = materials.iter().filter_map(|m| match &m.pattern {
            Some(Pattern::Image(image)) => Some(sampler_bits(image)),
            _ => None,
        });
        let first = bits.next()?;
        bits.all(|b| b == first).then_some(first)
    }

    pub fn is_empty(&self) -> bool {
        self.records.is_empty()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene::{Sampler, Texture, UvTransform};

    fn textured(sampler: Sampler) -> Material {
        let mut m = crate::scene::default_scene().materials[0].clone();
        m.pattern = Some(Pattern::Image(Arc::new(ImageTexture {
            name: "t".into(),
            texture: Texture::new(2, 1, vec![[0.25; 3], [0.5; 3]]),
            sampler,
            transform: UvTransform::IDENTITY,
        })));
        m
    }

    /// Each texture once, its levels after the records, each texel padded
    /// to four floats; the materials point at their texture.
    #[test]
    fn a_shared_texture_is_stored_once_with_its_levels() {
        let shared = textured(Sampler::GLTF_DEFAULT);
        let plain = crate::scene::default_scene().materials[1].clone();
        let table = TextureTable::new(&[shared.clone(), plain, shared]);
        assert_eq!(table.material_texture, [Some(0), None, Some(0)]);
        // One texture record, then its two levels (2 x 1, 1 x 1).
        assert_eq!(table.records[0][..2], [1, 2]);
        assert_eq!(table.records[1], [0, 2, 1, 0]);
        assert_eq!(table.records[2], [2, 1, 1, 0]);
        assert_eq!(
            table.texels,
            [
                [0.25, 0.25, 0.25, 0.0],
                [0.5, 0.5, 0.5, 0.0],
                [0.375, 0.375, 0.375, 0.0]
            ]
        );
    }

    #[test]
    fn one_sampler_is_common_and_two_are_not() {
        let nearest = Sampler {
            mipmap: None,
            ..Sampler::GLTF_DEFAULT
        };
        let a = textured(Sampler::GLTF_DEFAULT);
        let b = textured(nearest);
        // REPEAT both ways, LINEAR magnification and minification, mipmap
        // LINEAR: 0 | 0 << 2 | 1 << 4 | 1 << 5 | 2 << 6.
        assert_eq!(
            TextureTable::common_sampler(&[a.clone(), a.clone()]),
            Some(176)
        );
        assert_eq!(TextureTable::common_sampler(&[a, b]), None);
        assert_eq!(TextureTable::common_sampler(&[]), None);
    }
}
