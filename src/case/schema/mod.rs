//! The case-file schema. Field names follow the physics spec (k_p, c_p, d_p, m_t, …);
//! units are SI throughout and given on each field.

mod actuator;
mod analysis;
mod beam;
mod imported;
mod output;
mod plate;

pub use actuator::*;
pub use analysis::*;
pub use beam::*;
pub use imported::*;
pub use output::*;
pub use plate::*;

use super::signal;
use crate::error::{Error, Result};
use serde::{Deserialize, Serialize};

/// One simulation case.
#[derive(Clone, Debug, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct Case {
    /// Free text shown in reports.
    #[serde(default)]
    pub title: String,
    /// `beam` (default): actuator feet stand on the beam; `rigid`: on a rigid base.
    #[serde(default)]
    pub base: BaseKind,
    /// The beam (defaults: the paper's clamped–clamped steel beam).
    #[serde(default)]
    pub beam: BeamSpec,
    /// A thin plate in place of the beam (spec §16).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub plate: Option<PlateSpec>,
    /// A model from another FE code in place of the beam (spec §17).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub imported: Option<ImportedSpec>,
    #[serde(default)]
    pub damping: DampingSpec,
    #[serde(default)]
    pub actuator: Vec<ActuatorSpec>,
    #[serde(default)]
    pub sensor: Vec<SensorSpec>,
    /// Prescribed point forces on the beam (transient and steady-state analyses).
    #[serde(default)]
    pub load: Vec<LoadSpec>,
    #[serde(default)]
    pub analysis: Vec<AnalysisSpec>,
    /// Measured data to set beside the predictions (docs/case-format.md, `[[measurement]]`).
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub measurement: Vec<super::measured::MeasurementSpec>,
    #[serde(default)]
    pub output: OutputSpec,
}

#[derive(Clone, Copy, Debug, Default, Deserialize, Serialize, PartialEq, Eq)]
#[serde(rename_all = "snake_case")]
pub enum BaseKind {
    #[default]
    Beam,
    Rigid,
}

fn d_true() -> bool {
    true
}

// ---------------------------------------------------------------------------------------
// Validation

fn positive(file: &str, field: &str, v: f64) -> Result<()> {
    if v > 0.0 && v.is_finite() {
        Ok(())
    } else {
        Err(Error::input(file, field, format!("must be positive and finite, got {v}")))
    }
}

fn non_negative(file: &str, field: &str, v: f64) -> Result<()> {
    if v >= 0.0 && v.is_finite() {
        Ok(())
    } else {
        Err(Error::input(file, field, format!("must be zero or positive and finite, got {v}")))
    }
}

/// What a case's points must lie on: the beam's [0, L], the plate's rectangle, or nothing
/// (a rigid base).
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Extent {
    Rigid,
    Beam {
        length: f64,
    },
    Plate {
        lx: f64,
        ly: f64,
    },
    /// An imported model: points are its nodes, checked when the model is loaded.
    Imported,
}

impl Extent {
    /// Whether a point lies on the structure, or why not.
    pub fn holds(&self, at: &crate::structure::Location) -> std::result::Result<(), String> {
        use crate::structure::Location;
        match (*self, *at) {
            (Extent::Beam { length }, Location::Beam { x }) if x.is_finite() && (0.0..=length).contains(&x) => Ok(()),
            (Extent::Beam { length }, Location::Beam { x }) => {
                Err(format!("x = {x} m is outside the beam [0, {length}] m"))
            }
            (Extent::Plate { lx, ly }, Location::Plate { x, y }) => {
                let inside = |v: f64, l: f64| v.is_finite() && (0.0..=l).contains(&v);
                if inside(x, lx) && inside(y, ly) {
                    Ok(())
                } else {
                    Err(format!("{at} is outside the plate [0, {lx}] × [0, {ly}] m"))
                }
            }
            (Extent::Imported, Location::Near { xyz, .. }) => crate::structure::location::finite_point(&xyz),
            (Extent::Imported, Location::Node { .. }) => Ok(()),
            (Extent::Imported, _) => {
                Err("an imported model takes a point as `node` (its id) or `at = [x, y, z]` (m), \
                 with `component` (e.g. \"uz\")"
                    .into())
            }
            (_, Location::Node { .. }) => Err("`node` and `component` name a point of an imported model".into()),
            (_, Location::Near { .. }) => Err("`at = [x, y, z]` names a point of an imported model".into()),
            (Extent::Rigid, _) => Err("the base is rigid: there is no structure to stand on".into()),
            (Extent::Beam { .. }, _) => Err("a beam takes a position as `x` (m)".into()),
            (Extent::Plate { .. }, _) => Err("a plate takes a position as `at = [x, y]` (m)".into()),
        }
    }
}

