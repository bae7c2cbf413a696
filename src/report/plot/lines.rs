//! Line plots and panels of them: axes, series (lines, markers, stems), clipping to the
//! plot area and reduction of long series to what the pixels can show.

use std::borrow::Cow;

use plotters::coord::ranged1d::{Ranged, ValueFormatter};
use plotters::coord::Shift;
use plotters::prelude::*;

use super::axis::{fit_range, symlog, Axis, Scale};
use super::legend::{Entry, Legend, Place, Swatch};
use super::{
    axis_texts, check_range, check_values, de, font, plot_pixels, titled, x_label_height, y_label_width, DrawResult,
    Drawable, LinePlot, Marker, MultiPanel, Series, SeriesStyle, LINE_W, TICK_PX, TITLE_PX,
};
use crate::error::{Error, Result};

/// What the panels of one figure share so that their plot areas line up.
#[derive(Clone, Copy, Debug)]
pub(super) struct Share {
    pub y_area: u32,
    pub place: Place,
}

impl LinePlot {
    pub(super) fn check(&self, file: &str, prefix: &str) -> Result<()> {
        check_range(file, &format!("{prefix}x_range"), self.x_range, self.log_x)?;
        check_range(file, &format!("{prefix}y_range"), self.y_range, self.log_y && self.symlog_y.is_none())?;
        if let Some(c) = self.symlog_y {
            if !(c.is_finite() && c > 0.0) {
                return Err(Error::input(file, format!("{prefix}symlog_y"), format!("threshold {c} must be positive")));
            }
        }
        for (i, s) in self.series.iter().enumerate() {
            let name = format!("{prefix}series[{i}] `{}`", s.label);
            if s.x.len() != s.y.len() {
                return Err(Error::input(file, name, format!("x has {} values but y has {}", s.x.len(), s.y.len())));
            }
            check_values(file, &format!("{name}.x"), &s.x, self.log_x)?;
            check_values(file, &format!("{name}.y"), &s.y, self.log_y && self.symlog_y.is_none())?;
        }
        Ok(())
    }

