//! TOML and serde errors as one readable sentence with the file, line and
//! column: which table the line belongs to (`[materials.plaster]`,
//! `[[objects]] #2`, the `pattern` table of it), which key, and what was
//! expected, in the scene format's words rather than the parser's types.

use crate::scene::error::SceneError;

/// 1-based line and column of byte `offset` in `text`.
pub(super) fn line_col(text: &str, offset: usize) -> (usize, usize) {
    let offset = offset.min(text.len());
    let before = text.get(..offset).unwrap_or(text);
    let line = before.matches('\n').count() + 1;
    let col = before
        .rsplit('\n')
        .next()
        .map_or(1, |l| l.chars().count() + 1);
    (line, col)
}

/// The table header on a line (`[camera]`, `[[objects]]`), if it is one.
fn header_of(line: &str) -> Option<&str> {
    let t = line.split('#').next().unwrap_or("").trim();
    if t.starts_with('[') && t.ends_with(']') && !t.contains('=') {
        Some(t)
    } else {
        None
    }
}

/// The key of the inline table that column `column` (1-based) of `line`
/// lies in, for a line `key = { ... }`.
fn inline_table_key(line: &str, column: usize) -> Option<&str> {
    let (key, rest) = line.split_once('=')?;
    let key = key.trim();
    let brace = line.len() - rest.len() + rest.find('{')?;
    let bare = !key.is_empty()
        && key
            .chars()
            .all(|c| c.is_ascii_alphanumeric() || c == '_' || c == '-');
    (bare && rest.trim_start().starts_with('{') && column > brace + 1).then_some(key)
}

/// The table a 0-based line belongs to, as `[name]` or `[[objects]] #N`.
fn table_context(text: &str, line0: usize) -> Option<String> {
    let lines: Vec<&str> = text.lines().collect();
    let upto = lines.get(..=line0.min(lines.len().saturating_sub(1)))?;
    let (idx, header) = upto
        .iter()
        .enumerate()
        .rev()
        .find_map(|(i, l)| header_of(l).map(|h| (i, h)))?;
    if header.starts_with("[[") {
        let n = upto[..=idx]
            .iter()
            .filter(|l| header_of(l) == Some(header))
            .count();
        Some(format!("{header} #{n}"))
    } else {
        Some(header.to_string())
    }
}

/// The key assigned on the line of `offset` (`key = ...`), if any.
fn key_before(text: &str, offset: usize) -> Option<String> {
    let before = text.get(..offset.min(text.len()))?;
    let line = before.rsplit('\n').next()?;
    let eq = line.find('=')?;
    let key = line[..eq].trim();
    let ok = !key.is_empty()
        && key
            .chars()
            .all(|c| c.is_alphanumeric() || "_-.\"' ".contains(c));
    ok.then(|| key.to_string())
}

/// Turns serde's `a`, `b` list into `a, b`.
fn unquote_list(s: &str) -> String {
    s.replace('`', "")
}

/// ` in [table]` where the table is known.
fn in_ctx(c: &Option<String>) -> String {
    c.as_ref().map(|c| format!(" in {c}")).unwrap_or_default()
}

/// One readable sentence from a TOML parser error.
pub(super) fn toml_error(label: &str, text: &str, err: &toml::de::Error) -> SceneError {
    let raw = err
        .message()
        .lines()
        .map(str::trim)
        .filter(|l| !l.is_empty())
        .collect::<Vec<_>>()
        .join("; ");
    let Some(span) = err.span() else {
        return unplaced_error(label, raw);
    };
    let (line, column) = line_col(text, span.start);
    let line_text = text.lines().nth(line - 1).unwrap_or("");
    let on_header = header_of(line_text).is_some();
    let own_context = table_context(text, line - 1);
    let context = if on_header { None } else { own_context.clone() };
    // A key inside an inline table (`pattern = { ... }`) belongs to it.
    let context = match (inline_table_key(line_text, column), context) {
        (Some(key), Some(table)) => Some(format!("the `{key}` table of {table}")),
        (Some(key), None) => Some(format!("the `{key}` table")),
        (None, context) => context,
    };
    let message = if let Some(rest) = raw.strip_prefix("unknown field `") {
        unknown_key(rest, &context)
    } else if let Some(rest) = raw.strip_prefix("missing field `") {
        missing_key(rest, &own_context)
    } else if let Some(rest) = raw.strip_prefix("unknown variant `") {
        unknown_value(rest, key_before(text, span.start), &context)
    } else {
        wrong_value(&raw, key_before(text, span.start), &context)
    };
    SceneError::Syntax {
        file: label.to_string(),
        line,
        column,
        message,
    }
}

