//! Drive signals as a case file writes them, and how they become the signals physics
//! evaluates ([`VoltageInput`]): the one place that reads a signal's CSV file.

use std::path::{Path, PathBuf};

use serde::{Deserialize, Serialize};

use crate::error::{Error, Result};
use crate::signal::csv::{check_time_axis, read_columns};
use crate::signal::voltage::{ChirpLaw, SineComponent, VoltageInput};

fn default_time_column() -> String {
    "time".to_string()
}
fn default_voltage_column() -> String {
    "voltage".to_string()
}

/// A drive signal (a stack's voltage in V, a point load's force in N) as a case file
/// writes it: a TOML table with a `kind` key, unknown keys rejected.
///
/// ```toml
/// voltage = { kind = "sine", amplitude = 48.0, frequency = 30.0 }            # offset = 0, phase = 0
/// voltage = { kind = "sines", offset = 10.0, components = [
///     { amplitude = 12.0, frequency = 60.0 }, { amplitude = 3.0, frequency = 180.0, phase = 0.5 } ] }
/// voltage = { kind = "chirp", amplitude = 10.0, f_start = 5.0, f_end = 500.0, duration = 2.0, sweep = "log" }
/// voltage = { kind = "step", time = 0.01, from = 0.0, to = 50.0, rise_time = 1e-3 }
/// voltage = { kind = "series", file = "drive.csv", time_column = "t", voltage_column = "u" }
/// ```
///
/// The analytic kinds mean what the [`VoltageInput`] variants of the same name compute.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(tag = "kind", rename_all = "snake_case", deny_unknown_fields)]
pub enum SignalSpec {
    /// `V = offset + amplitude·sin(2π·frequency·t + phase)`.
    Sine {
        amplitude: f64,
        frequency: f64,
        #[serde(default)]
        offset: f64,
        #[serde(default)]
        phase: f64,
    },
    /// `V = offset + Σ amplitude_k·sin(2π·frequency_k·t + phase_k)`.
    Sines {
        #[serde(default)]
        offset: f64,
        components: Vec<SineComponent>,
    },
    /// `V = offset + amplitude·sin φ(t)`, with the instantaneous frequency `φ'/2π` sweeping
    /// from `f_start` at t = 0 to `f_end` at t = `duration` (linearly or geometrically).
    ///
    /// The phase is continuous everywhere: before t = 0 the frequency is `f_start`, after
    /// `duration` the signal **continues at `f_end`** (it does not stop or restart).
    Chirp {
        amplitude: f64,
        f_start: f64,
        f_end: f64,
        duration: f64,
        #[serde(default)]
        sweep: ChirpLaw,
        #[serde(default)]
        offset: f64,
    },
    /// `from` before `time`, `to` after; with `rise_time > 0` a linear ramp over
    /// `[time, time + rise_time]`. With `rise_time = 0` the jump is at `time` and
    /// `V(time) = to` (right-continuous).
    Step {
        time: f64,
        from: f64,
        to: f64,
        #[serde(default)]
        rise_time: f64,
    },
    /// Tabulated values from a CSV file with a header row (`file` relative to the case
    /// file's directory), read by [`SignalSpec::build`].
    Series {
        file: PathBuf,
        #[serde(default = "default_time_column")]
        time_column: String,
        #[serde(default = "default_voltage_column")]
        voltage_column: String,
    },
}

