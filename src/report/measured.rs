//! Measurements beside predictions: per measurement and analysis, one figure with a row
//! per quantity — measured and predicted levels at the compared harmonics (the prediction
//! as stems, the measurement as markers: a line spectrum is never joined up) beside the
//! level error per harmonic — and for force and acceleration one period of both, rebuilt
//! from those harmonics.

use super::plot::{save, Dest};
use super::plot::{LinePlot, MultiPanel, Series, SeriesStyle};
use crate::analysis::case_run::Comparison;
use crate::case::measured::MeasuredQuantity;
use crate::error::Result;
use crate::power::spectra::db;
use std::f64::consts::PI;
use std::path::PathBuf;

/// Points per period of the rebuilt time panels.
const SAMPLES: usize = 200;

/// The figures of a run's comparisons, named `<stem>_<analysis>_measured_<name>` where
/// `tags[i]` names analysis `i` (its type, see [`super::figures::analysis_tags`]).
pub fn figures(dir: Dest, stem: &str, tags: &[String], comparisons: &[Comparison]) -> Result<Vec<PathBuf>> {
    let mut out = Vec::new();
    let mut keys: Vec<(usize, &str)> = comparisons.iter().map(|c| (c.analysis, c.name.as_str())).collect();
    keys.dedup();
    for (a, name) in keys {
        let mine: Vec<&Comparison> = comparisons.iter().filter(|c| c.analysis == a && c.name == name).collect();
        let mut panels = Vec::new();
        for c in &mine {
            panels.push(levels(c));
            panels.push(errors(c));
        }
        for c in mine.iter().filter(|c| c.quantity != MeasuredQuantity::Power && !c.harmonic.is_empty()) {
            panels.push(period(c));
        }
        let title = format!("{name} at {}: measured and predicted", mine[0].point);
        let fig = MultiPanel::new(title, panels).with_columns(2);
        out.extend(save(&fig, dir, &format!("{stem}_{}_measured_{name}", tags[a]))?);
    }
    Ok(out)
}

/// The unit as set in figures (a real superscript).
fn unit(c: &Comparison) -> String {
    c.unit().replace("^2", "²")
}

/// Levels at the compared harmonics: dB re 1 unit (force, acceleration) or re 1 pW (|power|).
fn levels(c: &Comparison) -> LinePlot {
    let (ylabel, level): (String, Box<dyn Fn(f64) -> f64>) = match c.quantity {
        MeasuredQuantity::Power => {
            ("|power| level (dB re 1 pW)".into(), Box::new(|p: f64| 10.0 * (p.abs() / 1e-12).log10()))
        }
        _ => (format!("{} level (dB re 1 {})", c.quantity.name(), unit(c)), Box::new(|x: f64| db(x, 1.0))),
    };
    let mut p = LinePlot::new(format!("{}: levels at the harmonics", c.quantity.name()), "frequency (Hz)", ylabel);
    p.stem_base = f64::NEG_INFINITY;
    let amp = |v: &[num_complex::Complex64]| -> Vec<f64> {
        v.iter().map(|x| if c.quantity == MeasuredQuantity::Power { level(x.re) } else { level(x.norm()) }).collect()
    };
    p.series.push(Series::line("predicted", c.frequency.clone(), amp(&c.predicted)).with_style(SeriesStyle::Stems));
    p.series.push(Series::line("measured", c.frequency.clone(), amp(&c.measured)).with_style(SeriesStyle::Markers));
    p
}

/// The level error per compared harmonic (measured over predicted, dB), with the verdict.
fn errors(c: &Comparison) -> LinePlot {
    let verdict = match (c.agrees(), c.tolerance_db) {
        (Some(true), Some(t)) => format!(", within {t} dB"),
        (Some(false), Some(t)) => format!(", NOT within {t} dB"),
        _ => String::new(),
    };
    let mut p = LinePlot::new(
        format!("{}: largest |error| {:.2} dB{verdict}", c.quantity.name(), c.max_abs_error_db()),
        "frequency (Hz)",
        "level error (dB)",
    );
    p.series.push(
        Series::line("measured / predicted", c.frequency.clone(), c.error_db.clone()).with_style(SeriesStyle::Stems),
    );
    let top = c.tolerance_db.unwrap_or(0.0).max(c.max_abs_error_db()).max(0.1) * 1.15;
    p.y_range = Some((-top, top));
    if let Some(t) = c.tolerance_db {
        p.notes.push(format!("tolerance ±{t} dB"));
    }
    p
}

/// One period of the measured and the predicted signal from their compared harmonics.
fn period(c: &Comparison) -> LinePlot {
    let f0 = c.frequency[0] / c.harmonic[0] as f64;
    let t: Vec<f64> = (0..=SAMPLES).map(|j| j as f64 / (SAMPLES as f64 * f0)).collect();
    let rebuild = |v: &[num_complex::Complex64]| -> Vec<f64> {
        t.iter()
            .map(|&t| {
                c.harmonic
                    .iter()
                    .zip(v)
                    .map(|(&k, x)| (x * num_complex::Complex64::from_polar(1.0, 2.0 * PI * k as f64 * f0 * t)).re)
                    .sum()
            })
            .collect()
    };
    let ms: Vec<f64> = t.iter().map(|x| 1e3 * x).collect();
    let mut p = LinePlot::new(
        format!("{}: one period from the compared harmonics", c.quantity.name()),
        "time (ms)",
        format!("{} ({})", c.quantity.name(), unit(c)),
    );
    p.series.push(Series::line("predicted", ms.clone(), rebuild(&c.predicted)));
    p.series.push(Series::line("measured", ms, rebuild(&c.measured)));
    p
}
