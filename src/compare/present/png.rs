//! The PNG images a presentation reads (each variant's image and heat map,
//! the reference) and the ones it encodes (the plot, the contact sheet).

use std::io::Cursor;
use std::path::Path;

use image::RgbImage;

use super::error::PresentError;

/// A PNG as read: its bytes (for data URIs) and its pixels.
pub(crate) struct Png {
    pub bytes: Vec<u8>,
    pub pixels: RgbImage,
}

impl Png {
    pub(super) fn read(dir: &Path, name: &str) -> Result<Png, PresentError> {
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
