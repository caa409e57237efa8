//! Image textures in every mode (docs/lighting-model.md, "Image
//! textures"): the level of detail each mode chooses against values worked
//! out here by hand, and the GPU against the f64 reference on the hard
//! cases for texturing (strong minification at a grazing angle, a 2 x 2
//! texture magnified, a uv seam, a texture seen in a mirror and through
//! glass) in every wrap mode and filter.

use crate::common;

use std::sync::Arc;

use crate::common::render_cpu;
use common::*;
use glam::{DVec2, DVec3};
use shadelab::scene::texture::MipLevel;
use shadelab::scene::{
    Filter, ImageTexture, Object, Pattern, Sampler, Scene, Shape, Texture, TriangleMesh,
    UvTransform, Wrap,
};
use shadelab::shading::Shading;
use shadelab::LinearImage;

const MODES: [Shading; 4] = [
    Shading::Flat,
    Shading::Gouraud,
    Shading::Phong,
    Shading::Raytrace,
];

fn image(texture: Texture, sampler: Sampler, scale: f64) -> Pattern {
    Pattern::Image(Arc::new(ImageTexture {
        name: "test".into(),
        texture,
        sampler,
        transform: UvTransform([scale, 0.0, 0.0, 0.0, scale, 0.0]),
    }))
}

fn sampler(
    wrap: Wrap,
    magnification: Filter,
    minification: Filter,
    mipmap: Option<Filter>,
) -> Sampler {
    Sampler {
        wrap_u: wrap,
        wrap_v: wrap,
        magnification,
        minification,
        mipmap,
    }
}

// ---------------------------------------------------------------------
// The level of detail, by hand.

/// Texels per side of level 0 of the level-coded texture.
const CODED: u32 = 256;
/// Its levels: 256 x 256 down to 1 x 1.
const CODED_LEVELS: u32 = 9;

/// A texture whose level `k` is uniformly `(k / 8, 1 - k / 8, 0.5)`: any
/// filter within a level gives its colour, and a blend of levels `k` and
/// `k + 1` by `f` has red `(k + f) / 8`, so red is the level of detail
/// itself, over 8, clamped to the chain.
fn level_coded_texture() -> Texture {
    let levels = (0..CODED_LEVELS)
        .map(|k| {
            let side = CODED >> k;
            let red = k as f32 / 8.0;
            MipLevel {
                width: side,
                height: side,
                texels: vec![[red, 1.0 - red, 0.5]; (side * side) as usize],
            }
        })
        .collect();
    Texture { levels }
}

/// The square's half edge, its distance from the eye, the image size and
/// the field of view.
const HALF: f64 = 4.0;
const DISTANCE: f64 = 10.0;
const PIXELS: u32 = 96;
const FOV_DEG: f64 = 50.0;
/// The texture repeats this often across the square: 256 * 6 texels over
/// its 8 units, seen from 10 units at 50 degrees over 96 pixels, is
/// 2^2.54 texels per pixel, between levels 2 and 3.
const REPEATS: f64 = 6.0;

/// Ambient light alone on a white material (`Ia = ka = 1`): a pixel shows
/// the texture's colour. The square faces the camera from `DISTANCE`, as
/// two triangles (bottom left, bottom right, top right; bottom left, top
/// right, top left) with `uv` 0 to 1 across it.
fn level_scene() -> Scene {
    let mut s = scene(PIXELS, PIXELS, FOV_DEG);
    s.lighting.ambient = DVec3::ONE;
    s.materials[0] = material(DVec3::ONE, 1.0, 0.0, 0.0, 1.0);
    s.materials[0].pattern = Some(image(level_coded_texture(), Sampler::GLTF_DEFAULT, REPEATS));
    s.objects.push(Object {
        shape: Shape::Mesh(TriangleMesh {
            positions: vec![
                DVec3::new(-HALF, -HALF, 0.0),
                DVec3::new(HALF, -HALF, 0.0),
                DVec3::new(HALF, HALF, 0.0),
                DVec3::new(-HALF, HALF, 0.0),
            ],
            normals: vec![DVec3::Z; 4],
            triangles: vec![[0, 1, 2], [0, 2, 3]],
            colors: Vec::new(),
            uvs: vec![
                DVec2::new(0.0, 0.0),
                DVec2::new(1.0, 0.0),
                DVec2::new(1.0, 1.0),
                DVec2::new(0.0, 1.0),
            ],
        }),
        material: 0,
    });
    s
}

