//! Report figures: line plots, stacked panels, grouped bars and heat maps, rendered to
//! PNG or SVG (chosen by the file extension) from one description.
//!
//! Design choices, and why:
//! * The figure is a plain data description (`LinePlot`, `BarChart`, ...), so the same
//!   figure can be written as PNG for quick looks and as SVG for a report.
//! * All data are validated before any drawing: a NaN or infinity, mismatched lengths, or
//!   non-positive values on a log axis are returned as [`Error::Input`] naming the file and
//!   the series, instead of silently drawing a misleading figure.
//! * Text uses the DejaVu Sans font embedded in the binary, so rendering needs no system
//!   font library and looks the same on every machine. (SVG files name the `sans-serif`
//!   family and let the viewer's font render the text; the embedded font is used for
//!   layout.)
//! * Files are written atomically (see [`crate::io::atomic`]).
//! * Data outside explicit axis ranges is clipped to the plot area, and very long line
//!   series are reduced to a per-pixel min/max envelope (which draws identically) to keep
//!   SVG files small.
//!
//! Axis labels are free text; by convention they carry the unit, e.g. `"time (s)"`.

use std::path::Path;
use std::sync::OnceLock;

use plotters::coord::combinators::{BindKeyPoints, LogCoord, WithKeyPoints};
use plotters::coord::ranged1d::{Ranged, ValueFormatter};
use plotters::coord::types::RangedCoordf64;
use plotters::coord::Shift;
use plotters::prelude::*;
use plotters::style::text_anchor::{HPos, Pos, VPos};

use crate::error::{Error, Result};
use crate::io::atomic::write_atomic;

/// DejaVu Sans (see `assets/fonts/DejaVu-LICENSE.txt`).
static FONT_BYTES: &[u8] = include_bytes!("../../assets/fonts/DejaVuSans.ttf");

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

const TITLE_PX: u32 = 24;
const DESC_PX: u32 = 18;
const TICK_PX: u32 = 15;
const MARKER_R: i32 = 3;
const LINE_W: u32 = 2;

fn font(px: u32) -> TextStyle<'static> {
    (FontFamily::SansSerif, px).into_text_style(&(0u32, 0u32))
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
    /// Vertical stems from zero (or the bottom of a log axis) with a marker on top:
    /// line spectra, where each value belongs to one discrete frequency.
    Stems,
}

/// One data series of a [`LinePlot`]. `x` and `y` must have equal length.
#[derive(Clone, Debug, Default)]
pub struct Series {
    /// Legend text; an empty label keeps the series out of the legend.
    pub label: String,
    pub x: Vec<f64>,
    pub y: Vec<f64>,
    pub style: SeriesStyle,
}

impl Series {
    /// A series drawn as a connected line.
    pub fn line(label: impl Into<String>, x: Vec<f64>, y: Vec<f64>) -> Self {
        Series { label: label.into(), x, y, style: SeriesStyle::Line }
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
    /// Figure size in pixels (width, height); ignored inside a [`MultiPanel`].
    pub size: (u32, u32),
}

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
            size: (1000, 600),
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
}

/// Several [`LinePlot`]s stacked vertically in one figure, e.g. force above acceleration.
#[derive(Clone, Debug)]
pub struct MultiPanel {
    /// Figure title above all panels (may be empty).
    pub title: String,
    pub panels: Vec<LinePlot>,
    /// Figure size in pixels; `None` gives 1000 px wide and 320 px per panel.
    pub size: Option<(u32, u32)>,
}

impl MultiPanel {
    pub fn new(title: impl Into<String>, panels: Vec<LinePlot>) -> Self {
        MultiPanel { title: title.into(), panels, size: None }
    }

    /// Writes the figure to `path` (`.png` or `.svg`).
    pub fn render(&self, path: impl AsRef<Path>) -> Result<()> {
        render_figure(self, path.as_ref())
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
    pub size: (u32, u32),
}

impl BarChart {
    pub fn new(title: impl Into<String>, x_label: impl Into<String>, y_label: impl Into<String>) -> Self {
        BarChart {
            title: title.into(),
            x_label: x_label.into(),
            y_label: y_label.into(),
            categories: Vec::new(),
            groups: Vec::new(),
            size: (1000, 600),
        }
    }

    /// Writes the figure to `path` (`.png` or `.svg`).
    pub fn render(&self, path: impl AsRef<Path>) -> Result<()> {
        render_figure(self, path.as_ref())
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
    pub size: (u32, u32),
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
            size: (1000, 700),
        }
    }

