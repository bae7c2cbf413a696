//! Measured data beside predictions: a synthetic measurement made from the model's own
//! prediction, scaled by a known factor or shifted by a known time, must give exactly that
//! error back; bad measurement files are refused before any solve, naming file and field.

use beamflow::analysis::case_run::Comparison;
use beamflow::analysis::case_run::{AnalysisResult, CaseRun};
use beamflow::app::runner::run_case;
use beamflow::case::measured::MeasuredQuantity;
use beamflow::case::LoadedCase;
use std::f64::consts::PI;
use std::path::Path;

/// A beam with an inertial actuator and a sensor, its exact periodic steady state.
const CASE: &str = "[beam.mesh]\nelements = 20\n[damping]\nkind = \"rayleigh\"\na0 = 5.0\na1 = 1e-5\n\
    [[actuator]]\ntype = \"inertial\"\nname = \"shaker\"\nx_e = 0.146\n\
    [actuator.voltage]\nkind = \"sine\"\namplitude = 48.0\nfrequency = 60.0\n\
    [[sensor]]\nname = \"mid\"\nx = 0.365\n\
    [[analysis]]\ntype = \"steady_state\"\nharmonics = 15\nsamples_per_period = 256\n";

fn run_in(dir: &Path, text: &str) -> beamflow::error::Result<CaseRun> {
    run_case(&LoadedCase::from_str(text, "measured.toml", dir.to_path_buf())?)
}

/// Writes a measurement CSV: time and the given columns (name with SI unit).
fn write_csv(path: &Path, t: &[f64], cols: &[(&str, &[f64])]) {
    let mut s = String::from("time (s)");
    for (name, _) in cols {
        s += &format!(",{name}");
    }
    s.push('\n');
    for (i, ti) in t.iter().enumerate() {
        s += &format!("{ti:e}");
        for (_, c) in cols {
            s += &format!(",{:e}", c[i]);
        }
        s.push('\n');
    }
    std::fs::write(path, s).unwrap();
}

fn find<'a>(run: &'a CaseRun, name: &str, q: MeasuredQuantity) -> &'a Comparison {
    run.measured.iter().find(|c| c.name == name && c.quantity == q).unwrap_or_else(|| panic!("{name} {q:?}"))
}

#[test]
fn a_scaled_or_shifted_prediction_gives_its_scale_and_shift_back() {
    let dir = tempfile::tempdir().unwrap();
    let base = run_in(dir.path(), CASE).unwrap();
    let AnalysisResult::SteadyState(s) = &base.results[0] else { panic!("steady state") };
    let (t, link, sensor) = (&s.t, &s.links[0], &s.sensors[0]);
    let n = t.len();
    // +0.5 dB on force and acceleration: the power made from them, F·A, also +0.5 dB (a
    // ratio g² of a squared quantity).
    let g = 10f64.powf(0.5 / 20.0);
    let scaled = |v: &[f64]| v.iter().map(|x| g * x).collect::<Vec<f64>>();
    let (f, a) = (scaled(&link.interface), scaled(&link.base_acceleration));
    write_csv(&dir.path().join("foot.csv"), t, &[("force (N)", &f), ("acceleration (m/s^2)", &a)]);
    // The sensor's record 7 samples late: x_m(t) = x(t − τ).
    let j = 7;
    let late: Vec<f64> = (0..n).map(|i| sensor.a[(i + n - j) % n]).collect();
    let tau = j as f64 * (t[1] - t[0]);
    write_csv(&dir.path().join("late.csv"), t, &[("accel (g)", &late.iter().map(|x| x / 9.80665).collect::<Vec<_>>())]);
    let text = format!(
        "{CASE}[[measurement]]\nfile = \"foot.csv\"\npoint = \"shaker_stack\"\ntolerance_db = 0.6\n\
         [[measurement]]\nname = \"late\"\nfile = \"late.csv\"\npoint = \"mid\"\n"
    );
    let run = run_in(dir.path(), &text).unwrap();
    assert_eq!(run.measured.len(), 4, "force, acceleration and power at the foot; acceleration at the sensor");
    for (q, db) in
        [(MeasuredQuantity::Force, 0.5), (MeasuredQuantity::Acceleration, 0.5), (MeasuredQuantity::Power, 0.5)]
    {
        let c = find(&run, "shaker_stack", q);
        assert!(c.harmonic.len() >= 2 && c.harmonic[0] == 1, "{q:?}: {:?}", c.harmonic);
        for (k, (e, p)) in c.harmonic.iter().zip(c.error_db.iter().zip(&c.phase_error)) {
            assert!((e - db).abs() < 1e-9 && p.abs() < 1e-9, "{q:?} harmonic {k}: {e} dB, {p} rad");
        }
        assert_eq!(c.agrees(), Some(true), "{q:?}");
        if q != MeasuredQuantity::Power {
            assert!((c.relative_rms_error - (g - 1.0)).abs() < 1e-9, "{q:?}: {}", c.relative_rms_error);
        }
    }
    let c = find(&run, "late", MeasuredQuantity::Acceleration);
    assert!(c.harmonic.len() >= 2);
    let w0 = 2.0 * PI * 60.0;
    for ((k, e), p) in c.harmonic.iter().zip(&c.error_db).zip(&c.phase_error) {
        let want = -(*k as f64) * w0 * tau;
        let wrapped = (want + PI).rem_euclid(2.0 * PI) - PI;
        assert!(e.abs() < 1e-9 && (p - wrapped).abs() < 1e-9, "harmonic {k}: {e} dB, {p} vs {wrapped} rad");
    }
    assert!(c.relative_rms_error > 0.1, "a shifted record differs in time: {}", c.relative_rms_error);
    assert_eq!(c.agrees(), None);
}

