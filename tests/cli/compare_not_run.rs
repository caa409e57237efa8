//! `compare` runs every variant it can: one over the memory limit is
//! reported as not run, with its reason, in the table, `report.json` and
//! the HTML page, the others are measured, and the exit status is 4; a
//! variant given twice is refused; and its progress shows in a log (stderr
//! not a terminal) as lines, none with `--quiet`.

use crate::common;

use common::cli::{shadelab, shadelab_with};

/// At 64 x 48 the default scene in Phong takes a few MiB; its spheres at
/// 2048 segments take about 17 GiB (16.8M triangles), far over 300 MiB
/// and far under what any machine has, so the limit cuts between them.
const SMALL_AND_HUGE: &str = "phong;gouraud:segments=2048";

#[test]
fn a_variant_over_the_memory_limit_is_reported_not_run_and_the_rest_measured() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let args = [
        "compare",
        "--out",
        "cmp",
        "--variants",
        SMALL_AND_HUGE,
        "--width",
        "64",
        "--height",
        "48",
        "--runs",
        "1",
        "--max-memory",
        "300M",
    ];
    let run = shadelab(d, &args);
    assert_eq!(run.code, 4, "{}\n{}", run.stdout, run.stderr);
    assert!(
        run.stderr
            .contains("1 of 2 variants not run (gouraud:segments=2048)"),
        "{}",
        run.stderr
    );
    let line = run
        .stdout
        .lines()
        .find(|l| l.starts_with("gouraud:segments=2048"))
        .unwrap_or_default();
    assert!(
        line.contains("not run:") && line.contains("memory limit"),
        "{}",
        run.stdout
    );
    let report: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(d.join("cmp/report.json")).unwrap()).unwrap();
    let measured: Vec<&str> = report["variants"]
        .as_array()
        .unwrap()
        .iter()
        .map(|v| v["name"].as_str().unwrap())
        .collect();
    assert_eq!(measured, ["phong"]);
    assert_eq!(report["not_run"][0]["name"], "gouraud:segments=2048");
    assert!(report["not_run"][0]["reason"]
        .as_str()
        .unwrap()
        .contains("over the memory limit of 300 MiB"));
    assert!(d.join("cmp/phong.png").is_file());
    let html = std::fs::read_to_string(d.join("cmp/report.html")).unwrap();
    assert!(
        html.contains("gouraud:segments=2048</td><td colspan=\"19\">not run: "),
        "the table"
    );
}

#[test]
fn a_variant_given_twice_is_refused_before_any_work() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let run = shadelab(
        d,
        &["compare", "--out", "cmp", "--variants", "phong;flat;phong"],
    );
    assert_eq!(run.code, 2, "{}", run.stderr);
    assert!(
        run.stderr.contains("--variants names phong twice"),
        "{}",
        run.stderr
    );
    assert!(!d.join("cmp/report.json").exists());
}

/// stderr is a pipe here, as in a CI log: lines, one per step with an
/// interval of 0 seconds; none with --quiet.
#[test]
fn progress_shows_in_a_log_as_lines_and_quiet_silences_it() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let args = [
        "compare",
        "--out",
        "cmp",
        "--variants",
        "flat;phong",
        "--width",
        "48",
        "--height",
        "36",
        "--runs",
        "1",
    ];
    let every_step = [("SHADELAB_PROGRESS_SECONDS", "0")];
    let run = shadelab_with(d, &args, &every_step);
    assert_eq!(run.code, 0, "{}", run.stderr);
    let lines: Vec<&str> = run
        .stderr
        .lines()
        .filter(|l| l.starts_with("shadelab: compare: "))
        .collect();
    assert!(
        lines.iter().any(|l| l.contains(" of 4 done, running ")),
        "{}",
        run.stderr
    );
    assert!(
        lines.iter().any(|l| l.contains("elapsed")),
        "{}",
        run.stderr
    );
    let mut quiet = args.to_vec();
    quiet.push("--quiet");
    let run = shadelab_with(d, &quiet, &every_step);
    assert_eq!(run.code, 0, "{}", run.stderr);
    assert!(
        !run.stderr.contains("shadelab: compare: "),
        "{}",
        run.stderr
    );
}
