//! Encoding a `LinearImage` to files, and decoding image files back.
//!
//! `.png` is 8-bit sRGB of `clamp(I, 0, 1)`; `.exr` is linear 32-bit float,
//! unclamped. Files are written to a temporary name in the same folder and
//! renamed into place, so a failure never leaves a half-written image.

use std::io::Cursor;
use std::path::{Path, PathBuf};

use crate::linear_image::LinearImage;

#[derive(Debug, thiserror::Error)]
pub enum OutputError {
    #[error("cannot write {path}: the file name must end in .png or .exr")]
    UnknownFormat { path: PathBuf },
    #[error("cannot write {path}: {source}")]
    Write {
        path: PathBuf,
        source: std::io::Error,
    },
    #[error("cannot encode {path}: {message}")]
    Encode { path: PathBuf, message: String },
    #[error("cannot read image {path}: {message}")]
    Read { path: PathBuf, message: String },
}

#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ImageFormat {
    Png,
    Exr,
}

impl ImageFormat {
    pub fn from_path(path: &Path) -> Result<Self, OutputError> {
        let ext = path
            .extension()
            .and_then(|e| e.to_str())
            .map(str::to_ascii_lowercase);
        match ext.as_deref() {
            Some("png") => Ok(Self::Png),
            Some("exr") => Ok(Self::Exr),
            _ => Err(OutputError::UnknownFormat {
                path: path.to_owned(),
            }),
        }
    }
}

pub use crate::srgb::{linear_to_srgb8, srgb8_to_linear};

/// Text a PNG carries about how it was made (`tEXt` chunks, keyword and
/// text). Every PNG shadelab writes has `Software`; `render` adds the
/// scene, the device and its settings.
#[derive(Debug, Clone, Default)]
pub struct ImageMetadata {
    pub text: Vec<(String, String)>,
}

impl ImageMetadata {
    /// The `Software` entry alone: `shadelab <version>`.
    pub fn software() -> Self {
        Self {
            text: vec![(
                "Software".to_string(),
                format!("shadelab {}", env!("CARGO_PKG_VERSION")),
            )],
        }
    }

    /// Adds an entry (keywords are 1 to 79 Latin-1 characters; the PNG
    /// writer refuses others).
    pub fn with(mut self, keyword: &str, text: impl Into<String>) -> Self {
        self.text.push((keyword.to_string(), text.into()));
        self
    }
}

/// Encodes `image` in the format named by `path`'s extension, with
/// `metadata` in a PNG (an EXR carries none).
pub fn encode_with(
    image: &LinearImage,
    path: &Path,
    metadata: &ImageMetadata,
) -> Result<Vec<u8>, OutputError> {
    let format = ImageFormat::from_path(path)?;
    let mut bytes = Cursor::new(Vec::new());
    let encode_err = |e: image::ImageError| OutputError::Encode {
        path: path.to_owned(),
        message: e.to_string(),
    };
    match format {
        ImageFormat::Png => {
            let raw: Vec<u8> = image
                .pixels
                .iter()
                .flat_map(|p| p.map(linear_to_srgb8))
                .collect();
            encode_png(&raw, image.width, image.height, metadata, bytes.get_mut()).map_err(
                |e| OutputError::Encode {
                    path: path.to_owned(),
                    message: e.to_string(),
                },
            )?;
        }
        ImageFormat::Exr => {
            let raw: Vec<f32> = image.pixels.iter().flatten().copied().collect();
            let buffer = image::Rgb32FImage::from_raw(image.width, image.height, raw)
                .expect("pixel count matches the image size");
            buffer
                .write_to(&mut bytes, image::ImageFormat::OpenExr)
                .map_err(encode_err)?;
        }
    }
    Ok(bytes.into_inner())
}

/// 8-bit sRGB `rgb` as a PNG into `out`: the `sRGB` chunk (with the `gAMA`
/// and `cHRM` fallbacks the PNG standard gives for it), so that viewers
/// show it as sRGB, and `metadata`'s text.
fn encode_png(
    rgb: &[u8],
    width: u32,
    height: u32,
    metadata: &ImageMetadata,
    out: &mut Vec<u8>,
) -> Result<(), png::EncodingError> {
    let mut encoder = png::Encoder::new(out, width, height);
    encoder.set_color(png::ColorType::Rgb);
    encoder.set_depth(png::BitDepth::Eight);
    // The `image` crate's defaults, which this replaces: fast deflate,
    // adaptive filter (15 ms more an image with the balanced deflate).
    encoder.set_compression(png::Compression::Fast);
    encoder.set_filter(png::Filter::Adaptive);
    encoder.set_source_srgb(png::SrgbRenderingIntent::Perceptual);
    // The fallbacks the PNG standard gives beside sRGB, for readers that
    // know only gAMA and cHRM: gamma 1/2.2 (45455) and the sRGB primaries.
    encoder.set_source_gamma(png::ScaledFloat::from_scaled(45455));
    let at = |x: u32, y: u32| {
        (
            png::ScaledFloat::from_scaled(x),
            png::ScaledFloat::from_scaled(y),
        )
    };
    encoder.set_source_chromaticities(png::SourceChromaticities {
        white: at(31270, 32900),
        red: at(64000, 33000),
        green: at(30000, 60000),
        blue: at(15000, 6000),
    });
    for (keyword, text) in &metadata.text {
        encoder.add_text_chunk(keyword.clone(), text.clone())?;
    }
    let mut writer = encoder.write_header()?;
    writer.write_image_data(rgb)?;
    writer.finish()
}

