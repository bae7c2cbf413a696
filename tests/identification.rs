//! Parameter identification end to end (physics spec §12): synthetic measurements
//! made by the simulator (`synth`) go through files into the identification commands, which
//! must recover the known parameters; their case fragments must load as part of a case; bad
//! files must fail with a message naming the file and the problem.
//!
//! Most round trips call the library functions the CLI calls
//! (`beamflow::app::identify`); the binary itself is run for a full round trip, the
//! reproducibility check and the bad-file errors.

mod common;

use beamflow::actuator::bouc_wen::BoucWen;
use beamflow::app::identify::{
    identify_bouc_wen, identify_dp, identify_modal, synth, BoucWenRequest, DpRequest, ModalRequest, SynthRequest,
};
use beamflow::case::LoadedCase;
use beamflow::identify::bouc_wen_fit::{self, normalised_squared_error, CycleOptions, FitOptions, FitTarget};
use beamflow::identify::dp::DpOptions;
use beamflow::identify::modal_fit::IdentifiedElement;
use beamflow::identify::synth::{SynthKind, SynthOptions};
use beamflow::io::measurement::LoadOptions;
use beamflow::signal::voltage::VoltageInput;
use common::rel;
use std::path::{Path, PathBuf};
use std::process::{Command, Output};

/// The spec's default stack (d_p = 1.3e-7, α = 0.3, β = 0.02, γ = 0.005; k_p = 3e7,
/// c_p = 200, m_p = 0.03) on the inertial actuator (m_t = 0.3), 48 V at 30 Hz, and a frame.
const CASE: &str = r#"title = "identification round trips"
base = "rigid"

[[actuator]]
type = "inertial"
name = "shaker"
m_t = 0.3
[actuator.voltage]
kind = "sine"
amplitude = 48.0
frequency = 30.0

[[actuator]]
type = "frame"
name = "frame"
[actuator.voltage]
kind = "sine"
amplitude = 48.0
frequency = 30.0
"#;

const TRUE: BoucWen = BoucWen { d_p: 1.3e-7, alpha: 0.3, beta: 0.02, gamma: 0.005 };

fn setup() -> (tempfile::TempDir, PathBuf) {
    let dir = tempfile::tempdir().unwrap();
    let case = dir.path().join("case.toml");
    std::fs::write(&case, CASE).unwrap();
    (dir, case)
}

fn make(case: &Path, out: PathBuf, options: SynthOptions) -> Vec<PathBuf> {
    synth(&SynthRequest { case: case.to_path_buf(), out, options, digits: Some(7) }).unwrap().files
}

/// Normalised RMS error of `p`'s periodic loop against the true loop (48 V, 30 Hz).
fn loop_error(p: &BoucWen) -> f64 {
    let input = VoltageInput::sine(48.0, 30.0);
    let a = TRUE.periodic_cycle(&input, 400, 1e-12, 2000).unwrap();
    let b = p.periodic_cycle(&input, 400, 1e-12, 2000).unwrap();
    normalised_squared_error(&a.stroke, &b.stroke).sqrt()
}

/// Loads `text` as a case (it must be valid).
fn load_case(text: &str) -> LoadedCase {
    LoadedCase::from_str(text, "spliced.toml", PathBuf::from("."))
        .unwrap_or_else(|e| panic!("spliced case does not load: {e}\n{text}"))
}

/// An inertial actuator with a stack fragment pasted below its `[[actuator]]` header.
fn splice_stack(fragment: &str) -> LoadedCase {
    load_case(&format!(
        "base = \"rigid\"\n[[actuator]]\ntype = \"inertial\"\nname = \"a\"\n{fragment}\n\
         [actuator.voltage]\nkind = \"sine\"\namplitude = 48.0\nfrequency = 30.0\n"
    ))
}

/// A frame actuator with a leg fragment pasted right below its `[[actuator]]` line.
fn splice_leg(fragment: &str) -> LoadedCase {
    load_case(&format!(
        "base = \"rigid\"\n[[actuator]]\n{fragment}\ntype = \"frame\"\nname = \"f\"\n[actuator.stack]\nk_p = 3.0e7\n\
         [actuator.voltage]\nkind = \"sine\"\namplitude = 48.0\nfrequency = 30.0\n"
    ))
}