/// Checks a point written as `x` (beam), `at` (plate) or `node` or `at = [x, y, z]` with
/// `component` (imported model) on the case's structure; `f` is the point's table, e.g.
/// `sensor[0]`.
fn on_structure(file: &str, f: &str, p: &analysis::PointSpec, extent: Extent) -> Result<()> {
    let given = [p.x.is_some(), p.at.is_some(), p.node.is_some()].iter().filter(|&&g| g).count();
    if given > 1 {
        return Err(Error::input(
            file,
            f,
            "give one of `x` (beam), `at` (plate, or a position on an imported model) or `node` (imported model), \
             not several",
        ));
    }
    let imported = extent == Extent::Imported;
    if p.component.is_some() && !imported {
        return Err(Error::input(
            file,
            format!("{f}.component"),
            "a component goes with `node` or `at = [x, y, z]` (an imported model)",
        ));
    }
    imported_tolerance(file, f, p.tolerance, imported && p.at.is_some(), "`at = [x, y, z]`")?;
    // The field the structure takes its points in, and whether it is given.
    let (field, given) = match extent {
        Extent::Plate { .. } => (format!("{f}.at"), p.at.is_some()),
        Extent::Imported => (format!("{f}.node"), p.node.is_some() || p.at.is_some()),
        Extent::Beam { .. } | Extent::Rigid => (format!("{f}.x"), p.x.is_some()),
    };
    if !given {
        let how = match extent {
            Extent::Plate { .. } => "a plate takes its points as `at = [x, y]` (m)",
            Extent::Imported => {
                "an imported model takes its points as `node` (with `component`) or `at = [x, y, z]` (m)"
            }
            Extent::Beam { .. } | Extent::Rigid => "a beam takes its points as `x` (m)",
        };
        let wrong = [(p.x.is_some(), "x"), (p.at.is_some(), "at"), (p.node.is_some(), "node")];
        let reason = match wrong.iter().find(|(g, _)| *g) {
            Some((_, name)) => format!("{how}, not `{name}`"),
            None => format!("required: the point's position on the structure ({how})"),
        };
        return Err(Error::input(file, field, reason));
    }
    if let Some(at) = &p.at {
        analysis::at_length(at, extent).map_err(|why| Error::input(file, format!("{f}.at"), why))?;
    }
    let at = p.location().map_err(|why| Error::input(file, format!("{f}.component"), why))?;
    extent.holds(&at).map_err(|why| Error::input(file, field, why))
}

/// Checks a point's `tolerance` (m): zero or positive, and only where a point is found by
/// position on an imported model (`by_position`, written as `what`).
fn imported_tolerance(file: &str, f: &str, tolerance: Option<f64>, by_position: bool, what: &str) -> Result<()> {
    let Some(t) = tolerance else { return Ok(()) };
    if !by_position {
        return Err(Error::input(
            file,
            format!("{f}.tolerance"),
            format!("a tolerance goes with {what} on an imported model: how far its nearest node may lie"),
        ));
    }
    non_negative(file, &format!("{f}.tolerance"), t)
}

