//! glTF 2.0 (`.gltf` with embedded or external buffers, `.glb`) as meshes
//! for a TOML scene, or as a whole scene.
//!
//! # Geometry
//!
//! The default scene (else the first scene; else every node that is no
//! other node's child) is walked depth-first; node transforms are composed
//! in `f64`. Every primitive with mode `TRIANGLES` becomes one
//! [`Object`] with a [`Shape::Mesh`] in world space (other modes are skipped
//! with a warning):
//!
//! - positions are transformed by the world matrix `M` (for a TOML `mesh`
//!   object `M = T * R * S * node_world`); a non-finite position is an error
//!   naming the file, mesh and accessor;
//! - when `det(M) < 0` the winding is flipped (indices 1 and 2 swapped) so
//!   triangles stay counter-clockwise seen from their front;
//! - **degenerate triangles**: a triangle is dropped when two of its indices
//!   are equal or when `|(b - a) x (c - a)| <= 1e-12 * max(|b - a|^2,
//!   |c - a|^2, |c - b|^2)` in world space (twice its area is at most 1e-12
//!   times its longest edge squared, i.e. its vertices are collinear up to
//!   rounding). Each primitive's dropped count is reported in
//!   `Scene::warnings`; a primitive with no triangle left is an error.
//!   Vertices no kept triangle uses are removed;
//! - **normals**: stored normals are transformed by the inverse transpose of
//!   the upper 3x3 of `M` and renormalised. Missing normals are computed
//!   area-weighted: the sum of the unnormalised face normals
//!   `(b - a) x (c - a)` of the kept triangles around the vertex, normalised.
//!   A stored normal that is zero-length or non-finite (before or after the
//!   transform) is replaced by that computed normal. Where the area-weighted
//!   sum itself cancels to zero, the unit face normal of the first kept
//!   triangle using the vertex is used;
//! - the node hierarchy must be a set of disjoint trees (a node reached
//!   twice, through a cycle or two parents, is an error);
//! - an index out of range, a sparse accessor, an accessor of the wrong type
//!   or one that does not fit its buffer view is an error; a primitive whose
//!   node transform is singular (a zero scale) is skipped with a warning.
//!
//! # Materials
//!
//! See [`map_material`] for the exact rule. Materials are added to
//! `Scene::materials` named `<file stem>/<material name or index>` (a
//! primitive without material uses `<file stem>/default`), once per file.
//!
//! # Base colour textures
//!
//! `pbrMetallicRoughness.baseColorTexture` becomes the material's
//! [`Pattern::Image`], multiplying `baseColorFactor` (which stays the
//! material's `color`):
//!
//! - texture coordinates: the primitive's `TEXCOORD_n` for the texture's
//!   `texCoord` n (or its `KHR_texture_transform` `texCoord`), floats or
//!   normalised unsigned bytes or shorts; a primitive without that set is
//!   an error naming the primitive, the set and the material;
//! - the sampler: `wrapS`/`wrapT` REPEAT (10497), CLAMP_TO_EDGE (33071),
//!   MIRRORED_REPEAT (33648); `magFilter` NEAREST (9728) or LINEAR (9729);
//!   `minFilter` NEAREST, LINEAR (no mipmaps) or NEAREST_MIPMAP_NEAREST
//!   (9984), LINEAR_MIPMAP_NEAREST (9985), NEAREST_MIPMAP_LINEAR (9986),
//!   LINEAR_MIPMAP_LINEAR (9987) (the first word within a level, the last
//!   between levels). glTF leaves the filters to the viewer where a
//!   sampler or a filter is absent: shadelab takes
//!   [`Sampler::GLTF_DEFAULT`] (REPEAT, LINEAR, LINEAR_MIPMAP_LINEAR). A
//!   value glTF does not define is an error naming the sampler and key;
//! - the image: a buffer view (in a GLB or any buffer), a base64 data URI,
//!   or a file beside the glTF (its URI percent-decoded), PNG or JPEG by
//!   its content, sRGB, decoded once per scene (`image_file`) and refused
//!   before decoding when it would not fit the memory limit. Its alpha is
//!   ignored, with a warning per image where it is not all opaque;
//! - `KHR_texture_transform` on it: `uv' = T R S uv` with `T` the offset,
//!   `S` the scale and `R = [[cos r, sin r], [-sin r, cos r]]` for the
//!   rotation `r` (the extension's convention), as a [`UvTransform`].

use std::borrow::Cow;
use std::collections::HashMap;
use std::path::{Path, PathBuf};

use glam::{DMat3, DMat4, DQuat, DVec2, DVec3};
use gltf::accessor::{DataType, Dimensions};
use gltf::mesh::Mode;

use super::defaults::{DEFAULT_FOV_Y_DEG, DEFAULT_MATERIAL};
use super::error::SceneError;
use super::footprint::{GeometrySize, LoadLimits};
use super::image_file::{ImageFailure, ImageKey, TextureRequest, TextureStore};
use super::model::{
    Camera, Filter, ImageSettings, Lighting, Material, Object, Pattern, PointLight, RenderSettings,
    Sampler, Scene, Shape, TriangleMesh, UvTransform, Wrap,
};

/// A parsed glTF file with its buffers loaded (images are loaded by the
/// materials that use them).
struct GltfFile {
    label: String,
    stem: String,
    /// Where files it names (buffers, images) lie.
    base: PathBuf,
    doc: gltf::Document,
    buffers: Vec<gltf::buffer::Data>,
    /// The raw JSON of what the `gltf` crate does not read for us.
    raw: RawParts,
}

/// The parts of the JSON read as plain JSON: the accessor references the
/// `gltf` crate indexes before validating them, the samplers and images it
/// would refuse with a vaguer message or unwrap, and the materials and
/// textures, for extensions it is not built to read (`KHR_materials_ior`)
/// and the texture transform's values in full precision. Everything else
/// is skipped rather than kept: a file instancing a mesh two million times
/// has two million nodes, and a JSON tree of them cost about 400 bytes each.
#[derive(serde::Deserialize, Default)]
struct RawParts {
    #[serde(default)]
    accessors: serde_json::Value,
    #[serde(default)]
    meshes: serde_json::Value,
    #[serde(default)]
    materials: serde_json::Value,
    #[serde(default)]
    samplers: serde_json::Value,
    #[serde(default)]
    images: serde_json::Value,
    #[serde(default)]
    textures: serde_json::Value,
}

fn open(path: &Path) -> Result<GltfFile, SceneError> {
    let label = path.display().to_string();
    let bytes = std::fs::read(path).map_err(|e| SceneError::Read {
        file: label.clone(),
        reason: e.to_string(),
    })?;
    let stem = path
        .file_stem()
        .map(|s| s.to_string_lossy().into_owned())
        .unwrap_or_else(|| "mesh".to_string());
    let base = path.parent().unwrap_or_else(|| Path::new("."));
    parse(&bytes, label, stem, base)
}

/// Parses a glTF or GLB held in memory; external buffers are read from
/// `base`.
fn parse(bytes: &[u8], label: String, stem: String, base: &Path) -> Result<GltfFile, SceneError> {
    let json_bytes: std::borrow::Cow<[u8]> = if bytes.starts_with(b"glTF") {
        check_glb_header(&label, bytes)?;
        let glb = gltf::Glb::from_slice(bytes).map_err(|e| {
            SceneError::mesh(&label, format!("not a valid binary glTF (.glb) file ({e})"))
        })?;
        glb.json
    } else {
        std::borrow::Cow::Borrowed(bytes)
    };
    let raw = raw_parts(&json_bytes).map_err(|e| {
        SceneError::mesh(&label, format!("not a valid glTF 2.0 file (bad JSON: {e})"))
    })?;
    drop(json_bytes);
    check_primitive_references(&label, &raw)?;
    check_samplers(&label, &raw)?;
    check_images_and_textures(&label, &raw)?;
    let gltf::Gltf { document, blob } = gltf::Gltf::from_slice(bytes)
        .map_err(|e| SceneError::mesh(&label, format!("not a valid glTF 2.0 file ({e})")))?;
    check_buffer_uris(&label, &document)?;
    check_buffer_files(&label, &document, base)?;
    let buffers = gltf::import_buffers(&document, Some(base), blob).map_err(|e| {
        SceneError::mesh(
            &label,
            format!(
                "cannot load the glTF buffers ({e}); check that every .bin file it names exists"
            ),
        )
    })?;
    Ok(GltfFile {
        label,
        stem,
        base: base.to_path_buf(),
        doc: document,
        buffers,
        raw,
    })
}

/// Reads [`RawParts`] from a JSON document. Any valid JSON is accepted here
/// (a top-level value that is not an object reads as empty parts): telling
/// the user what a glTF file must look like is the `gltf` crate's job.
fn raw_parts(json: &[u8]) -> serde_json::Result<RawParts> {
    let first = json.iter().find(|b| !b.is_ascii_whitespace());
    if first == Some(&b'{') {
        serde_json::from_slice(json)
    } else {
        serde_json::from_slice::<serde::de::IgnoredAny>(json).map(|_| RawParts::default())
    }
}

/// The `gltf` crate percent-decodes a relative buffer URI and unwraps the
/// result as UTF-8, so a URI such as `a%AA.bin` panics inside it (found by
/// fuzzing, `tests/fuzz_regressions.rs`). Refuse such a URI first.
fn check_buffer_uris(label: &str, document: &gltf::Document) -> Result<(), SceneError> {
    for buffer in document.buffers() {
        let gltf::buffer::Source::Uri(uri) = buffer.source() else {
            continue;
        };
        if uri.contains(':') {
            continue;
        }
        let decoded = percent_decoded_bytes(uri);
        if std::str::from_utf8(&decoded).is_err() {
            return Err(SceneError::mesh(
                label,
                format!(
                    "buffer {}: its uri `{uri}` percent-decodes to bytes that are not UTF-8; expected a file name or a data: URI",
                    buffer.index()
                ),
            ));
        }
    }
    Ok(())
}

/// Names the buffer file that is missing, where the `gltf` crate's error
/// says only "No such file or directory".
fn check_buffer_files(
    label: &str,
    document: &gltf::Document,
    base: &Path,
) -> Result<(), SceneError> {
    for buffer in document.buffers() {
        let gltf::buffer::Source::Uri(uri) = buffer.source() else {
            continue;
        };
        if uri.contains(':') {
            continue; // a data: URI, or a scheme the importer refuses itself
        }
        let name = percent_decoded(uri);
        let path = base.join(&name);
        if !path.is_file() {
            return Err(SceneError::mesh(
                label,
                format!(
                    "buffer {} names the file `{name}`, which does not exist ({}); put it beside the .gltf or fix the uri",
                    buffer.index(),
                    path.display()
                ),
            ));
        }
    }
    Ok(())
}

/// `uri` with its %XX escapes decoded, as text (checked UTF-8 by
/// `check_buffer_uris` before).
fn percent_decoded(uri: &str) -> String {
    String::from_utf8_lossy(&percent_decoded_bytes(uri)).into_owned()
}

