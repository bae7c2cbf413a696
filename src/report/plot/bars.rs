//! Grouped bar charts.

use plotters::coord::ranged1d::{Ranged, ValueFormatter};
use plotters::coord::types::RangedCoordf64;
use plotters::coord::Shift;
use plotters::prelude::*;
use plotters::style::text_anchor::HPos;

use super::axis::{fit_range, Axis};
use super::legend::{Entry, Legend, Place, Swatch};
use super::text::{self, eng, prefixable, si};
use super::{
    axis_texts, check_values, de, font, plot_pixels, titled, x_label_height, y_label_width, BarChart, DrawResult,
    Drawable, Marker, TICK_PX,
};
use crate::error::{Error, Result};

impl BarChart {
    fn legend(&self) -> Legend {
        let entries = self
            .groups
            .iter()
            .enumerate()
            .filter(|(_, (name, _))| !name.is_empty())
            .map(|(g, (name, _))| Entry {
                label: name.clone(),
                color: self.bar_colour(g, usize::MAX),
                swatch: Swatch::Bar,
                marker: Marker::nth(0),
            })
            .collect();
        Legend { entries, notes: self.notes.clone() }
    }

    /// A bar's value as text, in the y axis's unit with an SI prefix where it takes one.
    fn value_text(&self, v: f64) -> String {
        match prefixable(&self.y_label) {
            Some((_, unit)) => si(v, unit, 3),
            None => eng(v, 3),
        }
    }
}

impl Drawable for BarChart {
    fn size(&self) -> (u32, u32) {
        self.size
    }
    fn linear(&self) -> Option<Self> {
        self.log_y.then(|| BarChart { log_y: false, ..self.clone() })
    }
    fn validate(&self, file: &str) -> Result<()> {
        if self.categories.is_empty() || self.groups.is_empty() {
            return Err(Error::input(file, "categories", "a bar chart needs at least one category and one group"));
        }
        for (i, (name, v)) in self.groups.iter().enumerate() {
            let field = format!("groups[{i}] `{name}`");
            if v.len() != self.categories.len() {
                return Err(Error::input(
                    file,
                    field,
                    format!("{} values for {} categories", v.len(), self.categories.len()),
                ));
            }
            check_values(file, &field, v, self.log_y)?;
        }
        Ok(())
    }
    fn draw<DB: DrawingBackend>(&self, root: &DrawingArea<DB, Shift>) -> DrawResult {
        let n = self.categories.len();
        let values = || self.groups.iter().flat_map(|(_, v)| v.iter().copied());
        // Room above and below the bars for their values.
        let pad = if self.show_values { 0.12 } else { 0.06 };
        let (xlo, xhi) = (-0.5, n as f64 - 0.5);
        let ay = if self.log_y {
            // Bars rise from the decade below the smallest value.
            let (lo, hi) = fit_range(values(), true, pad, false);
            Axis::log(10f64.powf(lo.log10().floor()), hi, &self.y_label, true)
        } else {
            let (lo, hi) = fit_range(values(), false, pad, true);
            Axis::linear(lo, hi, &self.y_label, true)
        };
        let legend = self.legend();
        let place = Legend::place(&[&legend], root, root.dim_in_pixel().0);
        let body = titled(root, &self.title)?;
        let (chart_area, legend_area) = legend.split(place, &body);
        // Category names are drawn here, not by plotters, so they may take several lines.
        let lines = self.categories.iter().map(|c| c.lines().count()).max().unwrap_or(1).max(1) as u32;
        let mut b = ChartBuilder::on(&chart_area);
        b.margin(12)
            .margin_right(20)
            .x_label_area_size(x_label_height() + (lines - 1) * row())
            .y_label_area_size(y_label_width(&chart_area, &ay.samples()));
        let plot = if self.log_y {
            let c = b.build_cartesian_2d(xlo..xhi, ay.log_coord()).map_err(de)?;
            self.bars_on(c, &chart_area, &ay, ay.lo)?
        } else {
            let c = b.build_cartesian_2d(xlo..xhi, ay.lo..ay.hi).map_err(de)?;
            self.bars_on(c, &chart_area, &ay, 0.0)?
        };
        let plot = (plot.0, plot.1.start..plot.1.end + ((lines - 1) * row()) as i32);
        axis_texts(&chart_area, plot.clone(), &self.x_label, &ay.label)?;
        match (legend_area, place) {
            (Some(la), Place::Right(_)) => legend.draw(&la, 0, plot.1.start),
            (Some(la), Place::Below) => legend.draw(&la, plot.0.start, 0),
            _ => Ok(()),
        }
    }
}

/// Height of a line of category names.
fn row() -> u32 {
    TICK_PX * 6 / 5
}

impl BarChart {
    /// Grid, bars from `base`, category names and values on a built chart; returns the
    /// plotting area in pixels of `chart_area`.
    fn bars_on<DB: DrawingBackend, Y>(
        &self,
        mut c: ChartContext<'_, DB, Cartesian2d<RangedCoordf64, Y>>,
        chart_area: &DrawingArea<DB, Shift>,
        ay: &Axis,
        base: f64,
    ) -> std::result::Result<(std::ops::Range<i32>, std::ops::Range<i32>), String>
    where
        Y: Ranged<ValueType = f64> + ValueFormatter<f64>,
    {
        let fy = |v: &f64| ay.text(*v);
        c.configure_mesh()
            .disable_x_mesh()
            .x_labels(0)
            .y_label_formatter(&fy)
            .y_labels(8)
            .label_style(font(TICK_PX))
            .bold_line_style(BLACK.mix(0.15))
            .light_line_style(super::LIGHT_GRID)
            .draw()
            .map_err(de)?;
        let (xlo, xhi) = (-0.5, self.categories.len() as f64 - 0.5);
        let w = 0.8 / self.groups.len() as f64;
        for (g, (_, values)) in self.groups.iter().enumerate() {
            let bars = values.iter().enumerate().map(|(i, &v)| {
                let x0 = i as f64 - 0.4 + g as f64 * w;
                Rectangle::new([(x0 + 0.02 * w, base), (x0 + 0.98 * w, v)], self.bar_colour(g, i).filled())
            });
            c.draw_series(bars).map_err(de)?;
        }
        c.draw_series(std::iter::once(PathElement::new(vec![(xlo, base), (xhi, base)], BLACK.stroke_width(1))))
            .map_err(de)?;
        let plot = plot_pixels(chart_area, &c);
        let (bx, by) = chart_area.get_base_pixel();
        for (i, cat) in self.categories.iter().enumerate() {
            let (x, _) = c.backend_coord(&(i as f64, base));
            for (k, line) in cat.lines().enumerate() {
                let y = plot.1.end + 6_i32 + row() as i32 / 2 + k as i32 * row() as i32;
                text::draw(chart_area, line, (x - bx, y), TICK_PX, HPos::Center, false)?;
            }
        }
        if self.show_values {
            let size = TICK_PX;
            for (g, (_, values)) in self.groups.iter().enumerate() {
                for (i, &v) in values.iter().enumerate() {
                    let (x, y) = c.backend_coord(&(i as f64 - 0.4 + (g as f64 + 0.5) * w, v));
                    // Above a bar that rises, below one that falls.
                    let dy = if v >= base { -(size as i32) } else { size as i32 };
                    text::draw(chart_area, &self.value_text(v), (x - bx, y - by + dy), size, HPos::Center, false)?;
                }
            }
        }
        Ok(plot)
    }
}
