//! The README's tour, run as a new user would (issue 30): every command of
//! its "A tour of the commands" section, in order, from a scratch folder,
//! with the project's files (`assets/...`, `examples/...`) named from the
//! checkout as the README says to. Each must exit 0, or 1 where its comment
//! says `exit 1`.

use crate::common;

use std::path::Path;

use common::doc_commands::{expected_status, run_in_scratch, section_commands};

#[test]
fn the_readme_tour_runs_from_a_scratch_folder() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let readme = std::fs::read_to_string(root.join("README.md")).unwrap();
    let commands = section_commands(&readme, "## A tour of the commands");
    assert!(
        commands.len() >= 10,
        "the tour has {} commands",
        commands.len()
    );
    let scratch = tempfile::tempdir().unwrap();
    for command in commands {
        let expected = expected_status(&command);
        let out = run_in_scratch(scratch.path(), &command);
        assert_eq!(
            out.status.code(),
            Some(expected),
            "`{command}`: {}",
            String::from_utf8_lossy(&out.stderr)
        );
    }
}