/// The level of detail each mode should choose at pixel `(px, py)`, worked
/// out from the geometry alone. One pixel spans `pixel = 2 d tan(fov/2) /
/// height` units of the square at distance `d`, which holds
/// `texels = 256 * 6 / 8` texels per unit.
/// - Gouraud and Phong: the square is parallel to the image, so `uv` is
///   linear in the pixel position and every pixel steps `texels * pixel`
///   texels: `lambda = log2(texels * pixel)`.
/// - Ray tracing: a cone spreading `pixel / d` per unit of distance is `w =
///   t pixel / d` wide at a hit at distance `t`, meeting the square at
///   `cos = d / t`: `lambda = log2(texels * w / cos)`.
/// - Flat: that cone at the centroid of the pixel's triangle.
fn expected_lambda(shading: Shading, px: u32, py: u32) -> Option<f64> {
    let tan = (FOV_DEG.to_radians() / 2.0).tan();
    let pixel = 2.0 * DISTANCE * tan / f64::from(PIXELS);
    let texels = f64::from(CODED) * REPEATS / (2.0 * HALF);
    // The point of the square seen at the pixel's centre.
    let to_world = |w: u32| (2.0 * (f64::from(w) + 0.5) / f64::from(PIXELS) - 1.0) * DISTANCE * tan;
    let (x, y) = (to_world(px), -to_world(py));
    let margin = 0.2;
    if x.abs() > HALF - margin || y.abs() > HALF - margin || (x - y).abs() < margin {
        return None;
    }
    let cone = |point: DVec3| {
        let t = (point - DVec3::new(0.0, 0.0, DISTANCE)).length();
        let w = t * pixel / DISTANCE;
        (texels * w / (DISTANCE / t)).log2()
    };
    Some(match shading {
        Shading::Gouraud | Shading::Phong => (texels * pixel).log2(),
        Shading::Raytrace => cone(DVec3::new(x, y, 0.0)),
        Shading::Flat => {
            // Below the diagonal: the first triangle.
            let centroid = if y < x {
                DVec3::new(HALF, -HALF, 0.0) / 3.0
            } else {
                DVec3::new(-HALF, HALF, 0.0) / 3.0
            };
            cone(centroid)
        }
        Shading::Forward => unreachable!("the raster modes and the ray tracer only"),
    })
}

/// The largest error of the level read off the image's red channel.
fn worst_level_error(image: &LinearImage, shading: Shading) -> (f64, usize) {
    let mut worst = 0.0f64;
    let mut count = 0;
    for py in 0..PIXELS {
        for px in 0..PIXELS {
            let Some(lambda) = expected_lambda(shading, px, py) else {
                continue;
            };
            let red = f64::from(image.pixels[(py * PIXELS + px) as usize][0]);
            let expected = lambda.clamp(0.0, f64::from(CODED_LEVELS - 1)) / 8.0;
            worst = worst.max((red - expected).abs());
            count += 1;
        }
    }
    (worst, count)
}

#[test]
fn every_mode_reads_the_level_of_detail_worked_out_by_hand() {
    let scene = level_scene();
    let context = gpu();
    for shading in MODES {
        let (cpu, _) = render_cpu(&scene, shading).unwrap();
        let gpu_image = render(&context, &scene, shading);
        for (who, image) in [("cpu", &cpu.image), ("gpu", &gpu_image)] {
            let (worst, count) = worst_level_error(image, shading);
            assert!(count > 3000, "{shading:?}: only {count} pixels checked");
            // Red is lambda / 8. The CPU's is f64 (1e-12 would do); the
            // GPU's comes from f32 coordinates 6 apart whose one-pixel
            // differences are ~0.02: 1e-6 of relative error, a level
            // ~1e-5 off. 1e-4 in red (a level within 8e-4) leaves room.
            assert!(
                worst < 1e-4,
                "{who} {shading:?}: the level is {:.2e} off",
                worst * 8.0
            );
        }
    }
}

// ---------------------------------------------------------------------
// The GPU against the reference on hard cases.

/// A `size` x `size` texture of pseudo-random colours (a fixed LCG), so
/// that every texel and every mip level differs from its neighbours.
fn noise_texture(size: u32) -> Texture {
    let mut state = 12345u32;
    let mut next = || {
        state = state.wrapping_mul(1664525).wrapping_add(1013904223);
        (state >> 8) as f32 / (1u32 << 24) as f32
    };
    let texels = (0..size * size).map(|_| [next(), next(), next()]).collect();
    Texture::new(size, size, texels)
}

/// Every wrap mode and filter glTF has: (name, sampler).
fn samplers() -> Vec<(&'static str, Sampler)> {
    use Filter::{Linear, Nearest};
    vec![
        ("trilinear repeat", Sampler::GLTF_DEFAULT),
        (
            "nearest clamp",
            sampler(Wrap::ClampToEdge, Nearest, Nearest, None),
        ),
        (
            "bilinear mirror",
            sampler(Wrap::MirroredRepeat, Linear, Linear, None),
        ),
        (
            "nearest mip nearest",
            sampler(Wrap::Repeat, Nearest, Nearest, Some(Nearest)),
        ),
        (
            "linear mip nearest",
            sampler(Wrap::MirroredRepeat, Linear, Linear, Some(Nearest)),
        ),
        (
            "nearest mip linear",
            sampler(Wrap::ClampToEdge, Linear, Nearest, Some(Linear)),
        ),
    ]
}

