//! Report figures: line plots, stacked panels, grouped bars and heat maps, rendered to
//! SVG, PNG or PDF (chosen by the file extension) from one description.
//!
//! Design choices, and why:
//! * The figure is a plain data description (`LinePlot`, `BarChart`, ...), drawn once as
//!   SVG; PNG is that SVG rasterised with anti-aliasing (resvg) and PDF that SVG as vector
//!   paths (svg2pdf), so the three formats cannot disagree.
//! * All data are validated before any drawing: a NaN or infinity, mismatched lengths, or
//!   non-positive values on a log axis are returned as [`Error::Input`] naming the file and
//!   the series, instead of silently drawing a misleading figure.
//! * Text uses the DejaVu Sans font embedded in the binary, for layout and as outlines in
//!   the SVG ([`outline`]), so rendering needs no system font library and every viewer
//!   shows the same glyphs where the layout put them.
//! * Files are written atomically (see [`crate::io::atomic`]).
//! * Data outside explicit axis ranges is clipped to the plot area, and very long line
//!   series are reduced to a per-pixel min/max envelope (which draws identically) to keep
//!   SVG files small.
//! * Legends sit outside the data ([`legend`]); y axes with a unit take an SI prefix
//!   (`power (µW)`), other ticks use engineering notation ([`axis`]).
//! * Sizes are in pixels at 100 dpi; PNG files are rasterised at the process's resolution
//!   ([`set_png_dpi`], the command line's `--dpi`), SVG and PDF files are resolution-free.
//!
//! Axis labels, titles and legend entries are free text; by convention axis labels carry
//! the unit, e.g. `"time (s)"`, and `F_{T}` draws T as a subscript ([`text`]).

pub mod axis;
mod bars;
pub mod figure;
mod heat;
pub use figure::{save, Dest, Figure};
pub mod legend;
mod lines;
mod outline;
pub mod text;

use std::path::Path;
use std::sync::atomic::{AtomicU32, AtomicU8, Ordering};
use std::sync::OnceLock;

use plotters::coord::Shift;
use plotters::element::DashedPathElement;
use plotters::prelude::*;
use plotters::style::text_anchor::HPos;

use crate::error::{Error, Result};
use crate::io::atomic::write_atomic_bytes;

/// DejaVu Sans (see `assets/fonts/DejaVu-LICENSE.txt`).
static FONT_BYTES: &[u8] = include_bytes!("../../../assets/fonts/DejaVuSans.ttf");

/// Registers the embedded font as the `sans-serif` family, once per process.
fn ensure_font() -> Result<()> {
    static REGISTERED: OnceLock<std::result::Result<(), String>> = OnceLock::new();
    REGISTERED
        .get_or_init(|| {
            plotters::style::register_font("sans-serif", FontStyle::Normal, FONT_BYTES)
                .map_err(|_| "embedded font DejaVuSans.ttf could not be loaded".to_string())
        })
        .clone()
        .map_err(|m| Error::io("<font>", std::io::Error::other(m)))
}

/// The embedded font, parsed once, for drawing text as outlines.
fn font_ref() -> Result<&'static ab_glyph::FontRef<'static>> {
    static FONT: OnceLock<Option<ab_glyph::FontRef<'static>>> = OnceLock::new();
    FONT.get_or_init(|| ab_glyph::FontRef::try_from_slice(FONT_BYTES).ok())
        .as_ref()
        .ok_or_else(|| Error::io("<font>", std::io::Error::other("embedded font DejaVuSans.ttf could not be loaded")))
}

/// Colour cycle for series and bar groups: the Tableau 10 palette, chosen because its
/// colours stay distinguishable for most colour-vision deficiencies and in greyscale print.
pub const PALETTE: [(u8, u8, u8); 10] = [
    (31, 119, 180),
    (255, 127, 14),
    (44, 160, 44),
    (214, 39, 40),
    (148, 103, 189),
    (140, 86, 75),
    (227, 119, 194),
    (127, 127, 127),
    (188, 189, 34),
    (23, 190, 207),
];

/// The `i`-th colour of [`PALETTE`], cycling.
pub fn palette_color(i: usize) -> RGBColor {
    let (r, g, b) = PALETTE[i % PALETTE.len()];
    RGBColor(r, g, b)
}

/// Minor grid lines: faint, so that a log axis's eight per decade do not crowd the data.
const LIGHT_GRID: RGBAColor = RGBAColor(0, 0, 0, 0.035);

/// Text sizes, marker radius and line width at 100 dpi (pixels).
const TITLE_PX: u32 = 24;
const DESC_PX: u32 = 18;
const TICK_PX: u32 = 15;
const MARKER_R: i32 = 4;
const LINE_W: u32 = 2;

/// A dashed stroke through `points`, as wide as a series line.
fn dashed<C: Clone>(points: Vec<C>, color: RGBColor) -> DashedPathElement<std::vec::IntoIter<C>, u32> {
    DashedPathElement::new(points, 8, 5, color.stroke_width(LINE_W))
}

fn font(px: u32) -> TextStyle<'static> {
    (FontFamily::SansSerif, px).into_text_style(&(0u32, 0u32))
}

/// The formats every figure is written in, one bit per [`Format::ALL`] entry, as the
/// command line's `--formats` set them; 0: not set (a case's, else PNG and SVG).
static FORMATS: AtomicU8 = AtomicU8::new(0);

/// Formats when neither the command line nor the case names any: PNG and SVG.
const DEFAULT_FORMATS: u8 = 0b011;

/// How one run's figures look and which are drawn (a case's `[output.figures]`), in force
/// on this thread while a [`Scoped`] guard lives. The command line's `--formats` and
/// `--dpi` take precedence.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Settings {
    /// Every figure's width (px at 100 dpi), its height scaled with it.
    pub width: Option<u32>,
    /// Text and lines this many times their size against the figure.
    pub font_scale: Option<f64>,
    pub formats: Option<Vec<Format>>,
    pub dpi: Option<u32>,
    /// Every axis linear, also where the data span decades.
    pub linear: bool,
    /// Only figures whose names end in `_<one of these>`.
    pub only: Vec<String>,
}

