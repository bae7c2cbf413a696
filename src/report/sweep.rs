//! Figures and the best-case table of a sweep table.
//!
//! * Two parameters on a full grid, one of them with at most [`LINES_UP_TO`] values (a
//!   `values` list, a small `count`): one line of net power per value of that parameter
//!   over the other. A few discrete values are no continuum: a heat map would fill bands
//!   between them, as if cases had been solved there.
//! * Two parameters on a full grid, each with more values (e.g. position × frequency): a
//!   heat map of the net power into the beam on a **logarithmic** colour scale. In steady state the net power
//!   of an actuator alone on a damped beam equals the beam's dissipation, so it is positive
//!   and spans many decades (dips near mode nodes, peaks at resonances); a linear scale
//!   would show only the resonance peaks. If any value is negative or zero (several
//!   actuators, one taking power back), |P| is shown with a floor of 10⁻¹² × max and the
//!   colour-bar label says so.
//! * One parameter: net power against it (log y if all positive), one line per actuator.
//! * The best cases by net power, as Markdown; with a position parameter (`….x_e`) and one
//!   other parameter, also the best and worst position for each value of the other.

use crate::error::Result;
use crate::report::plot::{HeatMap, LinePlot, Series, SeriesStyle};
use crate::sweep::table::SweepTable;
use std::path::{Path, PathBuf};

/// A number with about 6 significant digits, without trailing zeros.
pub fn num(v: f64) -> String {
    if v == 0.0 || !v.is_finite() {
        return format!("{v}");
    }
    let a = v.abs();
    if (1e-3..1e6).contains(&a) {
        let decimals = (5 - a.log10().floor() as i32).max(0) as usize;
        let s = format!("{v:.decimals$}");
        if s.contains('.') {
            s.trim_end_matches('0').trim_end_matches('.').to_string()
        } else {
            s
        }
    } else {
        format!("{v:.4e}")
    }
}

fn label(t: &SweepTable, k: usize) -> String {
    with_unit(&t.parameters[k], &t.units[k])
}

/// `text (unit)`, or the text alone for a number without a unit.
fn with_unit(text: &str, unit: &str) -> String {
    if unit == "1" || unit == "?" {
        text.to_string()
    } else {
        format!("{text} ({unit})")
    }
}

/// A parameter as an axis of a figure: the quantity in words, whose it is and its unit
/// (`actuator[0].voltage.frequency` → `drive frequency, frame (Hz)`); the field path where
/// no name is known.
fn axis_label(t: &SweepTable, k: usize) -> String {
    axis_text(&t.parameters[k], &t.units[k], &t.actuators)
}

pub(crate) fn axis_text(path: &str, unit: &str, actuators: &[String]) -> String {
    let field = path.rsplit('.').next().unwrap_or(path);
    let what = match field {
        "x_e" => "position x_{E}",
        "at[0]" => "position x",
        "at[1]" => "position y",
        "direction" => "direction ψ",
        "node" => "stack-foot node",
        "frequency" => "drive frequency",
        "amplitude" => "drive amplitude",
        "offset" => "drive offset",
        "m_t" => "top mass m_{t}",
        "k_p" => "stack stiffness k_{p}",
        "c_p" => "stack damping c_{p}",
        "d_p" => "piezo constant d_{p}",
        "elements" => "mesh elements",
        _ => return with_unit(path, unit),
    };
    // Whose: an actuator by its name, else the path above the field.
    let owner = path.strip_suffix(field).unwrap_or("").trim_end_matches('.');
    let actuator = owner
        .strip_prefix("actuator[")
        .and_then(|r| r.split(']').next())
        .and_then(|i| i.parse::<usize>().ok())
        .and_then(|i| actuators.get(i));
    let whose = match actuator {
        Some(name) => format!(", {name}"),
        None if owner.is_empty() || owner.starts_with("beam") => String::new(),
        None => format!(", {owner}"),
    };
    with_unit(&format!("{what}{whose}"), unit)
}

