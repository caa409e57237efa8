//! `--shard auto`: the shard read from the variables each CI scheduler
//! sets for its parallel jobs, each with its own base, so that a job
//! whose variables went missing is refused rather than left to run the
//! whole suite (docs/golden.md, "Shards from the CI's own variables").

/// A source of variables: the process's environment, or a table in tests.
pub type Vars<'a> = &'a dyn Fn(&str) -> Option<String>;

/// A shard (1-based) and the variables that gave it, said for the log.
type Found = ((usize, usize), String);

/// One scheduler's variables: its name, the index's and the total's
/// variable, and the index's base (0 or 1).
struct Scheme {
    name: &'static str,
    index: &'static str,
    total: &'static str,
    base: usize,
}

/// The schedulers whose variables give both the index and the total.
/// Kubernetes Indexed Jobs set only `JOB_COMPLETION_INDEX` (0-based): the
/// total comes from `SHADELAB_SHARD_TOTAL`, set in the Job's template to
/// its `completions`. Slurm is read apart (`slurm`): its array may start
/// at any number.
const SCHEMES: [Scheme; 4] = [
    Scheme {
        name: "GitLab parallel",
        index: "CI_NODE_INDEX",
        total: "CI_NODE_TOTAL",
        base: 1,
    },
    Scheme {
        name: "Buildkite parallelism",
        index: "BUILDKITE_PARALLEL_JOB",
        total: "BUILDKITE_PARALLEL_JOB_COUNT",
        base: 0,
    },
    Scheme {
        name: "CircleCI parallelism",
        index: "CIRCLE_NODE_INDEX",
        total: "CIRCLE_NODE_TOTAL",
        base: 0,
    },
    Scheme {
        name: "a Kubernetes Indexed Job",
        index: "JOB_COMPLETION_INDEX",
        total: "SHADELAB_SHARD_TOTAL",
        base: 0,
    },
];

/// Every variable `--shard auto` reads, for the message when none is set.
const ALL_VARIABLES: &str = "SHADELAB_SHARD, CI_NODE_INDEX/CI_NODE_TOTAL (GitLab), SLURM_ARRAY_TASK_ID/SLURM_ARRAY_TASK_COUNT (Slurm), BUILDKITE_PARALLEL_JOB/BUILDKITE_PARALLEL_JOB_COUNT, CIRCLE_NODE_INDEX/CIRCLE_NODE_TOTAL, JOB_COMPLETION_INDEX with SHADELAB_SHARD_TOTAL (Kubernetes)";

/// The shard `(i, n)` (1-based) the variables give, and what gave it; or
/// why there is none: no scheduler's variables set, one's half set or not
/// numbers, or two that disagree.
pub fn shard_from_vars(vars: Vars) -> Result<Found, String> {
    let get = |k: &str| vars(k).filter(|v| !v.trim().is_empty());
    let mut found: Vec<Found> = Vec::new();
    if let Some(text) = get("SHADELAB_SHARD") {
        let shard = text
            .split_once('/')
            .and_then(|(i, n)| based(i, n, 1))
            .ok_or_else(|| {
                format!("--shard auto: SHADELAB_SHARD={text} is not I/N with 1 <= I <= N")
            })?;
        found.push((shard, format!("SHADELAB_SHARD={text}")));
    }
    for scheme in &SCHEMES {
        let (index, total) = (get(scheme.index), get(scheme.total));
        if index.is_none() && total.is_none() {
            continue;
        }
        let (Some(index), Some(total)) = (index, total) else {
            let (set, unset) = if get(scheme.index).is_some() {
                (scheme.index, scheme.total)
            } else {
                (scheme.total, scheme.index)
            };
            return Err(format!(
                "--shard auto: {set} is set but {unset} is not ({}): set both, or give --shard I/N",
                scheme.name
            ));
        };
        let what = format!("{}={index}, {}={total}", scheme.index, scheme.total);
        let shard = based(&index, &total, scheme.base).ok_or_else(|| {
            format!(
                "--shard auto: {what} ({}, {}-based) is not a shard",
                scheme.name, scheme.base
            )
        })?;
        found.push((shard, what));
    }
    if let Some(slurm) = slurm(&get)? {
        found.push(slurm);
    }
    let Some(first) = found.first().cloned() else {
        return Err(format!(
            "--shard auto found no CI shard variables (looked for {ALL_VARIABLES}); give --shard I/N, or set SHADELAB_SHARD=I/N (GitHub Actions: from the matrix)"
        ));
    };
    if let Some(other) = found.iter().find(|(s, _)| *s != first.0) {
        return Err(format!(
            "--shard auto: the CI's variables disagree: {} gives {}/{} and {} gives {}/{}; give --shard I/N",
            first.1, first.0 .0, first.0 .1, other.1, other.0 .0, other.0 .1
        ));
    }
    Ok(first)
}

/// `(index - base + 1, total)` where that is a shard.
fn based(index: &str, total: &str, base: usize) -> Option<(usize, usize)> {
    let index: usize = index.trim().parse().ok()?;
    let total: usize = total.trim().parse().ok()?;
    let i = index.checked_sub(base)? + 1;
    (total >= 1 && i <= total).then_some((i, total))
}

