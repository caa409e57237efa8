//! `speed-vs-error.png` and `.svg`: GPU time (x) against model RMSE (y),
//! one point per variant coloured by mode, the Pareto front as a line
//! through its points with each one named.
//!
//! An axis is logarithmic when its positive values span more than a factor
//! of 10, linear from zero otherwise. On a log axis a value of zero (a
//! variant identical to the reference) is drawn on the axis's lower edge,
//! and the caption says so.

use plotters::coord::ranged1d::{AsRangedCoord, Ranged, ValueFormatter};
use plotters::coord::Shift;
use plotters::prelude::*;

use super::font::{Typeset, FAMILY};
use super::{encode_png, figure, mode_colour, PresentError, PARETO_COLOUR};
use crate::compare::report::Report;
use crate::shading::Shading;

pub const WIDTH: u32 = 960;
pub const HEIGHT: u32 = 600;

pub(crate) struct Plot {
    pub png: Vec<u8>,
    pub svg: String,
}

pub(crate) fn draw(report: &Report) -> Result<Plot, PresentError> {
    let err = |message: String| PresentError::Draw {
        what: "speed against error plot",
        message,
    };
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

fn chart<DB: DrawingBackend>(root: &DrawingArea<DB, Shift>, report: &Report) -> Result<(), String> {
    let x = Axis::fit(report.variants.iter().map(|v| v.timing.gpu_ms));
    let y = Axis::fit(report.variants.iter().map(|v| v.model_error.rmse));
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
) -> Result<(), String>
where
    DB: DrawingBackend,
    XS: AsRangedCoord<Value = f64>,
    YS: AsRangedCoord<Value = f64>,
    XS::CoordDescType: Ranged<ValueType = f64> + ValueFormatter<f64>,
    YS::CoordDescType: Ranged<ValueType = f64> + ValueFormatter<f64>,
{
    let e = |e: DrawingAreaErrorKind<DB::ErrorType>| e.to_string();
    root.fill(&WHITE).map_err(e)?;
    let clamped = report.variants.iter().any(|v| {
        let (px, py) = (v.timing.gpu_ms, v.model_error.rmse);
        px.is_finite() && py.is_finite() && (x.place(px) != px || y.place(py) != py)
    });
    let mut caption = format!(
        "{}, {} x {}: GPU time against model error",
        report.scene, report.width, report.height
    );
    if clamped {
        caption.push_str(" (error 0 drawn on the lower edge)");
    }
    let mut chart = ChartBuilder::on(root)
        .caption(caption, (FAMILY, 20))
        .margin(16)
        .x_label_area_size(44)
        .y_label_area_size(72)
        .build_cartesian_2d(x_spec, y_spec)
        .map_err(e)?;
    let scale = |log: bool| if log { "log scale" } else { "linear" };
    chart
        .configure_mesh()
        .x_desc(format!(
            "GPU time per frame, ms (median of {} runs; {})",
            report.runs,
            scale(x.log)
        ))
        .y_desc(format!(
            "model error: RMSE against the reference ({})",
            scale(y.log)
        ))
        .x_label_formatter(&|v| figure(*v))
        .y_label_formatter(&|v| figure(*v))
        .label_style((FAMILY, 13))
        .axis_desc_style((FAMILY, 14))
        .light_line_style(RGBColor(235, 235, 235))
        .bold_line_style(RGBColor(210, 210, 210))
        .draw()
        .map_err(e)?;

    let place = |gpu: f64, rmse: f64| (x.place(gpu), y.place(rmse));
    let finite = |gpu: f64, rmse: f64| gpu.is_finite() && rmse.is_finite();

    // The front first, so the points sit on top of its line.
    let mut front: Vec<_> = report
        .variants
        .iter()
        .filter(|v| v.pareto && finite(v.timing.gpu_ms, v.model_error.rmse))
        .collect();
    front.sort_by(|a, b| a.timing.gpu_ms.total_cmp(&b.timing.gpu_ms));
    let (pr, pg, pb) = PARETO_COLOUR;
    let pareto = RGBColor(pr, pg, pb);
    chart
        .draw_series(LineSeries::new(
            front
                .iter()
                .map(|v| place(v.timing.gpu_ms, v.model_error.rmse)),
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
            .filter(|v| v.variant.shading == mode && finite(v.timing.gpu_ms, v.model_error.rmse))
            .map(|v| place(v.timing.gpu_ms, v.model_error.rmse))
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

    // Name each front point, alternately above and below it so that
    // neighbours' names overlap less, and to its left where the name would
    // run past the plot's right edge.
    let label_style = TextStyle::from((FAMILY, 13).into_font());
    let (area_x, _) = chart.plotting_area().get_base_pixel();
    let (area_w, _) = chart.plotting_area().dim_in_pixel();
    for (i, v) in front.iter().enumerate() {
        let p = place(v.timing.gpu_ms, v.model_error.rmse);
        let (px, _) = chart.backend_coord(&p);
        let (tw, _) = root.estimate_text_size(&v.name, &label_style).map_err(e)?;
        let dx = if px + 10 + tw as i32 > area_x + area_w as i32 {
            -(tw as i32) - 10
        } else {
            10
        };
        let dy = if i % 2 == 0 { -20 } else { 8 };
        chart
            .draw_series(std::iter::once(
                EmptyElement::at(p)
                    + Circle::new((0, 0), 8, pareto.stroke_width(2))
                    + Text::new(v.name.clone(), (dx, dy), label_style.clone()),
            ))
            .map_err(e)?;
    }

    chart
        .configure_series_labels()
        .label_font((FAMILY, 13))
        .background_style(WHITE.mix(0.9))
        .border_style(RGBColor(160, 160, 160))
        .position(SeriesLabelPosition::UpperRight)
        .draw()
        .map_err(e)?;
    Ok(())
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