/// Index of the position parameter (a path ending in `x_e`), if any.
fn position_param(t: &SweepTable) -> Option<usize> {
    t.parameters.iter().position(|p| p.ends_with("x_e"))
}

fn sorted_unique(v: impl Iterator<Item = f64>) -> Vec<f64> {
    let mut u: Vec<f64> = v.collect();
    u.sort_by(|a, b| a.total_cmp(b));
    u.dedup();
    u
}

/// A full grid over two parameters: (x parameter, y parameter, x values, y values, z
/// row-major ny × nx of total net power).
type Grid = (usize, usize, Vec<f64>, Vec<f64>, Vec<f64>);

fn grid(t: &SweepTable) -> Option<Grid> {
    if t.parameters.len() != 2 || t.rows.is_empty() {
        return None;
    }
    let px = position_param(t).unwrap_or(0);
    let py = 1 - px;
    let xs = sorted_unique(t.rows.iter().map(|r| r.inputs[px]));
    let ys = sorted_unique(t.rows.iter().map(|r| r.inputs[py]));
    if xs.len() * ys.len() != t.rows.len() {
        return None;
    }
    let mut z = vec![f64::NAN; xs.len() * ys.len()];
    for r in &t.rows {
        let i = xs.binary_search_by(|v| v.total_cmp(&r.inputs[px])).ok()?;
        let j = ys.binary_search_by(|v| v.total_cmp(&r.inputs[py])).ok()?;
        let cell = &mut z[j * xs.len() + i];
        if !cell.is_nan() {
            return None;
        }
        *cell = r.total_net_power();
    }
    Some((px, py, xs, ys, z))
}

/// A sweep's figure: a heat map over two parameters, or lines over one.
enum Figure {
    Heat(HeatMap),
    Lines(LinePlot),
}

impl Figure {
    fn render(&self, path: &Path) -> Result<()> {
        match self {
            Figure::Heat(h) => h.render(path),
            Figure::Lines(p) => p.render(path),
        }
    }

    fn svg(&self, name: &str) -> Result<String> {
        match self {
            Figure::Heat(h) => h.svg(name),
            Figure::Lines(p) => p.svg(name),
        }
    }
}

/// The report file `<stem>.<suffix>` beside the table `out`.
fn beside(out: &Path, suffix: &str) -> Result<PathBuf> {
    let stem = out.file_stem().map(|s| s.to_string_lossy().into_owned()).unwrap_or_else(|| "sweep".into());
    let dir = out.parent().map(Path::to_path_buf).unwrap_or_default();
    crate::io::paths::output_file(&dir, &format!("{stem}.{suffix}"))
}

const FIGURE: &str = "net_power";
const BEST: &str = "best.md";
const REPORT: &str = "report.html";

/// The report files [`plot`], [`write_markdown`] and [`write_report`] may write beside the
/// table `out` (the figure in every format a run can ask for).
pub fn files_beside(out: &Path) -> Vec<PathBuf> {
    let figures = crate::report::plot::Format::ALL.map(|f| format!("{FIGURE}.{}", f.ext()));
    figures.iter().map(String::as_str).chain([BEST, REPORT]).filter_map(|s| beside(out, s).ok()).collect()
}

/// Writes the figure for a table next to `out` (`<stem>.net_power.png`, and `.svg`, `.pdf`
/// where the run's figure formats ask for them) and returns the files written (none if
/// the table's shape has no figure).
pub fn plot(t: &SweepTable, out: &Path) -> Result<Vec<PathBuf>> {
    let Some(f) = figure(t) else { return Ok(Vec::new()) };
    let mut written = Vec::new();
    for format in crate::report::plot::figure_formats() {
        let path = beside(out, &format!("{FIGURE}.{}", format.ext()))?;
        f.render(&path)?;
        written.push(path);
    }
    Ok(written)
}

