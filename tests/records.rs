//! Non-periodic drives are analysed as records: no harmonics, but energies, PSDs and H1
//! FRFs with coherence, checked against the harmonic analysis of the same beam and
//! against the run's own energy balance.

use beamflow::analysis::case_run::{AnalysisResult, CaseRun};
use beamflow::analysis::transient::TransientResult;
use beamflow::app::runner::run_case;
use beamflow::case::LoadedCase;
use num_complex::Complex64;
use std::f64::consts::PI;
use std::path::PathBuf;

fn run(text: &str) -> CaseRun {
    run_case(
        &LoadedCase::from_str(text, "records.toml", PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("cases")).unwrap(),
    )
    .unwrap()
}

fn transient(r: &CaseRun) -> &TransientResult {
    r.results.iter().find_map(|a| if let AnalysisResult::Transient(t) = a { Some(t) } else { None }).unwrap()
}

/// A burst chirp on the beam: 10 to 400 Hz in 2 s, then silence while the response dies
/// out, written as a force series sampled at the run's step.
fn burst_csv(dir: &std::path::Path, dt: f64) {
    let (t1, total) = (2.0, 4.0);
    let mut csv = String::from("time,force\n");
    for j in 0..=((total / dt).round() as usize) {
        let t = j as f64 * dt;
        let f = if t < t1 { (2.0 * PI * (10.0 * t + 0.5 * 195.0 * t * t)).sin() } else { 0.0 };
        csv += &format!("{t:.10},{f:.17e}\n");
    }
    std::fs::write(dir.join("burst.csv"), csv).unwrap();
}

const DT: f64 = 1e-4;
const DAMPING: &str = "[damping]\nkind = \"rayleigh_ratio\"\nzeta = 0.02\n";

fn in_dir(dir: &std::path::Path, text: &str) -> CaseRun {
    run_case(&LoadedCase::from_str(text, "burst.toml", dir.to_path_buf()).unwrap()).unwrap()
}

/// The frequencies (Hz) average acceleration at `DT` responds at for drives at `f` (Hz).
fn shifted(f: &[f64]) -> Vec<f64> {
    shifted_at(f, DT)
}

/// The frequencies (Hz) average acceleration at step `dt` responds at for drives at `f`
/// (Hz): the trapezoidal rule maps iω to (2/Δt)·i·tan(ωΔt/2).
fn shifted_at(f: &[f64], dt: f64) -> Vec<f64> {
    f.iter().map(|&f| (2.0 / dt) * (PI * f * dt).tan() / (2.0 * PI)).collect()
}

#[test]
fn frfs_of_a_burst_chirp_force_are_the_harmonic_analysis() {
    let dir = tempfile::tempdir().unwrap();
    burst_csv(dir.path(), DT);
    let r = in_dir(
        dir.path(),
        &format!(
            "{DAMPING}[[load]]\nx = 0.2\n[load.force]\nkind = \"series\"\nfile = \"burst.csv\"\nvoltage_column = \"force\"\n\
             [[analysis]]\ntype = \"transient\"\ndt = {DT}\nduration = 4.0\n[output]\nhdf5 = false\nplots = false\n"
        ),
    );
    let t = transient(&r);
    // No harmonics of a record that does not repeat.
    assert!(t.spectra.is_empty() && t.load_spectra.is_empty() && t.mean_power.is_empty() && t.harmonics == 0);
    let rec = t.record.as_ref().unwrap();
    let p = &rec.points[0];
    assert!(p.end_activity < 1e-3, "the response has died out: {:e}", p.end_activity);
    assert!(p.acceleration_coherence.is_empty(), "one segment has no coherence");
    // Against the harmonic analysis of the same beam at the frequencies the stepped system
    // responds at: accelerance iω'·Y and the power FRF Re Y (a sine of amplitude A puts
    // ½A²·Re Y in).
    let bins: Vec<usize> = (0..rec.frequency.len()).filter(|&k| (20.0..=380.0).contains(&rec.frequency[k])).collect();
    let freqs: Vec<f64> = bins.iter().map(|&k| rec.frequency[k]).collect();
    let warped = shifted(&freqs);
    let h = r_harmonic(&warped);
    for (i, &k) in bins.iter().enumerate() {
        let y = h.mobility[i][0][0];
        let acc = y * Complex64::new(0.0, 2.0 * PI * warped[i]);
        let e = (p.acceleration_frf[k] - acc).norm() / acc.norm();
        assert!(e < 3e-4, "{} Hz: accelerance off by {e:e}", freqs[i]);
        let ep = (p.power_frf[k] - y.re).abs() / y.norm();
        assert!(ep < 1e-5, "{} Hz: power FRF off by {ep:e}", freqs[i]);
    }
    // The energy the force delivered is what the run's balance counted, and it has been
    // dissipated: little is left stored when the response has died out.
    let e_run = t.energy_run.beam;
    assert!((p.energy - e_run.input).abs() < 1e-6 * e_run.input, "{:e} J vs {:e} J", p.energy, e_run.input);
    assert!(e_run.stored_change.abs() < 1e-3 * e_run.input, "{:e} J still stored", e_run.stored_change);
    // The force's PSD integrates to its mean square (Parseval, one segment).
    let f = &t.loads[0].force;
    let mean = f.iter().sum::<f64>() / f.len() as f64;
    let ms = f.iter().map(|x| (x - mean) * (x - mean)).sum::<f64>() / f.len() as f64;
    let df = rec.frequency[1];
    let integral: f64 = p.force_psd.iter().sum::<f64>() * df;
    assert!((integral - ms).abs() < 1e-9 * ms, "{integral} vs {ms}");
}

