//! Measurement files: time series of voltage, displacement (stroke), force and acceleration.
//!
//! # File format
//!
//! A CSV table read by [`crate::signal::csv`] (separator `,` `;` tab or spaces, `#` comment
//! lines, one header row, then one row of numbers per sample). Each header names a quantity
//! and, optionally, its unit:
//!
//! | quantity | accepted names (any case) | units (default: SI) |
//! |---|---|---|
//! | time | `time`, `t` | `s`, `ms`, `us`/`µs` |
//! | voltage | `voltage`, `v` | `V`, `mV`, `kV` |
//! | displacement | `displacement`, `stroke`, `x` | `m`, `mm`, `um`/`µm`, `nm` |
//! | force | `force`, `f` | `N`, `mN`, `kN` |
//! | acceleration | `acceleration`, `accel`, `a` | `m/s^2` (`m/s²`, `m/s2`), `mm/s^2`, `g` (= 9.80665 m/s²) |
//!
//! The unit is written either in parentheses, `displacement (um)`, or in brackets,
//! `displacement [um]`; a bare name means SI. Values are converted to SI on reading. Other
//! columns are ignored.
//!
//! # Validation
//!
//! Every error names the file and the column: a required column missing (or given twice), an
//! unknown unit, rows of unequal length, an empty or non-numeric cell, NaN or infinity
//! (all from the CSV reader), fewer than 2 samples, and a time axis that is not strictly
//! increasing or not uniform: every step must lie within `uniform_tolerance` (relative,
//! default 1e-3) of the mean step. The tolerance is looser than a simulator's because
//! acquisition files often print time with few digits.

use std::path::Path;

use crate::error::{Error, Result};

/// A measured quantity (one column).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Quantity {
    Time,
    Voltage,
    Displacement,
    Force,
    Acceleration,
}

impl Quantity {
    /// All quantities in file order.
    pub const ALL: [Quantity; 5] =
        [Quantity::Time, Quantity::Voltage, Quantity::Displacement, Quantity::Force, Quantity::Acceleration];

    /// The canonical column name.
    pub fn name(self) -> &'static str {
        match self {
            Quantity::Time => "time",
            Quantity::Voltage => "voltage",
            Quantity::Displacement => "displacement",
            Quantity::Force => "force",
            Quantity::Acceleration => "acceleration",
        }
    }

    /// The SI unit written by [`write()`].
    pub fn si_unit(self) -> &'static str {
        match self {
            Quantity::Time => "s",
            Quantity::Voltage => "V",
            Quantity::Displacement => "m",
            Quantity::Force => "N",
            Quantity::Acceleration => "m/s^2",
        }
    }

    fn aliases(self) -> &'static [&'static str] {
        match self {
            Quantity::Time => &["time", "t"],
            Quantity::Voltage => &["voltage", "v"],
            Quantity::Displacement => &["displacement", "stroke", "x"],
            Quantity::Force => &["force", "f"],
            Quantity::Acceleration => &["acceleration", "accel", "a"],
        }
    }

    /// Factor converting `unit` to SI, None if the unit is not accepted for this quantity.
    fn unit_factor(self, unit: &str) -> Option<f64> {
        let u = unit.trim().replace('μ', "µ");
        let f = match (self, u.as_str()) {
            (Quantity::Time, "s") => 1.0,
            (Quantity::Time, "ms") => 1e-3,
            (Quantity::Time, "us" | "µs") => 1e-6,
            (Quantity::Voltage, "V") => 1.0,
            (Quantity::Voltage, "mV") => 1e-3,
            (Quantity::Voltage, "kV") => 1e3,
            (Quantity::Displacement, "m") => 1.0,
            (Quantity::Displacement, "mm") => 1e-3,
            (Quantity::Displacement, "um" | "µm") => 1e-6,
            (Quantity::Displacement, "nm") => 1e-9,
            (Quantity::Force, "N") => 1.0,
            (Quantity::Force, "mN") => 1e-3,
            (Quantity::Force, "kN") => 1e3,
            (Quantity::Acceleration, "m/s^2" | "m/s²" | "m/s2") => 1.0,
            (Quantity::Acceleration, "mm/s^2" | "mm/s²" | "mm/s2") => 1e-3,
            (Quantity::Acceleration, "g") => 9.80665,
            _ => return None,
        };
        Some(f)
    }

    fn accepted_units(self) -> &'static str {
        match self {
            Quantity::Time => "s, ms, us",
            Quantity::Voltage => "V, mV, kV",
            Quantity::Displacement => "m, mm, um, nm",
            Quantity::Force => "N, mN, kN",
            Quantity::Acceleration => "m/s^2, mm/s^2, g",
        }
    }
}

