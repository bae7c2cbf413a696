//! Sensors, loads and the analyses a case file asks for.

use super::d_true;
use super::signal::SignalSpec;
use super::{positive, BaseKind, Case};
use crate::error::{Error, Result};
use crate::signal::sampling::require_samples;
use crate::structure::Location;
use serde::{Deserialize, Serialize};

/// What a harmonic analysis solves: the bare beam, or the beam with its actuators attached
/// (stacks as spring and damper; their feet and stack forces become inputs).
#[derive(Clone, Copy, Debug, Default, Deserialize, Serialize, PartialEq, Eq)]
#[serde(rename_all = "snake_case")]
pub enum HarmonicSystem {
    #[default]
    Bare,
    Coupled,
}

impl HarmonicSystem {
    fn is_bare(&self) -> bool {
        *self == HarmonicSystem::Bare
    }
}

#[derive(Clone, Debug, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct SensorSpec {
    pub name: String,
    /// Position on a beam (m).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub x: Option<f64>,
    /// Position (x, y) on a plate, or (x, y, z) of a node of an imported model (m).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub at: Option<Vec<f64>>,
    /// A node of an imported model (its id in the DOF map) and the `component` there
    /// (`uz`, `-uz`, …).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub node: Option<i64>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub component: Option<String>,
    /// How far (m) `at = [x, y, z]` may lie from its node (default: 1 % of the node spacing).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub tolerance: Option<f64>,
}

/// A prescribed point force on the beam: F(t) (N, upward) at x (m), any signal the
/// actuators' voltages can follow (values in N instead of V).
#[derive(Clone, Debug, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct LoadSpec {
    /// Name in results (default `load<i>`, 1-based).
    #[serde(default)]
    pub name: Option<String>,
    /// Position on a beam (m).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub x: Option<f64>,
    /// Position (x, y) on a plate, or (x, y, z) of a node of an imported model (m).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub at: Option<Vec<f64>>,
    /// A node of an imported model (its id in the DOF map) and the `component` there
    /// (`uz`, `-uz`, …).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub node: Option<i64>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub component: Option<String>,
    /// How far (m) `at = [x, y, z]` may lie from its node (default: 1 % of the node spacing).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub tolerance: Option<f64>,
    /// The force's time history (N).
    pub force: SignalSpec,
}

impl LoadSpec {
    /// The name results use: as given, or `load<i+1>`.
    pub fn effective_name(&self, i: usize) -> String {
        self.name.clone().unwrap_or_else(|| format!("load{}", i + 1))
    }
}

/// A point force for harmonic analysis: amplitude (N) and phase (rad) at x (m).
#[derive(Clone, Debug, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct ForceSpec {
    /// Position on a beam (m).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub x: Option<f64>,
    /// Position (x, y) on a plate, or (x, y, z) of a node of an imported model (m).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub at: Option<Vec<f64>>,
    /// A node of an imported model (its id in the DOF map) and the `component` there
    /// (`uz`, `-uz`, …).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub node: Option<i64>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub component: Option<String>,
    /// How far (m) `at = [x, y, z]` may lie from its node (default: 1 % of the node spacing).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub tolerance: Option<f64>,
    #[serde(default = "d_one")]
    pub amplitude: f64,
    #[serde(default)]
    pub phase: f64,
}

/// The point of a spec that writes one with the fields `x`, `at`, `node` and `component`
/// (`serde(flatten)` cannot share them: it refuses `deny_unknown_fields`).
macro_rules! written_point {
    ($($spec:ty),*) => {$(
        impl $spec {
            /// Where the point is (a node without a valid component, which validation
            /// refuses, reads as NaN).
            pub fn location(&self) -> Location {
                self.point().location().unwrap_or(Location::Beam { x: f64::NAN })
            }

            pub fn point(&self) -> PointSpec {
                PointSpec {
                    x: self.x,
                    at: self.at.clone(),
                    node: self.node,
                    component: self.component.clone(),
                    tolerance: self.tolerance,
                }
            }
        }
    )*};
}

written_point!(SensorSpec, LoadSpec, ForceSpec);