/// `uri`'s bytes with each `%XX` escape replaced by its byte; a `%` not
/// followed by two hex digits is kept as it is.
fn percent_decoded_bytes(uri: &str) -> Vec<u8> {
    let bytes = uri.as_bytes();
    let mut decoded = Vec::with_capacity(bytes.len());
    let mut i = 0;
    while i < bytes.len() {
        let hex = bytes
            .get(i + 1..i + 3)
            .filter(|h| h.iter().all(u8::is_ascii_hexdigit))
            .and_then(|h| u8::from_str_radix(std::str::from_utf8(h).ok()?, 16).ok());
        match (bytes[i], hex) {
            (b'%', Some(byte)) => {
                decoded.push(byte);
                i += 3;
            }
            (byte, _) => {
                decoded.push(byte);
                i += 1;
            }
        }
    }
    decoded
}

/// The `gltf` crate's validator indexes `accessors` with a primitive's
/// POSITION before checking it exists; check every primitive's accessor
/// references first.
fn check_primitive_references(label: &str, raw: &RawParts) -> Result<(), SceneError> {
    let count = raw.accessors.as_array().map_or(0, Vec::len);
    let meshes = raw.meshes.as_array();
    for (mi, mesh) in meshes.into_iter().flatten().enumerate() {
        let prims = mesh.get("primitives").and_then(|p| p.as_array());
        for (pi, prim) in prims.into_iter().flatten().enumerate() {
            let attributes = prim.get("attributes").and_then(|a| a.as_object());
            let refs = attributes
                .into_iter()
                .flatten()
                .map(|(k, v)| (k.as_str(), v))
                .chain(prim.get("indices").map(|v| ("indices", v)));
            for (what, v) in refs {
                let ok = v.as_u64().is_some_and(|i| i < count as u64);
                if !ok {
                    return Err(SceneError::mesh(
                        label,
                        format!(
                            "mesh {mi}, primitive {pi}: {what} refers to accessor {v}, but the file has {count} accessors; expected an index below {count}"
                        ),
                    ));
                }
            }
        }
    }
    Ok(())
}

/// The values glTF defines for each sampler key, with their names.
const SAMPLER_VALUES: [(&str, &[(u64, &str)]); 4] = [
    ("magFilter", &[(9728, "NEAREST"), (9729, "LINEAR")]),
    (
        "minFilter",
        &[
            (9728, "NEAREST"),
            (9729, "LINEAR"),
            (9984, "NEAREST_MIPMAP_NEAREST"),
            (9985, "LINEAR_MIPMAP_NEAREST"),
            (9986, "NEAREST_MIPMAP_LINEAR"),
            (9987, "LINEAR_MIPMAP_LINEAR"),
        ],
    ),
    (
        "wrapS",
        &[
            (33071, "CLAMP_TO_EDGE"),
            (33648, "MIRRORED_REPEAT"),
            (10497, "REPEAT"),
        ],
    ),
    (
        "wrapT",
        &[
            (33071, "CLAMP_TO_EDGE"),
            (33648, "MIRRORED_REPEAT"),
            (10497, "REPEAT"),
        ],
    ),
];

/// A sampler value glTF does not define is refused here, naming the
/// sampler, the key and the values it may take. The `gltf` crate would
/// refuse most of them itself, but as "samplers[0].wrapS: Invalid value",
/// and it reads the number as a `u32` after truncating it: 4294977793
/// (2^32 + 10497) passed for REPEAT.
fn check_samplers(label: &str, raw: &RawParts) -> Result<(), SceneError> {
    for (i, sampler) in raw.samplers.as_array().into_iter().flatten().enumerate() {
        for (key, defined) in SAMPLER_VALUES {
            let Some(value) = sampler.get(key) else {
                continue;
            };
            let known = value
                .as_u64()
                .is_some_and(|v| defined.iter().any(|(code, _)| *code == v));
            if known {
                continue;
            }
            let name = match sampler.get("name").and_then(|n| n.as_str()) {
                Some(n) if !n.is_empty() => format!(" (`{n}`)"),
                _ => String::new(),
            };
            let expected: Vec<String> = defined
                .iter()
                .map(|(code, what)| format!("{code} ({what})"))
                .collect();
            return Err(SceneError::mesh(
                label,
                format!(
                    "sampler {i}{name}: {key} is {value}, which glTF does not define; expected one of {}",
                    expected.join(", ")
                ),
            ));
        }
    }
    Ok(())
}

/// What the `gltf` crate unwraps without a check when an image is read (a
/// buffer view without a MIME type, an image with neither a URI nor a
/// buffer view), and a texture without a source image (which it refuses as
/// "Missing data"): refused here, each naming the image or texture.
fn check_images_and_textures(label: &str, raw: &RawParts) -> Result<(), SceneError> {
    let present = |v: &serde_json::Value, key: &str| v.get(key).is_some_and(|x| !x.is_null());
    for (i, image) in raw.images.as_array().into_iter().flatten().enumerate() {
        let problem = if present(image, "bufferView") {
            (!present(image, "mimeType")).then_some(
                "is in a buffer view but has no mimeType; glTF requires one (\"image/png\" or \"image/jpeg\")",
            )
        } else {
            (!present(image, "uri"))
                .then_some("has neither a uri nor a bufferView; expected one of them")
        };
        if let Some(problem) = problem {
            return Err(SceneError::mesh(label, format!("image {i} {problem}")));
        }
    }
    for (i, texture) in raw.textures.as_array().into_iter().flatten().enumerate() {
        if !present(texture, "source") {
            let extensions: Vec<&String> = texture
                .get("extensions")
                .and_then(|e| e.as_object())
                .map(|e| e.keys().collect())
                .unwrap_or_default();
            let only = if extensions.is_empty() {
                String::new()
            } else {
                format!(
                    " (only through {}, which shadelab does not read)",
                    extensions
                        .iter()
                        .map(|e| e.as_str())
                        .collect::<Vec<_>>()
                        .join(", ")
                )
            };
            return Err(SceneError::mesh(
                label,
                format!("texture {i} has no source image{only}; expected a PNG or JPEG source"),
            ));
        }
    }
    Ok(())
}

/// The `gltf` crate subtracts 12 from the header's length field without a
/// check; reject such headers first.
fn check_glb_header(label: &str, bytes: &[u8]) -> Result<(), SceneError> {
    let word = |at: usize| {
        bytes
            .get(at..at + 4)
            .and_then(|s| <[u8; 4]>::try_from(s).ok())
            .map(u32::from_le_bytes)
    };
    let bad = |what: &str| {
        SceneError::mesh(
            label,
            format!("not a valid binary glTF (.glb) file ({what}); re-export the file"),
        )
    };
    let version = word(4).ok_or_else(|| bad("the 12-byte header is truncated"))?;
    let length = word(8).ok_or_else(|| bad("the 12-byte header is truncated"))?;
    if version != 2 {
        return Err(bad(&format!("version {version}, expected 2")));
    }
    if (length as usize) < 20 || length as usize > bytes.len() {
        return Err(bad(&format!(
            "header says {length} bytes but the file has {}",
            bytes.len()
        )));
    }
    Ok(())
}

fn f32x3(v: [f32; 3]) -> DVec3 {
    DVec3::new(f64::from(v[0]), f64::from(v[1]), f64::from(v[2]))
}

fn local_matrix(label: &str, node: &gltf::Node) -> Result<DMat4, SceneError> {
    let m = match node.transform() {
        gltf::scene::Transform::Matrix { matrix } => {
            let cols: Vec<f64> = matrix.iter().flatten().map(|&x| f64::from(x)).collect();
            let mut arr = [0.0; 16];
            arr.copy_from_slice(&cols);
            DMat4::from_cols_array(&arr)
        }
        gltf::scene::Transform::Decomposed {
            translation,
            rotation,
            scale,
        } => {
            let q = DQuat::from_xyzw(
                f64::from(rotation[0]),
                f64::from(rotation[1]),
                f64::from(rotation[2]),
                f64::from(rotation[3]),
            );
            // Renormalise in f64 so f32-rounded unit quaternions stay exact.
            let q = if q.length() > 0.0 {
                q.normalize()
            } else {
                DQuat::IDENTITY
            };
            DMat4::from_scale_rotation_translation(f32x3(scale), q, f32x3(translation))
        }
    };
    if !m.is_finite() {
        return Err(SceneError::mesh(
            label,
            format!("{} has a non-finite transform", node_name(node)),
        ));
    }
    Ok(m)
}

fn node_name(node: &gltf::Node) -> String {
    match node.name() {
        Some(n) if !n.is_empty() => format!("node `{n}` (index {})", node.index()),
        _ => format!("node {}", node.index()),
    }
}

fn mesh_name(mesh: &gltf::Mesh) -> String {
    match mesh.name() {
        Some(n) if !n.is_empty() => format!("mesh `{n}` (index {})", mesh.index()),
        _ => format!("mesh {}", mesh.index()),
    }
}

/// Calls `visit` on every node reachable from the scene's roots with its
/// world matrix, in depth-first order. Nothing is kept per node: a file
/// instancing a mesh millions of times has millions of nodes.
fn walk_nodes<'a>(
    file: &'a GltfFile,
    mut visit: impl FnMut(gltf::Node<'a>, &DMat4) -> Result<(), SceneError>,
) -> Result<(), SceneError> {
    let roots: Vec<gltf::Node> = match file
        .doc
        .default_scene()
        .or_else(|| file.doc.scenes().next())
    {
        Some(scene) => scene.nodes().collect(),
        None => {
            let mut is_child = vec![false; file.doc.nodes().len()];
            for n in file.doc.nodes() {
                for c in n.children() {
                    if let Some(flag) = is_child.get_mut(c.index()) {
                        *flag = true;
                    }
                }
            }
            file.doc
                .nodes()
                .filter(|n| !is_child.get(n.index()).copied().unwrap_or(false))
                .collect()
        }
    };
    let mut visited = vec![false; file.doc.nodes().len()];
    let mut stack: Vec<(gltf::Node, DMat4)> = Vec::new();
    for root in roots {
        stack.push((root, DMat4::IDENTITY));
        while let Some((node, parent)) = stack.pop() {
            match visited.get_mut(node.index()) {
                Some(seen) if !*seen => *seen = true,
                _ => {
                    return Err(SceneError::mesh(
                        &file.label,
                        format!(
                            "{} appears more than once in the node hierarchy (a cycle or several parents); expected disjoint trees as glTF requires",
                            node_name(&node)
                        ),
                    ))
                }
            }
            let world = parent * local_matrix(&file.label, &node)?;
            let children: Vec<gltf::Node> = node.children().collect();
            for child in children.into_iter().rev() {
                stack.push((child, world));
            }
            visit(node, &world)?;
        }
    }
    Ok(())
}

