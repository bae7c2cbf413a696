//! Heat maps with a colour bar.

use plotters::coord::ranged1d::{Ranged, ValueFormatter};
use plotters::coord::types::RangedCoordf64;
use plotters::coord::Shift;
use plotters::prelude::*;

use super::axis::{fit_range, linear_ticks, Axis};
use super::legend::Legend;
use super::text::plain;
use super::{
    check_values, de, font, plot_pixels, titled, x_label_height, y_label_width, DrawResult, Drawable, HeatMap, MapGrid,
    DESC_PX, TICK_PX,
};
use crate::error::{Error, Result};

/// Viridis, sampled at nine evenly spaced points and interpolated linearly: perceptually
/// ordered and readable in greyscale and by most colour-blind readers.
const VIRIDIS: [(u8, u8, u8); 9] = [
    (68, 1, 84),
    (72, 40, 120),
    (62, 73, 137),
    (49, 104, 142),
    (38, 130, 142),
    (31, 158, 137),
    (53, 183, 121),
    (110, 206, 88),
    (253, 231, 37),
];

/// Colour for `t` in [0, 1] (clamped).
fn viridis(t: f64) -> RGBColor {
    let s = t.clamp(0.0, 1.0) * (VIRIDIS.len() - 1) as f64;
    let i = (s.floor() as usize).min(VIRIDIS.len() - 2);
    let f = s - i as f64;
    let (a, b) = (VIRIDIS[i], VIRIDIS[i + 1]);
    let mix = |p: u8, q: u8| (p as f64 + f * (q as f64 - p as f64)).round() as u8;
    RGBColor(mix(a.0, b.0), mix(a.1, b.1), mix(a.2, b.2))
}

/// Blue–white–red for `t` in [0, 1] (clamped), white at ½: a signed field's two signs
/// apart, zero (a nodal line) white. Endpoints from ColorBrewer's RdBu.
fn diverging(t: f64) -> RGBColor {
    let t = t.clamp(0.0, 1.0);
    let (end, s) = if t < 0.5 { ((33.0, 102.0, 172.0), 1.0 - 2.0 * t) } else { ((178.0, 24.0, 43.0), 2.0 * t - 1.0) };
    let mix = |e: f64| (255.0 + s * (e - 255.0)).round() as u8;
    RGBColor(mix(end.0), mix(end.1), mix(end.2))
}

/// Cell edges from cell centres: midpoints inside, half a step beyond the ends.
fn edges(c: &[f64]) -> Vec<f64> {
    if c.len() == 1 {
        let h = if c[0] == 0.0 { 0.5 } else { 0.5 * c[0].abs() };
        return vec![c[0] - h, c[0] + h];
    }
    let mut e = Vec::with_capacity(c.len() + 1);
    e.push(c[0] - 0.5 * (c[1] - c[0]));
    e.extend(c.windows(2).map(|w| 0.5 * (w[0] + w[1])));
    e.push(c[c.len() - 1] + 0.5 * (c[c.len() - 1] - c[c.len() - 2]));
    e
}

impl HeatMap {
    /// The colour of a value already mapped to [0, 1].
    fn colour(&self, t: f64) -> RGBColor {
        if self.diverging {
            diverging(t)
        } else {
            viridis(t)
        }
    }

    /// Colour-scale range (data units) and the map from `z` to [0, 1].
    fn z_scale(&self) -> ((f64, f64), impl Fn(f64) -> f64) {
        let (lo, hi) = if self.diverging {
            let m = self.z.iter().fold(0.0f64, |m, v| m.max(v.abs()));
            let m = if m > 0.0 { m } else { 1.0 };
            (-m, m)
        } else {
            fit_range(self.z.iter().copied(), self.log_z, 0.0, false)
        };
        let log = self.log_z;
        let tf = move |v: f64| if log { v.log10() } else { v };
        let (a, b) = (tf(lo), tf(hi));
        ((lo, hi), move |z: f64| (tf(z) - a) / (b - a))
    }
}

