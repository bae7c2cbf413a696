//! One error type for the whole crate.
//!
//! Bad input is the common failure of an engineering tool, so the variants are built to
//! say *where* (file, field) and *why*; a user should be able to fix a case file from the
//! message alone, without reading the source.

use std::path::Path;

/// Every fallible function in beamflow returns this.
#[derive(Debug, thiserror::Error)]
pub enum Error {
    /// A value in an input (case file, mesh file, CSV record, CLI argument) is not acceptable.
    #[error("{file}: field `{field}`: {reason}")]
    Input {
        /// The file the value came from (or `<cli>`, `<case>` for values built in code).
        file: String,
        /// Dotted path of the field, e.g. `beam.youngs_modulus`, or a column name.
        field: String,
        /// What is wrong and, where it helps, the accepted range.
        reason: String,
    },
    /// A file could not be parsed at all (syntax), with the parser's location.
    #[error("{file}: {message}")]
    Parse { file: String, message: String },
    /// Reading or writing a file failed.
    #[error("{path}: {source}")]
    Io {
        path: String,
        #[source]
        source: std::io::Error,
    },
    /// The HDF5 library reported an error.
    #[error("{path}: HDF5: {message}")]
    Hdf5 { path: String, message: String },
    /// A solver met a situation it cannot handle (singular matrix, no convergence).
    #[error("numerical failure: {0}")]
    Numerical(String),
}

/// Crate-wide result alias.
pub type Result<T> = std::result::Result<T, Error>;

impl Error {
    /// Shorthand for [`Error::Input`].
    pub fn input(file: impl Into<String>, field: impl Into<String>, reason: impl Into<String>) -> Self {
        Error::Input { file: file.into(), field: field.into(), reason: reason.into() }
    }

    /// Shorthand for [`Error::Io`] with the path that failed.
    pub fn io(path: impl AsRef<Path>, source: std::io::Error) -> Self {
        Error::Io { path: path.as_ref().display().to_string(), source }
    }
}
