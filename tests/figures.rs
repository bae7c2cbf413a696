//! What a run's figures show, read back from the SVG files it writes: every axis names
//! its quantity and unit, and line spectra stand at their true frequencies.

use beamflow::app::runner::run_case;
use beamflow::case::LoadedCase;
use beamflow::report::figures::plot_run;
use std::path::Path;

/// The frame actuator on the beam, 12 V at 60 Hz: transient and steady state, three points.
fn frame_run_figures() -> (tempfile::TempDir, Vec<String>) {
    let case = Path::new(env!("CARGO_MANIFEST_DIR")).join("cases/beam-frame-12V-60Hz.toml");
    let run = run_case(&LoadedCase::load(&case).unwrap()).unwrap();
    let dir = tempfile::tempdir().unwrap();
    let files = plot_run(dir.path(), "c", &run).unwrap();
    let svgs = files
        .iter()
        .filter(|p| p.extension().is_some_and(|e| e == "svg"))
        .map(|p| p.file_name().unwrap().to_string_lossy().into_owned())
        .collect();
    (dir, svgs)
}

/// The SVG figures of a shipped case's run, read: (file name, SVG text).
fn case_figures(case: &str) -> Vec<(String, String)> {
    let case = Path::new(env!("CARGO_MANIFEST_DIR")).join("cases").join(case);
    let run = run_case(&LoadedCase::load(&case).unwrap()).unwrap();
    let dir = tempfile::tempdir().unwrap();
    let files = plot_run(dir.path(), "c", &run).unwrap();
    files
        .iter()
        .filter(|p| p.extension().is_some_and(|e| e == "svg"))
        .map(|p| (p.file_name().unwrap().to_string_lossy().into_owned(), std::fs::read_to_string(p).unwrap()))
        .collect()
}

/// The colour of each legend entry of an SVG figure: the stroke of the sample (a short
/// two-point line, level or upright) just left of the entry's text.
fn legend_colours(svg: &str) -> Vec<(String, String)> {
    let samples: Vec<((f64, f64), String)> = tags(svg, "polyline")
        .into_iter()
        .filter_map(|t| {
            let stroke = attr(t, "stroke").filter(|s| *s != "#000000")?;
            let pts: Vec<(f64, f64)> = attr(t, "points")?
                .split_whitespace()
                .filter_map(|p| p.split_once(',').and_then(|(x, y)| Some((x.parse().ok()?, y.parse().ok()?))))
                .collect();
            let short = pts.len() == 2 && (pts[0].0 - pts[1].0).abs() + (pts[0].1 - pts[1].1).abs() < 40.0;
            short.then(|| ((pts[0].0.max(pts[1].0), 0.5 * (pts[0].1 + pts[1].1)), stroke.to_string()))
        })
        .collect();
    labels(svg)
        .into_iter()
        .filter(|l| !l.turned)
        .filter_map(|l| {
            let (x, y) = l.centre;
            let near = samples.iter().filter(|((sx, sy), _)| *sx < x && x - sx < 120.0 && (sy - y).abs() < 8.0);
            let (_, c) = near.min_by(|a, b| (x - a.0 .0).total_cmp(&(x - b.0 .0)))?;
            Some((l.text, c.clone()))
        })
        .collect()
}

/// Each point has one colour in every figure of a run (forces, spectra, powers), and the
/// frame's stack foot, its legs and the inertial actuator's foot four different ones.
#[test]
fn each_point_has_one_colour_in_every_figure() {
    let points = ["stack foot", "left leg", "right leg"];
    let colours_of = |case: &str| {
        let mut seen: std::collections::BTreeMap<String, std::collections::BTreeSet<String>> = Default::default();
        let mut figures = 0;
        for (name, svg) in case_figures(case) {
            let entries: Vec<(String, String)> =
                legend_colours(&svg).into_iter().filter(|(l, _)| points.contains(&l.as_str())).collect();
            figures += !entries.is_empty() as usize;
            for (label, colour) in entries {
                seen.entry(label).or_default().insert(format!("{colour} ({name})"));
            }
        }
        assert!(figures >= 4, "{case}: {figures} figures name the points");
        seen.into_iter()
            .map(|(label, c)| {
                let distinct: std::collections::BTreeSet<&str> = c.iter().map(|s| &s[..7]).collect();
                assert_eq!(distinct.len(), 1, "{case}: {label} in several colours: {c:?}");
                (label, distinct.into_iter().next().unwrap().to_string())
            })
            .collect::<std::collections::BTreeMap<String, String>>()
    };
    let frame = colours_of("beam-frame-12V-60Hz.toml");
    let inertial = colours_of("beam-inertial-12V-60Hz.toml");
    assert_eq!(frame.len(), 3, "{frame:?}");
    let mut all: Vec<&String> = frame.values().collect();
    all.push(&inertial["stack foot"]);
    let distinct: std::collections::BTreeSet<&&String> = all.iter().collect();
    assert_eq!(distinct.len(), 4, "frame {frame:?}, inertial {inertial:?}");
    // They are the palette's, the one home of these colours.
    let hex = |c: plotters::style::RGBColor| format!("#{:02X}{:02X}{:02X}", c.0, c.1, c.2);
    assert_eq!(frame["left leg"], hex(beamflow::report::palette::point("frame", "left_leg")));
    assert_eq!(inertial["stack foot"], hex(beamflow::report::palette::point("inertial", "stack")));
}