/// A floor seen at a grazing angle, lit by a light and the ambient term:
/// strong minification toward the horizon, magnification at the front.
fn floor_scene(pattern: Pattern) -> Scene {
    let mut s = scene(160, 120, 60.0);
    s.camera.position = DVec3::new(0.0, 1.0, 6.0);
    s.camera.look_at = DVec3::new(0.0, 0.0, -20.0);
    s.lighting.ambient = DVec3::splat(0.3);
    s.materials[0] = material(DVec3::ONE, 1.0, 0.8, 0.3, 20.0);
    s.materials[0].pattern = Some(pattern);
    s.objects.push(Object {
        shape: Shape::Plane {
            center: DVec3::new(0.0, 0.0, -10.0),
            normal: DVec3::Y,
            size: 40.0,
            segments: 8,
        },
        material: 0,
    });
    s
}

/// The largest GPU-to-reference difference over the pixels the reference
/// does not mark as near an edge or a jump of colour, and how many those
/// are; panics where the texture did not change the image (a test that
/// would pass untextured).
fn worst_against_reference(scene: &Scene, shading: Shading) -> (f64, usize) {
    let context = gpu();
    let gpu_image = render(&context, scene, shading);
    let (cpu, coverage) = render_cpu(scene, shading).unwrap();
    let mut plain = scene.clone();
    for m in &mut plain.materials {
        m.pattern = None;
    }
    let untextured = render(&context, &plain, shading);
    assert!(
        worst_difference(&gpu_image, &untextured) > 0.1,
        "{shading:?}: the texture does not show"
    );
    let mut worst = 0.0f64;
    let mut compared = 0;
    for (i, (g, c)) in gpu_image.pixels.iter().zip(&cpu.image.pixels).enumerate() {
        if coverage.near_edge[i] {
            continue;
        }
        worst = worst.max(max_abs_diff(to_dvec(*g), to_dvec(*c)));
        compared += 1;
    }
    (worst, compared)
}

/// The GPU and the reference filter alike: their difference is f32
/// rounding of texture coordinates and of the level of detail, and of the
/// lighting (FLOAT_TOL's 1e-6). The level of detail is the worst: where a
/// pixel steps about one texel (lambda near 0, where trilinear blends the
/// two finest levels) neighbouring `uv` differ by 1/256 of the floor's
/// `[0, 4]`, and f32 rounds a `uv` near 3.2 by up to 2.4e-7, so the
/// difference, and `rho`, are ~9e-5 off relatively: lambda 1.3e-4 off,
/// which moves the blend of two levels of this noise (up to 1 apart) by as
/// much. Measured worst: 3e-5 (Phong, trilinear) with the floor's image
/// along its old axes, 1.13e-4 since it reads the right way round. Why it
/// grew: the image's top is now far from the camera, so the coordinate
/// that runs toward the camera is about 3.2 where pixels step a texel (z
/// about 1.8, 4.2 units from the eye; it was about 0.8 there, rounded 4x
/// finer). 2e-4 holds both, and a texel off (1/64 of the image) is still
/// 1e-2 away.
const TEXTURE_TOL: f64 = 2e-4;

/// `scene` with a second textured object whose image has another sampler:
/// the shaders then read each image's sampler at run time instead of
/// being specialised to one (`SAMPLER_FIXED`).
fn with_a_second_sampler(mut scene: Scene, sampler: Sampler) -> Scene {
    let other = if sampler == Sampler::GLTF_DEFAULT {
        samplers()[1].1
    } else {
        Sampler::GLTF_DEFAULT
    };
    let mut m = scene.materials[0].clone();
    m.pattern = Some(image(noise_texture(16), other, 1.0));
    scene.materials.push(m);
    scene.objects.push(Object {
        shape: Shape::Sphere {
            center: DVec3::new(1.5, 0.8, 0.0),
            radius: 0.8,
            segments: 32,
        },
        material: scene.materials.len() - 1,
    });
    scene
}

#[test]
fn a_floor_at_a_grazing_angle_matches_the_reference_in_every_filter_and_mode() {
    for (name, sampler) in samplers() {
        let one = floor_scene(image(noise_texture(64), sampler, 4.0));
        let two = with_a_second_sampler(one.clone(), sampler);
        for (scene, shading) in MODES.iter().flat_map(|&m| [(&one, m), (&two, m)]) {
            let (worst, compared) = worst_against_reference(scene, shading);
            // The floor covers half the image; pixels on a jump of a
            // NEAREST read are a small part of it.
            assert!(compared > 8000, "{name} {shading:?}: {compared} compared");
            assert!(
                worst < TEXTURE_TOL,
                "{name} {shading:?}: {worst:.2e} from the reference"
            );
        }
    }
}