impl From<&crate::case::FiguresSpec> for Settings {
    fn from(s: &crate::case::FiguresSpec) -> Self {
        let formats = s
            .formats
            .as_ref()
            .map(|names| Format::ALL.into_iter().filter(|f| names.iter().any(|n| n == f.ext())).collect::<Vec<_>>());
        Settings {
            width: s.width_px(),
            font_scale: s.font_scale,
            formats,
            dpi: s.dpi,
            linear: s.log_axes == Some(false),
            only: s.only.clone(),
        }
    }
}

thread_local! {
    static SETTINGS: std::cell::RefCell<Settings> = std::cell::RefCell::new(Settings::default());
}

/// The figure settings in force on this thread.
fn settings() -> Settings {
    SETTINGS.with(|s| s.borrow().clone())
}

/// Puts figure settings in force on this thread until it is dropped (then the previous
/// ones again), so one run's settings never leak into the next.
pub struct Scoped(Settings);

impl Scoped {
    pub fn new(s: Settings) -> Scoped {
        Scoped(SETTINGS.with(|c| c.replace(s)))
    }
}

impl Drop for Scoped {
    fn drop(&mut self) {
        let previous = std::mem::take(&mut self.0);
        SETTINGS.with(|c| *c.borrow_mut() = previous);
    }
}

/// Whether the figure named `name` is drawn under the settings in force.
pub fn wanted(name: &str) -> bool {
    let only = settings().only;
    only.is_empty() || only.iter().any(|o| name == o || name.ends_with(&format!("_{o}")))
}

/// Sets the formats of every figure this process writes (`png`, `svg`, `pdf`): the command
/// line's `--formats`. SVG is among them always: the HTML reports hold the SVG files.
pub fn set_figure_formats(names: &[String]) -> Result<()> {
    let mut mask = 0u8;
    for n in names {
        let name = n.trim().to_ascii_lowercase();
        let i = Format::ALL.iter().position(|f| f.ext() == name).ok_or_else(|| {
            Error::input("<cli>", "--formats", format!("`{n}` is not a figure format: use png, svg or pdf"))
        })?;
        mask |= 1 << i;
    }
    if mask & (1 << Format::Svg as u8) == 0 {
        return Err(Error::input("<cli>", "--formats", "must include svg: the reports hold every figure as SVG"));
    }
    FORMATS.store(mask, Ordering::Relaxed);
    Ok(())
}

/// The formats figures are written in ([`set_figure_formats`]).
pub fn figure_formats() -> Vec<Format> {
    let cli = FORMATS.load(Ordering::Relaxed);
    let case = settings().formats.map(|f| f.iter().fold(0u8, |m, f| m | 1 << *f as u8)).filter(|&m| m != 0);
    let mask = if cli != 0 { cli } else { case.unwrap_or(DEFAULT_FORMATS) };
    Format::ALL.into_iter().filter(|f| mask & (1 << *f as u8) != 0).collect()
}

/// The resolution PNG files are drawn at (dots per inch; sizes are given at 100) as the
/// command line's `--dpi` set it; 0: not set (a case's, else 100).
static PNG_DPI: AtomicU32 = AtomicU32::new(0);

/// The resolution of PNG files under the command line and the settings in force.
fn png_dpi() -> u32 {
    match PNG_DPI.load(Ordering::Relaxed) {
        0 => settings().dpi.unwrap_or(100),
        d => d,
    }
}

/// Sets the resolution of every PNG figure this process writes, like a printer setting:
/// the command line's `--dpi`. SVG files do not depend on it.
pub fn set_png_dpi(dpi: i64) -> Result<()> {
    if !(50..=600).contains(&dpi) {
        return Err(Error::input("<cli>", "--dpi", format!("{dpi} is outside 50..=600")));
    }
    PNG_DPI.store(dpi as u32, Ordering::Relaxed);
    Ok(())
}

/// A series' marker: a shape of its own, one per series of a plot in order, so that
/// series whose markers share a place (stems at one frequency, two estimates of one line)
/// stay apart in greyscale too; every series after the first is drawn hollow, so that one
/// marker on top of another leaves both visible.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Marker {
    pub shape: Shape,
    pub hollow: bool,
}

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Shape {
    Circle,
    Square,
    TriangleUp,
    Diamond,
    TriangleDown,
}

impl Marker {
    const SHAPES: [Shape; 5] = [Shape::Circle, Shape::Square, Shape::TriangleUp, Shape::Diamond, Shape::TriangleDown];

    /// The marker of the `i`-th series, shapes cycling.
    pub fn nth(i: usize) -> Marker {
        Marker { shape: Marker::SHAPES[i % Marker::SHAPES.len()], hollow: i > 0 }
    }

    /// The shape as a polygon around its centre (`None`: a circle), `r` its half-size.
    fn polygon(self, r: i32) -> Option<Vec<(i32, i32)>> {
        // Triangles and diamonds a little larger than r, for the same visual weight.
        let t = r + r / 3;
        match self.shape {
            Shape::Circle => None,
            Shape::Square => Some(vec![(-r, -r), (r, -r), (r, r), (-r, r)]),
            Shape::TriangleUp => Some(vec![(0, -t), (t, t * 2 / 3), (-t, t * 2 / 3)]),
            Shape::Diamond => Some(vec![(0, -t), (t, 0), (0, t), (-t, 0)]),
            Shape::TriangleDown => Some(vec![(0, t), (t, -t * 2 / 3), (-t, -t * 2 / 3)]),
        }
    }

    /// Draws the marker centred on `at` (pixels of `area`).
    fn draw<DB: DrawingBackend>(self, area: &DrawingArea<DB, Shift>, at: (i32, i32), color: RGBColor) -> DrawResult {
        let r = MARKER_R + self.hollow as i32;
        let style = if self.hollow { color.stroke_width(LINE_W) } else { color.filled() };
        match self.polygon(r) {
            None => area.draw(&Circle::new(at, r, style)).map_err(de),
            Some(p) => {
                let mut p: Vec<(i32, i32)> = p.into_iter().map(|(u, v)| (at.0 + u, at.1 + v)).collect();
                if self.hollow {
                    p.push(p[0]);
                    area.draw(&PathElement::new(p, style)).map_err(de)
                } else {
                    area.draw(&Polygon::new(p, style)).map_err(de)
                }
            }
        }
    }
}

// ---------------------------------------------------------------------------------------
// Public figure descriptions
// ---------------------------------------------------------------------------------------