    /// Writes the figure to `path` (`.png` or `.svg`).
    pub fn render(&self, path: impl AsRef<Path>) -> Result<()> {
        render_figure(self, path.as_ref())
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
    fn validate(&self, file: &str) -> Result<()>;
    fn draw<DB: DrawingBackend>(&self, root: &DrawingArea<DB, Shift>) -> DrawResult;
}

fn render_figure<F: Drawable>(fig: &F, path: &Path) -> Result<()> {
    let file = path.display().to_string();
    let ext = path.extension().map(|e| e.to_string_lossy().to_ascii_lowercase()).unwrap_or_default();
    if ext != "png" && ext != "svg" {
        return Err(Error::input(file, "extension", "figures are written as .png or .svg"));
    }
    let size = fig.size();
    if !(16..=20_000).contains(&size.0) || !(16..=20_000).contains(&size.1) {
        return Err(Error::input(file, "size", format!("{size:?} px is outside 16..=20000 px")));
    }
    fig.validate(&file)?;
    ensure_font()?;
    write_atomic(path, |tmp| {
        let drawn = if ext == "png" {
            draw_on(BitMapBackend::new(tmp, size).into_drawing_area(), fig)
        } else {
            draw_on(SVGBackend::new(tmp, size).into_drawing_area(), fig)
        };
        drawn.map_err(|m| Error::io(path, std::io::Error::other(format!("drawing figure: {m}"))))
    })
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
    let style = font(TITLE_PX).pos(Pos::new(HPos::Center, VPos::Center));
    top.draw(&Text::new(title.to_string(), (w as i32 / 2, h as i32 / 2 + 2), style)).map_err(de)?;
    Ok(rest)
}

// ---------------------------------------------------------------------------------------
// Validation and ranges
// ---------------------------------------------------------------------------------------

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

/// Axis range fitted to `values`: widened when all values are equal (a constant signal
/// must still get a usable axis), padded by `pad` (fraction of the span, in log decades
/// for log axes), and optionally forced to include zero (bars, stems).
fn fit_range(values: impl Iterator<Item = f64>, log: bool, pad: f64, include_zero: bool) -> (f64, f64) {
    let (mut lo, mut hi) = values.fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), v| (a.min(v), b.max(v)));
    if lo > hi {
        return if log { (1.0, 10.0) } else { (0.0, 1.0) };
    }
    if include_zero && !log {
        lo = lo.min(0.0);
        hi = hi.max(0.0);
    }
    if log {
        let (l, h) = (lo.log10(), hi.log10());
        let (l, h) = if h - l < 1e-12 { (l - 0.5, h + 0.5) } else { (l - pad * (h - l), h + pad * (h - l)) };
        return (10f64.powf(l), 10f64.powf(h));
    }
    if hi - lo <= 1e-12 * lo.abs().max(hi.abs()) {
        let d = if lo == 0.0 { 1.0 } else { 0.1 * lo.abs() };
        return (lo - d, hi + d);
    }
    let p = pad * (hi - lo);
    // Do not pad a bound that sits exactly on zero below the data (bars start at zero).
    let lo2 = if include_zero && lo == 0.0 { 0.0 } else { lo - p };
    let hi2 = if include_zero && hi == 0.0 { 0.0 } else { hi + p };
    (lo2, hi2)
}

// ---------------------------------------------------------------------------------------
// Tick labels
// ---------------------------------------------------------------------------------------

/// Shortest fixed-point text of `v` with at least `min_dec` decimals that is within `res`
/// of it.
fn fmt_fixed(v: f64, res: f64, min_dec: usize) -> String {
    for d in min_dec.min(12)..=12 {
        let s = format!("{v:.d$}");
        if s.parse::<f64>().is_ok_and(|p| (p - v).abs() <= res) {
            return if s.trim_start_matches('-').chars().all(|c| c == '0' || c == '.') { "0".into() } else { s };
        }
    }
    format!("{v:.12}")
}

/// Tick text: plain decimals for ordinary magnitudes, `1.5e-6` style otherwise. `res` is
/// the smallest difference worth showing (a millionth of the axis span); `min_dec` gives
/// all ticks of an axis the same number of decimals (`0.5`, `1.0`, `1.5`).
fn fmt_tick(v: f64, res: f64, sci: bool, min_dec: usize) -> String {
    if v.abs() <= res {
        return "0".into();
    }
    if sci {
        let e = v.abs().log10().floor();
        let scale = 10f64.powf(e);
        let m = fmt_fixed(v / scale, (res / scale).max(1e-12), 0);
        // Rounding can give a mantissa of 10 (9.9999 → "10"): renormalise.
        return match m.as_str() {
            "10" => format!("1e{}", e as i32 + 1),
            "-10" => format!("-1e{}", e as i32 + 1),
            _ => format!("{m}e{}", e as i32),
        };
    }
    fmt_fixed(v, res, min_dec)
}

fn needs_sci(m: f64) -> bool {
    m != 0.0 && !(1e-3..1e5).contains(&m)
}

/// Tick formatter for a linear axis over `(lo, hi)`.
fn linear_ticks(lo: f64, hi: f64) -> impl Fn(&f64) -> String {
    let res = (hi - lo).abs() * 1e-6;
    let sci = needs_sci(lo.abs().max(hi.abs()));
    let step = nice_step(lo, hi, 8);
    let min_dec = if sci { 0 } else { (-(step.log10() + 1e-9).floor()).max(0.0) as usize };
    move |v| fmt_tick(*v, res, sci, min_dec)
}