/// Encodes and writes `image` to `path` atomically (temporary file, rename).
pub fn write_image(image: &LinearImage, path: &Path) -> Result<(), OutputError> {
    write_image_with(image, path, &ImageMetadata::software())
}

/// [`write_image`] with `metadata` in a PNG.
pub fn write_image_with(
    image: &LinearImage,
    path: &Path,
    metadata: &ImageMetadata,
) -> Result<(), OutputError> {
    let bytes = encode_with(image, path, metadata)?;
    write_atomically(path, &bytes)
}

/// Makes sure `path` can be written before any work is done for it: its
/// folder is created if missing, and a probe file is written in it and
/// removed. A command calls this for every output it will write, so that a
/// long render never ends in "cannot write".
pub fn prepare_output_path(path: &Path) -> Result<(), OutputError> {
    let write_err = |source| OutputError::Write {
        path: path.to_owned(),
        source,
    };
    if path.file_name().is_none() {
        return Err(write_err(std::io::Error::other("the path names no file")));
    }
    if path.is_dir() {
        return Err(write_err(std::io::Error::other("it is a folder")));
    }
    let folder = match path.parent() {
        Some(p) if !p.as_os_str().is_empty() => p.to_path_buf(),
        _ => std::path::PathBuf::from("."),
    };
    prepare_output_folder(&folder).map_err(|e| match e {
        OutputError::Write { source, .. } => write_err(source),
        other => other,
    })
}

/// Creates `folder` if missing and checks that a file can be written in it.
pub fn prepare_output_folder(folder: &Path) -> Result<(), OutputError> {
    let write_err = |source| OutputError::Write {
        path: folder.to_owned(),
        source,
    };
    std::fs::create_dir_all(folder).map_err(write_err)?;
    let probe = folder.join(format!(".shadelab-probe.{}.tmp", std::process::id()));
    std::fs::write(&probe, b"").map_err(write_err)?;
    let _ = std::fs::remove_file(&probe);
    Ok(())
}

/// The temporary files being written now, removed by
/// [`remove_temporary_files`] when the process is stopped by a signal.
static WRITING: std::sync::Mutex<Vec<std::path::PathBuf>> = std::sync::Mutex::new(Vec::new());

/// Removes the temporary files this process is writing: called from the
/// SIGINT/SIGTERM handler, so that a stopped render leaves no
/// `.NAME.PID.tmp` behind (69 to 111 MB for a 4096x4096 EXR).
pub fn remove_temporary_files() {
    let files = WRITING.lock().map(|w| w.clone()).unwrap_or_default();
    for file in files {
        let _ = std::fs::remove_file(file);
    }
}

/// Writes `bytes` to a temporary file beside `path`, then renames it.
/// Temporary files of this kind in the same folder left by a process
/// that no longer runs (one killed before it could clean up) are removed.
pub fn write_atomically(path: &Path, bytes: &[u8]) -> Result<(), OutputError> {
    let write_err = |source| OutputError::Write {
        path: path.to_owned(),
        source,
    };
    let file_name = path
        .file_name()
        .ok_or_else(|| write_err(std::io::Error::other("the path names no file")))?;
    let mut temp_name = std::ffi::OsString::from(".");
    temp_name.push(file_name);
    temp_name.push(format!(".{}.tmp", std::process::id()));
    let temp = path.with_file_name(temp_name);
    remove_stale_temporary_files(&temp);
    if let Ok(mut writing) = WRITING.lock() {
        writing.push(temp.clone());
    }
    let written = std::fs::write(&temp, bytes)
        .and_then(|()| std::fs::rename(&temp, path))
        .map_err(|e| {
            let _ = std::fs::remove_file(&temp);
            write_err(e)
        });
    if let Ok(mut writing) = WRITING.lock() {
        writing.retain(|t| *t != temp);
    }
    written
}

/// Removes `.NAME.PID.tmp` files in `temp`'s folder whose process is gone
/// (no `/proc/PID`), once per folder and process.
fn remove_stale_temporary_files(temp: &Path) {
    static CLEANED: std::sync::Mutex<Vec<std::path::PathBuf>> = std::sync::Mutex::new(Vec::new());
    let folder = match temp.parent() {
        Some(p) if !p.as_os_str().is_empty() => p.to_path_buf(),
        _ => std::path::PathBuf::from("."),
    };
    {
        let Ok(mut cleaned) = CLEANED.lock() else {
            return;
        };
        if cleaned.contains(&folder) {
            return;
        }
        cleaned.push(folder.clone());
    }
    if !Path::new("/proc/self").exists() {
        return; // no way to tell a live process from a dead one
    }
    let Ok(entries) = std::fs::read_dir(&folder) else {
        return;
    };
    for entry in entries.flatten() {
        let name = entry.file_name();
        if let Some(pid) = name.to_str().and_then(stale_temporary_pid) {
            if !Path::new(&format!("/proc/{pid}")).exists() {
                let _ = std::fs::remove_file(entry.path());
            }
        }
    }
}