/// How a series is drawn.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum SeriesStyle {
    /// Connected line (time histories, transfer functions).
    #[default]
    Line,
    /// Line with a marker at every sample (sparse data).
    LineMarkers,
    /// Markers only (measured or scattered points).
    Markers,
    /// Vertical stems from [`LinePlot::stem_base`] with a marker on top: line spectra,
    /// where each value belongs to one discrete frequency. Every stem stands at its true x:
    /// where several series share an x the longest is drawn first, so each shows, and
    /// each series has its own marker ([`Marker::nth`]).
    Stems,
    /// Dashed line: a series that may lie on top of another (a dashed line over a solid
    /// one leaves both visible).
    Dashed,
}

/// One data series of a [`LinePlot`]. `x` and `y` must have equal length.
#[derive(Clone, Debug, Default)]
pub struct Series {
    /// Legend text; an empty label keeps the series out of the legend.
    pub label: String,
    pub x: Vec<f64>,
    pub y: Vec<f64>,
    pub style: SeriesStyle,
    /// An angle's period in y (e.g. 360 for a phase in degrees): a line is not joined
    /// across a jump of more than half of it, where the angle wraps.
    pub wrap: Option<f64>,
    /// Indices i where the line starts anew: no line joins point i − 1 to point i (a gap
    /// in the data, e.g. candidates that could not be solved).
    pub breaks: Vec<usize>,
    /// The series' own colour (a point's or an actuator's, [`crate::report::palette`]);
    /// `None`: the plot's colour cycle by the series' place.
    pub colour: Option<RGBColor>,
}

impl Series {
    /// A series drawn as a connected line.
    pub fn line(label: impl Into<String>, x: Vec<f64>, y: Vec<f64>) -> Self {
        Series { label: label.into(), x, y, style: SeriesStyle::Line, wrap: None, breaks: Vec::new(), colour: None }
    }

    /// The same series in `colour` (a point's or an actuator's, the same in every figure).
    pub fn coloured(mut self, colour: RGBColor) -> Self {
        self.colour = Some(colour);
        self
    }

    /// The colour it is drawn in, being the `i`-th series of its plot.
    fn colour_at(&self, i: usize) -> RGBColor {
        self.colour.unwrap_or_else(|| palette_color(i))
    }

    /// The same series as an angle of `period` (y units): lines break where it wraps.
    pub fn wrapped(mut self, period: f64) -> Self {
        self.wrap = Some(period);
        self
    }

    /// The same series with its line broken before each index of `breaks`.
    pub fn broken_at(mut self, breaks: Vec<usize>) -> Self {
        self.breaks = breaks;
        self
    }

    /// The same series with another style.
    pub fn with_style(mut self, style: SeriesStyle) -> Self {
        self.style = style;
        self
    }
}

/// An x–y plot with any number of series.
#[derive(Clone, Debug)]
pub struct LinePlot {
    pub title: String,
    /// Axis text including the unit, e.g. `"frequency (Hz)"`.
    pub x_label: String,
    pub y_label: String,
    pub series: Vec<Series>,
    /// Fixed axis range; `None` fits the data (with a small margin on y).
    pub x_range: Option<(f64, f64)>,
    pub y_range: Option<(f64, f64)>,
    pub log_x: bool,
    pub log_y: bool,
    /// A symmetric-log y axis with this linear threshold (data units): signed values that
    /// span decades, such as power per harmonic. Takes precedence over `log_y`.
    pub symlog_y: Option<f64>,
    /// Where stems start (clamped into the axis; `f64::NEG_INFINITY` is the bottom, as for
    /// levels in dB). Zero by default; the bottom on a log axis.
    pub stem_base: f64,
    /// Lines of text under the legend.
    pub notes: Vec<String>,
    /// Figure size in pixels at 100 dpi (width, height); ignored inside a [`MultiPanel`].
    pub size: (u32, u32),
    /// x intervals shaded as a light band behind the series (where an estimate is not to
    /// be trusted), with their legend text.
    pub shaded: Vec<(f64, f64)>,
    pub shaded_label: String,
}

/// The fill of [`LinePlot::shaded`] bands: light, so every series stays readable on it.
pub const SHADE: RGBColor = RGBColor(255, 226, 170);

impl Default for LinePlot {
    fn default() -> Self {
        LinePlot {
            title: String::new(),
            x_label: String::new(),
            y_label: String::new(),
            series: Vec::new(),
            x_range: None,
            y_range: None,
            log_x: false,
            log_y: false,
            symlog_y: None,
            stem_base: 0.0,
            notes: Vec::new(),
            size: (1000, 600),
            shaded: Vec::new(),
            shaded_label: String::new(),
        }
    }
}

impl LinePlot {
    /// An empty plot of the default size (1000 × 600 px) with linear axes.
    pub fn new(title: impl Into<String>, x_label: impl Into<String>, y_label: impl Into<String>) -> Self {
        LinePlot { title: title.into(), x_label: x_label.into(), y_label: y_label.into(), ..Default::default() }
    }

    /// Writes the figure to `path` (`.png` or `.svg`).
    pub fn render(&self, path: impl AsRef<Path>) -> Result<()> {
        render_figure(self, path.as_ref())
    }

    /// The figure as SVG text (`name` names it in error messages).
    pub fn svg(&self, name: &str) -> Result<String> {
        svg_string(self, name)
    }
}

/// Several [`LinePlot`]s in one figure, e.g. force above acceleration: stacked
/// vertically, or row by row in `columns` columns.
#[derive(Clone, Debug)]
pub struct MultiPanel {
    /// Figure title above all panels (may be empty).
    pub title: String,
    pub panels: Vec<LinePlot>,
    pub columns: usize,
    /// Figure size in pixels at 100 dpi; `None` gives 1000 px wide (700 per column with
    /// several) and 320 px per row.
    pub size: Option<(u32, u32)>,
}

impl MultiPanel {
    pub fn new(title: impl Into<String>, panels: Vec<LinePlot>) -> Self {
        MultiPanel { title: title.into(), panels, columns: 1, size: None }
    }

    /// The same panels laid out in `columns` columns.
    pub fn with_columns(mut self, columns: usize) -> Self {
        self.columns = columns.max(1);
        self
    }

