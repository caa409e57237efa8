//! `golden`'s judging of one case: its render encoded as its reference
//! file would hold it, compared with the reference found (this driver's,
//! then the shared one), and what a person needs to see a failure written
//! into the output folder; references made (`--create`) or accepted
//! (`--bless`).

use std::path::{Path, PathBuf};

use crate::diff::{compare_images, Judging};
use crate::linear_image::LinearImage;
use crate::metrics;
use crate::output::{self, ImageFormat, ImageMetadata};
use crate::Error;

use super::case::{CaseError, Judged, Pictures, Status};
use super::keys;

/// Where a case's reference is: this driver's, then the shared one.
fn find_reference(references: &Path, key: &str, file: &str) -> Option<(PathBuf, &'static str)> {
    let own = references.join(key).join(file);
    let shared = references.join(file);
    if own.is_file() {
        Some((own, "driver"))
    } else if shared.is_file() {
        Some((shared, "shared"))
    } else {
        None
    }
}

/// `NAME-actual.png` for `NAME.png`, in NAME's folder (`hard/x-phong.png`
/// gives `hard/x-phong-actual.png`).
fn beside(file: &str, what: &str, ext: &str) -> String {
    let path = Path::new(file);
    let stem = path
        .file_stem()
        .map_or_else(|| file.to_string(), |s| s.to_string_lossy().into_owned());
    let name = format!("{stem}-{what}.{ext}");
    match path.parent().filter(|p| !p.as_os_str().is_empty()) {
        Some(folder) => folder.join(name).to_string_lossy().into_owned(),
        None => name,
    }
}

fn png_of(image: &LinearImage) -> Result<Vec<u8>, Error> {
    Ok(output::encode_with(
        image,
        Path::new("picture.png"),
        &ImageMetadata::software(),
    )?)
}

/// What made a reference: the `shadelab:settings` of a PNG that `render`
/// or `golden` wrote.
fn made_with(reference_bytes: &[u8]) -> Option<serde_json::Value> {
    let text = output::png_text(reference_bytes, "shadelab:settings")?;
    serde_json::from_str(&text).ok()
}

/// Where the reference was made, from its settings: `device (driver)`.
fn made_on(settings: &serde_json::Value) -> Option<String> {
    let device = settings["device"].as_str()?;
    let driver = settings["driver"].as_str().unwrap_or("no driver");
    Some(format!("{device} ({driver})"))
}

/// What judging a case needs: where the references are and this
/// driver's folder of them, the limits, what may be written (references
/// made or accepted), and the folder a failure's pictures go to.
#[derive(Debug, Clone)]
pub struct JudgeOptions {
    /// DIR/KEY/NAME (this driver's), then DIR/NAME (shared).
    pub references: PathBuf,
    /// This driver's folder of references (`keys::driver_key`).
    pub key: String,
    pub judging: Judging,
    /// Make a missing reference from the render.
    pub create: bool,
    /// Accept the render: rewrite a reference it is over the limits of,
    /// make a missing one.
    pub bless: bool,
    /// Write made and accepted references into this driver's folder.
    pub per_driver: bool,
    /// Where a case's render, heat map and scaled error go when it does
    /// not pass.
    pub out: PathBuf,
}

/// A case's render, as judging it needs it: the reference's file name,
/// the image and what its file records of it, and where it was made.
pub struct CaseRender<'a> {
    /// The reference's file name (`.png` or `.exr`), below the folders.
    pub file: &'a str,
    pub image: &'a LinearImage,
    /// Written into the render's file, as into a reference made from it.
    pub metadata: &'a ImageMetadata,
    /// The settings that made it (`shadelab:settings`), to name the ones
    /// a reference was made with that differ.
    pub settings: &'a serde_json::Value,
    pub device: &'a str,
    pub driver: Option<&'a str>,
}

/// Removes a case's pictures from an earlier run, which would be read as
/// this run's: they come back only if this case fails.
pub fn clear_pictures(out: &Path, file: &str) {
    for stale in [
        beside(file, "actual", "png"),
        beside(file, "actual", "exr"),
        beside(file, "diff", "png"),
        beside(file, "error", "png"),
    ] {
        let _ = std::fs::remove_file(out.join(stale));
    }
}

impl JudgeOptions {
    /// The path a made or blessed reference goes to.
    fn target(&self, file: &str, found: Option<&Path>) -> PathBuf {
        match (self.per_driver, found) {
            (false, Some(found)) => found.to_path_buf(),
            (false, None) => self.references.join(file),
            (true, _) => self.references.join(&self.key).join(file),
        }
    }

