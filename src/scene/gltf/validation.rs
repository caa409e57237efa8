//! What the `gltf` crate would panic on, or refuse with a vague message,
//! checked first in the file's raw JSON and GLB header: each refusal names
//! the mesh, sampler, image or texture and says what was expected.

use crate::scene::error::SceneError;

/// The parts of the JSON read as plain JSON: the accessor references the
/// `gltf` crate indexes before validating them, the samplers and images it
/// would refuse with a vaguer message or unwrap, and the materials and
/// textures, for extensions it is not built to read (`KHR_materials_ior`)
/// and the texture transform's values in full precision. Everything else
/// is skipped rather than kept: a file instancing a mesh two million times
/// has two million nodes, and a JSON tree of them cost about 400 bytes each.
#[derive(serde::Deserialize, Default)]
pub(super) struct RawParts {
    #[serde(default)]
    pub(super) accessors: serde_json::Value,
    #[serde(default)]
    pub(super) meshes: serde_json::Value,
    #[serde(default)]
    pub(super) materials: serde_json::Value,
    #[serde(default)]
    pub(super) samplers: serde_json::Value,
    #[serde(default)]
    pub(super) images: serde_json::Value,
    #[serde(default)]
    pub(super) textures: serde_json::Value,
}

/// Reads [`RawParts`] from a JSON document. Any valid JSON is accepted here
/// (a top-level value that is not an object reads as empty parts): telling
/// the user what a glTF file must look like is the `gltf` crate's job.
pub(super) fn raw_parts(json: &[u8]) -> serde_json::Result<RawParts> {
    let first = json.iter().find(|b| !b.is_ascii_whitespace());
    if first == Some(&b'{') {
        serde_json::from_slice(json)
    } else {
        serde_json::from_slice::<serde::de::IgnoredAny>(json).map(|_| RawParts::default())
    }
}

/// The `gltf` crate's validator indexes `accessors` with a primitive's
/// POSITION before checking it exists; check every primitive's accessor
/// references first.
pub(super) fn check_primitive_references(label: &str, raw: &RawParts) -> Result<(), SceneError> {
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
pub(super) fn check_samplers(label: &str, raw: &RawParts) -> Result<(), SceneError> {
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
pub(super) fn check_images_and_textures(label: &str, raw: &RawParts) -> Result<(), SceneError> {
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
pub(super) fn check_glb_header(label: &str, bytes: &[u8]) -> Result<(), SceneError> {
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