/// Splits a header `name (unit)` / `name [unit]` / `name` into (lower-case name, unit).
fn split_header(h: &str) -> (String, Option<String>) {
    let h = h.trim();
    for (open, close) in [('(', ')'), ('[', ']')] {
        if h.ends_with(close) {
            if let Some(i) = h.rfind(open) {
                let name = h[..i].trim().to_lowercase();
                let unit = h[i + open.len_utf8()..h.len() - close.len_utf8()].trim().to_string();
                return (name, Some(unit));
            }
        }
    }
    (h.to_lowercase(), None)
}

/// Header fields of the first non-comment line, split as the CSV reader does.
fn header_fields(text: &str) -> Vec<String> {
    let Some(line) = text.lines().find(|l| {
        let t = l.trim();
        !t.is_empty() && !t.starts_with('#')
    }) else {
        return Vec::new();
    };
    let line = line.trim_start_matches('\u{feff}');
    let fields: Vec<&str> = if let Some(c) = [',', ';', '\t'].into_iter().find(|c| line.contains(*c)) {
        line.split(c).collect()
    } else {
        line.split_whitespace().collect()
    };
    fields
        .into_iter()
        .map(|f| {
            let f = f.trim();
            if f.len() >= 2 && f.starts_with('"') && f.ends_with('"') {
                f[1..f.len() - 1].trim().to_string()
            } else {
                f.to_string()
            }
        })
        .collect()
}

/// Settings of [`load`].
#[derive(Clone, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct LoadOptions {
    /// Allowed relative deviation of each time step from the mean step (default 1e-3).
    pub uniform_tolerance: f64,
}

impl Default for LoadOptions {
    fn default() -> Self {
        LoadOptions { uniform_tolerance: 1e-3 }
    }
}

/// A validated measurement: uniformly sampled, all columns of equal length, SI units.
#[derive(Clone, Debug, PartialEq, serde::Serialize)]
pub struct Measurement {
    /// The file it came from (or a label for synthetic data); used in every message.
    pub file: String,
    /// Sample times (s).
    pub time: Vec<f64>,
    /// Mean sample interval (s).
    pub dt: f64,
    /// Voltage (V).
    pub voltage: Option<Vec<f64>>,
    /// Displacement or stroke (m).
    pub displacement: Option<Vec<f64>>,
    /// Force (N).
    pub force: Option<Vec<f64>>,
    /// Acceleration (m/s²).
    pub acceleration: Option<Vec<f64>>,
}

impl Measurement {
    /// Builds and validates a measurement from columns in SI units (the same checks as
    /// [`load`], with its default tolerance).
    pub fn new(file: impl Into<String>, time: Vec<f64>, columns: Vec<(Quantity, Vec<f64>)>) -> Result<Self> {
        let file = file.into();
        let mut m =
            Measurement { file, time, dt: 0.0, voltage: None, displacement: None, force: None, acceleration: None };
        for (q, v) in columns {
            let label = m.file.clone();
            let Some(slot) = m.slot(q) else {
                return Err(Error::input(label, "time", "time is given separately, not as a column"));
            };
            if slot.is_some() {
                return Err(Error::input(label, q.name(), "column given twice"));
            }
            *slot = Some(v);
        }
        m.validate(&LoadOptions::default())?;
        Ok(m)
    }

    /// A measurement of the given columns (none of them time), not yet validated.
    fn unchecked(file: String, time: Vec<f64>, columns: Vec<(Quantity, Vec<f64>)>) -> Self {
        let mut m =
            Measurement { file, time, dt: 0.0, voltage: None, displacement: None, force: None, acceleration: None };
        for (q, c) in columns {
            *m.slot(q).expect("time is not a column") = Some(c);
        }
        m
    }

