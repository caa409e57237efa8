//! `shadelab compare` from the command line: every report file, bad
//! variants and shards refused, shards merged, a missed budget failing,
//! and a used folder cleared of its own earlier files only.

use crate::common::cli::{assert_one_line_refusal, shadelab};

#[test]
fn compare_writes_every_report_file() {
    let dir = tempfile::tempdir().unwrap();
    let run = shadelab(
        dir.path(),
        &[
            "compare",
            "--variants",
            "flat;phong:segments=16;raytrace:depth=1",
            "--runs",
            "1",
            "--width",
            "64",
            "--height",
            "48",
            "--out",
            "cmp",
        ],
    );
    assert_eq!(run.code, 0, "{}", run.stderr);
    for file in [
        "report.json",
        "report.csv",
        "report.html",
        "speed-vs-error.png",
        "speed-vs-error.svg",
        "contact-sheet.png",
        "reference.png",
    ] {
        assert!(
            dir.path().join("cmp").join(file).is_file(),
            "{file} missing"
        );
    }
    let json: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(dir.path().join("cmp/report.json")).unwrap())
            .unwrap();
    let names: Vec<&str> = json["variants"]
        .as_array()
        .unwrap()
        .iter()
        .map(|v| v["name"].as_str().unwrap())
        .collect();
    assert_eq!(names, ["flat", "phong:segments=16", "raytrace:depth=1"]);
}

#[test]
fn compare_rejects_bad_variants_and_shards() {
    let dir = tempfile::tempdir().unwrap();
    for args in [
        vec!["compare", "--variants", "flat:depth=3", "--out", "x"],
        vec!["compare", "--variants", "toon", "--out", "x"],
        vec!["compare", "--shard", "3/2", "--out", "x"],
        vec!["compare", "--shard", "0/2", "--out", "x"],
        vec!["compare", "--merge", "nowhere", "--out", "x"],
    ] {
        let run = shadelab(dir.path(), &args);
        assert_eq!(run.code, 2, "{args:?}: {}", run.stderr);
        assert!(!run.stderr.contains("panicked"), "{}", run.stderr);
    }
    // `--shard $CI_NODE_INDEX/$CI_NODE_TOTAL` with the variables unset.
    let args = ["compare", "--shard", "/", "--out", "x"];
    let run = shadelab(dir.path(), &args);
    assert_one_line_refusal(&run, &args, "variables empty");
    assert!(run.stderr.contains("--shard auto"), "{}", run.stderr);
    assert_eq!(
        shadelab(dir.path(), &["compare"]).code,
        2,
        "--out is required"
    );
}

#[test]
fn compare_shards_merge_from_the_command_line() {
    let dir = tempfile::tempdir().unwrap();
    let common = [
        "--variants",
        "flat;gouraud;phong",
        "--runs",
        "1",
        "--width",
        "48",
        "--height",
        "36",
    ];
    for (shard, out) in [("1/2", "a"), ("2/2", "b")] {
        let mut args = vec!["compare", "--shard", shard, "--out", out];
        args.extend_from_slice(&common);
        let run = shadelab(dir.path(), &args);
        assert_eq!(run.code, 0, "{}", run.stderr);
    }
    let run = shadelab(
        dir.path(),
        &["compare", "--merge", "b", "a", "--out", "merged", "--json"],
    );
    assert_eq!(run.code, 0, "{}", run.stderr);
    let json: serde_json::Value = serde_json::from_str(run.stdout.trim()).unwrap();
    assert_eq!(json["variants"].as_array().unwrap().len(), 3);
    assert!(json["shard"].is_null());
    assert!(dir.path().join("merged/report.html").is_file());
    assert!(
        dir.path().join("merged/gouraud.png").is_file(),
        "images come along"
    );

    // A report that names an image outside its folder is refused before
    // anything is copied.
    let report = dir.path().join("b/report.json");
    let text = std::fs::read_to_string(&report).unwrap();
    let tampered = text.replacen("\"phong.png\"", "\"../phong.png\"", 1);
    assert_ne!(text, tampered, "the shard names phong.png");
    std::fs::write(&report, tampered).unwrap();
    let run = shadelab(
        dir.path(),
        &["compare", "--merge", "a", "b", "--out", "evil"],
    );
    assert_eq!(run.code, 2, "{}", run.stderr);
    assert!(run.stderr.contains("../phong.png"), "{}", run.stderr);
    assert!(!dir.path().join("evil/flat.png").exists(), "nothing copied");

    // A shard of another variant list is of another run (once merged
    // silently into a report of neither): refused in one line that names
    // the setting.
    let mut args = vec!["compare", "--shard", "2/2", "--out", "c"];
    args.extend_from_slice(&common);
    args[6] = "flat;phong";
    let run = shadelab(dir.path(), &args);
    assert_eq!(run.code, 0, "{}", run.stderr);
    let args = ["compare", "--merge", "a", "c", "--out", "mixed"];
    let run = shadelab(dir.path(), &args);
    assert_one_line_refusal(
        &run,
        &args,
        "variants is [\"flat\",\"gouraud\",\"phong\"] against",
    );
}

