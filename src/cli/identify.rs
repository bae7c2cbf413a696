//! `beamflow identify …` and `beamflow synth` (placeholder until wired).

use crate::error::{Error, Result};
use clap::{Args, Subcommand};
use std::path::PathBuf;

/// Arguments of `beamflow identify`.
#[derive(Args, Debug)]
pub struct IdentifyArgs {
    #[command(subcommand)]
    pub what: IdentifyCommand,
}

#[derive(Subcommand, Debug)]
pub enum IdentifyCommand {
    /// d_p from two records whose voltages differ by a constant offset.
    Dp { first: PathBuf, second: PathBuf },
}

/// Arguments of `beamflow synth`.
#[derive(Args, Debug)]
pub struct SynthArgs {
    pub case: PathBuf,
    #[arg(long)]
    pub out: PathBuf,
}

pub fn identify(_args: &IdentifyArgs) -> Result<()> {
    Err(Error::Numerical("identification is not available in this build".into()))
}

pub fn synth(_args: &SynthArgs) -> Result<()> {
    Err(Error::Numerical("synth is not available in this build".into()))
}
