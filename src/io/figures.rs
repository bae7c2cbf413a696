//! Standard figures of a case run.
use crate::case::LoadedCase;
use crate::error::Result;
use crate::runner::CaseRun;
use std::path::{Path, PathBuf};

pub fn plot_run(_dir: &Path, _stem: &str, _lc: &LoadedCase, _run: &CaseRun) -> Result<Vec<PathBuf>> {
    Ok(Vec::new())
}