    /// Compares a case's render with its reference; writes what a person
    /// needs to see a failure, and the references made or blessed. The
    /// case's time is left for the caller, who knows the render's.
    pub fn judge(&self, made: &CaseRender) -> Result<Judged, Error> {
        let file = made.file;
        let render = Encoded::of(made)?;
        let found = find_reference(&self.references, &self.key, file);
        let mut judged = Judged::new(Status::Pass, found.clone());
        let Some((reference_path, _)) = &found else {
            self.judge_missing(file, &render, &mut judged)?;
            return Ok(judged);
        };
        let reference_bytes = std::fs::read(reference_path).map_err(|e| {
            Error::Usage(format!(
                "cannot read the reference {}: {e}",
                reference_path.display()
            ))
        })?;
        let expected = output::decode_image(&reference_bytes, render.format);
        let compared = match &expected {
            Ok(expected) => compare_images(expected, &render.image, &self.judging).map_err(|e| {
                format!(
                    "{} cannot be compared with the render: {e}",
                    reference_path.display()
                )
            }),
            Err(e) => Err(format!(
                "the reference {} cannot be read: {e}",
                reference_path.display()
            )),
        };
        let over = match &compared {
            Ok(pair) => !pair.failures.is_empty(),
            Err(_) => true,
        };
        if let Ok(pair) = &compared {
            judged.verdicts = pair.verdicts.clone();
            judged.failures = pair.failures.clone();
            judged.comparison = Some(pair.comparison.clone());
        }
        if !over {
            return Ok(judged);
        }
        if let Err(why) = &compared {
            judged.failures.push(why.clone());
        }
        judged.hint = why_else_it_differs(made, &reference_bytes);
        judged.pictures = Some(self.keep_against_reference(
            file,
            &render,
            &reference_bytes,
            &expected,
            &mut judged,
        )?);
        self.bless_or_fail(file, reference_path, &render, expected.is_ok(), &mut judged)?;
        Ok(judged)
    }

    /// A case with no reference: one made from the render (`--create`,
    /// `--bless`), or missing, its render kept to be seen.
    fn judge_missing(
        &self,
        file: &str,
        render: &Encoded,
        judged: &mut Judged,
    ) -> Result<(), Error> {
        if self.create || self.bless {
            let target = self.target(file, None);
            write_reference(&target, &render.bytes)?;
            judged.status = Status::Created;
            judged.reference = Some(target);
            judged.reference_kind = Some(if self.per_driver { "driver" } else { "shared" });
        } else {
            judged.status = Status::Missing;
            judged.failures.push(format!(
                "no reference {} (nor {}); run with --create to make it from this render",
                self.references.join(file).display(),
                self.references.join(&self.key).join(file).display()
            ));
            judged.pictures =
                Some(self.keep_pictures(file, render, None, None, &mut judged.written)?);
        }
        Ok(())
    }

    /// The pictures of a case over its limits: the reference (as a PNG, and
    /// as an image where it is the render's size), the render, the FLIP
    /// heat map and the scaled error.
    fn keep_against_reference(
        &self,
        file: &str,
        render: &Encoded,
        reference_bytes: &[u8],
        expected: &Result<LinearImage, String>,
        judged: &mut Judged,
    ) -> Result<Pictures, Error> {
        let heat = judged
            .comparison
            .as_ref()
            .map(|c| metrics::flip_heatmap(&c.flip));
        let expected_png = match expected {
            Ok(_) if render.format == ImageFormat::Png => Some(reference_bytes.to_vec()),
            Ok(image) => Some(png_of(image)?),
            Err(_) => None,
        };
        let actual = &render.image;
        let same_size = |e: &LinearImage| e.width == actual.width && e.height == actual.height;
        let expected_image = expected.as_ref().ok().filter(|e| same_size(e));
        self.keep_pictures(
            file,
            render,
            expected_png.map(|png| (png, expected_image)),
            heat.as_ref(),
            &mut judged.written,
        )
    }

    /// A case over its limits: its reference rewritten from the render
    /// under `--bless`, else failed (an error where the reference could
    /// not be read).
    fn bless_or_fail(
        &self,
        file: &str,
        reference_path: &Path,
        render: &Encoded,
        expected_read: bool,
        judged: &mut Judged,
    ) -> Result<(), Error> {
        if self.bless {
            let target = self.target(file, Some(reference_path));
            write_reference(&target, &render.bytes)?;
            // A driver's own reference made beside a shared one is new; any
            // other is the old one rewritten.
            judged.status = if target == *reference_path {
                Status::Updated
            } else {
                Status::Created
            };
            judged.reference = Some(target);
            if self.per_driver {
                judged.reference_kind = Some("driver");
            }
        } else if !expected_read {
            judged.status = Status::Error;
            judged.error = Some(CaseError {
                code: 2,
                message: judged.failures.join("; "),
            });
        } else {
            judged.status = Status::Fail;
        }
        Ok(())
    }

