//! `[output] full_history`: a transient keeps every period of its time histories.

mod common;
use beamflow::analysis::case_run::AnalysisResult;
use beamflow::app::runner::run_case;
use common::*;

fn transient(full_history: bool, analysis: &str) -> beamflow::analysis::transient::TransientResult {
    let text = format!(
        "[[actuator]]\ntype = \"frame\"\n[actuator.voltage]\nkind = \"sine\"\namplitude = 12.0\nfrequency = 60.0\n\
         [[analysis]]\ntype = \"transient\"\n{analysis}\n[output]\nfull_history = {full_history}\n"
    );
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
