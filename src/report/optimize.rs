//! Figures of an optimisation: the objective along each variable through the optimum, and
//! the mode-resolved power of the optimum beside a poor placement (why it is better).

use crate::error::Result;
use crate::optimize::explain::{ModalComparison, Profile};
use crate::report::plot::{BarChart, LinePlot, MultiPanel, Series, SeriesStyle};
use std::path::Path;

/// One panel per variable: the objective (`label`, `unit`) against the variable, with the
/// optimum marked.
pub fn plot_profiles(path: &Path, title: &str, label: &str, unit: &str, profiles: &[Profile]) -> Result<()> {
    let panels = profiles
        .iter()
        .map(|p| {
            let xl = if p.unit == "1" || p.unit == "?" {
                p.variable.clone()
            } else {
                format!("{} ({})", p.variable, p.unit)
            };
            let mut lp = LinePlot::new("", xl, format!("{label} ({unit})"));
            lp.series.push(
                Series::line("through the optimum", p.x.clone(), p.f.clone()).with_style(SeriesStyle::LineMarkers),
            );
            if let Some(k) = p.x.iter().position(|&x| x == p.x_best) {
                lp.series.push(Series::line("optimum", vec![p.x[k]], vec![p.f[k]]).with_style(SeriesStyle::Markers));
            }
            lp
        })
        .collect();
    MultiPanel::new(title, panels).render(path)
}

/// Grouped bars: each mode's share of the power the best and the poor candidate put into
/// the beam (their totals differ by orders of magnitude; the shares show where it goes).
pub fn plot_modal(path: &Path, m: &ModalComparison) -> Result<()> {
    let mut b = BarChart::new(
        "Where the power goes: share of each bare-beam mode",
        "mode (natural frequency)",
        "share of the net power (%)",
    );
    let share = |p: &[f64]| {
        let total: f64 = p.iter().sum();
        p.iter().map(|x| if total != 0.0 { 100.0 * x / total } else { 0.0 }).collect::<Vec<f64>>()
    };
    b.categories = m.mode_frequency_hz.iter().enumerate().map(|(r, f)| format!("{} ({f:.1} Hz)", r + 1)).collect();
    b.groups =
        vec![(format!("best: {}", m.best_label), share(&m.best)), (format!("poor: {}", m.poor_label), share(&m.poor))];
    b.size = (1200, 650);
    b.render(path)
}
