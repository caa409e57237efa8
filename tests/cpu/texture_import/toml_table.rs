//! The TOML `texture` table: its values and defaults, on a glTF mesh's
//! first coordinate set, beside a glTF's own textures, and its errors
//! naming the line and key.

use super::*;

fn toml_scene(dir: &Path, materials: &str, objects: &str) -> PathBuf {
    let text =
        format!("[camera]\nposition = [0, 0, 5]\nlook_at = [0, 0, 0]\n{materials}\n{objects}");
    let path = dir.join("t.toml");
    std::fs::write(&path, text).unwrap();
    path
}

#[test]
fn a_toml_texture_takes_its_values_and_defaults() {
    let dir = tempfile::tempdir().unwrap();
    std::fs::copy(data("checker-2x2.png"), dir.path().join("floor.png")).unwrap();
    let p = toml_scene(
        dir.path(),
        "[materials.plain]\ntexture = { file = \"floor.png\" }\n\
         [materials.set]\ncolor = [0.5, 0.5, 0.5]\ntexture = { file = \"floor.png\", scale = 4, wrap = \"mirror\", filter = \"nearest\" }\n\
         [materials.clamped]\ntexture = { file = \"./floor.png\", wrap = \"clamp\", filter = \"bilinear\" }\n\
         [materials.again]\ntexture = { file = \"floor.png\", scale = 1.0, wrap = \"repeat\", filter = \"trilinear\" }\n",
        "",
    );
    let s = scene(&p);
    assert!(s.warnings.is_empty(), "{:?}", s.warnings);
    let plain = image(&s, "plain");
    assert_checker(&plain.texture);
    assert_eq!(plain.name, "floor.png");
    assert_eq!(plain.sampler, Sampler::GLTF_DEFAULT, "repeat, trilinear");
    assert_eq!(plain.transform, UvTransform::IDENTITY);
    let set = image(&s, "set");
    assert_eq!(set.transform, UvTransform([4.0, 0.0, 0.0, 0.0, 4.0, 0.0]));
    assert_eq!(
        set.sampler,
        Sampler {
            wrap_u: Wrap::MirroredRepeat,
            wrap_v: Wrap::MirroredRepeat,
            magnification: Filter::Nearest,
            minification: Filter::Nearest,
            mipmap: None,
        }
    );
    let clamped = image(&s, "clamped");
    assert_eq!(
        clamped.sampler,
        FilterPreset::Bilinear.sampler(Wrap::ClampToEdge)
    );
    assert_eq!(clamped.sampler.mipmap, None);
    assert_eq!(clamped.sampler.minification, Filter::Linear);
    // The same file under the same settings (spelt out) is one texture;
    // `./floor.png` is the same file.
    assert!(Arc::ptr_eq(plain, image(&s, "again")));
    assert_eq!(clamped.texture, plain.texture);
}

/// A TOML material with a texture given to a glTF mesh reads its
/// TEXCOORD_0, whatever the file's own materials read.
#[test]
fn a_toml_texture_on_a_gltf_mesh_reads_texcoord_0() {
    let dir = tempfile::tempdir().unwrap();
    std::fs::copy(data("checker-2x2.png"), dir.path().join("floor.png")).unwrap();
    let p = toml_scene(
        dir.path(),
        "[materials.m]\ntexture = { file = \"floor.png\" }\n",
        &format!(
            "[[objects]]\nshape = \"mesh\"\nfile = \"{}\"\nmaterial = \"m\"\n",
            data("textured_texcoord1.gltf").display()
        ),
    );
    let s = scene(&p);
    assert_eq!(s.materials.len(), 1, "{:?}", names(&s));
    for mesh in meshes(&s) {
        assert_quad_uvs(mesh);
    }
    // Without TEXCOORD_0, the message names the texture's material.
    let p = toml_scene(
        dir.path(),
        "[materials.m]\ntexture = { file = \"floor.png\" }\n",
        &format!(
            "[[objects]]\nshape = \"mesh\"\nfile = \"{}\"\nmaterial = \"m\"\n",
            data("cube.glb").display()
        ),
    );
    let e = err(&p);
    assert!(
        e.contains(
            "has no texture coordinates (TEXCOORD_0), which the texture of material `m` needs"
        ),
        "{e}"
    );
}

/// A TOML scene's mesh file brings its own textures, shared with the
/// TOML's where they are the same file.
#[test]
fn a_gltf_in_a_toml_scene_brings_its_textures() {
    let dir = tempfile::tempdir().unwrap();
    let p = toml_scene(
        dir.path(),
        &format!(
            "[materials.m]\ntexture = {{ file = \"{}\" }}\n",
            data("checker-2x2.png").display()
        ),
        &format!(
            "[[objects]]\nshape = \"mesh\"\nfile = \"{}\"\n",
            data("textured_file.gltf").display()
        ),
    );
    let s = scene(&p);
    let toml = image(&s, "m");
    let gltf = image(&s, "textured_file/painted");
    assert!(
        Arc::ptr_eq(toml, gltf),
        "the same file, sampler and transform"
    );
}

#[test]
fn toml_texture_errors_name_the_line_and_key() {
    let dir = tempfile::tempdir().unwrap();
    std::fs::copy(data("checker-2x2.png"), dir.path().join("floor.png")).unwrap();
    std::fs::write(dir.path().join("notes.png"), "not an image").unwrap();
    for (material, parts) in [
        (
            "texture = { file = \"floor.png\", size = 2 }",
            &["line 5", "unknown key `size` in the `texture` table of [materials.m]", "file, scale, rotation, offset, wrap, filter"][..],
        ),
        ("texture = { scale = 2 }", &["line 5", "missing required key `file`"]),
        (
            "texture = { file = \"floor.png\", scale = 0 }",
            &["t.toml line 5", "`materials.m.texture.scale` is 0; expected a number > 0"],
        ),
        (
            "texture = { file = \"floor.png\", scale = 1e200 }",
            &["t.toml line 5", "`materials.m.texture.scale` is 1e200; expected a number > 0 whose square is finite"],
        ),
        (
            "texture = { file = \"floor.png\", wrap = \"tile\" }",
            &["line 5", "`materials.m.texture.wrap` is \"tile\"; expected one of \"repeat\", \"clamp\", \"mirror\""],
        ),
        (
            "texture = { file = \"floor.png\", filter = \"anisotropic\" }",
            &["line 5", "`materials.m.texture.filter` is \"anisotropic\"; expected one of \"nearest\", \"bilinear\", \"trilinear\""],
        ),
        (
            "pattern = { kind = \"checker\" }\ntexture = { file = \"floor.png\" }",
            &["t.toml line 6", "[materials.m] has both a `pattern` and a `texture`; expected one of them"],
        ),
        (
            "texture = { file = \"absent.png\" }",
            &["t.toml line 5", "`materials.m.texture.file`: cannot read `absent.png` (", "absent.png"],
        ),
        (
            "texture = { file = \"notes.png\" }",
            &["t.toml line 5", "`materials.m.texture.file`: `notes.png` is not a PNG or JPEG image"],
        ),
    ] {
        let p = toml_scene(dir.path(), &format!("[materials.m]\n{material}\n"), "");
        let e = err(&p);
        assert!(!e.contains('\n'), "{e}");
        for part in parts {
            assert!(e.contains(part), "{e}\nshould say: {part}");
        }
    }
}
