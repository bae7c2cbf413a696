//! The sweep file (TOML): which base case, which fields vary and how, and how each case is
//! evaluated. Loading checks everything a user can get wrong before any case runs, and every
//! message names the sweep file (or the base case file) and the field.

use crate::assembly::system::Rayleigh;
use crate::case::{AnalysisSpec, BaseKind, Case, DampingKind, LoadedCase, Spacing};
use crate::error::{Error, Result};
use crate::signal::voltage::VoltageInput;
use serde::Deserialize;
use std::path::{Path, PathBuf};

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
}

/// One segment of a dotted field path: `actuator[0]` is key `actuator`, index 0.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Segment {
    pub key: String,
    pub index: Option<usize>,
}

/// Parses `actuator[0].voltage.frequency` into segments.
pub fn parse_path(path: &str) -> std::result::Result<Vec<Segment>, String> {
    if path.trim().is_empty() {
        return Err("the path is empty".into());
    }
    let mut out = Vec::new();
    for part in path.split('.') {
        let (key, index) = match part.find('[') {
            Some(b) => {
                let rest = &part[b + 1..];
                let idx = rest
                    .strip_suffix(']')
                    .and_then(|d| d.parse::<usize>().ok())
                    .ok_or_else(|| format!("`{part}`: an index must be written `name[N]` with N ≥ 0"))?;
                (&part[..b], Some(idx))
            }
            None => (part, None),
        };
        if key.is_empty() || !key.chars().all(|c| c.is_ascii_alphanumeric() || c == '_') {
            return Err(format!("`{part}` is not a field name (letters, digits and `_`, optionally `[N]`)"));
        }
        out.push(Segment { key: key.to_string(), index });
    }
    Ok(out)
}

/// Sets `path` in a TOML document to `value`, creating missing tables on the way. Arrays
/// (e.g. `actuator`) must exist and hold the index: a sweep varies cases, it does not add
/// actuators.
pub fn set_path(root: &mut toml::Value, path: &[Segment], value: toml::Value) -> std::result::Result<(), String> {
    let mut cur = root;
    let mut walked = String::new();
    for (n, seg) in path.iter().enumerate() {
        let last = n + 1 == path.len();
        let table = cur.as_table_mut().ok_or_else(|| format!("`{walked}` in the base case is a value, not a table"))?;
        if !walked.is_empty() {
            walked.push('.');
        }
        walked.push_str(&seg.key);
        match seg.index {
            None if last => {
                table.insert(seg.key.clone(), value);
                return Ok(());
            }
            None => {
                cur = table.entry(seg.key.clone()).or_insert_with(|| toml::Value::Table(Default::default()));
            }
            Some(i) => {
                let arr = table
                    .get_mut(&seg.key)
                    .ok_or_else(|| format!("the base case has no `{walked}` to index"))?
                    .as_array_mut()
                    .ok_or_else(|| format!("`{walked}` in the base case is not an array"))?;
                let len = arr.len();
                let slot = arr
                    .get_mut(i)
                    .ok_or_else(|| format!("the base case has {len} entries in `{walked}`, not {}", i + 1))?;
                walked.push_str(&format!("[{i}]"));
                if last {
                    *slot = value;
                    return Ok(());
                }
                cur = slot;
            }
        }
    }
    Ok(())
}

/// The value at `path`, if the base case has one.
pub fn get_path<'a>(root: &'a toml::Value, path: &[Segment]) -> Option<&'a toml::Value> {
    let mut cur = root;
    for seg in path {
        cur = cur.as_table()?.get(&seg.key)?;
        if let Some(i) = seg.index {
            cur = cur.as_array()?.get(i)?;
        }
    }
    Some(cur)
}

/// A varied field and its values.
#[derive(Clone, Debug)]
pub struct Parameter {
    /// Dotted case-field path, e.g. `actuator[0].x_e`.
    pub path: String,
    pub segments: Vec<Segment>,
    pub values: Vec<f64>,
    /// Written as a TOML integer (the field is an integer, e.g. `beam.mesh.elements`).
    pub integer: bool,
    /// SI unit, from the field name (`"1"` dimensionless, `"?"` unknown).
    pub unit: &'static str,
}

impl Parameter {
    /// The actuator whose drive this parameter sets, if its path starts with
    /// `actuator[a].voltage.`: such a parameter changes what the stack is driven with, not
    /// the model that is assembled.
    pub fn drive_of(&self) -> Option<usize> {
        match self.segments.as_slice() {
            [a, v, _, ..] if a.key == "actuator" && v.key == "voltage" && v.index.is_none() => a.index,
            _ => None,
        }
    }

