//! `speed-vs-error.png` and `.svg`: GPU time (x) against error (y: the
//! report's metric against its reference, `Report::error_of`), one point
//! per variant coloured by mode, the Pareto front as a line through its
//! points. Every point carries its number, placed where it overlaps no
//! other label and no point (`labels`); the numbers and names are listed
//! beside the plot.
//!
//! An axis is logarithmic when its positive values span more than a factor
//! of 10, linear from zero otherwise. On a log axis a value of zero (a
//! variant identical to the reference) is drawn on the axis's lower edge,
//! and the caption says so.

use plotters::coord::ranged1d::{AsRangedCoord, Ranged, ValueFormatter};
use plotters::coord::Shift;
use plotters::prelude::*;

use super::error::PresentError;
use super::font::{Typeset, FAMILY};
use super::labels::{place_labels, Rect};
use super::png::encode_png;
use super::style::{figure, mode_colour, PARETO_COLOUR};
use crate::compare::report::{Report, VariantResult};
use crate::shading::Shading;

pub const WIDTH: u32 = 1280;
pub const HEIGHT: u32 = 640;
/// The column beside the plot that lists each point's number and name.
const LIST_WIDTH: u32 = 400;
/// Half the side of the square a point's marker takes, in pixels.
const MARKER: i32 = 6;

pub(crate) struct Plot {
    pub png: Vec<u8>,
    pub svg: String,
}

fn draw_error(message: String) -> PresentError {
    PresentError::Draw {
        what: "speed against error plot",
        message,
    }
}

/// The boxes of every label the plot draws (point numbers and the list
/// beside the plot), in pixels: what the test of overlaps reads.
pub fn label_boxes(report: &Report) -> Result<Vec<Rect>, PresentError> {
    super::font::register()?;
    let mut rgb = vec![255u8; (WIDTH * HEIGHT * 3) as usize];
    let root = Typeset(BitMapBackend::with_buffer(&mut rgb, (WIDTH, HEIGHT))).into_drawing_area();
    chart(&root, report).map_err(draw_error)
}

pub(crate) fn draw(report: &Report) -> Result<Plot, PresentError> {
    let err = draw_error;
    let mut rgb = vec![255u8; (WIDTH * HEIGHT * 3) as usize];
    {
        let root =
            Typeset(BitMapBackend::with_buffer(&mut rgb, (WIDTH, HEIGHT))).into_drawing_area();
        chart(&root, report).map_err(err)?;
        root.present().map_err(|e| err(e.to_string()))?;
    }
    let image = image::RgbImage::from_raw(WIDTH, HEIGHT, rgb)
        .ok_or_else(|| err("the bitmap has the wrong size".into()))?;
    let png = encode_png(&image, "speed against error plot")?;

    let mut svg = String::new();
    {
        let root = SVGBackend::with_string(&mut svg, (WIDTH, HEIGHT)).into_drawing_area();
        chart(&root, report).map_err(err)?;
        root.present().map_err(|e| err(e.to_string()))?;
    }
    Ok(Plot { png, svg })
}

/// One axis: its range, and whether it is logarithmic.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct Axis {
    pub lo: f64,
    pub hi: f64,
    pub log: bool,
}

impl Axis {
    /// The axis for `values` (non-finite ones are ignored).
    pub fn fit(values: impl IntoIterator<Item = f64>) -> Axis {
        let finite: Vec<f64> = values.into_iter().filter(|v| v.is_finite()).collect();
        let positive = finite.iter().copied().filter(|&v| v > 0.0);
        let min_pos = positive.clone().fold(f64::INFINITY, f64::min);
        let max_pos = positive.fold(0.0, f64::max);
        let min = finite.iter().copied().fold(0.0, f64::min);
        let max = finite.iter().copied().fold(0.0, f64::max);
        if min_pos.is_finite() && max_pos / min_pos > 10.0 {
            Axis {
                lo: min_pos / 1.6,
                hi: max_pos * 1.6,
                log: true,
            }
        } else {
            let span = max - min;
            let pad = if span > 0.0 { span * 0.08 } else { 1.0 };
            Axis {
                lo: if min < 0.0 { min - pad } else { 0.0 },
                hi: max + pad,
                log: false,
            }
        }
    }

    /// Where `v` is drawn: clamped to the lower edge on a log axis.
    pub fn place(&self, v: f64) -> f64 {
        if self.log && v < self.lo {
            self.lo
        } else {
            v
        }
    }
}

