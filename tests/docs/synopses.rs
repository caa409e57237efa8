//! The synopses in the docs match the binary's `--help` (issue 30: check.md
//! left out modes and flags, bench's flags were documented elsewhere).
//! Every flag a command's `--help` lists is in its synopsis, and every flag
//! the synopsis shows exists.

use std::collections::BTreeSet;
use std::path::Path;
use std::process::Command;

/// The flags `shadelab COMMAND --help` lists, less `--help` and the three
/// flags every command takes (`--device`, `--max-memory`, `--quiet`).
fn help_flags(command: &str) -> BTreeSet<String> {
    let out = Command::new(env!("CARGO_BIN_EXE_shadelab"))
        .args([command, "--help"])
        .output()
        .unwrap();
    let text = String::from_utf8_lossy(&out.stdout);
    text.lines()
        .filter_map(|l| {
            let l = l.trim_start();
            let l = l.strip_prefix("-o, ").unwrap_or(l);
            l.starts_with("--")
                .then(|| l.split([' ', '<', '=']).next().unwrap().to_string())
        })
        .filter(|f| !["--help", "--device", "--max-memory", "--quiet"].contains(&f.as_str()))
        .collect()
}

/// The flags in the first code block of `doc` on the lines of `shadelab
/// COMMAND` (its first line and the indented ones after it).
fn synopsis_flags(doc: &str, command: &str) -> BTreeSet<String> {
    let text = std::fs::read_to_string(Path::new(env!("CARGO_MANIFEST_DIR")).join(doc)).unwrap();
    let block = text.split("```").nth(1).expect("a code block");
    let mut flags = BTreeSet::new();
    let mut inside = false;
    for line in block.lines() {
        if line.starts_with("shadelab ") {
            inside = line.starts_with(&format!("shadelab {command} "));
        } else if !line.starts_with(' ') {
            inside = false;
        }
        if inside {
            let code = line.split('#').next().unwrap();
            for word in code.split(|c: char| !(c.is_ascii_alphanumeric() || c == '-')) {
                if word.starts_with("--") && word.len() > 2 {
                    flags.insert(word.to_string());
                }
            }
        }
    }
    flags
}

#[test]
fn every_synopsis_lists_exactly_its_commands_flags() {
    for (doc, command) in [
        ("docs/cli.md", "render"),
        ("docs/cli.md", "diff"),
        ("docs/cli.md", "bench"),
        ("docs/cli.md", "info"),
        ("docs/cli.md", "warm"),
        ("docs/check.md", "check"),
        ("docs/golden.md", "golden"),
        ("docs/compare.md", "compare"),
    ] {
        let help = help_flags(command);
        let synopsis = synopsis_flags(doc, command);
        assert!(!help.is_empty(), "{command}: no flags read from --help");
        let missing: Vec<_> = help.difference(&synopsis).collect();
        let unknown: Vec<_> = synopsis.difference(&help).collect();
        assert!(
            missing.is_empty() && unknown.is_empty(),
            "{doc}, shadelab {command}: missing from the synopsis {missing:?}, not in --help {unknown:?}"
        );
    }
}
