//! The case-file schema. Field names follow the physics spec (k_p, c_p, d_p, m_t, …);
//! units are SI throughout and given on each field.

use super::signal::SignalSpec;
use crate::actuator::bouc_wen::BoucWen;
use crate::error::{Error, Result};
use crate::signal::sampling::samples_for_harmonics;
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

/// The beam: geometry (m), material (Pa, kg/m³), mesh, supports and attachments.
#[derive(Clone, Debug, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct BeamSpec {
    #[serde(default = "d_length")]
    pub length: f64,
    #[serde(default = "d_width")]
    pub width: f64,
    #[serde(default = "d_thickness")]
    pub thickness: f64,
    #[serde(default = "d_e")]
    pub youngs_modulus: f64,
    #[serde(default = "d_rho")]
    pub density: f64,
    /// `consistent` (default) or `lumped`.
    #[serde(default)]
    pub mass: MassSpec,
    #[serde(default)]
    pub mesh: MeshSpec,
    /// Supports; default: clamped at x = 0 and x = L.
    #[serde(default)]
    pub support: Vec<SupportSpec>,
    #[serde(default)]
    pub point_mass: Vec<PointMassSpec>,
    #[serde(default)]
    pub spring: Vec<SpringSpec>,
}

fn d_length() -> f64 {
    0.730
}
fn d_width() -> f64 {
    0.050
}
fn d_thickness() -> f64 {
    0.005
}
fn d_e() -> f64 {
    210e9
}
fn d_rho() -> f64 {
    7850.0
}

impl Default for BeamSpec {
    fn default() -> Self {
        toml::from_str("").expect("defaults")
    }
}

#[derive(Clone, Copy, Debug, Default, Deserialize, Serialize, PartialEq, Eq)]
#[serde(rename_all = "snake_case")]
pub enum MassSpec {
    #[default]
    Consistent,
    Lumped,
}

/// Either a generated mesh of about `elements` elements, or a mesh file.
#[derive(Clone, Debug, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct MeshSpec {
    #[serde(default = "d_elements")]
    pub elements: usize,
    /// Mesh file (relative to the case file); overrides `elements`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub file: Option<String>,
}

fn d_elements() -> usize {
    200
}

impl Default for MeshSpec {
    fn default() -> Self {
        MeshSpec { elements: d_elements(), file: None }
    }
}

#[derive(Clone, Copy, Debug, Deserialize, Serialize, PartialEq, Eq)]
#[serde(rename_all = "snake_case")]
pub enum SupportKindSpec {
    Clamped,
    Pinned,
    Guided,
    Free,
    Spring,
}

#[derive(Clone, Debug, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct SupportSpec {
    /// Position (m).
    pub x: f64,
    pub kind: SupportKindSpec,
    /// Translational spring (N/m), for `spring`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub k_w: Option<f64>,
    /// Rotational spring (N·m/rad), for `spring`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub k_theta: Option<f64>,
}

#[derive(Clone, Debug, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct PointMassSpec {
    pub x: f64,
    /// kg
    pub mass: f64,
    /// kg·m²
    #[serde(default)]
    pub rotary_inertia: f64,
}

#[derive(Clone, Debug, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct SpringSpec {
    pub x: f64,
    /// N/m
    pub stiffness: f64,
    /// N·s/m
    #[serde(default)]
    pub damping: f64,
}

/// Beam damping.
#[derive(Clone, Debug, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct DampingSpec {
    #[serde(default)]
    pub kind: DampingKind,
    /// Damping ratio for `rayleigh_ratio` (–).
    #[serde(default = "d_zeta")]
    pub zeta: f64,
    /// The two bare-beam modes (1-based) where ζ is matched.
    #[serde(default = "d_modes")]
    pub modes: [usize; 2],
    /// Explicit coefficients for `rayleigh`: a₀ (1/s), a₁ (s).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub a0: Option<f64>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub a1: Option<f64>,
    /// Modal damping ratios per bare-beam mode for `modal` (the last repeats).
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub ratios: Vec<f64>,
    /// Loss factor η for `hysteretic` (–).
    #[serde(default = "d_eta")]
    pub eta: f64,
}

fn d_eta() -> f64 {
    0.01
}

fn d_zeta() -> f64 {
    0.01
}
fn d_modes() -> [usize; 2] {
    [1, 3]
}

