//! Running the commands a document shows, as a new user would: the `sh`
//! blocks of one section, line by line, from a scratch folder, with
//! `shadelab` on the PATH and the project's files (`assets/...`,
//! `examples/...`) named from the checkout.

use std::path::Path;
use std::process::{Command, Output};

/// The command lines of the `sh` blocks in the section of `text` headed
/// `heading` (up to the next heading of its level or above, `##` at
/// the most): `\`
/// continuations joined, comments kept (they carry the expected status).
pub fn section_commands(text: &str, heading: &str) -> Vec<String> {
    section_blocks(text, heading).concat()
}

/// [`section_commands`], block by block: the command lines of each `sh`
/// block of the section, in order.
pub fn section_blocks(text: &str, heading: &str) -> Vec<Vec<String>> {
    let start = text
        .find(heading)
        .unwrap_or_else(|| panic!("no section {heading:?}"));
    let level = heading.split(' ').next().unwrap_or("##");
    let rest = &text[start..];
    // The next heading of this level or above (not `# `, which inside a
    // code block is a shell comment).
    let end = (2..=level.len())
        .filter_map(|n| rest[3..].find(&format!("\n{} ", "#".repeat(n))))
        .min()
        .map_or(rest.len(), |i| i + 3);
    let section = &rest[..end];
    let mut blocks = Vec::new();
    for (k, block) in section.split("```").enumerate() {
        if k % 2 == 0 || !block.starts_with("sh\n") {
            continue;
        }
        let mut commands = Vec::new();
        let mut line = String::new();
        for part in block[3..].lines() {
            line.push_str(part.trim_end_matches('\\'));
            if !part.ends_with('\\') {
                if !line.trim().is_empty() && !line.trim().starts_with('#') {
                    commands.push(line.trim().to_string());
                }
                line.clear();
            }
        }
        blocks.push(commands);
    }
    blocks
}

/// The exit status a command's comment asks for: 1 where it says `exit 1`.
pub fn expected_status(command: &str) -> i32 {
    let comment = command.split_once(" #").map_or("", |(_, c)| c);
    if comment.contains("exit 1") {
        1
    } else {
        0
    }
}

/// Runs `command` with `sh` in `scratch`, the project's files from the
/// checkout, the validation layer on and the caches of the test suite.
pub fn run_in_scratch(scratch: &Path, command: &str) -> Output {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let bin = Path::new(env!("CARGO_BIN_EXE_shadelab"));
    let mesa_cache = Path::new(env!("CARGO_TARGET_TMPDIR")).join("mesa-shader-cache");
    let code = command.split(" #").next().unwrap();
    let code = code
        .replace(" assets/", &format!(" {}/assets/", root.display()))
        .replace("=examples/", &format!("={}/examples/", root.display()))
        .replace(" examples/", &format!(" {}/examples/", root.display()));
    Command::new("sh")
        .args(["-c", &code])
        .current_dir(scratch)
        .env(
            "PATH",
            format!(
                "{}:{}",
                bin.parent().unwrap().display(),
                std::env::var("PATH").unwrap_or_default()
            ),
        )
        .env("SHADELAB_VALIDATION", "1")
        .env("SHADELAB_CACHE_DIR", scratch.join(".cache"))
        .env("MESA_SHADER_CACHE_DIR", &mesa_cache)
        .output()
        .unwrap()
}
