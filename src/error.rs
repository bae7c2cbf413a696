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
    /// A setting a lower layer (model, assembly, analysis, solver) cannot accept, named in
    /// that layer's own terms. The layer that read the value from a file maps it to the
    /// file and field with [`Error::in_file`] (or [`Error::in_analysis`]); a lower layer
    /// never guesses which file a value came from.
    #[error("{scope} `{field}`: {reason}")]
    Setting {
        /// What `field` is relative to.
        scope: Scope,
        /// The setting's name within its scope, e.g. `duration`, `damping.kind`.
        field: String,
        reason: String,
    },
    /// A solver met a situation it cannot handle (singular matrix, no convergence).
    #[error("numerical failure: {0}")]
    Numerical(String),
    /// A factorisation met a zero, negative or non-finite pivot at `row` of the matrix it
    /// factors; the layer that knows the matrix's DOFs names the place
    /// ([`crate::assembly::DofMap::locate`]).
    #[error("numerical failure: {detail} (row {row})")]
    Singular { row: usize, detail: String },
    /// The work was asked to stop ([`crate::progress::Cancel`]) before it finished.
    #[error("stopped on request (interrupted) before the work was done")]
    Cancelled,
}

/// What the field of an [`Error::Setting`] is relative to.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Scope {
    /// A dotted path from the root of the case, e.g. `damping.kind`, `load[0].x`.
    Case,
    /// A field of the analysis being run, e.g. `duration` (the case's `analysis[i]` table).
    Analysis,
    /// An argument of a library function (identification, fitting) that the caller
    /// attributes to its own input.
    Argument,
}

impl std::fmt::Display for Scope {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(match self {
            Scope::Case => "case field",
            Scope::Analysis => "analysis setting",
            Scope::Argument => "argument",
        })
    }
}

/// Crate-wide result alias.
pub type Result<T> = std::result::Result<T, Error>;

impl Error {
    /// Shorthand for [`Error::Input`].
    pub fn input(file: impl Into<String>, field: impl Into<String>, reason: impl Into<String>) -> Self {
        Error::Input { file: file.into(), field: field.into(), reason: reason.into() }
    }

    /// A case field (dotted path from the case root) a lower layer cannot accept.
    pub fn case_field(field: impl Into<String>, reason: impl Into<String>) -> Self {
        Error::Setting { scope: Scope::Case, field: field.into(), reason: reason.into() }
    }

    /// A setting of the analysis being run that it cannot accept.
    pub fn analysis_setting(field: impl Into<String>, reason: impl Into<String>) -> Self {
        Error::Setting { scope: Scope::Analysis, field: field.into(), reason: reason.into() }
    }

    /// A function argument out of range.
    pub fn argument(field: impl Into<String>, reason: impl Into<String>) -> Self {
        Error::Setting { scope: Scope::Argument, field: field.into(), reason: reason.into() }
    }

    /// Names the file a setting came from: case fields and arguments keep their name,
    /// analysis settings are placed under `analysis` (the table path, e.g. `analysis[1]`);
    /// other errors pass through.
    pub fn in_analysis(self, file: &str, analysis: &str) -> Self {
        match self {
            Error::Setting { scope: Scope::Analysis, field, reason } => {
                Error::Input { file: file.to_string(), field: format!("{analysis}.{field}"), reason }
            }
            e @ (Error::Numerical(_) | Error::Singular { .. }) => {
                Error::Input { file: file.to_string(), field: analysis.to_string(), reason: e.to_string() }
            }
            e => e.in_file(file),
        }
    }

    /// Names the file and the table (`table`, e.g. `actuator[0].stack`) a setting came from:
    /// its field becomes `table.field`; other errors pass through.
    pub fn in_table(self, file: &str, table: &str) -> Self {
        match self {
            Error::Setting { field, reason, .. } => {
                Error::Input { file: file.to_string(), field: format!("{table}.{field}"), reason }
            }
            e => e,
        }
    }

    /// Names the file every setting came from (analysis settings keep their bare name).
    pub fn in_file(self, file: &str) -> Self {
        match self {
            Error::Setting { field, reason, .. } => Error::Input { file: file.to_string(), field, reason },
            e => e,
        }
    }

    /// Shorthand for [`Error::Io`] with the path that failed.
    pub fn io(path: impl AsRef<Path>, source: std::io::Error) -> Self {
        Error::Io { path: path.as_ref().display().to_string(), source }
    }
}