impl Default for DampingSpec {
    fn default() -> Self {
        DampingSpec {
            kind: DampingKind::RayleighRatio,
            zeta: d_zeta(),
            modes: d_modes(),
            a0: None,
            a1: None,
            ratios: Vec::new(),
            eta: d_eta(),
        }
    }
}

#[derive(Clone, Copy, Debug, Default, Deserialize, Serialize, PartialEq, Eq)]
#[serde(rename_all = "snake_case")]
pub enum DampingKind {
    /// Rayleigh with ζ matched at two bare-beam modes (default).
    #[default]
    RayleighRatio,
    /// Rayleigh with explicit a₀, a₁.
    Rayleigh,
    /// Modal damping ratios (frequency-domain analyses).
    Modal,
    /// Hysteretic (structural) damping: the beam's stiffness K·(1 + iη), loss factor `eta`
    /// (harmonic and steady-state analyses; no causal time-domain form).
    Hysteretic,
    /// Undamped beam.
    None,
}

#[derive(Clone, Copy, Debug, Deserialize, Serialize, PartialEq, Eq)]
#[serde(rename_all = "snake_case")]
pub enum ActuatorType {
    Inertial,
    Frame,
}

/// An actuator. Fields that do not apply to its type are rejected.
#[derive(Clone, Debug, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct ActuatorSpec {
    #[serde(rename = "type")]
    pub kind: ActuatorType,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub name: Option<String>,
    /// Stack foot position on the beam x_E (m); default 0.150.
    #[serde(default = "d_x_e")]
    pub x_e: f64,
    /// Inertial: top mass m_t (kg), default 0.1.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub m_t: Option<f64>,
    /// Frame: top beam mass m_b (kg), default 0.2.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub m_b: Option<f64>,
    /// Frame: top beam moment of inertia J_b (kg·m²), default 1.6667e-4.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub j_b: Option<f64>,
    /// Frame: half leg spacing a (m), default 0.040.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub a: Option<f64>,
    /// Frame: stack offset from the centre e (m), default 0.001.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub e: Option<f64>,
    /// Frame: leg stiffness k_l (N/m), default 1.5e9, and damping c_l (N·s/m), default 100.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub k_l: Option<f64>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub c_l: Option<f64>,
    /// Frame: right-leg values where the legs differ (default: as the left).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub k_l_right: Option<f64>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub c_l_right: Option<f64>,
    #[serde(default)]
    pub stack: StackSpec,
    pub voltage: SignalSpec,
}

fn d_x_e() -> f64 {
    0.150
}

/// The piezo stack (defaults: the spec's 7×7×20 mm PZT stack).
#[derive(Clone, Debug, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct StackSpec {
    /// N/m
    #[serde(default = "d_kp")]
    pub k_p: f64,
    /// N·s/m
    #[serde(default = "d_cp")]
    pub c_p: f64,
    /// kg
    #[serde(default = "d_mp")]
    pub m_p: f64,
    /// m/V
    #[serde(default = "d_dp")]
    pub d_p: f64,
    /// –
    #[serde(default = "d_alpha")]
    pub alpha: f64,
    /// 1/V
    #[serde(default = "d_beta")]
    pub beta: f64,
    /// 1/V
    #[serde(default = "d_gamma")]
    pub gamma: f64,
    /// Initial hysteretic displacement h(0) (m).
    #[serde(default)]
    pub h0: f64,
    /// false: linear stack, δ = d_p·V.
    #[serde(default = "d_true")]
    pub hysteresis: bool,
}

fn d_kp() -> f64 {
    3.0e7
}
fn d_cp() -> f64 {
    200.0
}
fn d_mp() -> f64 {
    0.030
}
fn d_dp() -> f64 {
    1.3e-7
}
fn d_alpha() -> f64 {
    0.3
}
fn d_beta() -> f64 {
    0.02
}
fn d_gamma() -> f64 {
    0.005
}
fn d_true() -> bool {
    true
}

impl Default for StackSpec {
    fn default() -> Self {
        toml::from_str("").expect("defaults")
    }
}

impl StackSpec {
    pub fn bouc_wen(&self) -> BoucWen {
        BoucWen { d_p: self.d_p, alpha: self.alpha, beta: self.beta, gamma: self.gamma }
    }
}

#[derive(Clone, Debug, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct SensorSpec {
    pub name: String,
    /// Position on the beam (m).
    pub x: f64,
}

