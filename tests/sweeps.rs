//! Parameter sweeps: reproducibility (threads, shards, merge), resuming, error messages,
//! and the fast steady-state path against `steady_state::run`.

use beamflow::analysis::plan::calibrated_model;
use beamflow::analysis::steady_state;
use beamflow::assembly::System;
use beamflow::case::LoadedCase;
use beamflow::progress::Cancel;
use beamflow::sweep::{self, RunOptions, Shard, SweepTable};
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicUsize, Ordering};
use std::sync::Arc;

/// A small beam (40 elements) keeps each case well under a millisecond.
const BASE: &str = r#"
title = "sweep test base"
[beam.mesh]
elements = 40
[[actuator]]
type = "inertial"
x_e = 0.150
[actuator.voltage]
kind = "sine"
amplitude = 12.0
frequency = 60.0
[[analysis]]
type = "steady_state"
harmonics = 5
samples_per_period = 256
"#;

const FRAME_BASE: &str = r#"
[beam.mesh]
elements = 40
[[actuator]]
type = "frame"
x_e = 0.150
[actuator.voltage]
kind = "sine"
amplitude = 12.0
frequency = 60.0
"#;

/// 5 positions × 4 frequencies = 20 cases.
const SWEEP: &str = r#"
title = "test sweep"
base = "base.toml"
[[parameter]]
path = "actuator[0].x_e"
values = [0.1, 0.2, 0.3, 0.45, 0.6]
[[parameter]]
path = "actuator[0].voltage.frequency"
start = 20.0
stop = 320.0
count = 4
spacing = "log"
"#;

struct Dir {
    dir: tempfile::TempDir,
}

impl Dir {
    fn new() -> Dir {
        let d = Dir { dir: tempfile::tempdir().unwrap() };
        d.write("base.toml", BASE);
        d.write("frame.toml", FRAME_BASE);
        d
    }
    fn path(&self, name: &str) -> PathBuf {
        self.dir.path().join(name)
    }
    fn write(&self, name: &str, text: &str) -> PathBuf {
        let p = self.path(name);
        std::fs::write(&p, text).unwrap();
        p
    }
    fn sweep(&self, name: &str, text: &str) -> sweep::Sweep {
        sweep::load(&self.write(name, text)).unwrap()
    }
    fn error(&self, text: &str) -> String {
        match sweep::load(&self.write("bad.sweep.toml", text)) {
            Ok(_) => panic!("sweep was accepted but should be rejected:\n{text}"),
            Err(e) => e.to_string(),
        }
    }
}

/// Serialises the tests that open HDF5 files with the one that starts `beamflow`
/// processes: libhdf5 opens files without close-on-exec, so a child started while another
/// test has a file open inherits the descriptor and its lock, and reopening that file then
/// fails with "unable to lock file" until the child exits.
static HDF5_AND_CHILDREN: std::sync::Mutex<()> = std::sync::Mutex::new(());

fn exclusive() -> std::sync::MutexGuard<'static, ()> {
    HDF5_AND_CHILDREN.lock().unwrap_or_else(|e| e.into_inner())
}

fn threads(n: usize) -> RunOptions {
    RunOptions { threads: Some(n), ..Default::default() }
}

fn counter() -> (Arc<AtomicUsize>, sweep::OnEvaluated) {
    let c = Arc::new(AtomicUsize::new(0));
    let c2 = c.clone();
    (
        c,
        Arc::new(move |_| {
            c2.fetch_add(1, Ordering::SeqCst);
        }),
    )
}