fn r_harmonic(freqs: &[f64]) -> beamflow::analysis::harmonic::HarmonicResult {
    harmonic_with(DAMPING, freqs)
}

/// The harmonic analysis of the beam with `damping` under a unit force at 0.2 m.
fn harmonic_with(damping: &str, freqs: &[f64]) -> beamflow::analysis::harmonic::HarmonicResult {
    let r = run(&format!(
        "{damping}[[analysis]]\ntype = \"harmonic\"\n[analysis.frequencies]\nvalues = {freqs:?}\n\
         [[analysis.force]]\nx = 0.2\n[output]\nhdf5 = false\nplots = false\n"
    ));
    r.results.into_iter().find_map(|a| if let AnalysisResult::Harmonic(h) = a { Some(h) } else { None }).unwrap()
}

#[test]
fn a_voltage_burst_gives_the_power_a_sine_would_put_in() {
    // A frame actuator with a linear stack driven by a voltage burst: its power FRF at f,
    // times ½A², is the mean power the steady state of a sine of amplitude A at f puts in.
    let dir = tempfile::tempdir().unwrap();
    burst_csv(dir.path(), DT);
    let frame = |voltage: &str| {
        format!(
            "{DAMPING}[[actuator]]\ntype = \"frame\"\nx_e = 0.3\n[actuator.stack]\nhysteresis = false\n[actuator.voltage]\n{voltage}"
        )
    };
    let r = in_dir(
        dir.path(),
        &format!(
            "{}[[analysis]]\ntype = \"transient\"\ndt = {DT}\nduration = 4.0\n[output]\nhdf5 = false\nplots = false\n",
            frame("kind = \"series\"\nfile = \"burst.csv\"\nvoltage_column = \"force\"\n")
        ),
    );
    let rec = transient(&r).record.as_ref().unwrap().clone();
    assert_eq!(rec.points.len(), 3, "a frame's stack and two legs");
    for f in [60.0, 200.0] {
        // The steady state of a sine at the frequency the stepped system responds at.
        let fs = shifted(&[f])[0];
        let s = run(&format!(
            "{}[[analysis]]\ntype = \"steady_state\"\n[output]\nhdf5 = false\nplots = false\n",
            frame(&format!("kind = \"sine\"\namplitude = 1.0\nfrequency = {fs:?}\n"))
        ));
        let ss =
            s.results.iter().find_map(|a| if let AnalysisResult::SteadyState(s) = a { Some(s) } else { None }).unwrap();
        let k = rec.frequency.iter().position(|&x| (x - f).abs() < 1e-9).unwrap();
        let scale = ss.mean_power.iter().fold(0.0f64, |m, p| m.max(p.abs()));
        for (l, p) in rec.points.iter().enumerate() {
            let from_record = 0.5 * p.power_frf[k];
            assert!(
                (from_record - ss.mean_power[l]).abs() < 1e-4 * scale,
                "{f} Hz, {}: {from_record:e} W vs {:e} W",
                p.name,
                ss.mean_power[l]
            );
        }
    }
}

