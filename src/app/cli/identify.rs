//! `beamflow identify …` and `beamflow synth`: argument parsing over
//! [`crate::app::identify`].

use crate::app::identify::{self as commands, BoucWenRequest, DpRequest, ModalRequest, SynthRequest};
use crate::error::{Error, Result};
use crate::identify::bouc_wen_fit::{CycleOptions, FitOptions, FitTarget};
use crate::identify::dp::DpOptions;
use crate::identify::modal_fit::IdentifiedElement;
use crate::identify::pso::PsoOptions;
use crate::identify::synth::{SynthKind, SynthOptions};
use crate::io::measurement::LoadOptions;
use clap::{Args, Subcommand, ValueEnum};
use std::path::PathBuf;

/// Arguments of `beamflow identify`.
#[derive(Args, Debug)]
pub struct IdentifyArgs {
    #[command(subcommand)]
    pub what: IdentifyCommand,
}

/// Options shared by the identify commands.
#[derive(Args, Debug, Clone)]
pub struct CommonArgs {
    /// Output directory for the case fragment, JSON and figures.
    #[arg(long, default_value = "out/identify")]
    pub out: PathBuf,
    /// Skip the figures.
    #[arg(long)]
    pub no_plots: bool,
    /// Allowed relative jitter of the time steps in the measurement files.
    #[arg(long, default_value_t = 1e-3)]
    pub uniform_tolerance: f64,
    #[command(flatten)]
    pub budget: super::BudgetArgs,
}

impl CommonArgs {
    fn load(&self) -> LoadOptions {
        LoadOptions { uniform_tolerance: self.uniform_tolerance }
    }
}

#[derive(Subcommand, Debug)]
pub enum IdentifyCommand {
    /// d_p from two records whose voltages differ by a constant offset (writes dp.toml).
    ///
    /// Each file: CSV with time, voltage and displacement (or force with --k-p) columns, or a
    /// beamflow results file FILE.h5[:ACTUATOR].
    // Negative numbers reach the checks that name their flag.
    #[command(allow_negative_numbers = true)]
    Dp {
        /// The record at the base voltage: CSV with time, voltage and displacement (or force)
        /// columns, or FILE.h5[:ACTUATOR].
        first: PathBuf,
        /// The record with the voltage offset by a constant, in the same form.
        second: PathBuf,
        /// Stack stiffness (N/m): records with a blocked-force column instead of a stroke.
        #[arg(long)]
        k_p: Option<f64>,
        /// Largest accepted std(V2 - V1) / |ΔV|.
        #[arg(long, default_value_t = 0.1)]
        offset_tolerance: f64,
        /// Pair samples by index instead of searching the best alignment.
        #[arg(long)]
        no_align: bool,
        #[command(flatten)]
        common: CommonArgs,
    },
    /// α, β, γ by particle swarm against a stroke or blocked-force cycle (writes bouc-wen.toml).
    #[command(name = "bouc-wen", allow_negative_numbers = true)]
    BoucWen {
        /// CSV with time, voltage and displacement (or force), or FILE.h5[:ACTUATOR].
        file: PathBuf,
        /// The stack's d_p (m/V), e.g. from `identify dp`.
        #[arg(long)]
        d_p: f64,
        /// What the response column is.
        #[arg(long, value_enum, default_value_t = TargetArg::Stroke)]
        target: TargetArg,
        /// Stack stiffness (N/m), required with --target force.
        #[arg(long)]
        k_p: Option<f64>,
        /// Seeds of the swarm, comma separated; the best fit is kept and the spread reported.
        #[arg(long, value_delimiter = ',', default_value = "1,2,3", value_parser = seed)]
        seeds: Vec<u64>,
        /// Voltage period (s); default: estimated from the voltage.
        #[arg(long)]
        period: Option<f64>,
        /// Whole periods fitted, from the end of the record.
        #[arg(long, default_value_t = 1, value_parser = super::count::<1>)]
        cycles: usize,
        /// Particles of the swarm.
        #[arg(long, default_value_t = 30, value_parser = super::count::<2>)]
        particles: usize,
        /// Iteration limit of the swarm.
        #[arg(long, default_value_t = 400, value_parser = super::count::<1>)]
        max_iterations: usize,
        #[command(flatten)]
        common: CommonArgs,
    },
    /// k, c from an impact test (force, acceleration): H1, modal fit, k = m·ω_n², c = 2ζ·m·ω_n
    /// (writes modal.toml).
    #[command(allow_negative_numbers = true)]
    Modal {
        /// CSV with time, force and acceleration columns.
        file: PathBuf,
        /// The known moving mass (kg), e.g. m_t + m_p/2 for the stack under the top mass.
        #[arg(long)]
        mass: f64,
        /// Modes of the multi-mode (rational-fraction) fit.
        #[arg(long, default_value_t = 1, value_parser = super::count::<1>)]
        modes: usize,
        /// Band F1,F2 (Hz) of the fits; default: the hammer's band for the peak search, and
        /// 0.5–1.5 × the peak frequency for a one-mode rational-fraction fit.
        #[arg(long, value_name = "F1,F2", value_parser = parse_band)]
        band: Option<(f64, f64)>,
        /// Which element the mass sits on: the fields written to the fragment.
        #[arg(long, value_enum, default_value_t = ElementArg::Stack)]
        element: ElementArg,
        /// With --modes > 1: the mode (1 = lowest) that gives k and c.
        #[arg(long, default_value_t = 1, value_parser = super::count::<1>)]
        use_mode: usize,
        /// Samples per hit; default: the shortest spacing between hits.
        #[arg(long, value_parser = super::count::<8>)]
        segment: Option<usize>,
        /// Exponential window on both channels, falling to this value at the segment end.
        #[arg(long)]
        exp_window: Option<f64>,
        /// Force window: keep the force for this many seconds from the segment start.
        #[arg(long)]
        force_window: Option<f64>,
        /// Frequency bins with lower coherence are left out of the fits.
        #[arg(long, default_value_t = 0.8)]
        min_coherence: f64,
        #[command(flatten)]
        common: CommonArgs,
    },
}

