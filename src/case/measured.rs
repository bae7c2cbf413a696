//! Measured data a case names (`[[measurement]]`), to be set beside its predictions: the
//! files are read and checked here, before any solve, with the reader identification uses
//! ([`crate::io::measurement`]); the comparison is [`crate::analysis::measured`].

use super::LoadedCase;
use crate::error::{Error, Result};
use crate::io::measurement::{self, LoadOptions, Measurement, Quantity};
use serde::{Deserialize, Serialize};
use std::path::Path;

/// What a measurement holds at its point.
#[derive(Clone, Copy, Debug, Deserialize, Serialize, PartialEq, Eq, PartialOrd, Ord)]
#[serde(rename_all = "snake_case")]
pub enum MeasuredQuantity {
    /// The force between actuator and beam at a link's foot (N), the model's interface
    /// force: what a force transducer under the foot reads.
    Force,
    /// The beam's acceleration at a link's foot or at a sensor (m/s²).
    Acceleration,
    /// The power into the beam per harmonic (W), from the file's force and acceleration
    /// columns, P_k = −½·Im(F_k·conj(A_k))/ω_k, as the paper measured it.
    Power,
}

impl MeasuredQuantity {
    /// The name in results and messages.
    pub fn name(self) -> &'static str {
        match self {
            MeasuredQuantity::Force => "force",
            MeasuredQuantity::Acceleration => "acceleration",
            MeasuredQuantity::Power => "power",
        }
    }

    /// The file columns it is made from.
    fn columns(self) -> &'static [Quantity] {
        match self {
            MeasuredQuantity::Force => &[Quantity::Force],
            MeasuredQuantity::Acceleration => &[Quantity::Acceleration],
            MeasuredQuantity::Power => &[Quantity::Force, Quantity::Acceleration],
        }
    }
}

/// One `[[measurement]]` entry.
#[derive(Clone, Debug, Deserialize, Serialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct MeasurementSpec {
    /// Name in the results (default: the point's).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub name: Option<String>,
    /// A CSV file (relative to the case file; columns as identification reads them:
    /// `time`, `force`, `acceleration` with optional units), or a beamflow results file
    /// `FILE.h5[:GROUP]`, whose records at the point are read.
    pub file: String,
    /// Where it was measured: a link `<actuator>_<link>` (e.g. `inertial_stack`,
    /// `frame_left_leg`) or a sensor's name.
    pub point: String,
    /// What to compare (default: every quantity the file's columns give at this point).
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub quantities: Vec<MeasuredQuantity>,
    /// The largest |error| (dB) at the compared harmonics for measurement and prediction
    /// to agree; without it the errors are reported without a verdict.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub tolerance_db: Option<f64>,
}

/// A measurement read and checked.
#[derive(Clone, Debug)]
pub struct Measured {
    /// The case table it came from, `measurement[i]`, for messages.
    pub field: String,
    pub name: String,
    pub point: String,
    pub quantities: Vec<MeasuredQuantity>,
    pub tolerance_db: Option<f64>,
    pub data: Measurement,
}

/// Reads every measurement of a case, checking what can be checked without the model:
/// the file exists and reads (columns, units, uniform sampling), it has the columns of
/// each quantity asked for, names are unique and tolerances positive.
pub fn load_measurements(lc: &LoadedCase) -> Result<Vec<Measured>> {
    let mut out: Vec<Measured> = Vec::new();
    for (i, spec) in lc.case.measurement.iter().enumerate() {
        let field = |f: &str| format!("measurement[{i}].{f}");
        let name = spec.name.clone().unwrap_or_else(|| spec.point.clone());
        if out.iter().any(|m| m.name == name) {
            return Err(Error::input(
                &lc.file,
                field("name"),
                format!("`{name}` names two measurements; give each a distinct `name`"),
            ));
        }
        if let Some(t) = spec.tolerance_db.filter(|t| !(t.is_finite() && *t > 0.0)) {
            return Err(Error::input(&lc.file, field("tolerance_db"), format!("must be positive, got {t}")));
        }
        let data = read(lc, &spec.file, &spec.point).map_err(|e| match e {
            Error::Io { .. } => Error::input(&lc.file, field("file"), e.to_string()),
            e => e,
        })?;
        let have = |q: MeasuredQuantity| q.columns().iter().all(|c| data.column(*c).is_ok());
        let quantities = if spec.quantities.is_empty() {
            let q: Vec<MeasuredQuantity> =
                [MeasuredQuantity::Force, MeasuredQuantity::Acceleration, MeasuredQuantity::Power]
                    .into_iter()
                    .filter(|&q| have(q))
                    .collect();
            if q.is_empty() {
                return Err(Error::input(
                    &data.file,
                    "force, acceleration",
                    "the file has neither a force nor an acceleration column: nothing to compare",
                ));
            }
            q
        } else {
            for q in &spec.quantities {
                for c in q.columns() {
                    data.column(*c).map_err(|e| match e {
                        Error::Input { file, field, reason } => {
                            Error::Input { file, field, reason: format!("{reason}; `{}` needs it", q.name()) }
                        }
                        e => e,
                    })?;
                }
            }
            spec.quantities.clone()
        };
        out.push(Measured {
            field: format!("measurement[{i}]"),
            name,
            point: spec.point.clone(),
            quantities,
            tolerance_db: spec.tolerance_db,
            data,
        });
    }
    Ok(out)
}

/// A measurement file, CSV or a beamflow results file (`FILE.h5[:GROUP]`), relative to the
/// case's folder.
fn read(lc: &LoadedCase, file: &str, point: &str) -> Result<Measurement> {
    let opts = LoadOptions::default();
    match measurement::split_hdf5_source(file) {
        Some((path, group)) => measurement::load_point_hdf5(&lc.dir.join(Path::new(path)), group, point, &opts),
        None => measurement::load(&lc.dir.join(file), &[], &opts),
    }
}