    /// Writes the figure to `path` (`.png` or `.svg`).
    pub fn render(&self, path: impl AsRef<Path>) -> Result<()> {
        render_figure(self, path.as_ref())
    }

    /// The figure as SVG text (`name` names it in error messages).
    pub fn svg(&self, name: &str) -> Result<String> {
        svg_string(self, name)
    }
}

/// Grouped bars: one cluster per category, one bar per group in each cluster. Values may
/// be negative (e.g. net power flowing back into an actuator); a zero line is drawn.
#[derive(Clone, Debug)]
pub struct BarChart {
    pub title: String,
    pub x_label: String,
    pub y_label: String,
    pub categories: Vec<String>,
    /// `(legend name, one value per category)`.
    pub groups: Vec<(String, Vec<f64>)>,
    /// Writes each bar's value on it (with the y axis's unit, SI-prefixed).
    pub show_values: bool,
    /// A logarithmic y axis (all values positive), for bars that differ by decades.
    pub log_y: bool,
    /// Lines of text under the legend.
    pub notes: Vec<String>,
    pub size: (u32, u32),
    /// Each group's colour (groups that are actuators); missing: the colour cycle.
    pub group_colours: Vec<RGBColor>,
    /// Each category's colour, for every bar in it (categories that are points or
    /// actuators); it takes precedence over the group's.
    pub category_colours: Vec<RGBColor>,
}

impl BarChart {
    pub fn new(title: impl Into<String>, x_label: impl Into<String>, y_label: impl Into<String>) -> Self {
        BarChart {
            title: title.into(),
            x_label: x_label.into(),
            y_label: y_label.into(),
            categories: Vec::new(),
            groups: Vec::new(),
            show_values: false,
            log_y: false,
            notes: Vec::new(),
            size: (1000, 600),
            group_colours: Vec::new(),
            category_colours: Vec::new(),
        }
    }

    /// The colour of group `g`'s bar in category `i`.
    fn bar_colour(&self, g: usize, i: usize) -> RGBColor {
        let group = || self.group_colours.get(g).copied().unwrap_or_else(|| palette_color(g));
        self.category_colours.get(i).copied().unwrap_or_else(group)
    }

    /// Writes the figure to `path` (`.png` or `.svg`).
    pub fn render(&self, path: impl AsRef<Path>) -> Result<()> {
        render_figure(self, path.as_ref())
    }

    /// The figure as SVG text (`name` names it in error messages).
    pub fn svg(&self, name: &str) -> Result<String> {
        svg_string(self, name)
    }
}

/// A colour map of `z` over a rectilinear grid, with a colour bar (viridis).
///
/// `x` (length nx) and `y` (length ny) are cell centres and must be strictly increasing;
/// spacing may be uneven. `z` is row-major ny × nx: `z[j * nx + i]` belongs to
/// `(x[i], y[j])`.
#[derive(Clone, Debug)]
pub struct HeatMap {
    pub title: String,
    pub x_label: String,
    pub y_label: String,
    pub x: Vec<f64>,
    pub y: Vec<f64>,
    pub z: Vec<f64>,
    /// Colour-bar text including the unit, e.g. `"power (W)"`.
    pub z_label: String,
    /// Logarithmic colour scale (all `z` must then be positive).
    pub log_z: bool,
    /// A signed field (a mode shape): a diverging scale, blue below zero and red above,
    /// symmetric about zero, white at zero.
    pub diverging: bool,
    /// Polylines drawn over the map (m): nodal lines, an outline.
    pub lines: Vec<Vec<(f64, f64)>>,
    /// Polylines drawn dashed (m): simply supported edges.
    pub dashed: Vec<Vec<(f64, f64)>>,
    /// Polylines drawn thin (m): free edges, the hatching of clamped ones.
    pub thin: Vec<Vec<(f64, f64)>>,
    /// A legend right of a map without a colour bar (a drawing: what its symbols are).
    pub legend: Vec<legend::Entry>,
    /// Points marked and labelled on the map: actuator feet, sensors, an optimum.
    pub marks: Vec<MapMark>,
    pub size: (u32, u32),
}

/// A labelled point on a [`HeatMap`].
#[derive(Clone, Debug)]
pub struct MapMark {
    pub x: f64,
    pub y: f64,
    pub label: String,
    pub marker: Marker,
}

/// Heat maps side by side (small multiples: a plate's mode shapes), `columns` per row.
#[derive(Clone, Debug)]
pub struct MapGrid {
    pub title: String,
    pub panels: Vec<HeatMap>,
    pub columns: usize,
}

impl MapGrid {
    pub fn render(&self, path: impl AsRef<Path>) -> Result<()> {
        render_figure(self, path.as_ref())
    }

    pub fn svg(&self, name: &str) -> Result<String> {
        svg_string(self, name)
    }
}

impl HeatMap {
    pub fn new(
        title: impl Into<String>,
        x_label: impl Into<String>,
        y_label: impl Into<String>,
        z_label: impl Into<String>,
    ) -> Self {
        HeatMap {
            title: title.into(),
            x_label: x_label.into(),
            y_label: y_label.into(),
            x: Vec::new(),
            y: Vec::new(),
            z: Vec::new(),
            z_label: z_label.into(),
            log_z: false,
            diverging: false,
            lines: Vec::new(),
            dashed: Vec::new(),
            thin: Vec::new(),
            legend: Vec::new(),
            marks: Vec::new(),
            size: (1000, 700),
        }
    }

    /// Writes the figure to `path` (`.png` or `.svg`).
    pub fn render(&self, path: impl AsRef<Path>) -> Result<()> {
        render_figure(self, path.as_ref())
    }

    /// The figure as SVG text (`name` names it in error messages).
    pub fn svg(&self, name: &str) -> Result<String> {
        svg_string(self, name)
    }
}

// ---------------------------------------------------------------------------------------
// Rendering driver
// ---------------------------------------------------------------------------------------

type DrawResult = std::result::Result<(), String>;

/// What every figure kind provides to [`render_figure`]: checks first, then drawing onto
/// any plotters backend (bitmap or SVG) so both formats share one code path.
trait Drawable {
    fn size(&self) -> (u32, u32);
    /// The figure with every axis linear, where it has a logarithmic one.
    fn linear(&self) -> Option<Self>
    where
        Self: Sized,
    {
        None
    }
    fn validate(&self, file: &str) -> Result<()>;
    fn draw<DB: DrawingBackend>(&self, root: &DrawingArea<DB, Shift>) -> DrawResult;
}