#[test]
fn expansion_is_cartesian_last_fastest_or_zipped() {
    let d = Dir::new();
    let s = d.sweep("s.sweep.toml", SWEEP);
    assert_eq!(s.len(), 20);
    let cases = s.cases();
    assert_eq!(cases[0].1, vec![("actuator[0].x_e".to_string(), 0.1), ("actuator[0].voltage.frequency".into(), 20.0)]);
    assert_eq!(cases[1].1[1].1, 20.0 * (16.0f64).powf(1.0 / 3.0));
    assert_eq!(cases[4].1[0].1, 0.2);
    assert_eq!(cases[19].1[1].1, 320.0);
    let lc = s.case(6).unwrap();
    assert_eq!(lc.case.actuator[0].x_e, 0.2);
    assert!(lc.case.analysis.is_empty(), "the base case's analyses are not run by a sweep");
    assert_eq!(s.harmonics, 5, "harmonics come from the base case's steady_state analysis");
    assert_eq!(s.samples_per_period, 256);
    assert!(s.base.cached_damping.is_some());

    let z = d.sweep(
        "z.sweep.toml",
        "base = \"base.toml\"\ncombine = \"zip\"\n[[parameter]]\npath = \"actuator[0].x_e\"\nvalues = [0.1, 0.2]\n\
         [[parameter]]\npath = \"actuator[0].m_t\"\nvalues = [0.1, 0.5]\n[[parameter]]\npath = \"damping.zeta\"\n\
         values = [0.01, 0.02]\n",
    );
    assert_eq!(z.len(), 2);
    assert_eq!(z.values(1), vec![0.2, 0.5, 0.02]);
    assert!(z.base.cached_damping.is_none(), "a sweep over damping must not cache it");
    assert_eq!(z.case(1).unwrap().case.damping.zeta, 0.02);
    // An integer field the base leaves at its default.
    let m = d.sweep(
        "m.sweep.toml",
        "base = \"base.toml\"\n[[parameter]]\npath = \"beam.mesh.elements\"\nvalues = [20, 30]\n",
    );
    assert_eq!(m.case(1).unwrap().case.beam.mesh.elements, 30);
}

#[test]
fn results_do_not_depend_on_thread_count() {
    let d = Dir::new();
    let s = d.sweep("s.sweep.toml", SWEEP);
    let one = sweep::run(&s, &threads(1)).unwrap();
    let two = sweep::run(&s, &threads(2)).unwrap();
    assert_eq!(one.rows.len(), 20);
    assert!(one.is_complete());
    assert!(one.bitwise_eq(&two), "1 and 2 threads gave different tables");
    assert!(one.rows.windows(2).all(|w| w[0].index < w[1].index));
    // Every case is physical: positive power, and it balances the beam's dissipation.
    for r in &one.rows {
        assert!(r.net_power[0] > 0.0, "case {}: {}", r.index, r.net_power[0]);
        assert!(r.balance_error < 1e-6, "case {}: balance error {}", r.index, r.balance_error);
        assert!(r.force_amplitude[0] > 0.0);
    }
}

