//! A scene given as a table of values rather than a file (the Python
//! package's `Scene.from_dict`): written out as TOML text and read by the
//! one parser, so it meets every rule a file does, with each error named
//! by the key path the caller wrote (`objects[2].radius`) instead of a
//! line of text they never saw.

use std::path::Path;

use crate::scene::error::SceneError;
use crate::scene::model::Scene;

/// The scene `table` describes (the schema of `docs/interface.md`), its
/// files (meshes, textures) named relative to `base_dir`.
pub fn from_table(table: &toml::Table, base_dir: &Path) -> Result<Scene, SceneError> {
    let text = toml::to_string(table).map_err(|e| SceneError::AtKey {
        key: String::new(),
        message: format!("cannot be written as TOML: {e}"),
    })?;
    super::parse(&text, base_dir, "<table>").map_err(|e| at_key(e, &key_paths(&text)))
}

/// The error `e` of the text whose lines set `paths`, named by key path.
fn at_key(e: SceneError, paths: &[String]) -> SceneError {
    let path_of = |line: usize| paths.get(line.wrapping_sub(1)).cloned().unwrap_or_default();
    match e {
        SceneError::Syntax { line, message, .. } | SceneError::Invalid { line, message, .. } => {
            SceneError::AtKey {
                key: path_of(line),
                message,
            }
        }
        SceneError::InObject { line, source, .. } => SceneError::AtKey {
            key: path_of(line),
            message: format!("mesh: {source}"),
        },
        SceneError::Toml { message, .. } => SceneError::AtKey {
            key: String::new(),
            message,
        },
        other => other,
    }
}

/// For each line (0-based) of TOML text as `toml::to_string` writes it,
/// the key path it sets or the table it opens: `camera.fov_y`,
/// `objects[2]`, `objects[2].pattern.kind`, `materials.glass.kt`.
pub(super) fn key_paths(text: &str) -> Vec<String> {
    let mut table = String::new();
    // Each array of tables' name with its last element's path.
    let mut arrays: Vec<(String, usize)> = Vec::new();
    let mut paths = Vec::new();
    for line in text.lines() {
        let t = line.trim();
        if let Some(name) = t.strip_prefix("[[").and_then(|r| r.strip_suffix("]]")) {
            let name = dotted(name);
            let index = match arrays.iter_mut().find(|(n, _)| *n == name) {
                Some((_, i)) => {
                    *i += 1;
                    *i
                }
                None => {
                    arrays.push((name.clone(), 0));
                    0
                }
            };
            table = format!("{name}[{index}]");
        } else if let Some(name) = t.strip_prefix('[').and_then(|r| r.strip_suffix(']')) {
            let name = dotted(name);
            // `[objects.pattern]` after `[[objects]]`: the last element's.
            table = arrays
                .iter()
                .filter(|(n, _)| name.starts_with(&format!("{n}.")))
                .max_by_key(|(n, _)| n.len())
                .map_or(name.clone(), |(n, i)| {
                    format!("{n}[{i}]{}", &name[n.len()..])
                });
        } else if let Some((key, _)) = t.split_once('=').filter(|_| !t.starts_with('#')) {
            let key = dotted(key.trim());
            paths.push(join(&table, &key));
            continue;
        }
        paths.push(table.clone());
    }
    paths
}

/// A TOML key as a path: the quotes of quoted parts taken off.
fn dotted(key: &str) -> String {
    key.split('.')
        .map(|part| part.trim().trim_matches('"').trim_matches('\''))
        .collect::<Vec<_>>()
        .join(".")
}

fn join(table: &str, key: &str) -> String {
    if table.is_empty() {
        key.to_string()
    } else {
        format!("{table}.{key}")
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn table(text: &str) -> toml::Table {
        text.parse().unwrap()
    }

    const SCENE: &str = r#"
[camera]
position = [0.0, 1.0, 6.0]
look_at = [0.0, 0.0, 0.0]

[[lights]]
position = [4.0, 6.0, 5.0]
intensity = 8.0

[materials.plaster]
color = [0.9, 0.85, 0.8]

[[objects]]
shape = "sphere"
center = [0.0, 0.0, 0.0]
radius = 1.0
material = "plaster"

[[objects]]
shape = "sphere"
center = [2.0, 0.0, 0.0]
radius = 1.0
material = "plaster"
"#;

    fn error_of(text: &str) -> (String, String) {
        match from_table(&table(text), Path::new(".")) {
            Err(SceneError::AtKey { key, message }) => (key, message),
            other => panic!("expected an error at a key, got {other:?}"),
        }
    }

    #[test]
    fn a_good_table_is_the_scene_its_text_is() {
        let from_text = super::super::parse(SCENE, Path::new("."), "t").unwrap();
        let from_table = from_table(&table(SCENE), Path::new(".")).unwrap();
        assert_eq!(from_text.objects.len(), 2);
        assert_eq!(
            format!("{:?}", from_text.objects),
            format!("{:?}", from_table.objects)
        );
    }

    #[test]
    fn a_wrong_type_is_named_by_its_key_path() {
        let bad = SCENE.replacen("radius = 1.0\nmaterial = \"plaster\"\n\n[[objects]]\nshape = \"sphere\"\ncenter = [2.0, 0.0, 0.0]\nradius = 1.0", "radius = 1.0\nmaterial = \"plaster\"\n\n[[objects]]\nshape = \"sphere\"\ncenter = [2.0, 0.0, 0.0]\nradius = \"big\"", 1);
        let (key, message) = error_of(&bad);
        assert_eq!(key, "objects[1].radius", "{message}");
        assert!(message.contains("number"), "{message}");
    }

    #[test]
    fn a_value_out_of_range_is_named_by_its_key_path() {
        let bad = SCENE.replace("[camera]\n", "[camera]\nfov_y = 200.0\n");
        assert_eq!(error_of(&bad).0, "camera.fov_y");
        let bad = SCENE.replace("color = [0.9, 0.85, 0.8]", "color = [0.9, -1.0, 0.8]");
        assert_eq!(error_of(&bad).0, "materials.plaster.color");
    }

    #[test]
    fn nested_tables_of_array_elements_keep_the_index() {
        let text = "[[objects]]\nshape = \"a\"\n\n[[objects]]\nshape = \"b\"\n\n[objects.pattern]\nkind = \"checker\"\n";
        let paths = key_paths(text);
        assert_eq!(paths[4], "objects[1].shape");
        assert_eq!(paths[7], "objects[1].pattern.kind");
    }
}