/// One reference for every variant (issue 30): by default the global one,
/// stated; a budget no variant meets is exit status 1 naming the reference
/// and the metric; a budget met names the fastest variant within it by the
/// same reference.
#[test]
fn compare_measures_every_variant_against_one_reference_and_a_missed_budget_fails() {
    let dir = tempfile::tempdir().unwrap();
    let base = [
        "compare",
        "--width",
        "32",
        "--height",
        "24",
        "--runs",
        "1",
        "--variants",
        "phong;raytrace:depth=2",
    ];
    let run = shadelab(
        dir.path(),
        &[&base[..], &["--out", "a", "--budget", "1e-9"]].concat(),
    );
    assert_eq!(run.code, 1, "{}\n{}", run.stdout, run.stderr);
    assert!(
        run.stderr.contains(
            "no variant has RMSE <= 0.000000001 against the global (ray-traced) reference"
        ),
        "{}",
        run.stderr
    );
    let report: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(dir.path().join("a/report.json")).unwrap())
            .unwrap();
    assert_eq!(report["plot_reference"], "global");
    // The variants' plotted errors are their global errors, Phong's too.
    let run = shadelab(
        dir.path(),
        &[&base[..], &["--out", "b", "--budget", "10", "--json"]].concat(),
    );
    assert_eq!(run.code, 0, "{}", run.stderr);
    let report: serde_json::Value = serde_json::from_str(run.stdout.trim()).unwrap();
    let variants = report["variants"].as_array().unwrap();
    let fastest = variants
        .iter()
        .min_by(|a, b| {
            a["timing"]["gpu_ms"]
                .as_f64()
                .partial_cmp(&b["timing"]["gpu_ms"].as_f64())
                .unwrap()
        })
        .unwrap();
    assert_eq!(report["budget"]["fastest"], fastest["name"]);
    let run = shadelab(
        dir.path(),
        &[&base[..], &["--out", "c", "--reference", "local"]].concat(),
    );
    assert_eq!(run.code, 0, "{}", run.stderr);
    assert!(
        run.stdout
            .contains("pareto front and budget: RMSE against the local reference"),
        "{}",
        run.stdout
    );
    // Both: two plots, two fronts, two budget answers, each naming its own.
    let run = shadelab(
        dir.path(),
        &[
            &base[..],
            &["--out", "d", "--reference", "both", "--budget", "10"],
        ]
        .concat(),
    );
    assert_eq!(run.code, 0, "{}", run.stderr);
    assert!(
        run.stdout
            .contains("budget: the fastest variant with RMSE <= 10 against the global"),
        "{}",
        run.stdout
    );
    assert!(
        run.stdout
            .contains("budget: the fastest variant with RMSE <= 10 against the local"),
        "{}",
        run.stdout
    );
    let global = std::fs::read_to_string(dir.path().join("d/speed-vs-error.svg")).unwrap();
    let local = std::fs::read_to_string(dir.path().join("d/speed-vs-error-local.svg")).unwrap();
    assert!(
        global.contains("against the global (ray-traced) reference")
            && !global.contains("against the local")
    );
    assert!(local.contains("against the local reference") && !local.contains("against the global"));
}

/// `compare --out` reused by a smaller run removes the earlier run's files,
/// and only them (issue 30: the bigger run's images stayed beside the new
/// ones), saying so.
#[test]
fn compare_into_a_used_folder_removes_only_its_own_earlier_files() {
    let dir = tempfile::tempdir().unwrap();
    let base = [
        "compare", "--width", "24", "--height", "16", "--runs", "1", "--out", "cmp",
    ];
    let run = shadelab(
        dir.path(),
        &[&base[..], &["--variants", "flat;gouraud"]].concat(),
    );
    assert_eq!(run.code, 0, "{}", run.stderr);
    assert!(dir.path().join("cmp/gouraud.png").is_file());
    std::fs::write(dir.path().join("cmp/notes.txt"), b"mine").unwrap();
    let run = shadelab(dir.path(), &[&base[..], &["--variants", "flat"]].concat());
    assert_eq!(run.code, 0, "{}", run.stderr);
    assert!(
        run.stderr.contains("files of an earlier comparison"),
        "{}",
        run.stderr
    );
    assert!(!dir.path().join("cmp/gouraud.png").exists());
    assert!(!dir.path().join("cmp/gouraud-heat.png").exists());
    assert!(dir.path().join("cmp/flat.png").is_file());
    assert!(dir.path().join("cmp/notes.txt").is_file());
}