/// Writes `<stem>.report.html` next to `out`: the best cases and the figure in one
/// self-contained page, and the sweep file when it can be read. Returns its path.
pub fn write_report(t: &SweepTable, out: &Path) -> Result<PathBuf> {
    use crate::report::html::{escape, markdown, Page};
    let path = beside(out, REPORT)?;
    let mut p = Page::new();
    p.section("best", "Best cases");
    // The Markdown report's own heading is the page's.
    let md = markdown(&markdown_report(t));
    p.push(md.split_once("</h2>\n").map_or(md.as_str(), |(_, rest)| rest));
    if let Some(f) = figure(t) {
        p.section("figure", &format!("Net power into the {}", t.into_word()));
        p.push(&format!("<figure>\n{}\n</figure>\n", f.svg(&path.display().to_string())?));
    }
    // The table names the file it came from (a merged shard may name any path): read it as
    // any input, or leave the section out.
    if let Ok(text) = crate::input_file::read_text(std::path::Path::new(&t.sweep_file)) {
        p.section("sweep", "Sweep file");
        p.push(&format!("<p><code>{}</code></p>\n<pre>{}</pre>\n", escape(&t.sweep_file), escape(&text)));
    }
    let title = if t.title.is_empty() { "Sweep".to_string() } else { t.title.clone() };
    let meta = format!(
        "sweep <code>{}</code> (id <code>{}</code>) · {} of {} cases · table <code>{}</code> · beamflow {}",
        escape(&t.sweep_file),
        escape(&t.hash),
        t.rows.len(),
        t.total_cases,
        escape(&out.display().to_string()),
        env!("CARGO_PKG_VERSION")
    );
    crate::io::atomic::write_atomic_string(&path, &p.finish(&format!("Sweep: {title}"), &meta))?;
    Ok(path)
}

/// Most values a parameter of a two-parameter grid may have to be drawn as one line per
/// value instead of as an axis of a heat map.
pub const LINES_UP_TO: usize = 6;

/// The figure of a table's shape, if it has one: titled by the sweep's title (or what it
/// shows), the net power named on the axis that carries it.
fn figure(t: &SweepTable) -> Option<Figure> {
    let into = t.into_word();
    let title = if t.title.is_empty() { format!("Net power into the {into}") } else { t.title.clone() };
    if let Some((px, py, xs, ys, z)) = grid(t) {
        if xs.len().min(ys.len()) <= LINES_UP_TO {
            // Lines over the parameter with more values (the position on a tie).
            let (along, per) = if ys.len() > xs.len() { (py, px) } else { (px, py) };
            return Some(Figure::Lines(lines_per_value(t, title, along, per)));
        }
        let max = z.iter().fold(0.0f64, |m, v| m.max(v.abs()));
        let signed = z.iter().any(|&v| v <= 0.0);
        let floor = if max > 0.0 { max * 1e-12 } else { 1e-30 };
        let mut h = HeatMap::new(
            title,
            axis_label(t, px),
            axis_label(t, py),
            if signed { format!("|net power| into the {into} (W)") } else { format!("net power into the {into} (W)") },
        );
        // The grid's best case marked (the largest net power).
        if let Some(k) = (0..z.len()).max_by(|&a, &b| z[a].total_cmp(&z[b])) {
            let (i, j) = (k % xs.len(), k / xs.len());
            h.marks.push(super::plot::MapMark {
                x: xs[i],
                y: ys[j],
                label: format!("best: {}", super::plot::text::si(z[k], "W", 4)),
                marker: super::plot::Marker { shape: super::plot::Shape::Diamond, hollow: false },
            });
        }
        h.x = xs;
        h.y = ys;
        h.z = z.iter().map(|v| v.abs().max(floor)).collect();
        h.log_z = true;
        return Some(Figure::Heat(h));
    }
    if t.parameters.len() == 1 && !t.rows.is_empty() {
        let x: Vec<f64> = t.rows.iter().map(|r| r.inputs[0]).collect();
        let mut p = LinePlot::new(title, axis_label(t, 0), format!("net power into the {into} (W)"));
        let style = if t.rows.len() <= 40 { SeriesStyle::LineMarkers } else { SeriesStyle::Line };
        let mut order: Vec<usize> = (0..x.len()).collect();
        order.sort_by(|&a, &b| x[a].total_cmp(&x[b]));
        let xs: Vec<f64> = order.iter().map(|&j| x[j]).collect();
        let mut all_pos = true;
        for (a, name) in t.actuators.iter().enumerate() {
            let y: Vec<f64> = order.iter().map(|&j| t.rows[j].net_power[a]).collect();
            all_pos &= y.iter().all(|&v| v > 0.0);
            let s = Series::line(name.clone(), xs.clone(), y).with_style(style);
            p.series.push(s.coloured(crate::report::palette::actuator(a)));
        }
        if t.actuators.len() > 1 {
            let y: Vec<f64> = order.iter().map(|&j| t.rows[j].total_net_power()).collect();
            all_pos &= y.iter().all(|&v| v > 0.0);
            p.series.push(Series::line("total", xs, y).with_style(style));
        }
        p.log_y = all_pos;
        return Some(Figure::Lines(p));
    }
    None
}