fn bin(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_beamflow")).args(args).output().expect("the beamflow binary runs")
}

fn ok(args: &[&str]) -> String {
    let o = bin(args);
    let (out, err) = (String::from_utf8_lossy(&o.stdout), String::from_utf8_lossy(&o.stderr));
    assert!(o.status.success(), "beamflow {args:?} failed:\n{out}\n{err}");
    out.into_owned()
}

fn fails(args: &[&str]) -> String {
    let o = bin(args);
    assert!(!o.status.success(), "beamflow {args:?} should fail");
    let err = String::from_utf8_lossy(&o.stderr).into_owned();
    assert!(err.starts_with("error: "), "{err}");
    err
}

fn s(p: &Path) -> &str {
    p.to_str().unwrap()
}

#[test]
fn dp_from_a_synthetic_pair_within_half_a_percent() {
    let (dir, case) = setup();
    for seed in 1..=4 {
        let files = make(
            &case,
            dir.path().join(format!("pair{seed}.csv")),
            SynthOptions { kind: SynthKind::DpPair, seed, ..SynthOptions::default() },
        );
        assert_eq!(files.len(), 2);
        assert!(files[0].ends_with(format!("pair{seed}_1.csv")) && files[1].ends_with(format!("pair{seed}_2.csv")));
        let out = identify_dp(&DpRequest {
            first: files[0].clone(),
            second: files[1].clone(),
            options: DpOptions::default(),
            load: LoadOptions::default(),
            out: Some(dir.path().join("dp")),
            plots: seed == 1,
        })
        .unwrap();
        let e = &out.estimate;
        let err = rel(e.d_p, TRUE.d_p);
        eprintln!(
            "d_p round trip, seed {seed}: rel error {err:.2e}, stated std error {:.2e}, delta_V {:.4} V",
            e.std_error / e.d_p,
            e.delta_v
        );
        assert!(err < 0.005, "d_p {} vs {}", e.d_p, TRUE.d_p);
        assert!(err < 4.0 * e.std_error / e.d_p, "error not covered by the stated standard error");
        assert!((e.delta_v - 12.0).abs() < 1e-3, "{}", e.delta_v);
        // The fragment loads as part of a case and carries the estimate.
        let lc = splice_stack(&out.fragment);
        assert!(rel(lc.case.actuator[0].stack.d_p, e.d_p) < 1e-5);
        assert_eq!(std::fs::read_to_string(dir.path().join("dp/dp.toml")).unwrap(), out.fragment);
    }
    for f in ["dp.json", "dp-difference.png", "dp-difference.svg"] {
        assert!(dir.path().join("dp").join(f).exists(), "{f}");
    }
}

