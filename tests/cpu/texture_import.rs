//! Image textures as the loaders read them (docs/scene-format.md, "glTF"
//! and the TOML `texture` table): glTF base colour textures from a GLB
//! buffer view, a data URI and a file beside the glTF, PNG and JPEG, their
//! texture coordinate sets, samplers and `KHR_texture_transform`; TOML
//! textures; and every kind of bad input, refused in one line naming the
//! file. The fixtures are `tests/data/make_fixtures.py`'s; the expected
//! texels are the sRGB formula in f64, worked here. The refusals are in
//! `texture_import/refusals.rs`, the TOML table in
//! `texture_import/toml_table.rs`.

mod refusals;
mod toml_table;

use std::path::{Path, PathBuf};
use std::sync::Arc;

use glam::{DVec2, DVec3};
use shadelab::scene::texture::FilterPreset;
use shadelab::scene::{
    load, Filter, ImageTexture, Pattern, Sampler, Scene, SceneError, Shape, Texture, TriangleMesh,
    UvTransform, Wrap,
};

fn data(name: &str) -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("tests/data")
        .join(name)
}

fn scene(path: &Path) -> Scene {
    load(path).unwrap_or_else(|e| panic!("{}: {e}", path.display()))
}

fn err(path: &Path) -> String {
    match load(path) {
        Ok(_) => panic!("{} loaded; expected an error", path.display()),
        Err(e) => e.to_string(),
    }
}

/// The image texture of the material named `name`.
fn image<'s>(scene: &'s Scene, name: &str) -> &'s Arc<ImageTexture> {
    let m = scene
        .materials
        .iter()
        .find(|m| m.name == name)
        .unwrap_or_else(|| panic!("no material {name}: {:?}", names(scene)));
    match &m.pattern {
        Some(Pattern::Image(image)) => image,
        other => panic!("material {name} has {other:?}"),
    }
}

fn names(scene: &Scene) -> Vec<&str> {
    scene.materials.iter().map(|m| m.name.as_str()).collect()
}

fn meshes(scene: &Scene) -> Vec<&TriangleMesh> {
    scene
        .objects
        .iter()
        .map(|o| match &o.shape {
            Shape::Mesh(m) => m,
            other => panic!("{other:?}"),
        })
        .collect()
}

/// The sRGB decoding in f64, from the formula.
fn linear(v: u8) -> f64 {
    let s = f64::from(v) / 255.0;
    if s <= 0.04045 {
        s / 12.92
    } else {
        ((s + 0.055) / 1.055).powf(2.4)
    }
}

fn close(got: [f32; 3], want: [f64; 3], tolerance: f64) {
    for c in 0..3 {
        assert!(
            (f64::from(got[c]) - want[c]).abs() <= tolerance,
            "{got:?} against {want:?}"
        );
    }
}

/// `checker-2x2.png`: red, green; blue, grey 128; and its 1x1 mean.
fn assert_checker(texture: &Texture) {
    let grey = linear(128);
    assert!((grey - 0.215_860_500_113_899).abs() < 1e-12, "{grey}");
    let level = &texture.levels[0];
    assert_eq!((level.width, level.height), (2, 2));
    let want = [
        [1.0, 0.0, 0.0],
        [0.0, 1.0, 0.0],
        [0.0, 0.0, 1.0],
        [grey, grey, grey],
    ];
    for (got, want) in level.texels.iter().zip(want) {
        close(*got, want, 1e-6);
    }
    assert_eq!(texture.levels.len(), 2);
    let mean = (1.0 + grey) / 4.0;
    close(texture.levels[1].texels[0], [mean, mean, mean], 1e-6);
}

/// A unit quad's corners in its own frame: `(x, y)` from its lower left
/// corner, each 0 or 1.
fn quad_corners(mesh: &TriangleMesh) -> Vec<(f64, f64)> {
    let left = mesh
        .positions
        .iter()
        .map(|p| p.x)
        .fold(f64::INFINITY, f64::min);
    mesh.positions.iter().map(|p| (p.x - left, p.y)).collect()
}

/// The quad's TEXCOORD_0: its corners (0,0), (1,0), (1,1), (0,1) in x, y
/// have u, v = (0,1), (1,1), (1,0), (0,0).
fn assert_quad_uvs(mesh: &TriangleMesh) {
    assert_eq!(mesh.uvs.len(), mesh.positions.len());
    for ((x, y), uv) in quad_corners(mesh).into_iter().zip(&mesh.uvs) {
        assert_eq!(*uv, DVec2::new(x, 1.0 - y), "at ({x}, {y})");
    }
}

