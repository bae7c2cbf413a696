//! The headline numbers of a run, for people (text) and scripts (JSON).

use crate::actuator::link_id;
use crate::analysis::case_run::{AnalysisResult, CaseRun};
use crate::analysis::mesh_estimate::{self, MeshCheck};
use crate::analysis::series::LoadSpectrum;
use crate::case::LoadedCase;
use crate::power::record::RecordAnalysis;
use crate::report::si;
use serde_json::{json, Map, Value};

/// A JSON object with one entry per analysis.
pub fn summary(lc: &LoadedCase, run: &CaseRun) -> Value {
    let mut analyses = Vec::new();
    let link_name = |l: usize| {
        let lk = &run.system.links[l];
        link_id(run.model.actuators[lk.actuator].name(), &lk.name)
    };
    let actuators: Vec<&str> = run.model.actuators.iter().map(|a| a.name()).collect();
    for r in &run.results {
        analyses.push(match r {
            AnalysisResult::Modes(m) => {
                let mut v = json!({"type": "modes", "frequencies_hz": m.frequencies_hz, "analytic_hz": m.analytic_hz, "relative_error": m.relative_error, "roundoff_bound": m.roundoff_bound, "rigid_body_modes": m.rigid_body_modes});
                if let Some(c) = &m.coupled {
                    v["coupled_frequencies_hz"] = json!(c.frequencies_hz);
                }
                v
            }
            AnalysisResult::Harmonic(h) => {
                let mut v = json!({"type": "harmonic", "frequency_hz": h.frequency_hz, "total_power_w": h.total_power, "dissipated_power_w": h.dissipated_power, "max_balance_error": h.balance_error.iter().fold(0.0f64, |a, b| a.max(*b)), "mesh_roundoff": h.mesh_roundoff});
                if !h.forced() {
                    unforced(&mut v);
                }
                if !h.transfer_inputs.is_empty() {
                    v["system"] = json!("coupled");
                    v["transfer_inputs"] = json!(h.transfer_inputs);
                    v["point_names"] = json!(h.point_names);
                }
                v
            }
            AnalysisResult::Transient(t) => {
                let mut points = Map::new();
                for (l, p) in t.mean_power.iter().enumerate() {
                    points.insert(link_name(l), json!(p));
                }
                let amp: Map<String, Value> = t.spectra.iter().enumerate().map(|(l, s)| (link_name(l), json!(s.transmitted.get(1).map_or(0.0, |c| c.norm())))).collect();
                let mut v = json!({"type": "transient", "dt_s": t.dt, "steps_per_period": t.steps_per_period, "harmonics": t.harmonics, "periods_run": t.periods_run, "converged": t.converged, "final_change": t.final_change,
                       "settling_estimate": finite_or_null(t.settling_estimate), "periods_needed": t.periods_needed, "periods_given": t.periods_given, "mesh_roundoff": t.mesh_roundoff,
                       "mean_power_w": points, "net_power_w": by_name(&actuators, &t.net_power), "load_power_w": load_powers(&t.load_spectra), "transmitted_force_amplitude_at_drive_n": amp,
                       "beam_dissipation_w": t.beam_dissipation, "structure_dissipation_w": t.beam_dissipation,
                       "energy_balance_rel_error": {"beam_run": balance(&t.energy_run.beam), "structure_run": balance(&t.energy_run.beam), "system_run": balance(&t.energy_run.system), "beam_last_period": balance(&t.energy_last_period.beam), "structure_last_period": balance(&t.energy_last_period.beam)}});
                add_reduction(&mut v, t.reduction.as_ref());
                if let Some(rec) = &t.record {
                    v = record_summary(t, rec, &actuators);
                    add_reduction(&mut v, t.reduction.as_ref());
                }
                v
            }
            AnalysisResult::SteadyState(s) => {
                let mut points = Map::new();
                for (l, p) in s.mean_power.iter().enumerate() {
                    points.insert(link_name(l), json!(p));
                }
                let amp: Map<String, Value> = s.spectra.iter().enumerate().map(|(l, sp)| (link_name(l), json!(sp.transmitted.get(1).map_or(0.0, |c| c.norm())))).collect();
                let modal = s.modal.as_ref().map(|m| json!({"mode_frequency_hz": m.mode_frequency_hz, "power_participation": m.power_participation, "point_residual_w": m.point_residual, "load_residual_w": m.load_residual, "modal_dissipation_w": m.dissipation}));
                let mut v = json!({"type": "steady_state", "harmonics": s.harmonics, "truncation_estimate": finite_or_null(s.truncation_estimate), "mesh_roundoff": s.mesh_roundoff, "mean_power_w": points, "net_power_w": by_name(&actuators, &s.net_power), "load_power_w": load_powers(&s.load_spectra), "modal": modal,
                       "transmitted_force_amplitude_at_drive_n": amp, "beam_dissipation_w": s.beam_dissipation, "structure_dissipation_w": s.beam_dissipation, "energy_balance_rel_error": s.balance_error});
                add_reduction(&mut v, s.reduction.as_ref());
                v
            }
        });
    }
    // Each solve's round-off bound beside the tolerance it is held to.
    let tolerance = run.model.roundoff_tolerance;
    for (a, r) in analyses.iter_mut().zip(&run.results) {
        if let Some(bound) = r.mesh_roundoff().filter(|_| a["mesh_roundoff"].is_number()) {
            a["roundoff_tolerance"] = json!(tolerance);
            a["roundoff_holds"] = json!(bound <= tolerance);
            a["mesh_roundoff_kind"] = json!(roundoff_kind(run));
        }
    }
    for (a, m) in analyses.iter_mut().zip(&run.mesh) {
        if let Some(m) = m {
            let loads: Vec<&str> = run.model.loads.iter().map(|l| l.name.as_str()).collect();
            a["mesh_estimate"] = mesh_estimate(m, &link_name, &actuators, &loads);
        }
    }
    if run.model.structure.is_none() {
        analyses.iter_mut().for_each(without_beam);
    }
    for (i, a) in analyses.iter_mut().enumerate() {
        let mine: Vec<Value> = run.measured.iter().filter(|c| c.analysis == i).map(measured).collect();
        if !mine.is_empty() {
            a["measurements"] = Value::Array(mine);
        }
    }
    json!({"case": lc.file, "title": lc.case.title, "base": if run.model.structure.is_some() { "beam" } else { "rigid" },
           "structure": run.model.structure.as_ref().map_or("none", |s| s.kind()),
           "actuators": run.model.actuators.iter().map(|a| a.name().to_string()).collect::<Vec<_>>(), "analyses": analyses})
}