    fn slot(&mut self, q: Quantity) -> Option<&mut Option<Vec<f64>>> {
        match q {
            Quantity::Time => None,
            Quantity::Voltage => Some(&mut self.voltage),
            Quantity::Displacement => Some(&mut self.displacement),
            Quantity::Force => Some(&mut self.force),
            Quantity::Acceleration => Some(&mut self.acceleration),
        }
    }

    /// The column of `q`, or an error naming the file and the missing column.
    pub fn column(&self, q: Quantity) -> Result<&[f64]> {
        let c = match q {
            Quantity::Time => Some(&self.time),
            Quantity::Voltage => self.voltage.as_ref(),
            Quantity::Displacement => self.displacement.as_ref(),
            Quantity::Force => self.force.as_ref(),
            Quantity::Acceleration => self.acceleration.as_ref(),
        };
        c.map(|v| v.as_slice()).ok_or_else(|| {
            Error::input(
                &self.file,
                q.name(),
                format!(
                    "column missing: this step needs a `{}` column (e.g. `{} ({})`)",
                    q.name(),
                    q.name(),
                    q.si_unit()
                ),
            )
        })
    }

    /// Number of samples.
    pub fn len(&self) -> usize {
        self.time.len()
    }

    /// True when there are no samples.
    pub fn is_empty(&self) -> bool {
        self.time.is_empty()
    }

    /// Quantities present (time first).
    pub fn quantities(&self) -> Vec<Quantity> {
        Quantity::ALL.into_iter().filter(|q| self.column(*q).is_ok()).collect()
    }

    fn validate(&mut self, opts: &LoadOptions) -> Result<()> {
        let n = self.time.len();
        for q in Quantity::ALL {
            if let Ok(c) = self.column(q) {
                if c.len() != n {
                    return Err(Error::input(
                        &self.file,
                        q.name(),
                        format!("has {} samples but time has {n}; all columns must have equal length", c.len()),
                    ));
                }
                if let Some(i) = c.iter().position(|v| !v.is_finite()) {
                    return Err(Error::input(
                        &self.file,
                        q.name(),
                        format!("row {}: value {} is not finite (NaN or infinity)", i + 1, c[i]),
                    ));
                }
            }
        }
        crate::signal::csv::check_time_axis(&self.file, "time", &self.time, false)?;
        let dt = (self.time[n - 1] - self.time[0]) / (n - 1) as f64;
        for i in 1..n {
            let step = self.time[i] - self.time[i - 1];
            if (step - dt).abs() > opts.uniform_tolerance * dt {
                return Err(Error::input(
                    &self.file,
                    "time",
                    format!(
                        "row {}: step {step:e} s differs from the mean step {dt:e} s by more than {} relative; \
                         the sampling must be uniform",
                        i + 1,
                        opts.uniform_tolerance
                    ),
                ));
            }
        }
        self.dt = dt;
        Ok(())
    }
}

/// Loads a measurement file, requiring the quantities in `required` (time is always
/// required) and loading every other recognised column present.
pub fn load(path: &Path, required: &[Quantity], opts: &LoadOptions) -> Result<Measurement> {
    let file = path.display().to_string();
    let text = crate::input_file::read_text(path)?;
    parse(&text, &file, required, opts)
}