/// A transient that keeps its whole history draws it from t = 0, the start-up visible, in
/// the points' colours.
#[test]
fn a_whole_history_is_drawn_from_the_start() {
    let case = Path::new(env!("CARGO_MANIFEST_DIR")).join("cases/beam-inertial-12V-60Hz.toml");
    let mut lc = LoadedCase::load(&case).unwrap();
    lc.case.output.full_history = true;
    let run = run_case(&lc).unwrap();
    let dir = tempfile::tempdir().unwrap();
    let files = plot_run(dir.path(), "c", &run).unwrap();
    let name = "c_transient_inertial_history.svg";
    assert!(files.iter().any(|f| f.ends_with(name)), "{files:?}");
    let svg = std::fs::read_to_string(dir.path().join(name)).unwrap();
    let colours = legend_colours(&svg);
    let hex = |c: plotters::style::RGBColor| format!("#{:02X}{:02X}{:02X}", c.0, c.1, c.2);
    assert_eq!(colours, [("stack foot".to_string(), hex(beamflow::report::palette::point("inertial", "stack")))]);
    // The time axis starts at zero: the start-up is in the figure.
    let numbers: Vec<(f64, f64)> =
        labels(&svg).iter().filter(|l| !l.turned).filter_map(|l| Some((l.text.parse().ok()?, l.centre.1))).collect();
    let bottom = numbers.iter().map(|n| n.1).fold(f64::NEG_INFINITY, f64::max);
    let x_ticks: Vec<f64> = numbers.iter().filter(|n| (n.1 - bottom).abs() < 3.0).map(|n| n.0).collect();
    // (The first tick stands within one spacing of t = 0; the last periods alone would start
    // seconds later.)
    assert!(x_ticks.len() >= 3 && x_ticks[0] <= 1.0001 * (x_ticks[1] - x_ticks[0]), "{x_ticks:?}");
}

/// The value of attribute `name` in a tag.
fn attr<'a>(tag: &'a str, name: &str) -> Option<&'a str> {
    let key = format!(" {name}=\"");
    let i = tag.find(&key)? + key.len();
    Some(&tag[i..i + tag[i..].find('"')?])
}

/// The attributes of the tags `<name …>` of an SVG text, each with a leading space.
fn tags<'a>(svg: &'a str, name: &str) -> Vec<&'a str> {
    let open = format!("<{name}");
    svg.split(&open).skip(1).filter(|t| t.starts_with(' ')).map(|t| &t[..t.find('>').unwrap_or(t.len())]).collect()
}

/// A piece of text as drawn (an outline path): its text, whether it is turned (an axis
/// label beside the plot) and the centre of its outline.
struct Label {
    text: String,
    turned: bool,
    centre: (f64, f64),
}

fn labels(svg: &str) -> Vec<Label> {
    tags(svg, "path")
        .into_iter()
        .filter_map(|t| {
            let text = attr(t, "aria-label")?.replace("&amp;", "&").replace("&lt;", "<").replace("&gt;", ">");
            let nums: Vec<f64> = attr(t, "d")?
                .split(|c: char| c.is_ascii_alphabetic() || c == ' ')
                .filter_map(|v| v.parse().ok())
                .collect();
            let (xs, ys): (Vec<f64>, Vec<f64>) = nums.chunks(2).map(|p| (p[0], p[1])).unzip();
            let mid = |v: &[f64]| {
                (v.iter().cloned().fold(f64::INFINITY, f64::min) + v.iter().cloned().fold(f64::NEG_INFINITY, f64::max))
                    / 2.0
            };
            Some(Label { text, turned: attr(t, "transform").is_some(), centre: (mid(&xs), mid(&ys)) })
        })
        .collect()
}