    /// The series as drawn: y mapped onto a symmetric-log axis.
    fn drawn(&self) -> Cow<'_, [Series]> {
        match self.symlog_y {
            None => Cow::Borrowed(&self.series),
            Some(c) => Cow::Owned(
                self.series
                    .iter()
                    .map(|s| Series { y: s.y.iter().map(|&y| symlog(y, c)).collect(), ..s.clone() })
                    .collect(),
            ),
        }
    }

    fn y_scale(&self) -> Scale {
        match self.symlog_y {
            Some(c) => Scale::SymLog(c),
            None if self.log_y => Scale::Log,
            None => Scale::Linear,
        }
    }

    /// Axis ranges actually drawn (y in mapped values on a symmetric-log axis).
    pub(super) fn ranges(&self) -> ((f64, f64), (f64, f64)) {
        let series = self.drawn();
        // Lines may run edge to edge; isolated stems and markers need room at the sides.
        let points = series.iter().any(|s| matches!(s.style, SeriesStyle::Stems | SeriesStyle::Markers));
        let x_pad = if points { 0.03 } else { 0.0 };
        let xr = self
            .x_range
            .unwrap_or_else(|| fit_range(series.iter().flat_map(|s| s.x.iter().copied()), self.log_x, x_pad, false));
        let (xlo, xhi) = xr;
        let log_y = self.y_scale() == Scale::Log;
        let zero = self.stem_base == 0.0 && series.iter().any(|s| s.style == SeriesStyle::Stems);
        let yr = match (self.y_range, self.symlog_y) {
            (Some((lo, hi)), Some(c)) => (symlog(lo, c), symlog(hi, c)),
            (Some(r), None) => r,
            (None, _) => {
                // Fit y to the points visible in the x range only.
                let visible = series
                    .iter()
                    .flat_map(|s| s.x.iter().zip(&s.y))
                    .filter(|(x, _)| **x >= xlo && **x <= xhi)
                    .map(|(_, y)| *y);
                let (lo, hi) = fit_range(visible, log_y, 0.05, zero);
                // Stems up from the bottom need room under the lowest line to be seen.
                let bottom = self.stem_base == f64::NEG_INFINITY && !log_y;
                if bottom && series.iter().any(|s| s.style == SeriesStyle::Stems) {
                    (lo - 0.1 * (hi - lo), hi)
                } else {
                    (lo, hi)
                }
            }
        };
        (xr, yr)
    }

    /// The two axes, ready to draw.
    pub(super) fn axes(&self) -> (Axis, Axis) {
        let ((xlo, xhi), (ylo, yhi)) = self.ranges();
        let x = if self.log_x {
            Axis::log(xlo, xhi, &self.x_label, false)
        } else {
            Axis::linear(xlo, xhi, &self.x_label, false)
        };
        let y = match self.y_scale() {
            Scale::SymLog(c) => Axis::symlog(ylo, yhi, c, &self.y_label),
            Scale::Log => Axis::log(ylo, yhi, &self.y_label, true),
            Scale::Linear => Axis::linear(ylo, yhi, &self.y_label, true),
        };
        (x, y)
    }

    /// The legend: one entry per labelled series, then the notes.
    pub(super) fn legend(&self) -> Legend {
        let entries = self
            .series
            .iter()
            .enumerate()
            .filter(|(_, s)| !s.label.is_empty())
            .map(|(i, s)| Entry {
                label: s.label.clone(),
                color: s.colour_at(i),
                marker: Marker::nth(i),
                swatch: match s.style {
                    SeriesStyle::Line => Swatch::Line,
                    SeriesStyle::Dashed => Swatch::Dashed,
                    SeriesStyle::LineMarkers => Swatch::LineMarkers,
                    SeriesStyle::Markers => Swatch::Markers,
                    SeriesStyle::Stems => Swatch::Stems,
                },
            })
            .collect::<Vec<_>>();
        let mut entries = entries;
        if !self.shaded.is_empty() && !self.shaded_label.is_empty() {
            let marker = Marker::nth(0);
            entries.push(Entry { label: self.shaded_label.clone(), color: super::SHADE, swatch: Swatch::Bar, marker });
        }
        Legend { entries, notes: self.notes.clone() }
    }

    /// Width of the left label area this plot needs.
    pub(super) fn y_area<DB: DrawingBackend>(&self, area: &DrawingArea<DB, Shift>) -> u32 {
        y_label_width(area, &self.axes().1.samples())
    }

    /// Draws into `area`; `share` sets the left label width and the legend's place (to
    /// line up the panels of a figure).
    pub(super) fn draw_in<DB: DrawingBackend>(
        &self,
        area: &DrawingArea<DB, Shift>,
        share: Option<Share>,
    ) -> DrawResult {
        let legend = self.legend();
        let share = share.unwrap_or_else(|| Share {
            y_area: self.y_area(area),
            place: Legend::place(&[&legend], area, area.dim_in_pixel().0),
        });
        let body = titled(area, &self.title)?;
        let (chart_area, legend_area) = legend.split(share.place, &body);
        let (ax, ay) = self.axes();
        let mut b = ChartBuilder::on(&chart_area);
        b.margin(12).margin_right(20).x_label_area_size(x_label_height()).y_label_area_size(share.y_area);
        let bx = Box2 { x: (ax.lo, ax.hi), y: (ay.lo, ay.hi), log_x: self.log_x, log_y: ay.scale == Scale::Log };
        let series = self.drawn();
        let plot = match (ax.scale, ay.scale) {
            (Scale::Log, Scale::Linear) => {
                let mut c = b.build_cartesian_2d(ax.log_coord(), ay.lo..ay.hi).map_err(de)?;
                finish(&mut c, self, &series, &ax, &ay, &bx)?;
                plot_pixels(&chart_area, &c)
            }
            (Scale::Log, Scale::Log) => {
                let mut c = b.build_cartesian_2d(ax.log_coord(), ay.log_coord()).map_err(de)?;
                finish(&mut c, self, &series, &ax, &ay, &bx)?;
                plot_pixels(&chart_area, &c)
            }
            (Scale::Log, Scale::SymLog(_)) => {
                let mut c = b.build_cartesian_2d(ax.log_coord(), ay.symlog_coord()).map_err(de)?;
                finish(&mut c, self, &series, &ax, &ay, &bx)?;
                plot_pixels(&chart_area, &c)
            }
            (_, Scale::Log) => {
                let mut c = b.build_cartesian_2d(ax.lo..ax.hi, ay.log_coord()).map_err(de)?;
                finish(&mut c, self, &series, &ax, &ay, &bx)?;
                plot_pixels(&chart_area, &c)
            }
            (_, Scale::SymLog(_)) => {
                let mut c = b.build_cartesian_2d(ax.lo..ax.hi, ay.symlog_coord()).map_err(de)?;
                finish(&mut c, self, &series, &ax, &ay, &bx)?;
                plot_pixels(&chart_area, &c)
            }
            (_, Scale::Linear) => {
                let mut c = b.build_cartesian_2d(ax.lo..ax.hi, ay.lo..ay.hi).map_err(de)?;
                finish(&mut c, self, &series, &ax, &ay, &bx)?;
                plot_pixels(&chart_area, &c)
            }
        };
        axis_texts(&chart_area, plot.clone(), &ax.label, &ay.label)?;
        match (legend_area, share.place) {
            (Some(la), Place::Right(_)) => legend.draw(&la, 0, plot.1.start),
            (Some(la), Place::Below) => legend.draw(&la, plot.0.start, 0),
            _ => Ok(()),
        }
    }
}

