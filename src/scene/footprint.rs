//! How much geometry a scene holds and what holding it costs, counted
//! before it is built, so that a scene too large for the machine is refused
//! with a clear message instead of being killed by the kernel halfway.
//!
//! The figures per vertex, triangle and object are the scene model's own
//! layout (`model.rs`); what the renderers add on top is `crate::memory`'s
//! business. `docs/memory.md` has the measurements behind both.

use std::sync::Arc;

use super::error::SceneError;
use super::model::{ImageTexture, Object, Pattern, Scene, Shape};
use super::tessellate;

/// Geometry counts: objects, vertices and triangles, as the raster modes
/// see them (primitive shapes tessellated, meshes as they are).
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct GeometrySize {
    pub objects: u64,
    pub vertices: u64,
    pub triangles: u64,
    /// Of `vertices` and `triangles`, those of meshes that carry vertex
    /// colours or texture coordinates, which every renderer holds apart.
    pub attributed_vertices: u64,
    pub attributed_triangles: u64,
}

/// A mesh object's bytes beyond its vertices and triangles: the `Object`
/// itself and three heap blocks (positions, normals, triangles) with the
/// allocator's header each.
const OBJECT_BYTES: u64 = std::mem::size_of::<Object>() as u64 + 3 * 16;
/// A position and a normal in `f64`.
const VERTEX_BYTES: u64 = 48;
/// Three `u32` indices.
const TRIANGLE_BYTES: u64 = 12;
/// A vertex colour and texture coordinates in `f64`.
const ATTRIBUTE_BYTES: u64 = 40;

impl GeometrySize {
    pub fn add(&mut self, objects: u64, vertices: u64, triangles: u64) {
        self.objects += objects;
        self.vertices += vertices;
        self.triangles += triangles;
    }

    /// Counts `vertices` and `triangles` (already added) as carrying vertex
    /// colours or texture coordinates.
    pub fn add_attributed(&mut self, vertices: u64, triangles: u64) {
        self.attributed_vertices += vertices;
        self.attributed_triangles += triangles;
    }

    /// Every object of `scene`, shapes counted as tessellated when
    /// `tessellated` (the raster modes), else as the single records the
    /// ray tracer intersects exactly.
    pub fn of_scene(scene: &Scene, tessellated: bool) -> Self {
        let mut size = GeometrySize::default();
        for object in &scene.objects {
            let (vertices, triangles) = match &object.shape {
                Shape::Mesh(_) => tessellate::counts(&object.shape),
                _ if tessellated => tessellate::counts(&object.shape),
                _ => (0, 0),
            };
            size.add(1, vertices, triangles);
            let attributed = match &object.shape {
                Shape::Mesh(m) => !m.colors.is_empty() || !m.uvs.is_empty(),
                // A patterned shape's tessellation carries coordinates.
                _ => tessellated && scene.materials[object.material].pattern.is_some(),
            };
            if attributed {
                size.add_attributed(vertices, triangles);
            }
        }
        size
    }

    /// The scene model's bytes for this much geometry held as meshes.
    pub fn model_bytes(&self) -> u64 {
        self.objects
            .saturating_mul(OBJECT_BYTES)
            .saturating_add(self.vertices.saturating_mul(VERTEX_BYTES))
            .saturating_add(self.triangles.saturating_mul(TRIANGLE_BYTES))
            .saturating_add(self.attributed_vertices.saturating_mul(ATTRIBUTE_BYTES))
    }
}

/// Limits a load must keep to.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct LoadLimits {
    /// The most bytes the loaded geometry may take.
    pub max_bytes: u64,
    /// How the limit was set, for the message that refuses a scene
    /// (for example "--max-memory 2G").
    pub source: String,
}

impl Default for LoadLimits {
    /// No limit.
    fn default() -> Self {
        LoadLimits {
            max_bytes: u64::MAX,
            source: "no limit".to_string(),
        }
    }
}

impl LoadLimits {
    /// Refuses the geometry a file would bring when holding it alone
    /// would exceed the limit.
    pub fn check(&self, file: &str, size: &GeometrySize) -> Result<(), SceneError> {
        let bytes = size.model_bytes();
        if bytes <= self.max_bytes {
            return Ok(());
        }
        Err(SceneError::TooLarge {
            file: file.to_string(),
            message: format!(
                "its nodes instance {} triangles in {} meshes; holding them would take about {}, over the memory limit of {} ({}); raise the limit with --max-memory or SHADELAB_MAX_MEMORY",
                size.triangles,
                size.objects,
                format_bytes(bytes),
                format_bytes(self.max_bytes),
                self.source
            ),
        })
    }
}