/// Multiples of 1, 2 or 5 × 10^k inside `(lo, hi)`, at most `max` of them: the values
/// plotters itself picks for a linear axis.
fn nice_ticks(lo: f64, hi: f64, max: usize) -> Vec<f64> {
    let step = nice_step(lo, hi, max);
    ((lo / step).ceil() as i64..=(hi / step).floor() as i64).map(|k| k as f64 * step).collect()
}

/// The tick spacing plotters chooses for a linear axis with at most `max` labels.
fn nice_step(lo: f64, hi: f64, max: usize) -> f64 {
    let span = hi - lo;
    let mag = 10f64.powf(span.log10().floor());
    [0.1, 0.2, 0.5, 1.0, 2.0, 5.0, 10.0].iter().map(|m| m * mag).find(|s| span / s <= max as f64).unwrap_or(10.0 * mag)
}

/// Tick positions and text for a logarithmic axis.
///
/// Plotters labels only whole decades, which leaves short ranges (common for y axes of
/// transfer functions) with one label or none; here the labelled ticks are decades, or
/// 1-2-5 steps, or 1…9 steps as the range narrows, and the grid shows every 1…9 × 10^k.
struct LogAxis {
    lo: f64,
    hi: f64,
    bold: Vec<f64>,
    light: Vec<f64>,
    sci: bool,
}

impl LogAxis {
    fn new(lo: f64, hi: f64) -> Self {
        let decades = (hi / lo).log10();
        let (k0, k1) = (lo.log10().floor() as i32 - 1, hi.log10().ceil() as i32 + 1);
        let inside = |v: &f64| *v >= lo * (1.0 - 1e-9) && *v <= hi * (1.0 + 1e-9);
        let at = |ms: &[f64], every: i32| -> Vec<f64> {
            (k0..=k1)
                .filter(|k| k.rem_euclid(every) == 0)
                .flat_map(|k| ms.iter().map(move |m| m * 10f64.powi(k)))
                .filter(inside)
                .collect()
        };
        let every = (decades / 8.0).ceil().max(1.0) as i32;
        let mut bold = match decades {
            d if d > 2.5 => at(&[1.0], every),
            d if d > 1.0 => at(&[1.0, 2.0, 5.0], 1),
            _ => at(&[1.0, 2.0, 3.0, 4.0, 5.0, 6.0, 7.0, 8.0, 9.0], 1),
        };
        if bold.len() < 2 {
            bold = nice_ticks(lo, hi, 6);
        }
        let light = at(&[1.0, 2.0, 3.0, 4.0, 5.0, 6.0, 7.0, 8.0, 9.0], 1);
        let sci = bold.iter().any(|v| needs_sci(v.abs()));
        LogAxis { lo, hi, bold, light, sci }
    }

    fn coord(&self) -> WithKeyPoints<LogCoord<f64>> {
        (self.lo..self.hi).log_scale().with_key_points(self.bold.clone()).with_light_points(self.light.clone())
    }

    fn fmt(&self) -> impl Fn(&f64) -> String {
        let sci = self.sci;
        move |v| fmt_tick(*v, v.abs() * 1e-6, sci, 0)
    }

    fn samples(&self) -> Vec<String> {
        let f = self.fmt();
        self.bold.iter().map(f).collect()
    }
}

/// Width in pixels reserved left of a plot for tick labels and the rotated axis text.
fn y_label_width<DB: DrawingBackend>(area: &DrawingArea<DB, Shift>, samples: &[String]) -> u32 {
    let tick = font(TICK_PX);
    let w = samples.iter().filter_map(|s| area.estimate_text_size(s, &tick).ok()).map(|(w, _)| w).max().unwrap_or(30);
    w + DESC_PX + 24
}

/// Tick texts like the ones plotters will draw on an axis, used only to size the label
/// area.
fn tick_samples(lo: f64, hi: f64, log: bool) -> Vec<String> {
    if log {
        return LogAxis::new(lo, hi).samples();
    }
    let f = linear_ticks(lo, hi);
    let v: Vec<String> = nice_ticks(lo, hi, 8).iter().map(f).collect();
    if v.is_empty() {
        vec![linear_ticks(lo, hi)(&lo)]
    } else {
        v
    }
}

// ---------------------------------------------------------------------------------------
// Line plots
// ---------------------------------------------------------------------------------------

impl LinePlot {
    fn check(&self, file: &str, prefix: &str) -> Result<()> {
        check_range(file, &format!("{prefix}x_range"), self.x_range, self.log_x)?;
        check_range(file, &format!("{prefix}y_range"), self.y_range, self.log_y)?;
        for (i, s) in self.series.iter().enumerate() {
            let name = format!("{prefix}series[{i}] `{}`", s.label);
            if s.x.len() != s.y.len() {
                return Err(Error::input(file, name, format!("x has {} values but y has {}", s.x.len(), s.y.len())));
            }
            check_values(file, &format!("{name}.x"), &s.x, self.log_x)?;
            check_values(file, &format!("{name}.y"), &s.y, self.log_y)?;
        }
        Ok(())
    }