    /// The value as TOML.
    fn toml(&self, v: f64) -> toml::Value {
        if self.integer {
            toml::Value::Integer(v as i64)
        } else {
            toml::Value::Float(v)
        }
    }
}

/// The unit of a case field, from its last name (physics spec and case schema).
pub fn unit_of(path: &str) -> &'static str {
    let name = path.rsplit('.').next().unwrap_or(path);
    let name = name.split('[').next().unwrap_or(name);
    match name {
        "x_e" | "a" | "e" | "x" | "length" | "width" | "thickness" | "h0" => "m",
        "frequency" | "f_start" | "f_end" => "Hz",
        "amplitude" | "offset" | "from" | "to" => "V",
        "phase" => "rad",
        "m_t" | "m_b" | "m_p" | "mass" => "kg",
        "j_b" | "rotary_inertia" => "kg m^2",
        "k_l" | "k_l_right" | "k_p" | "k_w" | "stiffness" => "N/m",
        "c_l" | "c_l_right" | "c_p" | "damping" => "N s/m",
        "k_theta" => "N m/rad",
        "d_p" => "m/V",
        "beta" | "gamma" => "1/V",
        "alpha" | "zeta" | "ratios" | "elements" | "modes" => "1",
        "youngs_modulus" => "Pa",
        "density" => "kg/m^3",
        "a0" => "1/s",
        "a1" | "duration" | "time" | "rise_time" => "s",
        _ => "?",
    }
}

/// A loaded, checked sweep.
#[derive(Clone, Debug)]
pub struct Sweep {
    /// The sweep file as given (for messages) and its text (embedded in the table).
    pub file: String,
    pub text: String,
    pub title: String,
    /// The base case file and its text.
    pub base_file: String,
    pub base_text: String,
    /// Directory the base case's relative paths resolve against.
    pub base_dir: PathBuf,
    pub combine: Combine,
    pub analysis: SweepAnalysis,
    /// Harmonics solved per case (sweep file, else the base case's analysis, else 9).
    pub harmonics: usize,
    /// Samples per period for the steady state's stack-force FFT.
    pub samples_per_period: usize,
    pub parameters: Vec<Parameter>,
    /// Rayleigh coefficients computed once from the base case and used by every case, when
    /// the sweep leaves the beam and its damping alone (`cache_damping`).
    pub cached_damping: Option<Rayleigh>,
    /// Rows in the best-placement table.
    pub best: usize,
    /// Identifies the sweep: FNV-1a (64 bit) of the sweep text, the base text and the
    /// beamflow version. Shards merge only when it agrees.
    pub hash: String,
    /// Actuator and link names of the base model (table columns).
    pub actuators: Vec<String>,
    pub links: Vec<String>,
    /// The base case with the analyses removed (and the cached damping inserted).
    base_value: toml::Value,
    counts: Vec<usize>,
}

/// FNV-1a, 64 bit: stable across platforms and versions of Rust (unlike `DefaultHasher`).
pub fn fnv1a(bytes: &[u8], mut h: u64) -> u64 {
    for &b in bytes {
        h ^= b as u64;
        h = h.wrapping_mul(0x0100_0000_01b3);
    }
    h
}

pub const FNV_OFFSET: u64 = 0xcbf2_9ce4_8422_2325;

/// Reads and checks a sweep file.
pub fn load(path: &Path) -> Result<Sweep> {
    let text = std::fs::read_to_string(path).map_err(|e| Error::io(path, e))?;
    let dir = path.parent().map(Path::to_path_buf).unwrap_or_default();
    Sweep::from_str(&text, &path.display().to_string(), &dir)
}