#[test]
fn bouc_wen_from_a_synthetic_stroke_reproduces_the_true_loop() {
    let (dir, case) = setup();
    let file = make(&case, dir.path().join("stroke.csv"), SynthOptions { seed: 11, ..SynthOptions::default() });
    let req = BoucWenRequest {
        file: file[0].clone(),
        target: FitTarget::Stroke,
        cycle: CycleOptions::default(),
        fit: FitOptions::new(TRUE.d_p),
        seeds: vec![1, 2, 3],
        load: LoadOptions::default(),
        out: Some(dir.path().join("bw")),
        plots: true,
    };
    let out = identify_bouc_wen(&req).unwrap();
    for f in &out.fit.fits {
        assert!(bouc_wen_fit::is_class_one(&f.params), "{:?}", f.params);
        assert_eq!(f.infeasible_candidates, 0);
        assert!(f.history.windows(2).all(|w| w[1] <= w[0]));
    }
    let best = &out.fit.best;
    let le = loop_error(&best.params);
    eprintln!(
        "Bouc-Wen round trip: alpha {:.5} beta {:.5e} gamma {:.5e}; data NRMSE {:.3e}; loop NRMSE vs truth {le:.2e}; \
         iterations {:?}",
        best.params.alpha,
        best.params.beta,
        best.params.gamma,
        best.nrmse,
        out.fit.fits.iter().map(|f| f.iterations).collect::<Vec<_>>()
    );
    assert!(le < 0.01, "loop NRMSE against the true loop {le}");
    // 1 % noise is the floor of the data misfit.
    assert!(best.nrmse > 0.007 && best.nrmse < 0.013, "{}", best.nrmse);
    // The fragment loads, and the loaded case's stack is the identified one (class I is
    // checked again by the case loader).
    let lc = splice_stack(&out.fragment);
    let st = &lc.case.actuator[0].stack;
    assert!(rel(st.alpha, best.params.alpha) < 1e-5 && rel(st.beta, best.params.beta) < 1e-5);
    assert!(rel(st.gamma, best.params.gamma) < 1e-4 && rel(st.d_p, TRUE.d_p) < 1e-9);
    for f in ["bouc-wen.toml", "bouc-wen.json", "bouc-wen-loop.png", "bouc-wen-loop.svg", "bouc-wen-convergence.png"] {
        assert!(dir.path().join("bw").join(f).exists(), "{f}");
    }

    // Blocked force = k_p·stroke, through its own file.
    let file = make(
        &case,
        dir.path().join("blocked.csv"),
        SynthOptions { kind: SynthKind::BlockedForce, seed: 12, ..SynthOptions::default() },
    );
    let out = identify_bouc_wen(&BoucWenRequest {
        file: file[0].clone(),
        target: FitTarget::BlockedForce { k_p: 3.0e7 },
        seeds: vec![7],
        out: None,
        ..req
    })
    .unwrap();
    let le = loop_error(&out.fit.best.params);
    eprintln!("Bouc-Wen from blocked force: loop NRMSE vs truth {le:.2e}");
    assert!(le < 0.01, "{le}");
    assert!(bouc_wen_fit::is_class_one(&out.fit.best.params));
}

#[test]
fn modal_from_a_synthetic_impact_test_of_the_stack_on_its_mass() {
    let (dir, case) = setup();
    let file = make(
        &case,
        dir.path().join("impact.csv"),
        SynthOptions { kind: SynthKind::Impact, seed: 3, ..SynthOptions::default() },
    );
    let (m, k, c): (f64, f64, f64) = (0.3 + 0.03 / 2.0, 3.0e7, 200.0);
    let wn = (k / m).sqrt();
    let zeta = c / (2.0 * (k * m).sqrt());
    let req = ModalRequest {
        out: Some(dir.path().join("modal")),
        ..ModalRequest::new(&file[0], m, IdentifiedElement::Stack)
    };
    let out = identify_modal(&req).unwrap();
    let p = &out.parameters;
    let (ew, ez) = (rel(p.omega_n, wn), rel(p.zeta, zeta));
    let rfp = &out.multi_mode.modes[0];
    eprintln!(
        "impact round trip: omega_n error {ew:.2e}, zeta error {ez:.2e}; k error {:.2e}, c error {:.2e}; \
         RFP fit: {:.2e}, {:.2e}; modal mass {:.4} kg; {} hits of {} samples",
        rel(p.k, k),
        rel(p.c, c),
        rel(rfp.omega_n, wn),
        rel(rfp.zeta, zeta),
        out.modal_mass,
        out.segments,
        out.segment_length
    );
    assert_eq!(out.segments, 8);
    assert!(ew < 0.005, "omega_n {} vs {wn}", p.omega_n);
    assert!(ez < 0.05, "zeta {} vs {zeta}", p.zeta);
    assert!(rel(rfp.omega_n, wn) < 0.005 && rel(rfp.zeta, zeta) < 0.05, "{rfp:?}");
    assert!(rel(out.modal_mass, m) < 0.05, "{}", out.modal_mass);
    // k = m·ω_n², c = 2ζ·m·ω_n in the fragment, as loaded in a case.
    let lc = splice_stack(&out.fragment);
    let st = &lc.case.actuator[0].stack;
    assert!(rel(st.k_p, m * p.omega_n * p.omega_n) < 1e-5 && rel(st.c_p, 2.0 * p.zeta * m * p.omega_n) < 1e-5);
    assert!(rel(st.k_p, k) < 0.01, "k_p {}", st.k_p);
    assert!(rel(st.c_p, c) < 0.06, "c_p {}", st.c_p);
    for f in ["modal.toml", "modal.json", "modal-frf.png", "modal-frf.svg"] {
        assert!(dir.path().join("modal").join(f).exists(), "{f}");
    }
}

