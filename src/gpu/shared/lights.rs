//! The scene's lights and the materials' pattern constants as both
//! renderers' shaders read them (`shaders/include/lights.glsl`,
//! `pattern.glsl`), and which lighting terms a scene uses at all: the
//! specialization constants every pipeline sets from them, so that a
//! scene without specular or attenuation compiles none of it.

use bytemuck::{Pod, Zeroable};
use glam::DVec3;

use crate::scene::{Falloff, Scene};

#[repr(C)]
#[derive(Debug, Clone, Copy, Pod, Zeroable)]
pub struct GpuLight {
    pub position: [f32; 4],
    pub intensity: [f32; 4],
}

/// A draw's pattern (`PATTERN` variants), pushed after `DrawConstants`.
#[repr(C)]
#[derive(Debug, Clone, Copy, Pod, Zeroable)]
pub struct PatternConstants {
    /// rgb: the checker's first colour; w: its scale, 0 for a material
    /// without a pattern (the pattern is then 1).
    pub checker_a: [f32; 4],
    /// rgb: the checker's second colour.
    pub checker_b: [f32; 4],
}

impl PatternConstants {
    /// The values for a material's pattern, or for none. An image
    /// (`TEXTURE` variants) is its index in the texture table
    /// (`gpu::shared::texture_table`) as `w = -1 - index`, and its uv transform's
    /// rows in the two `xyz`.
    pub fn of(pattern: Option<&crate::scene::Pattern>, texture: Option<u32>) -> Self {
        match pattern {
            None => PatternConstants::zeroed(),
            Some(crate::scene::Pattern::Checker {
                scale,
                colors: [a, b],
            }) => {
                let (a, b) = (a.as_vec3(), b.as_vec3());
                PatternConstants {
                    checker_a: [a.x, a.y, a.z, *scale as f32],
                    checker_b: [b.x, b.y, b.z, 0.0],
                }
            }
            Some(crate::scene::Pattern::Image(image)) => {
                let m = image.transform.0.map(|x| x as f32);
                let index = texture.expect("a material's image is in the texture table");
                PatternConstants {
                    checker_a: [m[0], m[1], m[2], -1.0 - index as f32],
                    checker_b: [m[3], m[4], m[5], 0.0],
                }
            }
        }
    }
}

pub fn lights(scene: &Scene, eye: DVec3) -> Vec<GpuLight> {
    scene
        .lights
        .iter()
        .map(|l| GpuLight {
            position: f32x4(l.position - eye),
            intensity: f32x4(l.intensity),
        })
        .collect()
}

fn f32x4(v: DVec3) -> [f32; 4] {
    let [x, y, z] = v.as_vec3().to_array();
    [x, y, z, 0.0]
}

/// The lighting terms a scene uses, which every pipeline's specialization
/// constants carry: the loop over exactly its lights, specular only if
/// some drawn material has `ks > 0`, attenuation only if the scene's
/// falloff has one.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct SceneLighting {
    pub light_count: i32,
    pub use_specular: bool,
    pub use_attenuation: bool,
    /// The attenuation is `1 / d^2`, not the lecture's `1 / (d + k)`.
    pub inverse_square: bool,
}

impl SceneLighting {
    pub fn of(scene: &Scene) -> Self {
        SceneLighting {
            light_count: scene.lights.len() as i32,
            use_specular: scene
                .objects
                .iter()
                .any(|o| scene.materials[o.material].ks > 0.0),
            use_attenuation: scene.lighting.falloff != Falloff::None,
            inverse_square: scene.lighting.falloff == Falloff::InverseSquare,
        }
    }
}