/// Grid, ticks and series of a built chart.
fn finish<DB, X, Y>(
    c: &mut ChartContext<'_, DB, Cartesian2d<X, Y>>,
    p: &LinePlot,
    series: &[Series],
    ax: &Axis,
    ay: &Axis,
    bx: &Box2,
) -> DrawResult
where
    DB: DrawingBackend,
    X: Ranged<ValueType = f64> + ValueFormatter<f64>,
    Y: Ranged<ValueType = f64> + ValueFormatter<f64>,
{
    let fx = |v: &f64| ax.text(*v);
    let fy = |v: &f64| ay.text(*v);
    // Bands first: behind the grid and the data.
    let bands = p.shaded.iter().filter_map(|&(a, b)| {
        let (lo, hi) = (a.max(bx.x.0), b.min(bx.x.1));
        (lo < hi).then(|| Rectangle::new([(lo, bx.y.0), (hi, bx.y.1)], super::SHADE.filled()))
    });
    c.draw_series(bands).map_err(de)?;
    c.configure_mesh()
        .x_label_formatter(&fx)
        .y_label_formatter(&fy)
        .x_labels(8)
        .y_labels(8)
        .max_light_lines(4)
        .label_style(font(TICK_PX))
        .bold_line_style(BLACK.mix(0.15))
        .light_line_style(super::LIGHT_GRID)
        .draw()
        .map_err(de)?;
    draw_series(c, p, series, bx)
}

/// The visible data box, in data units, and how each axis is scaled.
pub(super) struct Box2 {
    x: (f64, f64),
    y: (f64, f64),
    log_x: bool,
    log_y: bool,
}

impl Box2 {
    /// To the space where the axis is linear (log10 for log axes).
    fn fwd(&self, p: (f64, f64)) -> (f64, f64) {
        (if self.log_x { p.0.log10() } else { p.0 }, if self.log_y { p.1.log10() } else { p.1 })
    }
    fn inv(&self, p: (f64, f64)) -> (f64, f64) {
        (if self.log_x { 10f64.powf(p.0) } else { p.0 }, if self.log_y { 10f64.powf(p.1) } else { p.1 })
    }
    fn lin_bounds(&self) -> ((f64, f64), (f64, f64)) {
        (self.fwd((self.x.0, self.y.0)), self.fwd((self.x.1, self.y.1)))
    }
    fn contains(&self, p: (f64, f64)) -> bool {
        p.0 >= self.x.0 && p.0 <= self.x.1 && p.1 >= self.y.0 && p.1 <= self.y.1
    }
}

