//! A run's figures and its report: what they show is checked against the results they
//! are drawn from.

mod common;

use beamflow::analysis::case_run::{AnalysisResult, CaseRun};
use beamflow::analysis::steady_state::SteadyStateResult;
use beamflow::app::runner::run_case;
use beamflow::case::LoadedCase;
use beamflow::report::figures::{analysis_tags, modal_power_figure};
use std::path::Path;

fn shipped(name: &str) -> LoadedCase {
    LoadedCase::load(&Path::new(env!("CARGO_MANIFEST_DIR")).join("cases").join(name)).unwrap()
}

fn steady(run: &CaseRun) -> &SteadyStateResult {
    run.results
        .iter()
        .find_map(|r| if let AnalysisResult::SteadyState(s) = r { Some(s.as_ref()) } else { None })
        .expect("a steady_state analysis")
}

/// The bars by mode of each actuator add up to its net power, which the steady state
/// computes from the point spectra, not from modes; the `rest` bar is what the modes not
/// drawn carry plus what the truncated modal sum misses, and every mode left out of the
/// figure carries less than 1 % of its actuator's power.
#[test]
fn the_bars_by_mode_add_up_to_each_actuators_net_power() {
    let run = run_case(&shipped("two-frames.toml")).unwrap();
    let s = steady(&run);
    let m = s.modal.as_ref().expect("modal decomposition");
    let bar = modal_power_figure(m, &run, s);
    let shown: Vec<usize> = bar.categories[..bar.categories.len() - 1]
        .iter()
        .map(|c| c.lines().next().unwrap().parse::<usize>().unwrap() - 1)
        .collect();
    assert_eq!(bar.categories.last().unwrap(), "rest");
    assert_eq!(bar.groups.len(), 2);
    for (a, (name, v)) in bar.groups.iter().enumerate() {
        let net = s.net_power[a];
        let sum: f64 = v.iter().sum();
        assert!((sum - net).abs() <= 1e-12 * net.abs(), "{name}: bars {sum:e} W, net power {net:e} W");
        let links: Vec<usize> = (0..run.system.links.len()).filter(|&l| run.system.links[l].actuator == a).collect();
        let per_mode = |r: usize| links.iter().map(|&l| m.point_power[l][r]).sum::<f64>();
        let hidden: f64 = (0..m.mode_frequency_hz.len()).filter(|r| !shown.contains(r)).map(per_mode).sum();
        let residual: f64 = links.iter().map(|&l| m.point_residual[l]).sum();
        let rest = *v.last().unwrap();
        let scale: f64 = (0..m.mode_frequency_hz.len()).map(|r| per_mode(r).abs()).sum();
        assert!(
            (rest - hidden - residual).abs() <= 1e-9 * scale,
            "{name}: rest {rest:e} W, hidden modes {hidden:e} W + residual {residual:e} W"
        );
        if shown.len() < 16 {
            for r in (0..m.mode_frequency_hz.len()).filter(|r| !shown.contains(r)) {
                assert!(per_mode(r).abs() < 0.01 * scale, "{name}: mode {} matters but is not drawn", r + 1);
            }
        }
    }
}

/// Figure files are named by analysis type, numbered only where a type repeats.
#[test]
fn figures_are_named_by_analysis_type() {
    let lc = common::case(
        "[beam.mesh]\nelements = 20\n[[actuator]]\ntype = \"inertial\"\nx_e = 0.2\n\
         [actuator.voltage]\nkind = \"sine\"\namplitude = 12.0\nfrequency = 60.0\n\
         [[analysis]]\ntype = \"modes\"\ncount = 4\n\
         [[analysis]]\ntype = \"steady_state\"\nharmonics = 3\n\
         [[analysis]]\ntype = \"steady_state\"\nharmonics = 5\n",
    );
    let run = run_case(&lc).unwrap();
    assert_eq!(analysis_tags(&run), ["modes", "steady_state_1", "steady_state_2"]);
    let dir = tempfile::tempdir().unwrap();
    let files = beamflow::report::figures::plot_run(dir.path(), "c", &run).unwrap();
    let names: Vec<String> = files.iter().map(|p| p.file_name().unwrap().to_string_lossy().into_owned()).collect();
    for want in ["c_modes.svg", "c_steady_state_1_inertial_spectrum.png", "c_steady_state_2_power_by_mode.svg"] {
        assert!(names.iter().any(|n| n == want), "{want} not among {names:?}");
    }
}