/// Checks an accessor so that the `gltf` crate's reader cannot panic on it.
fn check_accessor(
    file: &GltfFile,
    what: &str,
    acc: &gltf::Accessor,
    dims: Dimensions,
    types: &[DataType],
) -> Result<(), SceneError> {
    let err = |msg: String| {
        SceneError::mesh(
            &file.label,
            format!("{what} (accessor {}) {msg}", acc.index()),
        )
    };
    if acc.dimensions() != dims || !types.contains(&acc.data_type()) || acc.normalized() {
        return Err(err(format!(
            "has type {:?} {:?}{}; expected {:?} of {:?}",
            acc.dimensions(),
            acc.data_type(),
            if acc.normalized() {
                " (normalized)"
            } else {
                ""
            },
            dims,
            types
        )));
    }
    check_accessor_storage(file, what, acc)
}

/// The part of `check_accessor` that holds for every type: not sparse, not
/// empty, and inside its buffer view and buffer.
fn check_accessor_storage(
    file: &GltfFile,
    what: &str,
    acc: &gltf::Accessor,
) -> Result<(), SceneError> {
    let err = |msg: String| {
        SceneError::mesh(
            &file.label,
            format!("{what} (accessor {}) {msg}", acc.index()),
        )
    };
    if acc.sparse().is_some() {
        return Err(err(
            "is a sparse accessor, which is not supported; export without sparse accessors".into(),
        ));
    }
    if acc.count() == 0 {
        return Err(err("is empty".into()));
    }
    let view = acc.view().ok_or_else(|| err("has no buffer view".into()))?;
    let elem = acc.size();
    let stride = view.stride().unwrap_or(elem);
    if stride < elem {
        return Err(err(format!(
            "has a byte stride {stride} smaller than its element size {elem}"
        )));
    }
    let end = stride
        .checked_mul(acc.count() - 1)
        .and_then(|x| x.checked_add(elem))
        .and_then(|x| x.checked_add(acc.offset()));
    if end.is_none_or(|e| e > view.length()) {
        return Err(err(format!(
            "does not fit in its buffer view {} ({} bytes)",
            view.index(),
            view.length()
        )));
    }
    let buffer_len = file
        .buffers
        .get(view.buffer().index())
        .map_or(0, |b| b.len());
    let view_end = view.offset().checked_add(view.length());
    if view_end.is_none_or(|e| e > buffer_len) {
        return Err(err(format!(
            "uses buffer view {} which runs past the end of buffer {}",
            view.index(),
            view.buffer().index()
        )));
    }
    Ok(())
}

/// One primitive's triangles in world space, or `None` when skipped.
fn primitive_mesh(
    file: &GltfFile,
    mesh: &gltf::Mesh,
    prim: &gltf::Primitive,
    world: DMat4,
    uv_use: Option<&UvUse>,
    warnings: &mut Vec<String>,
) -> Result<Option<TriangleMesh>, SceneError> {
    let what = format!("{}, primitive {}", mesh_name(mesh), prim.index());
    if prim.mode() != Mode::Triangles {
        warnings.push(format!(
            "{}: {what} has mode {:?}; only TRIANGLES is drawn, so it was skipped",
            file.label,
            prim.mode()
        ));
        return Ok(None);
    }
    let m3 = DMat3::from_mat4(world);
    let det = m3.determinant();
    if det == 0.0 || !det.is_finite() {
        warnings.push(format!(
            "{}: {what} has a singular node transform (a zero scale), so it was skipped",
            file.label
        ));
        return Ok(None);
    }
    let normal_matrix = m3.inverse().transpose();
    let flip = det < 0.0;

    let pos_acc = prim.get(&gltf::Semantic::Positions).ok_or_else(|| {
        SceneError::mesh(&file.label, format!("{what} has no POSITION attribute"))
    })?;
    let pos_what = format!("{what} POSITION");
    check_accessor(
        file,
        &pos_what,
        &pos_acc,
        Dimensions::Vec3,
        &[DataType::F32],
    )?;
    let nrm_acc = prim.get(&gltf::Semantic::Normals);
    if let Some(acc) = &nrm_acc {
        check_accessor(
            file,
            &format!("{what} NORMAL"),
            acc,
            Dimensions::Vec3,
            &[DataType::F32],
        )?;
    }
    if let Some(acc) = prim.indices() {
        check_accessor(
            file,
            &format!("{what} indices"),
            &acc,
            Dimensions::Scalar,
            &[DataType::U8, DataType::U16, DataType::U32],
        )?;
    }

    let reader = prim.reader(|b| file.buffers.get(b.index()).map(|d| &d.0[..]));
    let local: Vec<[f32; 3]> = reader
        .read_positions()
        .ok_or_else(|| SceneError::mesh(&file.label, format!("{pos_what} cannot be read")))?
        .collect();
    if local.len() != pos_acc.count() || local.len() > u32::MAX as usize {
        return Err(SceneError::mesh(
            &file.label,
            format!(
                "{pos_what} (accessor {}) could not be read completely",
                pos_acc.index()
            ),
        ));
    }
    let mut positions = Vec::with_capacity(local.len());
    for (i, p) in local.iter().enumerate() {
        let w = world.transform_point3(f32x3(*p));
        if !w.is_finite() {
            let why = if p.iter().all(|c| c.is_finite()) {
                "overflows to infinity under the node transform"
            } else {
                "is not a finite number"
            };
            return Err(SceneError::mesh(
                &file.label,
                format!(
                    "{pos_what} (accessor {}) vertex {i} {why}; expected finite coordinates",
                    pos_acc.index()
                ),
            ));
        }
        positions.push(w);
    }
    let n = positions.len();

    let stored_normals: Option<Vec<DVec3>> = match (&nrm_acc, reader.read_normals()) {
        (Some(_), Some(it)) => {
            let v: Vec<DVec3> = it
                .map(|nv| (normal_matrix * f32x3(nv)).normalize_or_zero())
                .collect();
            if v.len() == n {
                Some(v)
            } else {
                warnings.push(format!(
                    "{}: {what} has {} normals for {n} positions; normals were recomputed",
                    file.label,
                    v.len()
                ));
                None
            }
        }
        _ => None,
    };

    let colors = match prim.get(&gltf::Semantic::Colors(0)) {
        Some(acc) => vertex_colors(file, &what, &acc, &reader, n, warnings)?,
        None => Vec::new(),
    };
    let uvs = match uv_use {
        Some(used) => texture_coordinates(file, &what, prim, &reader, used, n)?,
        None => Vec::new(),
    };

    let indices: Vec<u32> = match reader.read_indices() {
        Some(it) => it.into_u32().collect(),
        None => (0..n as u32).collect(),
    };
    if let Some(&bad) = indices.iter().find(|&&i| i as usize >= n) {
        return Err(SceneError::mesh(
            &file.label,
            format!(
                "{what} uses vertex index {bad} but POSITION has only {n} vertices; expected indices below {n}"
            ),
        ));
    }
    if indices.len() % 3 != 0 {
        warnings.push(format!(
            "{}: {what} has {} indices, not a multiple of 3; the last {} were ignored",
            file.label,
            indices.len(),
            indices.len() % 3
        ));
    }

    let mut triangles = Vec::with_capacity(indices.len() / 3);
    let mut dropped = 0usize;
    for t in indices.chunks_exact(3) {
        let mut tri = [t[0], t[1], t[2]];
        if flip {
            tri.swap(1, 2);
        }
        if is_degenerate(&positions, tri) {
            dropped += 1;
        } else {
            triangles.push(tri);
        }
    }
    if dropped > 0 {
        warnings.push(format!(
            "{}: {what}: dropped {dropped} degenerate triangle(s) (repeated vertex or zero area)",
            file.label
        ));
    }
    if triangles.is_empty() {
        return Err(SceneError::mesh(
            &file.label,
            format!("{what} has no non-degenerate triangle; expected at least one triangle with non-zero area"),
        ));
    }
    let attributes = VertexAttributes { colors, uvs };
    Ok(Some(build_mesh(
        positions,
        stored_normals,
        attributes,
        triangles,
    )))
}