    /// Axis ranges actually drawn.
    fn ranges(&self) -> ((f64, f64), (f64, f64)) {
        // Lines may run edge to edge; isolated stems and markers need room at the sides.
        let points = self.series.iter().any(|s| matches!(s.style, SeriesStyle::Stems | SeriesStyle::Markers));
        let x_pad = if points { 0.03 } else { 0.0 };
        let xr = self.x_range.unwrap_or_else(|| {
            fit_range(self.series.iter().flat_map(|s| s.x.iter().copied()), self.log_x, x_pad, false)
        });
        let (xlo, xhi) = xr;
        let stems = self.series.iter().any(|s| s.style == SeriesStyle::Stems);
        let yr = self.y_range.unwrap_or_else(|| {
            // Fit y to the points visible in the x range only.
            let visible = self
                .series
                .iter()
                .flat_map(|s| s.x.iter().zip(&s.y))
                .filter(|(x, _)| **x >= xlo && **x <= xhi)
                .map(|(_, y)| *y);
            fit_range(visible, self.log_y, 0.05, stems)
        });
        (xr, yr)
    }

    /// Width of the left label area this plot needs.
    fn y_area<DB: DrawingBackend>(&self, area: &DrawingArea<DB, Shift>) -> u32 {
        let (_, (ylo, yhi)) = self.ranges();
        y_label_width(area, &tick_samples(ylo, yhi, self.log_y))
    }

    /// Draws into `area`; `y_area` forces the left label width (to align stacked panels).
    fn draw_in<DB: DrawingBackend>(&self, area: &DrawingArea<DB, Shift>, y_area: Option<u32>) -> DrawResult {
        let ((xlo, xhi), (ylo, yhi)) = self.ranges();
        let mut b = ChartBuilder::on(area);
        if !self.title.is_empty() {
            b.caption(&self.title, font(TITLE_PX));
        }
        b.margin(12)
            .margin_right(28)
            .x_label_area_size(TICK_PX + DESC_PX + 30)
            .y_label_area_size(y_area.unwrap_or_else(|| self.y_area(area)));
        let bx = Box2 { x: (xlo, xhi), y: (ylo, yhi), log_x: self.log_x, log_y: self.log_y };
        match (self.log_x, self.log_y) {
            (false, false) => {
                let mut c = b.build_cartesian_2d(xlo..xhi, ylo..yhi).map_err(de)?;
                mesh(&mut c, self, linear_ticks(xlo, xhi), linear_ticks(ylo, yhi))?;
                draw_series(&mut c, self, &bx)
            }
            (true, false) => {
                let ax = LogAxis::new(xlo, xhi);
                let mut c = b.build_cartesian_2d(ax.coord(), ylo..yhi).map_err(de)?;
                mesh(&mut c, self, ax.fmt(), linear_ticks(ylo, yhi))?;
                draw_series(&mut c, self, &bx)
            }
            (false, true) => {
                let ay = LogAxis::new(ylo, yhi);
                let mut c = b.build_cartesian_2d(xlo..xhi, ay.coord()).map_err(de)?;
                mesh(&mut c, self, linear_ticks(xlo, xhi), ay.fmt())?;
                draw_series(&mut c, self, &bx)
            }
            (true, true) => {
                let (ax, ay) = (LogAxis::new(xlo, xhi), LogAxis::new(ylo, yhi));
                let mut c = b.build_cartesian_2d(ax.coord(), ay.coord()).map_err(de)?;
                mesh(&mut c, self, ax.fmt(), ay.fmt())?;
                draw_series(&mut c, self, &bx)
            }
        }
    }
}

fn mesh<DB, X, Y>(
    c: &mut ChartContext<'_, DB, Cartesian2d<X, Y>>,
    p: &LinePlot,
    fx: impl Fn(&f64) -> String,
    fy: impl Fn(&f64) -> String,
) -> DrawResult
where
    DB: DrawingBackend,
    X: Ranged<ValueType = f64> + ValueFormatter<f64>,
    Y: Ranged<ValueType = f64> + ValueFormatter<f64>,
{
    c.configure_mesh()
        .x_desc(&p.x_label)
        .y_desc(&p.y_label)
        .x_label_formatter(&fx)
        .y_label_formatter(&fy)
        .x_labels(8)
        .y_labels(8)
        .label_style(font(TICK_PX))
        .axis_desc_style(font(DESC_PX))
        .bold_line_style(BLACK.mix(0.15))
        .light_line_style(BLACK.mix(0.05))
        .draw()
        .map_err(de)
}

