//! A suite that outgrows one machine: `golden` and `check` run as 3 shards
//! (`--shard I/3`) and merged (`--merge`) report what the unsharded run
//! reports: the same cases in the same order, the same verdicts and
//! figures, the same JUnit cases and exit status.

mod common;

use std::path::{Path, PathBuf};

use common::cli::{assert_one_line_refusal, shadelab, Run};

fn repo(path: &str) -> String {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join(path)
        .display()
        .to_string()
}

fn json(run: &Run) -> serde_json::Value {
    serde_json::from_str(&run.stdout)
        .unwrap_or_else(|e| panic!("{e}: {}\n{}", run.stdout, run.stderr))
}

/// Each case's fields that do not depend on where or when it ran.
fn cases(report: &serde_json::Value, fields: &[&str]) -> Vec<serde_json::Value> {
    report["cases"]
        .as_array()
        .unwrap()
        .iter()
        .map(|c| {
            let kept: serde_json::Map<String, serde_json::Value> = fields
                .iter()
                .map(|f| (f.to_string(), c[*f].clone()))
                .collect();
            serde_json::Value::Object(kept)
        })
        .collect()
}

/// The test cases of a JUnit file, as `classname/name:outcome`.
fn junit_cases(path: &Path) -> Vec<String> {
    let xml = std::fs::read_to_string(path).unwrap();
    xml.split("<testcase ")
        .skip(1)
        .map(|case| {
            let attr = |name: &str| {
                let start = case.find(&format!("{name}=\"")).unwrap() + name.len() + 2;
                case[start..start + case[start..].find('"').unwrap()].to_string()
            };
            let outcome = if case.contains("<failure") {
                "failure"
            } else if case.contains("<error") {
                "error"
            } else {
                "pass"
            };
            format!("{}/{}:{outcome}", attr("classname"), attr("name"))
        })
        .collect()
}

fn scenes() -> Vec<String> {
    [
        "assets/spheres.toml",
        "assets/whitted.toml",
        "assets/rt-mirror.toml",
    ]
    .iter()
    .map(|s| repo(s))
    .collect()
}

const SMALL: [&str; 6] = ["--shading", "flat,phong", "--width", "48", "--height", "36"];

#[test]
fn golden_in_three_shards_merged_reports_what_one_run_reports() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let golden = |extra: &[&str]| {
        let mut args: Vec<String> = vec!["golden".into()];
        args.extend(scenes());
        args.extend(SMALL.iter().map(|s| s.to_string()));
        args.extend(["--references".into(), "refs".into(), "--json".into()]);
        args.extend(extra.iter().map(|s| s.to_string()));
        let args: Vec<&str> = args.iter().map(String::as_str).collect();
        shadelab(d, &args)
    };
    assert_eq!(golden(&["--create", "--out", "made"]).code, 0);
    // One case fails: its reference is another scene's image.
    std::fs::copy(
        d.join("refs/spheres-phong.png"),
        d.join("refs/whitted-phong.png"),
    )
    .unwrap();
    let whole = golden(&["--out", "whole", "--junit", "whole.xml"]);
    assert_eq!(whole.code, 1, "{}", whole.stderr);
    for i in 1..=3 {
        let shard = format!("{i}/3");
        let out = format!("shard{i}");
        let run = golden(&["--shard", &shard, "--out", &out]);
        assert!(run.code == 0 || run.code == 1, "{}", run.stderr);
        assert!(d.join(&out).join("golden.json").is_file());
    }
    let merged = shadelab(
        d,
        &[
            "golden",
            "--merge",
            "shard3",
            "shard1",
            "shard2",
            "--out",
            "merged",
            "--junit",
            "merged.xml",
            "--json",
        ],
    );
    assert_eq!(merged.code, whole.code, "{}", merged.stderr);
    let fields = ["scene", "shading", "file", "status", "failures", "figures"];
    let (w, m) = (json(&whole), json(&merged));
    assert_eq!(cases(&m, &fields), cases(&w, &fields));
    assert_eq!(cases(&w, &["status"]).len(), 6);
    for count in [
        "passed", "failed", "missing", "created", "updated", "errors",
    ] {
        assert_eq!(m[count], w[count], "{count}");
    }
    assert_eq!(
        junit_cases(&d.join("merged.xml")),
        junit_cases(&d.join("whole.xml"))
    );
    // The failure's pictures came along, and the page shows it.
    assert!(d.join("merged/whitted-phong-actual.png").is_file());
    let page = std::fs::read_to_string(d.join("merged/report.html")).unwrap();
    assert!(page.contains("5 of 6 cases passed") && page.contains("whitted/phong: FAIL"));
    // A missing shard, or one given twice, is refused.
    let missing = shadelab(d, &["golden", "--merge", "shard1", "shard2", "--out", "m2"]);
    assert_eq!(missing.code, 2);
    assert!(
        missing.stderr.contains("shard 3/3 is missing"),
        "{}",
        missing.stderr
    );
    merged_record_names_its_own_files_and_the_shards_figures(d, "merged");
    // A shard of another run: one scene fewer, or another width. Each is
    // refused in one line naming the setting, and nothing merged.
    let one_scene = |extra: &[&str]| {
        let mut args = vec!["golden".to_string(), scenes()[0].clone()];
        args.extend(SMALL.iter().map(|s| s.to_string()));
        args.extend(["--references", "refs", "--shard", "3/3"].map(String::from));
        args.extend(extra.iter().map(|s| s.to_string()));
        let args: Vec<&str> = args.iter().map(String::as_str).collect();
        shadelab(d, &args)
    };
    assert!(one_scene(&["--out", "other3"]).code <= 1);
    let mut golden_wide = vec!["golden".to_string()];
    golden_wide.extend(scenes());
    golden_wide
        .extend(["--shading", "flat,phong", "--width", "40", "--height", "36"].map(String::from));
    golden_wide
        .extend(["--references", "refs", "--shard", "3/3", "--out", "wide3"].map(String::from));
    let run = shadelab(
        d,
        &golden_wide.iter().map(String::as_str).collect::<Vec<_>>(),
    );
    assert!(run.code <= 1, "{}", run.stderr);
    for (other, setting) in [
        ("other3", "cases is ["),
        ("wide3", "width is 48 against 40"),
    ] {
        let args = [
            "golden", "--merge", "shard1", "shard2", other, "--out", "mixed",
        ];
        let run = shadelab(d, &args);
        assert_one_line_refusal(&run, &args, setting);
        assert!(run.stderr.contains(other), "{}", run.stderr);
        assert!(!d.join("mixed/golden.json").exists());
    }
}

