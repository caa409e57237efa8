//! `diff`'s image readers (PNG decoded from sRGB, EXR as stored) on
//! arbitrary bytes: an error or an image whose pixel count matches its
//! size, never a panic.
#![no_main]

use libfuzzer_sys::fuzz_target;
use shadelab::output::{decode_image, ImageFormat};

fuzz_target!(|data: &[u8]| {
    for format in [ImageFormat::Png, ImageFormat::Exr] {
        if let Ok(image) = decode_image(data, format) {
            assert_eq!(
                image.pixels.len() as u64,
                u64::from(image.width) * u64::from(image.height)
            );
        }
    }
});
