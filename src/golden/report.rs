//! `golden`'s reports: the cases in JSON and JUnit, each case's record as
//! `golden.json` keeps it, and `report.html`: every case in a table, then
//! each one that did not pass (or was accepted) as its reference, its
//! render and the FLIP heat map side by side. One self-contained page in
//! `compare`'s style: images inline, no script, all text escaped.

use std::fmt::Write as _;
use std::path::Path;

use crate::compare::present::{escape, img, page_start, PAGE_END};
use crate::junit::TestCase;
use crate::metrics::format_figure;
use crate::output::write_atomically;
use crate::shading::Shading;
use crate::Error;

use super::case::{Judged, Status};
use super::record::{count, RunRecord};

/// A case as the report shows it.
pub struct ReportCase {
    pub scene: String,
    pub shading: Shading,
    /// The reference's file name.
    pub file: String,
    pub judged: Judged,
}

/// `shared: NAME` or `driver: NAME`: the folder is in the page's head.
fn reference_cell(j: &Judged) -> String {
    match (&j.reference, j.reference_kind) {
        (Some(path), Some(kind)) => {
            let name = path
                .file_name()
                .map_or_else(String::new, |n| n.to_string_lossy().into_owned());
            format!("{kind}: {name}")
        }
        _ => "none".to_string(),
    }
}

fn figure_cells(j: &Judged) -> String {
    match &j.comparison {
        Some(c) => format!(
            "<td>{}</td><td>{}</td><td>{}</td>",
            format_figure(c.stats.max_abs),
            (c.stats.fraction_over * c.stats.pixels as f64).round(),
            format_figure(c.flip.mean)
        ),
        None => "<td>-</td><td>-</td><td>-</td>".to_string(),
    }
}

/// The case in `--json`.
pub fn case_json(c: &ReportCase) -> serde_json::Value {
    let j = &c.judged;
    serde_json::json!({
        "scene": c.scene,
        "shading": c.shading,
        "file": c.file,
        "status": j.status,
        "reference": j.reference,
        "reference_kind": j.reference_kind,
        "failures": j.failures,
        "verdicts": j.verdicts,
        "figures": j.comparison,
        "hint": j.hint,
        "error": j.error.as_ref().map(|e| e.message.clone()),
        "written": j.written,
        "time_s": j.time_s,
    })
}

/// The cases in `--junit`.
pub fn junit_cases(cases: &[&ReportCase]) -> Vec<TestCase> {
    cases
        .iter()
        .map(|c| {
            let j = &c.judged;
            let mut lines = j.failures.clone();
            lines.extend(j.hint.clone());
            TestCase {
                classname: c.scene.clone(),
                name: c.shading.to_string(),
                time_s: j.time_s,
                failure: matches!(j.status, Status::Fail | Status::Missing)
                    .then(|| lines.join("\n")),
                error: (j.status == Status::Error).then(|| {
                    j.error
                        .as_ref()
                        .map_or_else(String::new, |e| e.message.clone())
                }),
                output: match j.status {
                    Status::Created | Status::Updated => format!(
                        "{} {}",
                        j.status.word().to_lowercase(),
                        j.reference
                            .as_ref()
                            .map_or_else(String::new, |p| p.display().to_string())
                    ),
                    _ => String::new(),
                },
            }
        })
        .collect()
}

/// A case's row of the page's table.
pub fn case_row_html(c: &ReportCase) -> String {
    let j = &c.judged;
    let class = if j.status == Status::Pass {
        ""
    } else {
        " class=\"fail\""
    };
    let mut why = j.failures.join("; ");
    if let Some(e) = &j.error {
        why = e.message.clone();
    }
    format!(
        "<tr{class}><td class=\"name\">{}</td><td class=\"name\">{}</td><td class=\"flag\">{}</td>{}<td class=\"name\">{}</td><td class=\"name\">{}</td></tr>\n",
        escape(&c.scene),
        c.shading,
        j.status.word(),
        figure_cells(j),
        escape(&reference_cell(j)),
        escape(&why)
    )
}