/// A primitive's `COLOR_0`, one linear RGB per vertex. glTF allows RGB or
/// RGBA, as floats or as normalised unsigned bytes or shorts (divided by
/// their maximum here, in f64, so that 255 is exactly 1). Alpha is not a
/// colour in the lighting model: where it is not all 1 a warning says it
/// was ignored.
fn vertex_colors<'a, 's, F>(
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
struct UvUse {
    set: u32,
    user: String,
}

/// A primitive's `TEXCOORD_n`, one `(u, v)` per vertex, which its
/// material needs (`used`): floats as they are, normalised unsigned bytes
/// or shorts divided by their maximum. Missing, of another type or count,
/// or not finite: an error naming the primitive.
fn texture_coordinates<'a, 's, F>(
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

/// The degenerate-triangle rule documented at the top of this module.
pub(crate) fn is_degenerate(positions: &[DVec3], t: [u32; 3]) -> bool {
    if t[0] == t[1] || t[1] == t[2] || t[0] == t[2] {
        return true;
    }
    let (Some(a), Some(b), Some(c)) = (
        positions.get(t[0] as usize),
        positions.get(t[1] as usize),
        positions.get(t[2] as usize),
    ) else {
        return true;
    };
    let (e1, e2, e3) = (*b - *a, *c - *a, *c - *b);
    let longest = e1
        .length_squared()
        .max(e2.length_squared())
        .max(e3.length_squared());
    let twice_area = e1.cross(e2).length();
    let well_shaped = twice_area.is_finite() && twice_area > 1e-12 * longest;
    !well_shaped
}

/// Compacts the vertices to those the kept triangles use and fills in the
/// normals (rule in the module docs). `triangles` must be in range.
/// What a vertex may carry besides its position and normal, each list
/// empty or one per vertex.
struct VertexAttributes {
    colors: Vec<DVec3>,
    uvs: Vec<DVec2>,
}

fn build_mesh(
    positions: Vec<DVec3>,
    stored: Option<Vec<DVec3>>,
    attributes: VertexAttributes,
    triangles: Vec<[u32; 3]>,
) -> TriangleMesh {
    // Keep the used vertices in their original order.
    let mut used = vec![false; positions.len()];
    for t in &triangles {
        for &i in t {
            used[i as usize] = true;
        }
    }
    let mut remap = vec![0u32; positions.len()];
    let mut out_pos = Vec::new();
    let mut out_stored = Vec::new();
    let mut out_colors = Vec::new();
    let mut out_uvs = Vec::new();
    for (i, p) in positions.iter().enumerate() {
        if used[i] {
            remap[i] = out_pos.len() as u32;
            out_pos.push(*p);
            out_stored.push(stored.as_ref().map_or(DVec3::ZERO, |s| s[i]));
            out_colors.extend(attributes.colors.get(i));
            out_uvs.extend(attributes.uvs.get(i));
        }
    }
    let tris: Vec<[u32; 3]> = triangles
        .iter()
        .map(|t| t.map(|i| remap[i as usize]))
        .collect();
    let mut sum = vec![DVec3::ZERO; out_pos.len()];
    let mut first_face = vec![DVec3::ZERO; out_pos.len()];
    for t in &tris {
        let [a, b, c] = t.map(|i| out_pos[i as usize]);
        let face = (b - a).cross(c - a);
        for &i in t {
            sum[i as usize] += face;
            if first_face[i as usize] == DVec3::ZERO {
                first_face[i as usize] = face.normalize_or_zero();
            }
        }
    }
    let normals = out_stored
        .iter()
        .zip(sum.iter().zip(&first_face))
        .map(|(s, (area, first))| {
            if s.is_finite() && s.length_squared() > 0.0 {
                *s
            } else {
                let n = area.normalize_or_zero();
                if n == DVec3::ZERO {
                    *first
                } else {
                    n
                }
            }
        })
        .collect();
    TriangleMesh {
        positions: out_pos,
        normals,
        triangles: tris,
        colors: out_colors,
        uvs: out_uvs,
    }
}

/// Maps a glTF metallic-roughness material to the lecture's model.
///
/// With `base = baseColorFactor`, `m = metallicFactor`, `r = roughnessFactor`
/// (both clamped to [0, 1]):
///
/// ```text
/// color = base.rgb
/// ka    = 0.2
/// kd    = 0.8 * (1 - m * (1 - r))
/// ks    = (0.04 + 0.96 * m) * (1 - r)
/// p     = clamp(2 / max(r^4, 1e-4) - 2, 1, 500)
/// kr    = m * (1 - r)
/// kt    = 1 - base.alpha   when alphaMode is BLEND, else 0
/// ior   = KHR_materials_ior.ior if present, else 1.5 when kt > 0, else 1.0
/// ```
///
/// Diffuse fades only for smooth metals: a rough metal scatters light
/// broadly, which this model can only show as diffuse. It also keeps a
/// material without a PBR block (glTF defaults m = r = 1) from rendering
/// ambient-only.
///
/// The base colour texture is added by the caller (`base_colour_texture`,
/// the module docs); the other textures and emission are not modelled
/// (each announced by a warning, `unmodelled_features`). Then any of `ka`, `kd`, `ks`, `p`, `kr`, `kt`,
/// `ior` present in the material's `extras` object replaces the computed
/// value (it must be a finite number, `>= 0`, and `ior > 0`; other extras
/// keys are ignored). A primitive without a material gets color 0.8 grey,
/// ka 0.2, kd 0.8, ks 0, p 32, kr 0, kt 0, ior 1.
pub fn map_material(
    file_label: &str,
    name: String,
    mat: &gltf::Material,
    raw_materials: &serde_json::Value,
) -> Result<Material, SceneError> {
    let pbr = mat.pbr_metallic_roughness();
    let base = pbr.base_color_factor();
    let m = f64::from(pbr.metallic_factor()).clamp(0.0, 1.0);
    let r = f64::from(pbr.roughness_factor()).clamp(0.0, 1.0);
    let kt = if mat.alpha_mode() == gltf::material::AlphaMode::Blend {
        (1.0 - f64::from(base[3])).clamp(0.0, 1.0)
    } else {
        0.0
    };
    let ior_ext = mat.index().and_then(|i| {
        raw_materials
            .get(i)?
            .get("extensions")?
            .get("KHR_materials_ior")?
            .get("ior")?
            .as_f64()
            .filter(|x| x.is_finite() && *x > 0.0)
    });
    let mut out = Material {
        name,
        color: f32x3([base[0], base[1], base[2]]).max(DVec3::ZERO),
        ka: DEFAULT_MATERIAL.ka,
        kd: 0.8 * (1.0 - m * (1.0 - r)),
        ks: (0.04 + 0.96 * m) * (1.0 - r),
        p: (2.0 / r.powi(4).max(1e-4) - 2.0).clamp(1.0, 500.0),
        kr: m * (1.0 - r),
        kt,
        ior: ior_ext.unwrap_or(if kt > 0.0 { 1.5 } else { 1.0 }),
        pattern: None,
    };
    if let Some(raw) = mat.extras() {
        let value: serde_json::Value = serde_json::from_str(raw.get()).unwrap_or_default();
        if let Some(obj) = value.as_object() {
            let which = mat.name().map_or_else(
                || format!("material {}", mat.index().unwrap_or(0)),
                |n| format!("material `{n}`"),
            );
            for (key, slot) in [
                ("ka", &mut out.ka),
                ("kd", &mut out.kd),
                ("ks", &mut out.ks),
                ("p", &mut out.p),
                ("kr", &mut out.kr),
                ("kt", &mut out.kt),
                ("ior", &mut out.ior),
            ] {
                let Some(v) = obj.get(key) else { continue };
                let x = v.as_f64().filter(|x| x.is_finite()).ok_or_else(|| {
                    SceneError::mesh(
                        file_label,
                        format!("{which}: extras key `{key}` is {v}; expected a finite number"),
                    )
                })?;
                let ok = if key == "ior" { x > 0.0 } else { x >= 0.0 };
                if !ok {
                    return Err(SceneError::mesh(
                        file_label,
                        format!(
                            "{which}: extras key `{key}` is {x}; expected a number {}",
                            if key == "ior" { "> 0" } else { ">= 0" }
                        ),
                    ));
                }
                *slot = x;
            }
        }
    }
    Ok(out)
}

/// What a glTF material carries that the lighting model does not take:
/// each named for the warning, so that an asset never renders in other
/// colours than its author's without a word. The textures other than the
/// base colour's and emission are not modelled; `KHR_materials_ior` is,
/// through `ior`, and `KHR_texture_transform` on the base colour texture
/// is. Other extensions on the base colour texture (its texture info or
/// its texture) are named too: its PNG or JPEG source is what is drawn.
fn unmodelled_features(file: &GltfFile, mat: &gltf::Material) -> Vec<String> {
    let raw_materials = &file.raw.materials;
    let pbr = mat.pbr_metallic_roughness();
    let mut features = Vec::new();
    let keys = |v: Option<&serde_json::Value>| -> Vec<String> {
        v.and_then(|v| v.get("extensions")?.as_object().cloned())
            .map(|o| o.keys().cloned().collect())
            .unwrap_or_default()
    };
    if let Some(info) = pbr.base_color_texture() {
        let info_json = mat.index().and_then(|i| {
            raw_materials
                .get(i)?
                .get("pbrMetallicRoughness")?
                .get("baseColorTexture")
        });
        let texture_json = file.raw.textures.get(info.texture().index());
        let others = keys(info_json)
            .into_iter()
            .filter(|k| k != "KHR_texture_transform")
            .chain(keys(texture_json));
        for name in others {
            features.push(format!(
                "the extension {name} on its base colour texture (its PNG or JPEG source is drawn)"
            ));
        }
    }
    let mut note = |present: bool, what: &str| {
        if present {
            features.push(what.to_string());
        }
    };
    note(
        pbr.metallic_roughness_texture().is_some(),
        "a metallic-roughness texture",
    );
    note(mat.normal_texture().is_some(), "a normal map");
    note(mat.occlusion_texture().is_some(), "an occlusion texture");
    note(mat.emissive_texture().is_some(), "an emissive texture");
    note(
        mat.emissive_factor() != [0.0; 3],
        "emission (emissiveFactor)",
    );
    note(
        mat.alpha_mode() == gltf::material::AlphaMode::Mask,
        "alpha masking (alphaMode MASK)",
    );
    let extensions = mat
        .index()
        .and_then(|i| {
            raw_materials
                .get(i)?
                .get("extensions")?
                .as_object()
                .cloned()
        })
        .unwrap_or_default();
    for name in extensions.keys().filter(|k| *k != "KHR_materials_ior") {
        features.push(format!("the extension {name}"));
    }
    features
}

/// The material of a primitive without one, as [`map_material`] states it.
fn default_material(name: String) -> Material {
    Material {
        name,
        color: DVec3::splat(0.8),
        ..DEFAULT_MATERIAL
    }
}

/// Adds `m` to `materials` and returns its index; an identical material
/// (same name and values) already there is reused. A different material
/// with the same name gets a `#2`, `#3`, ... suffix.
pub(crate) fn push_material(materials: &mut Vec<Material>, m: Material) -> usize {
    let base = m.name.clone();
    let mut k = 1;
    loop {
        let name = if k == 1 {
            base.clone()
        } else {
            format!("{base}#{k}")
        };
        let candidate = Material {
            name: name.clone(),
            ..m.clone()
        };
        match materials.iter().position(|x| x.name == name) {
            None => {
                materials.push(candidate);
                return materials.len() - 1;
            }
            Some(i) if materials[i] == candidate => return i,
            Some(_) => k += 1,
        }
    }
}

/// The name a material goes by in messages: its name, else its index.
fn material_label(mat: &gltf::Material) -> String {
    match (mat.name(), mat.index()) {
        (Some(n), _) if !n.is_empty() => n.to_string(),
        (_, Some(i)) => i.to_string(),
        (_, None) => "default".to_string(),
    }
}

/// The `KHR_texture_transform` object on a material's base colour texture.
fn base_colour_transform_json<'f>(
    file: &'f GltfFile,
    mat: &gltf::Material,
) -> Option<&'f serde_json::Value> {
    file.raw
        .materials
        .get(mat.index()?)?
        .get("pbrMetallicRoughness")?
        .get("baseColorTexture")?
        .get("extensions")?
        .get("KHR_texture_transform")
}

/// The texture coordinate set a material's base colour texture reads (its
/// `KHR_texture_transform`'s `texCoord`, else its own), if it has one.
fn base_colour_set(file: &GltfFile, mat: &gltf::Material) -> Option<u32> {
    let info = mat.pbr_metallic_roughness().base_color_texture()?;
    let overridden = base_colour_transform_json(file, mat)
        .and_then(|t| t.get("texCoord")?.as_u64())
        .and_then(|set| u32::try_from(set).ok());
    Some(overridden.unwrap_or(info.tex_coord()))
}

/// `KHR_texture_transform` on a material's base colour texture as the map
/// of its texture coordinates, `uv' = T R S uv` (module docs): with
/// offset `(ox, oy)`, rotation `r` and scale `(sx, sy)`,
/// `[cos r sx, sin r sy, ox; -sin r sx, cos r sy, oy]`. The identity
/// without it.
fn base_colour_uv_transform(
    file: &GltfFile,
    mat: &gltf::Material,
    who: &str,
) -> Result<UvTransform, SceneError> {
    let Some(t) = base_colour_transform_json(file, mat) else {
        return Ok(UvTransform::IDENTITY);
    };
    let bad = |key: &str, expected: &str| {
        SceneError::mesh(
            &file.label,
            format!(
                "material `{who}`: KHR_texture_transform `{key}` is {}; expected {expected}",
                t.get(key).map_or("missing".to_string(), |v| v.to_string())
            ),
        )
    };
    let pair = |key: &str, default: [f64; 2]| match t.get(key) {
        None => Ok(default),
        Some(v) => match v
            .as_array()
            .map(|a| a.iter().map(|x| x.as_f64()).collect::<Vec<_>>())
        {
            Some(xs) if xs.len() == 2 && xs.iter().all(Option::is_some) => {
                Ok([xs[0].unwrap_or(0.0), xs[1].unwrap_or(0.0)])
            }
            _ => Err(bad(key, "two numbers")),
        },
    };
    let offset = pair("offset", [0.0, 0.0])?;
    let scale = pair("scale", [1.0, 1.0])?;
    let rotation = match t.get("rotation") {
        None => 0.0,
        Some(v) => v
            .as_f64()
            .ok_or_else(|| bad("rotation", "a number (radians)"))?,
    };
    let (sin, cos) = rotation.sin_cos();
    let m = [
        cos * scale[0],
        sin * scale[1],
        offset[0],
        -sin * scale[0],
        cos * scale[1],
        offset[1],
    ];
    // The renderers' level of detail takes its area scale, `|det|`.
    if !m.iter().all(|x| x.is_finite()) || !UvTransform(m).area_scale().is_finite() {
        return Err(bad(
            "scale",
            "two numbers whose product is finite (the scale of the texture's area)",
        ));
    }
    // No -0 (sin 0 times a scale): equal transforms compare and share as
    // equal.
    Ok(UvTransform(m.map(|x| x + 0.0)))
}

