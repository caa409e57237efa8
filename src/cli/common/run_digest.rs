//! What a whole run was, carried by each of its shards' records: the
//! settings that decide its results (the full case list with each scene's
//! content, the flags, references, limits, the binary's version) and a
//! digest of them. A merge compares digests, and where two differ names
//! the first setting that does, so that shards of different runs are
//! never joined into a report neither run made.

use std::path::Path;

use shadelab::digest::fnv1a_hex;

use super::args::{DepthArg, LightingArg, MsaaArg, TraversalArg};

/// `settings` (a JSON object) with the binary's version added, as a
/// record's `run`: `{"digest": ..., "settings": {...}}`.
pub fn run_identity(mut settings: serde_json::Value) -> serde_json::Value {
    settings["shadelab"] = env!("CARGO_PKG_VERSION").into();
    serde_json::json!({
        "digest": fnv1a_hex(settings.to_string().as_bytes()),
        "settings": settings,
    })
}

/// A run's cases (`SCENE/MODE` for each scene key and mode, in order) and
/// each scene's content digest by its key: what every command's run
/// identity starts from.
pub fn cases_and_scenes(
    keys: &[String],
    scenes: &[std::path::PathBuf],
    modes: &[shadelab::shading::Shading],
) -> (Vec<String>, serde_json::Map<String, serde_json::Value>) {
    let cases = keys
        .iter()
        .flat_map(|k| modes.iter().map(move |m| format!("{k}/{m}")))
        .collect();
    let digests = keys
        .iter()
        .zip(scenes)
        .map(|(k, p)| (k.clone(), content_digest(p).into()))
        .collect();
    (cases, digests)
}

/// The flags over a scene that a run's records keep alike in every command
/// (`check`, `golden`): the lighting hook by its content, the engine, the
/// raster samples and the ray tracers' depths as given.
pub fn scene_flags(
    lighting: &LightingArg,
    traversal: &TraversalArg,
    msaa: &MsaaArg,
    depth: &DepthArg,
) -> serde_json::Value {
    serde_json::json!({
        "lighting": lighting.lighting.as_deref().map(content_digest),
        "traversal": format!("{traversal:?}"),
        "msaa": format!("{msaa:?}"),
        "depth": format!("{depth:?}"),
    })
}

/// A digest of a file's bytes, so that a scene is known by what it holds
/// rather than by the path it was given as (`../box.toml` and its absolute
/// path are one scene); `unreadable: WHY` where it cannot be read.
pub fn content_digest(path: &Path) -> String {
    match std::fs::read(path) {
        Ok(bytes) => fnv1a_hex(&bytes),
        Err(e) => format!("unreadable: {e}"),
    }
}

/// Where two runs' `run` values differ, for a refusal to name: `None`
/// where they are one run (same digest). Records written before runs
/// carried settings have none to name, and say so.
pub fn run_difference(ours: &serde_json::Value, theirs: &serde_json::Value) -> Option<String> {
    if ours.get("digest").is_some() && ours.get("digest") == theirs.get("digest") {
        return None;
    }
    if ours == theirs && ours.get("digest").is_none() {
        return None;
    }
    let (a, b) = (&ours["settings"], &theirs["settings"]);
    Some(first_difference(a, b, "").unwrap_or_else(|| {
        "their run digests differ (a record written without its run's settings: make every shard again with this shadelab)".to_string()
    }))
}

/// The first setting (in key order, nested keys joined with `.`) whose
/// value differs between `a` and `b`, said as `SETTING is A against B`.
pub fn first_difference(a: &serde_json::Value, b: &serde_json::Value, at: &str) -> Option<String> {
    if let (Some(a), Some(b)) = (a.as_object(), b.as_object()) {
        let mut keys: Vec<&String> = a.keys().chain(b.keys()).collect();
        keys.sort();
        keys.dedup();
        return keys.into_iter().find_map(|k| {
            let null = serde_json::Value::Null;
            let name = if at.is_empty() {
                k.clone()
            } else {
                format!("{at}.{k}")
            };
            first_difference(a.get(k).unwrap_or(&null), b.get(k).unwrap_or(&null), &name)
        });
    }
    (a != b).then(|| format!("{at} is {} against {}", brief(a), brief(b)))
}

/// A value short enough for one line of an error.
fn brief(v: &serde_json::Value) -> String {
    let text = v.to_string();
    if text.chars().count() <= 120 {
        return text;
    }
    let cut: String = text.chars().take(117).collect();
    format!("{cut}...")
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn one_run_has_one_digest_and_another_names_its_first_difference() {
        let a = run_identity(serde_json::json!({"width": 32, "cases": ["a/phong"]}));
        let b = run_identity(serde_json::json!({"width": 32, "cases": ["a/phong"]}));
        let c = run_identity(serde_json::json!({"width": 48, "cases": ["a/phong", "b/phong"]}));
        assert_eq!(run_difference(&a, &b), None);
        let why = run_difference(&a, &c).unwrap();
        assert!(why.starts_with("cases is [\"a/phong\"] against"), "{why}");
        let nested = first_difference(
            &serde_json::json!({"s": {"x": 1, "y": 2}}),
            &serde_json::json!({"s": {"x": 1, "y": 3}}),
            "",
        );
        assert_eq!(nested.as_deref(), Some("s.y is 2 against 3"));
    }
}