/// A plate grid's error estimate with each number under its point's or actuator's name, or
/// why there is none.
fn mesh_estimate(m: &MeshCheck, link_name: &dyn Fn(usize) -> String, actuators: &[&str], loads: &[&str]) -> Value {
    match m {
        MeshCheck::Estimate(e) => {
            let per_link = |v: &[f64]| -> Map<String, Value> {
                v.iter().enumerate().map(|(l, x)| (link_name(l), json!(x))).collect()
            };
            json!({"elements": e.elements, "coarse_elements": e.coarse_elements, "order": mesh_estimate::ORDER,
                   "max_relative_error": e.max_relative_error, "relative_error": per_link(&e.relative_error),
                   "net_power_relative_error": by_name(actuators, &e.net_power_relative_error),
                   "coarse_mean_power_w": per_link(&e.coarse_mean_power),
                   "load_relative_error": by_name(loads, &e.load_relative_error),
                   "coarse_load_power_w": by_name(loads, &e.coarse_load_power)})
        }
        MeshCheck::NotEstimated(why) => json!({"not_estimated": why}),
    }
}

/// A measurement against the prediction: where, what, and the errors.
fn measured(c: &crate::analysis::case_run::Comparison) -> Value {
    json!({"name": c.name, "point": c.point, "quantity": c.quantity.name(), "file": c.file,
           "harmonics_compared": c.harmonic.len(), "drive_error_db": c.drive_error_db(),
           "max_abs_error_db": finite_or_null(c.max_abs_error_db()), "relative_rms_error": finite_or_null(c.relative_rms_error),
           "tolerance_db": c.tolerance_db, "agrees": c.agrees()})
}

