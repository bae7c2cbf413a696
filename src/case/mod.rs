//! Case files: what a user writes (TOML), checked and turned into a [`Model`] plus the
//! analyses to run.
//!
//! Every table rejects unknown fields, every number is checked with a message naming the
//! file, the dotted field and the reason; defaults are the paper's beam and actuators
//! (`docs/case-format.md` lists them all).

pub mod build;
pub mod measured;
pub mod plate_mesh;
pub mod plausible;
pub mod ranges;
pub mod schema;
pub mod signal;

pub use build::build_model;
pub use schema::*;

use crate::error::{Error, Result};

impl Case {
    /// Checks every field, then the admissible range of every number (`ranges`); the first
    /// problem is returned, naming file and field.
    pub fn validate(&self, file: &str) -> Result<()> {
        self.validate_fields(file)?;
        ranges::check(self, file)
    }
}
use std::path::{Path, PathBuf};

/// A parsed case and where it came from.
#[derive(Clone, Debug)]
pub struct LoadedCase {
    pub case: Case,
    /// The file as given (for messages).
    pub file: String,
    /// Directory relative paths in the case are resolved against.
    pub dir: PathBuf,
    /// The TOML text, embedded in results.
    pub text: String,
}

impl LoadedCase {
    /// Reads and validates a case file.
    pub fn load(path: &Path) -> Result<LoadedCase> {
        let text = crate::input_file::read_text(path)?;
        let dir = path.parent().map(Path::to_path_buf).unwrap_or_default();
        LoadedCase::from_str(&text, &path.display().to_string(), dir)
    }

    /// Parses and validates case text; `file` names it in messages.
    pub fn from_str(text: &str, file: &str, dir: PathBuf) -> Result<LoadedCase> {
        let case: Case = crate::toml_input::parse(text, file, crate::toml_input::Kind::Case)?;
        case.validate(file).map_err(|e| plausible::blame_slips(e, &case))?;
        Ok(LoadedCase { case, file: file.to_string(), dir, text: text.to_string() })
    }

    /// The files this case reads, each with what it is (for messages): the case file
    /// itself and its [`Case::data_files`].
    pub fn input_files(&self) -> Vec<(PathBuf, String)> {
        let mut files = vec![(PathBuf::from(&self.file), "the case file".to_string())];
        files.extend(self.case.data_files(&self.dir, &self.file));
        files
    }

    /// A validated case that is solved and not written (an optimiser's candidate): its
    /// `text` is left empty, as nothing embeds it.
    pub fn unwritten(case: Case, file: &str, dir: PathBuf) -> Result<LoadedCase> {
        case.validate(file)?;
        Ok(LoadedCase { case, file: file.to_string(), dir, text: String::new() })
    }

    /// A case built in code (sweeps): serialised back to TOML so results embed what ran.
    pub fn from_case(case: Case, file: &str, dir: PathBuf) -> Result<LoadedCase> {
        case.validate(file)?;
        let text = toml::to_string(&case)
            .map_err(|e| Error::Parse { file: file.to_string(), message: format!("cannot serialise the case: {e}") })?;
        Ok(LoadedCase { case, file: file.to_string(), dir, text })
    }
}

impl Case {
    /// The mesh file the case's structure reads, if any: the field naming it
    /// (`beam.mesh.file`, `plate.mesh.file`) and the path as written.
    pub fn mesh_file(&self) -> Option<(&'static str, &str)> {
        match &self.plate {
            Some(p) => p.mesh.file.as_deref().map(|f| ("plate.mesh.file", f)),
            None => self.beam.mesh.file.as_deref().map(|f| ("beam.mesh.file", f)),
        }
    }

    /// The files besides itself a case (`file`) reads, relative paths resolved against
    /// `dir`, each with what it is: its mesh file and the CSV files of tabulated drives and
    /// loads.
    pub fn data_files(&self, dir: &Path, file: &str) -> Vec<(PathBuf, String)> {
        let mut files = Vec::new();
        if let Some((field, m)) = self.mesh_file() {
            files.push((dir.join(m), format!("the mesh file of {file} ({field})")));
        }
        let drives = self.actuator.iter().enumerate().map(|(i, a)| (format!("actuator[{i}].voltage"), &a.voltage));
        let loads = self.load.iter().enumerate().map(|(i, l)| (format!("load[{i}].force"), &l.force));
        for (field, signal) in drives.chain(loads) {
            if let crate::case::signal::SignalSpec::Series { file: csv, .. } = signal {
                files.push((dir.join(csv), format!("the series file of {file} ({field}.file)")));
            }
        }
        files
    }
}
