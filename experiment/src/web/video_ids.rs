//! Opaque names for encoded videos (issue 48 item 1 and 5). A subject's browser names a video by
//! a session-scoped id, HMAC-SHA-256(study key, "session" | subject token | pack hash): stable
//! for that subject (through server restarts, so the browser's cache stays valid), different
//! for every subject, and saying nothing of the level, point set, scene or stimulus to whoever
//! lacks the study key. An export for a static server names each video once for every subject,
//! HMAC(study key, "export" | pack hash). The study key is 128 random bits kept in
//! `OUT/web/tokens.json`.

use hmac::{Hmac, Mac};
use sha2::Sha256;

/// HMAC-SHA-256 (RFC 2104), by the RustCrypto `hmac` crate.
pub fn hmac_sha256(key: &[u8], message: &[u8]) -> [u8; 32] {
    let mut mac = Hmac::<Sha256>::new_from_slice(key).expect("HMAC takes a key of any length");
    mac.update(message);
    mac.finalize().into_bytes().into()
}

/// 32 lowercase hex digits (128 bits) of HMAC(key, parts joined by `|`).
fn name(key: &str, parts: &[&str]) -> String {
    let h = hmac_sha256(key.as_bytes(), parts.join("|").as_bytes());
    super::packs::hex(&h[..16])
}

/// The id subject `token` sees for the video whose pack hashes to `sha256`.
pub fn session_id(key: &str, token: &str, sha256: &str) -> String {
    name(key, &["session", token, sha256])
}

/// The file stem of the video whose pack hashes to `sha256` in a study's export.
pub fn export_name(key: &str, sha256: &str) -> String {
    name(key, &["export", sha256])
}

#[cfg(test)]
mod tests {
    use super::*;

    fn unhex(s: &str) -> Vec<u8> {
        (0..s.len())
            .step_by(2)
            .map(|i| u8::from_str_radix(&s[i..i + 2], 16).unwrap())
            .collect()
    }

    #[test]
    fn hmac_matches_rfc_4231() {
        // Test case 2 (a short key) and test case 6 (a key longer than the block).
        assert_eq!(
            super::super::packs::hex(&hmac_sha256(b"Jefe", b"what do ya want for nothing?")),
            "5bdcc146bf60754e6a042426089575c75a003f089d2739839dec58b964ec3843"
        );
        let key = [0xaau8; 131];
        let msg = b"Test Using Larger Than Block-Size Key - Hash Key First";
        assert_eq!(
            hmac_sha256(&key, msg).to_vec(),
            unhex("60e431591ee0b67f0d8a26aacbf5b77f8e0bc6213728c5140546040f0ee37f54")
        );
    }

    #[test]
    fn ids_differ_between_subjects_and_from_export_names() {
        let (k, sha) = ("0123456789abcdef0123456789abcdef", "ab".repeat(32));
        let a = session_id(k, "t1", &sha);
        assert_eq!(a, session_id(k, "t1", &sha), "stable");
        assert_ne!(a, session_id(k, "t2", &sha));
        assert_ne!(a, session_id("another key", "t1", &sha));
        assert_ne!(a, export_name(k, &sha));
        assert!(super::super::tokens::looks_like_token(&a));
    }
}
