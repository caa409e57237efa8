//! What a primitive's vertices carry besides positions and normals: vertex
//! colours (`COLOR_0`) and texture coordinates (`TEXCOORD_n`), in every
//! encoding glTF allows, one per vertex or refused naming the primitive.

use glam::{DVec2, DVec3};
use gltf::accessor::{DataType, Dimensions};

use super::accessors::check_accessor_storage;
use super::document::GltfFile;
use crate::scene::error::SceneError;

/// A primitive's `COLOR_0`, one linear RGB per vertex. glTF allows RGB or
/// RGBA, as floats or as normalised unsigned bytes or shorts (divided by
/// their maximum here, in f64, so that 255 is exactly 1). Alpha is not a
/// colour in the lighting model: where it is not all 1 a warning says it
/// was ignored.
pub(super) fn vertex_colors<'a, 's, F>(
    file: &GltfFile,
    what: &str,
    acc: &gltf::Accessor,
    reader: &gltf::mesh::Reader<'a, 's, F>,
    vertex_count: usize,
    warnings: &mut Vec<String>,
) -> Result<Vec<DVec3>, SceneError>
where
    F: Clone + Fn(gltf::Buffer<'a>) -> Option<&'s [u8]>,
{
    let col_what = format!("{what} COLOR_0");
    let err = |msg: String| {
        SceneError::mesh(
            &file.label,
            format!("{col_what} (accessor {}) {msg}", acc.index()),
        )
    };
    let normalized_int = matches!(acc.data_type(), DataType::U8 | DataType::U16);
    let known = matches!(acc.dimensions(), Dimensions::Vec3 | Dimensions::Vec4)
        && (normalized_int == acc.normalized())
        && (normalized_int || acc.data_type() == DataType::F32);
    if !known {
        return Err(err(format!(
            "has type {:?} {:?}{}; expected VEC3 or VEC4 of floats, or of normalized unsigned bytes or shorts",
            acc.dimensions(),
            acc.data_type(),
            if acc.normalized() { " (normalized)" } else { "" },
        )));
    }
    check_accessor_storage(file, &col_what, acc)?;
    use gltf::mesh::util::ReadColors;
    let unorm8 = |c: u8| f64::from(c) / 255.0;
    let unorm16 = |c: u16| f64::from(c) / 65535.0;
    let rgba: Vec<[f64; 4]> = match reader.read_colors(0) {
        Some(ReadColors::RgbU8(it)) => it.map(|c| [c[0], c[1], c[2], 255].map(unorm8)).collect(),
        Some(ReadColors::RgbaU8(it)) => it.map(|c| c.map(unorm8)).collect(),
        Some(ReadColors::RgbU16(it)) => {
            it.map(|c| [c[0], c[1], c[2], 65535].map(unorm16)).collect()
        }
        Some(ReadColors::RgbaU16(it)) => it.map(|c| c.map(unorm16)).collect(),
        Some(ReadColors::RgbF32(it)) => {
            it.map(|c| [c[0], c[1], c[2], 1.0].map(f64::from)).collect()
        }
        Some(ReadColors::RgbaF32(it)) => it.map(|c| c.map(f64::from)).collect(),
        None => return Err(err("cannot be read".into())),
    };
    if rgba.len() != vertex_count {
        return Err(err(format!(
            "has {} colours for {vertex_count} positions; expected one per vertex",
            rgba.len()
        )));
    }
    if let Some(i) = rgba
        .iter()
        .position(|c| c[..3].iter().any(|v| !v.is_finite() || *v < 0.0))
    {
        return Err(err(format!(
            "vertex {i} has colour {:?}; expected finite values of at least 0",
            &rgba[i][..3]
        )));
    }
    if rgba.iter().any(|c| c[3] != 1.0) {
        warnings.push(format!(
            "{}: {what} has vertex colours with alpha below 1; shadelab uses their RGB and ignores the alpha",
            file.label
        ));
    }
    Ok(rgba.iter().map(|c| DVec3::new(c[0], c[1], c[2])).collect())
}

/// Which texture coordinates a primitive's material reads, and who reads
/// them (for messages: "the pattern of material `m`").
pub(super) struct UvUse {
    pub(super) set: u32,
    pub(super) user: String,
}

/// A primitive's `TEXCOORD_n`, one `(u, v)` per vertex, which its
/// material needs (`used`): floats as they are, normalised unsigned bytes
/// or shorts divided by their maximum. Missing, of another type or count,
/// or not finite: an error naming the primitive.
pub(super) fn texture_coordinates<'a, 's, F>(
    file: &GltfFile,
    what: &str,
    prim: &gltf::Primitive,
    reader: &gltf::mesh::Reader<'a, 's, F>,
    used: &UvUse,
    vertex_count: usize,
) -> Result<Vec<DVec2>, SceneError>
where
    F: Clone + Fn(gltf::Buffer<'a>) -> Option<&'s [u8]>,
{
    let set = used.set;
    let Some(acc) = prim.get(&gltf::Semantic::TexCoords(set)) else {
        return Err(SceneError::mesh(
            &file.label,
            format!(
                "{what} has no texture coordinates (TEXCOORD_{set}), which {} needs",
                used.user
            ),
        ));
    };
    let uv_what = format!("{what} TEXCOORD_{set}");
    let err = |msg: String| {
        SceneError::mesh(
            &file.label,
            format!("{uv_what} (accessor {}) {msg}", acc.index()),
        )
    };
    let normalized_int = matches!(acc.data_type(), DataType::U8 | DataType::U16);
    let known = acc.dimensions() == Dimensions::Vec2
        && normalized_int == acc.normalized()
        && (normalized_int || acc.data_type() == DataType::F32);
    if !known {
        return Err(err(format!(
            "has type {:?} {:?}{}; expected VEC2 of floats, or of normalized unsigned bytes or shorts",
            acc.dimensions(),
            acc.data_type(),
            if acc.normalized() { " (normalized)" } else { "" },
        )));
    }
    check_accessor_storage(file, &uv_what, &acc)?;
    use gltf::mesh::util::ReadTexCoords;
    let uvs: Vec<[f64; 2]> = match reader.read_tex_coords(set) {
        Some(ReadTexCoords::U8(it)) => it.map(|c| c.map(|x| f64::from(x) / 255.0)).collect(),
        Some(ReadTexCoords::U16(it)) => it.map(|c| c.map(|x| f64::from(x) / 65535.0)).collect(),
        Some(ReadTexCoords::F32(it)) => it.map(|c| c.map(f64::from)).collect(),
        None => return Err(err("cannot be read".into())),
    };
    if uvs.len() != vertex_count {
        return Err(err(format!(
            "has {} coordinates for {vertex_count} positions; expected one per vertex",
            uvs.len()
        )));
    }
    if let Some(i) = uvs.iter().position(|c| !c.iter().all(|x| x.is_finite())) {
        return Err(err(format!(
            "vertex {i} has coordinates {:?}; expected finite numbers",
            uvs[i]
        )));
    }
    Ok(uvs.iter().map(|&[u, v]| DVec2::new(u, v)).collect())
}

#[cfg(test)]
mod tests {
    use std::path::PathBuf;

    use glam::{DMat4, DVec2, DVec3};

    use crate::scene::footprint::LoadLimits;
    use crate::scene::gltf::contents::Loading;
    use crate::scene::gltf::import::load_meshes;
    use crate::scene::gltf::materials::default_material;
    use crate::scene::gltf::test_support::{err_of, load_patched, meshes, write_gltf, Loaded};
    use crate::scene::image_file::TextureStore;
    use crate::scene::model::{Material, Object, Shape, TriangleMesh};

    fn vertex_colors_model() -> PathBuf {
        PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("assets/models/vertex-colors.gltf")
    }

    fn mesh_named(l: &Loaded, vertices: usize) -> &TriangleMesh {
        l.objects
            .iter()
            .find_map(|o| match &o.shape {
                Shape::Mesh(m) if m.positions.len() == vertices => Some(m),
                _ => None,
            })
            .unwrap_or_else(|| panic!("no mesh of {vertices} vertices"))
    }

    /// COLOR_0 in the three encodings glTF allows, against the values the
    /// fixture script wrote (tests/data/make_fixtures.py): bytes and shorts
    /// divided by their maximum, floats as they are.
    #[test]
    fn vertex_colours_are_read_in_every_encoding() {
        let l = meshes(&vertex_colors_model(), DMat4::IDENTITY).unwrap();
        assert!(l.warnings.is_empty(), "{:?}", l.warnings);
        // The cube: each corner's colour is its position in the model's own
        // frame plus 0.5 (so 0 or 1 per channel). Its node turns it 30
        // degrees about +Y and lifts it by 0.5: undone here by hand.
        let cube = mesh_named(&l, 24);
        let (s, c) = (30f64.to_radians().sin(), 30f64.to_radians().cos());
        for (p, color) in cube.positions.iter().zip(&cube.colors) {
            let q = *p - DVec3::new(0.0, 0.5, 0.0);
            // The inverse of the rotation about +Y by 30 degrees.
            let local = DVec3::new(c * q.x - s * q.z, q.y, s * q.x + c * q.z);
            let want = local + DVec3::splat(0.5);
            // The node's rotation is read as f32: 1e-6 covers its rounding.
            assert!((*color - want).abs().max_element() < 1e-6, "{color} at {p}");
            assert!(color.to_array().iter().all(|v| *v == 0.0 || *v == 1.0));
        }
        let floor = mesh_named(&l, 4);
        let shorts = [
            [65535.0, 52428.0, 39321.0],
            [13107.0, 26214.0, 65535.0],
            [65535.0, 65535.0, 65535.0],
            [32768.0, 65535.0, 13107.0],
        ];
        for (got, want) in floor.colors.iter().zip(shorts) {
            assert_eq!(*got, DVec3::from_array(want) / 65535.0);
        }
        let sail = mesh_named(&l, 3);
        let floats = [[1.0, 0.2, 0.2], [0.2, 1.0, 0.2], [0.2, 0.2, 1.0]];
        for (got, want) in sail.colors.iter().zip(floats) {
            let want = DVec3::from_array(want.map(|v: f32| f64::from(v)));
            assert_eq!(*got, want);
        }
    }

    /// The model's JSON with `patch` applied, written beside nothing (its
    /// buffer is a data URI), and what loading it says.
    fn load_patched_model(patch: impl FnOnce(&mut serde_json::Value)) -> Result<Loaded, String> {
        load_patched(&vertex_colors_model(), patch)
    }

    /// Accessor indices in the fixture: the cube's COLOR_0 (bytes, VEC4),
    /// the floor's (shorts, VEC3), the sail's positions and COLOR_0.
    const CUBE_COLORS: usize = 2;
    const FLOOR_COLORS: usize = 6;
    const SAIL_POSITIONS: usize = 8;
    const FLOOR_UVS: usize = 12;
    const SAIL_INDICES: usize = 10;

    type Patch = Box<dyn FnOnce(&mut serde_json::Value)>;

    /// Points the sail's (mesh 2's) `attribute` at `accessor`.
    fn sail_attribute(d: &mut serde_json::Value, attribute: &str, accessor: usize) {
        d["meshes"][2]["primitives"][0]["attributes"][attribute] = accessor.into();
    }

    /// Each patch makes `load` fail with a message that says its text and
    /// every one of `also`.
    fn assert_each_refused(
        cases: Vec<(&str, Patch)>,
        load: impl Fn(Patch) -> Result<(), String>,
        also: &[&str],
    ) {
        for (want, patch) in cases {
            let err = load(patch)
                .err()
                .unwrap_or_else(|| panic!("loaded; expected {want}"));
            assert!(err.contains(want), "{err}\nshould say: {want}");
            for part in also {
                assert!(err.contains(part), "{err}\nshould say: {part}");
            }
        }
    }

    #[test]
    fn bad_vertex_colours_are_refused_naming_the_primitive() {
        let cases: Vec<(&str, Patch)> = vec![
            (
                "expected VEC3 or VEC4 of floats, or of normalized unsigned bytes or shorts",
                Box::new(|d| sail_attribute(d, "COLOR_0", SAIL_INDICES)),
            ),
            (
                "has type Vec4 U8; expected VEC3 or VEC4",
                Box::new(|d| d["accessors"][CUBE_COLORS]["normalized"] = false.into()),
            ),
            (
                "has 4 colours for 3 positions; expected one per vertex",
                Box::new(|d| sail_attribute(d, "COLOR_0", FLOOR_COLORS)),
            ),
            (
                "vertex 0 has colour [-2.5, 0.0, -1.0]; expected finite values of at least 0",
                Box::new(|d| sail_attribute(d, "COLOR_0", SAIL_POSITIONS)),
            ),
        ];
        let load = |p| load_patched_model(p).map(|_| ());
        assert_each_refused(cases, load, &["COLOR_0", "patched.gltf"]);
    }

    /// Loads the model (patched) with a patterned material given to all of
    /// it, as a TOML mesh object with `material` does: texture coordinates
    /// are read then, and only then.
    fn load_patterned(patch: impl FnOnce(&mut serde_json::Value)) -> Result<Vec<Object>, String> {
        let text = std::fs::read_to_string(vertex_colors_model()).unwrap();
        let mut doc: serde_json::Value = serde_json::from_str(&text).unwrap();
        patch(&mut doc);
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("patched.gltf");
        std::fs::write(&path, doc.to_string()).unwrap();
        let mut materials = vec![Material {
            pattern: Some(crate::scene::Pattern::Checker {
                scale: 2.0,
                colors: [DVec3::ONE, DVec3::ZERO],
            }),
            ..default_material("tiles".into())
        }];
        let mut warnings = Vec::new();
        let limits = LoadLimits::default();
        load_meshes(
            &path,
            DMat4::IDENTITY,
            Some(0),
            &mut materials,
            &mut warnings,
            &mut Loading {
                limits: &limits,
                textures: &mut TextureStore::default(),
            },
        )
        .map_err(|e| e.to_string())
    }

    #[test]
    fn texture_coordinates_are_read_in_every_encoding_for_a_pattern() {
        let objects = load_patterned(|_| {}).unwrap();
        let uvs = |vertices: usize| {
            objects
                .iter()
                .find_map(|o| match &o.shape {
                    Shape::Mesh(m) if m.positions.len() == vertices => Some(m.uvs.clone()),
                    _ => None,
                })
                .unwrap()
        };
        // The cube: floats, 0 to 1 across each face, corners in order.
        let corners = [(0.0, 0.0), (1.0, 0.0), (1.0, 1.0), (0.0, 1.0)];
        let want: Vec<DVec2> = (0..24)
            .map(|i| DVec2::new(corners[i % 4].0, corners[i % 4].1))
            .collect();
        assert_eq!(uvs(24), want);
        // The floor: shorts over 65535; the sail: bytes over 255.
        assert_eq!(uvs(4)[0], DVec2::new(0.0, 1.0));
        assert_eq!(uvs(4)[2], DVec2::new(1.0, 0.0));
        assert_eq!(uvs(3)[2], DVec2::new(128.0 / 255.0, 1.0));
        // Without a pattern, none are read.
        let plain = meshes(&vertex_colors_model(), DMat4::IDENTITY).unwrap();
        assert!(plain.objects.iter().all(|o| match &o.shape {
            Shape::Mesh(m) => m.uvs.is_empty(),
            _ => true,
        }));
    }

    #[test]
    fn bad_texture_coordinates_are_refused_naming_the_primitive() {
        let cases: Vec<(&str, Patch)> = vec![
            (
                "expected VEC2 of floats, or of normalized unsigned bytes or shorts",
                Box::new(|d| sail_attribute(d, "TEXCOORD_0", SAIL_POSITIONS)),
            ),
            (
                "has 4 coordinates for 3 positions",
                Box::new(|d| sail_attribute(d, "TEXCOORD_0", FLOOR_UVS)),
            ),
            (
                "has no texture coordinates (TEXCOORD_0), which the pattern of material `tiles` needs",
                Box::new(|d| {
                    let attributes = &mut d["meshes"][2]["primitives"][0]["attributes"];
                    attributes.as_object_mut().unwrap().remove("TEXCOORD_0");
                }),
            ),
        ];
        let load = |p| load_patterned(p).map(|_| ());
        assert_each_refused(cases, load, &["`sail` (index 2), primitive 0"]);
    }

    #[test]
    fn a_nan_vertex_colour_is_refused() {
        let dir = tempfile::tempdir().unwrap();
        let tri = [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]];
        let colours = [[0.5, 0.5, 0.5], [0.5, f32::NAN, 0.5], [0.5, 0.5, 0.5]];
        // The colours go in as the normals' accessor, then become COLOR_0.
        let p = write_gltf(dir.path(), "nan", &tri, Some(&colours), None, |d| {
            let attributes = &mut d["meshes"][0]["primitives"][0]["attributes"];
            attributes["COLOR_0"] = attributes["NORMAL"].take();
            attributes.as_object_mut().unwrap().remove("NORMAL");
        });
        let err = err_of(&p);
        assert!(err.contains("COLOR_0"), "{err}");
        assert!(err.contains("vertex 1 has colour [0.5, NaN, 0.5]"), "{err}");
    }

    /// A colour's alpha is no colour: read as RGBA with alpha 0 (the
    /// shorts' padding), it loads with a warning saying it was ignored.
    #[test]
    fn vertex_colour_alpha_is_ignored_with_a_warning() {
        let l =
            load_patched_model(|d| d["accessors"][FLOOR_COLORS]["type"] = "VEC4".into()).unwrap();
        assert_eq!(l.warnings.len(), 1, "{:?}", l.warnings);
        assert!(
            l.warnings[0]
                .contains("`floor` (index 1), primitive 0 has vertex colours with alpha below 1"),
            "{:?}",
            l.warnings
        );
        let floor = mesh_named(&l, 4);
        assert_eq!(
            floor.colors[0],
            DVec3::new(1.0, 52428.0 / 65535.0, 39321.0 / 65535.0)
        );
    }
}
