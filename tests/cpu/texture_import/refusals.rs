//! Bad textures refused: a decompression bomb by its estimate, texture
//! bytes counted against the memory limit with the geometry, and every
//! bad image or sampler in one line naming the file, from the loader and
//! from the command line.

use shadelab::scene::image_file::MAX_TEXTURE_SIDE;
use shadelab::scene::{load_within, LoadLimits};

use super::*;
use crate::common;

/// A decompression bomb's shape: a valid PNG header declaring `side` x
/// `side` RGBA pixels, with a few bytes of data (an empty zlib stream).
fn bomb(side: u32) -> Vec<u8> {
    let chunk = |tag: &[u8; 4], data: &[u8]| {
        let mut c = (data.len() as u32).to_be_bytes().to_vec();
        let body = [&tag[..], data].concat();
        c.extend_from_slice(&body);
        c.extend_from_slice(&crc32(&body).to_be_bytes());
        c
    };
    let mut ihdr = side.to_be_bytes().to_vec();
    ihdr.extend_from_slice(&side.to_be_bytes());
    ihdr.extend_from_slice(&[8, 6, 0, 0, 0]);
    [
        &b"\x89PNG\r\n\x1a\n"[..],
        &chunk(b"IHDR", &ihdr),
        &chunk(b"IDAT", &[0x78, 0x9c, 0x03, 0x00, 0x00, 0x00, 0x00, 0x01]),
        &chunk(b"IEND", &[]),
    ]
    .concat()
}

fn limit(bytes: u64) -> LoadLimits {
    LoadLimits {
        max_bytes: bytes,
        source: "--max-memory in the test".into(),
    }
}

/// A small file declaring 60000 x 60000 pixels is refused by the estimate
/// from its header, before anything is decoded: the process's peak memory
/// does not grow by the 14 GB it would decode to.
#[test]
fn a_decompression_bomb_is_refused_by_the_estimate() {
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(dir.path().join("bomb.png"), bomb(60000)).unwrap();
    let p = patched("textured_file.gltf", dir.path(), |d| {
        d["images"][0]["uri"] = "bomb.png".into();
    });
    let before = shadelab::memory::peak_resident_bytes();
    let e = load_within(&p, &limit(8 << 30)).unwrap_err();
    assert!(matches!(e, SceneError::TooLarge { .. }), "{e:?}");
    let e = e.to_string();
    for part in [
        "scene.gltf: image 0 (`bomb.png`) (the base colour texture of material `painted`) is 60000 x 60000 pixels",
        "over the memory limit of 8.0 GiB (--max-memory in the test)",
        "--max-memory or SHADELAB_MAX_MEMORY",
    ] {
        assert!(e.contains(part), "{e}\nshould say: {part}");
    }
    assert!(!e.contains('\n'), "{e}");
    if let (Some(before), Some(after)) = (before, shadelab::memory::peak_resident_bytes()) {
        assert!(
            after - before < 512 << 20,
            "peak grew from {before} to {after}"
        );
    }
    // Without a limit the side is still bounded.
    let e = err(&p);
    assert!(
        e.contains(&format!(
            "is 60000 x 60000 pixels; expected at most {MAX_TEXTURE_SIDE} along each side"
        )),
        "{e}"
    );
    // And in a TOML scene's texture table.
    let toml = dir.path().join("t.toml");
    std::fs::write(
        &toml,
        "[camera]\nposition = [0, 0, 5]\nlook_at = [0, 0, 0]\n[materials.floor]\ntexture = { file = \"bomb.png\" }\n",
    )
    .unwrap();
    let e = load_within(&toml, &limit(1 << 30)).unwrap_err().to_string();
    assert!(
        e.contains(
            "t.toml: line 5: `materials.floor.texture.file`: `bomb.png` is 60000 x 60000 pixels"
        ),
        "{e}"
    );
}

/// The textures count with the geometry against the limit: a limit that
/// holds the quad alone, not its texture, refuses the file.
#[test]
fn texture_bytes_count_against_the_limit_with_the_geometry() {
    let p = data("textured_file.gltf");
    // 2x2 and 1x1 texels, TEXEL_COPIES copies of 12 bytes; the file's
    // bytes, 16 decoded, 16 as RGBA.
    let file = std::fs::metadata(data("checker-2x2.png")).unwrap().len();
    let copies = shadelab::scene::footprint::TEXEL_COPIES;
    let texture = copies * 12 * 5 + file + 16 + 16;
    let geometry = {
        let mut size = shadelab::scene::GeometrySize::default();
        size.add(1, 4, 2);
        size.add_attributed(4, 2);
        size.model_bytes()
    };
    assert!(load_within(&p, &limit(geometry + texture)).is_ok());
    let e = load_within(&p, &limit(geometry + texture - 1)).unwrap_err();
    assert!(matches!(e, SceneError::TooLarge { .. }), "{e:?}");
    assert!(e.to_string().contains("is 2 x 2 pixels"), "{e}");
    let s = scene(&p);
    assert_eq!(shadelab::scene::footprint::scene_texture_bytes(&s), 12 * 5);
}

/// A change to a glTF document (and the folder beside it).
type Patch = Box<dyn FnOnce(&mut serde_json::Value, &Path)>;

