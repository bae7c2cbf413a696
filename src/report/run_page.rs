//! `report.html` of a case run: the case, headline numbers with units, warnings, the
//! accuracy each result states, tables of point powers, harmonics, modes and energy
//! balance, and every figure, in one self-contained page ([`super::html`]).
//!
//! Headline numbers and accuracy estimates are read from the run's JSON summary
//! ([`crate::io::summary`]), so the page shows exactly what `<case>.json` holds; the
//! tables per harmonic and per mode come from the results themselves.

use std::path::PathBuf;

use serde_json::Value;

use super::figures::analysis_tags;
use super::html::{cell, details, escape, figure, num, table, Page};
use crate::analysis::case_run::{AnalysisResult, CaseRun};
use crate::analysis::series::LinkSpectrum;
use crate::case::LoadedCase;
use crate::error::Result;

/// The report's file name in a run's output folder.
pub const FILE: &str = "report.html";

/// A start-up transient left above this (relative) is worth a warning even when the run
/// met its own tolerance: the mean powers are then good to about this much only.
const SETTLING_WARN: f64 = 1e-3;
/// Harmonics left out carrying more than this share of the largest point power.
const TRUNCATION_WARN: f64 = 1e-4;
/// What a plate's or an imported model's `mesh_roundoff` is.
const ROUNDOFF_ESTIMATE: &str =
    "relative, an estimate, not a bound: it follows the round-off law measured on beams (docs/structures.md)";
/// Why a harmonic analysis without forces states no balance.
const UNFORCED: &str = "no force applied (transfer functions only): nothing to balance";
/// An energy balance worse than this points to a problem with the model or the run.
const BALANCE_WARN: f64 = 1e-6;
/// A modal reduction whose point powers are off by more than this.
const REDUCTION_WARN: f64 = 1e-3;
/// A plate grid's error estimate above which a reader is warned: a percent.
const MESH_WARN: f64 = 1e-2;

/// Everything the page is made from.
pub struct RunReport<'a> {
    pub lc: &'a LoadedCase,
    pub run: &'a CaseRun,
    /// The run's JSON summary, as written to `<case>.json`.
    pub summary: &'a Value,
    /// The files written beside the report (figures among them, as `.svg`).
    pub files: &'a [PathBuf],
}

fn f(v: &Value) -> f64 {
    v.as_f64().unwrap_or(f64::NAN)
}

