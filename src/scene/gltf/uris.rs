//! A glTF URI's percent escapes (`%20`) decoded, for the names of the
//! files its buffers and images name.

/// `uri` with its %XX escapes decoded, as text (checked UTF-8 by
/// `check_buffer_uris` before).
pub(super) fn percent_decoded(uri: &str) -> String {
    String::from_utf8_lossy(&percent_decoded_bytes(uri)).into_owned()
}

/// `uri`'s bytes with each `%XX` escape replaced by its byte; a `%` not
/// followed by two hex digits is kept as it is.
pub(super) fn percent_decoded_bytes(uri: &str) -> Vec<u8> {
    let bytes = uri.as_bytes();
    let mut decoded = Vec::with_capacity(bytes.len());
    let mut i = 0;
    while i < bytes.len() {
        let hex = bytes
            .get(i + 1..i + 3)
            .filter(|h| h.iter().all(u8::is_ascii_hexdigit))
            .and_then(|h| u8::from_str_radix(std::str::from_utf8(h).ok()?, 16).ok());
        match (bytes[i], hex) {
            (b'%', Some(byte)) => {
                decoded.push(byte);
                i += 3;
            }
            (byte, _) => {
                decoded.push(byte);
                i += 1;
            }
        }
    }
    decoded
}
