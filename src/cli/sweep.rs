//! `beamflow sweep` and `beamflow merge` (placeholder until the sweep module lands).

use crate::error::{Error, Result};
use clap::Args;
use std::path::PathBuf;

/// Arguments of `beamflow sweep`.
#[derive(Args, Debug)]
pub struct SweepArgs {
    /// Sweep file (TOML).
    pub sweep: PathBuf,
    /// Output HDF5 table.
    #[arg(long)]
    pub out: PathBuf,
}

/// Arguments of `beamflow merge`.
#[derive(Args, Debug)]
pub struct MergeArgs {
    /// Shard files to join.
    pub shards: Vec<PathBuf>,
    #[arg(long)]
    pub out: PathBuf,
}

pub fn sweep(_args: &SweepArgs) -> Result<()> {
    Err(Error::Numerical("sweeps are not available in this build".into()))
}

pub fn merge(_args: &MergeArgs) -> Result<()> {
    Err(Error::Numerical("merge is not available in this build".into()))
}