/// [`load`] on text already in memory; `file` names it in messages.
pub fn parse(text: &str, file: &str, required: &[Quantity], opts: &LoadOptions) -> Result<Measurement> {
    if opts.uniform_tolerance.is_nan() || opts.uniform_tolerance <= 0.0 {
        return Err(Error::input(file, "uniform_tolerance", "must be positive"));
    }
    let header = header_fields(text);
    // Find each quantity's header field and unit factor.
    let mut found: Vec<(Quantity, String, f64)> = Vec::new();
    for q in Quantity::ALL {
        let mut hits = Vec::new();
        for h in &header {
            let (name, unit) = split_header(h);
            if q.aliases().contains(&name.as_str()) {
                hits.push((h.clone(), unit));
            }
        }
        match hits.len() {
            0 => {
                if q == Quantity::Time || required.contains(&q) {
                    return Err(Error::input(
                        file,
                        q.name(),
                        format!(
                            "column missing: no header names {} (accepted: {}, optionally with a unit like `{} ({})`); \
                             the header has: {}",
                            q.name(),
                            q.aliases().join(", "),
                            q.name(),
                            q.si_unit(),
                            header.join(", ")
                        ),
                    ));
                }
            }
            1 => {
                let (h, unit) = hits.pop().unwrap();
                let factor = match unit {
                    None => 1.0,
                    Some(u) => q.unit_factor(&u).ok_or_else(|| {
                        Error::input(
                            file,
                            &h,
                            format!("unknown unit `{u}` for {}; accepted: {}", q.name(), q.accepted_units()),
                        )
                    })?,
                };
                found.push((q, h, factor));
            }
            _ => {
                let names: Vec<String> = hits.into_iter().map(|(h, _)| h).collect();
                return Err(Error::input(
                    file,
                    q.name(),
                    format!("several columns name this quantity ({}); keep one", names.join(", ")),
                ));
            }
        }
    }
    let names: Vec<&str> = found.iter().map(|(_, h, _)| h.as_str()).collect();
    let cols = crate::signal::csv::parse_columns(text, file, &names)?;
    let mut time = Vec::new();
    let mut columns = Vec::new();
    for ((q, _, factor), mut c) in found.into_iter().zip(cols) {
        if factor != 1.0 {
            c.iter_mut().for_each(|v| *v *= factor);
        }
        if q == Quantity::Time {
            time = c;
        } else {
            columns.push((q, c));
        }
    }
    let mut m = Measurement::unchecked(file.to_string(), time, columns);
    m.validate(opts)?;
    Ok(m)
}

/// Writes a measurement as CSV with SI unit headers (`time [s],voltage [V],...`), values in
/// shortest round-trip form, so [`load`] gives back the same numbers.
pub fn write(path: &Path, m: &Measurement) -> Result<()> {
    std::fs::write(path, to_csv(m)).map_err(|e| Error::io(path, e))
}

/// The CSV text [`write()`] puts in a file.
pub fn to_csv(m: &Measurement) -> String {
    to_csv_with(m, &["beamflow measurement".to_string()], None)
}

/// CSV text with `comments` as `# ` lines above the header. `digits`: significant digits of
/// the data columns (None: shortest round-trip form). Time is always written with enough
/// digits (at least 12 significant) to keep its sampling uniform on reading.
pub fn to_csv_with(m: &Measurement, comments: &[String], digits: Option<usize>) -> String {
    let qs = m.quantities();
    let cols: Vec<&[f64]> = qs.iter().map(|q| m.column(*q).unwrap()).collect();
    let mut s = String::with_capacity(24 * qs.len() * (m.len() + 1));
    for c in comments {
        for line in c.lines() {
            s.push_str("# ");
            s.push_str(line);
            s.push('\n');
        }
    }
    let head: Vec<String> = qs.iter().map(|q| format!("{} [{}]", q.name(), q.si_unit())).collect();
    s.push_str(&head.join(","));
    s.push('\n');
    let fmt = |v: f64, time: bool| -> String {
        match digits {
            None => format!("{v:e}"),
            Some(d) => {
                let d = if time { d.max(12) } else { d.max(1) };
                let txt = format!("{v:.prec$e}", prec = d - 1);
                // Shortest form of the rounded value ("1.5e-3" rather than "1.500000e-3").
                txt.parse::<f64>().map(|r| format!("{r:e}")).unwrap_or(txt)
            }
        }
    };
    for i in 0..m.len() {
        for (k, c) in cols.iter().enumerate() {
            if k > 0 {
                s.push(',');
            }
            s.push_str(&fmt(c[i], qs[k] == Quantity::Time));
        }
        s.push('\n');
    }
    s
}

// ---------------------------------------------------------------------------------------
// Measurements from beamflow results (HDF5)
// ---------------------------------------------------------------------------------------

/// Splits `FILE.h5[:SELECTOR]` (also `.hdf5`): Some((file, selector)) for an HDF5 source.
pub fn split_hdf5_source(source: &str) -> Option<(&str, Option<&str>)> {
    for ext in [".h5", ".hdf5"] {
        if source.ends_with(ext) {
            return Some((source, None));
        }
        if let Some(i) = source.find(&format!("{ext}:")) {
            let end = i + ext.len();
            return Some((&source[..end], Some(&source[end + 1..])));
        }
    }
    None
}