/// Total net power against parameter `along`, one line per value of parameter `per`,
/// labelled by that value (`83 Hz`), on a log axis where every value is positive.
fn lines_per_value(t: &SweepTable, title: String, along: usize, per: usize) -> LinePlot {
    let mut p = LinePlot::new(title, axis_label(t, along), format!("net power into the {} (W)", t.into_word()));
    let mut all_pos = true;
    for v in sorted_unique(t.rows.iter().map(|r| r.inputs[per])) {
        let mut rows: Vec<_> = t.rows.iter().filter(|r| r.inputs[per] == v).collect();
        rows.sort_by(|a, b| a.inputs[along].total_cmp(&b.inputs[along]));
        let x = rows.iter().map(|r| r.inputs[along]).collect();
        let y: Vec<f64> = rows.iter().map(|r| r.total_net_power()).collect();
        all_pos &= y.iter().all(|&v| v > 0.0);
        let style = if rows.len() <= 40 { SeriesStyle::LineMarkers } else { SeriesStyle::Line };
        p.series.push(Series::line(super::plot::text::quantity(v, &t.units[per]), x, y).with_style(style));
    }
    p.notes = vec![format!("one line per {}", axis_text(&t.parameters[per], "1", &t.actuators))];
    p.log_y = all_pos;
    p
}

/// The rows that are local maxima of the total net power over the sweep's grid of one or
/// two parameters (no neighbour along either parameter or diagonally is higher): the
/// distinct optima, where the best rows overall would crowd around one peak. None when
/// the rows do not fill such a grid.
fn local_maxima(t: &SweepTable) -> Option<Vec<usize>> {
    let axes: Vec<Vec<f64>> =
        (0..t.parameters.len()).map(|k| sorted_unique(t.rows.iter().map(|r| r.inputs[k]))).collect();
    if !(1..=2).contains(&axes.len()) || axes.iter().map(Vec::len).product::<usize>() != t.rows.len() {
        return None;
    }
    let mut at = std::collections::HashMap::new();
    for (j, r) in t.rows.iter().enumerate() {
        let cell: Vec<i64> = axes
            .iter()
            .zip(&r.inputs)
            .map(|(a, v)| a.binary_search_by(|x| x.total_cmp(v)).ok().map(|i| i as i64))
            .collect::<Option<_>>()?;
        if at.insert(cell, j).is_some() {
            return None;
        }
    }
    let p = |j: usize| t.rows[j].total_net_power();
    let steps: Vec<Vec<i64>> = if axes.len() == 1 {
        vec![vec![-1], vec![1]]
    } else {
        (-1..=1).flat_map(|a| (-1..=1).map(move |b| vec![a, b])).filter(|d| d != &[0, 0]).collect()
    };
    let mut optima: Vec<usize> = at
        .iter()
        .filter(|(cell, &j)| {
            steps.iter().all(|d| {
                let n: Vec<i64> = cell.iter().zip(d).map(|(c, d)| c + d).collect();
                at.get(&n).is_none_or(|&k| p(k) <= p(j))
            })
        })
        .map(|(_, &j)| j)
        .collect();
    optima.sort_unstable();
    Some(optima)
}

