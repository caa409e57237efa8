//! A suite split over machines: `--shard I/N` deals a command's cases out
//! by a stable key (a case stays on its shard when others are added or
//! taken away), each shard records its cases in its `--out` folder, and
//! `--merge` joins the shards' records into the report the whole run
//! would have made (`golden` and `check`; `compare` deals its variants in
//! contiguous runs and merges its own way).

use std::path::{Path, PathBuf};

use super::failure::Failure;
use super::run_digest::run_difference;
use shadelab::digest::fnv1a;

/// `I/N` with `1 <= I <= N`, or `auto`: the shard the CI's own variables
/// give (`shard_env.rs`).
pub fn parse_shard(text: &str) -> Result<(usize, usize), String> {
    if text.trim() == "auto" {
        let (shard, from) = super::shard_env::shard_from_vars(&|k| std::env::var(k).ok())?;
        eprintln!(
            "shadelab: note: --shard auto is {}/{} ({from})",
            shard.0, shard.1
        );
        return Ok(shard);
    }
    let bad = || format!("--shard {text} is invalid; expected I/N with 1 <= I <= N, e.g. 2/4");
    let (i, n) = text.split_once('/').ok_or_else(bad)?;
    if i.trim().is_empty() || n.trim().is_empty() {
        // What `--shard $CI_NODE_INDEX/$CI_NODE_TOTAL` becomes where the
        // variables are not set: never a whole suite passed off as a shard.
        return Err(format!(
            "--shard {text} is invalid: it looks like --shard $INDEX/$TOTAL with the variables empty (not set in this job?); give --shard auto to read the CI's own variables, or I/N"
        ));
    }
    let i: usize = i.trim().parse().map_err(|_| bad())?;
    let n: usize = n.trim().parse().map_err(|_| bad())?;
    if i == 0 || n == 0 || i > n {
        return Err(bad());
    }
    Ok((i, n))
}

/// Whether the case of `key` (its scene's key and mode) is shard `(i, n)`'s:
/// the key's FNV-1a digest modulo `n` is `i - 1`. No shard: every case.
pub fn on_shard(key: &str, shard: Option<(usize, usize)>) -> bool {
    match shard {
        None => true,
        Some((i, n)) => fnv1a(key.as_bytes()) % n as u64 == (i - 1) as u64,
    }
}

/// Reads `FILE` (the record a shard leaves, `golden.json` or
/// `check.json`) from each shard folder, checks that they are shards 1 to
/// N of one run, each once, and returns them in shard order, each with
/// its folder.
pub fn read_shards(
    dirs: &[PathBuf],
    file: &str,
) -> Result<Vec<(PathBuf, serde_json::Value)>, Failure> {
    let mut records = Vec::new();
    for dir in dirs {
        let path = dir.join(file);
        let text = std::fs::read_to_string(&path)
            .map_err(|e| Failure::usage(format!("cannot read {}: {e}", path.display())))?;
        let record: serde_json::Value = serde_json::from_str(&text).map_err(|e| {
            Failure::usage(format!(
                "{} is not a shadelab shard record: {e}",
                path.display()
            ))
        })?;
        records.push((dir.clone(), path, record));
    }
    let shard_of = |r: &serde_json::Value| -> Option<(u64, u64)> {
        let s = r.get("shard")?.as_array()?;
        Some((s.first()?.as_u64()?, s.get(1)?.as_u64()?))
    };
    let n = records
        .first()
        .and_then(|(_, _, r)| shard_of(r))
        .map(|(_, n)| n);
    let mut seen = vec![false; n.unwrap_or(0) as usize];
    for (_, path, record) in &records {
        let (i, their_n) = shard_of(record).ok_or_else(|| {
            Failure::usage(format!(
                "{} is of a whole run, not a shard: nothing to merge",
                path.display()
            ))
        })?;
        if Some(their_n) != n {
            return Err(Failure::usage(format!(
                "{} is shard {i}/{their_n}, the first is of {} shards",
                path.display(),
                n.unwrap_or(0)
            )));
        }
        let slot = &mut seen[(i - 1) as usize];
        if *slot {
            return Err(Failure::usage(format!(
                "shard {i}/{their_n} is given twice ({})",
                path.display()
            )));
        }
        *slot = true;
        let null = serde_json::Value::Null;
        let run_of = |r: &'_ serde_json::Value| r.get("run").unwrap_or(&null).clone();
        if let Some(why) = run_difference(&run_of(&records[0].2), &run_of(record)) {
            return Err(Failure::usage(format!(
                "{} is of another run than {}: {why}",
                path.display(),
                records[0].1.display(),
            )));
        }
    }
    if let Some(missing) = seen.iter().position(|s| !s) {
        return Err(Failure::usage(format!(
            "shard {}/{} is missing: give every shard's folder",
            missing + 1,
            n.unwrap_or(0)
        )));
    }
    records.sort_by_key(|(_, _, r)| shard_of(r).map_or(0, |(i, _)| i));
    Ok(records.into_iter().map(|(dir, _, r)| (dir, r)).collect())
}

