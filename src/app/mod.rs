//! The application layer: what a user runs. The command line ([`cli`]) parses arguments
//! and calls [`commands`], which load a case or sweep, run it ([`runner`] for a case's
//! analyses, [`paper`] for the paper's experiments, [`identify`] for parameter
//! identification from measurements) and hand the results to `io` and `report`. Nothing
//! below this layer prints to the console, parses arguments or decides file names.

pub mod cli;
pub mod commands;
pub mod console;
pub mod identify;
pub mod optimize;
pub mod paper;
pub mod runner;
pub mod sweep;

/// The files a loaded case reads, for the overwrite checks of [`crate::io::paths`].
pub fn case_inputs(lc: &crate::case::LoadedCase) -> Vec<crate::io::paths::Input> {
    lc.input_files().into_iter().map(|(p, what)| crate::io::paths::Input::new(p, what)).collect()
}
