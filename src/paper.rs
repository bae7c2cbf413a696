//! `beamflow paper`: the paper's nine experiments (Figs. 8–16).
use crate::error::{Error, Result};
use std::path::Path;

pub fn run(_out: &Path) -> Result<()> {
    Err(Error::Numerical("paper: not yet available".into()))
}