/// What [`best_table`] holds, in words: `Best 3 distinct optima (…)` or `Best 8 cases`.
pub fn best_title(t: &SweepTable) -> String {
    match local_maxima(t) {
        Some(o) => format!("Best {} distinct optima (local maxima of the grid)", o.len().min(t.best)),
        None => format!("Best {} cases", t.rows.len().min(t.best)),
    }
}

/// The best cases by total net power, as a Markdown table of at most `n` rows: on a grid
/// its distinct optima ([`local_maxima`]), else the best rows.
pub fn best_table(t: &SweepTable, n: usize) -> String {
    let mut order: Vec<usize> = local_maxima(t).unwrap_or_else(|| (0..t.rows.len()).collect());
    order.sort_by(|&a, &b| t.rows[b].total_net_power().total_cmp(&t.rows[a].total_net_power()));
    let mut s = String::from("| rank | case |");
    for k in 0..t.parameters.len() {
        s += &format!(" {} |", label(t, k));
    }
    for a in &t.actuators {
        s += &format!(" P {a} |");
    }
    s += &format!(" {} dissipation | balance error |\n|---:|---:|", t.into_word());
    s += &"---:|".repeat(t.parameters.len() + t.actuators.len() + 2);
    s.push('\n');
    for (rank, &j) in order.iter().take(n).enumerate() {
        let r = &t.rows[j];
        s += &format!("| {} | {} |", rank + 1, r.index);
        for v in &r.inputs {
            s += &format!(" {} |", num(*v));
        }
        for v in &r.net_power {
            s += &format!(" {} |", watts(*v));
        }
        s += &format!(" {} | {:.1e} |\n", watts(r.beam_dissipation), r.balance_error);
    }
    s
}

/// A power in the tables: four significant digits on an SI-prefixed watt (`12.35 µW`).
fn watts(v: f64) -> String {
    crate::report::plot::text::si(v, "W", 4)
}

/// With a position parameter and one other: for each value of the other, the best and the
/// worst position (Markdown).
pub fn best_positions(t: &SweepTable) -> Option<String> {
    let px = position_param(t)?;
    if t.parameters.len() != 2 {
        return None;
    }
    let py = 1 - px;
    let ys = sorted_unique(t.rows.iter().map(|r| r.inputs[py]));
    let mut s = format!(
        "| {} | best {} | net power | worst {} | net power | best/worst |\n|---:|---:|---:|---:|---:|---:|\n",
        label(t, py),
        label(t, px),
        label(t, px)
    );
    for y in ys {
        let rows: Vec<_> = t.rows.iter().filter(|r| r.inputs[py] == y).collect();
        let best = rows.iter().max_by(|a, b| a.total_net_power().total_cmp(&b.total_net_power()))?;
        let worst = rows.iter().min_by(|a, b| a.total_net_power().total_cmp(&b.total_net_power()))?;
        let (pb, pw) = (best.total_net_power(), worst.total_net_power());
        s += &format!(
            "| {} | {} | {} | {} | {} | {} |\n",
            num(y),
            num(best.inputs[px]),
            watts(pb),
            num(worst.inputs[px]),
            watts(pw),
            if pw != 0.0 { format!("{}×", crate::report::plot::text::significant(pb / pw, 4)) } else { "–".into() }
        );
    }
    Some(s)
}