/// A Slurm array task: `SLURM_ARRAY_TASK_ID` counted from the array's
/// first (`SLURM_ARRAY_TASK_MIN`: `--array=1-4` starts at 1, `0-3` at 0)
/// in its steps, of `SLURM_ARRAY_TASK_COUNT`. An array that is not one
/// even range (`--array=1,5,9-10`) is refused: its tasks are not
/// numbered 1 to N.
fn slurm(get: &dyn Fn(&str) -> Option<String>) -> Result<Option<Found>, String> {
    let Some(id) = get("SLURM_ARRAY_TASK_ID") else {
        return Ok(None);
    };
    let number = |k: &str| get(k).and_then(|v| v.trim().parse::<usize>().ok());
    let what = format!("SLURM_ARRAY_TASK_ID={id}");
    let bad =
        |why: &str| format!("--shard auto: {what} is in a Slurm array {why}; give --shard I/N");
    let (Some(id), Some(min), Some(max), Some(count)) = (
        id.trim().parse::<usize>().ok(),
        number("SLURM_ARRAY_TASK_MIN"),
        number("SLURM_ARRAY_TASK_MAX"),
        number("SLURM_ARRAY_TASK_COUNT"),
    ) else {
        return Err(bad(
            "without numbers in SLURM_ARRAY_TASK_MIN, _MAX and _COUNT",
        ));
    };
    let step = number("SLURM_ARRAY_TASK_STEP").unwrap_or(1).max(1);
    let even = max >= min && (max - min) % step == 0 && (max - min) / step + 1 == count;
    if !even || id < min || (id - min) % step != 0 || id > max {
        return Err(bad(&format!(
            "that is not one even range (MIN {min}, MAX {max}, STEP {step}, COUNT {count})"
        )));
    }
    let shard = ((id - min) / step + 1, count);
    Ok(Some((
        shard,
        format!("{what} of SLURM_ARRAY_TASK_MIN={min}..MAX={max}"),
    )))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn from(pairs: &[(&str, &str)]) -> Result<(usize, usize), String> {
        let table: Vec<(String, String)> = pairs
            .iter()
            .map(|(k, v)| (k.to_string(), v.to_string()))
            .collect();
        let vars = move |k: &str| table.iter().find(|(n, _)| n == k).map(|(_, v)| v.clone());
        shard_from_vars(&vars).map(|(s, _)| s)
    }

    #[test]
    fn each_scheduler_is_read_with_its_own_base() {
        assert_eq!(
            from(&[("CI_NODE_INDEX", "1"), ("CI_NODE_TOTAL", "4")]),
            Ok((1, 4))
        );
        assert_eq!(
            from(&[("CI_NODE_INDEX", "4"), ("CI_NODE_TOTAL", "4")]),
            Ok((4, 4))
        );
        assert!(from(&[("CI_NODE_INDEX", "0"), ("CI_NODE_TOTAL", "4")]).is_err());
        let buildkite = [
            ("BUILDKITE_PARALLEL_JOB", "0"),
            ("BUILDKITE_PARALLEL_JOB_COUNT", "3"),
        ];
        assert_eq!(from(&buildkite), Ok((1, 3)));
        let circle = [("CIRCLE_NODE_INDEX", "2"), ("CIRCLE_NODE_TOTAL", "3")];
        assert_eq!(from(&circle), Ok((3, 3)));
        assert!(from(&[("CIRCLE_NODE_INDEX", "3"), ("CIRCLE_NODE_TOTAL", "3")]).is_err());
        let k8s = [("JOB_COMPLETION_INDEX", "0"), ("SHADELAB_SHARD_TOTAL", "5")];
        assert_eq!(from(&k8s), Ok((1, 5)));
        let half = from(&[("JOB_COMPLETION_INDEX", "0")]).unwrap_err();
        assert!(half.contains("SHADELAB_SHARD_TOTAL is not"), "{half}");
        assert_eq!(from(&[("SHADELAB_SHARD", "2/4")]), Ok((2, 4)));
        let slurm = |id: &str, min: &str, max: &str, count: &str| {
            from(&[
                ("SLURM_ARRAY_TASK_ID", id),
                ("SLURM_ARRAY_TASK_MIN", min),
                ("SLURM_ARRAY_TASK_MAX", max),
                ("SLURM_ARRAY_TASK_COUNT", count),
            ])
        };
        assert_eq!(slurm("1", "1", "4", "4"), Ok((1, 4)));
        assert_eq!(slurm("0", "0", "3", "4"), Ok((1, 4)));
        assert_eq!(slurm("3", "0", "3", "4"), Ok((4, 4)));
        assert!(slurm("5", "1", "9", "3")
            .unwrap_err()
            .contains("not one even range"));
    }

    #[test]
    fn none_set_or_disagreeing_variables_are_refused_never_the_whole_suite() {
        let none = from(&[("CI_NODE_INDEX", ""), ("CI_NODE_TOTAL", "")]).unwrap_err();
        assert!(none.contains("found no CI shard variables"), "{none}");
        let two = from(&[
            ("CI_NODE_INDEX", "1"),
            ("CI_NODE_TOTAL", "2"),
            ("SHADELAB_SHARD", "2/2"),
        ])
        .unwrap_err();
        assert!(two.contains("disagree"), "{two}");
        let agreeing = [
            ("CIRCLE_NODE_INDEX", "1"),
            ("CIRCLE_NODE_TOTAL", "2"),
            ("SHADELAB_SHARD", "2/2"),
        ];
        assert_eq!(from(&agreeing), Ok((2, 2)));
        assert!(from(&[("CI_NODE_INDEX", "x"), ("CI_NODE_TOTAL", "2")]).is_err());
    }
}