#[test]
fn multi_mode_fit_through_a_file() {
    // A 2-DOF chain ground –k1– m1 –k2– m2 with proportional damping, hammer and
    // accelerometer on m2; 6 hits, 1 % noise, written as a measurement CSV.
    use beamflow::identify::frf::{add_hammer_pulse, impact_response};
    use beamflow::identify::pso::Rng;
    use beamflow::identify::synth::add_noise;
    use beamflow::io::measurement::{self, Measurement, Quantity};
    let dir = tempfile::tempdir().unwrap();
    let (m1, m2, k1, k2) = (1.0, 0.5, 4.0e5, 2.0e5);
    let mm = vec![vec![m1, 0.0], vec![0.0, m2]];
    let kk = vec![vec![k1 + k2, -k2], vec![-k2, k2]];
    let (a0, a1) = (8.0, 2.0e-5);
    let cc: Vec<Vec<f64>> = (0..2).map(|i| (0..2).map(|j| a0 * mm[i][j] + a1 * kk[i][j]).collect()).collect();
    let (a, b, cq) = (m1 * m2, -((k1 + k2) * m2 + k2 * m1), k1 * k2);
    let disc: f64 = (b * b - 4.0 * a * cq).sqrt();
    let wn = [((-b - disc) / (2.0 * a)).sqrt(), ((-b + disc) / (2.0 * a)).sqrt()];
    let (dt, n, hits) = (1.0 / 1024.0, 2048, 6);
    let mut f = vec![0.0; hits * n];
    let mut rng = Rng::new(77);
    for h in 0..hits {
        add_hammer_pulse(&mut f, dt, (h * n + 40) as f64 * dt + rng.uniform() * dt, 2e-3, 50.0);
    }
    let mut acc = impact_response(&mm, &cc, &kk, 1, 1, &f, dt).unwrap();
    add_noise(&mut f, 0.01, &mut rng);
    add_noise(&mut acc, 0.01, &mut rng);
    let t: Vec<f64> = (0..f.len()).map(|i| i as f64 * dt).collect();
    let path = dir.path().join("chain.csv");
    let m = Measurement::new("chain", t, vec![(Quantity::Force, f), (Quantity::Acceleration, acc)]).unwrap();
    measurement::write(&path, &m).unwrap();
    let req = ModalRequest {
        modes: 2,
        band: Some((30.0, 300.0)),
        use_mode: 2,
        out: Some(dir.path().join("modal")),
        ..ModalRequest::new(&path, m2, IdentifiedElement::Stack)
    };
    let out = identify_modal(&req).unwrap();
    assert_eq!(out.used, "multi_mode");
    assert_eq!(out.multi_mode.modes.len(), 2, "{:?}", out.multi_mode.modes);
    for (r, mode) in out.multi_mode.modes.iter().enumerate() {
        let zeta = a0 / (2.0 * wn[r]) + a1 * wn[r] / 2.0;
        eprintln!(
            "2-DOF mode {r}: omega_n error {:.2e}, zeta error {:.2e}",
            rel(mode.omega_n, wn[r]),
            rel(mode.zeta, zeta)
        );
        assert!(rel(mode.omega_n, wn[r]) < 0.005 && rel(mode.zeta, zeta) < 0.05, "{mode:?}");
    }
    // Mode 2 gives k and c; the single-mode fit takes the highest peak.
    assert!(rel(out.parameters.omega_n, wn[1]) < 0.005);
    assert!(rel(out.parameters.k, m2 * out.multi_mode.modes[1].omega_n.powi(2)) < 1e-12);
    assert_eq!(out.single_mode.modes.len(), 1);
    assert!(dir.path().join("modal/modal-frf.png").exists());
    // A mode beyond those fitted is refused before the file is read, naming the flags.
    let e = identify_modal(&ModalRequest { use_mode: 3, out: None, ..req }).unwrap_err().to_string();
    assert!(e.contains("--use-mode 3") && e.contains("--modes 2") && !e.contains("chain.csv"), "{e}");
}