/// On a rigid base nothing moves the base, so powers into it and the beam's dissipation
/// and balance are not defined: they stay in the summary (one shape for every case) as
/// null, and the transmitted forces carry the result.
fn without_beam(a: &mut Value) {
    for key in ["mean_power_w", "net_power_w", "beam_dissipation_w", "structure_dissipation_w", "truncation_estimate"] {
        if a.get(key).is_some() {
            a[key] = Value::Null;
        }
    }
    match a.get_mut("energy_balance_rel_error") {
        Some(Value::Object(m)) => {
            for key in ["beam_run", "structure_run", "beam_last_period", "structure_last_period"] {
                m.insert(key.into(), Value::Null);
            }
        }
        Some(v) => *v = Value::Null,
        None => {}
    }
    if let Some(m) = a.get_mut("modal") {
        *m = Value::Null;
    }
}

/// A harmonic analysis that applies no force (transfer functions only) puts no power in:
/// there is nothing to balance and no input power whose round-off could be bounded, so
/// both are null, not a perfect 0.
fn unforced(v: &mut Value) {
    v["max_balance_error"] = Value::Null;
    v["mesh_roundoff"] = Value::Null;
    v["forced"] = json!(false);
}

/// An energy balance's relative error, or null when it has nothing to balance (no work in,
/// none dissipated, none stored): 0 there would claim a perfect balance.
fn balance(e: &crate::power::balance::EnergyBalance) -> Value {
    if e.input == 0.0 && e.dissipated == 0.0 && e.stored_change == 0.0 {
        Value::Null
    } else {
        json!(e.relative_error())
    }
}

/// What `mesh_roundoff` is: a bound on a beam, whose round-off law was measured and whose
/// solves are refined against element rows; an estimate on a plate or an imported model,
/// which follow the beam's law without that refinement (docs/structures.md).
fn roundoff_kind(run: &CaseRun) -> &'static str {
    match run.model.structure {
        Some(crate::structure::Structure::Beam(_)) | None => "bound",
        Some(_) => "estimate",
    }
}

/// The word for the structure a run's power goes into: `beam`, `plate`, `model` (an
/// imported one) or, on a rigid base, `base`.
pub fn structure_word(summary: &Value) -> &str {
    match summary["structure"].as_str() {
        Some("none") | None => "base",
        Some("imported") => "model",
        Some(s) => s,
    }
}

