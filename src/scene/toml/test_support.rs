//! What the TOML parser's unit tests share: a scene parsed as a file
//! `scene.toml` would be, its error as the one line a user reads, and a
//! camera to put in front of the tables a test is about.

use std::path::{Path, PathBuf};

use super::parse;
use crate::scene::model::Scene;

pub(super) fn fixture(name: &str) -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("tests/data")
        .join(name)
}

pub(super) fn parse_ok(text: &str) -> Scene {
    parse(text, Path::new("."), "scene.toml").unwrap_or_else(|e| panic!("{e}"))
}

pub(super) fn parse_err(text: &str) -> String {
    match parse(text, Path::new("."), "scene.toml") {
        Ok(_) => panic!("expected an error for:\n{text}"),
        Err(e) => e.to_string(),
    }
}

pub(super) fn assert_has(msg: &str, parts: &[&str]) {
    for p in parts {
        assert!(msg.contains(p), "`{p}` missing from: {msg}");
    }
    assert!(!msg.contains('\n'), "not one line: {msg}");
}

pub(super) const CAMERA: &str = "[camera]\nposition = [0, 0, 5]\nlook_at = [0, 0, 0]\n";

pub(super) fn with_camera(rest: &str) -> String {
    format!("{CAMERA}{rest}")
}