/// Clips segment `a`–`b` to the box `[lo, hi]` (Liang–Barsky); `None` if fully outside.
fn clip_segment(a: (f64, f64), b: (f64, f64), lo: (f64, f64), hi: (f64, f64)) -> Option<((f64, f64), (f64, f64))> {
    let (dx, dy) = (b.0 - a.0, b.1 - a.1);
    let (mut t0, mut t1) = (0.0f64, 1.0f64);
    for (p, q) in [(-dx, a.0 - lo.0), (dx, hi.0 - a.0), (-dy, a.1 - lo.1), (dy, hi.1 - a.1)] {
        if p == 0.0 {
            if q < 0.0 {
                return None;
            }
        } else {
            let r = q / p;
            if p < 0.0 {
                t0 = t0.max(r);
            } else {
                t1 = t1.min(r);
            }
        }
    }
    // Unclipped ends are returned exactly, so consecutive segments join without gaps.
    let at = |t: f64| {
        if t == 0.0 {
            a
        } else if t == 1.0 {
            b
        } else {
            (a.0 + t * dx, a.1 + t * dy)
        }
    };
    (t0 <= t1).then(|| (at(t0), at(t1)))
}

/// Splits a polyline into the pieces inside the box (in axis-linear space), so nothing is
/// drawn outside the plot area when explicit ranges cut the data.
/// A series' samples as runs to be joined: all of them, or for an angle the runs between
/// its wraps (jumps of more than half its period).
fn wrap_runs(s: &Series) -> Vec<(&[f64], &[f64])> {
    let mut runs = Vec::new();
    let mut start = 0;
    for i in 1..s.y.len() {
        let wraps = s.wrap.is_some_and(|period| (s.y[i] - s.y[i - 1]).abs() > 0.5 * period);
        if wraps || s.breaks.contains(&i) {
            runs.push((&s.x[start..i], &s.y[start..i]));
            start = i;
        }
    }
    runs.push((&s.x[start..], &s.y[start..]));
    runs
}

fn clip_polyline(x: &[f64], y: &[f64], bx: &Box2) -> Vec<Vec<(f64, f64)>> {
    let (lo, hi) = bx.lin_bounds();
    let pts: Vec<(f64, f64)> = x.iter().zip(y).map(|(&x, &y)| bx.fwd((x, y))).collect();
    let mut out: Vec<Vec<(f64, f64)>> = Vec::new();
    let mut cur: Vec<(f64, f64)> = Vec::new();
    if pts.len() == 1 && bx.contains((x[0], y[0])) {
        return vec![vec![(x[0], y[0])]];
    }
    for w in pts.windows(2) {
        match clip_segment(w[0], w[1], lo, hi) {
            Some((a, b)) => {
                if cur.last() != Some(&a) {
                    if cur.len() > 1 {
                        out.push(std::mem::take(&mut cur));
                    }
                    cur.clear();
                    cur.push(a);
                }
                cur.push(b);
            }
            None => {
                if cur.len() > 1 {
                    out.push(std::mem::take(&mut cur));
                }
                cur.clear();
            }
        }
    }
    if cur.len() > 1 {
        out.push(cur);
    }
    out.into_iter().map(|piece| piece.into_iter().map(|p| bx.inv(p)).collect()).collect()
}

/// Reduces a long polyline with non-decreasing x to first/min/max/last per pixel column:
/// the drawn line is the same, the file is far smaller.
fn decimate(pts: Vec<(f64, f64)>, columns: usize, bx: &Box2) -> Vec<(f64, f64)> {
    if pts.len() <= 4 * columns || pts.windows(2).any(|w| w[1].0 < w[0].0) {
        return pts;
    }
    let ((x0, _), (x1, _)) = bx.lin_bounds();
    let col = |x: f64| {
        let u = if bx.log_x { x.log10() } else { x };
        (((u - x0) / (x1 - x0)) * columns as f64).floor() as i64
    };
    let mut out = Vec::with_capacity(4 * columns + 4);
    let mut start = 0;
    while start < pts.len() {
        let c = col(pts[start].0);
        let mut end = start + 1;
        while end < pts.len() && col(pts[end].0) == c {
            end += 1;
        }
        let bucket = &pts[start..end];
        let (mut imin, mut imax) = (0, 0);
        for (i, p) in bucket.iter().enumerate() {
            if p.1 < bucket[imin].1 {
                imin = i;
            }
            if p.1 > bucket[imax].1 {
                imax = i;
            }
        }
        let mut keep = vec![0, imin, imax, bucket.len() - 1];
        keep.sort_unstable();
        keep.dedup();
        out.extend(keep.into_iter().map(|i| bucket[i]));
        start = end;
    }
    out
}

