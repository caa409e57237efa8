//! Which way an image reads on a plane and on a box's six faces
//! (docs/scene-format.md, "Which way an image reads"): a 4 x 4 PNG with a
//! colour per texel, loaded from a TOML scene as a user writes it, seen
//! from outside each face by a camera whose up is the rule's (world up on
//! walls; -Z looking down at a floor, +Z looking up at a ceiling). Read as
//! in an image viewer, texel `(i, j)` (column, row from the top) lies at
//! the `(i, j)` cell of the face's picture: that is the oracle, worked out
//! here by hand, and each of the four GPU modes and the CPU reference must
//! show it. The texture's `rotation` is checked the same way.

use crate::common;

use std::path::Path;

use crate::common::render_cpu;
use common::*;
use glam::DVec3;
use shadelab::scene::{load, Scene};
use shadelab::shading::Shading;
use shadelab::LinearImage;

const SIDE: u32 = 64;
/// Texels per side of the test image.
const TEXELS: u32 = 4;

/// Texel `(i, j)`'s sRGB bytes: red by column, green by row, so every
/// texel differs from every other by 60 steps in one channel at least.
fn texel_srgb(i: u32, j: u32) -> [u8; 3] {
    [(30 + 60 * i) as u8, (30 + 60 * j) as u8, 128]
}

fn texel_linear(i: u32, j: u32) -> DVec3 {
    let f = |c: u8| {
        let c = f64::from(c) / 255.0;
        if c <= 0.04045 {
            c / 12.92
        } else {
            ((c + 0.055) / 1.055).powf(2.4)
        }
    };
    let [r, g, b] = texel_srgb(i, j);
    DVec3::new(f(r), f(g), f(b))
}

fn write_texture(dir: &Path) {
    let mut img = image::RgbImage::new(TEXELS, TEXELS);
    for j in 0..TEXELS {
        for i in 0..TEXELS {
            img.put_pixel(i, j, image::Rgb(texel_srgb(i, j)));
        }
    }
    img.save(dir.join("texels.png")).expect("the test texture");
}

/// A scene of `object` under a material that shows the texture's colour
/// exactly (ambient 1, ka 1, no light), seen from `eye` toward the origin
/// with `up`.
fn scene_toml(eye: [f64; 3], up: [f64; 3], object: &str, texture_extra: &str) -> String {
    format!(
        "[camera]\nposition = {eye:?}\nlook_at = [0.0, 0.0, 0.0]\nup = {up:?}\nfov_y = 40.0\n\
         [image]\nwidth = {SIDE}\nheight = {SIDE}\nbackground = [0.0, 0.0, 0.0]\n\
         [lighting]\nambient = 1.0\n\
         [materials.m]\nka = 1.0\nkd = 0.0\nks = 0.0\n\
         texture = {{ file = \"texels.png\", filter = \"nearest\"{texture_extra} }}\n\
         [[objects]]\n{object}material = \"m\"\n"
    )
}

fn load_scene(dir: &Path, toml: &str) -> Scene {
    let path = dir.join("scene.toml");
    std::fs::write(&path, toml).unwrap();
    load(&path).unwrap_or_else(|e| panic!("{e}"))
}

/// The pixel at the middle of cell `(i, j)` of a square face of half-edge
/// `half`, seen face on from `distance` (its centre at the image's centre):
/// cell `(0, 0)` is the picture's top left.
fn cell_pixel(i: u32, j: u32, half: f64, distance: f64) -> (u32, u32) {
    let tan = 20f64.to_radians().tan();
    let to_pixel = |a: f64| {
        // a in [-1, 1] across the face, left to right or top to bottom.
        let ndc = a * half / (distance * tan);
        ((ndc + 1.0) * 0.5 * f64::from(SIDE)).floor() as u32
    };
    let centre = |k: u32| (f64::from(k) + 0.5) / f64::from(TEXELS) * 2.0 - 1.0;
    (to_pixel(centre(i)), to_pixel(centre(j)))
}

/// The texel `image` shows at `(x, y)`: the one whose colour it is within
/// 1e-3 (the GPU's f32), or a message naming the nearest.
fn texel_at(image: &LinearImage, x: u32, y: u32) -> Result<(u32, u32), String> {
    let got = to_dvec(image.get(x, y));
    let mut best = (u32::MAX, u32::MAX, f64::INFINITY);
    for j in 0..TEXELS {
        for i in 0..TEXELS {
            let d = max_abs_diff(got, texel_linear(i, j));
            if d < best.2 {
                best = (i, j, d);
            }
        }
    }
    if best.2 <= 1e-3 {
        Ok((best.0, best.1))
    } else {
        Err(format!(
            "{got} is no texel (nearest ({}, {}), {:.2e} off)",
            best.0, best.1, best.2
        ))
    }
}

const MODES: [Shading; 4] = [
    Shading::Flat,
    Shading::Gouraud,
    Shading::Phong,
    Shading::Raytrace,
];

/// Every GPU mode's image and the CPU reference's, named.
fn renders(scene: &Scene) -> Vec<(String, LinearImage)> {
    let context = gpu();
    let mut out = Vec::new();
    for mode in MODES {
        out.push((format!("gpu {mode:?}"), render(&context, scene, mode)));
        let (cpu, _) = render_cpu(scene, mode).expect("the CPU reference renders");
        out.push((format!("cpu {mode:?}"), cpu.image));
    }
    out
}