fn chart<DB: DrawingBackend>(
    root: &DrawingArea<DB, Shift>,
    report: &Report,
) -> Result<Vec<Rect>, String> {
    let x = Axis::fit(report.variants.iter().map(|v| v.timing.gpu_ms));
    let y = Axis::fit(report.variants.iter().map(|v| report.error_of(v)));
    match (x.log, y.log) {
        (false, false) => chart_in(root, report, x, y, x.lo..x.hi, y.lo..y.hi),
        (true, false) => chart_in(root, report, x, y, (x.lo..x.hi).log_scale(), y.lo..y.hi),
        (false, true) => chart_in(root, report, x, y, x.lo..x.hi, (y.lo..y.hi).log_scale()),
        (true, true) => chart_in(
            root,
            report,
            x,
            y,
            (x.lo..x.hi).log_scale(),
            (y.lo..y.hi).log_scale(),
        ),
    }
}

fn chart_in<DB, XS, YS>(
    root: &DrawingArea<DB, Shift>,
    report: &Report,
    x: Axis,
    y: Axis,
    x_spec: XS,
    y_spec: YS,
) -> Result<Vec<Rect>, String>
where
    DB: DrawingBackend,
    XS: AsRangedCoord<Value = f64>,
    YS: AsRangedCoord<Value = f64>,
    XS::CoordDescType: Ranged<ValueType = f64> + ValueFormatter<f64>,
    YS::CoordDescType: Ranged<ValueType = f64> + ValueFormatter<f64>,
{
    let e = |e: DrawingAreaErrorKind<DB::ErrorType>| e.to_string();
    root.fill(&WHITE).map_err(e)?;
    let (plot_area, list_area) = root.split_horizontally(WIDTH - LIST_WIDTH);
    let mut chart = ChartBuilder::on(&plot_area)
        .caption(caption(report, x, y), (FAMILY, 20))
        .margin(16)
        .x_label_area_size(44)
        .y_label_area_size(72)
        .build_cartesian_2d(x_spec, y_spec)
        .map_err(e)?;
    draw_mesh(&mut chart, report, x, y)?;
    draw_points(&mut chart, report, x, y)?;
    let label_style = TextStyle::from((FAMILY, 13).into_font());
    let mut placed = draw_point_numbers(root, &chart, report, x, y, &label_style)?;
    placed.extend(draw_list(&list_area, report, &label_style)?);
    Ok(placed)
}

/// The plot's title, which says so when an error of 0 had to be drawn on a
/// log axis's lower edge.
fn caption(report: &Report, x: Axis, y: Axis) -> String {
    let clamped = report.variants.iter().any(|v| {
        let (px, py) = (v.timing.gpu_ms, report.error_of(v));
        px.is_finite() && py.is_finite() && (x.place(px) != px || y.place(py) != py)
    });
    let mut caption = format!(
        "{}, {} x {}: GPU time against error",
        report.scene, report.width, report.height
    );
    if clamped {
        caption.push_str(" (error 0 drawn on the lower edge)");
    }
    caption
}

/// Where a variant's point is drawn, or `None` when its time or error is
/// not finite and it is left out of the plot.
fn point(report: &Report, v: &VariantResult, x: Axis, y: Axis) -> Option<(f64, f64)> {
    let (gpu, error) = (v.timing.gpu_ms, report.error_of(v));
    (gpu.is_finite() && error.is_finite()).then(|| (x.place(gpu), y.place(error)))
}

/// The grid, the ticks and the axes' titles (metric, reference, scale).
fn draw_mesh<'a, DB, X, Y>(
    chart: &mut ChartContext<'a, DB, Cartesian2d<X, Y>>,
    report: &Report,
    x: Axis,
    y: Axis,
) -> Result<(), String>
where
    DB: DrawingBackend + 'a,
    X: Ranged<ValueType = f64> + ValueFormatter<f64>,
    Y: Ranged<ValueType = f64> + ValueFormatter<f64>,
{
    let scale = |log: bool| if log { "log scale" } else { "linear" };
    chart
        .configure_mesh()
        .x_desc(format!(
            "GPU time per frame, ms (median of {} runs; {})",
            report.runs,
            scale(x.log)
        ))
        .y_desc(format!(
            "{} against the {} ({})",
            report.plot_metric.name(),
            report.plot_reference.describe(),
            scale(y.log)
        ))
        .x_label_formatter(&|v| figure(*v))
        .y_label_formatter(&|v| figure(*v))
        .label_style((FAMILY, 13))
        .axis_desc_style((FAMILY, 14))
        .light_line_style(RGBColor(235, 235, 235))
        .bold_line_style(RGBColor(210, 210, 210))
        .draw()
        .map_err(|e| e.to_string())
}

