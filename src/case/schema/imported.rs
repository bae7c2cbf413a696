//! A structure from another FE code (spec §17) as a case file writes it: `[imported]` in
//! place of `[beam]`, naming its matrix files and DOF map (paths relative to the case file).

use crate::error::{Error, Result};
use serde::{Deserialize, Serialize};
use std::path::{Path, PathBuf};

#[derive(Clone, Debug, Deserialize, Serialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct ImportedSpec {
    /// Mass matrix M (Matrix Market).
    pub mass: PathBuf,
    /// Stiffness matrix K (Matrix Market).
    pub stiffness: PathBuf,
    /// Damping matrix C (Matrix Market), used as given with `damping.kind = "given"`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub damping: Option<PathBuf>,
    /// The DOF map, `row,node,x_m,y_m,z_m,component` (CSV).
    pub dofs: PathBuf,
    /// 1-based matrix rows held at zero (boundary conditions not applied in the files).
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub fixed: Vec<usize>,
}

impl ImportedSpec {
    /// The files with paths resolved against the case's folder `dir`.
    pub fn files(&self, dir: &Path) -> crate::imported::Files {
        crate::imported::Files {
            mass: dir.join(&self.mass),
            stiffness: dir.join(&self.stiffness),
            damping: self.damping.as_ref().map(|d| dir.join(d)),
            dofs: dir.join(&self.dofs),
            fixed: self.fixed.clone(),
        }
    }

    pub(super) fn validate(&self, file: &str) -> Result<()> {
        for (field, p) in
            [("imported.mass", &self.mass), ("imported.stiffness", &self.stiffness), ("imported.dofs", &self.dofs)]
                .into_iter()
                .chain(self.damping.iter().map(|d| ("imported.damping", d)))
        {
            if p.as_os_str().is_empty() {
                return Err(Error::input(file, field, "an empty path: name the file"));
            }
        }
        if let Some(i) = self.fixed.iter().position(|&r| r == 0) {
            return Err(Error::input(file, format!("imported.fixed[{i}]"), "rows are 1-based: 0 is not a row"));
        }
        // A row named twice is most often a slip for another row.
        for (j, r) in self.fixed.iter().enumerate() {
            if let Some(i) = self.fixed[..j].iter().position(|x| x == r) {
                return Err(Error::input(
                    file,
                    format!("imported.fixed[{j}]"),
                    format!("row {r} is already listed as imported.fixed[{i}]: was another row meant?"),
                ));
            }
        }
        Ok(())
    }
}
