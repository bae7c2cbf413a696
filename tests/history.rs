//! `[output] full_history`: a transient keeps every period of its time histories.

mod common;
use beamflow::analysis::case_run::AnalysisResult;
use beamflow::app::runner::run_case;
use common::*;

const FRAME: &str = "[[actuator]]\ntype = \"frame\"\n[actuator.voltage]\nkind = \"sine\"\namplitude = 12.0\n\
                     frequency = 60.0\n[[analysis]]\ntype = \"transient\"\n";

fn transient(full_history: bool, analysis: &str) -> beamflow::analysis::transient::TransientResult {
    thinned(full_history, 1, analysis)
}

fn thinned(full_history: bool, every: usize, analysis: &str) -> beamflow::analysis::transient::TransientResult {
    let text = format!("{FRAME}{analysis}\n[output]\nfull_history = {full_history}\nhistory_every = {every}\n");
    let run = run_case(&case(&text)).unwrap();
    match run.results.into_iter().next() {
        Some(AnalysisResult::Transient(t)) => *t,
        _ => panic!("one transient"),
    }
}

#[test]
fn full_history_keeps_every_period_and_changes_nothing_else() {
    for analysis in ["periods = 7", "tolerance = 1e-3"] {
        let (short, full) = (transient(false, analysis), transient(true, analysis));
        assert_eq!(full.periods_run, short.periods_run, "{analysis}: same run");
        let n = full.steps_per_period;
        assert_eq!(short.t.len(), 3 * n, "{analysis}: the default keeps three periods");
        assert_eq!(full.t.len(), full.periods_run * n, "{analysis}: every period kept");
        assert_eq!(full.t[0], 0.0, "from the start of the run");
        // The window the default keeps is the end of the full history, bit for bit.
        let tail = full.t.len() - short.t.len();
        assert_eq!(&full.t[tail..], &short.t[..]);
        for (lf, ls) in full.links.iter().zip(&short.links) {
            assert_eq!(&lf.transmitted[tail..], &ls.transmitted[..], "{analysis}: {}", lf.name);
            assert_eq!(lf.power.len(), full.t.len());
        }
        for (bf, bs) in full.bodies.iter().zip(&short.bodies) {
            assert_eq!(&bf.q[tail..], &bs.q[..]);
        }
        assert_eq!(full.mean_power, short.mean_power, "{analysis}: powers come from the last period");
        // The history starts from rest: the first sample's stretch is zero.
        assert!(full.links.iter().all(|l| l.stretch[0] == 0.0));
    }
}

/// `history_every = k` keeps the last three periods whole and every k-th step of the run
/// before them: the samples kept are the whole history's own, bit for bit, and the powers
/// and spectra (from the last period) are unchanged.
#[test]
fn a_thinned_history_keeps_every_kth_step_before_a_whole_end() {
    let every = 7;
    let (full, thin) = (transient(true, "periods = 9"), thinned(true, every, "periods = 9"));
    let n = full.steps_per_period;
    let early = (full.periods_run - 3) * n;
    let kept: Vec<usize> = (0..early).filter(|i| i % every == 0).chain(early..full.t.len()).collect();
    assert_eq!(thin.t.len(), kept.len());
    let pick = |v: &[f64]| kept.iter().map(|&i| v[i]).collect::<Vec<f64>>();
    assert_eq!(thin.t, pick(&full.t));
    for (lt, lf) in thin.links.iter().zip(&full.links) {
        assert_eq!(lt.transmitted, pick(&lf.transmitted), "{}", lt.name);
        assert_eq!(lt.power, pick(&lf.power), "{}", lt.name);
    }
    for (bt, bf) in thin.bodies.iter().zip(&full.bodies) {
        assert_eq!(bt.q, pick(&bf.q));
    }
    assert_eq!(thin.mean_power, full.mean_power);
    assert_eq!(thin.spectra.len(), full.spectra.len());
}

#[test]
fn history_every_is_refused_without_a_whole_history_or_at_zero() {
    let e = case_error(&format!("{FRAME}[output]\nhistory_every = 10\n"));
    assert!(e.contains("bad.toml") && e.contains("output.history_every") && e.contains("full_history"), "{e}");
    let e = case_error(&format!("{FRAME}[output]\nfull_history = true\nhistory_every = 0\n"));
    assert!(e.contains("output.history_every") && e.contains("0 keeps no step"), "{e}");
}
