//! `[output]`: what a run writes, and `[output.figures]`: how its figures look and which
//! are drawn.

use super::d_true;
use crate::case::ranges::within;
use crate::error::{Error, Result};
use serde::{Deserialize, Serialize};

/// What to write.
#[derive(Clone, Debug, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct OutputSpec {
    /// One HDF5 file per run.
    #[serde(default = "d_true")]
    pub hdf5: bool,
    /// PNG/SVG figures.
    #[serde(default = "d_true")]
    pub plots: bool,
    /// K, M, C in Matrix Market format.
    #[serde(default)]
    pub matrices: bool,
    /// Keep whole time histories in the HDF5 file (else the last periods only).
    #[serde(default)]
    pub full_history: bool,
    /// With `full_history`: keep every this-many-th step of the periods before the last
    /// three (which stay whole, for spectra and powers), so a long start-up fits in memory.
    #[serde(default = "d_one", skip_serializing_if = "is_one")]
    pub history_every: usize,
    /// How the figures look and which are drawn.
    #[serde(default, skip_serializing_if = "FiguresSpec::is_default")]
    pub figures: FiguresSpec,
}

impl OutputSpec {
    /// What a transient keeps of its history: None, the last periods only; Some(k), every
    /// period, those before the last three every k-th step.
    pub fn history(&self) -> Option<usize> {
        self.full_history.then_some(self.history_every)
    }

    /// Checks the history settings and the figures', naming the field.
    pub fn validate(&self, file: &str) -> Result<()> {
        if self.history_every == 0 {
            return Err(Error::input(
                file,
                "output.history_every",
                "0 keeps no step: give 1 (every step) or more (every k-th step of the early periods)",
            ));
        }
        if self.history_every > 1 && !self.full_history {
            return Err(Error::input(
                file,
                "output.history_every",
                "thins the whole history `full_history = true` keeps; without it only the last periods are kept, whole",
            ));
        }
        self.figures.validate(file)
    }
}

impl Default for OutputSpec {
    fn default() -> Self {
        toml::from_str("").expect("defaults")
    }
}

fn d_one() -> usize {
    1
}

fn is_one(n: &usize) -> bool {
    *n == 1
}

/// The figure formats a case may ask for.
pub const FIGURE_FORMATS: [&str; 3] = ["png", "svg", "pdf"];

/// Figure settings of a case. The command line's `--formats` and `--dpi`, where given,
/// take precedence over `formats` and `dpi`.
#[derive(Clone, Debug, Default, Deserialize, Serialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct FiguresSpec {
    /// Width of every figure in pixels at 100 dpi (its height follows its own aspect).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub width: Option<u32>,
    /// The same in inches (100 px to the inch), for a page layout.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub width_in: Option<f64>,
    /// Text and lines this many times their size against the figure (1: as drawn).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub font_scale: Option<f64>,
    /// File formats, from png, svg, pdf; svg always among them (reports hold it).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub formats: Option<Vec<String>>,
    /// Resolution of PNG files (dots per inch).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub dpi: Option<u32>,
    /// Logarithmic axes where the data span decades (false: every axis linear).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub log_axes: Option<bool>,
    /// Only the figures whose names end in one of these (`time`, `spectrum`,
    /// `power_points`, `record_spectra`, …); empty: all.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub only: Vec<String>,
}

/// Admissible widths (px at 100 dpi), font scales and resolutions.
pub const FIGURE_WIDTH_PX: (u32, u32) = (200, 8000);
pub const FONT_SCALE: (f64, f64) = (0.5, 3.0);
pub const FIGURE_DPI: (u32, u32) = (50, 600);

impl FiguresSpec {
    pub fn validate(&self, file: &str) -> Result<()> {
        let f = |name: &str| format!("output.figures.{name}");
        let (lo, hi) = FIGURE_WIDTH_PX;
        if self.width.is_some() && self.width_in.is_some() {
            return Err(Error::input(
                file,
                f("width_in"),
                "give the width once: `width` in px or `width_in` in inches",
            ));
        }
        if let Some(w) = self.width.filter(|w| !(lo..=hi).contains(w)) {
            return Err(Error::input(file, f("width"), format!("{w} px is outside {lo}..={hi} px")));
        }
        if let Some(w) = self.width_in {
            within(file, &f("width_in"), w, (lo as f64 / 100.0, hi as f64 / 100.0), "in")?;
        }
        if let Some(s) = self.font_scale {
            within(file, &f("font_scale"), s, FONT_SCALE, "")?;
        }
        if let Some(d) = self.dpi {
            let (a, b) = FIGURE_DPI;
            if !(a..=b).contains(&d) {
                return Err(Error::input(file, f("dpi"), format!("{d} is outside {a}..={b}")));
            }
        }
        if let Some(formats) = &self.formats {
            if let Some(bad) = formats.iter().find(|n| !FIGURE_FORMATS.contains(&n.as_str())) {
                return Err(Error::input(
                    file,
                    f("formats"),
                    format!("`{bad}` is not a figure format: use png, svg or pdf"),
                ));
            }
            if !formats.iter().any(|n| n == "svg") {
                return Err(Error::input(
                    file,
                    f("formats"),
                    "must include \"svg\": the report holds every figure as SVG",
                ));
            }
        }
        for (i, name) in self.only.iter().enumerate() {
            let ok = !name.is_empty() && name.chars().all(|c| c.is_ascii_lowercase() || c.is_ascii_digit() || c == '_');
            if !ok {
                return Err(Error::input(
                    file,
                    format!("output.figures.only[{i}]"),
                    format!("{name:?} is not a figure name: lower-case letters, digits and `_`, e.g. \"time\" or \"spectrum\""),
                ));
            }
        }
        Ok(())
    }

    /// Whether nothing is set (the case need not write the table).
    pub fn is_default(&self) -> bool {
        *self == FiguresSpec::default()
    }

    /// The width in pixels at 100 dpi, if set.
    pub fn width_px(&self) -> Option<u32> {
        self.width.or(self.width_in.map(|w| (w * 100.0).round() as u32))
    }
}