/// Splits a polyline where it turns back in y; consecutive runs share that point.
fn monotone_runs(pts: &[(f64, f64)]) -> Vec<Vec<(f64, f64)>> {
    let mut runs = Vec::new();
    let mut run: Vec<(f64, f64)> = Vec::new();
    let mut dir = 0i8;
    for &p in pts {
        if let Some(&q) = run.last() {
            // Direction of this step in y: up, down, or flat (which continues any run).
            let d = (p.1 > q.1) as i8 - (p.1 < q.1) as i8;
            if d != 0 && dir != 0 && d != dir {
                runs.push(std::mem::replace(&mut run, vec![q]));
            }
            if d != 0 {
                dir = d;
            }
        }
        run.push(p);
    }
    if run.len() > 1 || runs.is_empty() {
        runs.push(run);
    }
    runs
}

fn draw_series<DB, X, Y>(
    c: &mut ChartContext<'_, DB, Cartesian2d<X, Y>>,
    p: &LinePlot,
    series: &[Series],
    bx: &Box2,
) -> DrawResult
where
    DB: DrawingBackend,
    X: Ranged<ValueType = f64> + ValueFormatter<f64>,
    Y: Ranged<ValueType = f64> + ValueFormatter<f64>,
{
    let columns = c.plotting_area().dim_in_pixel().0.max(1) as usize;
    // Stems start at their base (zero by default), or at the bottom of a log axis, clamped
    // into the box.
    let base = if bx.log_y { bx.y.0 } else { p.stem_base.clamp(bx.y.0, bx.y.1) };
    let stems: Vec<usize> = (0..series.len()).filter(|&i| series[i].style == SeriesStyle::Stems).collect();
    if !stems.is_empty() && !bx.log_y && base == 0.0 {
        let axis = PathElement::new(vec![(bx.x.0, 0.0), (bx.x.1, 0.0)], BLACK.stroke_width(1));
        c.draw_series(std::iter::once(axis)).map_err(de)?;
    }
    let lw = LINE_W;
    // Every stem at its true x; the longest first, so that a shorter one at the same x is
    // drawn over it and both show.
    let mut lines: Vec<(f64, f64, usize)> = stems
        .iter()
        .flat_map(|&i| series[i].x.iter().zip(&series[i].y).map(move |(&x, &y)| (x, y, i)))
        .filter(|(x, _, _)| *x >= bx.x.0 && *x <= bx.x.1)
        .map(|(x, y, i)| (x, y.clamp(bx.y.0, bx.y.1), i))
        .collect();
    let length = |y: f64| (bx.fwd((1.0, y)).1 - bx.fwd((1.0, base)).1).abs();
    lines.sort_by(|a, b| length(b.1).total_cmp(&length(a.1)));
    c.draw_series(
        lines
            .iter()
            .map(|&(x, y, i)| PathElement::new(vec![(x, base), (x, y)], series[i].colour_at(i).stroke_width(lw))),
    )
    .map_err(de)?;
    for (i, s) in series.iter().enumerate() {
        let color = s.colour_at(i);
        if matches!(s.style, SeriesStyle::Line | SeriesStyle::LineMarkers | SeriesStyle::Dashed) {
            // A decimated piece is a per-column envelope whose strokes reverse within a
            // pixel column; joins of a thick polyline at such turns spike far outside the
            // plot area, so it is drawn as runs that are monotone in y, joined only where
            // they do not turn back.
            let mut paths = Vec::new();
            for pc in wrap_runs(s).into_iter().flat_map(|(x, y)| clip_polyline(x, y, bx)) {
                if pc.len() > 4 * columns {
                    paths.extend(monotone_runs(&decimate(pc, columns, bx)));
                } else {
                    paths.push(pc);
                }
            }
            if s.style == SeriesStyle::Dashed {
                c.draw_series(paths.into_iter().map(|pc| super::dashed(pc, color))).map_err(de)?;
            } else {
                c.draw_series(paths.into_iter().map(|pc| PathElement::new(pc, color.stroke_width(lw)))).map_err(de)?;
            }
        }
        if matches!(s.style, SeriesStyle::LineMarkers | SeriesStyle::Markers | SeriesStyle::Stems) {
            let area = c.plotting_area();
            let (bx0, by0) = area.get_base_pixel();
            let shift = area.strip_coord_spec();
            for q in s.x.iter().zip(&s.y).map(|(&x, &y)| (x, y)).filter(|&q| bx.contains(q)) {
                let (u, v) = area.map_coordinate(&q);
                Marker::nth(i).draw(&shift, (u - bx0, v - by0), color)?;
            }
        }
    }
    Ok(())
}

