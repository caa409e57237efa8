//! FNV-1a (64 bits), the one digest shadelab keeps: a film's checksum of
//! its sums, a shard record's run digest, a scene's or a hook's content,
//! and the key that deals a case to its shard. A check against accidents
//! (bytes overwritten, files mixed up), not against forgery; stable across
//! versions and machines, as shard records and reference settings keep it.

/// FNV-1a of `bytes`.
pub fn fnv1a(bytes: &[u8]) -> u64 {
    bytes.iter().fold(0xcbf2_9ce4_8422_2325, |hash, byte| {
        (hash ^ u64::from(*byte)).wrapping_mul(0x0000_0100_0000_01b3)
    })
}

/// [`fnv1a`] as 16 hex digits, as records write it.
pub fn fnv1a_hex(bytes: &[u8]) -> String {
    format!("{:016x}", fnv1a(bytes))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The published test vectors (the empty string, "a").
    #[test]
    fn fnv1a_matches_its_test_vectors() {
        assert_eq!(fnv1a_hex(b""), "cbf29ce484222325");
        assert_eq!(fnv1a_hex(b"a"), "af63dc4c8601ec8c");
    }
}