fn on_beam(file: &str, field: &str, x: f64, length: f64) -> Result<()> {
    if x.is_finite() && (0.0..=length).contains(&x) {
        Ok(())
    } else {
        Err(Error::input(file, field, format!("x = {x} m is outside the beam [0, {length}] m")))
    }
}

/// Longest actuator or sensor name: names become parts of file and HDF5 group names.
pub const NAME_MAX: usize = 64;

/// Checks a name that reaches file and group names: 1 to [`NAME_MAX`] characters from
/// letters, digits, `_` and `-`, so it can neither leave the output folder (`/`, `..`) nor
/// hide a file (a leading `.`) nor break a path (NUL, control characters).
fn valid_name(file: &str, field: &str, name: &str) -> Result<()> {
    let ok = !name.is_empty()
        && name.chars().count() <= NAME_MAX
        && name.chars().all(|c| c.is_ascii_alphanumeric() || c == '_' || c == '-');
    if ok {
        Ok(())
    } else {
        Err(Error::input(
            file,
            field,
            format!("{name:?} is not a valid name: use 1 to {NAME_MAX} letters, digits, `_` or `-`"),
        ))
    }
}

/// Endings a name may not have: results name an actuator's interface points
/// `<actuator>_stack`, `<actuator>_left_leg`, `<actuator>_right_leg` beside the loads, and
/// its figures `<actuator>_power_spectrum` beside an actuator's `_spectrum` figure.
const RESERVED_ENDINGS: [&str; 4] = ["_stack", "_left_leg", "_right_leg", "_power"];

/// Checks that `name` is not a name results give to something else: one of
/// [`RESERVED_ENDINGS`], or `force_<n>` (a harmonic analysis's force points).
fn not_reserved(file: &str, field: &str, name: &str) -> Result<()> {
    let lower = name.to_ascii_lowercase();
    let forced = lower.strip_prefix("force_").is_some_and(|n| !n.is_empty() && n.bytes().all(|b| b.is_ascii_digit()));
    match RESERVED_ENDINGS.iter().find(|e| lower.ends_with(*e)) {
        Some(e) => Err(Error::input(
            file,
            field,
            format!(
                "{name:?} ends in `{e}`, which results use for an actuator's points and figures; choose another name"
            ),
        )),
        None if forced => Err(Error::input(
            file,
            field,
            format!("{name:?} is reserved: harmonic analyses name their force points force_<n>; choose another name"),
        )),
        None => Ok(()),
    }
}

impl Case {
    /// Names of actuators (as given), loads and sensors: valid, not reserved, and unique
    /// across all three ignoring case, so no two result groups or figure files share a
    /// name (not even on a file system that ignores case).
    fn validate_names(&self, file: &str) -> Result<()> {
        let count = self.actuator.len();
        let actuators = self
            .actuator
            .iter()
            .enumerate()
            .map(|(i, a)| (format!("actuator[{i}].name"), a.name.is_some(), a.effective_name(i, count)));
        let loads = self.load.iter().enumerate().map(|(i, l)| (format!("load[{i}].name"), true, l.effective_name(i)));
        let sensors = self.sensor.iter().enumerate().map(|(i, s)| (format!("sensor[{i}].name"), true, s.name.clone()));
        let mut seen = std::collections::HashMap::new();
        for (field, given, name) in actuators.chain(loads).chain(sensors) {
            if given {
                valid_name(file, &field, &name)?;
                not_reserved(file, &field, &name)?;
            }
            if let Some(first) = seen.insert(name.to_ascii_lowercase(), field.clone()) {
                return Err(Error::input(
                    file,
                    field,
                    format!(
                        "{name:?} is already the name of {first} (names are unique across actuators, loads and \
                         sensors, ignoring case)"
                    ),
                ));
            }
        }
        Ok(())
    }