    /// Writes the render (`NAME-actual.EXT`), the FLIP heat map
    /// (`NAME-diff.png`) and the scaled error (`NAME-error.png`) into
    /// `--out`, and returns the pictures for the report. `expected` is the
    /// reference as a PNG, and as an image where it is the render's size.
    fn keep_pictures(
        &self,
        file: &str,
        render: &Encoded,
        expected: Option<(Vec<u8>, Option<&LinearImage>)>,
        heat: Option<&LinearImage>,
        written: &mut Vec<PathBuf>,
    ) -> Result<Pictures, Error> {
        let (format, actual_bytes, actual) = (render.format, &render.bytes, &render.image);
        let mut keep = |what: &str, image: &LinearImage| -> Result<Vec<u8>, Error> {
            let path = self.out.join(beside(file, what, "png"));
            let bytes = png_of(image)?;
            output::write_atomically(&path, &bytes)?;
            written.push(path);
            Ok(bytes)
        };
        let ext = match format {
            ImageFormat::Png => "png",
            ImageFormat::Exr => "exr",
        };
        let heatmap = heat.map(|heat| keep("diff", heat)).transpose()?;
        let (expected_png, expected_image) = expected.map_or((None, None), |(p, i)| (Some(p), i));
        let error = match expected_image {
            Some(reference) => {
                let (image, scale) = metrics::scaled_error_heatmap(reference, actual);
                Some((keep("error", &image)?, scale))
            }
            None => None,
        };
        let actual_path = self.out.join(beside(file, "actual", ext));
        output::write_atomically(&actual_path, actual_bytes)?;
        written.insert(0, actual_path);
        let actual_png = match format {
            ImageFormat::Png => actual_bytes.to_vec(),
            ImageFormat::Exr => png_of(actual)?,
        };
        Ok(Pictures {
            expected: expected_png,
            actual: actual_png,
            heatmap,
            error,
            width: actual.width,
            height: actual.height,
        })
    }
}

/// The render as its reference file would hold it: compared after the same
/// encoding, so that a repeated render is exactly equal.
struct Encoded {
    format: ImageFormat,
    /// The file's bytes.
    bytes: Vec<u8>,
    /// Those bytes decoded.
    image: LinearImage,
}

impl Encoded {
    fn of(made: &CaseRender) -> Result<Self, Error> {
        let file = made.file;
        let format = ImageFormat::from_path(Path::new(file))?;
        let bytes = output::encode_with(made.image, Path::new(file), made.metadata)?;
        let image = output::decode_image(&bytes, format)
            .map_err(|e| Error::Usage(format!("cannot decode the render of {file}: {e}")))?;
        Ok(Encoded {
            format,
            bytes,
            image,
        })
    }
}

/// Why a render over its limits may differ from its reference, besides a
/// change: the reference was made with other settings, or on another
/// driver.
fn why_else_it_differs(made: &CaseRender, reference_bytes: &[u8]) -> Option<String> {
    let reference_settings = made_with(reference_bytes);
    let mut hints = Vec::new();
    if let Some(settings) = &reference_settings {
        let differences = keys::settings_differences(settings, made.settings);
        if !differences.is_empty() {
            hints.push(format!(
                "the reference was made with other settings ({}): run with the reference's, or accept this render with --bless",
                differences.join(", ")
            ));
        }
    }
    if let Some(there) = reference_settings.as_ref().and_then(made_on) {
        let here = format!("{} ({})", made.device, made.driver.unwrap_or("no driver"));
        if there != here {
            hints.push(format!(
                "the reference was made on {there}, this render on {here}: where a driver's images differ, keep references per driver (--per-driver --bless)"
            ));
        }
    }
    (!hints.is_empty()).then(|| hints.join("; "))
}

fn write_reference(path: &Path, bytes: &[u8]) -> Result<(), Error> {
    output::prepare_output_path(path)?;
    Ok(output::write_atomically(path, bytes)?)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_drivers_own_reference_is_found_before_the_shared_one() {
        let dir = tempfile::tempdir().unwrap();
        let refs = dir.path();
        assert_eq!(find_reference(refs, "k", "a.png"), None);
        std::fs::write(refs.join("a.png"), b"x").unwrap();
        assert_eq!(
            find_reference(refs, "k", "a.png"),
            Some((refs.join("a.png"), "shared"))
        );
        std::fs::create_dir(refs.join("k")).unwrap();
        std::fs::write(refs.join("k/a.png"), b"x").unwrap();
        assert_eq!(
            find_reference(refs, "k", "a.png"),
            Some((refs.join("k/a.png"), "driver"))
        );
        assert_eq!(
            find_reference(refs, "other", "a.png"),
            Some((refs.join("a.png"), "shared"))
        );
    }
}
