//! Inputs the fuzzers (`ci/fuzz.sh`) found to crash shadelab, kept as
//! regression tests: each must now be one clear error, exit status 2,
//! through the library and through the binary.

use crate::common;

use std::path::{Path, PathBuf};

use common::cli::shadelab;
use shadelab::scene::gltf::scene_from_slice;
use shadelab::scene::LoadLimits;

fn data(name: &str) -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("tests/data/fuzz")
        .join(name)
}

/// gltf_import, after 3 million inputs: a buffer whose relative URI
/// percent-decodes to bytes that are not UTF-8 made the `gltf` crate
/// unwrap an error and panic.
#[test]
fn a_buffer_uri_that_is_not_utf8_once_decoded_is_an_error() {
    let file = data("gltf-buffer-uri-not-utf8.gltf");
    let bytes = std::fs::read(&file).unwrap();
    let e = scene_from_slice(&bytes, "found.gltf", Path::new("."), &LoadLimits::default())
        .unwrap_err()
        .to_string();
    assert!(e.contains("buffer 0") && e.contains("not UTF-8"), "{e}");
    // The smallest such file, written out, through the binary.
    let dir = tempfile::tempdir().unwrap();
    let small = r#"{"asset":{"version":"2.0"},"buffers":[{"byteLength":4,"uri":"a%AAb.bin"}]}"#;
    std::fs::write(dir.path().join("uri.gltf"), small).unwrap();
    let run = shadelab(dir.path(), &["render", "uri.gltf", "-o", "out.png"]);
    assert_eq!(run.code, 2, "{}", run.stderr);
    assert!(
        run.stderr.contains("uri.gltf: buffer 0") && !run.stderr.contains("panicked"),
        "{}",
        run.stderr
    );
    assert!(!dir.path().join("out.png").exists());
    // Percent-encoded UTF-8 is a file name like any other: it is looked
    // for, not refused.
    let fine = r#"{"asset":{"version":"2.0"},"buffers":[{"byteLength":4,"uri":"caf%C3%A9.bin"}]}"#;
    std::fs::write(dir.path().join("fine.gltf"), fine).unwrap();
    let run = shadelab(dir.path(), &["render", "fine.gltf", "-o", "out.png"]);
    assert_eq!(run.code, 2);
    // Decoded, and named (issue 30: the missing .bin was not named).
    assert!(
        run.stderr
            .contains("buffer 0 names the file `café.bin`, which does not exist"),
        "{}",
        run.stderr
    );
}
