//! The `beamflow` command line: argument parsing, progress and messages. Each command is a
//! thin call into the library.

pub mod identify;
pub mod sweep;

use crate::error::Result;
use clap::{Parser, Subcommand};
use std::path::PathBuf;
use std::process::ExitCode;

/// Vibrational power flow from piezoelectric force actuators into beams.
#[derive(Parser, Debug)]
#[command(name = "beamflow", version, about, long_about = None)]
pub struct Cli {
    #[command(subcommand)]
    pub command: Command,
}

#[derive(Subcommand, Debug)]
pub enum Command {
    /// Natural modes of a case's bare beam, against closed-form values where they exist.
    Modes {
        case: PathBuf,
        /// Number of modes (default: the case's modes analysis, else 10).
        #[arg(long)]
        count: Option<usize>,
        /// Also write the frequencies and errors as JSON.
        #[arg(long)]
        json: Option<PathBuf>,
    },
    /// Runs every analysis of a case; writes HDF5, figures and a JSON summary.
    Run {
        case: PathBuf,
        /// Output directory (default: out/<case name>).
        #[arg(long)]
        out: Option<PathBuf>,
        /// Headline numbers as JSON (for scripts).
        #[arg(long)]
        json: Option<PathBuf>,
        /// Skip figures.
        #[arg(long)]
        no_plots: bool,
    },
    /// Reproduces the paper's experiments (Figs. 8–16): figures, HDF5 and a summary.
    Paper {
        #[arg(long, default_value = "out/paper")]
        out: PathBuf,
    },
    /// Checks a case file without running it.
    Check { case: PathBuf },
    /// Runs a parameter sweep in parallel.
    Sweep(sweep::SweepArgs),
    /// Joins sweep shards into one table.
    Merge(sweep::MergeArgs),
    /// Identifies stack and frame parameters from measurements.
    Identify(identify::IdentifyArgs),
    /// Makes synthetic measurements from a case, with noise.
    Synth(identify::SynthArgs),
}

/// The body of [`say!`](crate::say).
pub fn say_line(args: std::fmt::Arguments) {
    use std::io::Write;
    let mut out = std::io::stdout().lock();
    if let Err(e) = out.write_fmt(args).and_then(|()| out.write_all(b"\n")) {
        if e.kind() != std::io::ErrorKind::BrokenPipe {
            eprintln!("warning: could not write to standard output: {e}");
        }
    }
}

/// Entry point of the binary.
pub fn main() -> ExitCode {
    let cli = Cli::parse();
    match dispatch(&cli.command) {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("error: {e}");
            ExitCode::FAILURE
        }
    }
}

fn dispatch(cmd: &Command) -> Result<()> {
    match cmd {
        Command::Modes { case, count, json } => crate::app::commands::modes(case, *count, json.as_deref()),
        Command::Run { case, out, json, no_plots } => {
            crate::app::commands::run(case, out.as_deref(), json.as_deref(), !no_plots)
        }
        Command::Paper { out } => crate::app::paper::run(out),
        Command::Check { case } => crate::app::commands::check(case),
        Command::Sweep(a) => sweep::sweep(a),
        Command::Merge(a) => sweep::merge(a),
        Command::Identify(a) => identify::identify(a),
        Command::Synth(a) => identify::synth(a),
    }
}
