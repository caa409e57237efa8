//! Scenes for the photon map's caustics (`tests/cpu/caustics.rs` for
//! the f64 twin, `tests/gpu/caustics.rs` for the GPU), and the answer the
//! mirror's caustic is held to, worked out by hand (also read by
//! `benches/caustics.rs`).
#![allow(dead_code)]

use glam::DVec3;

/// A point light at (0, 0.5, 0) over a white floor (y = 0), a mirror
/// (kr = 0.8, kd = 0) standing at x = 0.5 from the floor to y = 2,
/// |z| <= 1, facing the light; the lecture's falloff `1 / (d + k)`, k = 1,
/// `d` along the light's path.
pub const MIRROR_BESIDE_A_LIGHT: &str = r#"
[camera]
position = [0.0, 3.0, 5.0]
look_at = [0.0, 0.0, 0.0]
fov_y = 45.0

[image]
width = 64
height = 48

[lighting]
ambient = 0.0
falloff = "lecture"
k = 1.0

[[lights]]
position = [0.0, 0.5, 0.0]
intensity = 1.0

[materials.white]
color = [1.0, 1.0, 1.0]
kd = 1.0

[materials.mirror]
color = [1.0, 1.0, 1.0]
kd = 0.0
kr = 0.8

[[objects]]
shape = "plane"
center = [0.0, 0.0, 0.0]
normal = [0.0, 1.0, 0.0]
size = 10.0
material = "white"

[[objects]]
shape = "plane"
center = [0.5, 1.0, 0.0]
normal = [-1.0, 0.0, 0.0]
size = 2.0
material = "mirror"
"#;

/// A glass ball (kt = 1, ior 1.5) under a light, over a white floor, seen
/// from above at an angle; no ambient, no highlight, lecture falloff.
pub const GLASS_BALL_ON_A_FLOOR: &str = r#"
[camera]
position = [0.0, 3.0, 3.5]
look_at = [0.0, 0.0, 0.0]
fov_y = 40.0

[image]
width = 96
height = 72

[lighting]
ambient = 0.0

[[lights]]
position = [0.3, 3.0, 0.0]
intensity = 3.0

[render]
depth = 8
samples = 16

[materials.white]
color = [1.0, 1.0, 1.0]
kd = 0.8
ks = 0.0

[materials.glass]
color = [1.0, 1.0, 1.0]
kd = 0.0
ks = 0.0
kt = 1.0
ior = 1.5

[[objects]]
shape = "plane"
center = [0.0, 0.0, 0.0]
normal = [0.0, 1.0, 0.0]
size = 6.0
material = "white"

[[objects]]
shape = "sphere"
center = [0.0, 0.8, 0.0]
radius = 0.5
material = "glass"
"#;

/// A white wall behind `MIRROR_BESIDE_A_LIGHT`'s light (z = -1, facing
/// the camera), added to its objects: the mirror's light on the floor
/// lights it, and its light from the mirror lights the floor.
pub const WALL_BEHIND_THE_LIGHT: &str = r#"
[[objects]]
shape = "plane"
center = [0.0, 1.0, -1.0]
normal = [0.0, 0.0, 1.0]
size = 6.0
material = "white"
"#;

/// `toml` loaded as a scene file.
pub fn scene_of(toml: &str) -> shadelab::scene::Scene {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("scene.toml");
    std::fs::write(&path, toml).unwrap();
    shadelab::scene::load(&path).unwrap()
}

/// The caustic the mirror of `MIRROR_BESIDE_A_LIGHT` throws on the floor
/// point `p`, in the image's units: a light of intensity `kr Il` at the
/// mirror image (1, 0.5, 0), `kd C kr Il cos / (d + k)` with `d` from the
/// image (kd C = 1, Il = 1, k = 1). `None` off the patch the test holds
/// (away from the mirror's edges and its foot).
pub fn mirror_caustic_at(p: DVec3) -> Option<f64> {
    if !(p.x > -0.45 && p.x < 0.25 && p.z.abs() < 0.25) {
        return None;
    }
    let to = DVec3::new(1.0, 0.5, 0.0) - p;
    let d = to.length();
    Some(0.8 * (to.y / d) / (d + 1.0))
}

/// Every pixel of `image` (a caustic image of `scene`, the mirror scene)
/// whose centre sees the floor patch, against `mirror_caustic_at`: the
/// ratios got / wanted.
pub fn mirror_caustic_ratios(
    scene: &shadelab::scene::Scene,
    image: &shadelab::LinearImage,
) -> Vec<f64> {
    let view = shadelab::camera::View::new(scene, scene.image.width, scene.image.height);
    let mut ratios = Vec::new();
    for y in 0..scene.image.height {
        for x in 0..scene.image.width {
            let dir = view.ray_direction(f64::from(x) + 0.5, f64::from(y) + 0.5);
            let t = -view.eye.y / dir.y;
            let p = view.eye + t * dir;
            let Some(want) = mirror_caustic_at(p).filter(|_| t > 0.0) else {
                continue;
            };
            let got = f64::from(image.pixels[(y * scene.image.width + x) as usize][0]);
            ratios.push(got / want);
        }
    }
    ratios
}

/// The mean of `ratios`, their spread (standard deviation) and the worst
/// one's distance from 1.
pub fn summary(ratios: &[f64]) -> (f64, f64, f64) {
    let n = ratios.len() as f64;
    let mean = ratios.iter().sum::<f64>() / n;
    let spread = (ratios.iter().map(|r| (r - mean).powi(2)).sum::<f64>() / n).sqrt();
    let worst = ratios.iter().map(|r| (r - 1.0).abs()).fold(0.0, f64::max);
    (mean, spread, worst)
}