    /// Measurement names (as given, or their point's) name figure files and result groups,
    /// so they follow the same rule, checked here rather than when a figure is written.
    fn validate_measurement_names(&self, file: &str) -> Result<()> {
        for (i, m) in self.measurement.iter().enumerate() {
            match &m.name {
                Some(name) => valid_name(file, &format!("measurement[{i}].name"), name)?,
                None => valid_name(file, &format!("measurement[{i}].point"), &m.point)?,
            }
        }
        Ok(())
    }

    /// An imported model stands alone (no `[beam]` or `[plate]`, a structure to stand on),
    /// and its damping matrix is used exactly when `damping.kind = "given"`.
    fn validate_imported(&self, file: &str) -> Result<()> {
        let given = self.damping.kind == DampingKind::Given;
        let Some(m) = &self.imported else {
            if given {
                return Err(Error::input(
                    file,
                    "damping.kind",
                    "\"given\" uses an imported model's damping matrix; this case has none",
                ));
            }
            return Ok(());
        };
        if self.plate.is_some() || self.beam != BeamSpec::default() {
            return Err(Error::input(
                file,
                "imported",
                "a case describes one structure: give `[imported]` alone, without `[beam]` or `[plate]`",
            ));
        }
        if self.base == BaseKind::Rigid {
            return Err(Error::input(file, "base", "base = \"rigid\" has no structure: drop `[imported]` or the base"));
        }
        match (&m.damping, given) {
            (Some(_), false) => Err(Error::input(
                file,
                "damping.kind",
                "the imported model gives a damping matrix (`imported.damping`): set damping.kind = \"given\" to use it, or drop the file",
            )),
            (None, true) => Err(Error::input(file, "damping.kind", "\"given\" needs `imported.damping`, the damping matrix file")),
            _ => m.validate(file),
        }
    }

    /// What the case's points lie on.
    pub fn extent(&self) -> Extent {
        match (&self.plate, self.base) {
            (_, BaseKind::Rigid) => Extent::Rigid,
            (Some(p), _) => p.extent(),
            (None, _) if self.imported.is_some() => Extent::Imported,
            (None, BaseKind::Beam) => Extent::Beam { length: self.beam.length },
        }
    }

    /// Checks every field on its own terms (the admissible ranges are checked after, by
    /// [`Case::validate`]); the first problem is returned, naming file and field.
    pub(super) fn validate_fields(&self, file: &str) -> Result<()> {
        let b = &self.beam;
        b.validate(file)?;
        self.validate_imported(file)?;
        if let Some(p) = &self.plate {
            if *b != BeamSpec::default() {
                return Err(Error::input(
                    file,
                    "plate",
                    "a case describes one structure: give `[beam]` or `[plate]`, not both",
                ));
            }
            if self.base == BaseKind::Rigid {
                return Err(Error::input(
                    file,
                    "base",
                    "base = \"rigid\" has no structure: drop `[plate]` or the base",
                ));
            }
            p.validate(file)?;
        }
        let extent = self.extent();
        self.damping.validate(file)?;
        for (i, a) in self.actuator.iter().enumerate() {
            a.validate(file, &format!("actuator[{i}]"), extent)?;
        }
        for (i, s) in self.sensor.iter().enumerate() {
            on_structure(file, &format!("sensor[{i}]"), &s.point(), extent)?;
        }
        for (i, l) in self.load.iter().enumerate() {
            if self.base == BaseKind::Rigid {
                return Err(Error::input(
                    file,
                    format!("load[{i}]"),
                    "a point load acts on the beam, and base = \"rigid\" has none",
                ));
            }
            on_structure(file, &format!("load[{i}]"), &l.point(), extent)?;
            l.force.validate(file, &format!("load[{i}].force"))?;
        }
        self.validate_names(file)?;
        self.validate_measurement_names(file)?;
        self.output.validate(file)?;
        for (i, an) in self.analysis.iter().enumerate() {
            an.validate(file, &format!("analysis[{i}]"), self)?;
        }
        Ok(())
    }
}