/// A point as written: `x` on a beam, `at = [x, y]` on a plate, or on an imported model
/// `node` or `at = [x, y, z]` (its nearest node within `tolerance`) with `component`.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct PointSpec {
    pub x: Option<f64>,
    pub at: Option<Vec<f64>>,
    pub node: Option<i64>,
    pub component: Option<String>,
    pub tolerance: Option<f64>,
}

impl PointSpec {
    /// The point (validation makes sure the case gives the one its structure takes; an unset
    /// coordinate reads as NaN, which the validation refuses first). Errors with the reason
    /// if a node's component is missing or not one.
    pub fn location(&self) -> std::result::Result<Location, String> {
        let needs = |what: String| Err(format!("{what} needs a `component` (e.g. \"uz\")"));
        match (self.node, self.at.as_deref(), &self.component) {
            (Some(n), _, Some(c)) => Location::node(n, c),
            (Some(n), _, None) => needs(format!("node {n}")),
            (None, Some(&[x, y, z]), Some(c)) => Location::near([x, y, z], c, self.tolerance),
            (None, Some(&[x, y, z]), None) => needs(format!("the position [{x}, {y}, {z}]")),
            (None, at, _) => Ok(location(self.x, at)),
        }
    }
}

/// A point written as `x` on a beam or `at = [x, y]` on a plate (see [`PointSpec`]); an
/// `at` of another length reads as NaN, which validation refuses first ([`at_length`]).
pub fn location(x: Option<f64>, at: Option<&[f64]>) -> Location {
    match (x, at) {
        (_, Some(&[x, y])) => Location::Plate { x, y },
        (_, Some(_)) => Location::Plate { x: f64::NAN, y: f64::NAN },
        (x, None) => Location::Beam { x: x.unwrap_or(f64::NAN) },
    }
}

/// Checks that a point's `at` has the numbers its structure takes: [x, y] on a plate,
/// [x, y, z] on an imported model; the reason if not.
pub fn at_length(at: &[f64], extent: super::Extent) -> std::result::Result<(), String> {
    let (want, form) = match extent {
        super::Extent::Imported => (3, "[x, y, z] (m), the position of a node of the imported model"),
        _ => (2, "[x, y] (m), the position on the plate"),
    };
    if at.len() != want {
        return Err(format!("{} numbers: give {form}", at.len()));
    }
    match at.iter().find(|v| !v.is_finite()) {
        Some(v) => Err(format!("{v} is not a finite number: give {form}")),
        None => Ok(()),
    }
}

fn d_one() -> f64 {
    1.0
}

/// A list of frequencies (Hz): explicit values, a range, or both.
#[derive(Clone, Debug, Default, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct FrequencySpec {
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub values: Vec<f64>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub start: Option<f64>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub stop: Option<f64>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub count: Option<usize>,
    /// `linear` (default) or `log`.
    #[serde(default)]
    pub spacing: Spacing,
}

#[derive(Clone, Copy, Debug, Default, Deserialize, Serialize, PartialEq, Eq)]
#[serde(rename_all = "snake_case")]
pub enum Spacing {
    #[default]
    Linear,
    Log,
}

impl FrequencySpec {
    /// The frequencies (Hz) in the order given (values, then the range).
    pub fn list(&self) -> Vec<f64> {
        let mut f = self.values.clone();
        if let (Some(a), Some(b), Some(n)) = (self.start, self.stop, self.count) {
            for i in 0..n {
                let s = if n == 1 { 0.0 } else { i as f64 / (n - 1) as f64 };
                f.push(match self.spacing {
                    Spacing::Linear => a + (b - a) * s,
                    Spacing::Log => a * (b / a).powf(s),
                });
            }
        }
        f
    }

    fn validate(&self, file: &str, field: &str) -> Result<()> {
        for (i, &v) in self.values.iter().enumerate() {
            if !(v > 0.0 && v.is_finite()) {
                return Err(Error::input(
                    file,
                    format!("{field}.values[{i}]"),
                    format!("frequencies must be positive and finite, got {v} Hz"),
                ));
            }
        }
        let range = [self.start.is_some(), self.stop.is_some(), self.count.is_some()];
        if range.iter().any(|&b| b) && !range.iter().all(|&b| b) {
            return Err(Error::input(file, field, "a range needs all of `start`, `stop` and `count`"));
        }
        if let (Some(a), Some(b), Some(n)) = (self.start, self.stop, self.count) {
            for (name, v) in [("start", a), ("stop", b)] {
                if !(v > 0.0 && v.is_finite()) {
                    return Err(Error::input(
                        file,
                        format!("{field}.{name}"),
                        format!("frequencies must be positive and finite, got {v} Hz"),
                    ));
                }
            }
            if n == 0 {
                return Err(Error::input(file, format!("{field}.count"), "must be at least 1"));
            }
        }
        if self.values.is_empty() && self.count.is_none() {
            return Err(Error::input(file, field, "no frequencies given: set `values` or `start`, `stop`, `count`"));
        }
        Ok(())
    }
}