#[test]
fn frame_leg_impact_test_gives_a_leg_fragment() {
    let (dir, case) = setup();
    // One frame leg (k_l = 1.5e9, c_l = 100) under half the top beam (0.1 kg): f_n ≈ 19.5 kHz.
    let file = make(
        &case,
        dir.path().join("leg.csv"),
        SynthOptions {
            kind: SynthKind::Impact,
            actuator: Some("frame".into()),
            element: IdentifiedElement::Leg,
            hits: 3,
            seed: 5,
            ..SynthOptions::default()
        },
    );
    let (m, k, c) = (0.1, 1.5e9, 100.0);
    let out = identify_modal(&ModalRequest { plots: false, ..ModalRequest::new(&file[0], m, IdentifiedElement::Leg) })
        .unwrap();
    let p = &out.parameters;
    eprintln!("leg impact: k error {:.2e}, c error {:.2e}", rel(p.k, k), rel(p.c, c));
    assert!(rel(p.k, k) < 0.01 && rel(p.c, c) < 0.06, "{p:?}");
    let lc = splice_leg(&out.fragment);
    let ((kl, cl), (kr, cr)) = legs(&lc.case.actuator[0]);
    assert!(rel(kl, p.k) < 1e-5 && rel(cl, p.c) < 1e-5 && kr == kl && cr == cl);
    // The right leg's fields.
    let right =
        identify_modal(&ModalRequest { plots: false, ..ModalRequest::new(&file[0], m, IdentifiedElement::LegRight) })
            .unwrap();
    let lc = splice_leg(&right.fragment);
    let ((kl, _), (kr, cr)) = legs(&lc.case.actuator[0]);
    assert_eq!(kl, 1.5e9); // the default left leg
    assert!(rel(kr, p.k) < 1e-5 && rel(cr, p.c) < 1e-5);
}

#[test]
fn cli_round_trip_is_reproducible_by_seed() {
    let (dir, case) = setup();
    let d = dir.path();
    let stroke = d.join("stroke.csv");
    let printed = ok(&["synth", s(&case), "--out", s(&stroke), "--noise", "0.01", "--seed", "21"]);
    assert!(printed.contains("alpha = 0.3") && printed.contains("600 samples"), "{printed}");
    // The same seed makes the same file.
    let again = d.join("stroke-again.csv");
    ok(&["synth", s(&case), "--out", s(&again), "--seed", "21"]);
    assert_eq!(std::fs::read(&stroke).unwrap(), std::fs::read(&again).unwrap());

    let (o1, o2) = (d.join("run1"), d.join("run2"));
    let mut reports = Vec::new();
    for o in [&o1, &o2] {
        reports.push(ok(&["identify", "bouc-wen", s(&stroke), "--d-p", "1.3e-7", "--seeds", "4,5", "--out", s(o)]));
    }
    let r = &reports[0];
    for word in ["alpha", "beta", "gamma", "cost J", "iterations", "converged", "spread over 2 seed(s)", "holds"] {
        assert!(r.contains(word), "`{word}` missing in\n{r}");
    }
    for f in ["bouc-wen.toml", "bouc-wen.json"] {
        let (a, b) = (std::fs::read_to_string(o1.join(f)).unwrap(), std::fs::read_to_string(o2.join(f)).unwrap());
        assert_eq!(a, b, "{f} differs between two runs with the same seeds");
    }
    let frag = std::fs::read_to_string(o1.join("bouc-wen.toml")).unwrap();
    let lc = splice_stack(&frag);
    assert!(loop_error(&lc.case.actuator[0].stack.bouc_wen()) < 0.01);
    for f in ["bouc-wen-loop.png", "bouc-wen-loop.svg", "bouc-wen-convergence.png", "bouc-wen-convergence.svg"] {
        assert!(std::fs::metadata(o1.join(f)).unwrap().len() > 1000, "{f}");
    }

    // d_p and modal through the binary.
    let pair = d.join("pair.csv");
    ok(&["synth", s(&case), "--out", s(&pair), "--kind", "dp-pair", "--seed", "2"]);
    let r = ok(&["identify", "dp", s(&d.join("pair_1.csv")), s(&d.join("pair_2.csv")), "--out", s(&o1)]);
    assert!(r.contains("d_p") && r.contains("std error") && r.contains("delta_V"), "{r}");
    let lc = splice_stack(&std::fs::read_to_string(o1.join("dp.toml")).unwrap());
    assert!(rel(lc.case.actuator[0].stack.d_p, TRUE.d_p) < 0.005);
    let imp = d.join("impact.csv");
    ok(&["synth", s(&case), "--out", s(&imp), "--kind", "impact", "--hits", "4"]);
    let r = ok(&["identify", "modal", s(&imp), "--mass", "0.315", "--band", "1000,2500", "--out", s(&o1)]);
    assert!(r.contains("k = ") && r.contains("c = ") && r.contains("zeta"), "{r}");
    assert!(r.contains("over 1000.00..2500.00 Hz"), "{r}");
    let lc = splice_stack(&std::fs::read_to_string(o1.join("modal.toml")).unwrap());
    assert!(rel(lc.case.actuator[0].stack.k_p, 3.0e7) < 0.01);
    assert!(o1.join("modal-frf.png").exists());
}

