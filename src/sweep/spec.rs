//! The sweep file (TOML): which base case, which fields vary and how, and how each case is
//! evaluated. Loading checks everything a user can get wrong before any case runs, and every
//! message names the sweep file (or the base case file) and the field.

use super::base::BaseCase;
pub use super::field::{get_path, parse_path, set_path, unit_of, Field, Segment};
use crate::case::DEFAULT_SAMPLES_PER_PERIOD;
use crate::case::{LoadedCase, Spacing};
use crate::error::{Error, Result};
use crate::signal::sampling::require_samples;
use crate::signal::voltage::VoltageInput;
use serde::Deserialize;
use std::path::Path;

/// How the parameters' value lists combine into cases.
#[derive(Clone, Copy, Debug, Default, Deserialize, PartialEq, Eq)]
#[serde(rename_all = "snake_case")]
pub enum Combine {
    /// Every combination; the first parameter varies slowest, the last fastest.
    #[default]
    Cartesian,
    /// Case i takes the i-th value of every parameter (all lists equally long).
    Zip,
}

/// What is solved for each case.
#[derive(Clone, Copy, Debug, Default, Deserialize, PartialEq, Eq)]
#[serde(rename_all = "snake_case")]
pub enum SweepAnalysis {
    /// Frequency-domain periodic steady state (physics spec §9), in its headline mode.
    #[default]
    SteadyState,
    /// Newmark time integration to the steady state (§8).
    Transient,
}

impl SweepAnalysis {
    pub fn as_str(self) -> &'static str {
        match self {
            SweepAnalysis::SteadyState => "steady_state",
            SweepAnalysis::Transient => "transient",
        }
    }
}

/// The file as written.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
struct SweepFile {
    #[serde(default)]
    title: String,
    /// Base case, relative to the sweep file.
    base: String,
    #[serde(default)]
    combine: Combine,
    #[serde(default)]
    analysis: SweepAnalysis,
    harmonics: Option<usize>,
    samples_per_period: Option<usize>,
    #[serde(default = "d_true")]
    cache_damping: bool,
    #[serde(default = "d_best")]
    best: usize,
    #[serde(default)]
    parameter: Vec<ParameterFile>,
}

fn d_true() -> bool {
    true
}
fn d_best() -> usize {
    10
}

#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
struct ParameterFile {
    path: String,
    values: Option<Vec<f64>>,
    start: Option<f64>,
    stop: Option<f64>,
    count: Option<usize>,
    spacing: Option<Spacing>,
    /// The nodes of an imported model inside a box (a `node` field's values).
    nodes_in: Option<super::base::NodeBox>,
}

/// A varied field and its values.
#[derive(Clone, Debug)]
pub struct Parameter {
    pub field: Field,
    pub values: Vec<f64>,
}

impl Parameter {
    /// Dotted case-field path, e.g. `actuator[0].x_e`.
    pub fn path(&self) -> &str {
        &self.field.path
    }
}

/// A loaded, checked sweep.
#[derive(Clone, Debug)]
pub struct Sweep {
    /// The sweep file as given (for messages) and its text (embedded in the table).
    pub file: String,
    pub text: String,
    pub title: String,
    /// The base case, as the cases start from it.
    pub base: BaseCase,
    pub combine: Combine,
    pub analysis: SweepAnalysis,
    /// Harmonics solved per case (sweep file, else the base case's analysis, else 9).
    pub harmonics: usize,
    /// Samples per period for the steady state's stack-force FFT.
    pub samples_per_period: usize,
    pub parameters: Vec<Parameter>,
    /// Rows in the best-placement table.
    pub best: usize,
    /// Identifies the sweep: FNV-1a (64 bit) of the sweep text, the base text and the
    /// beamflow version. Shards merge only when it agrees.
    pub hash: String,
    counts: Vec<usize>,
}

pub use crate::io::hash::{fnv1a, FNV_OFFSET};

/// Most values one parameter's range may take (its values are held before any case runs).
pub const MAX_PARAMETER_VALUES: usize = 100_000;

/// Reads and checks a sweep file.
pub fn load(path: &Path) -> Result<Sweep> {
    let text = crate::input_file::read_text(path)?;
    let dir = path.parent().map(Path::to_path_buf).unwrap_or_default();
    Sweep::from_str(&text, &path.display().to_string(), &dir)
}