impl RunReport<'_> {
    /// The page as HTML.
    pub fn html(&self) -> Result<String> {
        let mut p = Page::new();
        let warnings = self.warnings();
        if !warnings.is_empty() {
            p.section("warnings", "Warnings");
            let items: String = warnings.iter().map(|w| format!("<li>{}</li>", escape(w))).collect();
            p.push(&format!("<div class=\"warn\"><ul>{items}</ul></div>\n"));
        }
        p.section("headline", "Headline numbers");
        p.push(&self.headline());
        p.section("accuracy", "Accuracy");
        p.para(
            "What each result states about its own accuracy: how far a transient had settled, what the \
             harmonics left out carry, the solves' round-off, how well energy balances and, on a plate, \
             how far its grid's point powers are from a coarser grid's.",
        );
        p.push(&self.accuracy());
        if let Some(svg) = self.svg_named(&format!("{}_layout", self.stem())) {
            p.section("layout", "Layout");
            p.push(&figure(svg)?);
        }
        let tags = analysis_tags(self.run);
        for (i, (r, tag)) in self.run.results.iter().zip(&tags).enumerate() {
            p.section(&format!("analysis-{tag}"), &format!("Analysis {}: {}", i + 1, tag.replace('_', " ")));
            p.push(&self.analysis_tables(r));
            p.push(&self.measurements(i));
            let stem = self.stem();
            let prefix = format!("{stem}_{tag}");
            for svg in self.files.iter().filter(|f| f.extension().is_some_and(|e| e == "svg")) {
                let name = svg.file_stem().map(|s| s.to_string_lossy().into_owned()).unwrap_or_default();
                if name == prefix || name.starts_with(&format!("{prefix}_")) {
                    p.push(&figure(svg)?);
                }
            }
        }
        p.section("files", "Files of this run");
        p.push(&super::html::file_list(self.files));
        p.push(&details(
            &format!("Every number of {}.json", self.stem()),
            &table(&["key", "value"], &json_rows(self.summary)),
        ));
        p.section("case", "Case file");
        p.push(&format!("<p><code>{}</code></p>\n<pre>{}</pre>\n", escape(&self.lc.file), escape(&self.lc.text)));
        let title = if self.lc.case.title.is_empty() { self.lc.file.clone() } else { self.lc.case.title.clone() };
        let meta = format!(
            "case <code>{}</code> · base: {} · actuators: {} · beamflow {}",
            escape(&self.lc.file),
            escape(match self.summary["structure"].as_str() {
                Some("none") | None => "rigid",
                Some(kind) => kind,
            }),
            escape(&self.run.model.actuators.iter().map(|a| a.name().to_string()).collect::<Vec<_>>().join(", ")),
            env!("CARGO_PKG_VERSION")
        );
        Ok(p.finish(&title, &meta))
    }

    /// The SVG figure among the files written whose name is `name`.svg.
    fn svg_named(&self, name: &str) -> Option<&std::path::PathBuf> {
        self.files
            .iter()
            .find(|f| f.extension().is_some_and(|e| e == "svg") && f.file_stem().is_some_and(|s| s == name))
    }

    /// The structure the power goes into, as the page names it (`beam`, `plate`, `model`,
    /// `base` on a rigid one).
    fn word(&self) -> &str {
        crate::io::summary::structure_word(self.summary)
    }

    fn stem(&self) -> String {
        std::path::Path::new(&self.lc.file).file_stem().map_or("case".into(), |s| s.to_string_lossy().into_owned())
    }

    fn analyses(&self) -> Vec<&Value> {
        self.summary["analyses"].as_array().map(|a| a.iter().collect()).unwrap_or_default()
    }

    /// Per analysis: net and point powers, load powers, dissipation and the transmitted
    /// force at the drive frequency; natural frequencies for a modes analysis.
    fn headline(&self) -> String {
        let mut rows = Vec::new();
        for (a, tag) in self.analyses().into_iter().zip(analysis_tags(self.run)) {
            let mut row =
                |what: String, v: &Value, unit: &str| rows.push(vec![cell(&tag), cell(&what), num(f(v), unit)]);
            for (name, v) in a["net_power_w"].as_object().into_iter().flatten() {
                row(format!("net power into the {} of {name}", self.word()), v, "W");
            }
            for (k, v) in a["mean_power_w"].as_object().into_iter().flatten() {
                row(format!("mean power at {k}"), v, "W");
            }
            for (k, v) in a["load_power_w"].as_object().into_iter().flatten() {
                row(format!("mean power of load {k}"), v, "W");
            }
            if a["structure_dissipation_w"].is_number() {
                row(format!("power dissipated in the {}", self.word()), &a["structure_dissipation_w"], "W");
            }
            for (k, v) in a["transmitted_force_amplitude_at_drive_n"].as_object().into_iter().flatten() {
                row(format!("transmitted force amplitude at the drive frequency, {k}"), v, "N");
            }
            if let Some(r) = a.get("record") {
                for (k, v) in r["energy_j"].as_object().into_iter().flatten() {
                    row(format!("energy delivered at {k}"), v, "J");
                }
                for (k, v) in r["mean_power_w"].as_object().into_iter().flatten() {
                    row(format!("mean power over the record at {k}"), v, "W");
                }
                for (name, v) in r["net_energy_j"].as_object().into_iter().flatten() {
                    row(format!("net energy of {name}"), v, "J");
                }
            }
            for (i, v) in a["frequencies_hz"].as_array().into_iter().flatten().enumerate() {
                row(format!("natural frequency of mode {}", i + 1), v, "Hz");
            }
            if let Some(fr) = a["frequency_hz"].as_array() {
                let peak = a["total_power_w"]
                    .as_array()
                    .into_iter()
                    .flatten()
                    .enumerate()
                    .max_by(|x, y| f(x.1).abs().total_cmp(&f(y.1).abs()))
                    .filter(|(_, p)| f(p) != 0.0);
                // Without forces (transfer functions only) no power goes in: no row.
                if let Some((k, p)) = peak {
                    row(format!("largest input power (at {} Hz)", crate::report::sweep::num(f(&fr[k]))), p, "W");
                }
            }
        }
        table(&["analysis", "quantity", "value"], &rows)
    }

    /// The accuracy estimates each result states, with what they mean.
    fn accuracy(&self) -> String {
        let mut rows = Vec::new();
        for (a, tag) in self.analyses().into_iter().zip(analysis_tags(self.run)) {
            let mut row = |what: &str, v: &Value, unit: &str, means: &str| {
                rows.push(vec![cell(&tag), cell(what), num(f(v), unit), cell(means)])
            };
            if a["type"] == "transient" {
                row("time step Δt", &a["dt_s"], "s", "");
                if let Some(r) = a.get("record") {
                    row("record length", &r["duration_s"], "s", r["description"].as_str().unwrap_or(""));
                    if r["end_activity_max"].is_number() {
                        row("end activity (rates at the end / peak)", &r["end_activity_max"], "", "");
                    }
                    if r["min_coherence_in_band"].is_number() {
                        row("least coherence in the band", &r["min_coherence_in_band"], "", "");
                    }
                } else {
                    row("periods run", &a["periods_run"], "", "");
                }
                if a["settling_estimate"].is_number() {
                    let state = if a["converged"] == true { "settled" } else { "NOT settled" };
                    row("settling: start-up transient left", &a["settling_estimate"], "", state);
                    row("change over the last period", &a["final_change"], "", "");
                }
            }
            if a["truncation_estimate"].is_number() {
                row(
                    "harmonic truncation",
                    &a["truncation_estimate"],
                    "",
                    &format!("share of the largest point power the harmonics beyond {} carry", a["harmonics"]),
                );
            }
            if a["mesh_roundoff"].is_number() && a["mesh_roundoff_kind"] == "estimate" {
                // The law behind it was measured on beams only: not a bound here.
                row("round-off of the point powers", &a["mesh_roundoff"], "", ROUNDOFF_ESTIMATE);
            } else if a["mesh_roundoff"].is_number() {
                row("round-off of the beam modes", &a["mesh_roundoff"], "", "relative, bound on mode 1");
            }
            match &a["energy_balance_rel_error"] {
                Value::Object(m) => {
                    for (k, v) in m.iter().filter(|(_, v)| v.is_number()) {
                        row(&format!("energy balance ({})", k.replace('_', " ")), v, "", "relative error");
                    }
                }
                v if v.is_number() => {
                    row("energy balance", v, "", &format!("net input against {} dissipation", self.word()))
                }
                _ => {}
            }
            if a["max_balance_error"].is_number() {
                row("energy balance (worst frequency)", &a["max_balance_error"], "", "relative error");
            }
            if let Some(e) = a.get("reduction").map(|r| &r["error"]["max_relative_error"]).filter(|e| e.is_number()) {
                row("modal reduction", e, "", "point powers against the full model, relative");
            }
            if let Some(m) = a.get("mesh_estimate") {
                let e = &m["max_relative_error"];
                if e.is_number() {
                    let c = &m["coarse_elements"];
                    row(
                        "plate grid",
                        e,
                        "",
                        &format!("point powers against a {} × {} grid's, relative (estimate)", c[0], c[1]),
                    );
                } else {
                    let why = m["not_estimated"].as_str().unwrap_or("?");
                    rows.push(vec![cell(&tag), cell("plate grid"), cell("not estimated"), cell(why)]);
                }
            }
            if a["forced"] == false {
                rows.push(vec![cell(&tag), cell("energy balance"), cell("n/a (no forcing)"), cell(UNFORCED)]);
            }
        }
        table(&["analysis", "estimate", "value", "meaning"], &rows)
    }

    /// The measurements compared in analysis `i`: where, what, and the errors.
    fn measurements(&self, i: usize) -> String {
        let rows: Vec<Vec<String>> = self
            .run
            .measured
            .iter()
            .filter(|c| c.analysis == i)
            .map(|c| {
                let verdict = match (c.agrees(), c.tolerance_db) {
                    (Some(true), Some(t)) => format!("agrees (within {t} dB)"),
                    (Some(false), Some(t)) => format!("DIFFERS (more than {t} dB)"),
                    _ => "–".into(),
                };
                let rms = if c.quantity == crate::case::measured::MeasuredQuantity::Power {
                    cell("–")
                } else {
                    num(c.relative_rms_error, "")
                };
                vec![
                    cell(&c.name),
                    cell(&c.point),
                    cell(c.quantity.name()),
                    cell(&c.harmonic.len().to_string()),
                    c.drive_error_db().map_or(cell("–"), |e| num(e, "dB")),
                    num(c.max_abs_error_db(), "dB"),
                    rms,
                    cell(&verdict),
                    cell(&c.file),
                ]
            })
            .collect();
        if rows.is_empty() {
            return String::new();
        }
        let head = [
            "measurement",
            "point",
            "quantity",
            "harmonics compared",
            "level error at the drive frequency",
            "largest |level error|",
            "RMS error (relative)",
            "verdict",
            "file",
        ];
        format!("<h3>Measured beside predicted</h3>\n{}", table(&head, &rows))
    }

    /// Warnings a reader should not miss: the case's likely slips of units, what the run's
    /// stated accuracies say ([`Self::accuracy_warnings`]) and, on a rigid base, what its
    /// result means.
    pub fn warnings(&self) -> Vec<String> {
        let mut w = crate::case::plausible::warnings(&self.lc.case);
        w.extend(self.accuracy_warnings());
        if self.summary["base"] == "rigid" {
            w.push("Rigid base: nothing moves the base, so no power flows into it; the transmitted forces carry the result.".into());
        }
        w
    }

    /// What the run's stated accuracies and measurements warn of, each led by its
    /// analysis: the report lists them.
    pub fn accuracy_warnings(&self) -> Vec<String> {
        self.warnings_of(true)
    }

    /// [`Self::accuracy_warnings`] but a round-off bound above its tolerance, which the run
    /// says on the console as it finds it: what the console prints after the results.
    pub fn console_warnings(&self) -> Vec<String> {
        self.warnings_of(false)
    }

    fn warnings_of(&self, roundoff: bool) -> Vec<String> {
        let mut w = Vec::new();
        for (a, tag) in self.analyses().into_iter().zip(analysis_tags(self.run)) {
            if a["converged"] == false {
                w.push(format!(
                    "{tag}: NOT settled after {} periods; the start-up transient left {:.1e} (relative); {}.",
                    a["periods_run"],
                    f(&a["settling_estimate"]),
                    crate::io::summary::raise_periods(a)
                ));
            } else if f(&a["settling_estimate"]) > SETTLING_WARN {
                w.push(format!("{tag}: the start-up transient left {:.1e} (relative).", f(&a["settling_estimate"])));
            }
            for rw in a["record"]["warnings"].as_array().into_iter().flatten() {
                w.push(format!("{tag}: {}", rw.as_str().unwrap_or("?")));
            }
            if f(&a["truncation_estimate"]) > TRUNCATION_WARN {
                w.push(format!(
                    "{tag}: the harmonics left out carry {:.1e} of the largest point power; raise `harmonics`.",
                    f(&a["truncation_estimate"])
                ));
            }
            if roundoff && a["roundoff_holds"] == false {
                w.push(format!(
                    "{tag}: the point powers' round-off bound is {:.1e}, above the tolerance {:.0e} (`beam.mesh.roundoff_tolerance`).",
                    f(&a["mesh_roundoff"]),
                    f(&a["roundoff_tolerance"])
                ));
            }
            let balances: Vec<f64> = match &a["energy_balance_rel_error"] {
                Value::Object(m) => m.values().map(f).collect(),
                v => vec![f(v), f(&a["max_balance_error"])],
            };
            if let Some(e) =
                balances.into_iter().filter(|e| e.is_finite()).reduce(f64::max).filter(|e| *e > BALANCE_WARN)
            {
                w.push(format!("{tag}: energy balances only to {e:.1e} (relative)."));
            }
            if let Some(m) = a.get("mesh_estimate") {
                let e = f(&m["max_relative_error"]);
                if e > MESH_WARN {
                    w.push(format!(
                        "{tag}: the plate grid's point powers differ from a {} × {} grid's by up to {e:.1e}: \
                         refine `plate.mesh.elements` until this difference is below what you need.",
                        m["coarse_elements"][0], m["coarse_elements"][1]
                    ));
                } else if let Some(why) = m["not_estimated"].as_str() {
                    w.push(format!("{tag}: no estimate of the plate grid's error: {why}."));
                }
            }
            let red = a.get("reduction").map_or(f64::NAN, |r| f(&r["error"]["max_relative_error"]));
            if red > REDUCTION_WARN {
                w.push(format!(
                    "{tag}: the modal reduction's point powers are off by up to {red:.1e}; raise `factor`."
                ));
            }
        }
        for c in self.run.measured.iter().filter(|c| c.agrees() == Some(false)) {
            w.push(format!(
                "{}: measured {} at {} differs from the prediction by up to {:.2} dB (tolerance {} dB).",
                c.name,
                c.quantity.name(),
                c.point,
                c.max_abs_error_db(),
                c.tolerance_db.unwrap_or(f64::NAN)
            ));
        }
        w
    }

    /// Point powers, harmonics, modes and energy balance of one analysis.
    fn analysis_tables(&self, r: &AnalysisResult) -> String {
        let run = self.run;
        let link = |l: usize| {
            let lk = &run.system.links[l];
            format!("{}: {}", run.model.actuators[lk.actuator].name(), lk.name.replace('_', " "))
        };
        let word = self.word();
        let mut s = String::new();
        match r {
            AnalysisResult::Modes(m) => {
                let rows: Vec<Vec<String>> = (0..m.frequencies_hz.len())
                    .map(|i| {
                        vec![
                            cell(&(i + 1).to_string()),
                            num(m.frequencies_hz[i], "Hz"),
                            num(m.analytic_hz.get(i).copied().unwrap_or(f64::NAN), "Hz"),
                            num(m.relative_error.get(i).copied().unwrap_or(f64::NAN), ""),
                            num(m.roundoff_bound.get(i).copied().unwrap_or(f64::NAN), ""),
                        ]
                    })
                    .collect();
                s += &format!("<p>Reference: {}</p>\n", escape(&m.reference));
                s += &table(&["mode", "f", "closed form", "relative error", "round-off bound"], &rows);
                if let Some(c) = &m.coupled {
                    s += &coupled_modes(m, c, word);
                }
            }
            AnalysisResult::Harmonic(h) => {
                let rows: Vec<Vec<String>> = (0..h.frequency_hz.len())
                    .map(|k| {
                        vec![
                            num(h.frequency_hz[k], "Hz"),
                            num(h.total_power[k], "W"),
                            num(h.dissipated_power[k], "W"),
                            num(h.balance_error[k], ""),
                        ]
                    })
                    .collect();
                // Transfer functions alone apply no force: no power to tabulate.
                if h.input_power.first().is_some_and(|p| !p.is_empty()) {
                    s += &details(
                        &format!("Input power and dissipation at {} frequencies", rows.len()),
                        &table(&["frequency", "input power", &format!("{word} dissipation"), "balance error"], &rows),
                    );
                }
                if !h.transfer_inputs.is_empty() {
                    s += &format!(
                        "<p>Transfer functions of the {word} with its actuators attached, from {} inputs ({}) to {} \
                         response points ({}): magnitude and phase in the figure below, complex values in the \
                         HDF5 file (<code>transfer_velocity</code>, <code>transfer_interface</code>).</p>\n",
                        h.transfer_inputs.len(),
                        escape(&h.transfer_inputs.join(", ")),
                        h.point_names.len(),
                        escape(&h.point_names.join(", "))
                    );
                }
            }
            AnalysisResult::Transient(t) if t.record.is_none() => {
                s += &point_powers(&t.mean_power, &t.spectra, &link, word);
                s += &harmonics(&t.spectra, &link);
                s += &table(
                    &[
                        "energy balance",
                        "net input power",
                        &format!("{word} dissipation"),
                        "relative error (last period)",
                    ],
                    &[vec![
                        cell(&format!("{word}, steady state")),
                        num(t.net_power.iter().sum(), "W"),
                        num(t.beam_dissipation, "W"),
                        num(t.energy_last_period.beam.relative_error(), ""),
                    ]],
                );
            }
            AnalysisResult::Transient(t) => {
                s += "<p>A non-periodic record: no period, so no harmonics; energies and mean powers over the record \
                      above, PSDs and FRFs (figures, HDF5 file) ";
                if let Some(r) = &t.record {
                    s += &format!("by {}.</p>\n", escape(&r.estimate.describe(r.dt, r.segments)));
                }
            }
            AnalysisResult::SteadyState(ss) => {
                s += &point_powers(&ss.mean_power, &ss.spectra, &link, word);
                s += &harmonics(&ss.spectra, &link);
                s += &table(
                    &["energy balance", "net input power", &format!("{word} dissipation"), "relative error"],
                    &[vec![
                        cell(word),
                        num(
                            ss.net_power.iter().sum::<f64>()
                                + ss.load_spectra.iter().map(|l| l.power_total).sum::<f64>(),
                            "W",
                        ),
                        num(ss.beam_dissipation, "W"),
                        num(ss.balance_error, ""),
                    ]],
                );
                if let Some(m) = &ss.modal {
                    let rows: Vec<Vec<String>> = (0..m.mode_frequency_hz.len())
                        .map(|r| {
                            vec![
                                cell(&(r + 1).to_string()),
                                num(m.mode_frequency_hz[r], "Hz"),
                                num(m.power_participation[r], ""),
                                num(m.dissipation[r], "W"),
                                num(m.kinetic_energy[r], "J"),
                            ]
                        })
                        .collect();
                    s += &details(
                        &format!("Power and energy by bare-{word} mode ({} modes)", rows.len()),
                        &table(&["mode", "f", "share of net power", "dissipated power", "kinetic energy"], &rows),
                    );
                }
            }
        }
        s
    }
}