impl Drawable for HeatMap {
    fn size(&self) -> (u32, u32) {
        self.size
    }
    fn validate(&self, file: &str) -> Result<()> {
        let (nx, ny) = (self.x.len(), self.y.len());
        if nx == 0 || ny == 0 {
            return Err(Error::input(file, "x, y", "a heat map needs at least one x and one y value"));
        }
        if self.z.len() != nx * ny {
            return Err(Error::input(
                file,
                "z",
                format!("{} values, expected ny × nx = {ny} × {nx} = {}", self.z.len(), nx * ny),
            ));
        }
        for (name, v) in [("x", &self.x), ("y", &self.y)] {
            check_values(file, name, v, false)?;
            if let Some(i) = v.windows(2).position(|w| w[1] <= w[0]) {
                return Err(Error::input(file, name, format!("values must increase strictly (index {})", i + 1)));
            }
        }
        check_values(file, "z", &self.z, self.log_z)
    }
    fn draw<DB: DrawingBackend>(&self, root: &DrawingArea<DB, Shift>) -> DrawResult {
        let body = titled(root, &self.title)?;
        let ((zlo, zhi), unit) = self.z_scale();
        let az = if self.log_z {
            Axis::log(zlo, zhi, &self.z_label, true)
        } else {
            Axis::linear(zlo, zhi, &self.z_label, true)
        };
        // Colour bar strip: 40 px of gradient plus its labels on the right; for a map that
        // is only a drawing (no `z_label`), its legend there, if it has one.
        let bar_labels = y_label_width(root, &az.samples());
        let legend = Legend { entries: self.legend.clone(), notes: Vec::new() };
        let bar_w = match (self.z_label.is_empty(), legend.is_empty()) {
            (false, _) => bar_labels + 56,
            (true, false) => legend.width(root),
            (true, true) => 0,
        };
        let (w, _) = body.dim_in_pixel();
        let (main, bar) = body.split_horizontally(w.saturating_sub(bar_w));
        let (xe, ye) = (edges(&self.x), edges(&self.y));
        let (xlo, xhi, ylo, yhi) = (xe[0], xe[xe.len() - 1], ye[0], ye[ye.len() - 1]);
        let ay = Axis::linear(ylo, yhi, &self.y_label, false);

        let mut c = ChartBuilder::on(&main)
            .margin(12)
            .x_label_area_size(x_label_height())
            .y_label_area_size(y_label_width(root, &ay.samples()))
            .build_cartesian_2d(xlo..xhi, ylo..yhi)
            .map_err(de)?;
        let (fx, fy) = (linear_ticks(xlo, xhi), |v: &f64| ay.text(*v));
        let (xd, yd) = (plain(&self.x_label), plain(&self.y_label));
        c.configure_mesh()
            .disable_mesh()
            .x_desc(&xd)
            .y_desc(&yd)
            .x_label_formatter(&fx)
            .y_label_formatter(&fy)
            .label_style(font(TICK_PX))
            .axis_desc_style(font(DESC_PX))
            .draw()
            .map_err(de)?;
        let nx = self.x.len();
        let cells = self.z.iter().enumerate().map(|(k, &z)| {
            let (i, j) = (k % nx, k / nx);
            Rectangle::new([(xe[i], ye[j]), (xe[i + 1], ye[j + 1])], self.colour(unit(z)).filled())
        });
        c.draw_series(cells).map_err(de)?;
        for line in &self.lines {
            c.draw_series(std::iter::once(PathElement::new(line.clone(), BLACK.stroke_width(2)))).map_err(de)?;
        }
        c.draw_series(self.dashed.iter().map(|l| super::dashed(l.clone(), BLACK))).map_err(de)?;
        c.draw_series(self.thin.iter().map(|l| PathElement::new(l.clone(), BLACK.stroke_width(1)))).map_err(de)?;
        for m in &self.marks {
            let area = c.plotting_area().strip_coord_spec();
            let (bx, by) = area.get_base_pixel();
            let (px, py) = c.backend_coord(&(m.x, m.y));
            let at = (px - bx, py - by);
            m.marker.draw(&area, at, BLACK)?;
            if !m.label.is_empty() {
                // Labels of points in the right third go to their left, and of points near
                // the top below them: inside the map, never over its frame.
                let (w, _) = area.dim_in_pixel();
                let (dx, pos) = if at.0 > 2 * w as i32 / 3 { (-9, super::HPos::Right) } else { (9, super::HPos::Left) };
                let dy = if at.1 < 2 * TICK_PX as i32 { 12 } else { -12 };
                super::text::draw(&area, &m.label, (at.0 + dx, at.1 + dy), TICK_PX, pos, false)?;
            }
        }

        if self.z_label.is_empty() {
            let top = plot_pixels(&main, &c).1.start;
            return if legend.is_empty() { Ok(()) } else { legend.draw(&bar, 0, top) };
        }
        let mut cb = ChartBuilder::on(&bar);
        cb.margin(12)
            .margin_left(4)
            .x_label_area_size(x_label_height())
            .y_label_area_size(0)
            .right_y_label_area_size(bar_labels);
        let fz = |v: &f64| az.text(*v);
        let label = plain(&az.label);
        if self.log_z {
            let c = cb.build_cartesian_2d(0f64..1f64, az.log_coord()).map_err(de)?;
            colour_bar(c, &label, &unit, &|t| self.colour(t), fz, |t| zlo * (zhi / zlo).powf(t))
        } else {
            let c = cb.build_cartesian_2d(0f64..1f64, zlo..zhi).map_err(de)?;
            colour_bar(c, &label, &unit, &|t| self.colour(t), fz, |t| zlo + t * (zhi - zlo))
        }
    }
}