/// Each bad image or sampler, with what its refusal must say.
fn bad_inputs() -> Vec<(&'static str, Patch)> {
    use serde_json::json;
    let image_uri = |uri: &str| -> Patch {
        let uri = uri.to_string();
        Box::new(move |d, _| d["images"][0]["uri"] = uri.into())
    };
    let file = |name: &'static str, bytes: Vec<u8>| -> Patch {
        Box::new(move |d, dir| {
            std::fs::write(dir.join(name), bytes).unwrap();
            d["images"][0]["uri"] = name.into();
        })
    };
    let sampler = |key: &'static str, value: serde_json::Value| -> Patch {
        Box::new(move |d, _| d["samplers"][0][key] = value)
    };
    let whole = png(&[[1, 2, 3, 255]; 4], 2, 2);
    vec![
        (
            "image 0 (`absent.png`) names the file `absent.png`, which cannot be read (",
            image_uri("absent.png"),
        ),
        (
            "image 0 (`text.png`) (the base colour texture of material `painted`) is not a PNG or JPEG image",
            file("text.png", b"just some text, no image".to_vec()),
        ),
        (
            "image 0 (`cut.png`) (the base colour texture of material `painted`) cannot be decoded (",
            file("cut.png", whole[..whole.len() - 20].to_vec()),
        ),
        (
            "image 0 (`bad-header.png`) (the base colour texture of material `painted`) cannot be decoded (",
            file("bad-header.png", {
                let mut b = whole.clone();
                b[20] ^= 0xFF; // inside IHDR: its CRC no longer holds
                b
            }),
        ),
        (
            "(the base colour texture of material `painted`) is a Gif image; expected a PNG or JPEG image",
            file("anim.gif", b"GIF89a\x01\x00\x01\x00\x00\x00\x00;".to_vec()),
        ),
        (
            "image 0 (`checker`) is a data URI that is not valid base64 (",
            image_uri("data:image/png;base64,iVBORw0KGgo*!*"),
        ),
        (
            "image 0 (`checker`) is a data URI that is not base64 (`data:image/png`)",
            image_uri("data:image/png,rawbytes"),
        ),
        (
            "image 0: its uri `https://example.com/x.png` is neither a file beside the glTF nor a data: URI",
            image_uri("https://example.com/x.png"),
        ),
        (
            "has no texture coordinates (TEXCOORD_2), which the base colour texture of material `painted` needs",
            Box::new(|d, _| {
                d["materials"][0]["pbrMetallicRoughness"]["baseColorTexture"]["texCoord"] = 2.into()
            }),
        ),
        (
            "sampler 0: wrapS is 1234, which glTF does not define; expected one of 33071 (CLAMP_TO_EDGE), 33648 (MIRRORED_REPEAT), 10497 (REPEAT)",
            sampler("wrapS", json!(1234)),
        ),
        (
            // 2^32 + 10497: the gltf crate truncates it to REPEAT.
            "sampler 0: wrapT is 4294977793, which glTF does not define",
            sampler("wrapT", json!(4_294_977_793u64)),
        ),
        (
            "sampler 0: magFilter is 9987, which glTF does not define; expected one of 9728 (NEAREST), 9729 (LINEAR)",
            sampler("magFilter", json!(9987)),
        ),
        (
            "sampler 0: minFilter is \"LINEAR\", which glTF does not define",
            sampler("minFilter", json!("LINEAR")),
        ),
        (
            "sampler 0: minFilter is 9729.5, which glTF does not define",
            sampler("minFilter", json!(9729.5)),
        ),
        (
            "image 0 is in a buffer view but has no mimeType",
            Box::new(|d, _| d["images"][0] = json!({"bufferView": 0})),
        ),
        (
            "image 0 has neither a uri nor a bufferView",
            Box::new(|d, _| d["images"][0] = json!({"name": "nothing"})),
        ),
        (
            "texture 0 has no source image (only through EXT_texture_webp, which shadelab does not read)",
            Box::new(|d, _| d["textures"][0] = json!({"extensions": {"EXT_texture_webp": {"source": 0}}})),
        ),
    ]
}

/// Each bad input: one line naming the file and what is wrong.
#[test]
fn bad_images_and_samplers_are_refused_naming_the_file() {
    for (want, patch) in bad_inputs() {
        let dir = tempfile::tempdir().unwrap();
        let p = patched("textured_datauri.gltf", dir.path(), |d| {
            patch(d, dir.path())
        });
        let e = err(&p);
        assert!(e.contains(want), "{e}\nshould say: {want}");
        assert!(e.starts_with(&format!("{}: ", p.display())), "{e}");
        assert!(!e.contains('\n'), "{e}");
    }
}

/// From the command line: exit status 2, one line naming the file,
/// nothing written.
#[test]
fn the_command_line_refuses_a_bad_texture_with_exit_2() {
    let dir = tempfile::tempdir().unwrap();
    let p = patched("textured_file.gltf", dir.path(), |d| {
        d["images"][0]["uri"] = "missing.png".into();
    });
    let run = common::cli::shadelab(
        dir.path(),
        &[
            "render",
            p.to_str().unwrap(),
            "--backend",
            "cpu",
            "--out",
            "out.png",
        ],
    );
    assert_eq!(run.code, 2, "{}", run.stderr);
    let lines: Vec<&str> = run.stderr.lines().collect();
    assert_eq!(lines.len(), 1, "{}", run.stderr);
    assert!(
        lines[0].contains("scene.gltf: image 0 (`missing.png`) names the file `missing.png`"),
        "{}",
        lines[0]
    );
    assert!(!dir.path().join("out.png").exists());
}