/// Time-integration scheme.
#[derive(Clone, Copy, Debug, Default, Deserialize, Serialize, PartialEq, Eq)]
#[serde(rename_all = "snake_case")]
pub enum SchemeKind {
    /// Newmark γ = 1/2, β = 1/4 (default).
    #[default]
    AverageAcceleration,
    /// Newmark γ = 1/2, β = 1/6 (conditionally stable).
    LinearAcceleration,
    /// HHT-α with `alpha` ∈ [0, 1/3].
    Hht,
    /// Generalised-α (Chung–Hulbert) with spectral radius `rho_inf` ∈ [0, 1].
    GeneralizedAlpha,
}

/// An analysis to run.
#[derive(Clone, Debug, Deserialize, Serialize)]
#[serde(tag = "type", rename_all = "snake_case", deny_unknown_fields)]
pub enum AnalysisSpec {
    /// Natural modes of the bare beam.
    Modes {
        #[serde(default = "d_mode_count")]
        count: usize,
    },
    /// Harmonic response of the beam to point forces.
    Harmonic {
        frequencies: FrequencySpec,
        #[serde(default)]
        force: Vec<ForceSpec>,
        /// The bare beam, or the beam coupled with its (passive) actuators.
        #[serde(default, skip_serializing_if = "HarmonicSystem::is_bare")]
        system: HarmonicSystem,
    },
    /// Time integration of the coupled system.
    Transient {
        /// Time step (s); default: the drive period / 200, and at most 1/20 of the period of
        /// the highest harmonic analysed.
        #[serde(default, skip_serializing_if = "Option::is_none")]
        dt: Option<f64>,
        /// Steps per drive period instead of `dt` (Δt = period / steps_per_period exactly).
        #[serde(default, skip_serializing_if = "Option::is_none")]
        steps_per_period: Option<usize>,
        /// Run length in drive periods, or to steady state if `steady_state`.
        #[serde(default, skip_serializing_if = "Option::is_none")]
        periods: Option<usize>,
        /// Run length (s), for non-periodic inputs.
        #[serde(default, skip_serializing_if = "Option::is_none")]
        duration: Option<f64>,
        #[serde(default)]
        scheme: SchemeKind,
        /// HHT α.
        #[serde(default, skip_serializing_if = "Option::is_none")]
        alpha: Option<f64>,
        /// Generalised-α ρ∞.
        #[serde(default, skip_serializing_if = "Option::is_none")]
        rho_inf: Option<f64>,
        /// Run whole periods until the mean powers settle (default true for periodic drives).
        #[serde(default = "d_true")]
        steady_state: bool,
        /// Relative per-period change of the mean powers that counts as settled.
        #[serde(default = "d_tol")]
        tolerance: f64,
        #[serde(default = "d_max_periods")]
        max_periods: usize,
        /// Highest harmonic of the drive frequency analysed (spectra, Δt limit); default:
        /// as many as the time step resolves at 20 steps per harmonic period.
        #[serde(default, skip_serializing_if = "Option::is_none")]
        harmonics: Option<usize>,
        /// A non-periodic record's Welch segment for PSDs and FRFs (s); default: the whole
        /// record as one segment.
        #[serde(default, skip_serializing_if = "Option::is_none")]
        segment: Option<f64>,
        /// Run on a modal-reduced model (see [`ReductionSpec`]); default: the full model.
        #[serde(default, skip_serializing_if = "Option::is_none")]
        reduction: Option<ReductionSpec>,
    },
    /// Periodic steady state solved in the frequency domain.
    SteadyState {
        /// Harmonics kept; default: the fewest whose neglected rest changes no point power
        /// by more than `harmonic_tolerance` (on a modal-reduced model 9, which set its
        /// cut-off, raised on that reduction where 9 leave out more than the tolerance).
        #[serde(default, skip_serializing_if = "Option::is_none")]
        harmonics: Option<usize>,
        /// Relative truncation tolerance of the automatic harmonic count.
        #[serde(default = "d_harmonic_tolerance")]
        harmonic_tolerance: f64,
        #[serde(default = "d_samples")]
        samples_per_period: usize,
        /// Run on a modal-reduced model (see [`ReductionSpec`]); default: the full model.
        #[serde(default, skip_serializing_if = "Option::is_none")]
        reduction: Option<ReductionSpec>,
    },
}