/// The visible data box, in data units, and how each axis is scaled.
struct Box2 {
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

/// The corner of the plot area whose legend box would cover the fewest data points
/// (upper right on a tie, then upper left, lower right, lower left). The box's size is
/// estimated from the labels (`area_px`: the plot area in pixels).
fn legend_corner(p: &LinePlot, bx: &Box2, area_px: (u32, u32)) -> SeriesLabelPosition {
    let labels: Vec<&str> = p.series.iter().map(|s| s.label.as_str()).filter(|l| !l.is_empty()).collect();
    let ((x0, y0), (x1, y1)) = bx.lin_bounds();
    let (sx, sy) = (x1 - x0, y1 - y0);
    // Points as fractions of the plot area (0..1 across, 0..1 up).
    let points = p.series.iter().flat_map(|s| s.x.iter().zip(&s.y)).map(|(&x, &y)| {
        let q = bx.fwd((x, y));
        ((q.0 - x0) / sx, (q.1 - y0) / sy)
    });
    emptiest_corner(points, &labels, area_px)
}

/// The legend corner for points given as fractions of the plot area (see `legend_corner`).
fn emptiest_corner(
    points: impl Iterator<Item = (f64, f64)>,
    labels: &[&str],
    area_px: (u32, u32),
) -> SeriesLabelPosition {
    let chars = labels.iter().map(|l| l.chars().count()).max().unwrap_or(0);
    // Sample line, gap, text at ≈ 0.55 em a character, padding; a row per label.
    let (w_px, h_px) = (40.0 + 0.55 * TICK_PX as f64 * chars as f64 + 20.0, 10.0 + labels.len() as f64 * 20.0);
    let (fx, fy) = ((w_px / area_px.0.max(1) as f64).min(1.0), (h_px / area_px.1.max(1) as f64).min(1.0));
    let corners = [
        (SeriesLabelPosition::UpperRight, true, true),
        (SeriesLabelPosition::UpperLeft, false, true),
        (SeriesLabelPosition::LowerRight, true, false),
        (SeriesLabelPosition::LowerLeft, false, false),
    ];
    let mut counts = [0usize; 4];
    for (u, v) in points {
        if !(u.is_finite() && v.is_finite() && (0.0..=1.0).contains(&u) && (0.0..=1.0).contains(&v)) {
            continue;
        }
        for (k, &(_, right, upper)) in corners.iter().enumerate() {
            let in_x = if right { u >= 1.0 - fx } else { u <= fx };
            let in_y = if upper { v >= 1.0 - fy } else { v <= fy };
            counts[k] += usize::from(in_x && in_y);
        }
    }
    let best = (0..4).min_by_key(|&k| (counts[k], k)).unwrap_or(0);
    corners[best].0.clone()
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

fn draw_series<'a, DB, X, Y>(c: &mut ChartContext<'a, DB, Cartesian2d<X, Y>>, p: &LinePlot, bx: &Box2) -> DrawResult
where
    DB: DrawingBackend + 'a,
    X: Ranged<ValueType = f64> + ValueFormatter<f64>,
    Y: Ranged<ValueType = f64> + ValueFormatter<f64>,
{
    let columns = c.plotting_area().dim_in_pixel().0.max(1) as usize;
    // Stems start at zero, or at the bottom of a log axis, clamped into the box.
    let base = if bx.log_y { bx.y.0 } else { 0.0f64.clamp(bx.y.0, bx.y.1) };
    if p.series.iter().any(|s| s.style == SeriesStyle::Stems) && !bx.log_y && base == 0.0 {
        let axis = PathElement::new(vec![(bx.x.0, 0.0), (bx.x.1, 0.0)], BLACK.stroke_width(1));
        c.draw_series(std::iter::once(axis)).map_err(de)?;
    }
    for (i, s) in p.series.iter().enumerate() {
        let color = palette_color(i);
        let line = matches!(s.style, SeriesStyle::Line | SeriesStyle::LineMarkers | SeriesStyle::Stems);
        let marker = s.style != SeriesStyle::Line;
        let anno = match s.style {
            SeriesStyle::Line | SeriesStyle::LineMarkers => {
                // A decimated piece is a per-column envelope whose strokes reverse within a
                // pixel column; the bitmap backend's joins of a thick polyline at such turns
                // spike far outside the plot area, so it is drawn as runs that are monotone
                // in y, joined only where they do not turn back.
                let mut paths = Vec::new();
                for pc in clip_polyline(&s.x, &s.y, bx) {
                    if pc.len() > 4 * columns {
                        paths.extend(monotone_runs(&decimate(pc, columns, bx)));
                    } else {
                        paths.push(pc);
                    }
                }
                c.draw_series(paths.into_iter().map(|pc| PathElement::new(pc, color.stroke_width(LINE_W))))
                    .map_err(de)?
            }
            SeriesStyle::Markers => c.draw_series(std::iter::empty::<PathElement<(f64, f64)>>()).map_err(de)?,
            SeriesStyle::Stems => {
                let stems = s.x.iter().zip(&s.y).filter(|(x, _)| **x >= bx.x.0 && **x <= bx.x.1).map(|(&x, &y)| {
                    PathElement::new(vec![(x, base), (x, y.clamp(bx.y.0, bx.y.1))], color.stroke_width(LINE_W))
                });
                c.draw_series(stems).map_err(de)?
            }
        };
        if !s.label.is_empty() {
            let line_style = if line { color.stroke_width(LINE_W) } else { color.mix(0.0).stroke_width(1) };
            let r = if marker { MARKER_R } else { 0 };
            anno.label(s.label.clone()).legend(move |(x, y)| {
                EmptyElement::at((x, y))
                    + PathElement::new(vec![(0, 0), (20, 0)], line_style)
                    + Circle::new((10, 0), r, color.filled())
            });
        }
        if marker {
            let dots = s.x.iter().zip(&s.y).map(|(&x, &y)| (x, y)).filter(|&q| bx.contains(q));
            c.draw_series(dots.map(|q| Circle::new(q, MARKER_R, color.filled()))).map_err(de)?;
        }
    }
    if p.series.iter().any(|s| !s.label.is_empty()) {
        let (w, h) = c.plotting_area().dim_in_pixel();
        c.configure_series_labels()
            .position(legend_corner(p, bx, (w, h)))
            .label_font(font(TICK_PX))
            .background_style(WHITE.mix(0.85))
            .border_style(BLACK.mix(0.5))
            .draw()
            .map_err(de)?;
    }
    Ok(())
}

impl Drawable for LinePlot {
    fn size(&self) -> (u32, u32) {
        self.size
    }
    fn validate(&self, file: &str) -> Result<()> {
        self.check(file, "")
    }
    fn draw<DB: DrawingBackend>(&self, root: &DrawingArea<DB, Shift>) -> DrawResult {
        self.draw_in(root, None)
    }
}

impl Drawable for MultiPanel {
    fn size(&self) -> (u32, u32) {
        let title = if self.title.is_empty() { 0 } else { TITLE_PX + 20 };
        self.size.unwrap_or((1000, 320 * self.panels.len().max(1) as u32 + title))
    }
    fn validate(&self, file: &str) -> Result<()> {
        if self.panels.is_empty() {
            return Err(Error::input(file, "panels", "a multi-panel figure needs at least one panel"));
        }
        self.panels.iter().enumerate().try_for_each(|(i, p)| p.check(file, &format!("panels[{i}].")))
    }
    fn draw<DB: DrawingBackend>(&self, root: &DrawingArea<DB, Shift>) -> DrawResult {
        let body = titled(root, &self.title)?;
        // One label width for all panels, so the plot areas line up vertically.
        let y_area = self.panels.iter().map(|p| p.y_area(&body)).max();
        for (area, panel) in body.split_evenly((self.panels.len(), 1)).iter().zip(&self.panels) {
            panel.draw_in(area, y_area)?;
        }
        Ok(())
    }
}

// ---------------------------------------------------------------------------------------
// Bar charts
// ---------------------------------------------------------------------------------------

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
        let (ylo, yhi) = fit_range(self.groups.iter().flat_map(|(_, v)| v.iter().copied()), false, 0.06, true);
        let (xlo, xhi) = (-0.5, n as f64 - 0.5);
        let cats = &self.categories;
        let mut b = ChartBuilder::on(root);
        if !self.title.is_empty() {
            b.caption(&self.title, font(TITLE_PX));
        }
        b.margin(12)
            .margin_right(28)
            .x_label_area_size(TICK_PX + DESC_PX + 30)
            .y_label_area_size(y_label_width(root, &tick_samples(ylo, yhi, false)));
        // With at most `n` ticks over a span of `n`, plotters puts them on the integers,
        // i.e. on the category centres; the formatter names them (and blanks anything else).
        let mut c = b.build_cartesian_2d(xlo..xhi, ylo..yhi).map_err(de)?;
        let fy = linear_ticks(ylo, yhi);
        let fx = |v: &f64| {
            let i = v.round();
            if (v - i).abs() < 1e-6 && i >= 0.0 && (i as usize) < n {
                cats[i as usize].clone()
            } else {
                String::new()
            }
        };
        c.configure_mesh()
            .disable_x_mesh()
            .x_desc(&self.x_label)
            .y_desc(&self.y_label)
            .x_label_formatter(&fx)
            .y_label_formatter(&fy)
            .x_labels(n)
            .y_labels(8)
            .label_style(font(TICK_PX))
            .axis_desc_style(font(DESC_PX))
            .bold_line_style(BLACK.mix(0.15))
            .light_line_style(BLACK.mix(0.05))
            .draw()
            .map_err(de)?;