/// Harmonics and samples per period of a study: its own, else its base case's analysis,
/// else [`DEFAULT_HARMONICS`] and [`DEFAULT_SAMPLES_PER_PERIOD`]; checked so that the
/// samples resolve the harmonics.
pub fn harmonic_counts(
    harmonics: Option<usize>,
    samples: Option<usize>,
    base: &BaseCase,
    file: &str,
) -> Result<(usize, usize)> {
    let harmonics = harmonics.unwrap_or(base.harmonics);
    if harmonics == 0 {
        return Err(Error::input(file, "harmonics", "must be at least 1"));
    }
    let samples_per_period = samples.or(base.samples_per_period).unwrap_or(DEFAULT_SAMPLES_PER_PERIOD);
    require_samples(harmonics, samples_per_period).map_err(|r| Error::input(file, "samples_per_period", r))?;
    Ok((harmonics, samples_per_period))
}

impl Sweep {
    /// Parses and checks sweep text; `file` names it in messages and `dir` is where the
    /// base case path is resolved.
    pub fn from_str(text: &str, file: &str, dir: &Path) -> Result<Sweep> {
        let sf: SweepFile = crate::toml_input::parse(text, file, crate::toml_input::Kind::Sweep)?;
        let mut base = BaseCase::load(file, "base", dir, &sf.base)?;
        let (harmonics, samples_per_period) = harmonic_counts(sf.harmonics, sf.samples_per_period, &base, file)?;
        if sf.best == 0 {
            return Err(Error::input(file, "best", "must be at least 1"));
        }
        if sf.parameter.is_empty() {
            return Err(Error::input(file, "parameter", "a sweep needs at least one [[parameter]]"));
        }

        let mut parameters: Vec<Parameter> = Vec::new();
        for (i, p) in sf.parameter.iter().enumerate() {
            let name = format!("parameter[{i}]");
            let field = Field::parse(&p.path).map_err(|r| Error::input(file, format!("{name}.path"), r))?;
            if let Some(j) = parameters.iter().position(|q| q.path() == p.path) {
                return Err(Error::input(
                    file,
                    format!("{name}.path"),
                    format!("`{}` is already varied by parameter[{j}]", p.path),
                ));
            }
            let values = match &p.nodes_in {
                Some(b) => {
                    let others = [p.values.is_some(), p.start.is_some(), p.stop.is_some(), p.count.is_some()];
                    if others.contains(&true) || p.spacing.is_some() {
                        return Err(Error::input(
                            file,
                            &name,
                            "give either `nodes_in` or `values` or `start`, `stop`, `count`, not several",
                        ));
                    }
                    base.nodes_in(&field, b, file, &name)?.into_iter().map(|id| id as f64).collect()
                }
                None => parameter_values(p, file, &name)?,
            };
            parameters.push(Parameter { field, values });
        }
        if sf.combine == Combine::Zip {
            let n = parameters[0].values.len();
            if let Some((i, q)) = parameters.iter().enumerate().find(|(_, q)| q.values.len() != n) {
                return Err(Error::input(
                    file,
                    format!("parameter[{i}]"),
                    format!(
                        "combine = \"zip\" needs equally many values: `{}` has {}, `{}` has {n}",
                        q.path(),
                        q.values.len(),
                        parameters[0].path()
                    ),
                ));
            }
        }

        let counts: Vec<usize> = parameters.iter().map(|p| p.values.len()).collect();
        if sf.combine == Combine::Cartesian && counts.iter().try_fold(1usize, |a, &n| a.checked_mul(n)).is_none() {
            let factors = counts.iter().map(|n| n.to_string()).collect::<Vec<_>>().join(" × ");
            return Err(Error::input(
                file,
                "parameter",
                format!("{factors} cases are more than can be counted (2⁶⁴): vary fewer parameters or fewer values"),
            ));
        }

        // Each parameter on its own, over all its values, on the base case: unknown paths,
        // integer fields and out-of-range values fail here, before anything runs.
        for (i, p) in parameters.iter_mut().enumerate() {
            base.check_field(&mut p.field, &p.values, file, &format!("parameter[{i}]"))?;
        }
        let varied: Vec<&Field> = parameters.iter().map(|p| &p.field).collect();
        if sf.analysis == SweepAnalysis::SteadyState {
            base.share_structure(&varied);
        }
        if sf.cache_damping {
            base.cache_damping(&varied)?;
        }

        let version = env!("CARGO_PKG_VERSION");
        let mut h = fnv1a(text.as_bytes(), FNV_OFFSET);
        h = fnv1a(b"\0", h);
        h = fnv1a(base.text.as_bytes(), h);
        h = fnv1a(b"\0", h);
        h = fnv1a(version.as_bytes(), h);
        Ok(Sweep {
            file: file.to_string(),
            text: text.to_string(),
            title: sf.title,
            base,
            combine: sf.combine,
            analysis: sf.analysis,
            harmonics,
            samples_per_period,
            parameters,
            best: sf.best,
            hash: format!("{h:016x}"),
            counts,
        })
    }