/// Modal reduction of a transient or steady-state analysis: the bare beam's modes up to a
/// cut-off, a static (residual-flexibility) correction at the actuator feet, and the
/// actuator bodies kept physical.
///
/// ```toml
/// reduction = "auto"                        # modes up to 5× the highest analysed harmonic
/// reduction = { modes_up_to_hz = 2500.0 }   # an explicit cut-off (Hz)
/// reduction = { factor = 8.0, static_correction = false, error_estimate = false }
/// ```
///
/// `factor` (default 5) sets the cut-off as a multiple of the highest analysed harmonic
/// frequency (harmonics × f₀); `modes_up_to_hz` replaces it. `static_correction` (default
/// true) adds the residual-flexibility vectors; `error_estimate` (default true) compares
/// the frequency-domain steady state of the reduced and the full model and stores the
/// difference of the point powers with the result.
#[derive(Clone, Debug, PartialEq, Deserialize, Serialize)]
#[serde(try_from = "RawReduction", into = "RawReduction")]
pub struct ReductionSpec {
    /// Cut-off (Hz).
    pub modes_up_to_hz: Option<f64>,
    /// Cut-off as a multiple of the highest analysed harmonic frequency (–).
    pub factor: Option<f64>,
    pub static_correction: bool,
    pub error_estimate: bool,
}

impl Default for ReductionSpec {
    /// `"auto"`.
    fn default() -> Self {
        ReductionSpec { modes_up_to_hz: None, factor: None, static_correction: true, error_estimate: true }
    }
}

impl ReductionSpec {
    fn validate(&self, file: &str, f: &str, base: BaseKind) -> Result<()> {
        if base == BaseKind::Rigid {
            return Err(Error::input(file, f, "a modal reduction needs a beam, but base = \"rigid\""));
        }
        if self.modes_up_to_hz.is_some() && self.factor.is_some() {
            return Err(Error::input(file, f, "give either `modes_up_to_hz` or `factor`, not both"));
        }
        if let Some(hz) = self.modes_up_to_hz {
            positive(file, &format!("{f}.modes_up_to_hz"), hz)?;
        }
        if let Some(k) = self.factor {
            positive(file, &format!("{f}.factor"), k)?;
        }
        Ok(())
    }
}

/// The table form of [`ReductionSpec`].
#[derive(Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
struct ReductionTable {
    #[serde(default, skip_serializing_if = "Option::is_none")]
    modes_up_to_hz: Option<f64>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    factor: Option<f64>,
    #[serde(default = "d_true")]
    static_correction: bool,
    #[serde(default = "d_true")]
    error_estimate: bool,
}

/// What a case file may hold: a keyword or a table (parsed in `try_from` so that a bad
/// table gets its own message, not serde's "did not match any variant").
#[derive(Deserialize, Serialize)]
#[serde(untagged)]
enum RawReduction {
    Keyword(String),
    Table(toml::Table),
}

impl TryFrom<RawReduction> for ReductionSpec {
    type Error = String;
    fn try_from(raw: RawReduction) -> std::result::Result<Self, String> {
        match raw {
            RawReduction::Keyword(k) if k == "auto" => Ok(ReductionSpec::default()),
            RawReduction::Keyword(k) => Err(format!(
                "`reduction`: unknown keyword \"{k}\"; expected \"auto\" or a table such as \
                 {{ modes_up_to_hz = 2500.0 }}"
            )),
            RawReduction::Table(t) => {
                let t: ReductionTable =
                    toml::Value::Table(t).try_into().map_err(|e: toml::de::Error| format!("`reduction`: {e}"))?;
                Ok(ReductionSpec {
                    modes_up_to_hz: t.modes_up_to_hz,
                    factor: t.factor,
                    static_correction: t.static_correction,
                    error_estimate: t.error_estimate,
                })
            }
        }
    }
}