        let m = self.groups.len() as f64;
        let w = 0.8 / m;
        for (g, (name, values)) in self.groups.iter().enumerate() {
            let color = palette_color(g);
            let bars = values.iter().enumerate().map(|(i, &v)| {
                let x0 = i as f64 - 0.4 + g as f64 * w;
                Rectangle::new([(x0 + 0.02 * w, 0.0), (x0 + 0.98 * w, v)], color.filled())
            });
            let anno = c.draw_series(bars).map_err(de)?;
            if !name.is_empty() {
                anno.label(name.clone())
                    .legend(move |(x, y)| Rectangle::new([(x, y - 6), (x + 14, y + 6)], color.filled()));
            }
        }
        c.draw_series(std::iter::once(PathElement::new(vec![(xlo, 0.0), (xhi, 0.0)], BLACK.stroke_width(1))))
            .map_err(de)?;
        if self.groups.iter().any(|(n, _)| !n.is_empty()) {
            // The bars as a grid of points, for the legend to avoid them.
            let (sx, sy) = (xhi - xlo, yhi - ylo);
            let mut points = Vec::new();
            for (g, (_, values)) in self.groups.iter().enumerate() {
                for (i, &v) in values.iter().enumerate() {
                    let x0 = i as f64 - 0.4 + g as f64 * w;
                    for a in 0..=4 {
                        for b in 0..=10 {
                            let (x, y) = (x0 + w * a as f64 / 4.0, v * b as f64 / 10.0);
                            points.push(((x - xlo) / sx, (y - ylo) / sy));
                        }
                    }
                }
            }
            let labels: Vec<&str> = self.groups.iter().map(|(n, _)| n.as_str()).filter(|n| !n.is_empty()).collect();
            let corner = emptiest_corner(points.into_iter(), &labels, c.plotting_area().dim_in_pixel());
            c.configure_series_labels()
                .position(corner)
                .label_font(font(TICK_PX))
                .background_style(WHITE.mix(0.85))
                .border_style(BLACK.mix(0.5))
                .draw()
                .map_err(de)?;
        }
        Ok(())
    }
}