#[test]
fn merge_of_shards_equals_single_run_bitwise() {
    let _serial = exclusive();
    let d = Dir::new();
    let sp = d.write("s.sweep.toml", SWEEP);
    let s = sweep::load(&sp).unwrap();
    let single = d.path("single.h5");
    sweep::execute(&s, &single, &threads(2)).unwrap();
    let mut shards = Vec::new();
    for k in 1..=3 {
        let out = d.path(&format!("shard{k}.h5"));
        let ex = sweep::execute(&s, &out, &RunOptions { shard: Shard { k, n: 3 }, ..threads(1) }).unwrap();
        assert_eq!(ex.table.rows.len(), Shard { k, n: 3 }.indices(20).len());
        assert!(ex.table.rows.iter().all(|r| r.index % 3 == k - 1));
        assert!(!sweep::parts_dir(&out).exists(), "checkpoints are removed once the table is written");
        shards.push(out);
    }
    // Out of order on purpose: merge sorts by case index.
    let merged = sweep::merge_files(&[&shards[2], &shards[0], &shards[1]]).unwrap();
    let from_file = SweepTable::read(&single).unwrap();
    assert!(merged.bitwise_eq(&from_file), "merge of 3 shards differs from the single run");
    let merged_path = d.path("merged.h5");
    merged.write(&merged_path).unwrap();
    assert!(SweepTable::read(&merged_path).unwrap().bitwise_eq(&from_file));
    assert_eq!(
        std::fs::read(&merged_path).unwrap(),
        std::fs::read(&single).unwrap(),
        "the merged file and the single-run file differ byte for byte"
    );
    assert_eq!(from_file.sweep_text, SWEEP);
    assert_eq!(from_file.units, vec!["m", "Hz"]);

    // Missing, duplicated, foreign shards.
    let e = sweep::merge_files(&[&shards[0], &shards[1]]).unwrap_err().to_string();
    assert!(e.contains("shard1.h5") && e.contains("6 of 20 cases are missing") && e.contains("e.g. 2, 5"), "{e}");
    let e = sweep::merge_files(&[&shards[0], &shards[1], &shards[2], &shards[1]]).unwrap_err().to_string();
    assert!(e.contains("shard2.h5") && e.contains("case 1 is also in") && e.contains("case_index"), "{e}");
    let other = d.sweep("o.sweep.toml", &SWEEP.replace("0.6]", "0.61]"));
    let op = d.path("other.h5");
    sweep::execute(&other, &op, &RunOptions { shard: Shard { k: 3, n: 3 }, ..threads(2) }).unwrap();
    let e = sweep::merge_files(&[&shards[0], &shards[1], &op]).unwrap_err().to_string();
    assert!(e.contains("other.h5") && e.contains("different sweep") && e.contains("sweep_hash"), "{e}");
}

#[test]
fn interrupted_sweep_resumes_without_recomputing() {
    let _serial = exclusive();
    let d = Dir::new();
    let s = d.sweep("s.sweep.toml", SWEEP);
    let reference = sweep::run(&s, &threads(2)).unwrap();

    // Library level: a checkpoint directory and a cancel flag set after 7 evaluations.
    let parts = d.path("parts");
    let cancel = Cancel::new();
    let (c1, cb) = counter();
    let (flag, seen) = (cancel.clone(), c1.clone());
    let stop_after_7: sweep::OnEvaluated = Arc::new(move |i| {
        cb(i);
        if seen.load(Ordering::SeqCst) >= 7 {
            flag.cancel();
        }
    });
    let opts = RunOptions {
        checkpoint: Some(parts.clone()),
        cancel: Some(cancel),
        on_evaluated: Some(stop_after_7),
        ..threads(2)
    };
    let partial = sweep::run(&s, &opts).unwrap();
    let first = c1.load(Ordering::SeqCst);
    assert!((7..20).contains(&first), "{first} cases before the stop took effect");
    assert_eq!(partial.rows.len(), first);
    assert_eq!(partial.missing().len(), 20 - first);
    // Checkpoint files hold fixed-length rows (`encode_part`): count the rows saved.
    let record = sweep::encode_part(&reference.rows[0], &s.hash).len();
    let saved: usize = std::fs::read_dir(&parts)
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|e| e == "bin"))
        .map(|p| std::fs::read(p).unwrap().len() / record)
        .sum();
    assert_eq!(saved, first, "every finished case is checkpointed");

    let (c2, cb2) = counter();
    let resumed =
        sweep::run(&s, &RunOptions { checkpoint: Some(parts.clone()), on_evaluated: Some(cb2), ..threads(2) }).unwrap();
    assert_eq!(c2.load(Ordering::SeqCst), 20 - first, "finished cases must not be recomputed");
    assert!(resumed.bitwise_eq(&reference), "a resumed sweep differs from an uninterrupted one");

    // A damaged checkpoint row is recomputed, not trusted (and only that row).
    let victim = std::fs::read_dir(&parts)
        .unwrap()
        .map(|e| e.unwrap().path())
        .find(|p| p.extension().is_some_and(|e| e == "bin"))
        .unwrap();
    let mut bytes = std::fs::read(&victim).unwrap();
    bytes[record / 2] ^= 0x55;
    std::fs::write(&victim, &bytes).unwrap();
    let (c3, cb3) = counter();
    let again =
        sweep::run(&s, &RunOptions { checkpoint: Some(parts.clone()), on_evaluated: Some(cb3), ..threads(1) }).unwrap();
    assert_eq!(c3.load(Ordering::SeqCst), 1);
    assert!(again.bitwise_eq(&reference));

    // CLI level (`execute`): an interrupted run leaves FILE.h5.parts and no table; the rerun
    // computes the rest; a third run computes nothing.
    let out = d.path("resume.h5");
    let cancel = Cancel::new();
    let flag = cancel.clone();
    let stop_now: sweep::OnEvaluated = Arc::new(move |_| flag.cancel());
    let e = sweep::execute(&s, &out, &RunOptions { cancel: Some(cancel), on_evaluated: Some(stop_now), ..threads(1) })
        .unwrap_err()
        .to_string();
    assert!(e.contains("resume.h5") && e.contains("interrupted with 1 of 20") && e.contains("rerun"), "{e}");
    assert!(!out.exists() && sweep::parts_dir(&out).exists());
    let ex = sweep::execute(&s, &out, &threads(2)).unwrap();
    assert_eq!((ex.computed, ex.reused), (19, 1));
    assert!(ex.table.bitwise_eq(&reference));
    let ex = sweep::execute(&s, &out, &threads(2)).unwrap();
    assert_eq!((ex.computed, ex.reused), (0, 20));
    // Another sweep must not write over it.
    let other = d.sweep("o.sweep.toml", &SWEEP.replace("0.6]", "0.61]"));
    let e = sweep::execute(&other, &out, &threads(1)).unwrap_err().to_string();
    assert!(e.contains("resume.h5") && e.contains("another sweep"), "{e}");
}