impl SignalSpec {
    /// Checks the parameters: finite numbers, positive frequencies and duration,
    /// `rise_time ≥ 0`, at least one sine component, non-empty file and column names.
    /// `field` is the dotted path of this table in the case file (e.g. `actuator[0].voltage`);
    /// messages name `file`, `field.<parameter>` and the reason.
    pub fn validate(&self, file: &str, field: &str) -> Result<()> {
        let f = |name: &str| format!("{field}.{name}");
        match self {
            SignalSpec::Sine { amplitude, frequency, offset, phase } => {
                check_finite(file, f("amplitude"), *amplitude)?;
                check_positive(file, f("frequency"), *frequency, "Hz")?;
                check_finite(file, f("offset"), *offset)?;
                check_finite(file, f("phase"), *phase)?;
            }
            SignalSpec::Sines { offset, components } => {
                check_finite(file, f("offset"), *offset)?;
                if components.is_empty() {
                    return Err(Error::input(
                        file,
                        f("components"),
                        "needs at least one component { amplitude, frequency, phase }",
                    ));
                }
                for (i, c) in components.iter().enumerate() {
                    let g = |name: &str| format!("{field}.components[{i}].{name}");
                    check_finite(file, g("amplitude"), c.amplitude)?;
                    check_positive(file, g("frequency"), c.frequency, "Hz")?;
                    check_finite(file, g("phase"), c.phase)?;
                }
            }
            SignalSpec::Chirp { amplitude, f_start, f_end, duration, offset, .. } => {
                check_finite(file, f("amplitude"), *amplitude)?;
                check_positive(file, f("f_start"), *f_start, "Hz")?;
                check_positive(file, f("f_end"), *f_end, "Hz")?;
                check_positive(file, f("duration"), *duration, "s")?;
                check_finite(file, f("offset"), *offset)?;
            }
            SignalSpec::Step { time, from, to, rise_time } => {
                check_finite(file, f("time"), *time)?;
                check_finite(file, f("from"), *from)?;
                check_finite(file, f("to"), *to)?;
                if !(rise_time.is_finite() && *rise_time >= 0.0) {
                    return Err(Error::input(
                        file,
                        f("rise_time"),
                        format!("must be a finite number ≥ 0 s (0 = jump), got {rise_time}"),
                    ));
                }
            }
            SignalSpec::Series { file: csv, time_column, voltage_column } => {
                if csv.as_os_str().is_empty() {
                    return Err(Error::input(file, f("file"), "must name a CSV file"));
                }
                if time_column.trim().is_empty() {
                    return Err(Error::input(file, f("time_column"), "must name a column"));
                }
                if voltage_column.trim().is_empty() {
                    return Err(Error::input(file, f("voltage_column"), "must name a column"));
                }
            }
        }
        Ok(())
    }

    /// The signal as physics sees it: the analytic kinds as they are, a `series` read from
    /// its CSV file (path relative to `case_dir`, the case file's directory). `file`/`field`
    /// name the case file and this table for a file that cannot be read; errors inside the
    /// CSV name the CSV file, the column and the row. The time column must be strictly
    /// increasing (≥ 2 rows).
    pub fn build(&self, case_dir: &Path, file: &str, field: &str) -> Result<VoltageInput> {
        Ok(match self.clone() {
            SignalSpec::Sine { amplitude, frequency, offset, phase } => {
                VoltageInput::Sine { amplitude, frequency, offset, phase }
            }
            SignalSpec::Sines { offset, components } => VoltageInput::Sines { offset, components },
            SignalSpec::Chirp { amplitude, f_start, f_end, duration, sweep, offset } => {
                VoltageInput::Chirp { amplitude, f_start, f_end, duration, sweep, offset }
            }
            SignalSpec::Step { time, from, to, rise_time } => VoltageInput::Step { time, from, to, rise_time },
            SignalSpec::Series { file: csv, time_column, voltage_column } => {
                if csv.as_os_str().is_empty() {
                    return Err(Error::input(file, format!("{field}.file"), "must name a CSV file"));
                }
                let path = case_dir.join(&csv);
                let mut cols =
                    read_columns(&path, &[time_column.as_str(), voltage_column.as_str()]).map_err(|e| match e {
                        Error::Io { path, source } => Error::input(
                            file,
                            format!("{field}.file"),
                            format!("cannot read the series `{path}`: {source}"),
                        ),
                        other => other,
                    })?;
                let v = cols.pop().unwrap_or_default();
                let t = cols.pop().unwrap_or_default();
                let label = path.display().to_string();
                check_time_axis(&label, &time_column, &t, false)?;
                // A load's series is a force, an actuator's a voltage.
                let unit = if field.ends_with(".force") { "N" } else { "V" };
                super::ranges::series_values(&label, &voltage_column, &v, unit)?;
                VoltageInput::from_samples(&label, t, v)?
            }
        })
    }
}

