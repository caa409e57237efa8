//! `contact-sheet.png`: every variant's image in a grid, scaled to
//! `THUMB_WIDTH`, with its name and "GPU x ms, RMSE y, FLIP z" (against
//! the report's one plotted reference) under it. Pareto variants get a thick orange border, the others a
//! thin grey one.

use image::imageops::{self, FilterType};
use image::{Rgb, RgbImage};
use plotters::prelude::*;
use plotters::style::TextStyle;

use super::error::PresentError;
use super::font::{Typeset, FAMILY};
use super::png::{encode_png, VariantImages};
use super::style::{figure, PARETO_COLOUR};
use crate::compare::report::{ReferenceChoice, Report, VariantResult};

pub const THUMB_WIDTH: u32 = 240;
/// The most columns; fewer when there are fewer variants.
pub const COLUMNS: u32 = 5;
const PAD: u32 = 14;
const BORDER: u32 = 4;
const LINE: u32 = 17;
const FONT_SIZE: f64 = 14.0;
const HEADER: u32 = 52;

fn draw_error(message: String) -> PresentError {
    PresentError::Draw {
        what: "contact sheet",
        message,
    }
}

/// Where the cells sit: `cols` to a row, each `cell_w` by `cell_h`, the
/// thumbnails at most `thumb_h` tall.
struct Grid {
    cols: u32,
    cell_w: u32,
    cell_h: u32,
    thumb_h: u32,
}

impl Grid {
    /// The top left corner of cell `i`.
    fn origin(&self, i: u32) -> (u32, u32) {
        (
            PAD + (i % self.cols) * self.cell_w,
            HEADER + (i / self.cols) * self.cell_h,
        )
    }
}

pub(crate) fn draw(report: &Report, images: &[VariantImages]) -> Result<Vec<u8>, PresentError> {
    let thumbs = thumbnails(images);
    let n = report.variants.len() as u32;
    let cols = n.clamp(1, COLUMNS);
    let rows = n.div_ceil(cols);
    let style = TextStyle::from((FAMILY, FONT_SIZE).into_font()).color(&BLACK);
    let labels = lay_out_labels(report, &style)?;
    let thumb_h = thumbs.iter().map(|t| t.height()).max().unwrap_or(1);
    let text_h = labels.iter().map(|l| l.len() as u32).max().unwrap_or(1) * LINE;
    let grid = Grid {
        cols,
        cell_w: THUMB_WIDTH + 2 * PAD,
        cell_h: thumb_h + text_h + 2 * PAD + BORDER,
        thumb_h,
    };
    let (w, h) = (cols * grid.cell_w + PAD, HEADER + rows * grid.cell_h);

    let mut sheet = RgbImage::from_pixel(w, h, Rgb([255, 255, 255]));
    paste_thumbnails(&mut sheet, &thumbs, report, &grid);
    let mut rgb = sheet.into_raw();
    draw_text(&mut rgb, (w, h), report, &labels, &style, &grid)?;
    let sheet =
        RgbImage::from_raw(w, h, rgb).ok_or_else(|| draw_error("wrong buffer size".into()))?;
    encode_png(&sheet, "contact sheet")
}

/// Each variant's image scaled to `THUMB_WIDTH`, its aspect kept.
fn thumbnails(images: &[VariantImages]) -> Vec<RgbImage> {
    images
        .iter()
        .map(|i| {
            let (w, h) = i.image.pixels.dimensions();
            let th = ((THUMB_WIDTH as f64 * h as f64 / w.max(1) as f64).round() as u32).max(1);
            imageops::resize(&i.image.pixels, THUMB_WIDTH, th, FilterType::Triangle)
        })
        .collect()
}

/// Every variant's lines of text. They are laid out before the sheet's
/// size is known, which depends on them: measured on a scratch backend
/// with the same font.
fn lay_out_labels(report: &Report, style: &TextStyle) -> Result<Vec<Vec<String>>, PresentError> {
    let mut scratch = vec![0u8; 3];
    let area = Typeset(BitMapBackend::with_buffer(&mut scratch, (1, 1))).into_drawing_area();
    let width = |s: &str| area.estimate_text_size(s, style).map(|(w, _)| w);
    report
        .variants
        .iter()
        .map(|v| label(v, report.plot_reference, &width))
        .collect::<Result<_, _>>()
        .map_err(|e| draw_error(e.to_string()))
}