#[test]
fn a_record_cut_while_the_drive_goes_on_says_so() {
    // A chirp continues at f_end after its sweep: a record that ends with it cannot hold
    // the whole response, and the end activity shows it.
    let r = run(&format!(
        "{DAMPING}[[load]]\nx = 0.2\n[load.force]\nkind = \"chirp\"\namplitude = 1.0\nf_start = 10.0\nf_end = 300.0\nduration = 1.0\n\
         [[analysis]]\ntype = \"transient\"\ndt = {DT}\nduration = 1.0\n[output]\nhdf5 = false\nplots = false\n"
    ));
    let p = &transient(&r).record.as_ref().unwrap().points[0];
    assert!(p.end_activity > 0.3, "{:e}", p.end_activity);
    // Welch segments average: coherence exists, and lies in [0, 1].
    let r = run(&format!(
        "{DAMPING}[[load]]\nx = 0.2\n[load.force]\nkind = \"chirp\"\namplitude = 1.0\nf_start = 10.0\nf_end = 300.0\nduration = 1.0\n\
         [[analysis]]\ntype = \"transient\"\ndt = {DT}\nduration = 1.0\nsegment = 0.25\n[output]\nhdf5 = false\nplots = false\n"
    ));
    let rec = transient(&r).record.as_ref().unwrap();
    // Hann segments of 0.25 s overlapping by three quarters, reaching back before t = 0.
    assert_eq!((rec.segments, rec.frequency[1]), (16, 4.0));
    let coh = &rec.points[0].acceleration_coherence;
    assert!(!coh.is_empty() && coh.iter().all(|c| (0.0..=1.0).contains(c)));
    let e = run_case(
        &LoadedCase::from_str(
            &format!(
                "[[load]]\nx = 0.2\n[load.force]\nkind = \"step\"\ntime = 0.0\nfrom = 0.0\nto = 1.0\n\
                 [[analysis]]\ntype = \"transient\"\ndt = {DT}\nduration = 0.1\nsegment = 0.0005\n"
            ),
            "seg.toml",
            PathBuf::from("."),
        )
        .unwrap(),
    )
    .unwrap_err()
    .to_string();
    assert!(e.contains("analysis[0].segment") && e.contains("[8, 1000]"), "{e}");
}

/// A unit force at 0.2 m on the beam with the default damping, driven by `force` (a
/// `[load.force]` table's body), its transient run with `analysis` (extra fields).
fn default_load(force: &str, analysis: &str) -> (LoadedCase, CaseRun) {
    let text = format!(
        "[[load]]\nx = 0.2\n[load.force]\n{force}[[sensor]]\nname = \"mid\"\nx = 0.3\n\
         [[analysis]]\ntype = \"transient\"\n{analysis}[output]\nhdf5 = false\nplots = false\n"
    );
    let lc = LoadedCase::from_str(&text, "default.toml", PathBuf::from(".")).unwrap();
    let r = run_case(&lc).unwrap();
    (lc, r)
}

/// Compares a record's accelerance at the load against the harmonic analysis of the same
/// beam at the frequencies the stepped system responds at, over `lo..=hi` Hz where the
/// coherence exceeds 0.99 (everywhere for one segment): the worst relative error, where
/// (Hz), and the bins compared out of those in the range.
fn against_harmonic(rec: &beamflow::power::record::RecordAnalysis, lo: f64, hi: f64) -> (f64, f64, usize, usize) {
    let p = &rec.points[0];
    let in_range: Vec<usize> = (1..rec.frequency.len()).filter(|&k| (lo..=hi).contains(&rec.frequency[k])).collect();
    let coherent = |k: usize| p.acceleration_coherence.get(k).map_or(true, |&c| c > 0.99);
    let bins: Vec<usize> = in_range.iter().copied().filter(|&k| coherent(k)).collect();
    let freqs: Vec<f64> = bins.iter().map(|&k| rec.frequency[k]).collect();
    let warped = shifted_at(&freqs, rec.dt);
    let h = harmonic_with("", &warped);
    let (mut worst, mut at) = (0.0f64, 0.0);
    for (i, &k) in bins.iter().enumerate() {
        let acc = h.mobility[i][0][0] * Complex64::new(0.0, 2.0 * PI * warped[i]);
        let e = (p.acceleration_frf[k] - acc).norm() / acc.norm();
        if e > worst {
            (worst, at) = (e, freqs[i]);
        }
    }
    (worst, at, bins.len(), in_range.len())
}