/// The merged `golden.json` names the copies in the merged folder (as a
/// whole run names its own files), and its figures are the shards'
/// exactly, digit for digit, as text: a record read back and written
/// again must not move a float by its last digit.
fn merged_record_names_its_own_files_and_the_shards_figures(d: &Path, merged: &str) {
    let text = |p: PathBuf| std::fs::read_to_string(p).unwrap();
    let record: serde_json::Value =
        serde_json::from_str(&text(d.join(merged).join("golden.json"))).unwrap();
    let written: Vec<&str> = record["cases"]
        .as_array()
        .unwrap()
        .iter()
        .flat_map(|c| c["written"].as_array().unwrap())
        .map(|w| w.as_str().unwrap())
        .collect();
    assert!(!written.is_empty());
    for w in written {
        assert!(w.starts_with(&format!("{merged}/")), "{w}");
        assert!(d.join(w).is_file(), "{w}");
    }
    let mut shards: Vec<String> = (1..=3)
        .flat_map(|i| figure_texts(&text(d.join(format!("shard{i}/golden.json")))))
        .collect();
    let mut whole = figure_texts(&text(d.join(merged).join("golden.json")));
    shards.sort();
    whole.sort();
    assert_eq!(whole.len(), 6);
    assert_eq!(whole, shards);
}

/// Each `"figures":{...}` object of a record, as the text written.
fn figure_texts(text: &str) -> Vec<String> {
    let key = "\"figures\":{";
    let mut found = Vec::new();
    let mut rest = text;
    while let Some(at) = rest.find(key) {
        let body = &rest[at + key.len() - 1..];
        let mut depth = 0;
        let end = body
            .char_indices()
            .find(|&(_, c)| {
                depth += match c {
                    '{' => 1,
                    '}' => -1,
                    _ => 0,
                };
                depth == 0
            })
            .map(|(k, _)| k + 1)
            .unwrap();
        found.push(body[..end].to_string());
        rest = &body[end..];
    }
    found
}