    /// Number of cases.
    pub fn len(&self) -> usize {
        match self.combine {
            Combine::Cartesian => self.counts.iter().product(),
            Combine::Zip => self.counts[0],
        }
    }

    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// The cases `shard` of this sweep takes (`n` of them), as a [`Cost`] to hold to a
    /// budget before any case runs.
    ///
    /// [`Cost`]: crate::analysis::budget::Cost
    pub fn cases_cost(&self, shard: super::Shard) -> (usize, crate::analysis::budget::Cost) {
        let n = self.len().saturating_sub(shard.k - 1).div_ceil(shard.n);
        let numbers = self.parameters.len() + self.base.actuators.len() + 3 * self.base.links.len();
        let sep = if self.combine == Combine::Zip { " zipped with " } else { " × " };
        let factors = self.parameters.iter().map(|p| p.values.len().to_string()).collect::<Vec<_>>().join(sep);
        let of_shard = if shard == super::Shard::ALL { String::new() } else { format!(", shard {shard}") };
        let cost = crate::analysis::cost::cases(
            "this sweep",
            u64::try_from(n).ok(),
            numbers as u64,
            format!("{factors} values{of_shard}"),
            "parameter",
            "vary fewer values, or split the sweep with --shard",
        );
        (n, cost)
    }

    /// Holds every case of the sweep to `budget` before any runs: each parameter at its
    /// least and greatest value, and the analysis on the largest case
    /// ([`BaseCase::admit_cases`]).
    pub fn admit(&self, budget: &crate::analysis::budget::Budget) -> Result<()> {
        let counts = (self.harmonics, self.samples_per_period);
        self.base.admit_cases(&self.file, &self.extremes(), self.analysis, counts, budget)
    }

    /// Each parameter at its least and greatest value: `(name, field, value)`.
    pub fn extremes(&self) -> Vec<(String, &Field, toml::Value)> {
        let mut extremes = Vec::new();
        for (i, p) in self.parameters.iter().enumerate() {
            let (lo, hi) = p.values.iter().fold((f64::INFINITY, f64::NEG_INFINITY), |(l, h), &v| (l.min(v), h.max(v)));
            for v in [lo, hi] {
                extremes.push((format!("parameter[{i}]"), &p.field, p.field.toml(v)));
            }
        }
        extremes
    }

    /// Parameter paths, in file order.
    pub fn parameter_names(&self) -> Vec<String> {
        self.parameters.iter().map(|p| p.field.path.clone()).collect()
    }

    /// The parameter values of case `i`, in parameter order.
    pub fn values(&self, i: usize) -> Vec<f64> {
        match self.combine {
            Combine::Zip => self.parameters.iter().map(|p| p.values[i]).collect(),
            Combine::Cartesian => {
                let mut rest = i;
                let mut out = vec![0.0; self.parameters.len()];
                for (k, p) in self.parameters.iter().enumerate().rev() {
                    let n = p.values.len();
                    out[k] = p.values[rest % n];
                    rest /= n;
                }
                out
            }
        }
    }

    /// Every case: its index and `(path, value)` pairs.
    pub fn cases(&self) -> Vec<(usize, Vec<(String, f64)>)> {
        (0..self.len()).map(|i| (i, self.parameter_names().into_iter().zip(self.values(i)).collect())).collect()
    }

    /// `path = value, …` of case `i`, for messages.
    pub fn describe(&self, i: usize) -> String {
        self.parameters
            .iter()
            .zip(self.values(i))
            .map(|(p, v)| format!("{} = {v}", p.path()))
            .collect::<Vec<_>>()
            .join(", ")
    }

    /// Identifies the model of case `i` up to the actuators' drives: the bits of its values
    /// of the parameters that are not [`Field::drive_of`] an actuator. Cases with equal
    /// keys assemble the same system (the voltage enters only the stack forces).
    pub fn model_key(&self, i: usize) -> Vec<u64> {
        self.parameters
            .iter()
            .zip(self.values(i))
            .filter(|(p, _)| p.field.drive_of().is_none())
            .map(|(_, v)| v.to_bits())
            .collect()
    }

    /// Actuators whose drive some parameter changes.
    pub fn driven_actuators(&self) -> Vec<usize> {
        let mut a: Vec<usize> = self.parameters.iter().filter_map(|p| p.field.drive_of()).collect();
        a.sort_unstable();
        a.dedup();
        a
    }

    /// Case `i`'s fields and values.
    fn assignment(&self, i: usize) -> impl Iterator<Item = (&Field, toml::Value)> {
        self.parameters.iter().map(|p| &p.field).zip(self.values(i)).map(|(f, v)| (f, f.toml(v)))
    }