fn check_finite(file: &str, field: String, x: f64) -> Result<()> {
    if x.is_finite() {
        Ok(())
    } else {
        Err(Error::input(file, field, format!("must be a finite number, got {x}")))
    }
}

fn check_positive(file: &str, field: String, x: f64, unit: &str) -> Result<()> {
    if x.is_finite() && x > 0.0 {
        Ok(())
    } else {
        Err(Error::input(file, field, format!("must be a finite number > 0 {unit}, got {x}")))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn temp_dir(tag: &str) -> PathBuf {
        let d = std::env::temp_dir().join(format!("beamflow-signal-{tag}-{}", std::process::id()));
        std::fs::create_dir_all(&d).unwrap();
        d
    }

    fn parse(s: &str) -> std::result::Result<SignalSpec, toml::de::Error> {
        toml::from_str(s)
    }

    #[test]
    fn parses_all_kinds_from_toml() {
        let v = parse("kind = \"sine\"\namplitude = 48\nfrequency = 30\n").unwrap();
        assert_eq!(v, SignalSpec::Sine { amplitude: 48.0, frequency: 30.0, offset: 0.0, phase: 0.0 });
        let v = parse(
            "kind = \"sines\"\noffset = 2\ncomponents = [{ amplitude = 1, frequency = 60 }, { amplitude = 0.5, frequency = 180, phase = 1 }]\n",
        )
        .unwrap();
        assert_eq!(v.build(Path::new("."), "c", "v").unwrap().period(), Some(1.0 / 60.0));
        let v =
            parse("kind = \"chirp\"\namplitude = 1\nf_start = 1\nf_end = 10\nduration = 2\nsweep = \"log\"\n").unwrap();
        assert!(matches!(v, SignalSpec::Chirp { sweep: ChirpLaw::Log, .. }));
        let v = parse("kind = \"step\"\ntime = 0.1\nfrom = 0\nto = 10\n").unwrap();
        assert!(matches!(v, SignalSpec::Step { rise_time, .. } if rise_time == 0.0));
        let v = parse("kind = \"series\"\nfile = \"v.csv\"\n").unwrap();
        match v {
            SignalSpec::Series { time_column, voltage_column, .. } => {
                assert_eq!((time_column.as_str(), voltage_column.as_str()), ("time", "voltage"));
            }
            _ => panic!(),
        }
    }

    #[test]
    fn rejects_unknown_fields_and_kinds() {
        let e = parse("kind = \"sine\"\namplitude = 48\nfrequency = 30\nfreq = 3\n").unwrap_err();
        assert!(e.to_string().contains("unknown field `freq`"), "{e}");
        let e = parse("kind = \"sines\"\ncomponents = [{ amplitude = 1, frequency = 60, offset = 1 }]\n").unwrap_err();
        assert!(e.to_string().contains("unknown field `offset`"), "{e}");
        let e = parse("kind = \"step\"\ntime = 0\nfrom = 0\nto = 1\nrise = 1\n").unwrap_err();
        assert!(e.to_string().contains("unknown field `rise`"), "{e}");
        let e = parse("kind = \"series\"\nfile = \"a.csv\"\nsamples = 3\n").unwrap_err();
        assert!(e.to_string().contains("unknown field `samples`"), "{e}");
        let e = parse("kind = \"square\"\namplitude = 1\n").unwrap_err();
        assert!(e.to_string().contains("unknown variant"), "{e}");
        let e = parse("kind = \"chirp\"\namplitude = 1\nf_start = 1\nf_end = 10\nduration = 2\nsweep = \"cubic\"\n")
            .unwrap_err();
        assert!(e.to_string().contains("cubic"), "{e}");
    }

    #[test]
    fn validation_names_the_field() {
        let bad = [
            (SignalSpec::Sine { amplitude: 1.0, frequency: 0.0, offset: 0.0, phase: 0.0 }, "v.frequency"),
            (SignalSpec::Sine { amplitude: f64::NAN, frequency: 1.0, offset: 0.0, phase: 0.0 }, "v.amplitude"),
            (SignalSpec::Sines { offset: 0.0, components: vec![] }, "v.components"),
            (
                SignalSpec::Sines {
                    offset: 0.0,
                    components: vec![
                        SineComponent { amplitude: 1.0, frequency: 1.0, phase: 0.0 },
                        SineComponent { amplitude: 1.0, frequency: -1.0, phase: 0.0 },
                    ],
                },
                "v.components[1].frequency",
            ),
            (
                SignalSpec::Chirp {
                    amplitude: 1.0,
                    f_start: 1.0,
                    f_end: 2.0,
                    duration: 0.0,
                    sweep: ChirpLaw::Linear,
                    offset: 0.0,
                },
                "v.duration",
            ),
            (
                SignalSpec::Chirp {
                    amplitude: 1.0,
                    f_start: 1.0,
                    f_end: f64::INFINITY,
                    duration: 1.0,
                    sweep: ChirpLaw::Log,
                    offset: 0.0,
                },
                "v.f_end",
            ),
            (SignalSpec::Step { time: 0.0, from: 0.0, to: 1.0, rise_time: -1e-3 }, "v.rise_time"),
            (
                SignalSpec::Series { file: PathBuf::new(), time_column: "t".into(), voltage_column: "v".into() },
                "v.file",
            ),
        ];
        for (input, field) in bad {
            let e = input.validate("case.toml", "v").unwrap_err().to_string();
            assert!(e.starts_with("case.toml: field `") && e.contains(&format!("`{field}`")), "{e}");
        }
        for text in [
            "kind = \"sine\"\namplitude = 48\nfrequency = 30\noffset = 5\nphase = 0.3\n",
            "kind = \"sines\"\ncomponents = [{ amplitude = 10, frequency = 60 }, { amplitude = 4, frequency = 180, phase = 1 }]\n",
            "kind = \"chirp\"\namplitude = 20\nf_start = 80\nf_end = 5\nduration = 0.5\nsweep = \"log\"\noffset = -3\n",
            "kind = \"step\"\ntime = 0.1\nfrom = 1\nto = 5\nrise_time = 0.05\n",
        ] {
            parse(text).unwrap().validate("case.toml", "v").unwrap();
        }
    }

    #[test]
    fn series_load_and_errors() {
        let dir = temp_dir("series");
        let write = |name: &str, text: &str| std::fs::write(dir.join(name), text).unwrap();
        write("ok.csv", "time,u,voltage\n0,9,0\n0.5,9,2\n1.0,9,-2\n");
        write("dup.csv", "time,voltage\n0,0\n0.5,1\n0.5,2\n");
        write("nan.csv", "time,voltage\n0,0\n0.5,nan\n");
        write("cols.csv", "t,voltage\n0,0\n0.5,1\n");
        let series = |f: &str, tc: &str| SignalSpec::Series {
            file: f.into(),
            time_column: tc.into(),
            voltage_column: "voltage".into(),
        };
        let ok = series("ok.csv", "time").build(&dir, "case.toml", "actuator[0].voltage").unwrap();
        assert_eq!(ok.value(0.25), 1.0);
        assert_eq!(ok.value(0.75), 0.0);
        assert_eq!(ok.turning_points(0.0, 1.0), vec![0.5]);

        let err =
            |f: &str, tc: &str| series(f, tc).build(&dir, "case.toml", "actuator[0].voltage").unwrap_err().to_string();
        let e = err("dup.csv", "time");
        assert!(
            e.contains("dup.csv") && e.contains("`time`") && e.contains("row 3") && e.contains("strictly increasing"),
            "{e}"
        );
        let e = err("nan.csv", "time");
        assert!(
            e.contains("nan.csv") && e.contains("`voltage`") && e.contains("row 2") && e.contains("not finite"),
            "{e}"
        );
        let e = err("cols.csv", "time");
        assert!(e.contains("cols.csv") && e.contains("`time`") && e.contains("not found"), "{e}");
        let e = err("missing.csv", "time");
        assert!(e.contains("case.toml") && e.contains("actuator[0].voltage.file") && e.contains("missing.csv"), "{e}");
        std::fs::remove_dir_all(&dir).ok();
    }
}
