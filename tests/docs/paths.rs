//! Every path the repository names exists in it, and nothing points outside
//! it. Whoever clones shadelab has only the repository: a `docs/...` that the
//! code cites, a link in the README or a script a doc tells you to run must
//! be there. Checked: relative Markdown links in every `.md`, and every
//! mention of a path under a top-level folder (`docs/`, `src/`, `ci/`, ...)
//! in the docs, the code, the shaders, the tests and the scripts.

use std::collections::BTreeSet;
use std::fs;
use std::path::{Path, PathBuf};

/// Top-level folders whose paths, mentioned anywhere, must exist.
const TOP_LEVEL: &[&str] = &[
    "docs", "src", "shaders", "ci", "tests", "assets", "examples", "fuzz",
];

/// Folders not searched: build output, and fuzzing's generated corpora.
const SKIPPED: &[&str] = &[
    "target",
    ".git",
    "fuzz/target",
    "fuzz/corpus",
    "fuzz/artifacts",
    "fuzz/coverage",
    "mutants.out",
    "mutants.out.old",
    "out",
    "check-out",
    "tests/data",
];

/// File kinds that hold prose or code naming paths.
const TEXT_EXTENSIONS: &[&str] = &["md", "rs", "glsl", "sh", "py", "toml"];

fn root() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

fn text_files(root: &Path) -> Vec<PathBuf> {
    fn walk(root: &Path, dir: &Path, out: &mut Vec<PathBuf>) {
        let Ok(entries) = fs::read_dir(dir) else {
            return;
        };
        for entry in entries.flatten() {
            let path = entry.path();
            let rel = path
                .strip_prefix(root)
                .unwrap()
                .to_string_lossy()
                .replace('\\', "/");
            // This file's own examples are not paths of the repository, nor
            // are the small trees the layout check's test builds.
            if SKIPPED.contains(&rel.as_str())
                || rel == "tests/docs/paths.rs"
                || rel == "ci/test_layout_check.py"
            {
                continue;
            }
            if path.is_dir() {
                walk(root, &path, out);
            } else if path
                .extension()
                .and_then(|e| e.to_str())
                .is_some_and(|e| TEXT_EXTENSIONS.contains(&e))
                || rel == ".ci/run"
            {
                out.push(path);
            }
        }
    }
    let mut out = Vec::new();
    walk(root, root, &mut out);
    out.sort();
    out
}

/// Relative link targets of a Markdown text: `](target)`, without the
/// anchor; web links and pure anchors are left out.
fn markdown_links(text: &str) -> Vec<String> {
    let mut links = Vec::new();
    let mut rest = text;
    while let Some(at) = rest.find("](") {
        rest = &rest[at + 2..];
        let Some(end) = rest.find(')') else { break };
        let target = rest[..end].split('#').next().unwrap().trim();
        let external = target.contains("://") || target.starts_with("mailto:");
        if !target.is_empty() && !external {
            links.push(target.to_string());
        }
    }
    links
}

/// Mentions of repository paths: a top-level folder name followed by `/`,
/// at the start of a word, up to the first character that cannot be in one
/// of our paths. A glob (`assets/*.toml`) is cut at the `*` to its folder.
fn path_mentions(text: &str) -> Vec<String> {
    let is_path_char = |c: char| c.is_ascii_alphanumeric() || "_-./".contains(c);
    let mut found = Vec::new();
    for (start, _) in text.char_indices() {
        let before = text[..start].chars().next_back();
        if before.is_some_and(|c| is_path_char(c) || c == '$' || c == '~') {
            continue;
        }
        let rest = &text[start..];
        for dir in TOP_LEVEL {
            if rest.starts_with(dir) && rest[dir.len()..].starts_with('/') {
                let len = rest.find(|c: char| !is_path_char(c)).unwrap_or(rest.len());
                // A sentence may end right after a path.
                let path = rest[..len].trim_end_matches('.');
                // `fuzz/corpus/TARGET`: a placeholder, not a path.
                let placeholder = path.split('/').any(|part| {
                    part.len() > 1 && part.chars().all(|c| c.is_ascii_uppercase() || c == '_')
                });
                if !placeholder {
                    found.push(path.to_string());
                }
            }
        }
    }
    found
}

fn rel(path: &Path) -> String {
    path.strip_prefix(root()).unwrap().display().to_string()
}