/// A prescribed point force on the beam: F(t) (N, upward) at x (m), any signal the
/// actuators' voltages can follow (values in N instead of V).
#[derive(Clone, Debug, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct LoadSpec {
    /// Name in results (default `load<i>`, 1-based).
    #[serde(default)]
    pub name: Option<String>,
    /// Position on the beam (m).
    pub x: f64,
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
    pub x: f64,
    #[serde(default = "d_one")]
    pub amplitude: f64,
    #[serde(default)]
    pub phase: f64,
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
        if self.list().is_empty() {
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
        /// by more than `harmonic_tolerance` (9 on a modal-reduced model).
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
fn d_samples() -> usize {
    1024
}

/// What to write.
#[derive(Clone, Debug, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct OutputSpec {
    /// One HDF5 file per run.
    #[serde(default = "d_true")]
    pub hdf5: bool,
    /// PNG/SVG figures.
    #[serde(default = "d_true")]
    pub plots: bool,
    /// K, M, C in Matrix Market format.
    #[serde(default)]
    pub matrices: bool,
    /// Keep whole time histories in the HDF5 file (else the last periods only).
    #[serde(default)]
    pub full_history: bool,
}

impl Default for OutputSpec {
    fn default() -> Self {
        toml::from_str("").expect("defaults")
    }
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

