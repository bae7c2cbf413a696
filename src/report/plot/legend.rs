//! Legends, drawn outside the data: in a strip right of the plot, or below it when the
//! labels are too long for a strip that leaves the plot most of the width.

use plotters::coord::Shift;
use plotters::prelude::*;
use plotters::style::text_anchor::HPos;

use super::{dashed, de, text, DrawResult, Marker, LINE_W, TICK_PX};

/// How an entry's sample is drawn: as its series is.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Swatch {
    Line,
    Dashed,
    LineMarkers,
    Markers,
    Stems,
    Bar,
    /// A thin line: a free edge.
    Thin,
    /// A line hatched on one side: a clamped edge.
    Hatched,
}

/// One legend entry.
#[derive(Clone, Debug)]
pub struct Entry {
    pub label: String,
    pub color: RGBColor,
    pub swatch: Swatch,
    /// The series' marker shape, where the swatch has a marker.
    pub marker: Marker,
}

/// A legend: entries, then free lines of text (notes such as a ratio beside the paper's).
#[derive(Clone, Debug, Default)]
pub struct Legend {
    pub entries: Vec<Entry>,
    pub notes: Vec<String>,
}

/// Where a figure's legends go; one placement for all panels of a figure, so that their
/// plot areas line up.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Place {
    None,
    /// A strip this wide right of the plot.
    Right(u32),
    /// Below the plot.
    Below,
}

/// Sample width, gap before the text, padding around.
const SAMPLE: u32 = 26;
const GAP: u32 = 8;
const PAD: u32 = 10;

fn row_h() -> u32 {
    TICK_PX * 3 / 2
}

impl Legend {
    pub fn is_empty(&self) -> bool {
        self.entries.is_empty() && self.notes.is_empty()
    }

    /// Width the legend needs beside a plot (pixels).
    pub fn width<DB: DrawingBackend>(&self, area: &DrawingArea<DB, Shift>) -> u32 {
        let f = TICK_PX;
        let entries = self.entries.iter().map(|e| (SAMPLE + GAP) + text::width(area, &e.label, f)).max().unwrap_or(0);
        let notes = self.notes.iter().map(|n| text::width(area, n, f)).max().unwrap_or(0);
        entries.max(notes) + 2 * PAD
    }

    /// Height of the legend's rows (pixels).
    pub fn height(&self) -> u32 {
        let gap = if self.notes.is_empty() || self.entries.is_empty() { 0 } else { row_h() / 2 };
        (self.entries.len() + self.notes.len()) as u32 * row_h() + gap + PAD
    }

    /// Right of the plot when it takes at most 30 % of `total_w`, else below.
    pub fn place<DB: DrawingBackend>(legends: &[&Legend], area: &DrawingArea<DB, Shift>, total_w: u32) -> Place {
        let w = legends.iter().filter(|l| !l.is_empty()).map(|l| l.width(area)).max();
        match w {
            None => Place::None,
            Some(w) if w * 10 <= total_w * 3 => Place::Right(w),
            Some(_) => Place::Below,
        }
    }

    /// Splits `area` into the plot's part and the legend's.
    pub fn split<DB: DrawingBackend>(
        &self,
        place: Place,
        area: &DrawingArea<DB, Shift>,
    ) -> (DrawingArea<DB, Shift>, Option<DrawingArea<DB, Shift>>) {
        let (w, h) = area.dim_in_pixel();
        match place {
            Place::Right(lw) => {
                let (a, b) = area.split_horizontally(w.saturating_sub(lw));
                (a, Some(b))
            }
            Place::Below if !self.is_empty() => {
                let (a, b) = area.split_vertically(h.saturating_sub(self.height()));
                (a, Some(b))
            }
            _ => (area.clone(), None),
        }
    }

    /// Draws the legend into `area`, its first row at `top` and its samples from `left`
    /// (pixels in `area`).
    pub fn draw<DB: DrawingBackend>(&self, area: &DrawingArea<DB, Shift>, left: i32, top: i32) -> DrawResult {
        let r = row_h() as i32;
        let x0 = left + PAD as i32;
        let mut y = top + r / 2;
        for e in &self.entries {
            swatch(area, e, (x0, y))?;
            text::draw(area, &e.label, (x0 + (SAMPLE + GAP) as i32, y), TICK_PX, HPos::Left, false)?;
            y += r;
        }
        if !self.entries.is_empty() {
            y += r / 2;
        }
        for n in &self.notes {
            text::draw(area, n, (x0, y), TICK_PX, HPos::Left, false)?;
            y += r;
        }
        Ok(())
    }
}

fn swatch<DB: DrawingBackend>(area: &DrawingArea<DB, Shift>, e: &Entry, (x, y): (i32, i32)) -> DrawResult {
    let w = SAMPLE as i32;
    let stroke = e.color.stroke_width(LINE_W);
    let dot = |at: (i32, i32)| e.marker.draw(area, at, e.color);
    let h = TICK_PX as i32 / 2;
    match e.swatch {
        Swatch::Line => area.draw(&PathElement::new(vec![(x, y), (x + w, y)], stroke)).map_err(de),
        Swatch::Dashed => area.draw(&dashed(vec![(x, y), (x + w, y)], e.color)).map_err(de),
        Swatch::LineMarkers => {
            area.draw(&PathElement::new(vec![(x, y), (x + w, y)], stroke)).map_err(de)?;
            dot((x + w / 2, y))
        }
        Swatch::Markers => dot((x + w / 2, y)),
        Swatch::Stems => {
            area.draw(&PathElement::new(vec![(x + w / 2, y + h), (x + w / 2, y - h + 2)], stroke)).map_err(de)?;
            dot((x + w / 2, y - h + 2))
        }
        Swatch::Thin => area.draw(&PathElement::new(vec![(x, y), (x + w, y)], e.color.stroke_width(1))).map_err(de),
        Swatch::Hatched => {
            area.draw(&PathElement::new(vec![(x, y), (x + w, y)], stroke)).map_err(de)?;
            let ticks = (0..4).map(|k| x + 4 + k * (w - 4) / 4);
            ticks
                .map(|u| PathElement::new(vec![(u, y), (u - 5, y + 6)], e.color.stroke_width(1)))
                .try_for_each(|t| area.draw(&t).map_err(de))
        }
        Swatch::Bar => area
            .draw(&Rectangle::new([(x + w / 4, y - h + 1), (x + 3 * w / 4, y + h - 1)], e.color.filled()))
            .map_err(de),
    }
}
