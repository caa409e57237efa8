//! The presentation of a comparison run: a `Report` and the images it names
//! become the files a person reads. It owns the CSV table, the speed
//! against error plot (PNG and SVG), the contact sheet and the
//! self-contained HTML page. It reads the report and its images and writes
//! those files; it renders nothing and measures nothing.
//!
//! Text is drawn with DejaVu Sans, embedded in the binary (`font.rs`), so
//! the images look the same on every machine and need no system fonts.

mod contact_sheet;
mod font;
mod html;
pub mod labels;
pub mod plot;
mod table;

pub use html::{escape, img, page_start, png_data_uri, PAGE_END};

use std::io::Cursor;
use std::path::{Path, PathBuf};

use image::RgbImage;

use super::report::Report;
use crate::output::{write_atomically, OutputError};
use crate::shading::Shading;

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

#[derive(Debug, thiserror::Error)]
pub enum PresentError {
    #[error("the report has no variants to present")]
    NoVariants,
    #[error("cannot read image {path}: {message}")]
    ReadImage { path: PathBuf, message: String },
    #[error(transparent)]
    Write(#[from] OutputError),
    #[error("cannot draw the {what}: {message}")]
    Draw { what: &'static str, message: String },
}

impl PresentError {
    /// True for problems with the input (no variants, a missing or corrupt
    /// image), false for failures to draw or write.
    pub fn is_bad_input(&self) -> bool {
        matches!(
            self,
            PresentError::NoVariants | PresentError::ReadImage { .. }
        )
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

/// A PNG as read: its bytes (for data URIs) and its pixels.
pub(crate) struct Png {
    pub bytes: Vec<u8>,
    pub pixels: RgbImage,
}

impl Png {
    fn read(dir: &Path, name: &str) -> Result<Png, PresentError> {
        let path = dir.join(name);
        let err = |message: String| PresentError::ReadImage {
            path: path.clone(),
            message,
        };
        let bytes = std::fs::read(&path).map_err(|e| err(e.to_string()))?;
        let pixels = image::load_from_memory_with_format(&bytes, image::ImageFormat::Png)
            .map_err(|e| err(format!("not a readable PNG: {e}")))?
            .to_rgb8();
        Ok(Png { bytes, pixels })
    }
}

pub(crate) struct VariantImages {
    pub image: Png,
    pub heatmap: Png,
}

/// Encodes an RGB image as PNG bytes.
pub(crate) fn encode_png(image: &RgbImage, what: &'static str) -> Result<Vec<u8>, PresentError> {
    let mut bytes = Vec::new();
    image
        .write_to(&mut Cursor::new(&mut bytes), image::ImageFormat::Png)
        .map_err(|e| PresentError::Draw {
            what,
            message: e.to_string(),
        })?;
    Ok(bytes)
}

/// Each mode's colour in the plot and the page (matplotlib's tab10).
pub(crate) fn mode_colour(mode: Shading) -> (u8, u8, u8) {
    match mode {
        Shading::Flat => (31, 119, 180),
        Shading::Gouraud => (44, 160, 44),
        Shading::Phong => (214, 39, 40),
        Shading::Raytrace => (148, 103, 189),
    }
}

/// The colour that marks the Pareto front everywhere.
pub(crate) const PARETO_COLOUR: (u8, u8, u8) = (255, 127, 14);

/// A figure for people: 4 significant digits, scientific outside
/// [0.001, 100000), `0` for zero.
pub(crate) fn figure(x: f64) -> String {
    if x == 0.0 {
        return "0".into();
    }
    if !x.is_finite() {
        return format!("{x}");
    }
    let a = x.abs();
    if !(1e-3..1e5).contains(&a) {
        let s = format!("{x:.3e}");
        let (mantissa, exponent) = s.split_once('e').unwrap_or((&s, "0"));
        let mantissa = mantissa.trim_end_matches('0').trim_end_matches('.');
        return format!("{mantissa}e{exponent}");
    }
    let digits = 3 - a.log10().floor() as i32;
    let s = format!("{x:.*}", digits.max(0) as usize);
    if s.contains('.') {
        s.trim_end_matches('0').trim_end_matches('.').into()
    } else {
        s
    }
}

#[cfg(test)]
mod tests {
    use super::figure;

    #[test]
    fn figures_keep_four_significant_digits() {
        assert_eq!(figure(0.0), "0");
        assert_eq!(figure(12.3456), "12.35");
        assert_eq!(figure(0.0123456), "0.01235");
        assert_eq!(figure(1234.6), "1235");
        assert_eq!(figure(2.0), "2");
        assert_eq!(figure(0.00001234), "1.234e-5");
        assert_eq!(figure(0.0005), "5e-4");
        assert_eq!(figure(2.5e6), "2.5e6");
        assert_eq!(figure(-0.5), "-0.5");
        assert_eq!(figure(f64::NAN), "NaN");
    }
}