// ---------------------------------------------------------------------------------------
// Heat maps
// ---------------------------------------------------------------------------------------

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
    /// Colour-scale range (data units) and the map from `z` to [0, 1].
    fn z_scale(&self) -> ((f64, f64), impl Fn(f64) -> f64) {
        let (lo, hi) = fit_range(self.z.iter().copied(), self.log_z, 0.0, false);
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
        // Colour bar strip: 40 px of gradient plus its labels on the right.
        let bar_labels = y_label_width(root, &tick_samples(zlo, zhi, self.log_z));
        let bar_w = bar_labels + 56;
        let (w, _) = body.dim_in_pixel();
        let (main, bar) = body.split_horizontally(w.saturating_sub(bar_w));
        let (xe, ye) = (edges(&self.x), edges(&self.y));
        let (xlo, xhi, ylo, yhi) = (xe[0], xe[xe.len() - 1], ye[0], ye[ye.len() - 1]);
        let x_area = TICK_PX + DESC_PX + 30;

        let mut c = ChartBuilder::on(&main)
            .margin(12)
            .x_label_area_size(x_area)
            .y_label_area_size(y_label_width(root, &tick_samples(ylo, yhi, false)))
            .build_cartesian_2d(xlo..xhi, ylo..yhi)
            .map_err(de)?;
        let (fx, fy) = (linear_ticks(xlo, xhi), linear_ticks(ylo, yhi));
        c.configure_mesh()
            .disable_mesh()
            .x_desc(&self.x_label)
            .y_desc(&self.y_label)
            .x_label_formatter(&fx)
            .y_label_formatter(&fy)
            .label_style(font(TICK_PX))
            .axis_desc_style(font(DESC_PX))
            .draw()
            .map_err(de)?;
        let nx = self.x.len();
        let cells = self.z.iter().enumerate().map(|(k, &z)| {
            let (i, j) = (k % nx, k / nx);
            Rectangle::new([(xe[i], ye[j]), (xe[i + 1], ye[j + 1])], viridis(unit(z)).filled())
        });
        c.draw_series(cells).map_err(de)?;

        let mut cb = ChartBuilder::on(&bar);
        cb.margin(12).margin_left(4).x_label_area_size(x_area).y_label_area_size(0).right_y_label_area_size(bar_labels);
        if self.log_z {
            let az = LogAxis::new(zlo, zhi);
            let c = cb.build_cartesian_2d(0f64..1f64, az.coord()).map_err(de)?;
            colour_bar(c, &self.z_label, &unit, az.fmt(), |t| zlo * (zhi / zlo).powf(t))
        } else {
            let c = cb.build_cartesian_2d(0f64..1f64, zlo..zhi).map_err(de)?;
            colour_bar(c, &self.z_label, &unit, linear_ticks(zlo, zhi), |t| zlo + t * (zhi - zlo))
        }
    }
}