#[test]
fn a_file_beside_the_gltf_is_its_base_colour_texture() {
    let s = scene(&data("textured_file.gltf"));
    // The missing light's warning alone: nothing about the texture.
    assert_eq!(s.warnings.len(), 1, "{:?}", s.warnings);
    assert!(s.warnings[0].contains("no point light"), "{:?}", s.warnings);
    let m = &s.materials[0];
    assert_eq!(
        m.color,
        DVec3::new(0.5, 1.0, 1.0),
        "baseColorFactor stays the colour"
    );
    let t = image(&s, "textured_file/painted");
    assert_checker(&t.texture);
    assert!(t.name.contains("checker-2x2.png"), "{}", t.name);
    // No sampler: glTF's defaults as shadelab reads them.
    assert_eq!(t.sampler, Sampler::GLTF_DEFAULT);
    assert_eq!(
        t.sampler,
        Sampler {
            wrap_u: Wrap::Repeat,
            wrap_v: Wrap::Repeat,
            magnification: Filter::Linear,
            minification: Filter::Linear,
            mipmap: Some(Filter::Linear),
        }
    );
    assert_eq!(t.transform, UvTransform::IDENTITY);
    assert_quad_uvs(meshes(&s)[0]);
}

#[test]
fn a_glb_buffer_view_is_read_with_its_sampler() {
    let s = scene(&data("textured.glb"));
    let t = image(&s, "textured/painted");
    assert_checker(&t.texture);
    // LINEAR, NEAREST_MIPMAP_NEAREST, REPEAT, CLAMP_TO_EDGE.
    assert_eq!(
        t.sampler,
        Sampler {
            wrap_u: Wrap::Repeat,
            wrap_v: Wrap::ClampToEdge,
            magnification: Filter::Linear,
            minification: Filter::Nearest,
            mipmap: Some(Filter::Nearest),
        }
    );
    assert_quad_uvs(meshes(&s)[0]);
}

/// The data URI's fixture has `KHR_texture_transform` with offset
/// (0.5, -0.25), rotation 0.5 and scale (2, 3): `uv' = T R S uv` with
/// `R = [cos r, sin r; -sin r, cos r]`, worked out by hand:
/// cos 0.5 = 0.8775825618903728, sin 0.5 = 0.479425538604203.
#[test]
fn a_data_uri_is_read_with_its_sampler_and_texture_transform() {
    let s = scene(&data("textured_datauri.gltf"));
    let t = image(&s, "textured_datauri/painted");
    assert_checker(&t.texture);
    assert_eq!(
        t.name,
        format!(
            "{} image 0 (`checker`)",
            data("textured_datauri.gltf").display()
        )
    );
    // NEAREST, NEAREST_MIPMAP_LINEAR, CLAMP_TO_EDGE, MIRRORED_REPEAT.
    assert_eq!(
        t.sampler,
        Sampler {
            wrap_u: Wrap::ClampToEdge,
            wrap_v: Wrap::MirroredRepeat,
            magnification: Filter::Nearest,
            minification: Filter::Nearest,
            mipmap: Some(Filter::Linear),
        }
    );
    let want = [
        2.0 * 0.877_582_561_890_372_8,
        3.0 * 0.479_425_538_604_203,
        0.5,
        -2.0 * 0.479_425_538_604_203,
        3.0 * 0.877_582_561_890_372_8,
        -0.25,
    ];
    for (got, want) in t.transform.0.iter().zip(want) {
        assert!((got - want).abs() < 1e-15, "{:?}", t.transform);
    }
}

/// The fixture `name` with `patch` applied, written to `dir` as
/// `scene.gltf` (its materials then named `scene/...`).
fn patched(name: &str, dir: &Path, patch: impl FnOnce(&mut serde_json::Value)) -> PathBuf {
    let text = std::fs::read_to_string(data(name)).unwrap();
    let mut doc: serde_json::Value = serde_json::from_str(&text).unwrap();
    patch(&mut doc);
    let path = dir.join("scene.gltf");
    std::fs::write(&path, doc.to_string()).unwrap();
    path
}

fn transform_of(patch: serde_json::Value) -> UvTransform {
    let dir = tempfile::tempdir().unwrap();
    let p = patched("textured_datauri.gltf", dir.path(), |d| {
        d["materials"][0]["pbrMetallicRoughness"]["baseColorTexture"]["extensions"]
            ["KHR_texture_transform"] = patch;
    });
    image(&scene(&p), "scene/painted").transform
}

