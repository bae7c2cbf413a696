//! The `beamflow` command line: argument parsing, progress and messages. Each command is a
//! thin call into the library.

pub mod identify;
pub mod optimize;
pub mod progress;
pub mod sweep;

use super::console::{is_stdout, set_status, write_text_or_stdout, Status};
use crate::error::Result;
use clap::{Parser, Subcommand};
use std::path::PathBuf;
use std::process::ExitCode;

/// Vibrational power flow from piezoelectric force actuators into beams, plates and
/// imported FE models.
#[derive(Parser, Debug)]
#[command(name = "beamflow", version, about, long_about = None)]
pub struct Cli {
    /// Print no status lines (results files and errors only).
    #[arg(long, global = true)]
    pub quiet: bool,
    /// Resolution of PNG figures in dots per inch (default 100, e.g. 1000 × 600 pixels for a
    /// plot; 50 to 600), for the commands that draw figures. SVG figures do not depend on
    /// it.
    #[arg(long, global = true, value_name = "DPI", allow_negative_numbers = true)]
    pub dpi: Option<i64>,
    /// Formats of every figure the command draws, comma-separated: png, svg, pdf (default
    /// png,svg). SVG is always among them: the HTML reports hold it. PDF is vector, for
    /// publishers.
    #[arg(long, global = true, value_name = "LIST", value_delimiter = ',')]
    pub formats: Option<Vec<String>>,
    #[command(subcommand)]
    pub command: Command,
}

#[derive(Subcommand, Debug)]
pub enum Command {
    /// Natural modes of a case's bare structure (beam, plate or imported model), against
    /// closed-form values where they exist.
    Modes {
        /// The case file (TOML; see docs/case-format.md).
        case: PathBuf,
        /// Number of modes (default: the case's modes analysis, else 10).
        #[arg(long, allow_negative_numbers = true, value_parser = count::<1>)]
        count: Option<usize>,
        /// Also write the frequencies and errors as JSON (`-`: standard output, status
        /// lines then go to standard error).
        #[arg(long)]
        json: Option<PathBuf>,
    },
    /// Runs every analysis of a case; writes HDF5, figures and a JSON summary.
    Run {
        /// The case file (TOML; see docs/case-format.md).
        case: PathBuf,
        /// Output directory (default: out/<case name>).
        #[arg(long)]
        out: Option<PathBuf>,
        /// Headline numbers as JSON, for scripts (`-`: standard output, status lines then
        /// go to standard error).
        #[arg(long)]
        json: Option<PathBuf>,
        /// Skip figures.
        #[arg(long)]
        no_plots: bool,
        /// Also write the results as tidy CSV tables (units in the header line).
        #[arg(long)]
        csv: bool,
        #[command(flatten)]
        budget: BudgetArgs,
    },
    /// Reproduces the paper's experiments (Figs. 8–16): figures, HDF5 and a summary.
    Paper {
        /// Output directory.
        #[arg(long, default_value = "out/paper")]
        out: PathBuf,
        /// Also write each run's results as tidy CSV tables (units in the header line).
        #[arg(long)]
        csv: bool,
        #[command(flatten)]
        budget: BudgetArgs,
    },
    /// Checks a case file without running it (with the same bounds as `run`).
    Check {
        /// The case file (TOML; see docs/case-format.md).
        case: PathBuf,
        #[command(flatten)]
        budget: BudgetArgs,
    },
    /// Runs a parameter sweep in parallel.
    Sweep(sweep::SweepArgs),
    /// Joins sweep shards into one table.
    Merge(sweep::MergeArgs),
    /// Finds the actuator placement (and drive) that maximises or minimises an objective.
    Optimize(optimize::OptimizeArgs),
    /// Identifies stack and frame parameters from measurements.
    Identify(identify::IdentifyArgs),
    /// Makes synthetic measurements from a case, with noise.
    Synth(identify::SynthArgs),
    /// Prints a shell completion script, e.g. `beamflow completions bash > ~/.local/share/bash-completion/completions/beamflow`.
    Completions {
        /// The shell.
        shell: clap_complete::Shell,
    },
}