/// A glTF sampler as the renderers sample (module docs); glTF's defaults
/// where it says nothing: [`Sampler::GLTF_DEFAULT`].
fn sampler_of(texture: &gltf::Texture) -> Sampler {
    use gltf::texture::{MagFilter, MinFilter, WrappingMode};
    let s = texture.sampler();
    let wrap = |w: WrappingMode| match w {
        WrappingMode::Repeat => Wrap::Repeat,
        WrappingMode::ClampToEdge => Wrap::ClampToEdge,
        WrappingMode::MirroredRepeat => Wrap::MirroredRepeat,
    };
    let default = Sampler::GLTF_DEFAULT;
    let magnification = match s.mag_filter() {
        Some(MagFilter::Nearest) => Filter::Nearest,
        Some(MagFilter::Linear) => Filter::Linear,
        None => default.magnification,
    };
    let (minification, mipmap) = match s.min_filter() {
        None => (default.minification, default.mipmap),
        Some(MinFilter::Nearest) => (Filter::Nearest, None),
        Some(MinFilter::Linear) => (Filter::Linear, None),
        Some(MinFilter::NearestMipmapNearest) => (Filter::Nearest, Some(Filter::Nearest)),
        Some(MinFilter::LinearMipmapNearest) => (Filter::Linear, Some(Filter::Nearest)),
        Some(MinFilter::NearestMipmapLinear) => (Filter::Nearest, Some(Filter::Linear)),
        Some(MinFilter::LinearMipmapLinear) => (Filter::Linear, Some(Filter::Linear)),
    };
    Sampler {
        wrap_u: wrap(s.wrap_s()),
        wrap_v: wrap(s.wrap_t()),
        magnification,
        minification,
        mipmap,
    }
}

/// Where an image's bytes lie.
enum ImageSource<'f> {
    /// A file beside the glTF: its path and the URI's decoded name.
    File(PathBuf, String),
    /// A base64 data URI.
    DataUri(&'f str),
    /// A buffer view.
    View(gltf::buffer::View<'f>),
}

/// An image's name for messages: its file ("image 2 (`wood.png`)"), else
/// its name, else its index alone ("image 2").
fn image_what(image: &gltf::Image, source: &ImageSource) -> String {
    let name = match source {
        ImageSource::File(_, name) => Some(name.clone()),
        _ => image.name().filter(|n| !n.is_empty()).map(str::to_string),
    };
    match name {
        Some(n) => format!("image {} (`{n}`)", image.index()),
        None => format!("image {}", image.index()),
    }
}

/// Where `image`'s bytes lie (checked by `check_images_and_textures`, so
/// that the `gltf` crate's `source` does not panic).
fn image_source<'f>(
    file: &GltfFile,
    image: &gltf::Image<'f>,
) -> Result<ImageSource<'f>, SceneError> {
    Ok(match image.source() {
        gltf::image::Source::View { view, .. } => ImageSource::View(view),
        gltf::image::Source::Uri { uri, .. } if uri.starts_with("data:") => {
            ImageSource::DataUri(uri)
        }
        gltf::image::Source::Uri { uri, .. } => {
            if uri.contains(':') {
                return Err(SceneError::mesh(
                    &file.label,
                    format!(
                        "image {}: its uri `{uri}` is neither a file beside the glTF nor a data: URI; expected a relative file name or a data: URI",
                        image.index()
                    ),
                ));
            }
            let Ok(name) = String::from_utf8(percent_decoded_bytes(uri)) else {
                return Err(SceneError::mesh(
                    &file.label,
                    format!(
                        "image {}: its uri `{uri}` percent-decodes to bytes that are not UTF-8; expected a file name or a data: URI",
                        image.index()
                    ),
                ));
            };
            ImageSource::File(file.base.join(&name), name)
        }
    })
}

/// The bytes of an image, read (a file), decoded (a data URI) or borrowed
/// (a buffer view); `what` names it in messages.
fn image_bytes<'f>(
    file: &'f GltfFile,
    source: &ImageSource<'f>,
    what: &str,
) -> Result<Cow<'f, [u8]>, SceneError> {
    let err = |message: String| SceneError::mesh(&file.label, format!("{what} {message}"));
    match source {
        ImageSource::File(path, name) => std::fs::read(path).map(Cow::Owned).map_err(|e| {
            err(format!(
                "names the file `{name}`, which cannot be read ({}: {e}); put it beside the .gltf or fix the uri",
                path.display()
            ))
        }),
        ImageSource::DataUri(uri) => {
            use base64::Engine;
            let (header, data) = uri.split_once(',').unwrap_or((uri, ""));
            if !header.ends_with(";base64") {
                return Err(err(format!(
                    "is a data URI that is not base64 (`{}`); expected data:image/png;base64,... or data:image/jpeg;base64,...",
                    header.chars().take(60).collect::<String>()
                )));
            }
            base64::engine::general_purpose::STANDARD
                .decode(data)
                .map(Cow::Owned)
                .map_err(|e| err(format!("is a data URI that is not valid base64 ({e})")))
        }
        ImageSource::View(view) => {
            let bytes = file
                .buffers
                .get(view.buffer().index())
                .and_then(|b| b.0.get(view.offset()..view.offset().checked_add(view.length())?));
            bytes.map(Cow::Borrowed).ok_or_else(|| {
                err(format!(
                    "is in buffer view {}, which runs past the end of buffer {}",
                    view.index(),
                    view.buffer().index()
                ))
            })
        }
    }
}

/// A material's base colour texture as its pattern (module docs), from
/// `store`, which decodes each image once and holds the bytes of all to
/// `limits` together with `geometry` (the file's). A warning per image
/// whose alpha is not all opaque.
fn base_colour_texture(
    file: &GltfFile,
    mat: &gltf::Material,
    store: &mut TextureStore,
    limits: &LoadLimits,
    geometry: u64,
    warnings: &mut Vec<String>,
) -> Result<Option<Pattern>, SceneError> {
    let Some(info) = mat.pbr_metallic_roughness().base_color_texture() else {
        return Ok(None);
    };
    let who = material_label(mat);
    let texture = info.texture();
    let image = texture.source();
    let source = image_source(file, &image)?;
    let what = image_what(&image, &source);
    let key = match &source {
        ImageSource::File(path, _) => {
            ImageKey::File(std::fs::canonicalize(path).unwrap_or_else(|_| path.clone()))
        }
        _ => ImageKey::Embedded {
            label: file.label.clone(),
            index: image.index(),
        },
    };
    let request = TextureRequest {
        key,
        name: format!("{} {what}", file.label),
        sampler: sampler_of(&texture),
        transform: base_colour_uv_transform(file, mat, &who)?,
    };
    let fail = |failure: ImageFailure| {
        let message = format!(
            "{what} (the base colour texture of material `{who}`) {}",
            failure.message()
        );
        match failure {
            ImageFailure::TooLarge(_) => SceneError::TooLarge {
                file: file.label.clone(),
                message,
            },
            ImageFailure::Unreadable(_) => SceneError::mesh(&file.label, message),
        }
    };
    let fetched = store.texture(
        request,
        limits,
        geometry,
        || image_bytes(file, &source, &what),
        fail,
    )?;
    if fetched.newly_translucent {
        warnings.push(format!(
            "{}: {what} has alpha below 1 (not all opaque); shadelab uses its RGB and ignores the alpha",
            file.label
        ));
    }
    Ok(Some(Pattern::Image(fetched.texture)))
}

/// What a glTF file contributes to a scene.
struct Contents<'a> {
    objects: Vec<Object>,
    /// The nodes that carry a camera or a light, with their world matrices,
    /// in depth-first order.
    nodes: Vec<(gltf::Node<'a>, DMat4)>,
}

/// The geometry the file's nodes instance, counted from accessor sizes
/// alone: what loading it would build.
fn instanced_size(file: &GltfFile) -> Result<GeometrySize, SceneError> {
    let mut size = GeometrySize::default();
    walk_nodes(file, |node, _| {
        for prim in node.mesh().iter().flat_map(|m| m.primitives()) {
            let Some(positions) = prim.get(&gltf::Semantic::Positions) else {
                continue;
            };
            let vertices = positions.count() as u64;
            let corners = prim.indices().map_or(vertices, |i| i.count() as u64);
            size.add(1, vertices, corners / 3);
            // Counted whenever the file has them: coordinates are read only
            // for a texture or pattern, which is not known here, so this may
            // count more.
            let attributed = prim.attributes().any(|(s, _)| {
                matches!(s, gltf::Semantic::Colors(0) | gltf::Semantic::TexCoords(_))
            });
            if attributed {
                size.add_attributed(vertices, corners / 3);
            }
        }
        Ok(())
    })?;
    Ok(size)
}

/// How one glTF file is being loaded into a scene: the limit, and the
/// scene's textures so far.
pub(crate) struct Loading<'s> {
    pub limits: &'s LoadLimits,
    pub textures: &'s mut TextureStore,
}