/// An error serde gives without a place: only a missing top-level table.
fn unplaced_error(label: &str, raw: String) -> SceneError {
    let message = if let Some(rest) = raw.strip_prefix("missing field `") {
        let key = rest.split('`').next().unwrap_or(rest);
        format!("missing required table [{key}]")
    } else {
        raw
    };
    SceneError::Toml {
        file: label.to_string(),
        message,
    }
}

/// `unknown key `k` in [table]; expected one of ...`, from what follows
/// serde's "unknown field `".
fn unknown_key(rest: &str, context: &Option<String>) -> String {
    let (key, tail) = rest.split_once('`').unwrap_or((rest, ""));
    let expected = tail
        .trim_start_matches(',')
        .trim()
        .strip_prefix("expected one of ")
        .or_else(|| {
            tail.trim_start_matches(',')
                .trim()
                .strip_prefix("expected ")
        })
        .map(unquote_list);
    match expected {
        Some(e) => format!(
            "unknown key `{key}`{}; expected one of {e}",
            in_ctx(context)
        ),
        None => format!(
            "unknown key `{key}`{}; {}",
            in_ctx(context),
            tail.trim_start_matches(',').trim()
        ),
    }
}

/// A missing key, from what follows serde's "missing field `"; the
/// camera is a table of its own.
fn missing_key(rest: &str, own_context: &Option<String>) -> String {
    let key = rest.split('`').next().unwrap_or(rest);
    if key == "camera" {
        "missing required table [camera]; expected at least [camera] with position and look_at"
            .to_string()
    } else {
        format!("missing required key `{key}`{}", in_ctx(own_context))
    }
}

/// A value outside an enum's names, from what follows serde's "unknown
/// variant `".
fn unknown_value(rest: &str, key: Option<String>, context: &Option<String>) -> String {
    let (value, tail) = rest.split_once('`').unwrap_or((rest, ""));
    let key = key.map(|k| format!(" for key `{k}`")).unwrap_or_default();
    format!(
        "unknown value `{value}`{key}{}; {}",
        in_ctx(context),
        unquote_list(tail.trim_start_matches(',').trim())
    )
}

/// Any other error at a key: serde's message, its Rust type names put in
/// the scene format's words.
fn wrong_value(raw: &str, key: Option<String>, context: &Option<String>) -> String {
    let key = key
        .map(|k| format!("key `{k}`{}: ", in_ctx(context)))
        .unwrap_or_default();
    let fixed = raw
        .replace("invalid type:", "wrong type:")
        .replace("expected i64", "expected an integer")
        .replace(
            "expected struct PatternRaw",
            "expected a table such as { kind = \"checker\" }",
        )
        .replace(
            "expected struct TextureRaw",
            "expected a table such as { file = \"floor.png\" }",
        );
    format!("{key}{fixed}")
}

#[cfg(test)]
mod tests {
    use super::super::test_support::*;

    #[test]
    fn unknown_key_names_key_line_and_table() {
        let text = with_camera("[materials.plaster]\ncolour = [1, 1, 1]\n");
        let e = parse_err(&text);
        assert_has(
            &e,
            &[
                "scene.toml",
                "line 5",
                "`colour`",
                "[materials.plaster]",
                "color",
                "ior",
            ],
        );
        let e = parse_err(&with_camera(
            "[materials.m]\n[[objects]]\nshape = \"sphere\"\ncentre = [0, 0, 0]\n",
        ));
        assert_has(&e, &["line 7", "`centre`", "[[objects]] #1", "center"]);
        let e = parse_err(&with_camera("[imgae]\nwidth = 3\n"));
        assert_has(&e, &["line 4", "`imgae`", "image"]);
        let e = parse_err("[camera]\nposition = [0, 0, 5]\nlook_at = [0, 0, 0]\nzoom = 2\n");
        assert_has(&e, &["line 4", "`zoom`", "[camera]", "fov_y"]);
    }