#[test]
fn every_relative_markdown_link_resolves() {
    let mut broken = BTreeSet::new();
    let mut checked = 0;
    for file in text_files(&root()) {
        if file.extension().and_then(|e| e.to_str()) != Some("md") {
            continue;
        }
        let text = fs::read_to_string(&file).unwrap();
        for link in markdown_links(&text) {
            checked += 1;
            if !file.parent().unwrap().join(&link).exists() {
                broken.insert(format!("{}: ({link})", rel(&file)));
            }
        }
    }
    // The README and docs/README.md alone link to every page of docs/.
    assert!(
        checked >= 30,
        "only {checked} links found: the scan is broken"
    );
    assert!(
        broken.is_empty(),
        "links to nothing:\n{}",
        Vec::from_iter(broken).join("\n")
    );
}

#[test]
fn every_mentioned_repository_path_exists() {
    let root = root();
    let mut missing = BTreeSet::new();
    let mut checked = 0;
    for file in text_files(&root) {
        let text = fs::read_to_string(&file).unwrap();
        for path in path_mentions(&text) {
            // Folders that tools make (fuzzing's corpora, build output) are
            // not in a clean clone: naming them is fine.
            if SKIPPED.iter().any(|s| path.starts_with(s)) {
                continue;
            }
            checked += 1;
            if !root.join(&path).exists() {
                missing.insert(format!("{}: {path}", rel(&file)));
            }
        }
    }
    assert!(
        checked >= 200,
        "only {checked} paths found: the scan is broken"
    );
    assert!(
        missing.is_empty(),
        "paths that do not exist:\n{}",
        Vec::from_iter(missing).join("\n")
    );
}

/// The folder beside the repository that the project's contracts came
/// from, which a clone lacks, and its docs: written in pieces so that this
/// file does not name them itself.
const OUTSIDE: [[&str; 2]; 2] = [["../sha", "red"], ["sha", "red/docs"]];

#[test]
fn nothing_points_outside_the_repository() {
    let mut outside = BTreeSet::new();
    for file in text_files(&root()) {
        let text = fs::read_to_string(&file).unwrap();
        for (n, line) in text.lines().enumerate() {
            if OUTSIDE.iter().any(|o| line.contains(&o.concat())) {
                outside.insert(format!("{}:{}: {line}", rel(&file), n + 1));
            }
        }
    }
    assert!(
        outside.is_empty(),
        "outside the repository:\n{}",
        Vec::from_iter(outside).join("\n")
    );
}

#[test]
fn docs_index_links_every_page() {
    let docs = root().join("docs");
    let index = fs::read_to_string(docs.join("README.md")).unwrap();
    let linked: BTreeSet<String> = markdown_links(&index).into_iter().collect();
    let pages: Vec<String> = fs::read_dir(&docs)
        .unwrap()
        .flatten()
        .map(|e| e.file_name().to_string_lossy().into_owned())
        .filter(|name| name.ends_with(".md") && name != "README.md")
        .collect();
    assert!(pages.len() >= 10, "docs/ holds {} pages", pages.len());
    let unlinked: Vec<&String> = pages.iter().filter(|p| !linked.contains(*p)).collect();
    assert!(
        unlinked.is_empty(),
        "docs/README.md does not link {unlinked:?}"
    );
}

#[test]
fn the_scanners_find_what_they_should() {
    assert_eq!(
        markdown_links("[a](docs/x.md#y) [b](https://e.org) [c](#z) [d](../README.md)"),
        ["docs/x.md", "../README.md"]
    );
    assert_eq!(
        path_mentions("see `docs/a.md`. Run ci/b.sh, assets/*.toml; not mysrc/c, $src/d, ci/NAME"),
        ["docs/a.md", "ci/b.sh", "assets/"]
    );
}

/// The README is the front page: the two commands, what it does, a tour,
/// and links to the depth in `docs/`. Past 300 lines it had started to
/// hold that depth itself (318 twice); what outgrows it goes to `docs/`.
#[test]
fn the_readme_stays_a_front_page() {
    let text = std::fs::read_to_string(root().join("README.md")).unwrap();
    let lines = text.lines().count();
    assert!(
        lines <= 300,
        "README.md has {lines} lines; move depth to docs/"
    );
}
