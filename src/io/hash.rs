//! A stable content hash of input text: what a sweep's id and a results file's case hash
//! are made of.

/// FNV-1a, 64 bit: stable across platforms and versions of Rust (unlike `DefaultHasher`).
pub fn fnv1a(bytes: &[u8], mut h: u64) -> u64 {
    for &b in bytes {
        h ^= b as u64;
        h = h.wrapping_mul(0x0100_0000_01b3);
    }
    h
}

pub const FNV_OFFSET: u64 = 0xcbf2_9ce4_8422_2325;

/// The hash of a text as written in results: `fnv1a64:` and 16 hex digits.
pub fn text_hash(text: &str) -> String {
    format!("fnv1a64:{:016x}", fnv1a(text.as_bytes(), FNV_OFFSET))
}
