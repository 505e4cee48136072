//! SHA-256 of bytes as lowercase hex: the one spelling of a file's hash in the suite's records
//! (frame records, asset records, scene hashes). In the light core, so that the assets (light
//! core) and the jobs (tracer) share it.

use sha2::{Digest, Sha256};

/// Lowercase hex SHA-256 of `bytes`.
pub fn sha256_hex(bytes: &[u8]) -> String {
    hex(&Sha256::digest(bytes))
}

/// Lowercase hex of a finished digest (for hashes fed in pieces, as a manifest's frames are).
pub fn hex(digest: &[u8]) -> String {
    digest.iter().map(|b| format!("{b:02x}")).collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    /// FIPS 180-2's test vectors: the empty input and "abc".
    #[test]
    fn the_standard_s_test_vectors_hash_to_their_published_digests() {
        assert_eq!(
            sha256_hex(b""),
            "e3b0c44298fc1c149afbf4c8996fb92427ae41e4649b934ca495991b7852b855"
        );
        assert_eq!(
            sha256_hex(b"abc"),
            "ba7816bf8f01cfea414140de5dae2223b00361a396177a9cb410ff61f20015ad"
        );
    }
}