/// A non-periodic run: no period, so none of a periodic run's fields (harmonics, periods,
/// settling, mean power per period); instead the record's quantities — energy delivered and
/// mean power over the record per point and per actuator, the estimator of its spectra and
/// FRFs (in the HDF5 file), and what makes them untrustworthy.
fn record_summary(t: &crate::analysis::transient::TransientResult, rec: &RecordAnalysis, actuators: &[&str]) -> Value {
    let energy: Map<String, Value> = rec.points.iter().map(|p| (p.name.clone(), json!(p.energy))).collect();
    let power: Map<String, Value> =
        rec.points.iter().map(|p| (p.name.clone(), json!(p.energy / rec.duration))).collect();
    let end: Map<String, Value> = rec.points.iter().map(|p| (p.name.clone(), json!(p.end_activity))).collect();
    let e = &rec.estimate;
    json!({"type": "transient", "dt_s": t.dt, "steps_run": t.steps_run, "mesh_roundoff": t.mesh_roundoff,
        "beam_dissipated_energy_j": t.energy_run.beam.dissipated, "structure_dissipated_energy_j": t.energy_run.beam.dissipated,
        "energy_balance_rel_error": {"beam_run": balance(&t.energy_run.beam), "structure_run": balance(&t.energy_run.beam), "system_run": balance(&t.energy_run.system)},
        "record": {"duration_s": rec.duration, "band_hz": [rec.band.0, rec.band.1],
            "estimator": e.reason, "description": e.describe(rec.dt, rec.segments),
            "segment_s": rec.segment_s, "segments": rec.segments,
            "overlap": rec.welch.overlap, "window": if rec.welch.hann { "hann" } else { "rectangular" },
            "frequency_resolution_hz": 1.0 / rec.segment_s, "end_activity": end, "end_activity_max": e.end_activity,
            "min_coherence_in_band": e.min_coherence, "low_coherence_share": e.low_coherence_share,
            "trustworthy": e.warnings.is_empty(), "warnings": e.warnings,
            "energy_j": energy, "mean_power_w": power, "net_energy_j": by_name(actuators, &rec.net_energy),
            "net_mean_power_w": by_name(actuators, &rec.net_energy.iter().map(|x| x / rec.duration).collect::<Vec<_>>()),
            "sensors": rec.sensors.iter().map(|s| s.name.clone()).collect::<Vec<_>>()}})
}

/// Values per actuator (or point) as an object keyed by name, in the given order: every
/// power and energy of the summary is keyed the same way.
fn by_name(names: &[&str], values: &[f64]) -> Value {
    Value::Object(names.iter().zip(values).map(|(n, v)| (n.to_string(), json!(v))).collect())
}

/// Each point load's mean power into the beam (W), by name.
fn load_powers(loads: &[LoadSpectrum]) -> Value {
    Value::Object(loads.iter().map(|l| (l.name.clone(), json!(l.power_total))).collect())
}

/// A power of the summary as the console shows it (`6.323 µW`).
fn watts(p: &Value) -> String {
    si(p.as_f64().unwrap_or(f64::NAN), "W", 4)
}

/// A number, or JSON null where it is not defined (NaN).
fn finite_or_null(x: f64) -> Value {
    if x.is_finite() {
        json!(x)
    } else {
        Value::Null
    }
}

/// A reduced run's basis and error estimate, under `reduction`.
fn add_reduction(v: &mut Value, r: Option<&crate::analysis::reduction::ReductionReport>) {
    if let Some(r) = r {
        v["reduction"] = serde_json::to_value(r).expect("plain data serialises");
    }
}

/// A few lines for the terminal.
pub fn headline_text(v: &Value) -> String {
    let mut s = String::new();
    for a in v["analyses"].as_array().into_iter().flatten() {
        if let Some(t @ ("transient" | "steady_state")) = a["type"].as_str() {
            s += &format!("{t}:\n");
            if t == "transient" {
                s += &transient_status(a);
            } else {
                s += &format!("  {} harmonics", a["harmonics"]);
                match a["truncation_estimate"].as_f64() {
                    Some(e) => s += &format!("; the harmonics left out carry {e:.1e} of the largest point power\n"),
                    None => s += "\n",
                }
            }
            if let Some(f) = a["transmitted_force_amplitude_at_drive_n"].as_object().filter(|_| v["base"] == "rigid") {
                s += &rigid_forces(f);
            }
            // Named after the structure the power goes into.
            let into = structure_word(v);
            for (k, p) in a["mean_power_w"].as_object().into_iter().flatten() {
                let line = format!("mean power into the {into} at {k}");
                s += &format!("  {line:<52} {:>12}\n", watts(p));
            }
            for (k, p) in a["load_power_w"].as_object().into_iter().flatten() {
                let line = format!("mean power into the {into} by load {k}");
                s += &format!("  {line:<52} {:>12}\n", watts(p));
            }
            for (name, p) in a["net_power_w"].as_object().into_iter().flatten() {
                s += &format!("  net power of {name:<39} {:>12}\n", watts(p));
            }
            if let Some(r) = a.get("reduction") {
                s += &format!(
                    "  modal reduction: {} modes to {:.1} Hz + {} residual vectors, {} of {} DOFs",
                    r["modes_kept"],
                    r["cutoff_hz"].as_f64().unwrap_or(f64::NAN),
                    r["residual_vectors"],
                    r["reduced_dofs"],
                    r["full_dofs"]
                );
                match r["error"]["max_relative_error"].as_f64() {
                    Some(e) => s += &format!("; point powers within {e:.2e} of the full model\n"),
                    None => s += "\n",
                }
            }
        }
        if let Some(m) = a.get("mesh_estimate") {
            s += &mesh_line(m);
        }
        for m in a["measurements"].as_array().into_iter().flatten() {
            s += &measured_line(m);
        }
        if a["type"] == "harmonic" {
            let count = a["frequency_hz"].as_array().map_or(0, Vec::len);
            s += &match a["max_balance_error"].as_f64() {
                Some(e) => format!("harmonic: {count} frequencies, max energy-balance error {e:.2e}\n"),
                None => format!(
                    "harmonic: {count} frequencies of transfer functions (no force applied: no power to balance)\n"
                ),
            }
        }
    }
    s.trim_end().to_string()
}