impl From<ReductionSpec> for RawReduction {
    fn from(s: ReductionSpec) -> Self {
        if s == ReductionSpec::default() {
            return RawReduction::Keyword("auto".into());
        }
        let t = ReductionTable {
            modes_up_to_hz: s.modes_up_to_hz,
            factor: s.factor,
            static_correction: s.static_correction,
            error_estimate: s.error_estimate,
        };
        match toml::Value::try_from(t) {
            Ok(toml::Value::Table(t)) => RawReduction::Table(t),
            _ => unreachable!("a struct serialises to a table"),
        }
    }
}

fn d_mode_count() -> usize {
    10
}
fn d_tol() -> f64 {
    1e-4
}
fn d_max_periods() -> usize {
    400
}
fn d_harmonic_tolerance() -> f64 {
    1e-6
}
/// Samples per period of a steady state that does not name them.
pub const DEFAULT_SAMPLES_PER_PERIOD: usize = 1024;

/// Harmonics of a periodic analysis that must fix its count and was given none (a sweep's
/// headline, a modal-reduced steady state, whose cut-off follows the count).
pub const DEFAULT_HARMONICS: usize = 9;

fn d_samples() -> usize {
    DEFAULT_SAMPLES_PER_PERIOD
}

impl SchemeKind {
    /// The name a case file writes.
    fn name(self) -> &'static str {
        match self {
            SchemeKind::AverageAcceleration => "average_acceleration",
            SchemeKind::LinearAcceleration => "linear_acceleration",
            SchemeKind::Hht => "hht",
            SchemeKind::GeneralizedAlpha => "generalized_alpha",
        }
    }
}

/// Refuses a scheme parameter (`param`, given or not) that only `owner` reads: with any
/// other scheme it would be silently ignored.
fn refuse_unused(file: &str, f: &str, param: &str, given: bool, scheme: SchemeKind, owner: SchemeKind) -> Result<()> {
    if !given || scheme == owner {
        return Ok(());
    }
    Err(Error::input(
        file,
        format!("{f}.{param}"),
        format!(
            "`{param}` is a parameter of scheme = \"{}\", and scheme = \"{}\" ignores it: set scheme = \"{}\" \
             or remove `{param}`",
            owner.name(),
            scheme.name(),
            owner.name()
        ),
    ))
}

impl AnalysisSpec {
    /// Checks the analysis `f` (its table path, e.g. `analysis[0]`) of `case`.
    pub(super) fn validate(&self, file: &str, f: &str, case: &Case) -> Result<()> {
        let an = self;
        let f = f.to_string();
        match an {
            AnalysisSpec::Modes { count } => {
                if *count == 0 {
                    return Err(Error::input(file, format!("{f}.count"), "must be at least 1"));
                }
            }
            AnalysisSpec::Harmonic { frequencies, force, system } => {
                frequencies.validate(file, &format!("{f}.frequencies"))?;
                // A coupled system has inputs of its own: its feet and its drives.
                let coupled = *system == HarmonicSystem::Coupled && !case.actuator.is_empty();
                if force.is_empty() && case.load.is_empty() && !coupled {
                    return Err(Error::input(
                        file,
                        format!("{f}.force"),
                        "a harmonic analysis needs at least one [[analysis.force]] (or [[load]], or \
                         actuators with system = \"coupled\")",
                    ));
                }
                if *system == HarmonicSystem::Coupled && case.actuator.is_empty() {
                    return Err(Error::input(
                        file,
                        format!("{f}.system"),
                        "system = \"coupled\" couples the beam with its actuators, and the case has none",
                    ));
                }
                if force.is_empty() {
                    for (j, l) in case.load.iter().enumerate() {
                        if !matches!(l.force, SignalSpec::Sine { .. }) {
                            return Err(Error::input(
                                file,
                                format!("load[{j}].force.kind"),
                                format!(
                                    "{f} applies the case's loads as sinusoids at each of its frequencies, \
                                         so each needs kind = \"sine\" (its amplitude and phase are used): give \
                                         the analysis its own [[analysis.force]] instead"
                                ),
                            ));
                        }
                    }
                }
                for (j, p) in force.iter().enumerate() {
                    super::on_structure(file, &format!("{f}.force[{j}]"), &p.point(), case.extent())?;
                    if !p.amplitude.is_finite() || !p.phase.is_finite() {
                        return Err(Error::input(
                            file,
                            format!("{f}.force[{j}]"),
                            "amplitude and phase must be finite",
                        ));
                    }
                }
            }
            AnalysisSpec::Transient { .. } => self.validate_transient(file, &f, case.base)?,
            AnalysisSpec::SteadyState { harmonics, harmonic_tolerance, samples_per_period, reduction } => {
                if let Some(r) = reduction {
                    r.validate(file, &format!("{f}.reduction"), case.base)?;
                }
                positive(file, &format!("{f}.harmonic_tolerance"), *harmonic_tolerance)?;
                let harmonics = &harmonics.unwrap_or(1);
                if *harmonics == 0 {
                    return Err(Error::input(file, format!("{f}.harmonics"), "must be at least 1"));
                }
                require_samples(*harmonics, *samples_per_period)
                    .map_err(|r| Error::input(file, format!("{f}.samples_per_period"), r))?;
            }
        }
        Ok(())
    }

