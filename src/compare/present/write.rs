//! The files a presentation writes into a comparison's folder, and the
//! order it writes them in: the table, the plot, the contact sheet, then
//! the page that holds them all.

use std::path::{Path, PathBuf};

use super::error::PresentError;
use super::png::{Png, VariantImages};
use super::{contact_sheet, font, html, plot, table};
use crate::compare::report::Report;
use crate::output::write_atomically;

pub const CONTACT_SHEET: &str = "contact-sheet.png";
pub const PLOT_PNG: &str = "speed-vs-error.png";
pub const PLOT_SVG: &str = "speed-vs-error.svg";
pub const CSV: &str = "report.csv";
pub const HTML: &str = "report.html";

/// The files `write_presentation` wrote.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Presented {
    pub contact_sheet: PathBuf,
    pub plot_png: PathBuf,
    pub plot_svg: PathBuf,
    pub csv: PathBuf,
    pub html: PathBuf,
}

impl Presented {
    /// Every file, in the order they are written.
    pub fn all(&self) -> [&Path; 5] {
        [
            &self.csv,
            &self.plot_png,
            &self.plot_svg,
            &self.contact_sheet,
            &self.html,
        ]
    }
}

/// Writes `contact-sheet.png`, `speed-vs-error.png`, `speed-vs-error.svg`,
/// `report.csv` and `report.html` into `dir`, from `report` and the PNG
/// images it names (paths relative to `dir`). Each file is written to a
/// temporary name and renamed into place.
pub fn write_presentation(report: &Report, dir: &Path) -> Result<Presented, PresentError> {
    if report.variants.is_empty() {
        return Err(PresentError::NoVariants);
    }
    font::register()?;
    let mut images = Vec::with_capacity(report.variants.len());
    for v in &report.variants {
        images.push(VariantImages {
            image: Png::read(dir, &v.image)?,
            heatmap: Png::read(dir, &v.heatmap)?,
        });
    }
    let reference = if report.reference_image.is_empty() {
        None
    } else {
        Some(Png::read(dir, &report.reference_image)?)
    };

    let presented = Presented {
        contact_sheet: dir.join(CONTACT_SHEET),
        plot_png: dir.join(PLOT_PNG),
        plot_svg: dir.join(PLOT_SVG),
        csv: dir.join(CSV),
        html: dir.join(HTML),
    };

    write_atomically(&presented.csv, &table::csv(report)?)?;
    let plot = plot::draw(report)?;
    write_atomically(&presented.plot_png, &plot.png)?;
    write_atomically(&presented.plot_svg, plot.svg.as_bytes())?;
    let sheet = contact_sheet::draw(report, &images)?;
    write_atomically(&presented.contact_sheet, &sheet)?;
    let page = html::page(report, &images, reference.as_ref(), &plot.svg, &sheet);
    write_atomically(&presented.html, page.as_bytes())?;
    Ok(presented)
}

/// The plot of `report` (its own reference and front) as
/// `speed-vs-error-SUFFIX.png` and `.svg` in `dir`: the second plot of
/// `compare --reference both`. Returns the two paths.
pub fn write_plot_as(
    report: &Report,
    dir: &Path,
    suffix: &str,
) -> Result<(PathBuf, PathBuf), PresentError> {
    font::register()?;
    let plot = plot::draw(report)?;
    let png = dir.join(format!("speed-vs-error-{suffix}.png"));
    let svg = dir.join(format!("speed-vs-error-{suffix}.svg"));
    write_atomically(&png, &plot.png)?;
    write_atomically(&svg, plot.svg.as_bytes())?;
    Ok((png, svg))
}