impl Sweep {
    /// Parses and checks sweep text; `file` names it in messages and `dir` is where the
    /// base case path is resolved.
    pub fn from_str(text: &str, file: &str, dir: &Path) -> Result<Sweep> {
        let sf: SweepFile = toml::from_str(text)
            .map_err(|e| Error::Parse { file: file.to_string(), message: e.to_string().trim_end().to_string() })?;
        let base_path = dir.join(&sf.base);
        let base_file = base_path.display().to_string();
        let base_text = std::fs::read_to_string(&base_path)
            .map_err(|e| Error::input(file, "base", format!("cannot read the base case {base_file}: {e}")))?;
        let base_dir = base_path.parent().map(Path::to_path_buf).unwrap_or_default();
        // The base must be a valid case on its own; its errors name the base file.
        let base_lc = LoadedCase::from_str(&base_text, &base_file, base_dir.clone())?;
        let mut base_value: toml::Value = toml::from_str(&base_text)
            .map_err(|e| Error::Parse { file: base_file.clone(), message: e.to_string().trim_end().to_string() })?;
        if let Some(t) = base_value.as_table_mut() {
            t.remove("analysis");
        }

        let (base_harm, base_samples) = base_lc
            .case
            .analysis
            .iter()
            .find_map(|a| match a {
                AnalysisSpec::SteadyState { harmonics, samples_per_period, .. } => {
                    Some((harmonics.unwrap_or(9), Some(*samples_per_period)))
                }
                AnalysisSpec::Transient { harmonics, .. } => Some((harmonics.unwrap_or(9), None)),
                _ => None,
            })
            .unwrap_or((9, None));
        let harmonics = sf.harmonics.unwrap_or(base_harm);
        if harmonics == 0 {
            return Err(Error::input(file, "harmonics", "must be at least 1"));
        }
        let samples_per_period = sf.samples_per_period.or(base_samples).unwrap_or(1024);
        if samples_per_period < 4 * harmonics + 2 {
            return Err(Error::input(
                file,
                "samples_per_period",
                format!("must be at least 4·harmonics + 2 = {} to resolve the harmonics", 4 * harmonics + 2),
            ));
        }
        if sf.best == 0 {
            return Err(Error::input(file, "best", "must be at least 1"));
        }
        if sf.parameter.is_empty() {
            return Err(Error::input(file, "parameter", "a sweep needs at least one [[parameter]]"));
        }

        let mut parameters: Vec<Parameter> = Vec::new();
        for (i, p) in sf.parameter.iter().enumerate() {
            let field = format!("parameter[{i}]");
            let segments = parse_path(&p.path).map_err(|r| Error::input(file, format!("{field}.path"), r))?;
            if let Some(j) = parameters.iter().position(|q| q.path == p.path) {
                return Err(Error::input(
                    file,
                    format!("{field}.path"),
                    format!("`{}` is already varied by parameter[{j}]", p.path),
                ));
            }
            let values = parameter_values(p, file, &field)?;
            let integer = matches!(get_path(&base_value, &segments), Some(toml::Value::Integer(_)));
            parameters.push(Parameter { path: p.path.clone(), segments, values, integer, unit: unit_of(&p.path) });
        }
        if sf.combine == Combine::Zip {
            let n = parameters[0].values.len();
            if let Some((i, q)) = parameters.iter().enumerate().find(|(_, q)| q.values.len() != n) {
                return Err(Error::input(
                    file,
                    format!("parameter[{i}]"),
                    format!(
                        "combine = \"zip\" needs equally many values: `{}` has {}, `{}` has {n}",
                        q.path,
                        q.values.len(),
                        parameters[0].path
                    ),
                ));
            }
        }

        // Each parameter on its own, over all its values, on the base case: unknown paths,
        // integer fields and out-of-range values fail here, before anything runs.
        for (i, param) in parameters.iter_mut().enumerate() {
            let field = format!("parameter[{i}]");
            for k in 0..param.values.len() {
                let v = param.values[k];
                let attempt = |p: &Parameter| -> Result<()> {
                    let mut val = base_value.clone();
                    set_path(&mut val, &p.segments, p.toml(v))
                        .map_err(|r| Error::input(file, format!("{field}.path"), format!("`{}`: {r}", p.path)))?;
                    let case: Case = val.try_into().map_err(|e: toml::de::Error| {
                        Error::input(
                            file,
                            format!("{field}.path"),
                            format!(
                                "`{}` is not a case field the base case accepts: {}",
                                p.path,
                                e.message().trim_end()
                            ),
                        )
                    })?;
                    case.validate(&base_file).map_err(|e| {
                        Error::input(
                            file,
                            format!("{field}.values"),
                            format!("{} = {v} is not acceptable: {e}", p.path),
                        )
                    })
                };
                match attempt(param) {
                    Ok(()) => {}
                    Err(e) if k == 0 && !param.integer && v.fract() == 0.0 => {
                        // A field the base leaves at its default may be an integer.
                        let mut as_int = param.clone();
                        as_int.integer = true;
                        if attempt(&as_int).is_err() {
                            return Err(e);
                        }
                        param.integer = true;
                    }
                    Err(e) => return Err(e),
                }
                if param.integer && v.fract() != 0.0 {
                    return Err(Error::input(
                        file,
                        format!("{field}.values"),
                        format!("`{}` is an integer field, got {v}", param.path),
                    ));
                }
            }
        }

        // Beam damping computed once, if no case can change it.
        let touches_beam = parameters.iter().any(|p| matches!(p.segments[0].key.as_str(), "beam" | "damping" | "base"));
        let mut cached_damping = None;
        if sf.cache_damping
            && !touches_beam
            && base_lc.case.base == BaseKind::Beam
            && base_lc.case.damping.kind == DampingKind::RayleighRatio
        {
            let stripped: Case = base_value.clone().try_into().map_err(|e: toml::de::Error| Error::Parse {
                file: base_file.clone(),
                message: e.message().trim_end().to_string(),
            })?;
            let lc = LoadedCase { case: stripped, file: base_file.clone(), dir: base_dir.clone(), text: String::new() };
            let beam = crate::case::build::build_beam(&lc)?;
            let d = &lc.case.damping;
            let need = d.modes[0].max(d.modes[1]);
            let m = crate::analysis::modes::bare_modes(&beam, need)?;
            if m.count() < need {
                return Err(Error::input(
                    &base_file,
                    "damping.modes",
                    format!("the mesh has only {} modes", m.count()),
                ));
            }
            let r = Rayleigh::from_ratio(d.zeta, m.omega[d.modes[0] - 1], m.omega[d.modes[1] - 1]);
            let mut t = toml::map::Map::new();
            t.insert("kind".into(), toml::Value::String("rayleigh".into()));
            t.insert("a0".into(), toml::Value::Float(r.a0));
            t.insert("a1".into(), toml::Value::Float(r.a1));
            base_value.as_table_mut().expect("a case is a table").insert("damping".into(), toml::Value::Table(t));
            cached_damping = Some(r);
        }

        // Column names from the base model.
        let base_case: Case = base_value.clone().try_into().map_err(|e: toml::de::Error| Error::Parse {
            file: base_file.clone(),
            message: e.message().trim_end().to_string(),
        })?;
        let mut actuators = Vec::new();
        let mut links = Vec::new();
        for (i, a) in base_case.actuator.iter().enumerate() {
            let name = a.name.clone().unwrap_or_else(|| {
                let kind = match a.kind {
                    crate::case::ActuatorType::Inertial => "inertial",
                    crate::case::ActuatorType::Frame => "frame",
                };
                if base_case.actuator.len() > 1 {
                    format!("{kind}_{i}")
                } else {
                    kind.to_string()
                }
            });
            let l: &[&str] = match a.kind {
                crate::case::ActuatorType::Inertial => &["stack"],
                crate::case::ActuatorType::Frame => &["stack", "left_leg", "right_leg"],
            };
            links.extend(l.iter().map(|l| format!("{name}.{l}")));
            actuators.push(name);
        }
        if actuators.is_empty() {
            return Err(Error::input(&base_file, "actuator", "a sweep's base case needs at least one actuator"));
        }

        let version = env!("CARGO_PKG_VERSION");
        let mut h = fnv1a(text.as_bytes(), FNV_OFFSET);
        h = fnv1a(b"\0", h);
        h = fnv1a(base_text.as_bytes(), h);
        h = fnv1a(b"\0", h);
        h = fnv1a(version.as_bytes(), h);
        let counts = parameters.iter().map(|p| p.values.len()).collect();
        Ok(Sweep {
            file: file.to_string(),
            text: text.to_string(),
            title: sf.title,
            base_file,
            base_text,
            base_dir,
            combine: sf.combine,
            analysis: sf.analysis,
            harmonics,
            samples_per_period,
            parameters,
            cached_damping,
            best: sf.best,
            hash: format!("{h:016x}"),
            actuators,
            links,
            base_value,
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

    /// Parameter paths, in file order.
    pub fn parameter_names(&self) -> Vec<String> {
        self.parameters.iter().map(|p| p.path.clone()).collect()
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
        (0..self.len())
            .map(|i| (i, self.parameters.iter().map(|p| p.path.clone()).zip(self.values(i)).collect()))
            .collect()
    }

    /// `path = value, …` of case `i`, for messages.
    pub fn describe(&self, i: usize) -> String {
        self.parameters
            .iter()
            .zip(self.values(i))
            .map(|(p, v)| format!("{} = {v}", p.path))
            .collect::<Vec<_>>()
            .join(", ")
    }

    /// Identifies the model of case `i` up to the actuators' drives: the bits of its values
    /// of the parameters that are not [`Parameter::drive_of`] an actuator. Cases with equal
    /// keys assemble the same system (the voltage enters only the stack forces).
    pub fn model_key(&self, i: usize) -> Vec<u64> {
        self.parameters
            .iter()
            .zip(self.values(i))
            .filter(|(p, _)| p.drive_of().is_none())
            .map(|(_, v)| v.to_bits())
            .collect()
    }

    /// Actuators whose drive some parameter changes.
    pub fn driven_actuators(&self) -> Vec<usize> {
        let mut a: Vec<usize> = self.parameters.iter().filter_map(Parameter::drive_of).collect();
        a.sort_unstable();
        a.dedup();
        a
    }

    /// The voltage of actuator `a` in case `i`, as [`Sweep::case`] would build it (the base
    /// case's `actuator[a].voltage` with the case's values of the parameters under it set,
    /// loaded and validated), without expanding and checking the whole case.
    pub fn voltage(&self, i: usize, a: usize) -> Result<VoltageInput> {
        let field = format!("actuator[{a}].voltage");
        let file = format!("{} [sweep case {i}]", self.base_file);
        let wrap = |reason: String| Error::input(&self.file, format!("case {i} ({})", self.describe(i)), reason);
        let path = [Segment { key: "actuator".into(), index: Some(a) }, Segment { key: "voltage".into(), index: None }];
        let mut val = get_path(&self.base_value, &path).cloned().unwrap_or(toml::Value::Table(Default::default()));
        for (p, v) in self.parameters.iter().zip(self.values(i)) {
            if p.drive_of() == Some(a) {
                set_path(&mut val, &p.segments[2..], p.toml(v)).map_err(wrap)?;
            }
        }
        let mut voltage: VoltageInput =
            val.try_into().map_err(|e: toml::de::Error| wrap(e.message().trim_end().to_string()))?;
        voltage.load(&self.base_dir, &file, &field).map_err(|e| wrap(e.to_string()))?;
        voltage.validate(&file, &field).map_err(|e| wrap(e.to_string()))?;
        Ok(voltage)
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
        let mut val = self.base_value.clone();
        let wrap = |reason: String| Error::input(&self.file, format!("case {i} ({})", self.describe(i)), reason);
        for (p, v) in self.parameters.iter().zip(self.values(i)) {
            set_path(&mut val, &p.segments, p.toml(v)).map_err(wrap)?;
        }
        let case: Case = val.try_into().map_err(|e: toml::de::Error| wrap(e.message().trim_end().to_string()))?;
        let file = format!("{} [sweep case {i}]", self.base_file);
        LoadedCase::from_case(case, &file, self.base_dir.clone()).map_err(|e| wrap(e.to_string()))
    }
}

fn parameter_values(p: &ParameterFile, file: &str, field: &str) -> Result<Vec<f64>> {
    let range = [p.start.is_some(), p.stop.is_some(), p.count.is_some()];
    let values = match (&p.values, range.iter().any(|&b| b)) {
        (Some(_), true) => {
            return Err(Error::input(file, field, "give either `values` or `start`, `stop`, `count`, not both"));
        }
        (None, false) => {
            return Err(Error::input(file, field, "no values: give `values = [...]` or `start`, `stop`, `count`"));
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
    fn paths_parse() {
        assert_eq!(
            parse_path("actuator[0].voltage.frequency").unwrap(),
            vec![
                Segment { key: "actuator".into(), index: Some(0) },
                Segment { key: "voltage".into(), index: None },
                Segment { key: "frequency".into(), index: None },
            ]
        );
        for bad in ["", "a..b", "a[x].b", "a[0", "a b", "[0]"] {
            assert!(parse_path(bad).is_err(), "{bad}");
        }
    }

    #[test]
    fn set_path_creates_tables_but_not_array_entries() {
        let mut v: toml::Value = toml::from_str("[[actuator]]\nx_e = 0.1\n").unwrap();
        set_path(&mut v, &parse_path("damping.zeta").unwrap(), toml::Value::Float(0.02)).unwrap();
        set_path(&mut v, &parse_path("actuator[0].voltage.frequency").unwrap(), toml::Value::Float(60.0)).unwrap();
        assert_eq!(v["damping"]["zeta"].as_float(), Some(0.02));
        assert_eq!(v["actuator"][0]["voltage"]["frequency"].as_float(), Some(60.0));
        let e = set_path(&mut v, &parse_path("actuator[1].x_e").unwrap(), toml::Value::Float(0.2)).unwrap_err();
        assert!(e.contains("1 entries in `actuator`"), "{e}");
        let e = set_path(&mut v, &parse_path("sensor[0].x").unwrap(), toml::Value::Float(0.2)).unwrap_err();
        assert!(e.contains("no `sensor`"), "{e}");
    }

    #[test]
    fn hash_is_fnv1a() {
        // Reference values of 64-bit FNV-1a.
        assert_eq!(fnv1a(b"", FNV_OFFSET), 0xcbf29ce484222325);
        assert_eq!(fnv1a(b"a", FNV_OFFSET), 0xaf63dc4c8601ec8c);
    }
}