#[test]
fn texture_transforms_match_hand_worked_matrices() {
    use serde_json::json;
    assert_eq!(transform_of(json!({})), UvTransform::IDENTITY);
    assert_eq!(
        transform_of(json!({"offset": [0.25, 0.75]})),
        UvTransform([1.0, 0.0, 0.25, 0.0, 1.0, 0.75])
    );
    assert_eq!(
        transform_of(json!({"scale": [2, -1]})),
        UvTransform([2.0, 0.0, 0.0, 0.0, -1.0, 0.0])
    );
    // The extension's example: the lower left quadrant of the image,
    // turned 90 degrees clockwise. Corners map (0,0) -> (0,1),
    // (1,0) -> (0,0.5), (0,1) -> (0.5,1), (1,1) -> (0.5,0.5).
    let t = transform_of(
        json!({"offset": [0, 1], "rotation": std::f64::consts::FRAC_PI_2, "scale": [0.5, 0.5]}),
    );
    for ((u, v), want) in [
        ((0.0, 0.0), (0.0, 1.0)),
        ((1.0, 0.0), (0.0, 0.5)),
        ((0.0, 1.0), (0.5, 1.0)),
        ((1.0, 1.0), (0.5, 0.5)),
    ] {
        let got = t.apply(u, v);
        assert!(
            (got.0 - want.0).abs() < 1e-15 && (got.1 - want.1).abs() < 1e-15,
            "({u}, {v}) -> {got:?}, expected {want:?}"
        );
    }
    // A pure rotation by 30 degrees: [cos, sin; -sin, cos].
    let r = 30f64.to_radians();
    let t = transform_of(json!({"rotation": r}));
    let (s, c) = (0.5, 0.75f64.sqrt());
    for (got, want) in t.0.iter().zip([c, s, 0.0, -s, c, 0.0]) {
        assert!((got - want).abs() < 1e-15, "{t:?}");
    }
}

/// Every sampler value glTF defines, and each absent.
#[test]
fn every_sampler_value_maps_and_absent_ones_take_the_defaults() {
    use serde_json::json;
    let sampler_of = |sampler: serde_json::Value| {
        let dir = tempfile::tempdir().unwrap();
        let p = patched("textured_datauri.gltf", dir.path(), |d| {
            d["samplers"][0] = sampler;
        });
        image(&scene(&p), "scene/painted").sampler
    };
    let d = Sampler::GLTF_DEFAULT;
    assert_eq!(sampler_of(json!({})), d);
    for (code, filter) in [(9728, Filter::Nearest), (9729, Filter::Linear)] {
        let s = sampler_of(json!({ "magFilter": code }));
        assert_eq!(
            s,
            Sampler {
                magnification: filter,
                ..d
            }
        );
    }
    for (code, minification, mipmap) in [
        (9728, Filter::Nearest, None),
        (9729, Filter::Linear, None),
        (9984, Filter::Nearest, Some(Filter::Nearest)),
        (9985, Filter::Linear, Some(Filter::Nearest)),
        (9986, Filter::Nearest, Some(Filter::Linear)),
        (9987, Filter::Linear, Some(Filter::Linear)),
    ] {
        let s = sampler_of(json!({ "minFilter": code }));
        assert_eq!(
            s,
            Sampler {
                minification,
                mipmap,
                ..d
            },
            "minFilter {code}"
        );
    }
    for (code, wrap) in [
        (10497, Wrap::Repeat),
        (33071, Wrap::ClampToEdge),
        (33648, Wrap::MirroredRepeat),
    ] {
        let s = sampler_of(json!({ "wrapS": code }));
        assert_eq!(s, Sampler { wrap_u: wrap, ..d }, "wrapS {code}");
        let s = sampler_of(json!({ "wrapT": code }));
        assert_eq!(s, Sampler { wrap_v: wrap, ..d }, "wrapT {code}");
    }
    // A texture without a sampler: the same defaults.
    let dir = tempfile::tempdir().unwrap();
    let p = patched("textured_datauri.gltf", dir.path(), |d| {
        d["textures"][0].as_object_mut().unwrap().remove("sampler");
    });
    assert_eq!(image(&scene(&p), "scene/painted").sampler, d);
}

/// `texCoord` 1, and `KHR_texture_transform`'s `texCoord` overriding 0,
/// read TEXCOORD_1 (normalised bytes: the quad mirrored left to right);
/// `texCoord` 0 reads TEXCOORD_0. One image, one sampler, one transform:
/// one shared texture.
#[test]
fn texture_coordinate_sets_are_read_as_the_texture_names_them() {
    let s = scene(&data("textured_texcoord1.gltf"));
    let m = meshes(&s);
    assert_eq!(m.len(), 3);
    for (mesh, set) in m.iter().zip([1, 1, 0]) {
        assert_eq!(mesh.uvs.len(), 4);
        for ((x, y), uv) in quad_corners(mesh).into_iter().zip(&mesh.uvs) {
            let u = if set == 1 { 1.0 - x } else { x };
            assert_eq!(*uv, DVec2::new(u, 1.0 - y), "set {set} at ({x}, {y})");
        }
    }
    let [a, b, c] =
        ["set1", "transformed", "set0"].map(|n| image(&s, &format!("textured_texcoord1/{n}")));
    assert!(
        Arc::ptr_eq(a, c),
        "same image, sampler and transform: one texture"
    );
    assert!(
        Arc::ptr_eq(a, b),
        "a transform with only texCoord is the identity"
    );
    assert_eq!(b.transform, UvTransform::IDENTITY);
}