    #[test]
    fn missing_required_keys() {
        let e = parse_err("[camera]\nposition = [0, 0, 5]\n");
        assert_has(&e, &["scene.toml", "`look_at`", "[camera]"]);
        let e = parse_err("[image]\nwidth = 3\n");
        assert_has(&e, &["scene.toml", "[camera]"]);
        let e = parse_err(&with_camera("[materials.m]\n[[objects]]\nshape = \"sphere\"\ncenter = [0, 0, 0]\nmaterial = \"m\"\n"));
        assert_has(&e, &["line 6", "object 1 (sphere)", "`radius`"]);
        let e = parse_err(&with_camera(
            "[materials.m]\n[[objects]]\nshape = \"sphere\"\ncenter = [0, 0, 0]\nradius = 1\n",
        ));
        assert_has(&e, &["line 6", "object 1 (sphere)", "`material`"]);
        let e = parse_err(&with_camera("[[objects]]\nshape = \"mesh\"\n"));
        assert_has(&e, &["line 5", "`file`"]);
        let e = parse_err(&with_camera("[[lights]]\nposition = [0, 0, 0]\n"));
        assert_has(&e, &["`intensity`", "[[lights]] #1"]);
        let e = parse_err(&with_camera("[[objects]]\ncenter = [0, 0, 0]\n"));
        assert_has(&e, &["`shape`"]);
    }

    #[test]
    fn wrong_types() {
        let e = parse_err(&with_camera("[materials.m]\nka = \"high\"\n"));
        assert_has(&e, &["line 5", "`ka`", "wrong type", "finite number"]);
        let e = parse_err("[camera]\nposition = [0, 0]\nlook_at = [0, 0, 0]\n");
        assert_has(&e, &["line 2", "`position`", "3"]);
        let e = parse_err(&with_camera("[image]\nwidth = 640.5\n"));
        assert_has(&e, &["line 5", "`width`", "integer"]);
        let e = parse_err(&with_camera("[lighting]\ninterpolation = \"linear\"\n"));
        assert_has(&e, &["line 5", "`linear`", "perspective", "screen"]);
        let e = parse_err(&with_camera("[render]\nshadows = 1\n"));
        assert_has(&e, &["line 5", "`shadows`", "bool"]);
        let e = parse_err(&with_camera(
            "[[lights]]\nposition = [0, 0, 0]\nintensity = [1, 2]\n",
        ));
        assert_has(&e, &["line 6", "`intensity`", "3"]);
        let e = parse_err(&with_camera("lights = 3\n"));
        assert_has(&e, &["line 4", "`lights`"]);
        let e = parse_err("[camera\nposition = [0, 0, 5]\n");
        assert_has(&e, &["scene.toml line 1"]);
    }

    /// A texture or pattern given as a bare string is named as the table
    /// it should be, not as the loader's own type.
    #[test]
    fn a_texture_or_pattern_that_is_not_a_table_says_what_is_expected() {
        for (rest, parts) in [
            (
                "[materials.m]\ntexture = \"floor.png\"\n",
                &["line 5", "key `texture` in [materials.m]", "wrong type: string \"floor.png\", expected a table such as { file = \"floor.png\" }"][..],
            ),
            (
                "[materials.m]\npattern = \"checker\"\n",
                &["line 5", "expected a table such as { kind = \"checker\" }"],
            ),
        ] {
            let e = parse_err(&with_camera(rest));
            assert_has(&e, parts);
            assert!(!e.contains("Raw"), "{e}");
        }
    }

    #[test]
    fn messages_are_one_line_for_syntax_errors() {
        let e = parse_err("[camera]\nposition = [0, 0, 5\nlook_at = [0, 0, 0]\n");
        assert_has(&e, &["scene.toml line"]);
    }
}