/// The grid's error estimate in a line: the largest difference of a point's or an
/// actuator's net power from the coarser grid's, or why there is none.
fn mesh_line(m: &Value) -> String {
    let grid = |k: &str| format!("{} × {}", m[k][0], m[k][1]);
    match m["max_relative_error"].as_f64() {
        Some(e) => format!(
            "  plate grid {}: point powers within {e:.1e} of a {} grid's (the grid's error estimate)\n",
            grid("elements"),
            grid("coarse_elements")
        ),
        None => format!("  plate grid: no error estimate ({})\n", m["not_estimated"].as_str().unwrap_or("?")),
    }
}

/// One measurement's errors: at the drive frequency, the largest over the harmonics
/// compared, over the record, and the verdict against its tolerance.
fn measured_line(m: &Value) -> String {
    let f = |k: &str| m[k].as_f64();
    let mut s =
        format!("  measured {} at {}:", m["quantity"].as_str().unwrap_or("?"), m["point"].as_str().unwrap_or("?"));
    match f("drive_error_db") {
        Some(e) => s += &format!(" {e:+.2} dB at the drive frequency,"),
        None => s += " the drive frequency not compared,",
    }
    s += &format!(
        " largest |error| {:.2} dB over {} harmonic(s)",
        f("max_abs_error_db").unwrap_or(f64::NAN),
        m["harmonics_compared"]
    );
    if let Some(r) = f("relative_rms_error") {
        s += &format!(", RMS error {:.1} %", 100.0 * r);
    }
    match (m["agrees"].as_bool(), f("tolerance_db")) {
        (Some(true), Some(t)) => s += &format!(": agrees (within {t} dB)"),
        (Some(false), Some(t)) => s += &format!(": DIFFERS (more than {t} dB)"),
        _ => {}
    }
    s + "\n"
}

/// How a transient ran: its step, the harmonics it analysed, and whether (and how well) it
/// settled.
fn transient_status(a: &Value) -> String {
    if let Some(r) = a.get("record") {
        return record_status(a, r);
    }
    let n = a["steps_per_period"].as_u64().unwrap_or(0);
    let mut s = format!(
        "  Δt = {} ({n} steps per period), spectra to harmonic {} (20 steps per harmonic period)\n",
        si(a["dt_s"].as_f64().unwrap_or(f64::NAN), "s", 5),
        a["harmonics"]
    );
    let periods = a["periods_run"].as_u64().unwrap_or(0);
    match (a["converged"].as_bool(), a["settling_estimate"].as_f64()) {
        (Some(true), Some(e)) => {
            s += &format!("  settled after {periods} periods: start-up transient left {e:.1e} (relative)\n")
        }
        (Some(false), Some(e)) => {
            s += &format!(
                "  NOT settled after {periods} periods: start-up transient left {e:.1e} (relative); {}\n",
                raise_periods(a)
            )
        }
        _ => s += &format!("  ran {periods} period(s)\n"),
    }
    s
}