#[derive(Clone, Copy, Debug, ValueEnum)]
pub enum TargetArg {
    /// Free stroke (displacement column).
    Stroke,
    /// Blocked force (force column) = k_p·stroke.
    Force,
}

#[derive(Clone, Copy, Debug, ValueEnum)]
pub enum ElementArg {
    /// The stack: k_p, c_p in [actuator.stack].
    Stack,
    /// A frame leg (both legs alike): k_l, c_l.
    Leg,
    /// The right frame leg: k_l_right, c_l_right.
    LegRight,
}

impl From<ElementArg> for IdentifiedElement {
    fn from(e: ElementArg) -> IdentifiedElement {
        match e {
            ElementArg::Stack => IdentifiedElement::Stack,
            ElementArg::Leg => IdentifiedElement::Leg,
            ElementArg::LegRight => IdentifiedElement::LegRight,
        }
    }
}

#[derive(Clone, Copy, Debug, ValueEnum)]
pub enum KindArg {
    /// Free stroke cycle: time, voltage, displacement.
    Stroke,
    /// Blocked force = k_p·stroke: time, voltage, force.
    BlockedForce,
    /// Impact test: time, force, acceleration.
    Impact,
    /// Two stroke records, the second with the voltage offset by a constant: FILE_1, FILE_2.
    DpPair,
}

/// Arguments of `beamflow synth`.
#[derive(Args, Debug)]
#[command(allow_negative_numbers = true)]
pub struct SynthArgs {
    /// The case whose actuator is "measured".
    pub case: PathBuf,
    /// CSV file to write (a d_p pair writes STEM_1.csv and STEM_2.csv).
    #[arg(long)]
    pub out: PathBuf,
    /// What to measure.
    #[arg(long, value_enum, default_value_t = KindArg::Stroke)]
    pub kind: KindArg,
    /// Gaussian noise on each response column, as a fraction of its RMS.
    #[arg(long, default_value_t = 0.01)]
    pub noise: f64,
    /// Gaussian noise on the voltage column, as a fraction of its RMS (default: the clean,
    /// commanded voltage).
    #[arg(long, default_value_t = 0.0)]
    pub voltage_noise: f64,
    /// Seed of the noise.
    #[arg(long, default_value_t = 1, value_parser = seed)]
    pub seed: u64,
    /// Actuator name; default: the case's first actuator.
    #[arg(long)]
    pub actuator: Option<String>,
    /// Stroke records: periods.
    #[arg(long, default_value_t = 3, value_parser = super::count::<1>)]
    pub periods: usize,
    /// Stroke records: samples per period.
    #[arg(long, default_value_t = 200, value_parser = super::count::<8>)]
    pub samples_per_period: usize,
    /// d_p pair: voltage offset ΔV of the second record (V); default a quarter of the
    /// voltage's half range.
    #[arg(long, allow_hyphen_values = true)]
    pub offset: Option<f64>,
    /// Impact test: the element tested.
    #[arg(long, value_enum, default_value_t = ElementArg::Stack)]
    pub element: ElementArg,
    /// Impact test: moving mass (kg); default m_t + m_p/2 (stack), m_b/2 (leg).
    #[arg(long)]
    pub mass: Option<f64>,
    /// Impact test: hammer hits.
    #[arg(long, default_value_t = 8, value_parser = super::count::<1>)]
    pub hits: usize,
    /// Significant digits of the data columns (0: shortest exact form).
    #[arg(long, default_value_t = 7, value_parser = super::count::<0>)]
    pub digits: usize,
    #[command(flatten)]
    pub budget: super::BudgetArgs,
}