#[test]
fn a_chirp_at_default_settings_gives_the_harmonic_frfs_where_coherent() {
    // A chirp keeps running at f_end after its sweep: its response never dies out, so the
    // default record runs past the sweep and is averaged in Welch segments long enough
    // for the slowest decay in the band.
    let (_, r) = default_load("kind = \"chirp\"\namplitude = 1.0\nf_start = 10.0\nf_end = 400.0\nduration = 1.0\n", "");
    let rec = transient(&r).record.as_ref().unwrap();
    assert_eq!(rec.estimate.reason, "welch");
    assert!(rec.estimate.warnings.is_empty(), "{:?}", rec.estimate.warnings);
    assert!(rec.segment_s >= 0.99 * 32.0 / beamflow::analysis::drive::slowest_decay(&r.model));
    let (worst, at, compared, all) = against_harmonic(rec, 20.0, 380.0);
    assert!(worst < 0.03, "accelerance off by {worst:e} at {at} Hz");
    assert!(compared * 10 >= all * 9, "coherence above 0.99 over {compared} of {all} bins");
    // Every sensor gets its FRF, on the same bins.
    assert_eq!(rec.sensors.len(), 1);
    assert_eq!(rec.sensors[0].acceleration_frf.len(), rec.frequency.len());
}

#[test]
fn a_step_at_default_settings_gives_the_harmonic_frfs() {
    // A step holds still after its jump: the default record runs until the response has
    // died out, and one segment is exact. (The jump comes after the start: a drive that
    // jumps at t = 0 starts the run at the continuous system's consistent acceleration,
    // not at the stepped system's own rest state, which marks the accelerance.)
    let (lc, r) = default_load("kind = \"step\"\ntime = 0.01\nfrom = 0.0\nto = 1.0\n", "dt = 1e-4\n");
    let rec = transient(&r).record.as_ref().unwrap();
    assert_eq!(rec.estimate.reason, "decayed");
    assert!(rec.estimate.end_activity < beamflow::power::record::DECAYED, "{:e}", rec.estimate.end_activity);
    let (worst, at, compared, all) = against_harmonic(rec, 5.0, 450.0);
    assert!(worst < 0.03 && compared == all, "accelerance off by {worst:e} at {at} Hz ({compared} of {all} bins)");
    // Its summary says so, with a record's quantities and none of a periodic run's.
    let v = beamflow::io::summary::summary(&lc, &r);
    let a = &v["analyses"][0];
    for key in [
        "periods_run",
        "converged",
        "final_change",
        "settling_estimate",
        "harmonics",
        "steps_per_period",
        "mean_power_w",
        "net_power_w",
        "beam_dissipation_w",
    ] {
        assert!(a.get(key).is_none(), "{key} in a record's summary: {a}");
    }
    assert!(a["energy_balance_rel_error"].get("beam_last_period").is_none());
    assert_eq!(a["energy_balance_rel_error"]["structure_run"], a["energy_balance_rel_error"]["beam_run"]);
    let rj = &a["record"];
    assert_eq!(rj["estimator"], "decayed");
    assert!(rj["mean_power_w"]["load1"].as_f64().unwrap().is_finite());
    let text = beamflow::io::summary::headline_text(&v);
    assert!(text.contains("one segment, response decayed to"), "{text}");
    for word in ["settled", "max_periods", "NaN", "with coherence", "WARNING"] {
        assert!(!text.contains(word), "{word} in: {text}");
    }
    // The HDF5 file holds no periodic fields and no NaN.
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("step.h5");
    beamflow::io::results::write(&path, &lc, &r).unwrap();
    let h = beamflow::io::hdf5::ResultsReader::open(&path).unwrap();
    let g = "analysis_0_transient";
    for key in ["periods_run", "converged", "harmonics", "steps_per_period"] {
        assert!(h.attr_i64(g, key).is_err(), "{key} in a record's HDF5 group");
    }
    assert!(h.attr_f64(g, "final_change").is_err() && !h.exists(&format!("{g}/energy_last_period")));
    for p in ["load1"] {
        assert!(h.attr_f64(&format!("{g}/record/points/{p}"), "end_activity").unwrap().is_finite());
    }
    assert!(h.exists(&format!("{g}/record/sensors/mid/acceleration_frf")));
}

#[test]
fn a_record_too_short_for_its_band_is_flagged() {
    // The chirp's record ends with its sweep: segments cannot be as long as the band's
    // damping asks, and the response is still going. Console, summary and report say so.
    let (lc, r) = default_load(
        "kind = \"chirp\"\namplitude = 1.0\nf_start = 10.0\nf_end = 400.0\nduration = 1.0\n",
        "duration = 1.0\n",
    );
    let rec = transient(&r).record.as_ref().unwrap();
    assert!(!rec.estimate.warnings.is_empty());
    let v = beamflow::io::summary::summary(&lc, &r);
    assert_eq!(v["analyses"][0]["record"]["trustworthy"], false);
    let text = beamflow::io::summary::headline_text(&v);
    assert!(text.contains("WARNING: FRFs biased near resonances") && text.contains("`duration`"), "{text}");
}