/// A suite dealt over more shards than it has cases: the shards with none
/// open no device, yet their records merge into the whole run's report.
#[test]
fn a_shard_with_no_cases_merges() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let scene = repo("assets/spheres.toml");
    let golden = |extra: &[&str]| {
        let mut args = vec![
            "golden",
            &scene,
            "--shading",
            "flat",
            "--width",
            "32",
            "--height",
            "24",
        ];
        args.extend(["--references", "refs"]);
        args.extend_from_slice(extra);
        shadelab(d, &args)
    };
    assert_eq!(golden(&["--create", "--out", "made"]).code, 0);
    for i in 1..=3 {
        let run = golden(&["--shard", &format!("{i}/3"), "--out", &format!("g{i}")]);
        assert_eq!(run.code, 0, "{}", run.stderr);
    }
    let run = shadelab(
        d,
        &[
            "golden", "--merge", "g1", "g2", "g3", "--out", "g", "--json",
        ],
    );
    assert_eq!(run.code, 0, "{}", run.stderr);
    let merged = json(&run);
    assert_eq!(merged["passed"], 1);
    assert!(
        merged["key"].as_str().is_some_and(|k| k != "no-device"),
        "{merged}"
    );
}

#[test]
fn check_in_three_shards_merged_reports_what_one_run_reports() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let check = |extra: &[&str]| {
        let mut args: Vec<String> = vec!["check".into()];
        args.extend(scenes());
        args.extend(SMALL.iter().map(|s| s.to_string()));
        args.push("--json".into());
        args.extend(extra.iter().map(|s| s.to_string()));
        let args: Vec<&str> = args.iter().map(String::as_str).collect();
        shadelab(d, &args)
    };
    let whole = check(&["--out", "whole", "--junit", "whole.xml"]);
    assert_eq!(whole.code, 0, "{}", whole.stderr);
    for i in 1..=3 {
        let run = check(&["--shard", &format!("{i}/3"), "--out", &format!("shard{i}")]);
        assert_eq!(run.code, 0, "{}", run.stderr);
    }
    let merged = shadelab(
        d,
        &[
            "check",
            "--merge",
            "shard1",
            "shard2",
            "shard3",
            "--out",
            "merged",
            "--junit",
            "merged.xml",
            "--json",
        ],
    );
    assert_eq!(merged.code, 0, "{}", merged.stderr);
    let fields = [
        "scene",
        "shading",
        "passed",
        "failures",
        "interior",
        "edge_share",
        "flip_mean",
    ];
    let (w, m) = (json(&whole), json(&merged));
    assert_eq!(cases(&m, &fields), cases(&w, &fields));
    assert_eq!(cases(&w, &["passed"]).len(), 6);
    assert_eq!(
        junit_cases(&d.join("merged.xml")),
        junit_cases(&d.join("whole.xml"))
    );
    // Every case's images, from whichever shard made them.
    for scene in ["spheres", "whitted", "rt-mirror"] {
        for mode in ["flat", "phong"] {
            let image = d.join(format!("merged/{scene}/{mode}-actual.png"));
            assert!(image.is_file(), "{}", image.display());
        }
    }
    // A shard at another width is of another run.
    let mut wide: Vec<String> = vec!["check".into()];
    wide.extend(scenes());
    wide.extend(["--shading", "flat,phong", "--width", "40", "--height", "36"].map(String::from));
    wide.extend(["--shard", "3/3", "--out", "wide3"].map(String::from));
    let run = shadelab(d, &wide.iter().map(String::as_str).collect::<Vec<_>>());
    assert_eq!(run.code, 0, "{}", run.stderr);
    let args = [
        "check", "--merge", "shard1", "shard2", "wide3", "--out", "mixed",
    ];
    assert_one_line_refusal(&shadelab(d, &args), &args, "width is 48 against 40");
    // One case over three shards: two have none, and all three merge.
    let spheres = repo("assets/spheres.toml");
    for i in 1..=3 {
        let args = [
            "check",
            &spheres,
            "--shading",
            "flat",
            "--width",
            "32",
            "--height",
            "24",
        ];
        let mut args = args.to_vec();
        let (shard, out) = (format!("{i}/3"), format!("one{i}"));
        args.extend(["--shard", &shard, "--out", &out]);
        let run = shadelab(d, &args);
        assert_eq!(run.code, 0, "{}", run.stderr);
    }
    let args = [
        "check", "--merge", "one1", "one2", "one3", "--out", "one", "--json",
    ];
    let run = shadelab(d, &args);
    assert_eq!(run.code, 0, "{}", run.stderr);
    assert_eq!(cases(&json(&run), &["passed"]).len(), 1);
}