/// The Pareto front's line, each mode's points, the front's points ringed,
/// and the legend of modes and front.
fn draw_points<'a, DB, X, Y>(
    chart: &mut ChartContext<'a, DB, Cartesian2d<X, Y>>,
    report: &Report,
    x: Axis,
    y: Axis,
) -> Result<(), String>
where
    DB: DrawingBackend + 'a,
    X: Ranged<ValueType = f64> + ValueFormatter<f64>,
    Y: Ranged<ValueType = f64> + ValueFormatter<f64>,
{
    let e = |e: DrawingAreaErrorKind<DB::ErrorType>| e.to_string();
    // The front first, so the points sit on top of its line.
    let mut front: Vec<_> = report
        .variants
        .iter()
        .filter(|v| v.pareto && point(report, v, x, y).is_some())
        .collect();
    front.sort_by(|a, b| a.timing.gpu_ms.total_cmp(&b.timing.gpu_ms));
    let front: Vec<(f64, f64)> = front
        .iter()
        .filter_map(|v| point(report, v, x, y))
        .collect();
    let (pr, pg, pb) = PARETO_COLOUR;
    let pareto = RGBColor(pr, pg, pb);
    chart
        .draw_series(LineSeries::new(
            front.iter().copied(),
            pareto.stroke_width(2),
        ))
        .map_err(e)?
        .label("Pareto front")
        .legend(move |(lx, ly)| {
            PathElement::new([(lx, ly), (lx + 18, ly)], pareto.stroke_width(2))
        });

    for mode in Shading::ALL {
        let points: Vec<_> = report
            .variants
            .iter()
            .filter(|v| v.variant.shading == mode)
            .filter_map(|v| point(report, v, x, y))
            .collect();
        if points.is_empty() {
            continue;
        }
        let (r, g, b) = mode_colour(mode);
        let colour = RGBColor(r, g, b);
        chart
            .draw_series(
                points
                    .into_iter()
                    .map(|p| Circle::new(p, 5, colour.filled())),
            )
            .map_err(e)?
            .label(mode.name())
            .legend(move |(lx, ly)| Circle::new((lx + 9, ly), 5, colour.filled()));
    }

    // The front's points ringed.
    chart
        .draw_series(
            front
                .iter()
                .map(|&p| Circle::new(p, MARKER as u32 + 3, pareto.stroke_width(2))),
        )
        .map_err(e)?;

    chart
        .configure_series_labels()
        .label_font((FAMILY, 13))
        .background_style(WHITE.mix(0.9))
        .border_style(RGBColor(160, 160, 160))
        .position(SeriesLabelPosition::UpperRight)
        .draw()
        .map_err(e)
}

/// Every drawn point's number, where it overlaps nothing, with a leader
/// line where it had to move away; returns the numbers' boxes.
fn draw_point_numbers<'a, DB, X, Y>(
    root: &DrawingArea<DB, Shift>,
    chart: &ChartContext<'a, DB, Cartesian2d<X, Y>>,
    report: &Report,
    x: Axis,
    y: Axis,
    label_style: &TextStyle,
) -> Result<Vec<Rect>, String>
where
    DB: DrawingBackend + 'a,
    X: Ranged<ValueType = f64> + ValueFormatter<f64>,
    Y: Ranged<ValueType = f64> + ValueFormatter<f64>,
{
    let e = |e: DrawingAreaErrorKind<DB::ErrorType>| e.to_string();
    let (area_x, area_y) = chart.plotting_area().get_base_pixel();
    let (area_w, area_h) = chart.plotting_area().dim_in_pixel();
    let bounds = Rect {
        left: area_x,
        top: area_y,
        right: area_x + area_w as i32,
        bottom: area_y + area_h as i32,
    };
    let drawn: Vec<(usize, (i32, i32))> = report
        .variants
        .iter()
        .enumerate()
        .filter_map(|(i, v)| Some((i, chart.backend_coord(&point(report, v, x, y)?))))
        .collect();
    let mut sizes = Vec::with_capacity(drawn.len());
    for (i, _) in &drawn {
        sizes.push(
            root.estimate_text_size(&(i + 1).to_string(), label_style)
                .map_err(e)?,
        );
    }
    let points: Vec<(i32, i32)> = drawn.iter().map(|(_, p)| *p).collect();
    let boxes = place_labels(&points, &sizes, bounds, MARKER);
    let mut placed = Vec::new();
    for ((i, (px, py)), found) in drawn.iter().zip(&boxes) {
        let Some(b) = found else { continue };
        let (cx, cy) = ((b.left + b.right) / 2, (b.top + b.bottom) / 2);
        // A leader line where the label had to move away from its point.
        if (cx - px).abs() + (cy - py).abs() > 4 * MARKER {
            root.draw(&PathElement::new(
                [(*px, *py), (cx, cy)],
                RGBColor(170, 170, 170).stroke_width(1),
            ))
            .map_err(e)?;
        }
        root.draw(&Text::new(
            (i + 1).to_string(),
            (b.left, b.top),
            label_style.clone(),
        ))
        .map_err(e)?;
        placed.push(*b);
    }
    Ok(placed)
}