/// The shards' cases in the order the whole run has them (each case's
/// `order`).
pub fn merged_cases(records: &[(PathBuf, serde_json::Value)]) -> Vec<serde_json::Value> {
    let mut cases: Vec<serde_json::Value> = records
        .iter()
        .filter_map(|(_, r)| r.get("cases").and_then(|c| c.as_array()))
        .flatten()
        .cloned()
        .collect();
    cases.sort_by_key(|c| c.get("order").and_then(|o| o.as_u64()).unwrap_or(u64::MAX));
    cases
}

/// Copies `file` (relative to `from`) to the same place under `to`,
/// refusing a path that leaves the folder.
pub fn copy_into(from: &Path, to: &Path, file: &Path) -> Result<(), Failure> {
    let inside = file
        .components()
        .all(|c| matches!(c, std::path::Component::Normal(_)));
    if !inside {
        return Err(Failure::usage(format!(
            "{}: `{}` is not a path inside the shard's folder",
            from.display(),
            file.display()
        )));
    }
    let (source, target) = (from.join(file), to.join(file));
    if source == target {
        return Ok(());
    }
    if let Some(parent) = target.parent() {
        std::fs::create_dir_all(parent)
            .map_err(|e| Failure::usage(format!("cannot create {}: {e}", parent.display())))?;
    }
    std::fs::copy(&source, &target)
        .map_err(|e| Failure::usage(format!("cannot copy {}: {e}", source.display())))?;
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A record read back keeps every float to the digit: serde_json's
    /// default parser moves about one float in ten by its last digit
    /// (0.009856906946328695 came back ...696), and a merge reads every
    /// shard's record back (`float_roundtrip` is on for this).
    #[test]
    fn a_record_read_back_keeps_its_floats_exactly() {
        let mut state = 0x9e37_79b9_7f4a_7c15u64;
        for _ in 0..10_000 {
            state ^= state << 13;
            state ^= state >> 7;
            state ^= state << 17;
            let x = (state >> 11) as f64 / (1u64 << 53) as f64 * 0.01;
            let text = serde_json::json!({ "figure": x }).to_string();
            let back: serde_json::Value = serde_json::from_str(&text).unwrap();
            assert_eq!(back.to_string(), text);
        }
    }

    #[test]
    fn every_case_is_on_exactly_one_shard_and_stays_there() {
        let keys: Vec<String> = (0..40).map(|k| format!("scene{k}/phong")).collect();
        for n in 1..5 {
            for key in &keys {
                let on: Vec<usize> = (1..=n).filter(|&i| on_shard(key, Some((i, n)))).collect();
                assert_eq!(on.len(), 1, "{key} of {n}: {on:?}");
            }
        }
        // Three shards of 40 keys: none empty.
        for i in 1..=3 {
            assert!(keys.iter().any(|k| on_shard(k, Some((i, 3)))));
        }
        assert!(on_shard("anything", None));
        assert_eq!(parse_shard("2/3"), Ok((2, 3)));
        assert!(parse_shard("0/3").is_err() && parse_shard("4/3").is_err());
        for empty in ["/", " / ", "/4", "2/"] {
            let why = parse_shard(empty).unwrap_err();
            assert!(
                why.contains("variables empty") && why.contains("--shard auto"),
                "{why}"
            );
        }
    }

    #[test]
    fn shards_must_be_one_run_each_once() {
        let dir = tempfile::tempdir().unwrap();
        let write = |name: &str, v: serde_json::Value| {
            let d = dir.path().join(name);
            std::fs::create_dir_all(&d).unwrap();
            std::fs::write(d.join("r.json"), v.to_string()).unwrap();
            d
        };
        let a = write(
            "a",
            serde_json::json!({"shard": [1, 2], "run": "x", "cases": [{"order": 1}]}),
        );
        let b = write(
            "b",
            serde_json::json!({"shard": [2, 2], "run": "x", "cases": [{"order": 0}]}),
        );
        let c = write(
            "c",
            serde_json::json!({"shard": [2, 2], "run": "y", "cases": []}),
        );
        let records = read_shards(&[b.clone(), a.clone()], "r.json").unwrap();
        assert_eq!(
            merged_cases(&records),
            [
                serde_json::json!({"order": 0}),
                serde_json::json!({"order": 1})
            ]
        );
        let err = |dirs: &[PathBuf]| read_shards(dirs, "r.json").unwrap_err().message;
        assert!(err(std::slice::from_ref(&a)).contains("shard 2/2 is missing"));
        assert!(err(&[a.clone(), a.clone()]).contains("given twice"));
        assert!(err(&[a, c]).contains("another run"));
    }
}