fn render_figure<F: Drawable>(fig: &F, path: &Path) -> Result<()> {
    let file = path.display().to_string();
    let ext = path.extension().map(|e| e.to_string_lossy().to_ascii_lowercase()).unwrap_or_default();
    let Some(format) = Format::ALL.into_iter().find(|f| f.ext() == ext) else {
        return Err(Error::input(file, "extension", "figures are written as .png, .svg or .pdf"));
    };
    let size = fig.size();
    if !(16..=20_000).contains(&size.0) || !(16..=20_000).contains(&size.1) {
        return Err(Error::input(file, "size", format!("{size:?} px is outside 16..=20000 px")));
    }
    let svg = svg_string(fig, &file)?;
    match format {
        Format::Svg => crate::io::atomic::write_atomic_string(path, &svg),
        Format::Png => write_atomic_bytes(path, &png_bytes(&svg, png_dpi(), &file)?),
        Format::Pdf => write_atomic_bytes(path, &pdf_bytes(&svg, &file)?),
    }
}

/// The file formats of a figure, all drawn from one SVG.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum Format {
    Png = 0,
    Svg = 1,
    Pdf = 2,
}

impl Format {
    pub const ALL: [Format; 3] = [Format::Png, Format::Svg, Format::Pdf];

    /// The file extension, without the dot.
    pub fn ext(self) -> &'static str {
        match self {
            Format::Png => "png",
            Format::Svg => "svg",
            Format::Pdf => "pdf",
        }
    }
}

/// The figure as SVG text (`name` names it in messages), its text as outlines, under the
/// settings in force: every axis linear if asked; drawn on a canvas of its size over the
/// font scale and shown at the width asked (the view box scales text and lines with it).
fn svg_string<F: Drawable>(fig: &F, name: &str) -> Result<String> {
    let s = settings();
    if s.linear {
        if let Some(lin) = fig.linear() {
            return svg_string(&lin, name);
        }
    }
    fig.validate(name)?;
    ensure_font()?;
    let (w, h) = fig.size();
    let k = s.width.map_or(1.0, |width| width as f64 / w as f64);
    let shown = ((w as f64 * k).round() as u32, (h as f64 * k).round() as u32);
    let zoom = k / s.font_scale.unwrap_or(1.0);
    let canvas = ((w as f64 * zoom).round().max(16.0) as u32, (h as f64 * zoom).round().max(16.0) as u32);
    let mut out = String::new();
    draw_on(SVGBackend::with_string(&mut out, canvas).into_drawing_area(), fig).map_err(|m| drawing_error(name, m))?;
    if shown != canvas {
        let from = format!("<svg width=\"{}\" height=\"{}\"", canvas.0, canvas.1);
        out = out.replacen(&from, &format!("<svg width=\"{}\" height=\"{}\"", shown.0, shown.1), 1);
    }
    Ok(outline::outline_text(&out, font_ref()?))
}

fn drawing_error(name: &str, what: impl std::fmt::Display) -> Error {
    Error::io(name, std::io::Error::other(format!("drawing figure: {what}")))
}

/// An SVG figure as PNG: [`raster`].
fn png_bytes(svg: &str, dpi: u32, name: &str) -> Result<Vec<u8>> {
    raster(svg, dpi, name)?.encode_png().map_err(|e| drawing_error(name, e))
}

/// An SVG figure rasterised, anti-aliased, at `dpi` (its sizes are pixels at 100 dpi).
fn raster(svg: &str, dpi: u32, name: &str) -> Result<resvg::tiny_skia::Pixmap> {
    use resvg::{tiny_skia, usvg};
    let tree = usvg::Tree::from_str(svg, &usvg::Options::default()).map_err(|e| drawing_error(name, e))?;
    let scale = dpi as f32 / 100.0;
    let size = tree.size().to_int_size().scale_by(scale).ok_or_else(|| drawing_error(name, "empty figure"))?;
    let mut pixmap =
        tiny_skia::Pixmap::new(size.width(), size.height()).ok_or_else(|| drawing_error(name, "empty figure"))?;
    pixmap.fill(tiny_skia::Color::WHITE);
    resvg::render(&tree, tiny_skia::Transform::from_scale(scale, scale), &mut pixmap.as_mut());
    Ok(pixmap)
}

/// An SVG figure as a one-page vector PDF, 100 of its pixels to the inch.
fn pdf_bytes(svg: &str, name: &str) -> Result<Vec<u8>> {
    use svg2pdf::usvg;
    let tree = usvg::Tree::from_str(svg, &usvg::Options::default()).map_err(|e| drawing_error(name, e))?;
    let page = svg2pdf::PageOptions { dpi: 100.0 };
    svg2pdf::to_pdf(&tree, svg2pdf::ConversionOptions::default(), page).map_err(|e| drawing_error(name, e))
}

fn draw_on<DB: DrawingBackend, F: Drawable>(root: DrawingArea<DB, Shift>, fig: &F) -> DrawResult {
    root.fill(&WHITE).map_err(de)?;
    fig.draw(&root)?;
    // `present` writes the file; the backend would swallow an error on drop.
    root.present().map_err(de)
}

fn de<E: std::fmt::Display>(e: E) -> String {
    e.to_string()
}

/// Puts `title` in a strip above `area` and returns the rest (the area itself if there
/// is no title).
fn titled<DB: DrawingBackend>(
    area: &DrawingArea<DB, Shift>,
    title: &str,
) -> std::result::Result<DrawingArea<DB, Shift>, String> {
    if title.is_empty() {
        return Ok(area.clone());
    }
    let (top, rest) = area.split_vertically(TITLE_PX + 20);
    let (w, h) = top.dim_in_pixel();
    text::draw(&top, title, (w as i32 / 2, h as i32 / 2 + 2), TITLE_PX, HPos::Center, false)?;
    Ok(rest)
}

