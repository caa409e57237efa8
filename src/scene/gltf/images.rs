//! A texture's image: where its bytes lie (a buffer view, a base64 data
//! URI, or a file beside the glTF), its name in messages, and its bytes.

use std::borrow::Cow;
use std::path::PathBuf;

use super::document::GltfFile;
use super::uris::percent_decoded_bytes;
use crate::scene::error::SceneError;

/// Where an image's bytes lie.
pub(super) enum ImageSource<'f> {
    /// A file beside the glTF: its path and the URI's decoded name.
    File(PathBuf, String),
    /// A base64 data URI.
    DataUri(&'f str),
    /// A buffer view.
    View(gltf::buffer::View<'f>),
}

/// An image's name for messages: its file ("image 2 (`wood.png`)"), else
/// its name, else its index alone ("image 2").
pub(super) fn image_what(image: &gltf::Image, source: &ImageSource) -> String {
    let name = match source {
        ImageSource::File(_, name) => Some(name.clone()),
        _ => image.name().filter(|n| !n.is_empty()).map(str::to_string),
    };
    match name {
        Some(n) => format!("image {} (`{n}`)", image.index()),
        None => format!("image {}", image.index()),
    }
}

/// Where `image`'s bytes lie (checked by `check_images_and_textures`, so
/// that the `gltf` crate's `source` does not panic).
pub(super) fn image_source<'f>(
    file: &GltfFile,
    image: &gltf::Image<'f>,
) -> Result<ImageSource<'f>, SceneError> {
    Ok(match image.source() {
        gltf::image::Source::View { view, .. } => ImageSource::View(view),
        gltf::image::Source::Uri { uri, .. } if uri.starts_with("data:") => {
            ImageSource::DataUri(uri)
        }
        gltf::image::Source::Uri { uri, .. } => {
            if uri.contains(':') {
                return Err(SceneError::mesh(
                    &file.label,
                    format!(
                        "image {}: its uri `{uri}` is neither a file beside the glTF nor a data: URI; expected a relative file name or a data: URI",
                        image.index()
                    ),
                ));
            }
            let Ok(name) = String::from_utf8(percent_decoded_bytes(uri)) else {
                return Err(SceneError::mesh(
                    &file.label,
                    format!(
                        "image {}: its uri `{uri}` percent-decodes to bytes that are not UTF-8; expected a file name or a data: URI",
                        image.index()
                    ),
                ));
            };
            ImageSource::File(file.base.join(&name), name)
        }
    })
}

/// The bytes of an image, read (a file), decoded (a data URI) or borrowed
/// (a buffer view); `what` names it in messages.
pub(super) fn image_bytes<'f>(
    file: &'f GltfFile,
    source: &ImageSource<'f>,
    what: &str,
) -> Result<Cow<'f, [u8]>, SceneError> {
    let err = |message: String| SceneError::mesh(&file.label, format!("{what} {message}"));
    match source {
        ImageSource::File(path, name) => std::fs::read(path).map(Cow::Owned).map_err(|e| {
            err(format!(
                "names the file `{name}`, which cannot be read ({}: {e}); put it beside the .gltf or fix the uri",
                path.display()
            ))
        }),
        ImageSource::DataUri(uri) => {
            use base64::Engine;
            let (header, data) = uri.split_once(',').unwrap_or((uri, ""));
            if !header.ends_with(";base64") {
                return Err(err(format!(
                    "is a data URI that is not base64 (`{}`); expected data:image/png;base64,... or data:image/jpeg;base64,...",
                    header.chars().take(60).collect::<String>()
                )));
            }
            base64::engine::general_purpose::STANDARD
                .decode(data)
                .map(Cow::Owned)
                .map_err(|e| err(format!("is a data URI that is not valid base64 ({e})")))
        }
        ImageSource::View(view) => {
            let bytes = file
                .buffers
                .get(view.buffer().index())
                .and_then(|b| b.get(view.offset()..view.offset().checked_add(view.length())?));
            bytes.map(Cow::Borrowed).ok_or_else(|| {
                err(format!(
                    "is in buffer view {}, which runs past the end of buffer {}",
                    view.index(),
                    view.buffer().index()
                ))
            })
        }
    }
}