    /// The voltage of actuator `a` in case `i`, as [`Sweep::case`] would build it (the base
    /// case's `actuator[a].voltage` with the case's values of the parameters under it set,
    /// loaded and validated), without expanding and checking the whole case.
    pub fn voltage(&self, i: usize, a: usize) -> Result<VoltageInput> {
        let label = format!("{} [sweep case {i}]", self.base.file);
        self.base
            .voltage_with(a, self.assignment(i), &label)
            .map_err(|r| Error::input(&self.file, format!("case {i} ({})", self.describe(i)), r))
    }

    /// The case with index `i`: the base with the case's values set, deserialised and
    /// validated (analyses removed: the sweep says what to solve).
    pub fn case(&self, i: usize) -> Result<LoadedCase> {
        if i >= self.len() {
            return Err(Error::input(
                &self.file,
                "case",
                format!("case {i} does not exist (the sweep has {})", self.len()),
            ));
        }
        let label = format!("{} [sweep case {i}]", self.base.file);
        self.base
            .case_with(self.assignment(i), &label)
            .map_err(|r| Error::input(&self.file, format!("case {i} ({})", self.describe(i)), r))
    }
}

fn parameter_values(p: &ParameterFile, file: &str, field: &str) -> Result<Vec<f64>> {
    let range = [p.start.is_some(), p.stop.is_some(), p.count.is_some()];
    let values = match (&p.values, range.iter().any(|&b| b)) {
        (Some(_), true) => {
            return Err(Error::input(file, field, "give either `values` or `start`, `stop`, `count`, not both"));
        }
        (None, false) => {
            return Err(Error::input(
                file,
                field,
                "no values: give `values = [...]`, `start`, `stop`, `count`, or `nodes_in` (an imported model's nodes)",
            ));
        }
        (Some(v), false) => {
            if p.spacing.is_some() {
                return Err(Error::input(file, format!("{field}.spacing"), "applies only to a range"));
            }
            if v.is_empty() {
                return Err(Error::input(file, format!("{field}.values"), "is empty: give at least one value"));
            }
            v.clone()
        }
        (None, true) => {
            let missing: Vec<&str> =
                ["start", "stop", "count"].iter().zip(range).filter(|(_, given)| !given).map(|(n, _)| *n).collect();
            if !missing.is_empty() {
                return Err(Error::input(
                    file,
                    format!("{field}.{}", missing[0]),
                    "a range needs all of `start`, `stop` and `count`",
                ));
            }
            let (a, b, n) = (p.start.unwrap_or(0.0), p.stop.unwrap_or(0.0), p.count.unwrap_or(0));
            for (name, v) in [("start", a), ("stop", b)] {
                if !v.is_finite() {
                    return Err(Error::input(file, format!("{field}.{name}"), format!("must be finite, got {v}")));
                }
            }
            if n == 0 {
                return Err(Error::input(file, format!("{field}.count"), "must be at least 1"));
            }
            if n > MAX_PARAMETER_VALUES {
                return Err(Error::input(
                    file,
                    format!("{field}.count"),
                    format!(
                        "{n} values are more than one parameter may take ({MAX_PARAMETER_VALUES}); the cases of a \
                         sweep are the product of its parameters' values"
                    ),
                ));
            }
            if n > 1 && a == b {
                return Err(Error::input(
                    file,
                    format!("{field}.stop"),
                    format!("equals `start` ({a}): a range of {n} values needs start ≠ stop"),
                ));
            }
            let spacing = p.spacing.unwrap_or_default();
            if spacing == Spacing::Log && !(a > 0.0 && b > 0.0) {
                return Err(Error::input(
                    file,
                    format!("{field}.start"),
                    format!("a log range needs positive start and stop, got {a} and {b}"),
                ));
            }
            (0..n)
                .map(|i| {
                    let s = if n == 1 { 0.0 } else { i as f64 / (n - 1) as f64 };
                    match spacing {
                        Spacing::Linear => a + (b - a) * s,
                        Spacing::Log => a * (b / a).powf(s),
                    }
                })
                .collect()
        }
    };
    if let Some((k, v)) = values.iter().enumerate().find(|(_, v)| !v.is_finite()) {
        return Err(Error::input(file, format!("{field}.values[{k}]"), format!("must be finite, got {v}")));
    }
    Ok(values)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn hash_is_fnv1a() {
        // Reference values of 64-bit FNV-1a.
        assert_eq!(fnv1a(b"", FNV_OFFSET), 0xcbf29ce484222325);
        assert_eq!(fnv1a(b"a", FNV_OFFSET), 0xaf63dc4c8601ec8c);
    }
}