#[test]
fn bad_sweep_files_give_clear_errors() {
    let d = Dir::new();
    let head = "base = \"base.toml\"\n[[parameter]]\n";
    let cases: &[(&str, &[&str])] = &[
        // Unknown field path in the case schema.
        (
            "path = \"actuator[0].x_f\"\nvalues = [0.1]",
            &["bad.sweep.toml", "parameter[0].path", "actuator[0].x_f", "unknown field `x_f`"],
        ),
        ("path = \"actuator[0].voltage.frequncy\"\nvalues = [10.0]", &["parameter[0].path", "frequncy"]),
        ("path = \"actuator[1].x_e\"\nvalues = [0.1]", &["parameter[0].path", "1 entries in `actuator`"]),
        ("path = \"actuator[x].x_e\"\nvalues = [0.1]", &["parameter[0].path", "name[N]"]),
        // Values.
        ("path = \"actuator[0].x_e\"\nvalues = []", &["bad.sweep.toml", "parameter[0].values", "empty"]),
        ("path = \"actuator[0].x_e\"", &["parameter[0]", "no values"]),
        (
            "path = \"actuator[0].x_e\"\nvalues = [0.1, 0.9]",
            &["parameter[0].values", "actuator[0].x_e = 0.9", "outside the beam"],
        ),
        ("path = \"actuator[0].voltage.frequency\"\nvalues = [-5.0]", &["parameter[0].values", "frequency = -5"]),
        // Ranges.
        ("path = \"actuator[0].x_e\"\nstart = 0.1\nstop = 0.5\ncount = 0", &["parameter[0].count", "at least 1"]),
        ("path = \"actuator[0].x_e\"\nstart = 0.1\ncount = 4", &["parameter[0].stop", "start`, `stop` and `count"]),
        (
            "path = \"actuator[0].voltage.frequency\"\nstart = 0.0\nstop = 100.0\ncount = 4\nspacing = \"log\"",
            &["parameter[0].start", "log range needs positive"],
        ),
        ("path = \"actuator[0].x_e\"\nstart = 0.2\nstop = 0.2\ncount = 3", &["parameter[0].stop", "start ≠ stop"]),
        (
            "path = \"actuator[0].x_e\"\nvalues = [0.1]\nstart = 0.1\nstop = 0.2\ncount = 2",
            &["parameter[0]", "not both"],
        ),
        ("path = \"actuator[0].x_e\"\nvalues = [0.1]\nstep = 2", &["bad.sweep.toml", "unknown field `step`"]),
        // Integer fields.
        ("path = \"beam.mesh.elements\"\nvalues = [20.5]", &["parameter[0]", "elements"]),
    ];
    for (param, needles) in cases {
        let e = d.error(&format!("{head}{param}\n"));
        for n in *needles {
            assert!(e.contains(n), "message for\n{param}\nlacks {n:?}: {e}");
        }
    }
    // Whole-file problems.
    let e = d.error("base = \"missing.toml\"\n[[parameter]]\npath = \"actuator[0].x_e\"\nvalues = [0.1]\n");
    assert!(e.contains("bad.sweep.toml") && e.contains("`base`") && e.contains("missing.toml"), "{e}");
    let e = d.error("base = \"base.toml\"\n");
    assert!(e.contains("`parameter`") && e.contains("at least one"), "{e}");
    let e = d.error("base = \"base.toml\"\ncombine = \"zip\"\n[[parameter]]\npath = \"actuator[0].x_e\"\nvalues = [0.1, 0.2]\n[[parameter]]\npath = \"actuator[0].m_t\"\nvalues = [0.1]\n");
    assert!(e.contains("parameter[1]") && e.contains("zip"), "{e}");
    let e = d.error("base = \"base.toml\"\n[[parameter]]\npath = \"actuator[0].x_e\"\nvalues = [0.1]\n[[parameter]]\npath = \"actuator[0].x_e\"\nvalues = [0.2]\n");
    assert!(e.contains("parameter[1].path") && e.contains("already varied"), "{e}");
    let e = d.error(
        "base = \"base.toml\"\nanalysis = \"modal\"\n[[parameter]]\npath = \"actuator[0].x_e\"\nvalues = [0.1]\n",
    );
    assert!(e.contains("bad.sweep.toml") && e.contains("modal"), "{e}");
    // A field of the other actuator type, named with the parameter.
    let e = d.error("base = \"base.toml\"\n[[parameter]]\npath = \"actuator[0].k_l\"\nvalues = [1e9]\n");
    assert!(e.contains("parameter[0]") && e.contains("k_l") && e.contains("frame"), "{e}");
    // A combination that fails only together: the frame's leg off the beam at this offset.
    let s = d.sweep(
        "f.sweep.toml",
        "base = \"frame.toml\"\n[[parameter]]\npath = \"actuator[0].x_e\"\nvalues = [0.05, 0.3]\n\
         [[parameter]]\npath = \"actuator[0].e\"\nvalues = [0.0, 0.02]\n",
    );
    let e = sweep::run(&s, &threads(1)).unwrap_err().to_string();
    assert!(e.contains("f.sweep.toml") && e.contains("case 1") && e.contains("actuator[0].e = 0.02"), "{e}");
    assert!(e.contains("left leg"), "{e}");
    // Modal damping in a transient sweep is refused rather than swept undamped (a
    // steady-state sweep applies it in the complete modal basis: tests/modal_damping.rs).
    d.write("modal.toml", &format!("[damping]\nkind = \"modal\"\nratios = [0.01]\n{FRAME_BASE}"));
    let s = d.sweep(
        "m.sweep.toml",
        "base = \"modal.toml\"\nanalysis = \"transient\"\n[[parameter]]\npath = \"actuator[0].x_e\"\nvalues = [0.3]\n",
    );
    let e = sweep::run(&s, &threads(1)).unwrap_err().to_string();
    assert!(e.contains("m.sweep.toml") && e.contains("damping.kind") && e.contains("modal"), "{e}");

    // Shard specifications name the option.
    for (spec, why) in [("0/3", "1..=3"), ("4/3", "1..=3"), ("1/0", "at least 1"), ("2", "k/N"), ("a/3", "whole")] {
        let e = Shard::parse(spec, "<cli>", "--shard").unwrap_err().to_string();
        assert!(e.contains("<cli>") && e.contains("--shard") && e.contains(spec) && e.contains(why), "{e}");
    }
}

