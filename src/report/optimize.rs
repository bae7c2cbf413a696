//! Figures of an optimisation: the objective along each variable through the optimum, and
//! the mode-resolved power of the optimum beside a poor placement (why it is better).

use crate::error::Result;
use crate::optimize::explain::{ModalComparison, Profile};
use crate::report::plot::{save, BarChart, LinePlot, MultiPanel, Series, SeriesStyle};
use std::path::{Path, PathBuf};

/// One panel per variable: the objective (`label`, `unit`) against the variable (named in
/// words as a sweep's axes are, `actuators` naming whose) with the others held at the
/// optimum, the optimum marked, the line broken where candidates are infeasible.
pub fn plot_profiles(
    dir: &Path,
    name: &str,
    title: &str,
    (label, unit): (&str, &str),
    profiles: &[Profile],
    actuators: &[String],
) -> Result<Vec<PathBuf>> {
    let panels = profiles
        .iter()
        .map(|p| {
            let xl = crate::report::sweep::axis_text(&p.variable, p.unit, actuators);
            let mut lp = LinePlot::new("", xl, format!("{} ({unit})", label.replace('_', " ")));
            // A break in the line is where the constraints exclude the candidates: say so.
            let name = match p.gaps.is_empty() {
                true => "other variables at the optimum",
                false => "other variables at the optimum (breaks: infeasible)",
            };
            let line = Series::line(name, p.x.clone(), p.f.clone()).broken_at(p.gaps.clone());
            lp.series.push(line);
            lp.series.push(Series::line("optimum", vec![p.x_best], vec![p.f_best]).with_style(SeriesStyle::Markers));
            lp
        })
        .collect();
    save(&MultiPanel::new(title, panels), dir, name)
}

/// Grouped bars: each mode's share of the power the best and the poor candidate put into
/// the first modes (their totals differ by orders of magnitude; the shares show where it
/// goes). The shares are of the sum over the modes drawn, not of the net power, which
/// higher modes and the static residual also carry. The legend gives each candidate's
/// objective and, under it, the variables of both.
pub fn plot_modal(dir: &Path, name: &str, m: &ModalComparison) -> Result<Vec<PathBuf>> {
    save(&modal_chart(m), dir, name)
}

fn modal_chart(m: &ModalComparison) -> BarChart {
    let n = m.mode_frequency_hz.len();
    let mut b = BarChart::new(
        format!("Where the power goes: share of each mode of the bare {} in the power into modes 1–{n}", m.structure),
        "mode (natural frequency)",
        format!("share of the power into modes 1–{n} (%)"),
    );
    let share = |p: &[f64]| {
        let total: f64 = p.iter().sum();
        p.iter().map(|x| if total != 0.0 { 100.0 * x / total } else { 0.0 }).collect::<Vec<f64>>()
    };
    b.categories = m.mode_frequency_hz.iter().enumerate().map(|(r, f)| format!("{} ({f:.1} Hz)", r + 1)).collect();
    b.groups =
        vec![(format!("best: {}", m.best_label), share(&m.best)), (format!("poor: {}", m.poor_label), share(&m.poor))];
    b.notes = std::iter::once("variables: best | poor".to_string())
        .chain(m.variables.iter().map(|[name, best, poor]| format!("{name}: {best} | {poor}")))
        .collect();
    b.size = (1200, 650);
    b
}

/// The two objectives of every feasible candidate evaluated, the Pareto front among them
/// and the chosen compromise (the front's point nearest the ideal).
pub fn plot_pareto(
    (dir, name): (&Path, &str),
    axes: [(&str, &str); 2],
    feasible: [Vec<f64>; 2],
    front: [Vec<f64>; 2],
    chosen: [f64; 2],
) -> Result<Vec<PathBuf>> {
    let label = |(name, unit): (&str, &str)| if unit == "1" { name.to_string() } else { format!("{name} ({unit})") };
    let mut lp = LinePlot::new("Pareto front of the two objectives", label(axes[0]), label(axes[1]));
    let [fx, fy] = feasible;
    lp.series.push(Series::line("feasible candidates evaluated", fx, fy).with_style(SeriesStyle::Markers));
    let [px, py] = front;
    lp.series.push(Series::line("Pareto front", px, py).with_style(SeriesStyle::LineMarkers));
    lp.series.push(
        Series::line("chosen: nearest the ideal point", vec![chosen[0]], vec![chosen[1]])
            .with_style(SeriesStyle::Markers),
    );
    save(&lp, dir, name)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A plate's comparison: the title names the plate, the legend its candidates by their
    /// objective and the variables with units, and every text is escaped once.
    #[test]
    fn the_modal_figure_names_its_structure_and_units() {
        let m = ModalComparison {
            mode_frequency_hz: vec![75.2, 163.3],
            best: vec![1.0, 3.0],
            poor: vec![2.0, 0.5],
            structure: "plate",
            best_label: "26.43 mW".into(),
            poor_label: "2.13 µW".into(),
            variables: vec![["position x, frame_a".into(), "93.17 mm".into(), "339.6 mm".into()]],
        };
        let svg = modal_chart(&m).svg("modes.svg").unwrap();
        for text in ["mode of the bare plate", "best: 26.43 mW", "position x, frame_a: 93.17 mm | 339.6 mm"] {
            assert!(svg.contains(text), "{text}");
        }
        assert!(!svg.contains("&amp;") && !svg.contains("beam"), "escaped twice, or a beam on a plate");
    }
}
