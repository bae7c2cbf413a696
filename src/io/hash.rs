//! Stable content hashes: FNV-1a for a sweep's id and a table's checksum (fast, not meant
//! to resist tampering), SHA-256 for the inputs named in a results file's provenance (the
//! hash `sha256sum` prints, so a user can check which file a result came from).

use sha2::{Digest, Sha256};
use std::path::Path;

/// FNV-1a, 64 bit: stable across platforms and versions of Rust (unlike `DefaultHasher`).
pub fn fnv1a(bytes: &[u8], mut h: u64) -> u64 {
    for &b in bytes {
        h ^= b as u64;
        h = h.wrapping_mul(0x0100_0000_01b3);
    }
    h
}

pub const FNV_OFFSET: u64 = 0xcbf2_9ce4_8422_2325;

/// The hash of a text as written in results: `sha256:` and 64 hex digits.
pub fn text_hash(text: &str) -> String {
    hex_digest(Sha256::digest(text.as_bytes()).as_slice())
}

/// The SHA-256 of a file's bytes, as [`text_hash`] writes it; read in blocks, so a model
/// file of any size costs no memory.
pub fn file_hash(path: &Path) -> std::io::Result<String> {
    let mut h = Sha256::new();
    std::io::copy(&mut std::fs::File::open(path)?, &mut h)?;
    Ok(hex_digest(h.finalize().as_slice()))
}

fn hex_digest(d: &[u8]) -> String {
    let hex: String = d.iter().map(|b| format!("{b:02x}")).collect();
    format!("sha256:{hex}")
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn sha256_gives_the_published_test_vectors() {
        // FIPS 180-2, appendix B.1 and the empty message.
        let abc = "sha256:ba7816bf8f01cfea414140de5dae2223b00361a396177a9cb410ff61f20015ad";
        assert_eq!(text_hash("abc"), abc);
        let empty = "sha256:e3b0c44298fc1c149afbf4c8996fb92427ae41e4649b934ca495991b7852b855";
        assert_eq!(text_hash(""), empty);
        let dir = tempfile::tempdir().unwrap();
        std::fs::write(dir.path().join("m"), "abc").unwrap();
        assert_eq!(file_hash(&dir.path().join("m")).unwrap(), abc);
    }
}