#[test]
fn measurements_from_a_results_file() {
    // A transient run's drive record (voltage, stroke, f_p) read from the HDF5 file.
    let (dir, case) = setup();
    let text = format!("{CASE}\n[[analysis]]\ntype = \"transient\"\n");
    std::fs::write(&case, text).unwrap();
    let run = dir.path().join("run");
    ok(&["run", s(&case), "--out", s(&run), "--no-plots"]);
    let h5 = run.join("case.h5");
    assert!(h5.exists());
    let quick = FitOptions {
        pso: beamflow::identify::pso::PsoOptions { max_iterations: 120, ..Default::default() },
        ..FitOptions::new(TRUE.d_p)
    };
    let req = BoucWenRequest {
        file: PathBuf::from(format!("{}:shaker", h5.display())),
        target: FitTarget::Stroke,
        cycle: CycleOptions::default(),
        fit: quick,
        seeds: vec![1],
        load: LoadOptions::default(),
        out: None,
        plots: false,
    };
    let out = identify_bouc_wen(&req).unwrap();
    assert!(out.data.file.ends_with("/analysis_0_transient/drives/shaker"), "{}", out.data.file);
    let le = loop_error(&out.fit.best.params);
    eprintln!("Bouc-Wen from HDF5 (noise-free): loop NRMSE {le:.2e}");
    assert!(le < 1e-3, "{le}");
    // The blocked force is the recorded f_p = k_p·stroke.
    let bf = identify_bouc_wen(&BoucWenRequest {
        target: FitTarget::BlockedForce { k_p: 3.0e7 },
        file: PathBuf::from(format!("{}:analysis_0_transient/frame", h5.display())),
        ..req.clone()
    })
    .unwrap();
    assert!(loop_error(&bf.fit.best.params) < 1e-3);
    // A missing actuator names the file and what exists.
    let e = identify_bouc_wen(&BoucWenRequest { file: PathBuf::from(format!("{}:nope", h5.display())), ..req })
        .unwrap_err()
        .to_string();
    assert!(e.contains("case.h5") && e.contains("nope") && e.contains("analysis_0_transient"), "{e}");
}

/// A file with the given header and rows.
fn csv(dir: &Path, name: &str, header: &str, rows: &[String]) -> PathBuf {
    let p = dir.join(name);
    std::fs::write(&p, format!("{header}\n{}\n", rows.join("\n"))).unwrap();
    p
}