/// `actual` is `expected` (`quantity (unit)`), the unit perhaps with an SI prefix.
fn same_label(actual: &str, expected: &str) -> bool {
    if actual == expected {
        return true;
    }
    let Some((text, unit)) = expected.strip_suffix(')').and_then(|e| e.rsplit_once(" (")) else { return false };
    ["f", "p", "n", "µ", "m", "k", "M", "G"].iter().any(|p| actual == format!("{text} ({p}{unit})"))
}

/// Each figure's axes, panel by panel: (x label, y label). A figure a run writes that is
/// not here fails the test, so a new figure comes with its axes.
const AXES: &[(&str, &[(&str, &str)])] = &[
    ("_loop.svg", &[("voltage (V)", "free stroke δ (µm)")]),
    ("_power_points.svg", &[("interface point", "power (W)")]),
    ("_power_spectrum.svg", &[("frequency (Hz)", "power into the beam (W)")]),
    ("_spectrum.svg", &[("frequency (Hz)", "force level (dB re 1 N)")]),
    ("_time.svg", &[("time (ms)", "transmitted force (N)"), ("time (ms)", "force (N)"), ("time (ms)", "power (W)")]),
    ("_power_by_mode.svg", &[("bare-beam mode (number, natural frequency)", "power (W)")]),
    ("_history.svg", &[("time (s)", "transmitted force (N)")]),
];

#[test]
fn every_axis_names_its_quantity_and_unit() {
    let (dir, svgs) = frame_run_figures();
    assert!(svgs.len() >= 10, "{svgs:?}");
    for name in &svgs {
        let svg = std::fs::read_to_string(dir.path().join(name)).unwrap();
        assert!(!svg.contains("<text"), "{name}: text must be outlines, not left to the viewer's fonts");
        let (_, panels) = AXES
            .iter()
            .filter(|(suffix, _)| name.ends_with(suffix))
            .max_by_key(|(suffix, _)| suffix.len())
            .unwrap_or_else(|| panic!("{name} has no row in AXES"));
        let l = labels(&svg);
        let turned: Vec<&str> = l.iter().filter(|l| l.turned).map(|l| l.text.as_str()).collect();
        assert_eq!(turned.len(), panels.len(), "{name}: y axes {turned:?}");
        for ((x, y), got) in panels.iter().zip(&turned) {
            assert!(same_label(got, y), "{name}: y axis `{got}`, expected `{y}`");
            assert!(l.iter().any(|l| !l.turned && l.text == *x), "{name}: no x axis `{x}`");
            assert!(got.ends_with(')'), "{name}: y axis `{got}` has no unit");
        }
    }
}

/// Stems of several series at one harmonic stand at the same, true frequency (once they
/// were shifted sideways a few pixels each, so that 60 Hz read as 55 or 65).
#[test]
fn stems_stand_at_their_true_frequencies() {
    let (dir, svgs) = frame_run_figures();
    for name in svgs.iter().filter(|n| n.ends_with("_spectrum.svg")) {
        let svg = std::fs::read_to_string(dir.path().join(name)).unwrap();
        // The x axis: its tick labels (the lowest row of numbers) on its vertical grid lines.
        let numbers: Vec<(f64, (f64, f64))> = labels(&svg)
            .into_iter()
            .filter(|l| !l.turned)
            .filter_map(|l| Some((l.text.parse::<f64>().ok()?, l.centre)))
            .collect();
        let bottom = numbers.iter().map(|(_, c)| c.1).fold(f64::NEG_INFINITY, f64::max);
        let grid: Vec<f64> = tags(&svg, "line")
            .into_iter()
            .filter(|t| attr(t, "x1") == attr(t, "x2") && attr(t, "stroke") == Some("#000000"))
            .filter_map(|t| attr(t, "x1")?.parse().ok())
            .collect();
        let ticks: Vec<(f64, f64)> = numbers
            .iter()
            .filter(|(_, c)| (c.1 - bottom).abs() < 3.0)
            .map(|&(v, c)| {
                let at = grid.iter().copied().min_by(|a, b| (a - c.0).abs().total_cmp(&(b - c.0).abs())).unwrap();
                assert!((at - c.0).abs() < 3.0, "{name}: tick {v} at {c:?} has no grid line");
                (v, at)
            })
            .collect();
        assert!(ticks.len() >= 3, "{name}: x ticks {ticks:?}");
        let ((v0, p0), (v1, p1)) = (ticks[0], ticks[ticks.len() - 1]);
        let px_per_hz = (p1 - p0) / (v1 - v0);
        let hz = |x: f64| v0 + (x - p0) / px_per_hz;
        // Stems: vertical two-point lines in a series' colour.
        let mut stems: Vec<(f64, String)> = tags(&svg, "polyline")
            .into_iter()
            .filter(|t| attr(t, "stroke").is_some_and(|s| s != "#000000"))
            .filter_map(|t| {
                let pts: Vec<(f64, f64)> = attr(t, "points")?
                    .split_whitespace()
                    .filter_map(|p| p.split_once(',').and_then(|(x, y)| Some((x.parse().ok()?, y.parse().ok()?))))
                    .collect();
                (pts.len() == 2 && pts[0].0 == pts[1].0).then(|| (pts[0].0, attr(t, "stroke").unwrap().to_string()))
            })
            .collect();
        // The legend's samples stand right of the plot area, whose edge is the last grid line.
        let right = grid.iter().copied().fold(f64::NEG_INFINITY, f64::max);
        stems.retain(|s| s.0 <= right);
        stems.sort_by(|a, b| a.0.total_cmp(&b.0));
        let colours: std::collections::BTreeSet<&str> = stems.iter().map(|(_, c)| c.as_str()).collect();
        assert_eq!(colours.len(), 3, "{name}: stack foot, left and right leg, {stems:?}");
        for (x, colour) in &stems {
            let f = hz(*x);
            let k = (f / 60.0).round();
            assert!(k >= 1.0, "{name}: a stem at {f} Hz");
            // Within a pixel (positions are whole pixels) of its harmonic.
            assert!(
                ((f - 60.0 * k) * px_per_hz).abs() <= 1.0,
                "{name}: {colour} stem at {f:.2} Hz, not {} Hz",
                60.0 * k
            );
        }
        // At the drive frequency all three points have a line, and their stems coincide.
        let at_drive: Vec<f64> = stems.iter().map(|s| s.0).filter(|&x| (hz(x) - 60.0).abs() < 10.0).collect();
        assert_eq!(at_drive.len(), 3, "{name}: {at_drive:?}");
        assert!(at_drive.iter().all(|&x| x == at_drive[0]), "{name}: stems at 60 Hz drawn apart: {at_drive:?}");
    }
}