fn contents<'a>(
    file: &'a GltfFile,
    post: DMat4,
    material_override: Option<usize>,
    materials: &mut Vec<Material>,
    warnings: &mut Vec<String>,
    loading: &mut Loading,
) -> Result<Contents<'a>, SceneError> {
    let limits = loading.limits;
    let size = instanced_size(file)?;
    limits.check(&file.label, &size)?;
    let geometry = size.model_bytes();
    let mut per_file: HashMap<Option<usize>, usize> = HashMap::new();
    let mut objects = Vec::with_capacity(size.objects as usize);
    let mut nodes = Vec::new();
    walk_nodes(file, |node, world| {
        if node.camera().is_some() || node.light().is_some() {
            nodes.push((node.clone(), *world));
        }
        let Some(mesh) = node.mesh() else {
            return Ok(());
        };
        for prim in mesh.primitives() {
            // Texture coordinates are read only for a material that uses
            // them: a TOML material with a pattern or texture given to the
            // whole file (TEXCOORD_0), or the file's own material with a
            // base colour texture (its set).
            let uv_use = match material_override {
                Some(i) => materials[i].pattern.as_ref().map(|p| UvUse {
                    set: 0,
                    user: format!(
                        "the {} of material `{}`",
                        if p.image().is_some() {
                            "texture"
                        } else {
                            "pattern"
                        },
                        materials[i].name
                    ),
                }),
                None => {
                    let mat = prim.material();
                    base_colour_set(file, &mat).map(|set| UvUse {
                        set,
                        user: format!(
                            "the base colour texture of material `{}`",
                            material_label(&mat)
                        ),
                    })
                }
            };
            let at = post * *world;
            let Some(tri) = primitive_mesh(file, &mesh, &prim, at, uv_use.as_ref(), warnings)?
            else {
                continue;
            };
            let material = match material_override {
                Some(i) => i,
                None => {
                    let mat = prim.material();
                    let key = mat.index();
                    match per_file.get(&key) {
                        Some(&i) => i,
                        None => {
                            let m = match key {
                                Some(_) => {
                                    let label = material_label(&mat);
                                    let unmodelled = unmodelled_features(file, &mat);
                                    if !unmodelled.is_empty() {
                                        warnings.push(format!(
                                            "{}: material `{label}` has {}, which shadelab does not model; it renders without {}",
                                            file.label,
                                            unmodelled.join(", "),
                                            if unmodelled.len() == 1 { "it" } else { "them" }
                                        ));
                                    }
                                    let mut m = map_material(
                                        &file.label,
                                        format!("{}/{label}", file.stem),
                                        &mat,
                                        &file.raw.materials,
                                    )?;
                                    m.pattern = base_colour_texture(
                                        file,
                                        &mat,
                                        loading.textures,
                                        limits,
                                        geometry,
                                        warnings,
                                    )?;
                                    m
                                }
                                None => default_material(format!("{}/default", file.stem)),
                            };
                            let i = push_material(materials, m);
                            per_file.insert(key, i);
                            i
                        }
                    }
                }
            };
            objects.push(Object {
                shape: Shape::Mesh(tri),
                material,
            });
        }
        Ok(())
    })?;
    if objects.is_empty() {
        return Err(SceneError::mesh(
            &file.label,
            "contains no triangle mesh in its scene; expected at least one mesh primitive with mode TRIANGLES",
        ));
    }
    Ok(Contents { objects, nodes })
}

/// Loads every mesh of the glTF file at `path` for a TOML `mesh` object:
/// world transform `post * node_world`, materials either `material_override`
/// or the file's own (added to `materials`). Returns the objects.
pub(crate) fn load_meshes(
    path: &Path,
    post: DMat4,
    material_override: Option<usize>,
    materials: &mut Vec<Material>,
    warnings: &mut Vec<String>,
    loading: &mut Loading,
) -> Result<Vec<Object>, SceneError> {
    let file = open(path)?;
    Ok(contents(&file, post, material_override, materials, warnings, loading)?.objects)
}

/// Loads a glTF file as a whole scene (rules in the crate docs of `scene`):
/// its meshes, the first perspective camera of the node tree (else a camera
/// framing the bounding box), and its point lights.
pub(crate) fn load_scene(path: &Path, limits: &LoadLimits) -> Result<Scene, SceneError> {
    scene_of(&open(path)?, limits)
}

/// A glTF or GLB held in memory as a whole scene, as
/// [`scene::load_within`](crate::scene::load_within) reads a file; `label`
/// names it in messages, external buffers are read from `base`.
pub fn scene_from_slice(
    bytes: &[u8],
    label: &str,
    base: &Path,
    limits: &LoadLimits,
) -> Result<Scene, SceneError> {
    let file = parse(bytes, label.to_string(), "scene".to_string(), base)?;
    scene_of(&file, limits)
}