    /// Checks every field; the first problem is returned, naming file and field.
    pub fn validate(&self, file: &str) -> Result<()> {
        let b = &self.beam;
        positive(file, "beam.length", b.length)?;
        positive(file, "beam.width", b.width)?;
        positive(file, "beam.thickness", b.thickness)?;
        positive(file, "beam.youngs_modulus", b.youngs_modulus)?;
        positive(file, "beam.density", b.density)?;
        if b.mesh.file.is_none() && b.mesh.elements == 0 {
            return Err(Error::input(file, "beam.mesh.elements", "must be at least 1"));
        }
        for (i, s) in b.support.iter().enumerate() {
            on_beam(file, &format!("beam.support[{i}].x"), s.x, b.length)?;
            match s.kind {
                SupportKindSpec::Spring => {
                    if s.k_w.is_none() && s.k_theta.is_none() {
                        return Err(Error::input(
                            file,
                            format!("beam.support[{i}]"),
                            "a spring support needs `k_w` and/or `k_theta`",
                        ));
                    }
                    non_negative(file, &format!("beam.support[{i}].k_w"), s.k_w.unwrap_or(0.0))?;
                    non_negative(file, &format!("beam.support[{i}].k_theta"), s.k_theta.unwrap_or(0.0))?;
                }
                _ => {
                    if s.k_w.is_some() || s.k_theta.is_some() {
                        return Err(Error::input(
                            file,
                            format!("beam.support[{i}]"),
                            "`k_w`/`k_theta` apply only to kind = \"spring\"",
                        ));
                    }
                }
            }
        }
        for (i, p) in b.point_mass.iter().enumerate() {
            on_beam(file, &format!("beam.point_mass[{i}].x"), p.x, b.length)?;
            positive(file, &format!("beam.point_mass[{i}].mass"), p.mass)?;
            non_negative(file, &format!("beam.point_mass[{i}].rotary_inertia"), p.rotary_inertia)?;
        }
        for (i, s) in b.spring.iter().enumerate() {
            on_beam(file, &format!("beam.spring[{i}].x"), s.x, b.length)?;
            non_negative(file, &format!("beam.spring[{i}].stiffness"), s.stiffness)?;
            non_negative(file, &format!("beam.spring[{i}].damping"), s.damping)?;
        }
        let d = &self.damping;
        match d.kind {
            DampingKind::RayleighRatio => {
                non_negative(file, "damping.zeta", d.zeta)?;
                if d.modes[0] == 0 || d.modes[1] == 0 || d.modes[0] == d.modes[1] {
                    return Err(Error::input(
                        file,
                        "damping.modes",
                        format!("two different 1-based mode numbers are needed, got {:?}", d.modes),
                    ));
                }
            }
            DampingKind::Rayleigh => {
                non_negative(
                    file,
                    "damping.a0",
                    d.a0.ok_or_else(|| Error::input(file, "damping.a0", "required for kind = \"rayleigh\""))?,
                )?;
                non_negative(
                    file,
                    "damping.a1",
                    d.a1.ok_or_else(|| Error::input(file, "damping.a1", "required for kind = \"rayleigh\""))?,
                )?;
            }
            DampingKind::Modal => {
                if d.ratios.is_empty() {
                    return Err(Error::input(file, "damping.ratios", "modal damping needs at least one ratio"));
                }
                for (i, &z) in d.ratios.iter().enumerate() {
                    non_negative(file, &format!("damping.ratios[{i}]"), z)?;
                }
            }
            DampingKind::Hysteretic => {
                if !(d.eta > 0.0 && d.eta < 1.0) {
                    return Err(Error::input(file, "damping.eta", format!("must be in (0, 1), got {}", d.eta)));
                }
            }
            DampingKind::None => {}
        }
        for (i, a) in self.actuator.iter().enumerate() {
            a.validate(file, &format!("actuator[{i}]"), self.base, b.length)?;
        }
        for (i, s) in self.sensor.iter().enumerate() {
            on_beam(file, &format!("sensor[{i}].x"), s.x, b.length)?;
        }
        for (i, l) in self.load.iter().enumerate() {
            if self.base == BaseKind::Rigid {
                return Err(Error::input(
                    file,
                    format!("load[{i}]"),
                    "a point load acts on the beam, and base = \"rigid\" has none",
                ));
            }
            on_beam(file, &format!("load[{i}].x"), l.x, b.length)?;
            l.force.validate(file, &format!("load[{i}].force"))?;
        }
        self.validate_names(file)?;
        for (i, an) in self.analysis.iter().enumerate() {
            let f = format!("analysis[{i}]");
            match an {
                AnalysisSpec::Modes { count } => {
                    if *count == 0 {
                        return Err(Error::input(file, format!("{f}.count"), "must be at least 1"));
                    }
                }
                AnalysisSpec::Harmonic { frequencies, force } => {
                    frequencies.validate(file, &format!("{f}.frequencies"))?;
                    if force.is_empty() && self.load.is_empty() {
                        return Err(Error::input(
                            file,
                            format!("{f}.force"),
                            "a harmonic analysis needs at least one [[analysis.force]] (or [[load]])",
                        ));
                    }
                    if force.is_empty() {
                        for (j, l) in self.load.iter().enumerate() {
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
                        on_beam(file, &format!("{f}.force[{j}].x"), p.x, b.length)?;
                        if !p.amplitude.is_finite() || !p.phase.is_finite() {
                            return Err(Error::input(
                                file,
                                format!("{f}.force[{j}]"),
                                "amplitude and phase must be finite",
                            ));
                        }
                    }
                }
                AnalysisSpec::Transient {
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
                } => {
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
                        r.validate(file, &format!("{f}.reduction"), self.base)?;
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
                        (_, Some(0)) => {
                            return Err(Error::input(file, format!("{f}.steps_per_period"), "must be at least 1"))
                        }
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
                        return Err(Error::input(file, &f, "`max_periods` and `harmonics` must be at least 1"));
                    }
                    if let Some(a) = alpha {
                        if !(0.0..=1.0 / 3.0).contains(a) {
                            return Err(Error::input(
                                file,
                                format!("{f}.alpha"),
                                format!("HHT α must lie in [0, 1/3], got {a}"),
                            ));
                        }
                    } else if *scheme == SchemeKind::Hht {
                        return Err(Error::input(
                            file,
                            format!("{f}.alpha"),
                            "required for scheme = \"hht\" (0 ≤ α ≤ 1/3)",
                        ));
                    }
                    if let Some(r) = rho_inf {
                        if !(0.0..=1.0).contains(r) {
                            return Err(Error::input(
                                file,
                                format!("{f}.rho_inf"),
                                format!("ρ∞ must lie in [0, 1], got {r}"),
                            ));
                        }
                    } else if *scheme == SchemeKind::GeneralizedAlpha {
                        return Err(Error::input(
                            file,
                            format!("{f}.rho_inf"),
                            "required for scheme = \"generalized_alpha\" (0 ≤ ρ∞ ≤ 1)",
                        ));
                    }
                }
                AnalysisSpec::SteadyState { harmonics, harmonic_tolerance, samples_per_period, reduction } => {
                    if let Some(r) = reduction {
                        r.validate(file, &format!("{f}.reduction"), self.base)?;
                    }
                    positive(file, &format!("{f}.harmonic_tolerance"), *harmonic_tolerance)?;
                    let harmonics = &harmonics.unwrap_or(1);
                    if *harmonics == 0 {
                        return Err(Error::input(file, format!("{f}.harmonics"), "must be at least 1"));
                    }
                    if samples_for_harmonics(*harmonics).is_none_or(|n| *samples_per_period < n) {
                        return Err(Error::input(
                            file,
                            format!("{f}.samples_per_period"),
                            format!(
                                "must be at least 4·harmonics + 2 = {} to resolve the harmonics",
                                4 * (*harmonics as u128) + 2
                            ),
                        ));
                    }
                }
            }
        }
        Ok(())
    }
}