/// The PID in a temporary file's name `.NAME.PID.tmp` as `write_atomically`
/// makes them, or `None` for any other name.
fn stale_temporary_pid(name: &str) -> Option<u32> {
    let inner = name.strip_prefix('.')?.strip_suffix(".tmp")?;
    let (stem, pid) = inner.rsplit_once('.')?;
    if stem.is_empty() || pid.is_empty() || !pid.bytes().all(|b| b.is_ascii_digit()) {
        return None;
    }
    pid.parse().ok()
}

/// The text of a PNG's `tEXt` chunk named `keyword` (where `render`
/// writes its settings), or `None` where there is none or `bytes` is not a
/// PNG.
pub fn png_text(bytes: &[u8], keyword: &str) -> Option<String> {
    let reader = png::Decoder::new(Cursor::new(bytes)).read_info().ok()?;
    let info = reader.info();
    info.uncompressed_latin1_text
        .iter()
        .find(|c| c.keyword == keyword)
        .map(|c| c.text.clone())
}

/// Reads a PNG (decoded from sRGB to linear) or an EXR (linear as stored).
pub fn read_image(path: &Path) -> Result<LinearImage, OutputError> {
    let read_err = |message: String| OutputError::Read {
        path: path.to_owned(),
        message,
    };
    let format = ImageFormat::from_path(path)
        .map_err(|_| read_err("the file name must end in .png or .exr".into()))?;
    let bytes = std::fs::read(path).map_err(|e| read_err(e.to_string()))?;
    decode_image(&bytes, format).map_err(read_err)
}

/// Decodes a PNG or EXR held in memory, as [`read_image`] does a file
/// (the format is guessed from the bytes; `format` picks the colour
/// conversion). The error is the decoder's message.
pub fn decode_image(bytes: &[u8], format: ImageFormat) -> Result<LinearImage, String> {
    let decoded = image::ImageReader::new(std::io::Cursor::new(bytes))
        .with_guessed_format()
        .map_err(|e| e.to_string())?
        .decode()
        .map_err(|e| e.to_string())?;
    let (width, height) = (decoded.width(), decoded.height());
    // A 16-bit PNG is read at its 16 bits: as 8 it lost up to 2e-3
    // (issue 30: 32768/65535 against 128/255 read as no difference).
    let sixteen_bits = matches!(
        decoded,
        image::DynamicImage::ImageLuma16(_)
            | image::DynamicImage::ImageLumaA16(_)
            | image::DynamicImage::ImageRgb16(_)
            | image::DynamicImage::ImageRgba16(_)
    );
    let pixels = match format {
        ImageFormat::Png if sixteen_bits => decoded
            .to_rgb16()
            .pixels()
            .map(|p| p.0.map(crate::srgb::srgb16_to_linear))
            .collect(),
        ImageFormat::Png => decoded
            .to_rgb8()
            .pixels()
            .map(|p| p.0.map(srgb8_to_linear))
            .collect(),
        ImageFormat::Exr => decoded.to_rgb32f().pixels().map(|p| p.0).collect(),
    };
    Ok(LinearImage {
        width,
        height,
        pixels,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn only_names_write_atomically_makes_are_temporary_files() {
        assert_eq!(stale_temporary_pid(".x.png.1234.tmp"), Some(1234));
        assert_eq!(stale_temporary_pid(".report.json.7.tmp"), Some(7));
        for other in [
            "x.png.1234.tmp",
            ".x.png.tmp",
            ".x.png.12a.tmp",
            "..1.tmp",
            ".x.png.1234",
        ] {
            assert_eq!(stale_temporary_pid(other), None, "{other}");
        }
    }

    /// A dead process's temporary file goes, a live one's and the user's
    /// files stay.
    #[test]
    fn a_dead_process_temporary_file_is_removed_on_the_next_write() {
        let dir = tempfile::tempdir().unwrap();
        // PIDs are below 2^22 on Linux: this one runs no process.
        let dead = dir.path().join(".big.exr.4194999.tmp");
        let live = dir
            .path()
            .join(format!(".big.exr.{}.tmp", std::process::id()));
        let user = dir.path().join(".notes.1.txt");
        for f in [&dead, &live, &user] {
            std::fs::write(f, b"x").unwrap();
        }
        write_atomically(&dir.path().join("out.json"), b"{}").unwrap();
        assert!(!dead.exists());
        assert!(live.exists());
        assert!(user.exists());
        assert_eq!(std::fs::read(dir.path().join("out.json")).unwrap(), b"{}");
    }
}