/// A case's pictures on the page (reference, render, FLIP, scaled error),
/// for a case that has them: one that did not pass, or was accepted.
pub fn case_figure_html(c: &ReportCase) -> Option<String> {
    let j = &c.judged;
    let p = j.pictures.as_ref()?;
    let mut h = format!(
        "<h2>{}/{}: {}</h2>\n<figure class=\"variant\">",
        escape(&c.scene),
        c.shading,
        j.status.word()
    );
    let label = |what: &str| format!("{} {what}", c.file);
    match &p.expected {
        Some(bytes) => h.push_str(&img(bytes, p.width, p.height, &label("reference"), "image")),
        None => h.push_str("<span>(no reference)</span>"),
    }
    h.push_str(&img(
        &p.actual,
        p.width,
        p.height,
        &label("render"),
        "image",
    ));
    if let Some(bytes) = &p.heatmap {
        h.push_str(&img(
            bytes,
            p.width,
            p.height,
            &label("FLIP heat map"),
            "image",
        ));
    }
    if let Some((bytes, _)) = &p.error {
        h.push_str(&img(
            bytes,
            p.width,
            p.height,
            &label("error, scaled"),
            "image",
        ));
    }
    let mut caption = vec![format!(
        "reference <code>{}</code>",
        escape(
            &j.reference
                .as_ref()
                .map_or_else(|| "none".into(), |p| p.display().to_string())
        )
    )];
    if let Some((_, scale)) = &p.error {
        caption.push(format!(
            "left to right: the reference, this render, FLIP (0 to 1), the error scaled so that its largest ({}) is pale yellow",
            format_figure(*scale)
        ));
    }
    caption.extend(j.failures.iter().map(|f| escape(f)));
    caption.extend(j.hint.iter().map(|f| escape(f)));
    let _ = writeln!(
        h,
        "<figcaption>{}</figcaption></figure>",
        caption.join("<br>")
    );
    Some(h)
}

/// What the page's head says of the run.
pub struct PageHead<'a> {
    pub references: &'a Path,
    pub key: &'a str,
    pub device: &'a str,
    pub driver: &'a str,
    pub limits: &'a str,
}

/// Writes the page to `path`: `passed` of `rows.len()` cases, each case's
/// table row, then the figures of those that have them (a run's, or a
/// merge of shards', in the whole run's order).
pub fn write_page(
    path: &Path,
    head: &PageHead,
    passed: usize,
    rows: &[String],
    figures: &[String],
) -> Result<(), Error> {
    let title = format!("shadelab golden: {passed} of {} cases passed", rows.len());
    let mut h = page_start(&title);
    let _ = writeln!(
        h,
        "<p class=\"meta\">references {} (this driver's: {}); device {} ({}); limits {}.</p>",
        escape(&head.references.display().to_string()),
        escape(&head.references.join(head.key).display().to_string()),
        escape(head.device),
        escape(head.driver),
        escape(head.limits)
    );
    h.push_str("<table>\n<tr><th>scene</th><th>mode</th><th>result</th><th>max_abs</th><th>pixels over 0.01</th><th>FLIP mean</th><th>reference</th><th>why</th></tr>\n");
    for row in rows {
        h.push_str(row);
    }
    h.push_str("</table>\n");
    if !figures.is_empty() {
        h.push_str("<h2>Against the references</h2>\n<p class=\"meta\">Each case: the reference, this render, the FLIP error between them (black none, through purple and orange, to pale yellow for 1), and the per-pixel error scaled so that its largest is pale yellow (where they differ, however little).</p>\n");
    }
    for figure in figures {
        h.push_str(figure);
    }
    h.push_str(PAGE_END);
    Ok(write_atomically(path, h.as_bytes())?)
}

/// Each case's record: its JSON, its place in the whole run (`order`), its
/// JUnit case and its rows of the page, as `golden.json` keeps them for
/// `--merge`.
pub fn case_records(cases: &[(usize, ReportCase)]) -> Vec<serde_json::Value> {
    let junit = junit_cases(&cases.iter().map(|(_, c)| c).collect::<Vec<_>>());
    cases
        .iter()
        .zip(&junit)
        .map(|((order, c), t)| {
            let mut v = case_json(c);
            v["order"] = (*order).into();
            v["junit"] = t.to_json();
            v["html_row"] = case_row_html(c).into();
            v["html_figure"] = case_figure_html(c).into();
            v
        })
        .collect()
}

/// `report.html` at `html` from the run's head and the cases' records
/// (their rows and figures): a run's, or a merge of shards'.
pub fn write_run_page(
    html: &Path,
    run: &RunRecord,
    records: &[serde_json::Value],
) -> Result<(), Error> {
    let rows: Vec<String> = records
        .iter()
        .map(|v| v["html_row"].as_str().unwrap_or_default().to_string())
        .collect();
    let figures: Vec<String> = records
        .iter()
        .filter_map(|v| v["html_figure"].as_str().map(str::to_string))
        .collect();
    let head = PageHead {
        references: &run.references,
        key: run.key.as_deref().unwrap_or_default(),
        device: &run.device,
        driver: &run.driver,
        limits: &run.limits,
    };
    write_page(html, &head, count(records, Status::Pass), &rows, &figures)
}