impl ActuatorSpec {
    /// Its name: as given, or its type (with its index when the case has several).
    pub fn effective_name(&self, index: usize, count: usize) -> String {
        self.name.clone().unwrap_or_else(|| {
            let kind = match self.kind {
                ActuatorType::Inertial => "inertial",
                ActuatorType::Frame => "frame",
            };
            if count > 1 {
                format!("{kind}_{index}")
            } else {
                kind.to_string()
            }
        })
    }

    fn validate(&self, file: &str, f: &str, base: BaseKind, length: f64) -> Result<()> {
        let frame_only = [
            ("m_b", self.m_b),
            ("j_b", self.j_b),
            ("a", self.a),
            ("e", self.e),
            ("k_l", self.k_l),
            ("c_l", self.c_l),
            ("k_l_right", self.k_l_right),
            ("c_l_right", self.c_l_right),
        ];
        match self.kind {
            ActuatorType::Inertial => {
                if let Some((n, _)) = frame_only.iter().find(|(_, v)| v.is_some()) {
                    return Err(Error::input(file, format!("{f}.{n}"), "applies only to a frame actuator"));
                }
                positive(file, &format!("{f}.m_t"), self.m_t())?;
            }
            ActuatorType::Frame => {
                if self.m_t.is_some() {
                    return Err(Error::input(
                        file,
                        format!("{f}.m_t"),
                        "applies only to an inertial actuator (a frame has m_b, j_b)",
                    ));
                }
                positive(file, &format!("{f}.m_b"), self.m_b())?;
                positive(file, &format!("{f}.j_b"), self.j_b())?;
                positive(file, &format!("{f}.a"), self.a())?;
                if !self.e().is_finite() || self.e().abs() >= self.a() {
                    return Err(Error::input(
                        file,
                        format!("{f}.e"),
                        format!(
                            "the stack offset must lie between the legs, |e| < a = {} m, got {}",
                            self.a(),
                            self.e()
                        ),
                    ));
                }
                let (l, r) = self.legs();
                positive(file, &format!("{f}.k_l"), l.0)?;
                non_negative(file, &format!("{f}.c_l"), l.1)?;
                positive(file, &format!("{f}.k_l_right"), r.0)?;
                non_negative(file, &format!("{f}.c_l_right"), r.1)?;
            }
        }
        if base == BaseKind::Beam {
            on_beam(file, &format!("{f}.x_e"), self.x_e, length)?;
            if self.kind == ActuatorType::Frame {
                let xc = self.x_e - self.e();
                for (leg, x) in [("left leg", xc - self.a()), ("right leg", xc + self.a())] {
                    if !(0.0..=length).contains(&x) {
                        return Err(Error::input(
                            file,
                            format!("{f}.x_e"),
                            format!("the {leg} would stand at x = {x} m, outside the beam [0, {length}] m"),
                        ));
                    }
                }
            }
        }
        let s = &self.stack;
        positive(file, &format!("{f}.stack.k_p"), s.k_p)?;
        non_negative(file, &format!("{f}.stack.c_p"), s.c_p)?;
        positive(file, &format!("{f}.stack.m_p"), s.m_p)?;
        if !s.h0.is_finite() {
            return Err(Error::input(file, format!("{f}.stack.h0"), "must be finite"));
        }
        s.bouc_wen().validate().map_err(|e| e.in_table(file, &format!("{f}.stack")))?;
        self.voltage.validate(file, &format!("{f}.voltage"))?;
        Ok(())
    }

    pub fn m_t(&self) -> f64 {
        self.m_t.unwrap_or(0.1)
    }
    pub fn m_b(&self) -> f64 {
        self.m_b.unwrap_or(0.2)
    }
    pub fn j_b(&self) -> f64 {
        self.j_b.unwrap_or(1.6667e-4)
    }
    pub fn a(&self) -> f64 {
        self.a.unwrap_or(0.040)
    }
    pub fn e(&self) -> f64 {
        self.e.unwrap_or(0.001)
    }
    /// ((k_l, c_l) left, (k_l, c_l) right).
    pub fn legs(&self) -> ((f64, f64), (f64, f64)) {
        let k = self.k_l.unwrap_or(1.5e9);
        let c = self.c_l.unwrap_or(100.0);
        ((k, c), (self.k_l_right.unwrap_or(k), self.c_l_right.unwrap_or(c)))
    }
}