/// How many copies of a texture's linear texels (12 bytes a texel) a
/// render holds, rounded up: the scene's [`Texture`](super::Texture) (12
/// bytes a texel), and on the GPU path the texture table's copy on the
/// host and its buffer on the device (`gpu::shared::texture_table`, 16 bytes a
/// texel each: RGB and a pad), 44 bytes in all, counted as 48. The CPU
/// reference holds the first alone; the loader counts them all, so that it
/// errs high.
pub const TEXEL_COPIES: u64 = 4;

/// The bytes of one copy of the linear texels of a `width` x `height`
/// texture with its whole mip chain: 12 a texel (RGB in `f32`), summed over
/// the levels as [`Texture::new`](super::Texture::new) makes them (each
/// side halved, rounding down, at least 1), about 4/3 of level 0's
/// `12 width height`.
pub fn texel_bytes(width: u32, height: u32) -> u64 {
    let (mut w, mut h) = (u64::from(width.max(1)), u64::from(height.max(1)));
    let mut texels = 0u64;
    loop {
        texels = texels.saturating_add(w.saturating_mul(h));
        if w == 1 && h == 1 {
            return texels.saturating_mul(12);
        }
        w = (w / 2).max(1);
        h = (h / 2).max(1);
    }
}

/// The bytes of one copy of the texels of every distinct image texture
/// `scene`'s materials use (each `Arc` counted once, mip chains included):
/// what rendering adds per copy it holds ([`TEXEL_COPIES`] on the GPU
/// path, one on the CPU reference's).
pub fn scene_texture_bytes(scene: &Scene) -> u64 {
    let mut seen: Vec<&Arc<ImageTexture>> = Vec::new();
    let mut bytes = 0u64;
    for material in &scene.materials {
        if let Some(Pattern::Image(image)) = &material.pattern {
            if !seen.iter().any(|s| Arc::ptr_eq(s, image)) {
                seen.push(image);
                bytes = bytes.saturating_add(image.texture.texel_count().saturating_mul(12));
            }
        }
    }
    bytes
}

/// `bytes` for a person: "1.5 GiB", "320 MiB", "12 KiB", "100 B".
pub fn format_bytes(bytes: u64) -> String {
    const UNITS: [&str; 4] = ["KiB", "MiB", "GiB", "TiB"];
    if bytes < 1024 {
        return format!("{bytes} B");
    }
    let mut value = bytes as f64 / 1024.0;
    let mut unit = 0;
    while value >= 1024.0 && unit + 1 < UNITS.len() {
        value /= 1024.0;
        unit += 1;
    }
    if value < 10.0 {
        format!("{value:.1} {}", UNITS[unit])
    } else {
        format!("{value:.0} {}", UNITS[unit])
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn bytes_read_as_a_person_would_write_them() {
        assert_eq!(format_bytes(100), "100 B");
        assert_eq!(format_bytes(12 * 1024), "12 KiB");
        assert_eq!(format_bytes(1536 * 1024 * 1024), "1.5 GiB");
        assert_eq!(format_bytes(320 << 20), "320 MiB");
        assert_eq!(format_bytes(u64::MAX), "16777216 TiB");
    }

    #[test]
    fn the_limit_refuses_only_what_exceeds_it() {
        let mut size = GeometrySize::default();
        size.add(2, 300, 100);
        let bytes = size.model_bytes();
        assert_eq!(bytes, 2 * OBJECT_BYTES + 300 * 48 + 100 * 12);
        let at = LoadLimits {
            max_bytes: bytes,
            source: "--max-memory".into(),
        };
        assert!(at.check("f.gltf", &size).is_ok());
        let under = LoadLimits {
            max_bytes: bytes - 1,
            ..at
        };
        let e = under.check("f.gltf", &size).unwrap_err().to_string();
        assert!(
            e.starts_with("f.gltf: ") && e.contains("100 triangles") && e.contains("--max-memory"),
            "{e}"
        );
    }

    /// Every level of the chain, as `Texture::new` makes it.
    #[test]
    fn texel_bytes_count_the_whole_mip_chain() {
        assert_eq!(texel_bytes(1, 1), 12);
        // 4x4, 2x2, 1x1.
        assert_eq!(texel_bytes(4, 4), 12 * (16 + 4 + 1));
        // 5x3, 2x1, 1x1.
        assert_eq!(texel_bytes(5, 3), 12 * (15 + 2 + 1));
        let t = crate::scene::Texture::new(5, 3, vec![[0.0; 3]; 15]);
        assert_eq!(texel_bytes(5, 3), t.texel_count() * 12);
        // About 4/3 of level 0 for a large square.
        let big = texel_bytes(4096, 4096) as f64 / (12.0 * 4096.0 * 4096.0);
        assert!((big - 4.0 / 3.0).abs() < 1e-6, "{big}");
    }
}