/// Each thumbnail in its cell, framed: a thick orange border on the
/// Pareto front, a thin grey one elsewhere.
fn paste_thumbnails(sheet: &mut RgbImage, thumbs: &[RgbImage], report: &Report, grid: &Grid) {
    for (i, (thumb, v)) in thumbs.iter().zip(&report.variants).enumerate() {
        let (x, y) = grid.origin(i as u32);
        let (colour, width) = if v.pareto {
            (
                Rgb([PARETO_COLOUR.0, PARETO_COLOUR.1, PARETO_COLOUR.2]),
                BORDER,
            )
        } else {
            (Rgb([190, 190, 190]), 1)
        };
        let frame = RgbImage::from_pixel(
            thumb.width() + 2 * width,
            thumb.height() + 2 * width,
            colour,
        );
        imageops::replace(
            sheet,
            &frame,
            (x + BORDER - width) as i64,
            (y + BORDER - width) as i64,
        );
        imageops::replace(sheet, thumb, (x + BORDER) as i64, (y + BORDER) as i64);
    }
}

/// The title, the legend of the orange border, and each variant's lines
/// under its thumbnail, drawn into the sheet's pixels.
fn draw_text(
    rgb: &mut [u8],
    (w, h): (u32, u32),
    report: &Report,
    labels: &[Vec<String>],
    style: &TextStyle,
    grid: &Grid,
) -> Result<(), PresentError> {
    let root = Typeset(BitMapBackend::with_buffer(rgb, (w, h))).into_drawing_area();
    let e = |e: DrawingAreaErrorKind<_>| draw_error(e.to_string());
    let title = format!(
        "{}, {} x {}, {}: figures are the error against the {}",
        report.scene,
        report.width,
        report.height,
        report.device_and_driver(),
        report.plot_reference.describe()
    );
    root.draw_text(
        &title,
        &TextStyle::from((FAMILY, 16).into_font()),
        (PAD as i32, 14),
    )
    .map_err(e)?;
    let (pr, pg, pb) = PARETO_COLOUR;
    root.draw(&Rectangle::new(
        [(PAD as i32, 36), (PAD as i32 + 22, 46)],
        RGBColor(pr, pg, pb).filled(),
    ))
    .map_err(e)?;
    root.draw_text(
        &format!(
            "orange border: on the Pareto front of GPU time and {} against the {}",
            report.plot_metric.name(),
            report.plot_reference.describe()
        ),
        &TextStyle::from((FAMILY, 13).into_font()),
        (PAD as i32 + 30, 36),
    )
    .map_err(e)?;
    for (i, lines) in labels.iter().enumerate() {
        let (x, y) = grid.origin(i as u32);
        let top = y + grid.thumb_h + 2 * BORDER + 6;
        for (k, line) in lines.iter().enumerate() {
            root.draw_text(
                line,
                style,
                ((x + BORDER) as i32, (top + k as u32 * LINE) as i32),
            )
            .map_err(e)?;
        }
    }
    root.present().map_err(e)
}

/// The lines under one image: the name (broken after commas when it is too
/// wide), then the figures, broken after ", " when too wide.
fn label<E>(
    v: &VariantResult,
    reference: ReferenceChoice,
    width: &impl Fn(&str) -> Result<u32, E>,
) -> Result<Vec<String>, E> {
    let errors = v.errors_against(reference);
    let figures = format!(
        "GPU {} ms, RMSE {}, FLIP {}",
        figure(v.timing.gpu_ms),
        figure(errors.rmse),
        figure(errors.flip_mean)
    );
    let mut lines = wrap(&v.name, ",", width)?;
    lines.extend(wrap(&figures, ", ", width)?);
    Ok(lines)
}

/// Greedy wrapping at `sep` (kept at the end of a line) to `THUMB_WIDTH`.
/// A piece wider than that on its own stays whole.
fn wrap<E>(
    text: &str,
    sep: &str,
    width: &impl Fn(&str) -> Result<u32, E>,
) -> Result<Vec<String>, E> {
    let mut lines = Vec::new();
    let mut line = String::new();
    for piece in text.split_inclusive(sep) {
        let candidate = format!("{line}{piece}");
        if !line.is_empty() && width(candidate.trim_end())? > THUMB_WIDTH {
            lines.push(line.trim_end().to_string());
            line = piece.to_string();
        } else {
            line = candidate;
        }
    }
    lines.push(line.trim_end().to_string());
    Ok(lines)
}

#[cfg(test)]
mod tests {
    use super::wrap;

    #[test]
    fn wrapping_breaks_after_separators_only_when_needed() {
        // One "pixel" per character.
        let width = |s: &str| Ok::<u32, ()>(s.len() as u32);
        assert_eq!(wrap("flat", ",", &width).unwrap(), ["flat"]);
        let long = format!("{},{}", "a".repeat(200), "b".repeat(100));
        assert_eq!(
            wrap(&long, ",", &width).unwrap(),
            [format!("{},", "a".repeat(200)), "b".repeat(100)]
        );
        let unbreakable = "c".repeat(300);
        assert_eq!(wrap(&unbreakable, ",", &width).unwrap(), [unbreakable]);
    }
}