impl Drawable for MapGrid {
    fn size(&self) -> (u32, u32) {
        let rows = self.panels.len().div_ceil(self.columns.max(1)) as u32;
        let (w, h) = self.panels.first().map_or((600, 420), |p| p.size);
        (w * self.columns.max(1) as u32, h * rows.max(1) + 60)
    }
    fn validate(&self, file: &str) -> Result<()> {
        self.panels.iter().try_for_each(|p| p.validate(file))
    }
    fn draw<DB: DrawingBackend>(&self, root: &DrawingArea<DB, Shift>) -> DrawResult {
        let body = titled(root, &self.title)?;
        let cols = self.columns.max(1);
        let rows = self.panels.len().div_ceil(cols).max(1);
        for (p, area) in self.panels.iter().zip(body.split_evenly((rows, cols))) {
            p.draw(&area)?;
        }
        Ok(())
    }
}

/// Draws the colour gradient as 256 slices, with ticks and the label on the right (the
/// chart has only a right-hand label area, so the mesh puts its labels there).
fn colour_bar<DB, Y>(
    mut c: ChartContext<'_, DB, Cartesian2d<RangedCoordf64, Y>>,
    label: &str,
    unit: &dyn Fn(f64) -> f64,
    colour: &dyn Fn(f64) -> RGBColor,
    fy: impl Fn(&f64) -> String,
    at: impl Fn(f64) -> f64,
) -> DrawResult
where
    DB: DrawingBackend,
    Y: Ranged<ValueType = f64> + ValueFormatter<f64>,
{
    let slices = (0..256).map(|k| {
        let (a, b) = (at(k as f64 / 256.0), at((k + 1) as f64 / 256.0));
        Rectangle::new([(0.0, a), (1.0, b)], colour(unit(0.5 * (a + b))).filled())
    });
    c.draw_series(slices).map_err(de)?;
    c.configure_mesh()
        .disable_mesh()
        .x_labels(0)
        .y_labels(8)
        // A longer tick keeps its label clear of the tick (else "1e-4" reads as "-1e-4").
        .set_all_tick_mark_size(6)
        .y_desc(label)
        .y_label_formatter(&fy)
        .label_style(font(TICK_PX))
        .axis_desc_style(font(DESC_PX))
        .draw()
        .map_err(de)
}