/// What a reduced sweep says of its reduction.
pub fn reduction_text(c: &crate::sweep::ReductionCheck) -> String {
    format!(
        "Solved on a modal reduction shared by every case ({} modes to {:.1} Hz, a static correction per case). \
         Checked on the full model at {}: {} within {:.1e} of it.",
        c.modes_kept,
        c.cutoff_hz,
        c.case.map_or("the optimum".to_string(), |i| format!("the best case ({i})")),
        if c.case.is_some() { "point and net powers" } else { "net powers and dissipation" },
        c.max_relative_error
    )
}

/// The whole Markdown report (best cases, and best positions where it applies).
pub fn markdown_report(t: &SweepTable) -> String {
    use crate::report::html::{markdown_code, markdown_escape};
    let mut s = format!(
        "# Sweep results: {}\n\nSweep {} (id {}), {} of {} cases, analysis `{}` with {} harmonics. Ranked by the \
         net power into the {} (sum over actuators).\n\n## {}\n\n{}",
        if t.title.is_empty() { "(untitled)".to_string() } else { markdown_escape(&t.title) },
        markdown_code(&t.sweep_file),
        markdown_code(&t.hash),
        t.rows.len(),
        t.total_cases,
        t.analysis,
        t.harmonics,
        t.into_word(),
        best_title(t),
        best_table(t, t.best)
    );
    if let Some(c) = &t.reduction {
        s += &format!("\n{}\n", reduction_text(c));
    }
    if let Some(b) = best_positions(t) {
        let py = 1 - position_param(t).unwrap_or(0);
        s += &format!("\n## Best and worst position for each {}\n\n{b}", t.parameters[py]);
    }
    s
}

/// Writes `<stem>.best.md` next to `out` and returns its path.
pub fn write_markdown(t: &SweepTable, out: &Path) -> Result<PathBuf> {
    let md = beside(out, BEST)?;
    crate::io::atomic::write_atomic_string(&md, &markdown_report(t))?;
    Ok(md)
}

#[cfg(test)]
mod tests {
    use super::{axis_text, best_table, best_title, num};
    use crate::sweep::table::{Row, SweepTable};

    /// A sweep over position × frequency whose net power has two peaks, one of them on a
    /// frequency line where its neighbours are the next-best cases overall.
    fn two_peaks() -> SweepTable {
        let (xs, fs) = ([0.1, 0.2, 0.3, 0.4, 0.5, 0.6], [20.0, 40.0, 60.0]);
        let power = |x: f64, f: f64| {
            let near = |x0: f64, f0: f64, w: f64| w * (-((x - x0) / 0.1).powi(2) - ((f - f0) / 20.0).powi(2)).exp();
            near(0.2, 40.0, 10.0) + near(0.5, 40.0, 3.0)
        };
        let rows = fs
            .iter()
            .flat_map(|&f| xs.iter().map(move |&x| (x, f)))
            .enumerate()
            .map(|(index, (x, f))| Row {
                index,
                inputs: vec![x, f],
                net_power: vec![power(x, f)],
                mean_power: vec![],
                force_amplitude: vec![],
                beam_dissipation: power(x, f),
                balance_error: 0.0,
            })
            .collect();
        SweepTable {
            title: String::new(),
            sweep_file: "s.sweep.toml".into(),
            sweep_text: String::new(),
            base_text: String::new(),
            hash: String::new(),
            total_cases: 18,
            shard: crate::sweep::Shard::ALL,
            analysis: "steady_state".into(),
            harmonics: 1,
            samples_per_period: 64,
            damping: None,
            reduction: None,
            best: 8,
            parameters: vec!["actuator[0].x_e".into(), "actuator[0].voltage.frequency".into()],
            units: vec!["m".into(), "Hz".into()],
            actuators: vec!["frame".into()],
            links: vec![],
            rows,
        }
    }

    #[test]
    fn the_report_names_what_the_power_goes_into() {
        let mut t = two_peaks();
        for (base, word) in [
            ("[beam]\n", "beam"),
            ("[plate]\nlength_x = 0.5\n", "plate"),
            ("[imported]\nmass = \"m.mtx\"\n", "model"),
            ("base = \"rigid\"\n", "base"),
        ] {
            t.base_text = base.into();
            assert!(super::markdown_report(&t).contains(&format!("net power into the {word} (sum")), "{word}");
        }
    }