/// Checks that every value is finite (and positive on a log axis).
fn check_values(file: &str, field: &str, v: &[f64], log: bool) -> Result<()> {
    if let Some((i, x)) = v.iter().enumerate().find(|(_, x)| !x.is_finite()) {
        return Err(Error::input(file, field, format!("value {x} at index {i} is not finite")));
    }
    if log {
        if let Some((i, x)) = v.iter().enumerate().find(|(_, x)| **x <= 0.0) {
            return Err(Error::input(
                file,
                field,
                format!("logarithmic axis needs positive values, found {x} at index {i}"),
            ));
        }
    }
    Ok(())
}

fn check_range(file: &str, field: &str, r: Option<(f64, f64)>, log: bool) -> Result<()> {
    if let Some((lo, hi)) = r {
        if !(lo.is_finite() && hi.is_finite() && lo < hi) || (log && lo <= 0.0) {
            let need = if log { "positive, finite, low < high" } else { "finite, low < high" };
            return Err(Error::input(file, field, format!("range ({lo}, {hi}) must be {need}")));
        }
    }
    Ok(())
}

/// Width in pixels reserved left of a plot for tick labels and the rotated axis text.
fn y_label_width<DB: DrawingBackend>(area: &DrawingArea<DB, Shift>, samples: &[String]) -> u32 {
    let tick = font(TICK_PX);
    let w = samples.iter().filter_map(|s| area.estimate_text_size(s, &tick).ok()).map(|(w, _)| w).max().unwrap_or(30);
    w + (DESC_PX + 24)
}

/// Height of the label area under a plot: tick labels and the axis text.
fn x_label_height() -> u32 {
    TICK_PX + DESC_PX + 30
}

/// Draws the axis texts of a chart whose plotting area spans `plot` (pixels of `area`):
/// x centred under it, y turned, centred beside it at the left edge of `area`.
fn axis_texts<DB: DrawingBackend>(
    area: &DrawingArea<DB, Shift>,
    plot: (std::ops::Range<i32>, std::ops::Range<i32>),
    x_label: &str,
    y_label: &str,
) -> DrawResult {
    let (xr, yr) = plot;
    let x_mid = (xr.start + xr.end) / 2;
    let y_mid = (yr.start + yr.end) / 2;
    let d = DESC_PX as i32;
    text::draw(area, x_label, (x_mid, yr.end + (TICK_PX + 16) as i32 + d / 2), DESC_PX, HPos::Center, false)?;
    text::draw(area, y_label, (12_i32 + d / 2 + 2, y_mid), DESC_PX, HPos::Center, true)
}