impl Drawable for LinePlot {
    fn size(&self) -> (u32, u32) {
        self.size
    }
    fn linear(&self) -> Option<Self> {
        (self.log_x || self.log_y || self.symlog_y.is_some()).then(|| self.linearised())
    }
    fn validate(&self, file: &str) -> Result<()> {
        self.check(file, "")
    }
    fn draw<DB: DrawingBackend>(&self, root: &DrawingArea<DB, Shift>) -> DrawResult {
        self.draw_in(root, None)
    }
}

impl MultiPanel {
    fn rows(&self) -> usize {
        self.panels.len().div_ceil(self.columns.max(1)).max(1)
    }

    /// The panels, each over the union of their x ranges where they all share one x axis
    /// (the same label and scale): stacked panels then read off the same x at the same
    /// place, even where one has markers (a padded range) and another lines only.
    fn aligned(&self) -> Cow<'_, [LinePlot]> {
        let first = &self.panels[0];
        if self.panels.iter().any(|p| p.x_label != first.x_label || p.log_x != first.log_x) {
            return Cow::Borrowed(&self.panels);
        }
        let (lo, hi) = self
            .panels
            .iter()
            .map(|p| p.ranges().0)
            .fold((f64::INFINITY, f64::NEG_INFINITY), |a, r| (a.0.min(r.0), a.1.max(r.1)));
        Cow::Owned(self.panels.iter().map(|p| LinePlot { x_range: Some((lo, hi)), ..p.clone() }).collect())
    }
}

impl LinePlot {
    /// The same plot on linear axes.
    fn linearised(&self) -> LinePlot {
        LinePlot { log_x: false, log_y: false, symlog_y: None, ..self.clone() }
    }
}