#[test]
fn a_results_file_as_measurement_agrees_with_itself_and_lands_in_hdf5() {
    let dir = tempfile::tempdir().unwrap();
    let first = dir.path().join("first.toml");
    std::fs::write(&first, format!("{CASE}[output]\nplots = false\n")).unwrap();
    beamflow::app::commands::run(
        &first,
        Some(&dir.path().join("a")),
        None,
        false,
        false,
        &beamflow::analysis::budget::Budget::default(),
    )
    .unwrap();
    let second = dir.path().join("second.toml");
    std::fs::write(
        &second,
        format!(
            "{CASE}[output]\nplots = false\n[[measurement]]\nname = \"foot\"\n\
             file = \"a/first.h5:analysis_0_steady_state\"\npoint = \"shaker_stack\"\ntolerance_db = 0.1\n"
        ),
    )
    .unwrap();
    let out = dir.path().join("b");
    beamflow::app::commands::run(
        &second,
        Some(&out),
        None,
        false,
        true,
        &beamflow::analysis::budget::Budget::default(),
    )
    .unwrap();
    let tree = beamflow::io::hdf5::ResultsReader::open(out.join("second.h5")).unwrap().read_tree().unwrap();
    let g = tree.group("analysis_0_steady_state/measurements/foot/power").expect("the comparison's group");
    assert_eq!(g.attrs["agrees"], beamflow::io::tree::Attr::I64(1));
    let beamflow::io::tree::Data::F64(e) =
        &tree.dataset("analysis_0_steady_state/measurements/foot/force/error_db").unwrap().data
    else {
        panic!("real error_db")
    };
    assert!(!e.is_empty() && e.iter().all(|x| x.abs() < 1e-9), "{e:?}");
    let json: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("second.json")).unwrap()).unwrap();
    let m = &json["analyses"][0]["measurements"][0];
    assert_eq!((m["name"].as_str(), m["agrees"].as_bool()), (Some("foot"), Some(true)), "{m}");
    let csv = std::fs::read_to_string(out.join("second_analysis_0_steady_state_measurements_force.csv")).unwrap();
    assert!(csv.starts_with("measurement,point,harmonic,frequency [Hz],"), "{csv}");
}

#[test]
fn bad_measurements_are_refused_before_any_solve() {
    let dir = tempfile::tempdir().unwrap();
    let t: Vec<f64> = (0..100).map(|i| i as f64 * 1e-4).collect();
    let x = vec![1.0; 100];
    write_csv(&dir.path().join("short.csv"), &t, &[("force (N)", &x), ("acceleration (m/s^2)", &x)]);
    write_csv(&dir.path().join("accel.csv"), &t, &[("acceleration (m/s^2)", &x)]);
    let long: Vec<f64> = (0..400).map(|i| i as f64 * 1e-4).collect();
    write_csv(
        &dir.path().join("long.csv"),
        &long,
        &[("force (N)", &[1.0; 400]), ("acceleration (m/s^2)", &[1.0; 400])],
    );
    let err = |m: &str| {
        let e = run_in(dir.path(), &format!("{CASE}[[measurement]]\n{m}\n")).unwrap_err().to_string();
        assert!(e.contains("measured.toml") || e.contains(".csv"), "{e}");
        e
    };
    let e = err("file = \"missing.csv\"\npoint = \"shaker_stack\"");
    assert!(e.contains("measurement[0].file") && e.contains("missing.csv"), "{e}");
    let e = err("file = \"accel.csv\"\npoint = \"shaker_stack\"\nquantities = [\"power\"]");
    assert!(e.contains("accel.csv") && e.contains("force") && e.contains("power"), "{e}");
    let e = err("file = \"long.csv\"\npoint = \"nowhere\"");
    assert!(e.contains("measurement[0].point") && e.contains("shaker_stack") && e.contains("mid"), "{e}");
    let e = err("file = \"long.csv\"\npoint = \"mid\"\nquantities = [\"force\"]");
    assert!(e.contains("measurement[0].quantities") && e.contains("sensor"), "{e}");
    let e = err("file = \"short.csv\"\npoint = \"shaker_stack\"");
    assert!(e.contains("short.csv") && e.contains("less than one drive period"), "{e}");
    let e = err("file = \"long.csv\"\npoint = \"shaker_stack\"\ntolerance_db = -1");
    assert!(e.contains("measurement[0].tolerance_db"), "{e}");
    // `check` refuses the same way.
    let case = dir.path().join("c.toml");
    std::fs::write(&case, format!("{CASE}[[measurement]]\nfile = \"long.csv\"\npoint = \"nowhere\"\n")).unwrap();
    let e =
        beamflow::app::commands::check(&case, &beamflow::analysis::budget::Budget::default()).unwrap_err().to_string();
    assert!(e.contains("measurement[0].point"), "{e}");
}