#[test]
fn frequency_sweep_matches_direct_steady_state() {
    let d = Dir::new();
    // A linear stack (no hysteresis): F_p is a pure sine.
    d.write(
        "linear.toml",
        &BASE.replace("[actuator.voltage]", "[actuator.stack]\nhysteresis = false\n[actuator.voltage]"),
    );
    let s = d.sweep(
        "lin.sweep.toml",
        "base = \"linear.toml\"\n[[parameter]]\npath = \"actuator[0].voltage.frequency\"\n\
         values = [15.0, 49.0, 60.0, 137.0, 300.0]\n",
    );
    let fast = sweep::run(&s, &threads(2)).unwrap();
    let reference = sweep::run(&s, &RunOptions { reference: true, ..threads(2) }).unwrap();
    for (r, q) in fast.rows.iter().zip(&reference.rows) {
        // The fast path is steady_state::run without the time-domain reconstruction.
        assert!(r.bitwise_eq(q), "fast path differs from steady_state::run: {r:?} vs {q:?}");
        let f = r.inputs[0];
        // An independent direct run: the case written out by hand, its own Rayleigh damping.
        let text = BASE
            .replace("frequency = 60.0", &format!("frequency = {f:?}"))
            .replace("[actuator.voltage]", "[actuator.stack]\nhysteresis = false\n[actuator.voltage]");
        let lc = LoadedCase::from_str(&text, "direct.toml", d.path("")).unwrap();
        let model = calibrated_model(&lc).unwrap();
        let sys = System::assemble(&model).unwrap();
        let direct = steady_state::run(&model, &sys, 5, 256).unwrap();
        let rel = |a: f64, b: f64| (a - b).abs() / b.abs();
        assert!(
            rel(r.net_power[0], direct.net_power[0]) < 1e-12,
            "{f} Hz: {} vs {}",
            r.net_power[0],
            direct.net_power[0]
        );
        assert!(rel(r.beam_dissipation, direct.beam_dissipation) < 1e-12);
        assert!(rel(r.force_amplitude[0], direct.spectra[0].transmitted[1].norm()) < 1e-12);
        // A linear stack puts all power at the drive frequency.
        let p1 = direct.spectra[0].power[1];
        assert!(rel(p1, direct.net_power[0]) < 1e-9, "{f} Hz: P(f) = {p1}, P = {}", direct.net_power[0]);
    }
    // Power peaks near the first resonance (≈ 50 Hz, lowered a little by the actuator).
    let p: Vec<f64> = fast.rows.iter().map(|r| r.net_power[0]).collect();
    assert!(p[1] > 10.0 * p[0] && p[1] > 10.0 * p[2], "{p:?}");
}

