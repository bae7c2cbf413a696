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

/// The `data-value` numbers of a page (exact values of its table cells).
fn data_values(html: &str) -> Vec<f64> {
    html.split("data-value=\"").skip(1).filter_map(|s| s.split('"').next()?.parse().ok()).collect()
}

/// Every number of a JSON value.
fn json_numbers(v: &serde_json::Value, out: &mut Vec<f64>) {
    match v {
        serde_json::Value::Number(n) => out.push(n.as_f64().unwrap()),
        serde_json::Value::Array(a) => a.iter().for_each(|x| json_numbers(x, out)),
        serde_json::Value::Object(m) => m.values().for_each(|x| json_numbers(x, out)),
        _ => {}
    }
}

/// `beamflow run` writes report.html beside its other outputs: every figure inline, every
/// number of the JSON summary exactly, the case text, and nothing it would have to fetch.
#[test]
fn the_report_holds_every_figure_and_every_number_of_the_summary() {
    let dir = tempfile::tempdir().unwrap();
    let case = Path::new(env!("CARGO_MANIFEST_DIR")).join("cases/beam-frame-12V-60Hz.toml");
    let out = dir.path().join("out");
    beamflow::app::commands::run(&case, Some(&out), None, true, false, &beamflow::analysis::budget::Budget::default())
        .unwrap();
    let html = std::fs::read_to_string(out.join("report.html")).unwrap();
    let svgs: Vec<String> = std::fs::read_dir(&out)
        .unwrap()
        .flatten()
        .map(|e| e.file_name().to_string_lossy().into_owned())
        .filter(|n| n.ends_with(".svg"))
        .collect();
    assert!(svgs.len() >= 10, "{svgs:?}");
    assert_eq!(html.matches("<svg").count(), svgs.len());
    for s in &svgs {
        // Each figure under its anchor, linked to its files.
        let stem = s.trim_end_matches(".svg");
        assert!(html.contains(&format!("<figure id=\"fig-{stem}\">")), "{s} is not in the report");
        for f in [s.clone(), format!("{stem}.png")] {
            assert!(html.contains(&format!("<a href=\"{f}\">")), "{f} is not linked");
        }
    }
    let summary: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("beam-frame-12V-60Hz.json")).unwrap()).unwrap();
    let mut numbers = Vec::new();
    json_numbers(&summary, &mut numbers);
    let shown = data_values(&html);
    assert!(numbers.len() > 100, "{}", numbers.len());
    // serde_json reads a float back to within an ulp or two (without its `float_roundtrip`
    // feature), so "exactly" is to 10⁻¹⁵ here.
    for v in numbers {
        assert!(shown.iter().any(|s| (s - v).abs() <= 1e-15 * v.abs()), "{v:e} of the JSON is not in the report");
    }
    // The headline: the net power with its unit, and the case file itself.
    let net = summary["analyses"][0]["net_power_w"]["frame"].as_f64().unwrap();
    assert!(html.contains(&format!("data-value=\"{net:e}\" title=\"{net:e}\">6.323 µW<")), "net power {net:e}");
    assert!(html.contains("x_e = 0.150") && html.contains("<pre>"));
    assert!(!html.contains("<script") && !html.contains(" src=") && !html.contains("https://"));
}

/// Text from the case (title, names, the file) is escaped: a title holding markup shows as
/// text and cannot inject any.
#[test]
fn the_report_escapes_what_the_user_wrote() {
    let dir = tempfile::tempdir().unwrap();
    let case = dir.path().join("c&<x>.toml");
    std::fs::write(
        &case,
        "title = \"<script>alert('t')</script> & <b>\"\n[beam.mesh]\nelements = 10\n\
         [[actuator]]\ntype = \"inertial\"\nx_e = 0.2\n\
         [actuator.voltage]\nkind = \"sine\"\namplitude = 12.0\nfrequency = 60.0\n\
         [[analysis]]\ntype = \"steady_state\"\nharmonics = 3\n",
    )
    .unwrap();
    let out = dir.path().join("out");
    beamflow::app::commands::run(&case, Some(&out), None, false, false, &beamflow::analysis::budget::Budget::default())
        .unwrap();
    let html = std::fs::read_to_string(out.join("report.html")).unwrap();
    assert!(!html.contains("<script") && !html.contains("<b>") && !html.contains("<x>"), "{html}");
    assert!(html.contains("&lt;script&gt;alert(&#39;t&#39;)&lt;/script&gt; &amp; &lt;b&gt;"));
    assert!(html.contains("c&amp;&lt;x&gt;.toml"));
}

