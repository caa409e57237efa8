//! The presentation of a comparison run: a `Report` and the images it names
//! become the files a person reads. It owns the CSV table, the speed
//! against error plot (PNG and SVG), the contact sheet and the
//! self-contained HTML page. It reads the report and its images and writes
//! those files; it renders nothing and measures nothing.
//!
//! Text is drawn with DejaVu Sans, embedded in the binary (`font.rs`), so
//! the images look the same on every machine and need no system fonts.

mod contact_sheet;
mod error;
mod font;
mod html;
pub mod labels;
pub mod plot;
mod png;
mod style;
mod table;
mod write;

pub use error::PresentError;
pub use html::{escape, img, page_start, png_data_uri, PAGE_END};
pub use write::{
    write_plot_as, write_presentation, Presented, CONTACT_SHEET, CSV, HTML, PLOT_PNG, PLOT_SVG,
};
