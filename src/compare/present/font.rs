//! The one font every image is drawn with: DejaVu Sans (Bitstream Vera
//! licence, `assets/fonts/DejaVuSans-LICENSE.txt`), embedded in the binary
//! and registered with plotters as `sans-serif`, so no system font or
//! fontconfig is needed.

use std::sync::OnceLock;

use plotters::style::FontStyle;

use super::PresentError;

static DEJAVU_SANS: &[u8] = include_bytes!("../../../assets/fonts/DejaVuSans.ttf");

/// The family name plotters text styles use.
pub(crate) const FAMILY: &str = "sans-serif";

/// Registers the font once per process.
pub(crate) fn register() -> Result<(), PresentError> {
    static DONE: OnceLock<bool> = OnceLock::new();
    let ok = *DONE.get_or_init(|| {
        plotters::style::register_font(FAMILY, FontStyle::Normal, DEJAVU_SANS).is_ok()
    });
    if ok {
        Ok(())
    } else {
        Err(PresentError::Draw {
            what: "text",
            message: "the embedded DejaVu Sans font does not parse".into(),
        })
    }
}