#[test]
fn grouped_evaluation_equals_case_by_case() {
    let d = Dir::new();
    // Hysteresis on; placements × frequencies × amplitudes: two groups of six cases that
    // differ only in the drive.
    for base in ["base.toml", "frame.toml"] {
        let s = d.sweep(
            "g.sweep.toml",
            &format!(
                "base = \"{base}\"\n[[parameter]]\npath = \"actuator[0].voltage.amplitude\"\nvalues = [6.0, 12.0]\n\
                 [[parameter]]\npath = \"actuator[0].x_e\"\nvalues = [0.1, 0.3]\n\
                 [[parameter]]\npath = \"actuator[0].voltage.frequency\"\nvalues = [20.0, 60.0, 137.0]\n"
            ),
        );
        let all: Vec<usize> = (0..s.len()).collect();
        let groups = sweep::group_cases(&s, &all, usize::MAX);
        assert_eq!(groups, vec![vec![0, 1, 2, 6, 7, 8], vec![3, 4, 5, 9, 10, 11]], "{base}");
        assert_eq!(sweep::group_cases(&s, &all, 4)[..2], [vec![0, 1, 2, 6], vec![7, 8]]);
        let grouped = sweep::run(&s, &threads(2)).unwrap();
        let reference = sweep::run(&s, &RunOptions { reference: true, ..threads(1) }).unwrap();
        assert_eq!(grouped.rows.len(), 12);
        for (r, q) in grouped.rows.iter().zip(&reference.rows) {
            let alone = sweep::evaluate(&s, r.index).unwrap();
            assert!(r.bitwise_eq(&alone), "{base}: grouped differs from case by case: {r:?} vs {alone:?}");
            assert!(r.bitwise_eq(q), "{base}: grouped differs from steady_state::run: {r:?} vs {q:?}");
        }
        // Evaluated in another order, one group at a time, the rows are the same.
        let ev = sweep::Evaluator::new(&s, false);
        let mut rows = Vec::new();
        ev.evaluate_group(
            &[8, 2, 6],
            || false,
            |r| {
                rows.push(r);
                Ok(())
            },
        )
        .unwrap();
        for r in &rows {
            assert!(r.bitwise_eq(&grouped.rows[r.index]), "{base}: case {} out of order", r.index);
        }
    }
}