/// What an unsettled periodic run's reader should raise, and to about what, where its
/// decay tells.
pub fn raise_periods(a: &Value) -> String {
    let field = if a["periods_given"] == true { "periods" } else { "max_periods" };
    let short = a["periods_run"].as_u64().is_some_and(|n| n < crate::analysis::transient::DECAY_PERIODS as u64);
    match a["periods_needed"].as_u64() {
        Some(n) => format!("raise `{field}` (the decay over the last periods asks for about {n} in all)"),
        None if short => format!("raise `{field}`"),
        None => format!("raise `{field}` (the start-up transient was not decaying over the last periods)"),
    }
}

/// A non-periodic run: its record, how its spectra are averaged, and the energy each point
/// and each actuator delivered.
fn record_status(a: &Value, r: &Value) -> String {
    let f = |v: &Value| v.as_f64().unwrap_or(f64::NAN);
    let mut s = format!(
        "  non-periodic drive: one record of {} at Δt = {}, band {:.1}–{:.1} Hz; no period, so no \
         harmonics\n  PSDs and H1 FRFs in the HDF5 file: {}\n",
        si(f(&r["duration_s"]), "s", 5),
        si(f(&a["dt_s"]), "s", 5),
        f(&r["band_hz"][0]),
        f(&r["band_hz"][1]),
        r["description"].as_str().unwrap_or("?"),
    );
    if let Some(c) = r["min_coherence_in_band"].as_f64() {
        s += &format!(
            "  coherence in the band: least {c:.3}, below {} over {:.0} % of it\n",
            crate::power::record::COHERENCE_TRUSTED,
            100.0 * f(&r["low_coherence_share"])
        );
    }
    for w in r["warnings"].as_array().into_iter().flatten() {
        s += &format!("  WARNING: {}\n", w.as_str().unwrap_or("?"));
    }
    let powers = r["mean_power_w"].as_object();
    for (k, e) in r["energy_j"].as_object().into_iter().flatten() {
        let p = powers.and_then(|m| m.get(k)).map_or(f64::NAN, f);
        s += &format!(
            "  energy delivered into the structure at {k:<22} {:>12}, mean {:>11}\n",
            si(f(e), "J", 4),
            si(p, "W", 4)
        );
    }
    let net_p = r["net_mean_power_w"].as_object();
    for (name, e) in r["net_energy_j"].as_object().into_iter().flatten() {
        let p = net_p.and_then(|m| m.get(name)).map_or(f64::NAN, f);
        s += &format!("  net energy of {name:<46} {:>12}, mean {:>11}\n", si(f(e), "J", 4), si(p, "W", 4));
    }
    s
}

/// On a rigid base: each link's transmitted force amplitude at the drive frequency and,
/// for every pair of actuators, the ratio of their stack forces (the point of such a case).
fn rigid_forces(f: &Map<String, Value>) -> String {
    let mut s = String::from("  transmitted force amplitude at the drive frequency:\n");
    for (k, v) in f {
        s += &format!("    {k:<36} {:>12}\n", si(v.as_f64().unwrap_or(f64::NAN), "N", 4));
    }
    let stacks: Vec<(&String, f64)> =
        f.iter().filter(|(k, _)| k.ends_with("_stack")).map(|(k, v)| (k, v.as_f64().unwrap_or(f64::NAN))).collect();
    for (i, (a, fa)) in stacks.iter().enumerate() {
        for (b, fb) in &stacks[i + 1..] {
            let (hi, lo, r) = if fa >= fb { (a, b, fa / fb) } else { (b, a, fb / fa) };
            s += &format!("  {hi} / {lo} force ratio {r:.1}\n");
        }
    }
    s
}