/// A linear stack (no hysteresis) on a small beam: `amplitude` V at 60 Hz, then `rest`.
fn linear_case(amplitude: f64, rest: &str) -> String {
    format!(
        "[beam.mesh]\nelements = 20\n[damping]\nkind = \"rayleigh\"\na0 = 5.0\na1 = 1e-5\n\
         [[actuator]]\ntype = \"inertial\"\nname = \"shaker\"\nx_e = 0.2\n\
         [actuator.stack]\nhysteresis = false\n\
         [actuator.voltage]\nkind = \"sine\"\namplitude = {amplitude}\nfrequency = 60.0\n{rest}"
    )
}

/// Measured data and the coupled system reach the figures and the report: a measurement
/// made at 5 % more voltage on a linear stack is 20·log₁₀(1.05) dB above the prediction at
/// every harmonic, which the report's measurement table states (and, with a tolerance
/// below it, warns about); the coupled transfer functions and modes are drawn and inline.
#[test]
fn measurements_and_the_coupled_system_appear_in_figures_and_report() {
    let dir = tempfile::tempdir().unwrap();
    let steady = "[[analysis]]\ntype = \"steady_state\"\nharmonics = 5\n";
    let bench = dir.path().join("bench.toml");
    std::fs::write(&bench, linear_case(12.6, steady)).unwrap();
    beamflow::app::commands::run(
        &bench,
        Some(&dir.path().join("bench")),
        None,
        false,
        false,
        &beamflow::analysis::budget::Budget::default(),
    )
    .unwrap();
    let analyses = "[[analysis]]\ntype = \"modes\"\ncount = 4\n\
                    [[analysis]]\ntype = \"harmonic\"\nsystem = \"coupled\"\n\
                    [analysis.frequencies]\nvalues = [30.0, 60.0, 90.0]\n";
    let measurement = |tol: f64| {
        format!(
            "[[measurement]]\nname = \"bench\"\nfile = \"bench/bench.h5:analysis_0_steady_state\"\n\
             point = \"shaker_stack\"\nquantities = [\"force\"]\ntolerance_db = {tol}\n"
        )
    };
    let offset = 20.0 * 1.05f64.log10();
    for (tol, agrees) in [(1.0, true), (0.1, false)] {
        let case = dir.path().join("c.toml");
        std::fs::write(&case, linear_case(12.0, &format!("{analyses}{steady}{}", measurement(tol)))).unwrap();
        let out = dir.path().join(format!("out{tol}"));
        beamflow::app::commands::run(
            &case,
            Some(&out),
            None,
            true,
            false,
            &beamflow::analysis::budget::Budget::default(),
        )
        .unwrap();
        let html = std::fs::read_to_string(out.join("report.html")).unwrap();
        // Without forces the harmonic analysis has transfer functions only: no mobility figure.
        assert!(!out.join("c_harmonic.png").exists());
        for f in ["c_steady_state_measured_bench", "c_harmonic_transfer", "c_modes_coupled"] {
            assert!(out.join(format!("{f}.png")).exists(), "{f}.png");
            assert!(html.contains(&format!("<figure id=\"fig-{f}\">")), "{f} is not in the report");
        }
        let shown = data_values(&html);
        assert!(shown.iter().any(|v| (v - offset).abs() < 1e-6), "no level error of {offset} dB in the report");
        let verdict = if agrees { "agrees (within 1 dB)" } else { "DIFFERS (more than 0.1 dB)" };
        assert!(html.contains(verdict), "{verdict}");
        assert_eq!(html.contains("bench: measured force at shaker_stack differs"), !agrees);
        // The coupled modes beside their bare counterparts, matched by shape (MAC near 1).
        assert!(html.contains("coupled mode") && html.contains("MAC"));
    }
}