    #[test]
    fn the_best_cases_of_a_grid_are_its_distinct_optima() {
        let t = two_peaks();
        let table = best_table(&t, t.best);
        let ranked: Vec<&str> = table.lines().skip(2).collect();
        // Two peaks, not the eight cases nearest the higher one.
        assert_eq!(ranked.len(), 2, "{table}");
        assert!(ranked[0].starts_with("| 1 | 7 |") && ranked[1].starts_with("| 2 | 10 |"), "{table}");
        assert_eq!(best_title(&t), "Best 2 distinct optima (local maxima of the grid)");
        // Rows that fill no grid: the best rows, as before.
        let mut scattered = t.clone();
        scattered.rows.truncate(17);
        assert_eq!(best_table(&scattered, 8).lines().count(), 2 + 8);
    }

    /// The figure of a grid, by the number of values of each parameter.
    fn figure_of(xs: usize, fs: &[f64]) -> super::Figure {
        let mut t = two_peaks();
        let template = t.rows[0].clone();
        t.rows = fs
            .iter()
            .flat_map(|&f| (0..xs).map(move |i| (0.1 * (i + 1) as f64, f)))
            .enumerate()
            .map(|(index, (x, f))| Row { index, inputs: vec![x, f], net_power: vec![x * f], ..template.clone() })
            .collect();
        super::figure(&t).unwrap()
    }

    #[test]
    fn a_parameter_of_few_values_is_drawn_as_lines() {
        let super::Figure::Lines(p) = figure_of(73, &[83.0, 150.0]) else { panic!("two frequencies: lines") };
        let labels: Vec<&str> = p.series.iter().map(|s| s.label.as_str()).collect();
        assert_eq!(labels, ["83 Hz", "150 Hz"]);
        assert!(p.series.iter().all(|s| s.x.len() == 73) && p.x_label.starts_with("position x_{E}"));
        assert!(p.svg("s.svg").unwrap().contains("aria-label=\"83 Hz\""));
        // Fewer positions than frequencies: lines over the frequency.
        let super::Figure::Lines(p) = figure_of(3, &[10.0, 20.0, 30.0, 40.0, 50.0, 60.0, 70.0]) else { panic!() };
        assert_eq!(p.series.len(), 3);
        assert!(p.x_label.starts_with("drive frequency"), "{}", p.x_label);
        let many: Vec<f64> = (1..=super::LINES_UP_TO + 1).map(|k| 10.0 * k as f64).collect();
        assert!(matches!(figure_of(12, &many), super::Figure::Heat(_)));
    }

    #[test]
    fn axes_name_the_quantity_whose_it_is_and_its_unit() {
        let acts = vec!["frame".to_string()];
        assert_eq!(axis_text("actuator[0].voltage.frequency", "Hz", &acts), "drive frequency, frame (Hz)");
        assert_eq!(axis_text("actuator[0].x_e", "m", &acts), "position x_{E}, frame (m)");
        assert_eq!(axis_text("beam.mesh.elements", "1", &acts), "mesh elements");
        assert_eq!(axis_text("actuator[0].node", "1", &acts), "stack-foot node, frame");
        assert_eq!(axis_text("beam.damping.zeta", "1", &acts), "beam.damping.zeta");
        assert_eq!(axis_text("actuator[3].m_t", "kg", &acts), "top mass m_{t}, actuator[3] (kg)");
    }

    #[test]
    fn numbers_read_well() {
        assert_eq!(num(0.15000000000000002), "0.15");
        assert_eq!(num(60.0), "60");
        assert_eq!(num(123.456789), "123.457");
        assert_eq!(num(1.5e-7), "1.5000e-7");
        assert_eq!(num(0.0), "0");
    }
}
