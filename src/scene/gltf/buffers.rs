//! The glTF's buffers as bytes: the GLB's binary chunk, a base64 data URI,
//! or a file (beside the glTF, or a `file:` URI).
//!
//! Ours rather than the `gltf` crate's `import_buffers`: its `import`
//! feature also compiles the crate's image decoders (half a minute of a
//! fresh build) for images this importer decodes itself (`images.rs`).

use std::path::{Path, PathBuf};

use super::uris::percent_decoded;
use crate::scene::error::SceneError;

/// Every buffer of `document`, in order, each zero-padded to a multiple of
/// four bytes and at least its `byteLength` long. `blob` is the GLB's
/// binary chunk, which only a buffer without a URI may take.
pub(super) fn load_buffers(
    label: &str,
    document: &gltf::Document,
    base: &Path,
    mut blob: Option<Vec<u8>>,
) -> Result<Vec<Vec<u8>>, SceneError> {
    let mut buffers = Vec::with_capacity(document.buffers().len());
    for buffer in document.buffers() {
        let err = |message: String| {
            SceneError::mesh(label, format!("buffer {} {message}", buffer.index()))
        };
        let mut data = match buffer.source() {
            gltf::buffer::Source::Bin => blob.take().ok_or_else(|| {
                err("has no uri, so it is the binary chunk of a .glb, and this file has none (or an earlier buffer took it); give it a uri".into())
            })?,
            gltf::buffer::Source::Uri(uri) => read_uri(uri, base).map_err(err)?,
        };
        if data.len() < buffer.length() {
            return Err(err(format!(
                "holds {} bytes, fewer than its byteLength {}; re-export the file",
                data.len(),
                buffer.length()
            )));
        }
        // Accessors read four-byte components; a padded tail reads as zeros
        // rather than running off the end.
        data.resize(data.len().next_multiple_of(4), 0);
        buffers.push(data);
    }
    Ok(buffers)
}

/// The bytes a buffer's URI names, or what is wrong with it (the URI's
/// percent escapes were checked to decode to UTF-8 before).
fn read_uri(uri: &str, base: &Path) -> Result<Vec<u8>, String> {
    if let Some(rest) = uri.strip_prefix("data:") {
        let Some((_, data)) = rest.split_once(";base64,") else {
            let header = rest.split(',').next().unwrap_or_default();
            return Err(format!(
                "is a data URI that is not base64 (`data:{}`); expected data:application/octet-stream;base64,...",
                header.chars().take(60).collect::<String>()
            ));
        };
        use base64::Engine;
        return base64::engine::general_purpose::STANDARD
            .decode(data)
            .map_err(|e| format!("is a data URI that is not valid base64 ({e})"));
    }
    let (path, name) = if let Some(file) = uri
        .strip_prefix("file://")
        .or_else(|| uri.strip_prefix("file:"))
    {
        (PathBuf::from(file), file.to_string())
    } else if uri.contains(':') {
        return Err(format!(
            "has the uri `{uri}`, which is neither a file nor a data: URI; expected a relative file name or a data: URI"
        ));
    } else {
        let name = percent_decoded(uri);
        (base.join(&name), name)
    };
    std::fs::read(&path).map_err(|e| {
        format!(
            "names the file `{name}`, which cannot be read ({}: {e}); put it beside the .gltf or fix the uri",
            path.display()
        )
    })
}

#[cfg(test)]
mod tests {
    use super::read_uri;
    use crate::scene::gltf::test_support::load_patched_fixture;
    use std::path::Path;

    #[test]
    fn a_buffer_shorter_than_its_byte_length_or_without_a_source_is_refused() {
        let e = load_patched_fixture("textured_datauri.gltf", |d| {
            let n = d["buffers"][0]["byteLength"].as_u64().unwrap();
            d["buffers"][0]["byteLength"] = (n + 1).into();
        })
        .err()
        .expect("an error");
        assert!(
            e.contains("buffer 0 holds") && e.contains("fewer than its byteLength"),
            "{e}"
        );
        let e = load_patched_fixture("textured_datauri.gltf", |d| {
            d["buffers"][0].as_object_mut().unwrap().remove("uri");
        })
        .err()
        .expect("an error");
        assert!(e.contains("buffer 0 has no uri"), "{e}");
    }

    #[test]
    fn data_uris_decode_and_other_schemes_are_refused() {
        let base = Path::new(".");
        assert_eq!(
            read_uri("data:application/octet-stream;base64,AAECAw==", base).unwrap(),
            vec![0, 1, 2, 3]
        );
        let e = read_uri("data:application/octet-stream,0123", base).unwrap_err();
        assert!(e.contains("not base64"), "{e}");
        let e = read_uri("data:application/octet-stream;base64,A*==", base).unwrap_err();
        assert!(e.contains("not valid base64"), "{e}");
        let e = read_uri("https://example.com/a.bin", base).unwrap_err();
        assert!(e.contains("neither a file nor a data: URI"), "{e}");
    }

    #[test]
    fn files_are_read_by_relative_percent_decoded_name_or_file_uri() {
        let dir = tempfile::tempdir().unwrap();
        std::fs::write(dir.path().join("a b.bin"), [7u8, 8, 9]).unwrap();
        assert_eq!(read_uri("a%20b.bin", dir.path()).unwrap(), vec![7, 8, 9]);
        let absolute = format!("file://{}/a b.bin", dir.path().display());
        assert_eq!(read_uri(&absolute, Path::new("/")).unwrap(), vec![7, 8, 9]);
        let e = read_uri("gone.bin", dir.path()).unwrap_err();
        assert!(
            e.contains("`gone.bin`") && e.contains("cannot be read"),
            "{e}"
        );
    }
}