/// A noise seed: any whole number from 0 (a negative one is refused with the range).
fn seed(text: &str) -> std::result::Result<u64, String> {
    super::count::<0>(text).map(|s| s as u64)
}

/// `F1,F2` in Hz.
fn parse_band(s: &str) -> std::result::Result<(f64, f64), String> {
    let parts: Vec<&str> = s.split(',').map(str::trim).collect();
    let bad = || format!("expected two frequencies in Hz as F1,F2 (e.g. 30,300), got `{s}`");
    if parts.len() != 2 {
        return Err(bad());
    }
    let lo: f64 = parts[0].parse().map_err(|_| bad())?;
    let hi: f64 = parts[1].parse().map_err(|_| bad())?;
    Ok((lo, hi))
}

fn cli_err(field: &str, reason: impl Into<String>) -> Error {
    Error::input("<cli>", field, reason)
}

pub fn identify(args: &IdentifyArgs) -> Result<()> {
    match &args.what {
        IdentifyCommand::Dp { first, second, k_p, offset_tolerance, no_align, common } => {
            let req = DpRequest {
                first: first.clone(),
                second: second.clone(),
                options: DpOptions {
                    offset_tolerance: *offset_tolerance,
                    align: !no_align,
                    k_p: *k_p,
                    ..DpOptions::default()
                },
                load: common.load(),
                out: Some(common.out.clone()),
                plots: !common.no_plots,
            };
            print!("{}", commands::identify_dp(&req)?.report());
        }
        IdentifyCommand::BoucWen {
            file,
            d_p,
            target,
            k_p,
            seeds,
            period,
            cycles,
            particles,
            max_iterations,
            common,
        } => {
            let target = match (target, k_p) {
                (TargetArg::Stroke, _) => FitTarget::Stroke,
                (TargetArg::Force, Some(k)) => FitTarget::BlockedForce { k_p: *k },
                (TargetArg::Force, None) => {
                    return Err(cli_err("--k-p", "--target force needs the stack stiffness --k-p (N/m)"))
                }
            };
            let req = BoucWenRequest {
                file: file.clone(),
                target,
                cycle: CycleOptions { period: *period, cycles: *cycles },
                fit: FitOptions {
                    pso: PsoOptions { particles: *particles, max_iterations: *max_iterations, ..PsoOptions::default() },
                    budget: common.budget.budget(),
                    ..FitOptions::new(*d_p)
                },
                seeds: seeds.clone(),
                load: common.load(),
                out: Some(common.out.clone()),
                plots: !common.no_plots,
            };
            print!("{}", commands::identify_bouc_wen(&req)?.report());
        }
        IdentifyCommand::Modal {
            file,
            mass,
            modes,
            band,
            element,
            use_mode,
            segment,
            exp_window,
            force_window,
            min_coherence,
            common,
        } => {
            let req = ModalRequest {
                modes: *modes,
                band: *band,
                use_mode: *use_mode,
                segment: *segment,
                exp_window: *exp_window,
                force_window: *force_window,
                min_coherence: *min_coherence,
                load: common.load(),
                out: Some(common.out.clone()),
                plots: !common.no_plots,
                ..ModalRequest::new(file.clone(), *mass, (*element).into())
            };
            print!("{}", commands::identify_modal(&req)?.report());
        }
    }
    Ok(())
}

pub fn synth(args: &SynthArgs) -> Result<()> {
    let kind = match args.kind {
        KindArg::Stroke => SynthKind::Stroke,
        KindArg::BlockedForce => SynthKind::BlockedForce,
        KindArg::Impact => SynthKind::Impact,
        KindArg::DpPair => SynthKind::DpPair,
    };
    let req = SynthRequest {
        case: args.case.clone(),
        out: args.out.clone(),
        options: SynthOptions {
            kind,
            actuator: args.actuator.clone(),
            noise: args.noise,
            voltage_noise: args.voltage_noise,
            seed: args.seed,
            periods: args.periods,
            samples_per_period: args.samples_per_period,
            offset: args.offset,
            element: args.element.into(),
            mass: args.mass,
            hits: args.hits,
            budget: args.budget.budget(),
            ..SynthOptions::default()
        },
        digits: (args.digits > 0).then_some(args.digits),
    };
    print!("{}", commands::synth(&req)?.report());
    Ok(())
}