/// The coupled system's natural frequencies beside the bare-beam mode each resembles.
fn coupled_modes(
    m: &crate::analysis::modes::ModesResult,
    c: &crate::analysis::modes::CoupledModes,
    word: &str,
) -> String {
    let rows: Vec<Vec<String>> = (0..c.frequencies_hz.len())
        .map(|r| {
            let pair = c.shapes_w.get(r).and_then(|w| super::coupled::counterpart(m, w));
            vec![
                cell(&(r + 1).to_string()),
                num(c.frequencies_hz[r], "Hz"),
                pair.map_or(cell("–"), |(b, _)| cell(&(b + 1).to_string())),
                pair.map_or(cell("–"), |(b, _)| num(m.frequencies_hz[b], "Hz")),
                pair.map_or(cell("–"), |(_, v)| num(v, "")),
            ]
        })
        .collect();
    format!(
        "<p>With the actuators attached (their bodies: {}), the closest bare-{word} mode by shape \
         (MAC of w at the nodes):</p>\n{}",
        escape(&c.body_names.join(", ")),
        table(&["coupled mode", "f", "bare mode", "bare f", "MAC"], &rows)
    )
}

/// Mean power at each point and its transmitted-force amplitude at the drive frequency.
fn point_powers(mean: &[f64], spectra: &[LinkSpectrum], link: &dyn Fn(usize) -> String, word: &str) -> String {
    let rows: Vec<Vec<String>> = (0..mean.len())
        .map(|l| {
            let f1 = spectra[l].transmitted.get(1).map_or(f64::NAN, |c| c.norm());
            vec![cell(&link(l)), num(mean[l], "W"), num(f1, "N")]
        })
        .collect();
    let into = format!("mean power into the {word}");
    table(&["point", &into, "|F| at the drive frequency"], &rows)
}

