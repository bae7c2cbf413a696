//! Shared helpers for the integration tests.
#![allow(dead_code)]

use beamflow::case::LoadedCase;
use std::path::PathBuf;

/// Parses case text as if it were a file named `name` in the repository's `cases/`.
pub fn case(text: &str) -> LoadedCase {
    LoadedCase::from_str(text, "test.toml", PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("cases"))
        .expect("test case must be valid")
}

/// The error message a bad case text produces.
pub fn case_error(text: &str) -> String {
    match LoadedCase::from_str(text, "bad.toml", PathBuf::from(".")) {
        Ok(lc) => match beamflow::case::build_model(&lc) {
            Ok(_) => panic!("case was accepted but should be rejected:\n{text}"),
            Err(e) => e.to_string(),
        },
        Err(e) => e.to_string(),
    }
}

/// Relative difference.
pub fn rel(a: f64, b: f64) -> f64 {
    (a - b).abs() / b.abs()
}
