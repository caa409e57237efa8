//! docs/golden.md's worked example, run as a new user would: its lines in
//! order from a scratch folder, each with the exit status its comment
//! gives; then what the page says the runs leave behind.

use crate::common;

use std::path::Path;

use common::doc_commands::{expected_status, run_in_scratch, section_commands};

#[test]
fn the_golden_worked_example_runs_from_a_scratch_folder() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let page = std::fs::read_to_string(root.join("docs/golden.md")).unwrap();
    let commands = section_commands(&page, "## A worked example");
    assert!(commands.len() >= 8, "{commands:?}");
    let scratch = tempfile::tempdir().unwrap();
    let mut outputs = Vec::new();
    for command in &commands {
        let out = run_in_scratch(scratch.path(), command);
        assert_eq!(
            out.status.code(),
            Some(expected_status(command)),
            "`{command}`: {}{}",
            String::from_utf8_lossy(&out.stdout),
            String::from_utf8_lossy(&out.stderr)
        );
        outputs.push(String::from_utf8_lossy(&out.stdout).into_owned());
    }
    // "eight images", named as the page says.
    let mut refs: Vec<String> = std::fs::read_dir(scratch.path().join("refs"))
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    refs.sort();
    assert_eq!(refs.len(), 8, "{refs:?}");
    assert_eq!(refs.first().map(String::as_str), Some("spheres-flat.png"));
    assert_eq!(
        refs.last().map(String::as_str),
        Some("whitted-raytrace.png")
    );
    // The bless run names what it rewrote: the cases that had failed.
    let failed = outputs
        .iter()
        .find(|o| o.contains("FAIL "))
        .expect("a failing run");
    let blessed = outputs
        .iter()
        .find(|o| o.contains("UPDATED"))
        .expect("a bless run");
    assert_eq!(
        failed.matches("\nFAIL ").count() + usize::from(failed.starts_with("FAIL ")),
        blessed.matches("UPDATED").count(),
        "{failed}\n{blessed}"
    );
    assert!(
        outputs.last().unwrap().contains("8 passed"),
        "{}",
        outputs.last().unwrap()
    );
}
