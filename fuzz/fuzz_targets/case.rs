//! Case text → parse and validate (as `beamflow check`) → a run on a tiny budget.
//!
//! Parsing, validation, model building and the preflight see the input as it is: they
//! must refuse or accept any text without panicking, hanging or allocating without bound.
//! The run then sees the case with its sizes clamped (a few elements, harmonics, periods
//! and frequencies), so each input takes milliseconds; its results must be finite or
//! refused.
#![no_main]

use beamflow::analysis::budget::Budget;
use beamflow::case::{AnalysisSpec, Case, LoadedCase};
use libfuzzer_sys::fuzz_target;
use std::path::PathBuf;

/// What each input may take: enough for the shipped cases' meshes, far below the machine.
const BUDGET: Budget = Budget { memory: 256 << 20, steps: 200_000 };

/// Largest sizes the run uses.
const ELEMENTS: usize = 8;
const HARMONICS: usize = 8;
const SAMPLES: usize = 64;
const PERIODS: usize = 2;
const FREQUENCIES: usize = 4;
const MODES: usize = 4;

fn clamp(case: &mut Case) {
    case.beam.mesh.elements = case.beam.mesh.elements.min(ELEMENTS);
    if let Some(p) = &mut case.plate {
        // A plate's DOFs grow as the product of its sides' elements.
        p.mesh.elements = p.mesh.elements.map(|e| e.map(|n| n.min(8)));
    }
    for a in &mut case.analysis {
        match a {
            AnalysisSpec::Modes { count } => *count = (*count).min(MODES),
            AnalysisSpec::Harmonic { frequencies, .. } => {
                frequencies.values.truncate(FREQUENCIES);
                frequencies.count = frequencies.count.map(|n| n.min(FREQUENCIES));
            }
            AnalysisSpec::Transient {
                dt,
                steps_per_period,
                periods,
                duration,
                max_periods,
                harmonics,
                segment,
                ..
            } => {
                // The step follows the drive period (steps_per_period), never a given dt
                // that could divide a long period into billions of steps.
                *dt = None;
                *steps_per_period = Some(steps_per_period.unwrap_or(SAMPLES).min(SAMPLES));
                *periods = Some(periods.unwrap_or(PERIODS).min(PERIODS));
                *max_periods = (*max_periods).min(PERIODS);
                *harmonics = Some(harmonics.unwrap_or(HARMONICS).min(HARMONICS));
                *duration = None;
                *segment = None;
            }
            AnalysisSpec::SteadyState { harmonics, samples_per_period, .. } => {
                *harmonics = Some(harmonics.unwrap_or(HARMONICS).min(HARMONICS));
                *samples_per_period = (*samples_per_period).min(SAMPLES);
            }
        }
    }
}

fn dir() -> PathBuf {
    // Relative paths (meshes, series) resolve as for the shipped cases.
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../cases")
}

fuzz_target!(|data: &[u8]| {
    let Ok(text) = std::str::from_utf8(data) else { return };
    let Ok(lc) = LoadedCase::from_str(text, "fuzz.toml", dir()) else { return };
    // As the input is written, held to a small budget: the mesh and every analysis are
    // sized before they are built, so a huge request is refused, not allocated.
    let _ = beamflow::app::runner::planned(&lc, &BUDGET);
    let mut case = lc.case.clone();
    clamp(&mut case);
    let Ok(small) = LoadedCase::from_case(case, "fuzz.toml", dir()) else { return };
    if let Ok(run) = beamflow::app::runner::run_case_within(&small, &BUDGET) {
        if let Some(q) = run.results.iter().find_map(|r| r.non_finite()) {
            panic!("a run reported success with a non-finite result: {q}");
        }
    }
});