#[test]
fn the_textured_box_has_its_faces_and_two_colours() {
    let s = scene(&data("box-textured.gltf"));
    let m = meshes(&s);
    assert_eq!((m[0].positions.len(), m[0].triangles.len()), (24, 12));
    let corners = [(0.0, 1.0), (1.0, 1.0), (1.0, 0.0), (0.0, 0.0)];
    for (i, uv) in m[0].uvs.iter().enumerate() {
        assert_eq!(*uv, DVec2::new(corners[i % 4].0, corners[i % 4].1));
    }
    let t = image(&s, "box-textured/box");
    let level = &t.texture.levels[0];
    assert_eq!(
        (level.width, level.height, t.texture.levels.len()),
        (8, 8, 4)
    );
    let orange = [linear(230), linear(120), linear(30)];
    let cream = [linear(250), linear(240), linear(210)];
    for j in 0..8 {
        for i in 0..8 {
            let want = if (i / 2 + j / 2) % 2 == 0 {
                orange
            } else {
                cream
            };
            close(level.texel(i, j), want, 1e-6);
        }
    }
    assert_eq!(t.sampler, Sampler::GLTF_DEFAULT);
}

/// A JPEG beside the glTF: a flat colour survives JPEG's coding to within
/// a level or two of 255.
#[test]
fn a_jpeg_is_read() {
    let dir = tempfile::tempdir().unwrap();
    let pixels: Vec<u8> = [200u8, 100, 50].repeat(16 * 16);
    let mut jpeg = Vec::new();
    image::codecs::jpeg::JpegEncoder::new_with_quality(&mut jpeg, 95)
        .encode(&pixels, 16, 16, image::ExtendedColorType::Rgb8)
        .unwrap();
    std::fs::write(dir.path().join("flat.jpg"), &jpeg).unwrap();
    let p = patched("textured_file.gltf", dir.path(), |d| {
        d["images"][0]["uri"] = "flat.jpg".into();
    });
    let s = scene(&p);
    let level = &image(&s, "scene/painted").texture.levels[0];
    assert_eq!((level.width, level.height), (16, 16));
    for texel in &level.texels {
        // Two sRGB levels at 200 are about 0.012 in linear.
        close(*texel, [linear(200), linear(100), linear(50)], 0.012);
    }
}

/// One warning per image whose alpha is not all opaque, however many
/// materials use it.
#[test]
fn an_image_with_alpha_is_announced_once() {
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(
        dir.path().join("half.png"),
        png(&[[10, 20, 30, 128], [10, 20, 30, 255]], 2, 1),
    )
    .unwrap();
    let p = patched("textured_texcoord1.gltf", dir.path(), |d| {
        d["images"][0]["uri"] = "half.png".into();
    });
    let s = scene(&p);
    let alpha: Vec<&String> = s.warnings.iter().filter(|w| w.contains("alpha")).collect();
    assert_eq!(alpha.len(), 1, "{:?}", s.warnings);
    assert!(
        alpha[0].contains("image 0 (`half.png`) has alpha below 1 (not all opaque)"),
        "{}",
        alpha[0]
    );
    close(
        image(&s, "scene/set0").texture.levels[0].texels[0],
        [linear(10), linear(20), linear(30)],
        1e-6,
    );
}

/// An 8-bit RGBA PNG of `pixels`, `width` x `height`, with the `png` crate.
fn png(pixels: &[[u8; 4]], width: u32, height: u32) -> Vec<u8> {
    let mut out = Vec::new();
    let mut encoder = png::Encoder::new(&mut out, width, height);
    encoder.set_color(png::ColorType::Rgba);
    encoder.set_depth(png::BitDepth::Eight);
    let mut writer = encoder.write_header().unwrap();
    writer.write_image_data(pixels.as_flattened()).unwrap();
    writer.finish().unwrap();
    out
}

fn crc32(bytes: &[u8]) -> u32 {
    let mut c = 0xFFFF_FFFFu32;
    for &b in bytes {
        c ^= u32::from(b);
        for _ in 0..8 {
            c = if c & 1 != 0 {
                0xEDB8_8320 ^ (c >> 1)
            } else {
                c >> 1
            };
        }
    }
    !c
}

#[test]
fn the_crc_is_the_pngs() {
    // The CRC of "IEND" with no data, as every PNG ends.
    assert_eq!(crc32(b"IEND"), 0xAE42_6082);
}