fn scene_of(file: &GltfFile, limits: &LoadLimits) -> Result<Scene, SceneError> {
    let mut materials = Vec::new();
    let mut warnings = Vec::new();
    let mut textures = TextureStore::default();
    let Contents { objects, nodes } = contents(
        file,
        DMat4::IDENTITY,
        None,
        &mut materials,
        &mut warnings,
        &mut Loading {
            limits,
            textures: &mut textures,
        },
    )?;

    let (mut lo, mut hi) = (DVec3::splat(f64::INFINITY), DVec3::splat(f64::NEG_INFINITY));
    for o in &objects {
        if let Shape::Mesh(m) = &o.shape {
            for p in &m.positions {
                lo = lo.min(*p);
                hi = hi.max(*p);
            }
        }
    }
    let center = (lo + hi) * 0.5;

    let mut camera = None;
    for (node, world) in &nodes {
        let Some(cam) = node.camera() else { continue };
        let gltf::camera::Projection::Perspective(persp) = cam.projection() else {
            continue;
        };
        let fov = f64::from(persp.yfov()).to_degrees();
        let position = world.transform_point3(DVec3::ZERO);
        let forward = world.transform_vector3(DVec3::NEG_Z).normalize_or_zero();
        let up = world.transform_vector3(DVec3::Y).normalize_or_zero();
        let usable = fov > 0.0
            && fov < 180.0
            && position.is_finite()
            && forward != DVec3::ZERO
            && up.cross(forward).length() > 1e-9;
        if !usable {
            warnings.push(format!(
                "{}: camera on {} is unusable (field of view {fov} degrees or a degenerate node transform); it was ignored",
                file.label,
                node_name(node)
            ));
            continue;
        }
        camera = Some(Camera {
            position,
            look_at: position + forward,
            up,
            fov_y_deg: fov,
        });
        break;
    }
    let camera = camera.unwrap_or_else(|| {
        let fov = DEFAULT_FOV_Y_DEG;
        let radius = ((hi - lo).length() * 0.5).max(1e-6);
        let distance = radius / (fov.to_radians() * 0.5).sin();
        Camera {
            position: center + DVec3::Z * distance,
            look_at: center,
            up: DVec3::Y,
            fov_y_deg: fov,
        }
    });

    let mut lights = Vec::new();
    for (node, world) in &nodes {
        let Some(light) = node.light() else { continue };
        match light.kind() {
            gltf::khr_lights_punctual::Kind::Point => {
                let intensity = f32x3(light.color()) * f64::from(light.intensity());
                let position = world.transform_point3(DVec3::ZERO);
                if !intensity.is_finite() || intensity.min_element() < 0.0 || !position.is_finite()
                {
                    return Err(SceneError::mesh(
                        &file.label,
                        format!(
                            "point light on {} has a negative or non-finite intensity or position; expected finite values >= 0",
                            node_name(node)
                        ),
                    ));
                }
                if let Some(range) = light.range() {
                    warnings.push(format!(
                        "{}: the point light on {} has range {range}, which is ignored: lights fall off as Il / (d + k) (docs/lighting-model.md)",
                        file.label,
                        node_name(node)
                    ));
                }
                lights.push(PointLight {
                    position,
                    intensity,
                });
            }
            other => warnings.push(format!(
                "{}: {} light on {} is not supported (only point lights are); it was skipped",
                file.label,
                match other {
                    gltf::khr_lights_punctual::Kind::Directional => "directional",
                    _ => "spot",
                },
                node_name(node)
            )),
        }
    }
    if lights.is_empty() {
        let d = (camera.position - center).length().max(1e-6);
        lights.push(PointLight {
            position: camera.position,
            intensity: DVec3::splat(d),
        });
        warnings.push(format!(
            "{}: the file has no point light; added one at the camera with intensity {d:.3} so the scene is lit",
            file.label
        ));
    }

    Ok(Scene {
        camera,
        image: ImageSettings::default(),
        lighting: Lighting::default(),
        lights,
        materials,
        objects,
        render: RenderSettings::default(),
        lighting_hook: None,
        warnings,
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::path::PathBuf;

    fn fixture(name: &str) -> PathBuf {
        PathBuf::from(env!("CARGO_MANIFEST_DIR"))
            .join("tests/data")
            .join(name)
    }

    struct Loaded {
        objects: Vec<Object>,
        materials: Vec<Material>,
        warnings: Vec<String>,
    }

    fn meshes(path: &Path, post: DMat4) -> Result<Loaded, SceneError> {
        let mut materials = Vec::new();
        let mut warnings = Vec::new();
        let objects = load_meshes(
            path,
            post,
            None,
            &mut materials,
            &mut warnings,
            &mut Loading {
                limits: &LoadLimits::default(),
                textures: &mut TextureStore::default(),
            },
        )?;
        Ok(Loaded {
            objects,
            materials,
            warnings,
        })
    }

    fn only_mesh(l: &Loaded) -> &TriangleMesh {
        assert_eq!(l.objects.len(), 1);
        match &l.objects[0].shape {
            Shape::Mesh(m) => m,
            other => panic!("{other:?}"),
        }
    }

    fn err_of(path: &Path) -> String {
        match meshes(path, DMat4::IDENTITY) {
            Ok(_) => panic!("{} should not load", path.display()),
            Err(e) => e.to_string(),
        }
    }

    /// Geometric normals agree with the vertex normals, which are unit.
    fn assert_winding_matches_normals(m: &TriangleMesh) {
        for t in &m.triangles {
            let [a, b, c] = t.map(|i| m.positions[i as usize]);
            let g = (b - a).cross(c - a);
            for &i in t {
                let n = m.normals[i as usize];
                assert!((n.length() - 1.0).abs() < 1e-12);
                assert!(g.dot(n) > 0.0, "triangle {t:?} disagrees with normal {n}");
            }
        }
    }

    /// Writes a glTF with an external .bin: f32 positions, optional f32
    /// normals, optional u32 indices. `patch` edits the JSON afterwards.
    fn write_gltf(
        dir: &Path,
        name: &str,
        positions: &[[f32; 3]],
        normals: Option<&[[f32; 3]]>,
        indices: Option<&[u32]>,
        patch: impl FnOnce(&mut serde_json::Value),
    ) -> PathBuf {
        use serde_json::json;
        let mut bin = Vec::new();
        let mut views = Vec::new();
        let mut accessors = Vec::new();
        let mut attributes = serde_json::Map::new();
        let mut add_vec3 = |bin: &mut Vec<u8>, data: &[[f32; 3]]| {
            let offset = bin.len();
            for v in data {
                for c in v {
                    bin.extend_from_slice(&c.to_le_bytes());
                }
            }
            views.push(json!({"buffer": 0, "byteOffset": offset, "byteLength": data.len() * 12}));
            accessors.push(json!({"bufferView": views.len() - 1, "componentType": 5126,
                                  "count": data.len(), "type": "VEC3",
                                  "min": [-1e9, -1e9, -1e9], "max": [1e9, 1e9, 1e9]}));
            accessors.len() - 1
        };
        attributes.insert("POSITION".into(), json!(add_vec3(&mut bin, positions)));
        if let Some(n) = normals {
            attributes.insert("NORMAL".into(), json!(add_vec3(&mut bin, n)));
        }
        let mut prim = json!({"attributes": attributes});
        if let Some(idx) = indices {
            let offset = bin.len();
            for i in idx {
                bin.extend_from_slice(&i.to_le_bytes());
            }
            views.push(json!({"buffer": 0, "byteOffset": offset, "byteLength": idx.len() * 4}));
            accessors.push(json!({"bufferView": views.len() - 1, "componentType": 5125,
                                  "count": idx.len(), "type": "SCALAR"}));
            prim["indices"] = json!(accessors.len() - 1);
        }
        let bin_name = format!("{name}.bin");
        std::fs::write(dir.join(&bin_name), &bin).unwrap();
        let mut doc = json!({
            "asset": {"version": "2.0"},
            "scene": 0,
            "scenes": [{"nodes": [0]}],
            "nodes": [{"mesh": 0}],
            "meshes": [{"name": "m", "primitives": [prim]}],
            "buffers": [{"uri": bin_name, "byteLength": bin.len()}],
            "bufferViews": views,
            "accessors": accessors,
        });
        patch(&mut doc);
        let path = dir.join(format!("{name}.gltf"));
        std::fs::write(&path, serde_json::to_string_pretty(&doc).unwrap()).unwrap();
        path
    }

    /// What the model does not take is announced, one line per material
    /// naming each feature (issue 31: the Duck rendered white-grey without
    /// a word). Vertex colours and base colour textures are modelled now
    /// and say nothing; a normal map's image is never read.
    #[test]
    fn unmodelled_material_features_are_announced() {
        let dir = tempfile::tempdir().unwrap();
        let tri = [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]];
        let p = write_gltf(dir.path(), "painted", &tri, None, None, |d| {
            d["images"] = serde_json::json!([{"uri": "duck.png"}]);
            d["textures"] = serde_json::json!([{"source": 0}]);
            d["materials"] = serde_json::json!([{
                "name": "duck",
                "normalTexture": {"index": 0},
                "emissiveFactor": [0.5, 0.0, 0.0],
                "extensions": {"KHR_materials_ior": {"ior": 1.4}, "KHR_materials_clearcoat": {}}
            }]);
            d["meshes"][0]["primitives"][0]["material"] = 0.into();
            // COLOR_0 reuses the positions' accessor (VEC3 floats).
            d["meshes"][0]["primitives"][0]["attributes"]["COLOR_0"] = 0.into();
        });
        let l = meshes(&p, DMat4::IDENTITY).unwrap();
        let material: Vec<&String> = l
            .warnings
            .iter()
            .filter(|w| w.contains("material `duck`"))
            .collect();
        assert_eq!(material.len(), 1, "{:?}", l.warnings);
        for feature in [
            "a normal map",
            "emission (emissiveFactor)",
            "the extension KHR_materials_clearcoat",
        ] {
            assert!(material[0].contains(feature), "{feature}: {}", material[0]);
        }
        assert!(
            !material[0].contains("KHR_materials_ior") && !material[0].contains("base colour"),
            "{}",
            material[0]
        );
        assert!(
            material[0].ends_with("it renders without them"),
            "{}",
            material[0]
        );
        assert_eq!(l.warnings.len(), 1, "{:?}", l.warnings);
        let m = only_mesh(&l);
        assert_eq!(m.colors, m.positions, "COLOR_0 read as the floats it is");
        // A plain material says nothing.
        let plain = write_gltf(dir.path(), "plain", &tri, None, None, |d| {
            d["materials"] = serde_json::json!([{"name": "grey"}]);
            d["meshes"][0]["primitives"][0]["material"] = 0.into();
        });
        assert!(meshes(&plain, DMat4::IDENTITY).unwrap().warnings.is_empty());
    }

    /// The fixture `name` (tests/data) with `patch` applied, loaded from a
    /// scratch folder: what it gives, or its error's message.
    fn load_patched_fixture(
        name: &str,
        patch: impl FnOnce(&mut serde_json::Value),
    ) -> Result<Loaded, String> {
        load_patched(&fixture(name), patch)
    }

    /// The glTF JSON at `path` with `patch` applied, written to a folder
    /// of its own (its buffers and images must be data URIs), and what
    /// loading it says.
    fn load_patched(
        path: &std::path::Path,
        patch: impl FnOnce(&mut serde_json::Value),
    ) -> Result<Loaded, String> {
        let text = std::fs::read_to_string(path).unwrap();
        let mut doc: serde_json::Value = serde_json::from_str(&text).unwrap();
        patch(&mut doc);
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("patched.gltf");
        std::fs::write(&path, doc.to_string()).unwrap();
        meshes(&path, DMat4::IDENTITY).map_err(|e| e.to_string())
    }

    /// Extensions on the base colour texture other than the transform are
    /// named (their PNG source is drawn); the transform is not.
    #[test]
    fn other_extensions_on_the_base_colour_texture_are_announced() {
        let l = load_patched_fixture("textured_datauri.gltf", |d| {
            d["textures"][0]["extensions"] = serde_json::json!({"EXT_texture_webp": {"source": 0}});
            d["materials"][0]["pbrMetallicRoughness"]["baseColorTexture"]["extensions"]
                ["MSFT_lod"] = serde_json::json!({});
        })
        .unwrap();
        assert_eq!(l.warnings.len(), 1, "{:?}", l.warnings);
        let w = &l.warnings[0];
        for part in [
            "patched.gltf: material `painted` has ",
            "the extension MSFT_lod on its base colour texture (its PNG or JPEG source is drawn)",
            "the extension EXT_texture_webp on its base colour texture",
        ] {
            assert!(w.contains(part), "{w}\nshould say: {part}");
        }
        assert!(!w.contains("KHR_texture_transform"), "{w}");
        assert!(matches!(&l.materials[0].pattern, Some(Pattern::Image(_))));
    }

    /// An image's buffer view must lie inside its buffer; a texture's
    /// transform must be numbers.
    #[test]
    fn an_image_past_its_buffer_or_a_bad_transform_is_refused() {
        let e = load_patched_fixture("textured_datauri.gltf", |d| {
            let views = d["bufferViews"].as_array_mut().unwrap();
            views.push(serde_json::json!({"buffer": 0, "byteOffset": 16, "byteLength": 1_000_000}));
            let view = views.len() - 1;
            d["images"][0] = serde_json::json!({"bufferView": view, "mimeType": "image/png"});
        })
        .err()
        .expect("an error");
        assert!(
            e.ends_with(
                "patched.gltf: image 0 is in buffer view 4, which runs past the end of buffer 0"
            ),
            "{e}"
        );
        let e = load_patched_fixture("textured_datauri.gltf", |d| {
            d["materials"][0]["pbrMetallicRoughness"]["baseColorTexture"]["extensions"]
                ["KHR_texture_transform"]["scale"] = serde_json::json!([1e150, 1e150]);
            d["materials"][0]["pbrMetallicRoughness"]["baseColorTexture"]["extensions"]
                ["KHR_texture_transform"]["rotation"] = serde_json::json!(0.0);
        });
        // 1e150 is finite in f64 (the transform's precision; the gltf
        // crate's f32 would make it infinite), and so is the area's scale.
        let l = e.unwrap();
        let Some(Pattern::Image(image)) = &l.materials[0].pattern else {
            panic!("{:?}", l.materials[0].pattern)
        };
        assert_eq!(image.transform.0[0], 1e150);
        let e = load_patched_fixture("textured_datauri.gltf", |d| {
            d["materials"][0]["pbrMetallicRoughness"]["baseColorTexture"]["extensions"]
                ["KHR_texture_transform"]["scale"] = serde_json::json!([1e200, 1e200]);
        })
        .err()
        .expect("an error");
        assert!(
            e.contains("material `painted`: KHR_texture_transform `scale` is [1e+200,1e+200]; expected two numbers whose product is finite"),
            "{e}"
        );
    }

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

    #[test]
    fn indexed_triangle_with_normals_and_mapped_material() {
        let l = meshes(&fixture("tri_indexed.gltf"), DMat4::IDENTITY).unwrap();
        let m = only_mesh(&l);
        assert_eq!(m.positions, vec![DVec3::ZERO, DVec3::X, DVec3::Y]);
        assert_eq!(m.normals, vec![DVec3::Z; 3]);
        assert_eq!(m.triangles, vec![[0, 1, 2]]);
        assert!(l.warnings.is_empty(), "{:?}", l.warnings);
        // metallic 0, roughness 0.5, extras p = 64 and ka = 0.1.
        let mat = &l.materials[l.objects[0].material];
        assert_eq!(mat.name, "tri_indexed/red");
        assert_eq!(mat.color, DVec3::X);
        assert_eq!(mat.kd, 0.8);
        assert!((mat.ks - 0.02).abs() < 1e-12);
        assert_eq!(mat.p, 64.0, "extras override the computed 30");
        assert_eq!(mat.ka, 0.1, "extras override");
        assert_eq!((mat.kr, mat.kt, mat.ior), (0.0, 0.0, 1.0));
    }

    #[test]
    fn unindexed_primitive_uses_sequential_indices_and_default_material() {
        let l = meshes(&fixture("tri_unindexed.gltf"), DMat4::IDENTITY).unwrap();
        let m = only_mesh(&l);
        assert_eq!(m.triangles, vec![[0, 1, 2], [3, 4, 5]]);
        assert_eq!(m.positions.len(), 6);
        let mat = &l.materials[l.objects[0].material];
        assert_eq!(mat.name, "tri_unindexed/default");
        assert_eq!(
            (mat.color, mat.ka, mat.kd, mat.ks, mat.p),
            (DVec3::splat(0.8), 0.2, 0.8, 0.0, 32.0)
        );
    }

    #[test]
    fn hierarchy_composes_node_transforms() {
        let l = meshes(&fixture("hierarchy.gltf"), DMat4::IDENTITY).unwrap();
        let m = only_mesh(&l);
        let expected = [
            DVec3::new(1.0, 4.0, 3.0),
            DVec3::new(-1.0, 2.0, 3.0),
            DVec3::new(1.0, 2.0, 5.0),
        ];
        for (p, e) in m.positions.iter().zip(expected) {
            assert!((*p - e).length() < 1e-9, "{p} != {e}");
        }
        // Computed normals of a single triangle are its face normal.
        let face = (expected[1] - expected[0])
            .cross(expected[2] - expected[0])
            .normalize();
        for n in &m.normals {
            assert!((*n - face).length() < 1e-9);
        }
        // A post transform (the TOML mesh object's T * R * S) applies after.
        let post = DMat4::from_translation(DVec3::new(0.0, 0.0, -3.0));
        let l = meshes(&fixture("hierarchy.gltf"), post).unwrap();
        assert!((only_mesh(&l).positions[2] - DVec3::new(1.0, 2.0, 2.0)).length() < 1e-9);
    }

    #[test]
    fn missing_normals_are_area_weighted() {
        let l = meshes(&fixture("no_normals.gltf"), DMat4::IDENTITY).unwrap();
        let m = only_mesh(&l);
        assert_eq!(m.triangles.len(), 4);
        let expected = [DVec3::splat(-1.0).normalize(), DVec3::X, DVec3::Y, DVec3::Z];
        for (n, e) in m.normals.iter().zip(expected) {
            assert!((*n - e).length() < 1e-12, "{n} != {e}");
        }
    }

    #[test]
    fn mirrored_node_flips_the_winding() {
        let l = meshes(&fixture("mirrored.gltf"), DMat4::IDENTITY).unwrap();
        let m = only_mesh(&l);
        assert!(m.positions.contains(&DVec3::new(-1.0, 0.0, 0.0)));
        assert_eq!(m.normals, vec![DVec3::Z; 3]);
        assert_winding_matches_normals(m);
        assert_eq!(m.triangles, vec![[0, 2, 1]]);
    }

    #[test]
    fn degenerate_triangles_are_dropped_with_a_warning() {
        let l = meshes(&fixture("degenerate.gltf"), DMat4::IDENTITY).unwrap();
        let m = only_mesh(&l);
        assert_eq!(m.triangles.len(), 2);
        assert_eq!(
            m.positions.len(),
            4,
            "the unused midpoint vertex is removed"
        );
        assert_eq!(m.normals, vec![DVec3::Z; 4]);
        assert_eq!(l.warnings.len(), 1);
        assert!(
            l.warnings[0].contains("dropped 2 degenerate"),
            "{:?}",
            l.warnings
        );
        assert!(l.warnings[0].contains("degenerate.gltf"));
    }

    #[test]
    fn degenerate_rule_is_relative() {
        let tiny = [
            DVec3::ZERO,
            DVec3::new(1e-9, 0.0, 0.0),
            DVec3::new(0.0, 1e-9, 0.0),
        ];
        assert!(!is_degenerate(&tiny, [0, 1, 2]), "small but well-shaped");
        let sliver = [
            DVec3::ZERO,
            DVec3::new(1.0, 0.0, 0.0),
            DVec3::new(2.0, 1e-14, 0.0),
        ];
        assert!(is_degenerate(&sliver, [0, 1, 2]));
        assert!(is_degenerate(&tiny, [0, 0, 2]));
    }

    #[test]
    fn glb_cube_loads() {
        let l = meshes(&fixture("cube.glb"), DMat4::IDENTITY).unwrap();
        let m = only_mesh(&l);
        assert_eq!((m.positions.len(), m.triangles.len()), (24, 12));
        assert_winding_matches_normals(m);
        let mat = &l.materials[0];
        assert_eq!(mat.name, "cube/ochre");
        assert!(
            (mat.p - 30.0).abs() < 1e-9,
            "roughness 0.5 -> p = 2 / 0.0625 - 2"
        );
    }

    #[test]
    fn broken_files_are_errors_naming_the_file() {
        let e = err_of(&fixture("nan_position.gltf"));
        for part in [
            "nan_position.gltf",
            "mesh `broken`",
            "POSITION",
            "accessor 0",
            "vertex 1",
            "finite",
        ] {
            assert!(e.contains(part), "`{part}` missing from: {e}");
        }
        let e = err_of(&fixture("corrupt.glb"));
        assert!(
            e.contains("corrupt.glb") && e.contains("not a valid"),
            "{e}"
        );
        let dir = tempfile::tempdir().unwrap();
        for (name, bytes) in [
            ("empty.glb", &b""[..]),
            ("short.glb", &b"glTF\x02\0\0\0\x05\0\0\0"[..]),
            ("text.gltf", &b"{ not json"[..]),
            ("v1.glb", &b"glTF\x01\0\0\0\x20\0\0\0"[..]),
        ] {
            let p = dir.path().join(name);
            std::fs::write(&p, bytes).unwrap();
            let e = err_of(&p);
            assert!(e.contains(name), "{e}");
        }
        let e = err_of(&dir.path().join("absent.gltf"));
        assert!(
            e.contains("absent.gltf") && e.contains("cannot read"),
            "{e}"
        );
    }

    #[test]
    fn bad_geometry_is_an_error() {
        let dir = tempfile::tempdir().unwrap();
        let tri = [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]];
        let p = write_gltf(dir.path(), "oob", &tri, None, Some(&[0, 1, 7]), |_| {});
        let e = err_of(&p);
        assert!(
            e.contains("oob.gltf") && e.contains("index 7") && e.contains("3 vertices"),
            "{e}"
        );
        let p = write_gltf(
            dir.path(),
            "flat",
            &tri,
            None,
            Some(&[0, 1, 1, 2, 2, 2]),
            |_| {},
        );
        let e = err_of(&p);
        assert!(
            e.contains("flat.gltf") && e.contains("no non-degenerate triangle"),
            "{e}"
        );
        let p = write_gltf(dir.path(), "nobin", &tri, None, None, |d| {
            d["buffers"][0]["uri"] = "missing.bin".into();
        });
        let e = err_of(&p);
        assert!(
            e.contains("nobin.gltf") && e.contains("`missing.bin`, which does not exist"),
            "{e}"
        );
        let p = write_gltf(dir.path(), "vec2", &tri, None, None, |d| {
            d["accessors"][0]["type"] = "VEC2".into();
        });
        let e = err_of(&p);
        assert!(e.contains("vec2.gltf") && e.contains("POSITION"), "{e}");
        let p = write_gltf(dir.path(), "toolong", &tri, None, None, |d| {
            d["accessors"][0]["count"] = 1000.into();
        });
        let e = err_of(&p);
        assert!(e.contains("toolong.gltf"), "{e}");
        let p = write_gltf(dir.path(), "zeroscale", &tri, None, None, |d| {
            d["nodes"][0]["scale"] = serde_json::json!([1.0, 0.0, 1.0]);
        });
        let e = err_of(&p);
        assert!(
            e.contains("zeroscale.gltf") && e.contains("no triangle mesh"),
            "{e}"
        );
        let p = write_gltf(dir.path(), "badref", &tri, None, None, |d| {
            d["meshes"][0]["primitives"][0]["attributes"]["POSITION"] = 9.into();
        });
        let e = err_of(&p);
        assert!(e.contains("badref.gltf") && e.contains("accessor 9"), "{e}");
        let p = write_gltf(dir.path(), "cycle", &tri, None, None, |d| {
            d["nodes"] = serde_json::json!([{"mesh": 0, "children": [1]}, {"children": [0]}]);
        });
        let e = err_of(&p);
        assert!(
            e.contains("cycle.gltf") && e.contains("more than once"),
            "{e}"
        );
        let p = write_gltf(dir.path(), "dag", &tri, None, None, |d| {
            d["nodes"] = serde_json::json!([{"children": [1, 2]}, {"children": [2]}, {"mesh": 0}]);
        });
        let e = err_of(&p);
        assert!(e.contains("dag.gltf") && e.contains("node 2"), "{e}");
    }

    #[test]
    fn zero_or_nan_stored_normals_are_recomputed() {
        let dir = tempfile::tempdir().unwrap();
        let tri = [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]];
        let normals = [[0.0, 0.0, 0.0], [f32::NAN, 0.0, 1.0], [0.0, 0.0, 2.0]];
        let p = write_gltf(dir.path(), "zn", &tri, Some(&normals), None, |_| {});
        let l = meshes(&p, DMat4::IDENTITY).unwrap();
        assert_eq!(only_mesh(&l).normals, vec![DVec3::Z; 3]);
    }

    #[test]
    fn extras_must_be_numbers() {
        let dir = tempfile::tempdir().unwrap();
        let tri = [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]];
        let p = write_gltf(dir.path(), "extras", &tri, None, None, |d| {
            d["materials"] =
                serde_json::json!([{"name": "shiny", "extras": {"ks": "very", "kd": 0.1}}]);
            d["meshes"][0]["primitives"][0]["material"] = 0.into();
        });
        let e = err_of(&p);
        assert!(
            e.contains("extras.gltf") && e.contains("`shiny`") && e.contains("`ks`"),
            "{e}"
        );
        let p = write_gltf(dir.path(), "extras2", &tri, None, None, |d| {
            d["materials"] = serde_json::json!([{"name": "shiny", "extras": {"ks": 0.7, "kr": 0.25, "ior": 1.7, "kt": 0.5}}]);
            d["meshes"][0]["primitives"][0]["material"] = 0.into();
        });
        let l = meshes(&p, DMat4::IDENTITY).unwrap();
        let m = &l.materials[0];
        // Default glTF material: metallic 1, roughness 1 -> kd 0.8, p 1.
        assert_eq!((m.kd, m.p), (0.8, 1.0));
        assert_eq!((m.ks, m.kr, m.ior, m.kt), (0.7, 0.25, 1.7, 0.5));
    }

    #[test]
    fn gltf_as_scene_uses_camera_and_point_light() {
        let s = crate::scene::load(&fixture("scene_with_camera_light.gltf")).unwrap();
        assert_eq!(s.camera.position, DVec3::new(0.0, 0.0, 5.0));
        assert!((s.camera.look_at - DVec3::new(0.0, 0.0, 4.0)).length() < 1e-12);
        assert_eq!(s.camera.up, DVec3::Y);
        assert!((s.camera.fov_y_deg - 0.5f64.to_degrees()).abs() < 1e-9);
        assert_eq!(s.lights.len(), 1, "the spot light is skipped");
        assert_eq!(s.lights[0].position, DVec3::new(2.0, 3.0, 4.0));
        assert_eq!(s.lights[0].intensity, DVec3::new(4.0, 2.0, 1.0));
        assert!(
            s.warnings.iter().any(|w| w.contains("spot")),
            "{:?}",
            s.warnings
        );
        // Intensity is colour times intensity (above); range is ignored, said.
        assert!(
            s.warnings
                .iter()
                .any(|w| w.contains("has range 10, which is ignored")),
            "{:?}",
            s.warnings
        );
        assert_eq!(s.objects.len(), 1);
        let m = &s.materials[s.objects[0].material];
        assert_eq!(m.name, "scene_with_camera_light/window");
        assert_eq!((m.kt, m.ior, m.p, m.kd), (0.75, 1.25, 500.0, 0.8));
        assert!((m.ks - 0.04).abs() < 1e-12);
        assert_eq!((s.image.width, s.image.height), (640, 480));
        assert_eq!(s.lighting.ambient, DVec3::splat(0.2));
        assert_eq!(s.render, RenderSettings::default());
    }

    #[test]
    fn gltf_without_camera_or_light_is_framed_and_lit() {
        let s = crate::scene::load(&fixture("cube.glb")).unwrap();
        assert_eq!(s.camera.look_at, DVec3::ZERO);
        let d = s.camera.position.z;
        let r = 0.75f64.sqrt();
        assert!((d - r / 20f64.to_radians().sin()).abs() < 1e-9);
        assert_eq!(s.camera.fov_y_deg, 40.0);
        assert_eq!(s.lights.len(), 1);
        assert_eq!(s.lights[0].position, s.camera.position);
        assert!((s.lights[0].intensity - DVec3::splat(d)).length() < 1e-12);
        assert!(s.warnings.iter().any(|w| w.contains("no point light")));
    }
}
