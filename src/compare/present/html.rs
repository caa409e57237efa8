//! `report.html`: one self-contained page. The plot is inline SVG, every
//! image a base64 `data:` URI; there is no script and no external
//! resource, so it reads the same offline. All text from the report is
//! escaped.

use std::fmt::Write;

use base64::Engine;

use super::png::{Png, VariantImages};
use super::style::{figure, mode_colour, PARETO_COLOUR};
use crate::compare::report::{file_stem, Errors, Report};

pub use crate::markup::escape;

/// A `data:` URI for PNG bytes.
pub fn png_data_uri(bytes: &[u8]) -> String {
    format!(
        "data:image/png;base64,{}",
        base64::engine::general_purpose::STANDARD.encode(bytes)
    )
}

/// An `<img>` of PNG bytes, inline.
pub fn img(png_bytes: &[u8], width: u32, height: u32, alt: &str, class: &str) -> String {
    format!(
        r#"<img class="{class}" src="{}" width="{width}" height="{height}" alt="{}">"#,
        png_data_uri(png_bytes),
        escape(alt)
    )
}

fn png_img(png: &Png, alt: &str, class: &str) -> String {
    let (w, h) = png.pixels.dimensions();
    img(&png.bytes, w, h, alt, class)
}

/// The SVG document as an element to inline: no XML declaration, and no
/// namespace attribute (an HTML parser puts `<svg>` in the SVG namespace by
/// itself), so the page holds no URL at all.
fn inline_svg(svg: &str) -> String {
    let start = svg.find("<svg").unwrap_or(0);
    svg[start..].replacen(r#" xmlns="http://www.w3.org/2000/svg""#, "", 1)
}

const STYLE: &str = "
body { font-family: 'DejaVu Sans', Verdana, sans-serif; margin: 24px; color: #222; background: #fff; }
h1 { font-size: 1.5em; margin-bottom: 0.2em; }
h2 { font-size: 1.2em; margin-top: 1.6em; border-bottom: 1px solid #ddd; }
p.meta { color: #555; margin-top: 0; }
table { border-collapse: collapse; font-size: 0.85em; }
th, td { border: 1px solid #ccc; padding: 3px 7px; text-align: right; }
th { background: #f2f2f2; }
td.name { text-align: left; font-family: 'DejaVu Sans Mono', monospace; white-space: nowrap; }
tr.pareto td { background: #fff0e0; }
tr.pareto td.flag { color: #b35900; font-weight: bold; }
tr.fail td { background: #fde4e4; }
tr.fail td.flag { color: #b00000; font-weight: bold; }
span.swatch { display: inline-block; width: 0.8em; height: 0.8em; border-radius: 50%; margin-right: 0.4em; }
dl.legend dt { font-weight: bold; margin-top: 0.6em; }
dl.legend dd { margin-left: 1.5em; max-width: 60em; }
figure.variant { display: inline-block; vertical-align: top; margin: 0 18px 22px 0; }
figure.variant img { max-width: 512px; height: auto; border: 1px solid #ccc; margin-right: 6px; vertical-align: top; }
figure.pareto img.image { outline: 4px solid #ff7f0e; }
figcaption { font-size: 0.85em; margin-top: 4px; }
figcaption code { font-size: 1.1em; }
img.sheet { max-width: 100%; height: auto; }
div.plot svg { max-width: 100%; height: auto; }
";

/// A report page's head and title, with the reports' one style sheet:
/// `compare`'s and `golden`'s pages read alike. End it with [`PAGE_END`].
pub fn page_start(title: &str) -> String {
    format!(
        "<!DOCTYPE html>\n<html lang=\"en\">\n<head>\n<meta charset=\"utf-8\">\n<title>{}</title>\n<style>{STYLE}</style>\n</head>\n<body>\n<h1>{}</h1>\n",
        escape(title),
        escape(title)
    )
}

/// What closes a page begun with [`page_start`].
pub const PAGE_END: &str = "</body>\n</html>\n";

pub(crate) fn page(
    report: &Report,
    images: &[VariantImages],
    reference: Option<&Png>,
    plot_svg: &str,
    contact_sheet_png: &[u8],
) -> String {
    let title = format!("shadelab compare: {}", report.scene);
    let mut h = page_start(&title);
    meta(&mut h, report);
    plot_and_budget(&mut h, report, plot_svg);
    legend(&mut h, report);
    table(&mut h, report);
    contact_sheet(&mut h, contact_sheet_png);
    variants(&mut h, report, images);
    if let Some(r) = reference {
        let _ = writeln!(
            h,
            "<h2>Reference</h2>\n<figure class=\"variant\">{}<figcaption>{}</figcaption></figure>",
            png_img(r, "reference image", "image"),
            escape(&report.reference)
        );
    }
    h.push_str(PAGE_END);
    h
}

/// The line under the title (size, device, runs, reference, shard,
/// counts), and the variants not run with why.
fn meta(h: &mut String, report: &Report) {
    let shard = match report.shard {
        Some((i, n)) => format!("; shard {i} of {n}"),
        None => String::new(),
    };
    let _ = writeln!(
        h,
        "<p class=\"meta\">{} x {} pixels; device {}; {} per variant after a warm-up; reference: {}{}; {} variants, {} on the Pareto front.</p>",
        report.width,
        report.height,
        escape(&report.device_and_driver()),
        timed_runs(report.runs),
        escape(&report.reference),
        escape(&shard),
        report.variants.len(),
        report.variants.iter().filter(|v| v.pareto).count()
    );
    if !report.not_run.is_empty() {
        let _ = writeln!(
            h,
            "<p class=\"not-run\">Not run: {}.</p>",
            report
                .not_run
                .iter()
                .map(|v| format!("<code>{}</code> ({})", escape(&v.name), escape(&v.reason)))
                .collect::<Vec<_>>()
                .join("; ")
        );
    }
}

/// The plot, inline, and the budget's answer under it.
fn plot_and_budget(h: &mut String, report: &Report, plot_svg: &str) {
    h.push_str("<h2>Speed against error</h2>\n<div class=\"plot\">\n");
    h.push_str(&inline_svg(plot_svg));
    h.push_str("</div>\n");
    if let Some(budget) = &report.budget {
        let within = format!(
            "{} at most {}",
            report.plot_metric.name(),
            figure(budget.max_error)
        );
        let _ = match &budget.fastest {
            Some(name) => writeln!(
                h,
                "<p class=\"budget\">Budget: the fastest variant with {within} is <code>{}</code>.</p>",
                escape(name)
            ),
            None => writeln!(h, "<p class=\"budget\">Budget: no variant has {within}.</p>"),
        };
    }
}

fn contact_sheet(h: &mut String, contact_sheet_png: &[u8]) {
    h.push_str("<h2>Contact sheet</h2>\n");
    // The sheet's size is in its PNG header; the page only needs the ratio.
    let (sw, sh) = image::load_from_memory(contact_sheet_png)
        .map(|i| (i.width(), i.height()))
        .unwrap_or((0, 0));
    let _ = writeln!(
        h,
        "<p>{}</p>",
        img(
            contact_sheet_png,
            sw,
            sh,
            "contact sheet of every variant",
            "sheet"
        )
    );
}

/// Each variant's image beside its heat map, with its figures.
fn variants(h: &mut String, report: &Report, images: &[VariantImages]) {
    h.push_str("<h2>Variants</h2>\n<p>Each variant's image, and beside it the FLIP heat map of its error against the reference (black none, through purple and orange, to pale yellow for the most).</p>\n");
    for (v, imgs) in report.variants.iter().zip(images) {
        let class = if v.pareto {
            "variant pareto"
        } else {
            "variant"
        };
        let _ = writeln!(
            h,
            "<figure class=\"{class}\" id=\"{}\">{}{}<figcaption><code>{}</code>{}<br>GPU {} ms, model RMSE {}, FLIP {}; local RMSE {}; implementation RMSE {}</figcaption></figure>",
            escape(&file_stem(&v.name)),
            png_img(&imgs.image, &v.name, "image"),
            png_img(&imgs.heatmap, &format!("{} FLIP heat map", v.name), "heatmap"),
            escape(&v.name),
            if v.pareto { " (Pareto front)" } else { "" },
            figure(v.timing.gpu_ms),
            figure(v.model_error.rmse),
            figure(v.model_error.flip_mean),
            v.local_error.map_or_else(|| "-".to_string(), |e| figure(e.rmse)),
            figure(v.implementation_error.rmse),
        );
    }
}

fn legend(h: &mut String, report: &Report) {
    h.push_str("<h2>Reading the figures</h2>\n<dl class=\"legend\">\n");
    let _ = writeln!(
        h,
        "<dt>Implementation error</dt><dd>The variant rendered on the GPU against the CPU reference renderer running the same variant. It should be tiny: a large value means a bug in one of the two renderers, not a property of the shading model.</dd>\n\
<dt>Model error</dt><dd>The variant's GPU image against the scene's global reference image ({}): what the variant's simplifications cost in accuracy, shadows and reflections included.</dd>\n\
<dt>Local error</dt><dd>The variant's GPU image against the local reference ({}): the formula per pixel on exact geometry, without shadows, reflection or refraction, what Phong shading converges to. The plot, the Pareto front and the budget use {} against the {}.</dd>\n\
<dt>RMSE, max abs, PSNR, FLIP</dt><dd>Root mean square over every channel of every pixel, and the largest pixel error, both in linear intensity; PSNR in dB with peak 1.0 (&infin; for identical images); FLIP, NVIDIA's perceptual difference, averaged over the pixels (0 none, 1 the most).</dd>\n\
<dt>Times</dt><dd>Milliseconds, the median of {} after a warm-up, &plusmn; the spread (slowest minus fastest). GPU: queue submission to completion. Frame: the whole frame, uploads and read-back included (the pipeline is built once and reused). Pipeline: shader modules and pipeline creation, in the variant's first render. To image: that first render whole, the driver's code generation included.</dd>\n\
<dt><span class=\"swatch\" style=\"background: rgb{:?}\"></span>Pareto front</dt><dd>No other variant is at least as fast (GPU time) and at least as accurate (the plotted error), and strictly better in one. Marked orange in the plot, the table, the contact sheet and the images.</dd>",
        escape(&report.reference),
        escape(&report.local_reference),
        report.plot_metric.name(),
        report.plot_reference.describe(),
        timed_runs(report.runs),
        PARETO_COLOUR
    );
    h.push_str("</dl>\n");
}

fn table(h: &mut String, report: &Report) {
    h.push_str("<h2>Every figure</h2>\n<table>\n<thead>\n<tr><th rowspan=\"2\">variant</th><th colspan=\"4\">implementation error</th><th colspan=\"4\">model error</th><th colspan=\"4\">local error</th><th colspan=\"6\">time, ms</th><th rowspan=\"2\">Pareto</th></tr>\n<tr><th>RMSE</th><th>max abs</th><th>PSNR dB</th><th>FLIP</th><th>RMSE</th><th>max abs</th><th>PSNR dB</th><th>FLIP</th><th>RMSE</th><th>max abs</th><th>PSNR dB</th><th>FLIP</th><th>GPU</th><th>&plusmn;</th><th>frame</th><th>&plusmn;</th><th>pipeline</th><th>to image</th></tr>\n</thead>\n<tbody>\n");
    for v in &report.variants {
        let t = &v.timing;
        let (r, g, b) = mode_colour(v.variant.shading);
        let _ = write!(
            h,
            "<tr{}><td class=\"name\"><span class=\"swatch\" style=\"background: rgb({r}, {g}, {b})\"></span>{}</td>",
            if v.pareto { " class=\"pareto\"" } else { "" },
            escape(&v.name)
        );
        cells(h, &v.implementation_error);
        cells(h, &v.model_error);
        match &v.local_error {
            Some(e) => cells(h, e),
            None => h.push_str(&"<td>-</td>".repeat(4)),
        }
        for x in [
            t.gpu_ms,
            t.gpu_spread_ms,
            t.frame_ms,
            t.frame_spread_ms,
            t.pipeline_ms,
            t.image_ms,
        ] {
            let _ = write!(h, "<td>{}</td>", figure(x));
        }
        let _ = writeln!(
            h,
            "<td class=\"flag\">{}</td></tr>",
            if v.pareto { "&#9733; front" } else { "" }
        );
    }
    // The variants left out, in the same table, with why.
    for v in &report.not_run {
        let _ = writeln!(
            h,
            "<tr class=\"not-run\"><td class=\"name\">{}</td><td colspan=\"19\">not run: {}</td></tr>",
            escape(&v.name),
            escape(&v.reason)
        );
    }
    h.push_str("</tbody>\n</table>\n");
}

fn cells(h: &mut String, e: &Errors) {
    let psnr = e.psnr.map_or_else(|| "&infin;".to_string(), figure);
    let _ = write!(
        h,
        "<td>{}</td><td>{}</td><td>{}</td><td>{}</td>",
        figure(e.rmse),
        figure(e.max_abs),
        psnr,
        figure(e.flip_mean)
    );
}

/// "1 timed run", "3 timed runs".
fn timed_runs(n: usize) -> String {
    if n == 1 {
        "1 timed run".to_string()
    } else {
        format!("{n} timed runs")
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn escaping_covers_markup_and_quotes() {
        assert_eq!(
            escape(r#"<b>"a" & 'b'</b>"#),
            "&lt;b&gt;&quot;a&quot; &amp; &#39;b&#39;&lt;/b&gt;"
        );
    }

    #[test]
    fn inlined_svg_loses_its_declaration_and_namespace_url() {
        let svg = "<?xml version=\"1.0\"?>\n<svg width=\"2\" xmlns=\"http://www.w3.org/2000/svg\"><text>x</text></svg>";
        assert_eq!(inline_svg(svg), "<svg width=\"2\"><text>x</text></svg>");
    }
}
