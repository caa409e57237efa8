//! A suite that outgrows one machine: `golden` and `check` run as 3 shards
//! (`--shard I/3`) and merged (`--merge`) report what the unsharded run
//! reports: the same cases in the same order, the same verdicts and
//! figures, the same JUnit cases and exit status.

use crate::common;

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
    a_shard_of_another_run_is_refused(d);
}

/// A shard of another run (in `d`, beside `refs/`, `shard1/` and
/// `shard2/`): one scene fewer, or another width. Each is refused in one
/// line naming the setting, and nothing merged.
fn a_shard_of_another_run_is_refused(d: &Path) {
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

/// A one-node Slurm cluster of this machine, private to a test: its own
/// MUNGE socket and ports, so that runs side by side do not meet. Its
/// daemons are stopped (by their pids) when it is dropped.
struct Slurm {
    dir: PathBuf,
    conf: PathBuf,
}

impl Slurm {
    /// Starts munged, slurmctld and slurmd in `dir`; fails (never skips)
    /// where Slurm is not installed.
    fn start(dir: &Path) -> Slurm {
        for tool in ["munged", "slurmctld", "slurmd", "sbatch"] {
            let found = std::process::Command::new("sh")
                .args(["-c", &format!("command -v {tool}")])
                .output();
            assert!(
                found.is_ok_and(|o| o.status.success()),
                "{tool} is missing: install slurm-wlm and munge (ci/install-deps.sh --with-slurm)"
            );
        }
        let host = std::process::Command::new("hostname")
            .arg("-s")
            .output()
            .unwrap();
        let host = String::from_utf8_lossy(&host.stdout).trim().to_string();
        let port = 20000 + std::process::id() % 20000;
        let socket = dir.join("munge.sock");
        let d = dir.display();
        let munged = std::process::Command::new("munged")
            .arg("--force")
            .arg(format!("--socket={}", socket.display()))
            .arg(format!("--pid-file={d}/munged.pid"))
            .arg(format!("--log-file={d}/munged.log"))
            .arg(format!("--seed-file={d}/munged.seed"))
            .status()
            .unwrap();
        assert!(munged.success(), "munged did not start");
        let conf = dir.join("slurm.conf");
        std::fs::create_dir_all(dir.join("state")).unwrap();
        std::fs::create_dir_all(dir.join("spool")).unwrap();
        std::fs::write(dir.join("cgroup.conf"), "").unwrap();
        std::fs::write(
            &conf,
            format!(
                "ClusterName=shadelab\nSlurmctldHost={host}\nSlurmUser=root\nSlurmdUser=root\n\
                 AuthType=auth/munge\nCredType=cred/munge\nAuthInfo=socket={}\n\
                 SlurmctldPort={port}\nSlurmdPort={}\n\
                 StateSaveLocation={d}/state\nSlurmdSpoolDir={d}/spool\n\
                 SlurmctldPidFile={d}/slurmctld.pid\nSlurmdPidFile={d}/slurmd.pid\n\
                 SlurmctldLogFile={d}/slurmctld.log\nSlurmdLogFile={d}/slurmd.log\n\
                 ProctrackType=proctrack/linuxproc\nTaskPlugin=task/none\n\
                 JobAcctGatherType=jobacct_gather/none\nSelectType=select/cons_tres\n\
                 SelectTypeParameters=CR_Core\nMpiDefault=none\nReturnToService=2\n\
                 NodeName={host} CPUs=2 State=UNKNOWN\n\
                 PartitionName=shards Nodes={host} Default=YES MaxTime=INFINITE State=UP\n",
                socket.display(),
                port + 1
            ),
        )
        .unwrap();
        let slurm = Slurm {
            dir: dir.to_owned(),
            conf,
        };
        for daemon in ["slurmctld", "slurmd"] {
            let started = slurm.command(daemon).status().unwrap();
            assert!(
                started.success(),
                "{daemon} did not start: {}",
                slurm.logs()
            );
        }
        slurm
    }

    /// A Slurm command that reads this cluster's configuration.
    fn command(&self, tool: &str) -> std::process::Command {
        let mut command = std::process::Command::new(tool);
        command.env("SLURM_CONF", &self.conf);
        command
    }

    /// Submits `script` (a shell command line) with `options`; its job id.
    fn submit(&self, options: &[&str], script: &str) -> String {
        let out = self
            .command("sbatch")
            .arg("--parsable")
            .args(options)
            .arg(format!("--wrap={script}"))
            .output()
            .unwrap();
        assert!(
            out.status.success(),
            "sbatch: {}",
            String::from_utf8_lossy(&out.stderr)
        );
        String::from_utf8_lossy(&out.stdout).trim().to_string()
    }

    /// Waits until no job is queued or running (at most `seconds`).
    fn wait(&self, seconds: u64) {
        let start = std::time::Instant::now();
        loop {
            let queue = self.command("squeue").arg("-h").output().unwrap();
            if queue.status.success() && queue.stdout.is_empty() {
                return;
            }
            assert!(
                start.elapsed().as_secs() < seconds,
                "jobs still queued: {}",
                self.logs()
            );
            std::thread::sleep(std::time::Duration::from_millis(500));
        }
    }

    fn logs(&self) -> String {
        ["slurmctld.log", "slurmd.log"]
            .iter()
            .map(|f| std::fs::read_to_string(self.dir.join(f)).unwrap_or_default())
            .collect::<Vec<_>>()
            .join("\n")
    }
}

impl Drop for Slurm {
    fn drop(&mut self) {
        for pid in ["slurmd.pid", "slurmctld.pid", "munged.pid"] {
            if let Ok(pid) = std::fs::read_to_string(self.dir.join(pid)) {
                let _ = std::process::Command::new("kill").arg(pid.trim()).status();
            }
        }
    }
}

/// `--shard auto` under a real scheduler: a Slurm array `--array=0-2` (an
/// array from 0, where `SLURM_ARRAY_TASK_ID` is not the shard) runs
/// `check` as shards 1/3 to 3/3, and a job that depends on the array
/// merges them into the whole run's six cases.
#[test]
fn a_slurm_array_shards_a_suite_and_a_dependent_job_merges_it() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let slurm = Slurm::start(d);
    let exe = env!("CARGO_BIN_EXE_shadelab");
    let env = format!(
        "SHADELAB_VALIDATION=1 SHADELAB_CACHE_DIR={}/cache MESA_SHADER_CACHE_DIR={}",
        d.display(),
        common::cli::mesa_cache().display()
    );
    let shard = format!(
        "{env} {exe} check {} {} --shard auto --out shard-$SLURM_ARRAY_TASK_ID",
        scenes().join(" "),
        SMALL.join(" ")
    );
    let chdir = format!("--chdir={}", d.display());
    let array = slurm.submit(&[&chdir, "--array=0-2", "--output=shard-%a.log"], &shard);
    let merge = format!("{env} {exe} check --merge shard-0 shard-1 shard-2 --out merged --json");
    let after = format!("--dependency=afterok:{array}");
    slurm.submit(&[&chdir, &after, "--output=merge.log"], &merge);
    slurm.wait(180);
    for k in 0..3 {
        let log = std::fs::read_to_string(d.join(format!("shard-{k}.log"))).unwrap();
        let said = format!("--shard auto is {}/3 (SLURM_ARRAY_TASK_ID={k}", k + 1);
        assert!(log.contains(&said), "{log}");
    }
    let log = std::fs::read_to_string(d.join("merge.log")).unwrap();
    let line = log
        .lines()
        .find(|l| l.starts_with('{'))
        .unwrap_or_else(|| panic!("{log}"));
    let merged: serde_json::Value = serde_json::from_str(line).unwrap();
    assert_eq!(cases(&merged, &["passed"]).len(), 6, "{log}");
    assert_eq!(merged["failed"], 0, "{log}");
    drop(slurm);
}