#[test]
fn transient_option_agrees_with_steady_state() {
    let d = Dir::new();
    // 19 harmonics: the steady state then holds the 7th (420 Hz, near mode 4), which
    // carries 1.6 % of the inertial actuator's power; the transient's mean has them all.
    let text = "base = \"base.toml\"\nanalysis = \"transient\"\nharmonics = 19\n[[parameter]]\n\
                path = \"actuator[0].voltage.frequency\"\nvalues = [60.0]\n";
    let tr = sweep::run(&d.sweep("t.sweep.toml", text), &threads(1)).unwrap();
    let ss = sweep::run(&d.sweep("ss.sweep.toml", &text.replace("transient", "steady_state")), &threads(1)).unwrap();
    let (a, b) = (tr.rows[0].net_power[0], ss.rows[0].net_power[0]);
    // Settled to 1e-4 of its own periodic state, the transient differs from the exact one by
    // the time step's frequency warping, (ωΔt)²/12: 3e-5 at the drive with 380 steps a
    // period but 1e-3 at the 7th harmonic, which sits on the flank of mode 4.
    assert!((a - b).abs() / b < 5e-3, "transient {a} vs steady state {b}");
    assert_eq!(tr.analysis, "transient");
}

#[test]
fn cli_sweep_shards_merge_and_report() {
    let _serial = exclusive();
    let d = Dir::new();
    let sp = d.write("s.sweep.toml", SWEEP);
    let exe = env!("CARGO_BIN_EXE_beamflow");
    let run = |args: &[&std::ffi::OsStr]| {
        let o = std::process::Command::new(exe).args(args).output().unwrap();
        (o.status.success(), String::from_utf8_lossy(&o.stdout).into_owned() + &String::from_utf8_lossy(&o.stderr))
    };
    let os = |s: &str| std::ffi::OsString::from(s);
    let p = |p: &Path| p.as_os_str().to_owned();
    for k in 1..=2 {
        let out = d.path(&format!("s{k}.h5"));
        let (ok, text) = run(&[
            &os("sweep"),
            &p(&sp),
            &os("--out"),
            &p(&out),
            &os("--shard"),
            &os(&format!("{k}/2")),
            &os("--threads"),
            &os("1"),
            &os("--no-plots"),
        ]);
        assert!(ok, "{text}");
    }
    let merged = d.path("all.h5");
    let (ok, text) = run(&[&os("merge"), &p(&d.path("s1.h5")), &p(&d.path("s2.h5")), &os("--out"), &p(&merged)]);
    assert!(ok && text.contains("20 cases"), "{text}");
    // The figure in the default formats, PNG and SVG, and no PDF unless asked for.
    assert!(d.path("all.net_power.png").exists() && d.path("all.net_power.svg").exists());
    assert!(!d.path("all.net_power.pdf").exists());
    let md = std::fs::read_to_string(d.path("all.best.md")).unwrap();
    assert!(md.contains("| rank |") && md.contains("Best and worst position for each"), "{md}");
    // The best case in the table is the one with the largest net power.
    let t = SweepTable::read(&merged).unwrap();
    let best = t.rows.iter().max_by(|a, b| a.net_power[0].total_cmp(&b.net_power[0])).unwrap();
    assert!(text.contains(&format!("| 1 | {} |", best.index)), "{text}");

    let (ok, text) = run(&[&os("sweep"), &p(&sp), &os("--out"), &p(&d.path("x.h5")), &os("--shard"), &os("4/3")]);
    assert!(!ok && text.contains("--shard") && text.contains("4/3"), "{text}");
    let (ok, text) = run(&[&os("merge"), &p(&d.path("s1.h5")), &os("--out"), &p(&d.path("y.h5"))]);
    assert!(!ok && text.contains("missing"), "{text}");
}