/// A plate's layout draws everything that stands on it, each kind of edge in its own
/// style with a legend, and the run's report shows it in a section of its own.
#[test]
fn a_plate_layout_shows_masses_springs_and_edge_kinds_and_is_in_the_report() {
    let dir = tempfile::tempdir().unwrap();
    let case = dir.path().join("layout.toml");
    std::fs::write(
        &case,
        r#"
[plate]
length_x = 0.5
length_y = 0.4
thickness = 0.003
youngs_modulus = 70e9
poisson_ratio = 0.33
density = 2700.0
[plate.mesh]
elements = [10, 8]
[plate.edges]
x0 = "clamped"
x1 = "simply_supported"
y0 = "free"
y1 = "simply_supported"
[[plate.point_mass]]
at = [0.10, 0.10]
mass = 0.05
[[plate.spring]]
at = [0.40, 0.30]
stiffness = 2.0e4
damping = 1.0
[[sensor]]
name = "corner"
at = [0.5, 0.4]
[[actuator]]
type = "frame"
name = "drive"
at = [0.25, 0.2]
direction = 30.0
[actuator.voltage]
kind = "sine"
amplitude = 12.0
frequency = 60.0
[[analysis]]
type = "modes"
count = 2
"#,
    )
    .unwrap();
    let out = dir.path().join("out");
    beamflow::app::commands::run(&case, Some(&out), None, true, false, &beamflow::analysis::budget::Budget::default())
        .unwrap();
    let svg = std::fs::read_to_string(out.join("layout_layout.svg")).unwrap();
    let texts: Vec<String> = labels(&svg).into_iter().map(|l| l.text).collect();
    let frame_base = "frame base (joins its legs)";
    for t in
        ["point mass", "0.05 kg", "spring to the ground", "20 kN/m", "clamped edge", "free edge", "sensor", frame_base]
    {
        assert!(texts.iter().any(|s| s == t), "`{t}` is not in the layout: {texts:?}");
    }
    // The actuator is named once, at its stack; its three feet are marked, the legs unnamed.
    assert_eq!(texts.iter().filter(|s| s.contains("drive")).count(), 1, "{texts:?}");
    assert!(texts.iter().any(|s| s == "actuator foot: leg") && texts.iter().any(|s| s == "actuator foot: stack"));
    let html = std::fs::read_to_string(out.join("report.html")).unwrap();
    let layout = html.find("<figure id=\"fig-layout_layout\">").expect("the layout is in the report");
    assert!(html.find("<h2 id=\"layout\">").is_some_and(|h| h < layout), "under its own heading");
}