/// Loads a measurement from a CSV file, or from a beamflow results file when the path ends in
/// `.h5`/`.hdf5`, optionally followed by `:SELECTOR` (see [`load_hdf5`]).
pub fn load_source(source: &Path, required: &[Quantity], opts: &LoadOptions) -> Result<Measurement> {
    let text = source.to_string_lossy();
    match split_hdf5_source(&text) {
        Some((file, sel)) => load_hdf5(Path::new(file), sel, required, opts),
        None => load(source, required, opts),
    }
}

/// Reads the drive record of one actuator from a beamflow results file: time from
/// `/<analysis>/t`, voltage, stroke (as `displacement`) and the active force `f_p` = k_p·stroke
/// (as `force`: the blocked force) from `/<analysis>/drives/<name>/`.
///
/// `selector`: None takes the first analysis group with drive records and its first
/// actuator; `NAME` the actuator `NAME` in the first analysis group that has it;
/// `GROUP/NAME` (or `GROUP/drives/NAME`) that analysis group, e.g.
/// `analysis_0_transient/inertial`.
pub fn load_hdf5(
    path: &Path,
    selector: Option<&str>,
    required: &[Quantity],
    opts: &LoadOptions,
) -> Result<Measurement> {
    let file = path.display().to_string();
    let r = crate::io::hdf5::ResultsReader::open(path)?;
    let groups: Vec<String> = r
        .list_groups("/")?
        .into_iter()
        .filter(|g| g.starts_with("analysis_") && r.exists(&format!("/{g}/drives")) && r.exists(&format!("/{g}/t")))
        .collect();
    if groups.is_empty() {
        return Err(Error::input(
            &file,
            "drives",
            "no analysis group with drive records (`/analysis_*/drives`); run a transient or steady_state analysis",
        ));
    }
    let (want_group, want_name) = match selector.map(|s| s.trim_matches('/')) {
        None | Some("") => (None, None),
        Some(s) => match s.split_once('/') {
            Some((g, rest)) => (Some(g.to_string()), Some(rest.rsplit('/').next().unwrap_or(rest).to_string())),
            None => (None, Some(s.to_string())),
        },
    };
    let candidates: Vec<&String> = groups.iter().filter(|g| want_group.as_ref().is_none_or(|w| *g == w)).collect();
    let mut found = None;
    for g in &candidates {
        let drives = r.list_groups(&format!("/{g}/drives"))?;
        let name = match &want_name {
            Some(n) => drives.iter().find(|d| *d == n).cloned(),
            None => {
                // The model's actuator order if recorded, else alphabetical.
                let order: Vec<String> = r
                    .read_str_list("/model/actuators")
                    .unwrap_or_default()
                    .into_iter()
                    .map(|s| s.split(" (").next().unwrap_or_default().to_string())
                    .collect();
                order.iter().find(|o| drives.contains(o)).cloned().or_else(|| drives.first().cloned())
            }
        };
        if let Some(n) = name {
            found = Some(((*g).clone(), n));
            break;
        }
    }
    let Some((group, name)) = found else {
        return Err(Error::input(
            &file,
            "drives",
            format!(
                "no drive record matches `{}`; analysis groups with drives: {}",
                selector.unwrap_or(""),
                groups.join(", ")
            ),
        ));
    };
    let base = format!("/{group}/drives/{name}");
    let label = format!("{file}:{base}");
    let (time, _) = r.read_f64(&format!("/{group}/t"))?;
    let mut cols = Vec::new();
    for (q, ds) in [(Quantity::Voltage, "voltage"), (Quantity::Displacement, "stroke"), (Quantity::Force, "f_p")] {
        let p = format!("{base}/{ds}");
        if r.exists(&p) {
            cols.push((q, r.read_f64(&p)?.0));
        }
    }
    let mut m =
        Measurement { file: label, time, dt: 0.0, voltage: None, displacement: None, force: None, acceleration: None };
    for (q, c) in cols {
        *m.slot(q).unwrap() = Some(c);
    }
    for q in required {
        m.column(*q)?;
    }
    if m.time.len() < 2 {
        return Err(Error::input(&m.file, "time", "fewer than 2 samples"));
    }
    m.validate(opts)?;
    Ok(m)
}