/// Four texels of clearly different colours.
fn two_by_two() -> Texture {
    Texture::new(
        2,
        2,
        vec![
            [0.9, 0.1, 0.1],
            [0.1, 0.9, 0.1],
            [0.1, 0.1, 0.9],
            [0.9, 0.9, 0.1],
        ],
    )
}

#[test]
fn a_two_by_two_texture_magnified_matches_the_reference() {
    use Filter::{Linear, Nearest};
    for (name, sampler) in [
        ("linear", Sampler::GLTF_DEFAULT),
        (
            "nearest",
            sampler(Wrap::Repeat, Nearest, Linear, Some(Linear)),
        ),
    ] {
        // Each texel covers some 40 x 40 pixels of the square.
        let mut scene = level_scene();
        scene.materials[0].pattern = Some(image(two_by_two(), sampler, 1.0));
        for shading in MODES {
            let (worst, compared) = worst_against_reference(&scene, shading);
            assert!(compared > 5000, "{name} {shading:?}: {compared} compared");
            assert!(
                worst < TEXTURE_TOL,
                "{name} {shading:?}: {worst:.2e} from the reference"
            );
        }
    }
}

#[test]
fn a_sphere_seen_across_its_uv_seam_matches_the_reference() {
    // The sphere's seam (u = 0 and 1) faces -Z: the camera looks at it
    // from behind, where REPEAT joins the texture's two edges and
    // CLAMP_TO_EDGE does not.
    for wrap in [Wrap::Repeat, Wrap::ClampToEdge, Wrap::MirroredRepeat] {
        let mut s = scene(120, 120, 40.0);
        s.camera.position = DVec3::new(0.0, 1.0, -6.0);
        s.camera.look_at = DVec3::ZERO;
        s.lights[0].position = DVec3::new(2.0, 4.0, -8.0);
        s.materials[0] = material(DVec3::ONE, 0.4, 0.8, 0.3, 30.0);
        let filters = Sampler {
            wrap_u: wrap,
            wrap_v: wrap,
            ..Sampler::GLTF_DEFAULT
        };
        s.materials[0].pattern = Some(image(noise_texture(32), filters, 1.0));
        s.objects.push(Object {
            shape: Shape::Sphere {
                center: DVec3::ZERO,
                radius: 1.5,
                segments: 48,
            },
            material: 0,
        });
        for shading in MODES {
            let (worst, compared) = worst_against_reference(&s, shading);
            assert!(compared > 3000, "{wrap:?} {shading:?}: {compared} compared");
            assert!(
                worst < TEXTURE_TOL,
                "{wrap:?} {shading:?}: {worst:.2e} from the reference"
            );
        }
    }
}

#[test]
fn a_texture_seen_in_a_mirror_and_through_glass_matches_the_reference() {
    // The textured floor, a mirror behind it and a glass ball on it: the
    // cones of reflected and refracted rays, and the mirror ball's
    // curvature, set the level of detail of what they see.
    let mut s = floor_scene(image(noise_texture(64), Sampler::GLTF_DEFAULT, 4.0));
    let mut mirror = material(DVec3::splat(0.1), 0.1, 0.1, 0.5, 50.0);
    mirror.kr = 0.9;
    let mut glass = material(DVec3::ONE, 0.0, 0.05, 0.5, 80.0);
    glass.kt = 0.9;
    glass.ior = 1.5;
    let mut chrome = mirror.clone();
    chrome.kr = 0.8;
    s.materials.extend([mirror, glass, chrome]);
    s.render.depth = 5;
    s.objects.extend([
        Object {
            shape: Shape::Plane {
                center: DVec3::new(0.0, 3.0, -14.0),
                normal: DVec3::new(0.0, 0.2, 1.0).normalize(),
                size: 12.0,
                segments: 1,
            },
            material: 1,
        },
        Object {
            shape: Shape::Sphere {
                center: DVec3::new(-1.2, 0.8, 0.0),
                radius: 0.8,
                segments: 32,
            },
            material: 2,
        },
        Object {
            shape: Shape::Sphere {
                center: DVec3::new(1.4, 0.7, -1.0),
                radius: 0.7,
                segments: 32,
            },
            material: 3,
        },
    ]);
    let (worst, compared) = worst_against_reference(&s, Shading::Raytrace);
    assert!(compared > 10000, "{compared} compared");
    assert!(worst < TEXTURE_TOL, "{worst:.2e} from the reference");
}