/// A chart's plotting area in pixels of `area` (plotters gives it in the backend's).
fn plot_pixels<DB: DrawingBackend, X, Y>(
    area: &DrawingArea<DB, Shift>,
    c: &ChartContext<'_, DB, Cartesian2d<X, Y>>,
) -> (std::ops::Range<i32>, std::ops::Range<i32>)
where
    X: plotters::coord::ranged1d::Ranged,
    Y: plotters::coord::ranged1d::Ranged,
{
    let (xr, yr) = c.plotting_area().get_pixel_range();
    let (bx, by) = area.get_base_pixel();
    (xr.start - bx..xr.end - bx, yr.start - by..yr.end - by)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn dir() -> tempfile::TempDir {
        tempfile::tempdir().unwrap()
    }

    /// Copies a test figure to `$BEAMFLOW_KEEP_PLOTS` (a directory) when that is set, for a
    /// human to look at; tests never write into the source tree.
    fn keep(path: &Path) {
        if let Some(dest) = std::env::var_os("BEAMFLOW_KEEP_PLOTS") {
            let dest = Path::new(&dest);
            if std::fs::create_dir_all(dest).is_ok() {
                let _ = std::fs::copy(path, dest.join(path.file_name().unwrap()));
            }
        }
    }

    fn check_file(path: &Path, min: u64) {
        let bytes = std::fs::read(path).unwrap();
        assert!(bytes.len() as u64 > min, "{} is only {} bytes", path.display(), bytes.len());
        if path.extension().unwrap() == "png" {
            assert_eq!(&bytes[..8], b"\x89PNG\r\n\x1a\n");
        } else {
            let s = String::from_utf8(bytes).unwrap();
            assert!(s.starts_with("<svg") && s.trim_end().ends_with("</svg>"));
        }
        let siblings: Vec<_> = std::fs::read_dir(path.parent().unwrap())
            .unwrap()
            .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
            .filter(|n| n.contains(".tmp-"))
            .collect();
        assert!(siblings.is_empty(), "temporary files left: {siblings:?}");
    }

    fn transient() -> LinePlot {
        let t: Vec<f64> = (0..2000).map(|i| i as f64 * 5e-5).collect();
        let f: Vec<f64> =
            t.iter().map(|t| 2.5 * (2.0 * std::f64::consts::PI * 200.0 * t).sin() * (-t * 20.0).exp()).collect();
        let g: Vec<f64> = t.iter().map(|t| 1.2 * (2.0 * std::f64::consts::PI * 350.0 * t).cos()).collect();
        let mut p = LinePlot::new("Actuator force", "time (s)", "force (N)");
        p.series.push(Series::line("actuator 0", t.clone(), f));
        p.series.push(Series::line("actuator 1", t, g));
        p
    }

    #[test]
    fn line_plot_png_and_svg() {
        let d = dir();
        let p = transient();
        for name in ["line.png", "line.svg"] {
            let path = d.path().join(name);
            p.render(&path).unwrap();
            check_file(&path, 5_000);
            keep(&path);
        }
    }

    #[test]
    fn log_axes_styles_and_clipping() {
        let d = dir();
        let f: Vec<f64> = (1..=400).map(|i| i as f64 * 5.0).collect();
        let mag: Vec<f64> = f.iter().map(|f| 1e-4 / ((1.0 - (f / 600.0).powi(2)).abs() + 0.02)).collect();
        let lines: Vec<f64> = (1..=12).map(|k| k as f64 * 150.0).collect();
        let amp: Vec<f64> = lines.iter().map(|f| 2e-3 / f * 100.0).collect();
        let mut p = LinePlot::new("Point mobility", "frequency (Hz)", "mobility (m/(N s))");
        p.log_x = true;
        p.log_y = true;
        p.series.push(Series::line("FE model", f.clone(), mag.clone()));
        p.series.push(Series::line("harmonics", lines.clone(), amp.clone()).with_style(SeriesStyle::Stems));
        p.series.push(
            Series::line(
                "",
                f.iter().step_by(40).copied().collect(),
                mag.iter().step_by(40).map(|m| m * 2.0).collect(),
            )
            .with_style(SeriesStyle::Markers),
        );
        p.series.push(
            Series::line("fit", vec![10.0, 100.0, 1000.0], vec![1e-6, 1e-5, 1e-4]).with_style(SeriesStyle::LineMarkers),
        );
        p.x_range = Some((20.0, 1500.0)); // cuts data: must be clipped, not drawn outside
        for name in ["loglog.png", "loglog.svg"] {
            let path = d.path().join(name);
            p.render(&path).unwrap();
            check_file(&path, 5_000);
            keep(&path);
        }
        // Linear stems spectrum with negative values.
        let mut s = LinePlot::new("Spectrum", "frequency (Hz)", "amplitude (m/s²)");
        s.series.push(
            Series::line("a", lines, amp.iter().enumerate().map(|(i, a)| if i % 3 == 0 { -a } else { *a }).collect())
                .with_style(SeriesStyle::Stems),
        );
        let path = d.path().join("stems.png");
        s.render(&path).unwrap();
        check_file(&path, 3_000);
        keep(&path);
    }

    /// A dense zig-zag (hundreds of periods of a signal per pixel column, as a whole run's
    /// history) is drawn as its per-column envelope; none of it may land outside the
    /// plot area (thick strokes joined at such sharp turns spike far past their points).
    #[test]
    fn dense_lines_stay_inside_the_plot_area() {
        let t: Vec<f64> = (0..36_000).map(|i| i as f64 * 1e-4).collect();
        // Like a power history: a squared 60 Hz signal with a 7th harmonic and a decaying
        // start-up, 200 samples a period.
        let w = 2.0 * std::f64::consts::PI * 60.0;
        let y: Vec<f64> = t
            .iter()
            .map(|t| (w * t).sin() * (w * t + 0.4).sin() * (1.0 + (-5.0 * t).exp()) + 0.1 * (7.0 * w * t).sin())
            .collect();
        let mut p = LinePlot::new("", "time (s)", "power (W)");
        p.series.push(Series::line("", t, y));
        let (w, h) = (1000u32, 600u32);
        let pixmap = raster(&p.svg("dense.svg").unwrap(), 100, "dense.png").unwrap();
        // The series' colour, or a blend of it with white at an anti-aliased edge.
        let is_blue = |x: u32, y: u32| {
            let c = pixmap.pixel(x, y).unwrap();
            c.blue() as i32 - c.red() as i32 > 40
        };
        // Rows that hold the series' colour: they must form one band, the plot area.
        let rows: Vec<u32> = (0..h).filter(|&y| (0..w).any(|x| is_blue(x, y))).collect();
        assert!(!rows.is_empty(), "the series was drawn");
        let (top, bottom) = (rows[0], *rows.last().unwrap());
        // The plot area is inside the 12-px margin and above the x labels.
        assert!(top >= 12, "series drawn at row {top}, above the plot area");
        assert!(bottom < h - (TICK_PX + DESC_PX + 30), "series drawn at row {bottom}, below the plot area");
    }

    #[test]
    fn degenerate_and_empty_data_still_render() {
        let d = dir();
        let mut p = LinePlot::new("Constant", "time (s)", "power (W)");
        p.series.push(Series::line("flat", vec![0.0, 1.0, 2.0], vec![3.0; 3]));
        p.series.push(Series::line("single", vec![1.0], vec![3.0]).with_style(SeriesStyle::Markers));
        p.render(d.path().join("flat.png")).unwrap();
        let mut z = LinePlot::new("Zero", "x (m)", "y (m)");
        z.series.push(Series::line("", vec![5.0; 4], vec![0.0; 4]));
        z.render(d.path().join("zero.svg")).unwrap();
        let mut tiny = LinePlot::new("Tiny", "time (s)", "displacement (m)");
        tiny.series.push(Series::line("u", vec![0.0, 1e-3, 2e-3], vec![1e-9, 3e-9, -2e-9]));
        tiny.render(d.path().join("tiny.png")).unwrap();
        keep(&d.path().join("tiny.png"));
        LinePlot::new("Empty", "x", "y").render(d.path().join("empty.png")).unwrap();
    }

    #[test]
    fn invalid_input_is_an_error_and_writes_nothing() {
        let d = dir();
        let path = d.path().join("bad.png");
        let mut p = LinePlot::new("t", "x", "y");
        p.series.push(Series::line("s", vec![0.0, 1.0], vec![0.0, f64::NAN]));
        let e = p.render(&path).unwrap_err().to_string();
        assert!(e.contains("bad.png") && e.contains("not finite") && e.contains("series[0] `s`.y"), "{e}");
        p.series[0].y[1] = 1.0;
        p.log_y = true;
        let e = p.render(&path).unwrap_err().to_string();
        assert!(e.contains("positive"), "{e}");
        p.log_y = false;
        p.series[0].x.push(2.0);
        assert!(p.render(&path).unwrap_err().to_string().contains("x has 3 values but y has 2"));
        p.series[0].x.pop();
        p.y_range = Some((1.0, 1.0));
        assert!(p.render(&path).is_err());
        p.y_range = None;
        assert!(p.render(d.path().join("bad.eps")).unwrap_err().to_string().contains(".png, .svg or .pdf"));
        let mut h = HeatMap::new("h", "x", "y", "z");
        h.x = vec![0.0, 1.0];
        h.y = vec![0.0];
        h.z = vec![1.0];
        assert!(h.render(&path).unwrap_err().to_string().contains("ny × nx"));
        h.x = vec![1.0, 0.0];
        h.z = vec![1.0, 2.0];
        assert!(h.render(&path).unwrap_err().to_string().contains("increase"));
        let mut b = BarChart::new("b", "x", "y");
        b.categories = vec!["a".into()];
        b.groups = vec![("g".into(), vec![1.0, 2.0])];
        assert!(b.render(&path).is_err());
        let m = MultiPanel::new(
            "m",
            vec![p.clone(), {
                let mut q = p.clone();
                q.series[0].x[0] = f64::INFINITY;
                q
            }],
        );
        assert!(m.render(&path).unwrap_err().to_string().contains("panels[1]"));
        assert_eq!(std::fs::read_dir(d.path()).unwrap().count(), 0);
    }

    /// Text is drawn as outlines of the embedded font, whatever fonts a viewer has, and a
    /// subscript is its own run: `F_{T}` is `F`, then a smaller `T` lower down.
    #[test]
    fn svg_text_is_outlined_and_subscripts_sit_below() {
        let mut p = LinePlot::new("F_{T} over time", "t (s)", "F (N)");
        p.series.push(Series::line("F_{T}", vec![0.0, 1.0], vec![0.0, 1.0]));
        let s = p.svg("t.svg").unwrap();
        assert!(!s.contains("<text") && !s.contains("font-family"), "{s}");
        let start = |label: &str| -> (f64, f64) {
            let tag = s.split("<path aria-label=\"").find(|t| t.starts_with(&format!("{label}\""))).unwrap();
            let d = tag.split(" d=\"M").nth(1).unwrap();
            let mut xy = d.split([' ', 'L', 'Q', 'C', 'Z']).map(|v| v.parse::<f64>().unwrap());
            (xy.next().unwrap(), xy.next().unwrap())
        };
        let (f, t) = (start("F"), start("T"));
        assert!(t.0 > f.0 && t.1 > f.1 + 2.0, "subscript T at {t:?} must sit right of and below F at {f:?}");
    }

    /// Every PNG is the SVG rasterised with anti-aliasing: a sloping line's edges blend
    /// into the background through many intermediate shades.
    #[test]
    fn png_line_edges_are_anti_aliased() {
        let mut p = LinePlot::new("", "x (m)", "y (m)");
        p.series.push(Series::line("", vec![0.0, 1.0], vec![0.0, 1.0]));
        let d = dir();
        let path = d.path().join("slope.png");
        p.render(&path).unwrap();
        let png = std::fs::read(&path).unwrap();
        let pixmap = resvg::tiny_skia::Pixmap::decode_png(&png).unwrap();
        let blue = palette_color(0);
        let shades: std::collections::BTreeSet<u8> = pixmap
            .pixels()
            .iter()
            .filter(|c| c.blue() > c.red() + 10 && (c.red(), c.green(), c.blue()) != (blue.0, blue.1, blue.2))
            .map(|c| c.red())
            .collect();
        assert!(shades.len() > 20, "only {} shades between the line's colour and white", shades.len());
    }

    #[test]
    fn pdf_is_vector_and_png_follows_dpi() {
        let d = dir();
        let p = transient();
        let pdf = d.path().join("line.pdf");
        p.render(&pdf).unwrap();
        let bytes = std::fs::read(&pdf).unwrap();
        assert!(bytes.starts_with(b"%PDF-") && bytes.len() > 2_000, "{} bytes", bytes.len());
        let text = String::from_utf8_lossy(&bytes);
        assert!(!text.contains("/Subtype /Image") && !text.contains("/Subtype/Image"), "a PDF figure holds no image");
        // 1000 × 600 px at 100 per inch: a 720 × 432 pt page.
        let media = text.split("/MediaBox [").nth(1).and_then(|m| m.split(']').next()).unwrap();
        let size: Vec<f64> = media.split_whitespace().map(|v| v.parse().unwrap()).collect();
        assert!((size[2] - 720.0).abs() < 0.01 && (size[3] - 432.0).abs() < 0.01, "page {media}");
        keep(&pdf);
    }

    #[test]
    fn multi_panel() {
        let d = dir();
        let top = transient();
        let mut bottom = LinePlot::new("Acceleration at sensor", "time (s)", "acceleration (m/s²)");
        let t: Vec<f64> = (0..500).map(|i| i as f64 * 2e-4).collect();
        bottom.series.push(Series::line("sensor", t.clone(), t.iter().map(|t| 30.0 * (900.0 * t).sin()).collect()));
        let m = MultiPanel::new("Actuator 0: force and response", vec![top, bottom]);
        for name in ["panels.png", "panels.svg"] {
            let path = d.path().join(name);
            m.render(&path).unwrap();
            check_file(&path, 5_000);
            keep(&path);
        }
    }

    #[test]
    fn bar_chart() {
        let d = dir();
        let mut b = BarChart::new("Mean power per actuator", "actuator", "power (W)");
        b.categories = vec!["left".into(), "centre".into(), "right".into(), "tip".into()];
        b.groups = vec![
            ("input".into(), vec![0.012, 0.02, 0.008, 0.015]),
            ("returned".into(), vec![-0.004, -0.001, 0.002, -0.009]),
            ("net".into(), vec![0.008, 0.019, 0.010, 0.006]),
        ];
        for name in ["bars.png", "bars.svg"] {
            let path = d.path().join(name);
            b.render(&path).unwrap();
            check_file(&path, 3_000);
            keep(&path);
        }
        b.groups = vec![(String::new(), vec![0.0; 4])];
        b.render(d.path().join("zero.png")).unwrap();
    }

    #[test]
    fn heat_map() {
        let d = dir();
        let (nx, ny) = (60, 40);
        let mut h = HeatMap::new("Power flow along the beam", "position (m)", "frequency (Hz)", "power (W)");
        h.x = (0..nx).map(|i| i as f64 * 0.025).collect();
        h.y = (0..ny).map(|j| 10.0 + j as f64 * 25.0).collect();
        h.z = (0..nx * ny)
            .map(|k| {
                let (x, f) = (h.x[k % nx], h.y[k / nx]);
                1e-6 + 1e-3 * ((x * 6.0).sin() * (f / 150.0).cos()).powi(2)
            })
            .collect();
        h.log_z = true;
        for name in ["heat_log.png", "heat_log.svg"] {
            let path = d.path().join(name);
            h.render(&path).unwrap();
            check_file(&path, 5_000);
            keep(&path);
        }
        h.log_z = false;
        h.title = "Linear scale".into();
        let path = d.path().join("heat_lin.png");
        h.render(&path).unwrap();
        check_file(&path, 5_000);
        keep(&path);
        // A single cell and a constant field are still drawable.
        let one = HeatMap { x: vec![0.0], y: vec![1.0], z: vec![2.0], ..HeatMap::new("one", "x", "y", "z") };
        one.render(d.path().join("one.png")).unwrap();
    }
}