/// Checks that each render shows `want(i, j)` at cell `(i, j)` of the face
/// (`None`: a cell not checked in that render).
fn assert_cells(
    what: &str,
    images: &[(String, LinearImage)],
    half: f64,
    distance: f64,
    want: impl Fn(&str, u32, u32) -> Option<(u32, u32)>,
) {
    let mut failures = Vec::new();
    for (name, image) in images {
        for j in 0..TEXELS {
            for i in 0..TEXELS {
                let Some(expected) = want(name, i, j) else {
                    continue;
                };
                let (x, y) = cell_pixel(i, j, half, distance);
                match texel_at(image, x, y) {
                    Ok(got) if got == expected => {}
                    Ok(got) => failures.push(format!(
                        "{what}, {name}: cell ({i}, {j}) at pixel ({x}, {y}) shows texel {got:?}, expected {expected:?}"
                    )),
                    Err(e) => failures.push(format!("{what}, {name}: cell ({i}, {j}) at pixel ({x}, {y}): {e}")),
                }
            }
        }
    }
    assert!(failures.is_empty(), "{}", failures.join("\n"));
}

/// A plane facing the camera, cut into 8 x 8 cells so that flat shading
/// (one texel per triangle, at its centroid) lands in the cell's texel
/// too: each texel shows where an image viewer shows it.
#[test]
fn an_image_on_a_plane_facing_the_viewer_reads_as_in_an_image_viewer() {
    let dir = tempfile::tempdir().unwrap();
    write_texture(dir.path());
    let plane = "shape = \"plane\"\ncenter = [0.0, 0.0, 0.0]\nnormal = [0.0, 0.0, 1.0]\nsize = 2.0\nsegments = 8\n";
    let scene = load_scene(
        dir.path(),
        &scene_toml([0.0, 0.0, 5.0], [0.0, 1.0, 0.0], plane, ""),
    );
    assert_cells("plane", &renders(&scene), 1.0, 5.0, |_, i, j| Some((i, j)));
}

/// `rotation = 90` turns the image a quarter turn counter-clockwise: its
/// top right texel `(3, 0)` comes to the top left, and cell `(i, j)`
/// shows texel `(3 - j, i)`, worked out by hand.
#[test]
fn a_quarter_turn_brings_the_top_right_texel_to_the_top_left() {
    let dir = tempfile::tempdir().unwrap();
    write_texture(dir.path());
    let plane = "shape = \"plane\"\ncenter = [0.0, 0.0, 0.0]\nnormal = [0.0, 0.0, 1.0]\nsize = 2.0\nsegments = 8\n";
    let toml = scene_toml([0.0, 0.0, 5.0], [0.0, 1.0, 0.0], plane, ", rotation = 90");
    let scene = load_scene(dir.path(), &toml);
    assert_cells("plane turned 90", &renders(&scene), 1.0, 5.0, |_, i, j| {
        Some((3 - j, i))
    });
    // Half a turn: cell (i, j) shows (3 - i, 3 - j); -270 is 90.
    let toml = scene_toml([0.0, 0.0, 5.0], [0.0, 1.0, 0.0], plane, ", rotation = -270");
    let quarter = load_scene(dir.path(), &toml);
    assert_eq!(quarter.materials, scene.materials);
    let toml = scene_toml([0.0, 0.0, 5.0], [0.0, 1.0, 0.0], plane, ", rotation = 180");
    let half = load_scene(dir.path(), &toml);
    let context = gpu();
    let phong = [(
        "gpu Phong".to_string(),
        render(&context, &half, Shading::Phong),
    )];
    assert_cells("plane turned 180", &phong, 1.0, 5.0, |_, i, j| {
        Some((3 - i, 3 - j))
    });
}

/// A cube of edge 2 seen face on from outside each of its six faces, the
/// camera's up the rule's: each face shows the image as a viewer does. A
/// box face is two triangles, so flat shading shows two texels, each
/// triangle's centroid's: the lower right triangle (cells with
/// `i + j > 3`) texel `(2, 2)`, the upper left (`i + j < 3`) texel
/// `(1, 1)`; the diagonal's cells are not checked.
#[test]
fn every_face_of_a_box_reads_as_in_an_image_viewer_from_outside() {
    let dir = tempfile::tempdir().unwrap();
    write_texture(dir.path());
    let cube = "shape = \"box\"\ncenter = [0.0, 0.0, 0.0]\nsize = 2.0\n";
    let views = [
        ("+Z face", [0.0, 0.0, 5.0], [0.0, 1.0, 0.0]),
        ("-Z face", [0.0, 0.0, -5.0], [0.0, 1.0, 0.0]),
        ("+X face", [5.0, 0.0, 0.0], [0.0, 1.0, 0.0]),
        ("-X face", [-5.0, 0.0, 0.0], [0.0, 1.0, 0.0]),
        ("top face, from above", [0.0, 5.0, 0.0], [0.0, 0.0, -1.0]),
        ("bottom face, from below", [0.0, -5.0, 0.0], [0.0, 0.0, 1.0]),
    ];
    for (what, eye, up) in views {
        let scene = load_scene(dir.path(), &scene_toml(eye, up, cube, ""));
        assert_cells(what, &renders(&scene), 1.0, 4.0, |name, i, j| {
            if !name.contains("Flat") {
                Some((i, j))
            } else if i + j > 3 {
                Some((2, 2))
            } else if i + j < 3 {
                Some((1, 1))
            } else {
                None
            }
        });
    }
}