/// Power per harmonic and transmitted-force amplitude of every point.
fn harmonics(spectra: &[LinkSpectrum], link: &dyn Fn(usize) -> String) -> String {
    let Some(first) = spectra.first() else { return String::new() };
    let mut header: Vec<String> = vec!["k".into(), "frequency".into()];
    for l in 0..spectra.len() {
        header.push(format!("P, {}", link(l)));
        header.push(format!("|F|, {}", link(l)));
    }
    let rows: Vec<Vec<String>> = (1..first.frequency.len())
        .map(|k| {
            let mut row = vec![cell(&k.to_string()), num(first.frequency[k], "Hz")];
            for s in spectra {
                row.push(num(s.power.get(k).copied().unwrap_or(f64::NAN), "W"));
                row.push(num(s.transmitted.get(k).map_or(f64::NAN, |c| c.norm()), "N"));
            }
            row
        })
        .collect();
    let refs: Vec<&str> = header.iter().map(String::as_str).collect();
    details(&format!("Power and force per harmonic ({} harmonics)", rows.len()), &table(&refs, &rows))
}

/// Every number of a JSON value as (path, value) rows.
fn json_rows(v: &Value) -> Vec<Vec<String>> {
    fn walk(v: &Value, path: &str, unit: &str, out: &mut Vec<Vec<String>>) {
        match v {
            Value::Object(m) => {
                for (k, x) in m {
                    // Keys under a quantity are names (`mean_power_w.frame_stack`): they
                    // keep its unit whatever they end with.
                    let u = if unit.is_empty() { unit_of(k).unwrap_or("") } else { unit };
                    walk(x, &if path.is_empty() { k.clone() } else { format!("{path}.{k}") }, u, out);
                }
            }
            Value::Array(a) => {
                for (i, x) in a.iter().enumerate() {
                    walk(x, &format!("{path}[{i}]"), unit, out);
                }
            }
            Value::Number(n) => out.push(vec![cell(path), num(n.as_f64().unwrap_or(f64::NAN), unit)]),
            Value::Bool(b) => out.push(vec![cell(path), cell(&b.to_string())]),
            Value::String(s) => out.push(vec![cell(path), cell(s)]),
            Value::Null => out.push(vec![cell(path), cell("null")]),
        }
    }
    let mut out = Vec::new();
    walk(v, "", "", &mut out);
    out
}

/// The unit a summary key names by its suffix (`net_power_w` → W).
fn unit_of(key: &str) -> Option<&'static str> {
    [("_w", "W"), ("_hz", "Hz"), ("_n", "N"), ("_s", "s"), ("_j", "J")]
        .iter()
        .find(|(suffix, _)| key.ends_with(suffix))
        .map(|(_, u)| *u)
}