    /// Checks a transient analysis `f`: its step, length, scheme parameters and reduction.
    fn validate_transient(&self, file: &str, f: &str, base: BaseKind) -> Result<()> {
        let AnalysisSpec::Transient {
            dt,
            steps_per_period,
            periods,
            duration,
            alpha,
            rho_inf,
            tolerance,
            max_periods,
            harmonics,
            scheme,
            reduction,
            segment,
            ..
        } = self
        else {
            return Ok(());
        };
        if let Some(seg) = segment {
            positive(file, &format!("{f}.segment"), *seg)?;
            if duration.is_some_and(|d| *seg > d) {
                return Err(Error::input(
                    file,
                    format!("{f}.segment"),
                    format!("a segment of {seg} s is longer than the record (`duration`)"),
                ));
            }
        }
        if let Some(r) = reduction {
            r.validate(file, &format!("{f}.reduction"), base)?;
        }
        if let Some(dt) = dt {
            positive(file, &format!("{f}.dt"), *dt)?;
        }
        match (dt, steps_per_period) {
            (Some(_), Some(_)) => {
                return Err(Error::input(
                    file,
                    format!("{f}.steps_per_period"),
                    "give either `dt` or `steps_per_period`, not both",
                ))
            }
            (_, Some(0)) => return Err(Error::input(file, format!("{f}.steps_per_period"), "must be at least 1")),
            _ => {}
        }
        if let Some(d) = duration {
            positive(file, &format!("{f}.duration"), *d)?;
        }
        if periods == &Some(0) {
            return Err(Error::input(file, format!("{f}.periods"), "must be at least 1"));
        }
        positive(file, &format!("{f}.tolerance"), *tolerance)?;
        if *max_periods == 0 || *harmonics == Some(0) {
            return Err(Error::input(file, f, "`max_periods` and `harmonics` must be at least 1"));
        }
        refuse_unused(file, f, "alpha", alpha.is_some(), *scheme, SchemeKind::Hht)?;
        refuse_unused(file, f, "rho_inf", rho_inf.is_some(), *scheme, SchemeKind::GeneralizedAlpha)?;
        if let Some(a) = alpha {
            if !(0.0..=1.0 / 3.0).contains(a) {
                return Err(Error::input(file, format!("{f}.alpha"), format!("HHT α must lie in [0, 1/3], got {a}")));
            }
        } else if *scheme == SchemeKind::Hht {
            return Err(Error::input(file, format!("{f}.alpha"), "required for scheme = \"hht\" (0 ≤ α ≤ 1/3)"));
        }
        if let Some(r) = rho_inf {
            if !(0.0..=1.0).contains(r) {
                return Err(Error::input(file, format!("{f}.rho_inf"), format!("ρ∞ must lie in [0, 1], got {r}")));
            }
        } else if *scheme == SchemeKind::GeneralizedAlpha {
            return Err(Error::input(
                file,
                format!("{f}.rho_inf"),
                "required for scheme = \"generalized_alpha\" (0 ≤ ρ∞ ≤ 1)",
            ));
        }
        Ok(())
    }
}
