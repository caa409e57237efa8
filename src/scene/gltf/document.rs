//! A glTF or GLB file as a parsed document with its buffers loaded:
//! reading the bytes, the checks before the `gltf` crate parses them, and
//! the checks of the buffers' URIs before `buffers.rs` reads them.

use std::path::{Path, PathBuf};

use super::buffers::load_buffers;
use super::uris::{percent_decoded, percent_decoded_bytes};
use super::validation::{
    check_glb_header, check_images_and_textures, check_primitive_references, check_samplers,
    raw_parts, RawParts,
};
use crate::scene::error::SceneError;

/// A parsed glTF file with its buffers loaded (images are loaded by the
/// materials that use them).
pub(super) struct GltfFile {
    pub(super) label: String,
    pub(super) stem: String,
    /// Where files it names (buffers, images) lie.
    pub(super) base: PathBuf,
    pub(super) doc: gltf::Document,
    /// Every buffer's bytes, by index.
    pub(super) buffers: Vec<Vec<u8>>,
    /// The raw JSON of what the `gltf` crate does not read for us.
    pub(super) raw: RawParts,
}

pub(super) fn open(path: &Path) -> Result<GltfFile, SceneError> {
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
pub(super) fn parse(
    bytes: &[u8],
    label: String,
    stem: String,
    base: &Path,
) -> Result<GltfFile, SceneError> {
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
    let buffers = load_buffers(&label, &document, base, blob)?;
    Ok(GltfFile {
        label,
        stem,
        base: base.to_path_buf(),
        doc: document,
        buffers,
        raw,
    })
}

/// The `gltf` crate percent-decodes a relative buffer URI and unwraps the
/// result as UTF-8, so a URI such as `a%AA.bin` panics inside it (found by
/// fuzzing, `tests/cli/fuzz_regressions.rs`). Refuse such a URI first.
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

#[cfg(test)]
mod tests {
    use glam::DMat4;

    use crate::scene::gltf::test_support::{
        assert_winding_matches_normals, err_of, fixture, meshes, only_mesh,
    };

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
}
