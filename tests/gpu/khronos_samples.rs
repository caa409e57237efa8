//! Khronos glTF sample models (tests/data/khronos, with their licences)
//! render in their authors' colours in every mode: BoxTextured's base
//! colour texture and BoxVertexColors' `COLOR_0`, on the GPU and in the
//! reference alike, where before issue 31 both rendered as a grey box.

use crate::common;

use std::path::Path;

use crate::common::render_cpu;
use common::*;
use glam::DVec3;
use shadelab::scene::Scene;
use shadelab::shading::Shading;
use shadelab::LinearImage;

const MODES: [Shading; 4] = [
    Shading::Flat,
    Shading::Gouraud,
    Shading::Phong,
    Shading::Raytrace,
];

fn load(name: &str) -> Scene {
    let mut scene = shadelab::scene::load(&Path::new("tests/data/khronos").join(name)).unwrap();
    scene.image.width = 160;
    scene.image.height = 120;
    scene
}

/// Per pixel of the object, its colour over the untextured (or uncoloured)
/// render's: what the texture or the vertex colours multiplied in (exactly
/// so for the ambient and diffuse terms, diluted where a highlight adds
/// its untinted colour).
fn tint(image: &LinearImage, plain: &LinearImage, on_object: &[bool]) -> Vec<DVec3> {
    image
        .pixels
        .iter()
        .zip(&plain.pixels)
        .zip(on_object)
        .filter(|(_, &on)| on)
        .map(|((a, b), _)| to_dvec(*a) / to_dvec(*b).max(DVec3::splat(1e-3)))
        .collect()
}

/// Renders `scene` in every mode on the GPU and the reference, holds the two
/// to each other, and returns per mode the tints of the object's pixels.
fn render_everywhere(scene: &Scene, plain: &Scene) -> Vec<(Shading, Vec<DVec3>)> {
    let context = gpu();
    MODES
        .iter()
        .map(|&shading| {
            let image = render(&context, scene, shading);
            let untinted = render(&context, plain, shading);
            let (cpu, coverage) = render_cpu(scene, shading).unwrap();
            let mut worst = 0.0f64;
            for (i, (g, c)) in image.pixels.iter().zip(&cpu.image.pixels).enumerate() {
                if !coverage.near_edge[i] {
                    worst = worst.max(max_abs_diff(to_dvec(*g), to_dvec(*c)));
                }
            }
            // As tests/gpu/image_textures.rs: f32 rounding alone.
            assert!(
                worst < FLOAT_TOL,
                "{shading:?}: {worst:.2e} from the reference"
            );
            let on_object: Vec<bool> = (0..image.pixels.len())
                .map(|i| coverage.object_ids[i].is_some() && !coverage.near_edge[i])
                .collect();
            assert!(
                on_object.iter().filter(|&&o| o).count() > 2000,
                "{shading:?}: the box is too small to judge"
            );
            (shading, tint(&image, &untinted, &on_object))
        })
        .collect()
}

/// The texture's own colours, decoded here from the PNG in the file by the
/// `image` crate and the sRGB formula (not the project's decoder): the
/// mean linear colour of its texels.
fn box_textured_mean_texel() -> DVec3 {
    let text = std::fs::read_to_string("tests/data/khronos/BoxTextured.gltf").unwrap();
    let json: serde_json::Value = serde_json::from_str(&text).unwrap();
    let uri = json["images"][0]["uri"].as_str().unwrap();
    let base64 = uri.split_once(',').unwrap().1;
    let bytes = decode_base64(base64);
    let img = image::load_from_memory(&bytes).unwrap().to_rgb8();
    let to_linear = |c: u8| {
        let c = f64::from(c) / 255.0;
        if c <= 0.04045 {
            c / 12.92
        } else {
            ((c + 0.055) / 1.055).powf(2.4)
        }
    };
    let mut sum = DVec3::ZERO;
    for p in img.pixels() {
        sum += DVec3::new(to_linear(p[0]), to_linear(p[1]), to_linear(p[2]));
    }
    sum / f64::from(img.width() * img.height())
}

