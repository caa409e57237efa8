//! The README's tour, run as a new user would (issue 30): every command of
//! its "A tour of the commands" section, in order, from a scratch folder,
//! with the project's files (`assets/...`, `examples/...`) named from the
//! checkout as the README says to. Each must exit 0, or 1 where its comment
//! says `exit 1`.

use std::path::Path;
use std::process::Command;

/// The tour's command lines: `sh` blocks of the section, `\` continuations
/// joined, comments kept (they carry the expected status).
fn tour_commands(readme: &str) -> Vec<String> {
    let start = readme
        .find("## A tour of the commands")
        .expect("the tour section");
    let rest = &readme[start..];
    let end = rest[3..].find("\n## ").map_or(rest.len(), |i| i + 3);
    let section = &rest[..end];
    let mut commands = Vec::new();
    for (k, block) in section.split("```").enumerate() {
        if k % 2 == 0 || !block.starts_with("sh\n") {
            continue;
        }
        let mut line = String::new();
        for part in block[3..].lines() {
            line.push_str(part.trim_end_matches('\\'));
            if !part.ends_with('\\') {
                if !line.trim().is_empty() {
                    commands.push(line.trim().to_string());
                }
                line.clear();
            }
        }
    }
    commands
}

#[test]
fn the_readme_tour_runs_from_a_scratch_folder() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let readme = std::fs::read_to_string(root.join("README.md")).unwrap();
    let commands = tour_commands(&readme);
    assert!(
        commands.len() >= 10,
        "the tour has {} commands",
        commands.len()
    );
    let scratch = tempfile::tempdir().unwrap();
    let bin = Path::new(env!("CARGO_BIN_EXE_shadelab"));
    let mesa_cache = Path::new(env!("CARGO_TARGET_TMPDIR")).join("mesa-shader-cache");
    for command in commands {
        let comment = command.split_once(" #").map_or("", |(_, c)| c);
        let expected = if comment.contains("exit 1") { 1 } else { 0 };
        let code = command.split(" #").next().unwrap();
        // As the README says: the project's files from the checkout.
        let code = code
            .replace(" assets/", &format!(" {}/assets/", root.display()))
            .replace("=examples/", &format!("={}/examples/", root.display()))
            .replace(" examples/", &format!(" {}/examples/", root.display()));
        let out = Command::new("sh")
            .args(["-c", &code])
            .current_dir(scratch.path())
            .env(
                "PATH",
                format!(
                    "{}:{}",
                    bin.parent().unwrap().display(),
                    std::env::var("PATH").unwrap_or_default()
                ),
            )
            .env("SHADELAB_VALIDATION", "1")
            .env("SHADELAB_CACHE_DIR", scratch.path().join(".cache"))
            .env("MESA_SHADER_CACHE_DIR", &mesa_cache)
            .output()
            .unwrap();
        assert_eq!(
            out.status.code(),
            Some(expected),
            "`{command}`: {}",
            String::from_utf8_lossy(&out.stderr)
        );
    }
}