impl Drawable for MultiPanel {
    fn size(&self) -> (u32, u32) {
        let title = if self.title.is_empty() { 0 } else { TITLE_PX + 20 };
        let cols = self.columns.max(1) as u32;
        let width = if cols == 1 { 1000 } else { 700 * cols };
        self.size.unwrap_or((width, 320 * self.rows() as u32 + title))
    }
    fn linear(&self) -> Option<Self> {
        let log = self.panels.iter().any(|p| p.log_x || p.log_y || p.symlog_y.is_some());
        log.then(|| MultiPanel { panels: self.panels.iter().map(LinePlot::linearised).collect(), ..self.clone() })
    }
    fn validate(&self, file: &str) -> Result<()> {
        if self.panels.is_empty() {
            return Err(Error::input(file, "panels", "a multi-panel figure needs at least one panel"));
        }
        self.panels.iter().enumerate().try_for_each(|(i, p)| p.check(file, &format!("panels[{i}].")))
    }
    fn draw<DB: DrawingBackend>(&self, root: &DrawingArea<DB, Shift>) -> DrawResult {
        let body = titled(root, &self.title)?;
        let cells = body.split_evenly((self.rows(), self.columns.max(1)));
        let panels = self.aligned();
        // One label width and one legend place for all panels, so the plot areas line up.
        let legends: Vec<Legend> = panels.iter().map(LinePlot::legend).collect();
        let refs: Vec<&Legend> = legends.iter().collect();
        let place = Legend::place(&refs, &body, cells[0].dim_in_pixel().0);
        let y_area = panels.iter().map(|p| p.y_area(&body)).max().unwrap_or(0);
        for (area, panel) in cells.iter().zip(panels.iter()) {
            panel.draw_in(area, Some(Share { y_area, place }))?;
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn polylines_split_where_they_turn_back() {
        let p = [(0.0, 0.0), (1.0, 2.0), (2.0, 2.0), (3.0, 5.0), (4.0, 1.0), (5.0, 0.0), (6.0, 3.0)];
        let runs = monotone_runs(&p);
        assert_eq!(runs, vec![p[..4].to_vec(), p[3..6].to_vec(), p[5..].to_vec()]);
        assert_eq!(monotone_runs(&p[..1]), vec![p[..1].to_vec()]);
    }

    #[test]
    fn clipping_and_decimation() {
        let bx = Box2 { x: (0.0, 1.0), y: (0.0, 1.0), log_x: false, log_y: false };
        // Leaves through the top, comes back through the top further right: two pieces.
        let pieces = clip_polyline(&[-1.0, 0.5, 1.5, 0.5], &[0.5, 0.5, 2.0, 0.2], &bx);
        assert_eq!(pieces.len(), 2, "{pieces:?}");
        assert_eq!(pieces[0][0], (0.0, 0.5));
        assert!((pieces[0][2].0 - 0.5 - 1.0 / 3.0).abs() < 1e-12 && pieces[0][2].1 == 1.0, "{pieces:?}");
        assert!((pieces[1][0].0 - (1.5 - 1.0 / 1.8)).abs() < 1e-12 && pieces[1][1] == (0.5, 0.2), "{pieces:?}");
        // Leaving and re-entering at the same point stays one piece.
        assert_eq!(
            clip_polyline(&[0.5, 2.0, 0.5], &[0.5, 0.5, 0.5], &bx),
            vec![vec![(0.5, 0.5), (1.0, 0.5), (0.5, 0.5)]]
        );
        assert!(clip_polyline(&[2.0, 3.0], &[2.0, 3.0], &bx).is_empty());
        let n = 100_000;
        let pts: Vec<(f64, f64)> = (0..n).map(|i| (i as f64 / n as f64, (i as f64).sin())).collect();
        let d = decimate(pts, 500, &bx);
        assert!(d.len() <= 2000 && d.len() >= 500, "{}", d.len());
        assert!(d.iter().any(|p| p.1 > 0.999) && d.iter().any(|p| p.1 < -0.999));
    }

    /// Stacked panels over one x axis share its range: markers pad theirs, lines do not.
    #[test]
    fn panels_over_one_x_axis_share_its_range() {
        let mut lines = LinePlot::new("", "f (Hz)", "y (m)");
        lines.series.push(Series::line("a", vec![10.0, 100.0], vec![1.0, 2.0]));
        let mut markers = lines.clone();
        markers.series[0].style = SeriesStyle::Markers;
        let m = MultiPanel::new("", vec![lines.clone(), markers.clone()]);
        let ranges: Vec<_> = m.aligned().iter().map(|p| p.ranges().0).collect();
        assert_eq!(ranges[0], ranges[1]);
        assert!(ranges[0].0 < 10.0 && ranges[0].1 > 100.0, "{ranges:?}");
        markers.x_label = "t (s)".into();
        assert!(MultiPanel::new("", vec![lines, markers]).aligned().iter().all(|p| p.x_range.is_none()));
    }

    #[test]
    fn angles_break_where_they_wrap() {
        let s = Series::line("phase", vec![0.0, 1.0, 2.0, 3.0, 4.0], vec![170.0, 179.0, -178.0, -170.0, 10.0]);
        assert_eq!(wrap_runs(&s).len(), 1, "a line is joined unless it is an angle");
        let angle = s.clone().wrapped(360.0);
        let runs = wrap_runs(&angle);
        assert_eq!(
            runs,
            vec![(&[0.0, 1.0][..], &[170.0, 179.0][..]), (&[2.0, 3.0, 4.0][..], &[-178.0, -170.0, 10.0][..])]
        );
    }
}