/// Width and height of a PNG file from its IHDR chunk.
fn png_size(path: &Path) -> (u32, u32) {
    let b = std::fs::read(path).unwrap();
    assert_eq!(&b[1..4], b"PNG", "{}", path.display());
    let be = |i: usize| u32::from_be_bytes([b[i], b[i + 1], b[i + 2], b[i + 3]]);
    (be(16), be(20))
}

/// `beamflow --quiet <flags> run <case> --out <out>` in `dir`: whether it succeeded, and
/// its standard error.
fn run_with(dir: &Path, flags: &[&str], case: &Path, out: &str) -> (bool, String) {
    let o = std::process::Command::new(env!("CARGO_BIN_EXE_beamflow"))
        .arg("--quiet")
        .args(flags)
        .args(["run", case.to_str().unwrap(), "--out", out])
        .current_dir(dir)
        .output()
        .unwrap();
    (o.status.success(), String::from_utf8_lossy(&o.stderr).into_owned())
}

/// `--dpi` scales every PNG (200 dpi: twice the pixels of the default 100 in each
/// direction) and leaves the SVG files as they are; a resolution out of range is refused.
#[test]
fn dpi_scales_png_figures_and_leaves_svg_alone() {
    let dir = tempfile::tempdir().unwrap();
    let case = dir.path().join("c.toml");
    std::fs::write(&case, linear_case(12.0, "[[analysis]]\ntype = \"steady_state\"\nharmonics = 3\n")).unwrap();
    let run = |dpi: &str, out: &str| run_with(dir.path(), &["--dpi", dpi], &case, out);
    assert!(run("100", "a").0 && run("200", "b").0);
    let fig = "c_steady_state_shaker_spectrum";
    let (w, h) = png_size(&dir.path().join(format!("a/{fig}.png")));
    assert_eq!(png_size(&dir.path().join(format!("b/{fig}.png"))), (2 * w, 2 * h));
    let svg = |d: &str| std::fs::read(dir.path().join(format!("{d}/{fig}.svg"))).unwrap();
    assert_eq!(svg("a"), svg("b"));
    let (ok, err) = run("20", "c");
    assert!(!ok && err.contains("--dpi") && err.contains("50..=600"), "{err}");
}

/// `--formats` chooses the figure files: `svg,pdf` writes vector PDF beside each SVG and
/// no PNG; a list without SVG (the report holds it) or with an unknown format is refused.
#[test]
fn formats_choose_the_figure_files() {
    let dir = tempfile::tempdir().unwrap();
    let case = dir.path().join("c.toml");
    std::fs::write(&case, linear_case(12.0, "[[analysis]]\ntype = \"steady_state\"\nharmonics = 3\n")).unwrap();
    let run = |formats: &str, out: &str| run_with(dir.path(), &["--formats", formats], &case, out);
    assert!(run("svg,pdf", "a").0);
    let names: Vec<String> = std::fs::read_dir(dir.path().join("a"))
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    let count = |ext: &str| names.iter().filter(|n| n.ends_with(ext)).count();
    assert!(count(".svg") > 0 && count(".pdf") == count(".svg") && count(".png") == 0, "{names:?}");
    let pdf = std::fs::read(dir.path().join("a/c_steady_state_shaker_spectrum.pdf")).unwrap();
    assert!(pdf.starts_with(b"%PDF-"));
    for (bad, words) in [("png", "must include svg"), ("svg,eps", "`eps` is not a figure format")] {
        let (ok, err) = run(bad, "b");
        assert!(!ok && err.contains("--formats") && err.contains(words), "{bad}: {err}");
    }
    assert!(!dir.path().join("b").exists(), "a refused --formats writes nothing");
}