fn decode_base64(text: &str) -> Vec<u8> {
    let value = |c: u8| match c {
        b'A'..=b'Z' => c - b'A',
        b'a'..=b'z' => c - b'a' + 26,
        b'0'..=b'9' => c - b'0' + 52,
        b'+' => 62,
        b'/' => 63,
        _ => panic!("not base64: {c}"),
    };
    let digits: Vec<u8> = text.bytes().filter(|&c| c != b'=').map(value).collect();
    digits
        .chunks(4)
        .flat_map(|chunk| {
            let n = chunk
                .iter()
                .enumerate()
                .fold(0u32, |n, (i, &d)| n | u32::from(d) << (18 - 6 * i));
            let bytes = [(n >> 16) as u8, (n >> 8) as u8, n as u8];
            bytes.into_iter().take(chunk.len() - 1)
        })
        .collect()
}

#[test]
fn box_textured_shows_its_texture_in_every_mode() {
    let scene = load("BoxTextured.gltf");
    assert!(
        !scene
            .warnings
            .iter()
            .any(|w| w.contains("base colour texture")),
        "{:?}",
        scene.warnings
    );
    let mut plain = scene.clone();
    for m in &mut plain.materials {
        m.pattern = None;
    }
    let texel = box_textured_mean_texel();
    for (shading, tints) in render_everywhere(&scene, &plain) {
        let mean = tints.iter().copied().sum::<DVec3>() / tints.len() as f64;
        // The logo's colours: blue over green over red on average, as in
        // its texels, and at least half as far from grey. (The faces show
        // parts of the texture, not all of it evenly, and a highlight
        // dilutes the tint, so the means themselves differ.)
        assert!(
            texel.z > texel.y && texel.y > texel.x,
            "the texture's mean {texel:.3}"
        );
        assert!(
            mean.z > mean.y && mean.y > mean.x && mean.z - mean.x > 0.5 * (texel.z - texel.x),
            "{shading:?}: mean tint {mean:.3} against the texture's {texel:.3}"
        );
        // Not grey: the texture's blue and green differ by more than 0.1
        // in some pixels (a grey box has a tint of one everywhere).
        let coloured = tints
            .iter()
            .filter(|t| t.max_element() - t.min_element() > 0.1)
            .count();
        assert!(
            coloured * 10 > tints.len(),
            "{shading:?}: {coloured} of {} pixels coloured",
            tints.len()
        );
    }
}

#[test]
fn box_vertex_colors_shows_its_colours_in_every_mode() {
    let mut scene = load("BoxVertexColors.gltf");
    // Seen from a corner: three faces, x = 1, y = 1 and z = 1.
    scene.camera.position = DVec3::new(2.6, 2.2, 3.0);
    scene.camera.look_at = DVec3::splat(0.5);
    scene.lights[0].position = scene.camera.position;
    let mut plain = scene.clone();
    for object in &mut plain.objects {
        if let shadelab::scene::Shape::Mesh(m) = &mut object.shape {
            m.colors.clear();
        }
    }
    for (shading, tints) in render_everywhere(&scene, &plain) {
        // Each vertex's colour is its position in the unit cube: across the
        // visible faces each channel runs from 0 to 1. The
        // tints span most of that range in each channel; flat shading's
        // face colours are means of three corners, so thirds.
        let (below, above) = if shading == Shading::Flat {
            (0.34, 0.66)
        } else {
            (0.3, 0.7)
        };
        for channel in 0..3 {
            let values: Vec<f64> = tints.iter().map(|t| t[channel]).collect();
            let low = values.iter().copied().fold(f64::INFINITY, f64::min);
            let high = values.iter().copied().fold(0.0, f64::max);
            assert!(
                low < below && high > above,
                "{shading:?}: channel {channel} spans only {low:.2} to {high:.2}"
            );
        }
    }
}