#[test]
fn bad_files_fail_with_the_file_and_the_problem() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let head = "time (s),voltage (V),displacement (m)";
    let row = |i: usize, dv: f64, scale: f64| {
        let t = i as f64 * 1e-3;
        let v = scale * 48.0 * (2.0 * std::f64::consts::PI * 10.0 * t).sin() + dv;
        format!("{t:e},{v:e},{:e}", 1.3e-7 * v)
    };
    let good: Vec<String> = (0..300).map(|i| row(i, 0.0, 1.0)).collect();
    let good_path = csv(d, "good.csv", head, &good);
    let bw = |p: &Path| fails(&["identify", "bouc-wen", s(p), "--d-p", "1.3e-7", "--out", s(&d.join("o"))]);

    // Missing column.
    let p = csv(
        d,
        "nodisp.csv",
        "time (s),voltage (V)",
        &good.iter().map(|r| r.rsplit_once(',').unwrap().0.to_string()).collect::<Vec<_>>(),
    );
    let e = bw(&p);
    assert!(e.contains("nodisp.csv") && e.contains("displacement") && e.contains("column missing"), "{e}");
    // Unequal lengths: a short row.
    let mut rows = good.clone();
    rows[10] = rows[10].rsplit_once(',').unwrap().0.to_string();
    let e = bw(&csv(d, "short.csv", head, &rows));
    assert!(e.contains("short.csv") && e.contains("row 11") && e.contains("same length"), "{e}");
    // NaN.
    let mut rows = good.clone();
    rows[5] = "5e-3,NaN,1e-6".into();
    let e = bw(&csv(d, "nan.csv", head, &rows));
    assert!(e.contains("nan.csv") && e.contains("voltage") && e.contains("not finite"), "{e}");
    // Non-increasing time.
    let mut rows = good.clone();
    rows[7] = rows[6].clone();
    let e = bw(&csv(d, "repeat.csv", head, &rows));
    assert!(e.contains("repeat.csv") && e.contains("time") && e.contains("strictly increasing"), "{e}");
    // Non-uniform sampling: a gap.
    let rows: Vec<String> = (0..300).map(|i| row(if i < 150 { i } else { i + 1 }, 0.0, 1.0)).collect();
    let e = bw(&csv(d, "gap.csv", head, &rows));
    assert!(e.contains("gap.csv") && e.contains("time") && e.contains("uniform"), "{e}");
    // A pair without a constant voltage offset: the second voltage is scaled.
    let scaled = csv(d, "scaled.csv", head, &(0..300).map(|i| row(i, 3.0, 1.1)).collect::<Vec<_>>());
    let e = fails(&["identify", "dp", s(&good_path), s(&scaled), "--out", s(&d.join("o"))]);
    assert!(e.contains("good.csv") && e.contains("scaled.csv") && e.contains("not a constant voltage offset"), "{e}");
    // The same record twice: zero offset.
    let e = fails(&["identify", "dp", s(&good_path), s(&good_path), "--out", s(&d.join("o"))]);
    assert!(e.contains("not a constant voltage offset"), "{e}");
    // An impact test without acceleration; a file that does not exist.
    let e = fails(&["identify", "modal", s(&good_path), "--mass", "0.3", "--out", s(&d.join("o"))]);
    assert!(e.contains("good.csv") && e.contains("force") && e.contains("column missing"), "{e}");
    let missing = d.join("absent.csv");
    let e = bw(&missing);
    assert!(e.contains("absent.csv"), "{e}");
    // Bad arguments name the option.
    let e = fails(&["identify", "bouc-wen", s(&good_path), "--d-p", "1.3e-7", "--target", "force"]);
    assert!(e.contains("--k-p"), "{e}");
    let e = fails(&["identify", "modal", s(&good_path), "--mass=-1"]);
    assert!(e.contains("--mass"), "{e}");
    // Nothing was written by the failed commands.
    assert!(!d.join("o").join("bouc-wen.toml").exists() && !d.join("o").join("dp.toml").exists());
}

/// ((k_l, c_l) left, (k_l, c_l) right) of a frame actuator.
fn legs(a: &beamflow::case::ActuatorSpec) -> ((f64, f64), (f64, f64)) {
    match &a.body {
        beamflow::case::BodySpec::Frame(f) => ((f.left.k_l, f.left.c_l), (f.right.k_l, f.right.c_l)),
        other => panic!("not a frame: {other:?}"),
    }
}
