//! Grouped bar charts.

use plotters::coord::Shift;
use plotters::prelude::*;
use plotters::style::text_anchor::HPos;

use super::axis::{fit_range, Axis};
use super::legend::{Entry, Legend, Place, Swatch};
use super::text::{self, eng, prefixable, si};
use super::{
    axis_texts, check_values, de, font, palette_color, plot_pixels, px, titled, x_label_height, y_label_width,
    BarChart, DrawResult, Drawable, TICK_PX,
};
use crate::error::{Error, Result};

impl BarChart {
    fn legend(&self) -> Legend {
        let entries = self
            .groups
            .iter()
            .enumerate()
            .filter(|(_, (name, _))| !name.is_empty())
            .map(|(g, (name, _))| Entry { label: name.clone(), color: palette_color(g), swatch: Swatch::Bar })
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
            check_values(file, &field, v, false)?;
        }
        Ok(())
    }
    fn draw<DB: DrawingBackend>(&self, root: &DrawingArea<DB, Shift>) -> DrawResult {
        let n = self.categories.len();
        // Room above and below the bars for their values.
        let pad = if self.show_values { 0.12 } else { 0.06 };
        let (ylo, yhi) = fit_range(self.groups.iter().flat_map(|(_, v)| v.iter().copied()), false, pad, true);
        let (xlo, xhi) = (-0.5, n as f64 - 0.5);
        let ay = Axis::linear(ylo, yhi, &self.y_label, true);
        let legend = self.legend();
        let place = Legend::place(&[&legend], root, root.dim_in_pixel().0);
        let body = titled(root, &self.title)?;
        let (chart_area, legend_area) = legend.split(place, &body);
        let cats = &self.categories;
        // Category names are drawn here, not by plotters, so they may take several lines.
        let lines = cats.iter().map(|c| c.lines().count()).max().unwrap_or(1).max(1) as u32;
        let row = px(TICK_PX) * 6 / 5;
        let mut b = ChartBuilder::on(&chart_area);
        b.margin(px(12))
            .margin_right(px(20))
            .x_label_area_size(x_label_height() + (lines - 1) * row)
            .y_label_area_size(y_label_width(&chart_area, &ay.samples()));
        let mut c = b.build_cartesian_2d(xlo..xhi, ylo..yhi).map_err(de)?;
        let fy = |v: &f64| ay.text(*v);
        c.configure_mesh()
            .disable_x_mesh()
            .x_labels(0)
            .y_label_formatter(&fy)
            .y_labels(8)
            .label_style(font(px(TICK_PX)))
            .bold_line_style(BLACK.mix(0.15))
            .light_line_style(BLACK.mix(0.05))
            .draw()
            .map_err(de)?;

        let m = self.groups.len() as f64;
        let w = 0.8 / m;
        for (g, (_, values)) in self.groups.iter().enumerate() {
            let color = palette_color(g);
            let bars = values.iter().enumerate().map(|(i, &v)| {
                let x0 = i as f64 - 0.4 + g as f64 * w;
                Rectangle::new([(x0 + 0.02 * w, 0.0), (x0 + 0.98 * w, v)], color.filled())
            });
            c.draw_series(bars).map_err(de)?;
        }
        c.draw_series(std::iter::once(PathElement::new(vec![(xlo, 0.0), (xhi, 0.0)], BLACK.stroke_width(1))))
            .map_err(de)?;
        let plot = plot_pixels(&chart_area, &c);
        let (bx, by) = chart_area.get_base_pixel();
        for (i, cat) in cats.iter().enumerate() {
            let (x, _) = c.backend_coord(&(i as f64, 0.0));
            for (k, line) in cat.lines().enumerate() {
                let y = plot.1.end + px(6) as i32 + row as i32 / 2 + k as i32 * row as i32;
                text::draw(&chart_area, line, (x - bx, y), px(TICK_PX), HPos::Center, false)?;
            }
        }
        let plot = (plot.0, plot.1.start..plot.1.end + ((lines - 1) * row) as i32);
        if self.show_values {
            let size = px(TICK_PX);
            for (g, (_, values)) in self.groups.iter().enumerate() {
                for (i, &v) in values.iter().enumerate() {
                    let (x, y) = c.backend_coord(&(i as f64 - 0.4 + (g as f64 + 0.5) * w, v));
                    // Above a bar that rises, below one that falls.
                    let dy = if v >= 0.0 { -(size as i32) } else { size as i32 };
                    text::draw(&chart_area, &self.value_text(v), (x - bx, y - by + dy), size, HPos::Center, false)?;
                }
            }
        }
        axis_texts(&chart_area, plot.clone(), &self.x_label, &ay.label)?;
        match (legend_area, place) {
            (Some(la), Place::Right(_)) => legend.draw(&la, 0, plot.1.start),
            (Some(la), Place::Below) => legend.draw(&la, plot.0.start, 0),
            _ => Ok(()),
        }
    }
}
