//! The README's tour, run as a new user would (issue 30): every command of
//! its "A tour of the commands" section, block by block in order, each
//! block from a scratch folder of its own,
//! with the project's files (`assets/...`, `examples/...`) named from the
//! checkout as the README says to. Each must exit 0, or 1 where its comment
//! says `exit 1`.

use crate::common;

use std::path::Path;
use std::sync::atomic::{AtomicUsize, Ordering};

use common::doc_commands::{expected_status, run_in_scratch, section_blocks};

/// Each `sh` block of the tour is a user's session of its own (no block
/// reads another's files): the blocks run two at a time, each in its own
/// scratch folder and its commands in order, so that the tour (a minute
/// and a half of commands, many of them one core's work: start-up,
/// pipeline compilation, encoding) keeps both of a CI runner's cores busy.
#[test]
fn the_readme_tour_runs_from_a_scratch_folder() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let readme = std::fs::read_to_string(root.join("README.md")).unwrap();
    let blocks = section_blocks(&readme, "## A tour of the commands");
    let commands: usize = blocks.iter().map(Vec::len).sum();
    assert!(commands >= 10, "the tour has {commands} commands");
    let next = AtomicUsize::new(0);
    let failures: Vec<String> = std::thread::scope(|scope| {
        let worker = || {
            let mut failed = Vec::new();
            while let Some(block) = blocks.get(next.fetch_add(1, Ordering::Relaxed)) {
                let scratch = tempfile::tempdir().unwrap();
                for command in block {
                    let expected = expected_status(command);
                    let out = run_in_scratch(scratch.path(), command);
                    if out.status.code() != Some(expected) {
                        failed.push(format!(
                            "`{command}`: exit {:?}, expected {expected}: {}",
                            out.status.code(),
                            String::from_utf8_lossy(&out.stderr)
                        ));
                        break;
                    }
                }
            }
            failed
        };
        let workers: Vec<_> = (0..2).map(|_| scope.spawn(worker)).collect();
        workers
            .into_iter()
            .flat_map(|w| w.join().unwrap())
            .collect()
    });
    assert!(failures.is_empty(), "{}", failures.join("\n"));
}