/// What one request may take: memory and steps, estimated before it runs and refused
/// above these (see `crate::analysis::budget`).
#[derive(clap::Args, Debug, Clone, Default)]
pub struct BudgetArgs {
    /// Most memory one analysis may take, e.g. 8G or 512M (default: half of the memory the
    /// machine has available).
    #[arg(long, value_name = "SIZE", allow_hyphen_values = true, value_parser = crate::analysis::budget::parse_bytes)]
    pub max_memory: Option<u64>,
    /// Most time steps (or samples) one analysis may step through, and most cases of a
    /// sweep or an optimisation, e.g. 1e10 (default: 1e9).
    #[arg(long, value_name = "N", allow_negative_numbers = true, value_parser = crate::analysis::budget::parse_steps)]
    pub max_steps: Option<u64>,
}

impl BudgetArgs {
    /// The machine's default budget with these overrides.
    pub fn budget(&self) -> crate::analysis::budget::Budget {
        crate::analysis::budget::Budget::with(self.max_memory, self.max_steps)
    }
}

/// Parses a whole-number flag whose admissible values start at `MIN`. A negative number
/// reaches this parser as the flag's value (`allow_negative_numbers` on the flag), not as
/// an unknown flag, and is refused here with the range; values from 0 to `MIN` pass on to
/// the command's own check, which explains why they are too few.
pub fn count<const MIN: usize>(text: &str) -> std::result::Result<usize, String> {
    let refuse = || format!("{text}: give a whole number, at least {MIN}");
    match text.trim().parse::<i128>() {
        Ok(v) if v < 0 => Err(refuse()),
        Ok(v) => usize::try_from(v).map_err(|_| format!("{text}: give a whole number from {MIN} to {}", usize::MAX)),
        Err(_) => Err(refuse()),
    }
}

/// Entry point of the binary.
pub fn main() -> ExitCode {
    ExitCode::from(main_with(std::env::args_os()))
}

/// The command line on `args` (the program name first), as the binary runs it; returns its
/// exit status (the Python package's `beamflow` command calls this).
pub fn main_with<I: IntoIterator<Item = T>, T: Into<std::ffi::OsString> + Clone>(args: I) -> u8 {
    let cli = match Cli::try_parse_from(args) {
        Ok(cli) => cli,
        // --help and --version too: printed as clap prints them, with clap's status.
        Err(e) => {
            let _ = e.print();
            return e.exit_code() as u8;
        }
    };
    let json_to_stdout = match &cli.command {
        Command::Modes { json, .. } | Command::Run { json, .. } => json.as_deref().is_some_and(is_stdout),
        _ => false,
    };
    set_status(if cli.quiet {
        Status::Quiet
    } else if json_to_stdout {
        Status::Stderr
    } else {
        Status::Stdout
    });
    if let Some(Err(e)) = cli.dpi.map(crate::report::plot::set_png_dpi) {
        eprintln!("error: {e}");
        return 1;
    }
    if let Some(Err(e)) = cli.formats.as_deref().map(crate::report::plot::set_figure_formats) {
        eprintln!("error: {e}");
        return 1;
    }
    // Progress bars for the long computations of this thread, where someone can see them.
    let result = if !cli.quiet && std::io::IsTerminal::is_terminal(&std::io::stderr()) {
        crate::progress::observe(std::rc::Rc::new(progress::ConsoleBars::new()), || dispatch(&cli.command))
    } else {
        dispatch(&cli.command)
    };
    match result {
        Ok(()) => 0,
        Err(e) => {
            eprintln!("error: {e}");
            1
        }
    }
}

fn dispatch(cmd: &Command) -> Result<()> {
    match cmd {
        Command::Modes { case, count, json } => crate::app::commands::modes(case, *count, json.as_deref()),
        Command::Run { case, out, json, no_plots, csv, budget } => {
            crate::app::commands::run(case, out.as_deref(), json.as_deref(), !no_plots, *csv, &budget.budget())
        }
        Command::Paper { out, csv, budget } => crate::app::paper::run(out, *csv, &budget.budget()),
        Command::Check { case, budget } => crate::app::commands::check(case, &budget.budget()),
        Command::Sweep(a) => sweep::sweep(a),
        Command::Merge(a) => sweep::merge(a),
        Command::Optimize(a) => optimize::optimize(a),
        Command::Identify(a) => identify::identify(a),
        Command::Synth(a) => identify::synth(a),
        Command::Completions { shell } => {
            use clap::CommandFactory;
            let mut script = Vec::new();
            clap_complete::generate(*shell, &mut Cli::command(), "beamflow", &mut script);
            write_text_or_stdout(std::path::Path::new("-"), &String::from_utf8_lossy(&script))
        }
    }
}