/// `text` shortened in the middle (an ellipsis in place of what is cut)
/// until it is at most `max_width` pixels wide in `style`.
fn fit_width<DB: DrawingBackend>(
    area: &DrawingArea<DB, Shift>,
    text: &str,
    style: &TextStyle,
    max_width: u32,
) -> Result<String, String> {
    let e = |e: DrawingAreaErrorKind<DB::ErrorType>| e.to_string();
    let chars: Vec<char> = text.chars().collect();
    let mut fitted = text.to_string();
    let mut cut = 0;
    while area.estimate_text_size(&fitted, style).map_err(e)?.0 > max_width && cut < chars.len() {
        cut += 1;
        // Keep the start (the number and the mode) and the end (the file).
        let keep = chars.len() - cut;
        let head = keep * 2 / 5;
        let tail = keep - head;
        fitted = chars[..head].iter().collect::<String>()
            + "\u{2026}"
            + &chars[chars.len() - tail..].iter().collect::<String>();
    }
    Ok(fitted)
}

/// The list beside the plot: each variant's number and name, one per
/// line; returns the boxes of its lines.
fn draw_list<DB: DrawingBackend>(
    area: &DrawingArea<DB, Shift>,
    report: &Report,
    style: &TextStyle,
) -> Result<Vec<Rect>, String> {
    let e = |e: DrawingAreaErrorKind<DB::ErrorType>| e.to_string();
    let (left, top) = (area.get_base_pixel().0 + 8, 48);
    let (_, area_h) = area.dim_in_pixel();
    let line = ((area_h as i32 - top - 16) / report.variants.len().max(1) as i32).clamp(6, 18);
    let mut boxes = Vec::new();
    for (i, v) in report.variants.iter().enumerate() {
        let text = fit_width(
            area,
            &format!("{:>2}  {}", i + 1, v.name),
            style,
            LIST_WIDTH - 16,
        )?;
        let y = top + line * i as i32;
        // Lines closer than the text is tall would overlap: the font
        // shrinks with the spacing, so a long list still fits the column.
        let mut size = 13.0;
        let (mut fitted, (mut w, mut h)) = (
            style.clone(),
            area.estimate_text_size(&text, style).map_err(e)?,
        );
        while h as i32 > line && size > 4.0 {
            size -= 1.0;
            fitted = TextStyle::from((FAMILY, size).into_font());
            (w, h) = area.estimate_text_size(&text, &fitted).map_err(e)?;
        }
        area.draw(&Text::new(
            text,
            (left - area.get_base_pixel().0, y),
            fitted,
        ))
        .map_err(e)?;
        boxes.push(Rect::at(left, y, (w, h)));
    }
    Ok(boxes)
}

#[cfg(test)]
mod tests {
    use super::Axis;

    #[test]
    fn axes_go_logarithmic_past_a_factor_of_ten() {
        let a = Axis::fit([1.0, 5.0, 9.0]);
        assert!(!a.log);
        assert_eq!(a.lo, 0.0);
        assert!(a.hi > 9.0);
        let b = Axis::fit([0.5, 50.0, f64::NAN]);
        assert!(b.log);
        assert!(b.lo < 0.5 && b.hi > 50.0);
        // Zero stays on a log axis, at its lower edge.
        let c = Axis::fit([0.0, 0.001, 0.1]);
        assert!(c.log);
        assert_eq!(c.place(0.0), c.lo);
        assert_eq!(c.place(0.1), 0.1);
        // Nothing finite still gives a usable range.
        let d = Axis::fit([f64::NAN]);
        assert!(d.hi > d.lo);
    }
}