/// Draws the colour gradient as 256 slices, with ticks and the label on the right (the
/// chart has only a right-hand label area, so the mesh puts its labels there).
fn colour_bar<DB, Y>(
    mut c: ChartContext<'_, DB, Cartesian2d<RangedCoordf64, Y>>,
    label: &str,
    unit: &dyn Fn(f64) -> f64,
    fy: impl Fn(&f64) -> String,
    at: impl Fn(f64) -> f64,
) -> DrawResult
where
    DB: DrawingBackend,
    Y: Ranged<ValueType = f64> + ValueFormatter<f64>,
{
    let slices = (0..256).map(|k| {
        let (a, b) = (at(k as f64 / 256.0), at((k + 1) as f64 / 256.0));
        Rectangle::new([(0.0, a), (1.0, b)], viridis(unit(0.5 * (a + b))).filled())
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
        let mut buf = vec![255u8; (w * h * 3) as usize];
        ensure_font().unwrap();
        {
            let area = BitMapBackend::with_buffer(&mut buf, (w, h)).into_drawing_area();
            p.draw_in(&area, None).unwrap();
            area.present().unwrap();
        }
        let blue = palette_color(0);
        let is_blue = |x: u32, y: u32| {
            let i = ((y * w + x) * 3) as usize;
            (buf[i], buf[i + 1], buf[i + 2]) == (blue.0, blue.1, blue.2)
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
    fn polylines_split_where_they_turn_back() {
        let p = [(0.0, 0.0), (1.0, 2.0), (2.0, 2.0), (3.0, 5.0), (4.0, 1.0), (5.0, 0.0), (6.0, 3.0)];
        let runs = monotone_runs(&p);
        assert_eq!(runs, vec![p[..4].to_vec(), p[3..6].to_vec(), p[5..].to_vec()]);
        assert_eq!(monotone_runs(&p[..1]), vec![p[..1].to_vec()]);
    }

    #[test]
    fn the_legend_goes_where_the_data_is_not() {
        let corner = |x: Vec<f64>, y: Vec<f64>| {
            let mut p = LinePlot::new("", "x", "y");
            p.series.push(Series::line("a series", x, y));
            let ((x0, x1), (y0, y1)) = p.ranges();
            let bx = Box2 { x: (x0, x1), y: (y0, y1), log_x: false, log_y: false };
            legend_corner(&p, &bx, (900, 500))
        };
        let x: Vec<f64> = (0..=100).map(f64::from).collect();
        let pos = |p: SeriesLabelPosition| format!("{p:?}");
        // Flat along the bottom: the usual upper right is free.
        assert_eq!(pos(corner(x.clone(), x.iter().map(|_| 0.0).collect())), pos(SeriesLabelPosition::UpperRight));
        // A rising diagonal fills the upper right and the lower left.
        assert_eq!(pos(corner(x.clone(), x.clone())), pos(SeriesLabelPosition::UpperLeft));
        // A falling one fills the upper left and the lower right.
        assert_eq!(pos(corner(x.clone(), x.iter().map(|v| 100.0 - v).collect())), pos(SeriesLabelPosition::UpperRight));
        // Up at both ends (a cosine over one period): lower corners are free.
        let c: Vec<f64> = x.iter().map(|v| (v / 100.0 * 2.0 * std::f64::consts::PI).cos()).collect();
        assert_eq!(pos(corner(x.clone(), c)), pos(SeriesLabelPosition::LowerRight));
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
        assert!(p.render(d.path().join("bad.pdf")).unwrap_err().to_string().contains(".png or .svg"));
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

    #[test]
    fn tick_text() {
        let f = linear_ticks(0.0, 1.0);
        assert_eq!((f(&0.0), f(&0.5), f(&1.0), f(&0.2)), ("0".into(), "0.5".into(), "1.0".into(), "0.2".into()));
        let f = linear_ticks(-2e-9, 3e-9);
        assert_eq!((f(&1e-9), f(&-1.5e-9), f(&0.0)), ("1e-9".into(), "-1.5e-9".into(), "0".into()));
        let f = linear_ticks(0.0, 2e6);
        assert_eq!(f(&1.5e6), "1.5e6");
        let ax = LogAxis::new(20.0, 1500.0);
        assert_eq!(ax.samples(), vec!["20", "50", "100", "200", "500", "1000"]);
        let ay = LogAxis::new(2e-6, 3e-2);
        assert_eq!(ay.samples(), vec!["1e-5", "1e-4", "1e-3", "1e-2"]);
        assert!(ay.light.contains(&3e-6) && ay.light.len() > 30);
        assert_eq!(LogAxis::new(2.0, 7.0).samples(), vec!["2", "3", "4", "5", "6", "7"]);
        assert_eq!(LogAxis::new(1.01, 1.05).samples().len(), 5);
        assert!((5..=9).contains(&LogAxis::new(1.0, 1e40).bold.len()));
        assert_eq!(fmt_tick(9.99999999e-5, 1e-9, true, 0), "1e-4");
        let f = linear_ticks(-0.0014, 0.0007);
        assert_eq!((f(&-0.001), f(&0.0005), f(&0.0)), ("-0.0010".into(), "0.0005".into(), "0".into()));
    }

    #[test]
    fn ranges_and_clipping() {
        assert_eq!(fit_range([2.0, 2.0].into_iter(), false, 0.05, false), (1.8, 2.2));
        assert_eq!(fit_range([0.0].into_iter(), false, 0.05, false), (-1.0, 1.0));
        assert_eq!(fit_range(std::iter::empty(), true, 0.05, false), (1.0, 10.0));
        assert_eq!(fit_range([1.0, 3.0].into_iter(), false, 0.0, true), (0.0, 3.0));
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
}