/// Reads what was recorded at one point of a beamflow results file, as a measurement: time
/// from `/<analysis>/t`; at a link `<actuator>_<link>` the interface force (as `force`) and
/// the base acceleration at its foot (as `acceleration`) from `links/<point>/`, at a sensor
/// its acceleration from `sensors/<point>/a`. `group`: the analysis group (e.g.
/// `analysis_1_transient`); None takes the first one that recorded the point.
pub fn load_point_hdf5(path: &Path, group: Option<&str>, point: &str, opts: &LoadOptions) -> Result<Measurement> {
    let file = path.display().to_string();
    let r = crate::io::hdf5::ResultsReader::open(path)?;
    let groups: Vec<String> = r
        .list_groups("/")?
        .into_iter()
        .filter(|g| g.starts_with("analysis_") && group.is_none_or(|w| w.trim_matches('/') == g))
        .collect();
    let mut found = None;
    for g in &groups {
        for (dir, force, accel) in [("links", Some("interface"), "base_acceleration"), ("sensors", None, "a")] {
            let base = format!("/{g}/{dir}/{point}");
            if r.exists(&format!("/{g}/t")) && r.exists(&format!("{base}/{accel}")) {
                found = Some((g.clone(), base, force, accel));
                break;
            }
        }
        if found.is_some() {
            break;
        }
    }
    let Some((g, base, force, accel)) = found else {
        return Err(Error::input(
            &file,
            point,
            format!(
                "no analysis group{} recorded a link or sensor named `{point}` (`/analysis_*/links/{point}` or                  `/analysis_*/sensors/{point}` with a time axis `t`)",
                group.map(|g| format!(" `{g}`")).unwrap_or_default()
            ),
        ));
    };
    let mut columns = vec![(Quantity::Acceleration, r.read_f64(&format!("{base}/{accel}"))?.0)];
    if let Some(f) = force {
        columns.push((Quantity::Force, r.read_f64(&format!("{base}/{f}"))?.0));
    }
    let time = r.read_f64(&format!("/{g}/t"))?.0;
    let mut m = Measurement::unchecked(format!("{file}:{base}"), time, columns);
    if m.time.len() < 2 {
        return Err(Error::input(&m.file, "time", "fewer than 2 samples"));
    }
    m.validate(opts)?;
    Ok(m)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn err(text: &str, file: &str, req: &[Quantity]) -> String {
        parse(text, file, req, &LoadOptions::default()).unwrap_err().to_string()
    }

    #[test]
    fn reads_units_aliases_and_both_conventions() {
        let text = "# test\nTime (ms), Voltage [V], stroke (um), accel [g], other\n0, 1, 2, 1, 9\n0.5, 2, 3, 2, 9\n1.0, 3, 4, 0.5, 9\n";
        let m = parse(text, "u.csv", &[Quantity::Voltage, Quantity::Displacement], &LoadOptions::default()).unwrap();
        assert_eq!(m.time, vec![0.0, 0.5e-3, 1.0e-3]);
        assert!((m.dt - 0.5e-3).abs() < 1e-15);
        assert_eq!(m.voltage.as_deref(), Some(&[1.0, 2.0, 3.0][..]));
        let x = m.displacement.as_ref().unwrap();
        assert!((x[0] - 2e-6).abs() < 1e-20 && (x[2] - 4e-6).abs() < 1e-20);
        assert!((m.acceleration.as_ref().unwrap()[1] - 2.0 * 9.80665).abs() < 1e-12);
        assert!(m.force.is_none());
        let e = m.column(Quantity::Force).unwrap_err().to_string();
        assert!(e.contains("u.csv") && e.contains("force") && e.contains("missing"), "{e}");
        // Bare SI names.
        let m = parse("t,v,x\n0,1,2\n1,1,2\n", "b.csv", &[], &LoadOptions::default()).unwrap();
        assert_eq!(m.quantities(), vec![Quantity::Time, Quantity::Voltage, Quantity::Displacement]);
    }

    #[test]
    fn write_then_load_round_trips_exactly() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("synthetic.csv");
        let t: Vec<f64> = (0..50).map(|i| i as f64 / 3000.0).collect();
        let v: Vec<f64> = t.iter().map(|t| 48.0 * (2.0 * std::f64::consts::PI * 30.0 * t).sin()).collect();
        let x: Vec<f64> = v.iter().map(|v| 1.3e-7 * v + 1e-9 / 3.0).collect();
        let m = Measurement::new("synthetic", t, vec![(Quantity::Voltage, v), (Quantity::Displacement, x)]).unwrap();
        write(&path, &m).unwrap();
        // The header convention of every CSV file beamflow writes.
        let text = std::fs::read_to_string(&path).unwrap();
        let header = text.lines().find(|l| !l.starts_with('#')).unwrap();
        assert_eq!(header, "time [s],voltage [V],displacement [m]");
        let back = load(&path, &[Quantity::Voltage, Quantity::Displacement], &LoadOptions::default()).unwrap();
        assert_eq!(back.time, m.time);
        assert_eq!(back.voltage, m.voltage);
        assert_eq!(back.displacement, m.displacement);
        assert_eq!(back.file, path.display().to_string());
    }

    #[test]
    fn bad_files_name_the_file_and_the_problem() {
        let r = [Quantity::Voltage, Quantity::Displacement];
        // Missing column.
        let e = err("time (s),voltage (V)\n0,1\n1,2\n", "missing.csv", &r);
        assert!(e.contains("missing.csv") && e.contains("displacement") && e.contains("column missing"), "{e}");
        let e = err("voltage (V),displacement (m)\n0,1\n1,2\n", "notime.csv", &r);
        assert!(e.contains("notime.csv") && e.contains("time") && e.contains("column missing"), "{e}");
        // Unequal lengths (a short row).
        let e = err("time (s),voltage (V),displacement (m)\n0,1,2\n1,2\n2,3,4\n", "short.csv", &r);
        assert!(e.contains("short.csv") && e.contains("row 2") && e.contains("same length"), "{e}");
        // NaN.
        let e = err("time (s),voltage (V),displacement (m)\n0,1,2\n1,NaN,3\n", "nan.csv", &r);
        assert!(e.contains("nan.csv") && e.contains("voltage") && e.contains("not finite"), "{e}");
        // Non-increasing time.
        let e = err("time (s),voltage (V),displacement (m)\n0,1,2\n1,1,2\n1,1,2\n", "dup.csv", &r);
        assert!(e.contains("dup.csv") && e.contains("time") && e.contains("strictly increasing"), "{e}");
        // Non-uniform time.
        let e = err("time (s),voltage (V),displacement (m)\n0,1,2\n1,1,2\n2,1,2\n3.5,1,2\n", "gap.csv", &r);
        assert!(e.contains("gap.csv") && e.contains("time") && e.contains("uniform"), "{e}");
        // Unknown unit, duplicated quantity.
        let e = err("time (s),voltage (V),displacement (furlong)\n0,1,2\n1,1,2\n", "unit.csv", &r);
        assert!(e.contains("unit.csv") && e.contains("furlong"), "{e}");
        let e = err("time (s),voltage (V),x (m),displacement (m)\n0,1,2,3\n1,1,2,3\n", "two.csv", &r);
        assert!(e.contains("two.csv") && e.contains("several columns"), "{e}");
        // Columns of unequal length built in code.
        let e = Measurement::new("mem", vec![0.0, 1.0, 2.0], vec![(Quantity::Voltage, vec![1.0, 2.0])])
            .unwrap_err()
            .to_string();
        assert!(e.contains("mem") && e.contains("voltage") && e.contains("equal length"), "{e}");
        let e = Measurement::new("mem", vec![0.0, 1.0], vec![(Quantity::Force, vec![1.0, f64::NAN])])
            .unwrap_err()
            .to_string();
        assert!(e.contains("mem") && e.contains("force") && e.contains("not finite"), "{e}");
        // A file that does not exist: an I/O error naming it.
        let e = load(Path::new("/nonexistent/m.csv"), &r, &LoadOptions::default()).unwrap_err().to_string();
        assert!(e.contains("/nonexistent/m.csv"), "{e}");
    }

    #[test]
    fn loose_time_stamps_pass_within_tolerance() {
        // Time printed with 6 decimals at 25.6 kHz: steps jitter by ~2.6 %.
        let mut text = String::from("time (s),force (N)\n");
        for i in 0..100 {
            text.push_str(&format!("{:.6},{}\n", i as f64 / 25600.0, i));
        }
        assert!(parse(&text, "r.csv", &[], &LoadOptions::default()).is_err());
        parse(&text, "r.csv", &[], &LoadOptions { uniform_tolerance: 0.05 }).unwrap();
    }
}