/// A title is text in `best.md`: its HTML, Markdown and newlines are escaped, so it can
/// neither add markup nor start a heading of its own.
#[test]
fn sweep_title_is_escaped_in_best_md() {
    let _serial = exclusive();
    let d = Dir::new();
    let title = r#"<img src=x onerror=alert(1)>\n# Injected *bold* [link](http://e.x) | `code`"#;
    let sp = d.write(
        "t.sweep.toml",
        &format!(
            "title = \"{title}\"\nbase = \"base.toml\"\n[[parameter]]\npath = \"actuator[0].x_e\"\nvalues = [0.1, 0.3]\n"
        ),
    );
    let out = d.path("t.h5");
    let o = std::process::Command::new(env!("CARGO_BIN_EXE_beamflow"))
        .args([std::ffi::OsStr::new("sweep"), sp.as_os_str(), "--out".as_ref(), out.as_os_str()])
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let md = std::fs::read_to_string(d.path("t.best.md")).unwrap();
    let first = md.lines().next().unwrap();
    assert!(first.starts_with("# Sweep results: \\<img src=x onerror=alert\\(1\\)\\> \\# Injected"), "{md}");
    assert_eq!(md.lines().filter(|l| l.starts_with('#') && !l.starts_with("##")).count(), 1, "{md}");
    // Every character Markdown or HTML reads as markup is escaped with a backslash.
    let title_md = first.trim_start_matches("# Sweep results: ");
    let chars: Vec<char> = title_md.chars().collect();
    for (i, c) in chars.iter().enumerate() {
        if "<>*[]()|`#".contains(*c) {
            assert!(i > 0 && chars[i - 1] == '\\', "`{c}` at {i} reached best.md unescaped: {title_md}");
        }
    }
}

/// With `--csv` the table's CSV beside it is an output too: a sweep whose own file is that
/// CSV's path is refused before anything runs, and the file is left as it was.
#[test]
fn the_csv_beside_a_table_never_replaces_an_input() {
    let _serial = exclusive();
    let d = Dir::new();
    let text = "base = \"base.toml\"\n[[parameter]]\npath = \"actuator[0].x_e\"\nvalues = [0.1, 0.3]\n";
    let sp = d.write("t.csv", text);
    let out = d.path("t.h5");
    let o = std::process::Command::new(env!("CARGO_BIN_EXE_beamflow"))
        .args([std::ffi::OsStr::new("sweep"), sp.as_os_str(), "--out".as_ref(), out.as_os_str(), "--csv".as_ref()])
        .output()
        .unwrap();
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(!o.status.success() && err.contains("--out") && err.contains("t.csv"), "{err}");
    assert_eq!(std::fs::read_to_string(&sp).unwrap(), text);
    assert!(!out.exists());
}
