//! Axis ranges, tick positions and tick text.
//!
//! Tick text is chosen so a reader never counts zeros, and the unit in the label is the
//! ticks' unit: a y axis whose unit takes an SI prefix shows its values in that prefix
//! (`power (µW)`, ticks 0.5 … 2, on linear, log and symmetric-log axes alike); a log axis
//! whose ticks still span too many decades for decimals labels them as powers of ten
//! (`10⁻⁴`, in the unprefixed unit); any other linear axis whose values need an exponent
//! uses engineering notation (`250e-9`).

use plotters::coord::combinators::{BindKeyPoints, LogCoord, WithKeyPoints};
use plotters::coord::ranged1d::{DefaultFormatting, KeyPointHint, Ranged};
use plotters::coord::types::RangedCoordf64;
use plotters::prelude::*;

use super::text::{exponent3, prefixable, significant, with_prefix};

/// Axis range fitted to `values`: widened when all values are equal (a constant signal
/// must still get a usable axis), padded by `pad` (fraction of the span, in log decades
/// for log axes), and optionally forced to include zero (bars, stems).
pub fn fit_range(values: impl Iterator<Item = f64>, log: bool, pad: f64, include_zero: bool) -> (f64, f64) {
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

/// Tick text: plain decimals for ordinary magnitudes, engineering notation (`250e-9`)
/// otherwise. `res` is the smallest difference worth showing (a millionth of the axis
/// span); `min_dec` gives all ticks of an axis the same number of decimals (`0.5`, `1.0`).
pub fn fmt_tick(v: f64, res: f64, sci: bool, min_dec: usize) -> String {
    if v.abs() <= res {
        return "0".into();
    }
    if sci {
        let e = exponent3(v.abs());
        let scale = 10f64.powi(e);
        let m = fmt_fixed(v / scale, (res / scale).max(1e-12), 0);
        // Rounding can give a mantissa of 1000 (999.9999 → "1000"): renormalise.
        return match m.trim_start_matches('-') {
            "1000" => format!("{}1e{}", if v < 0.0 { "-" } else { "" }, e + 3),
            _ if e == 0 => m,
            _ => format!("{m}e{e}"),
        };
    }
    fmt_fixed(v, res, min_dec)
}

fn needs_sci(m: f64) -> bool {
    m != 0.0 && !(1e-3..1e5).contains(&m)
}

/// Tick formatter for a linear axis over `(lo, hi)`.
pub fn linear_ticks(lo: f64, hi: f64) -> impl Fn(&f64) -> String {
    let res = (hi - lo).abs() * 1e-6;
    let sci = needs_sci(lo.abs().max(hi.abs()));
    let step = nice_step(lo, hi, 8);
    let min_dec = if sci { 0 } else { (-(step.log10() + 1e-9).floor()).max(0.0) as usize };
    move |v| fmt_tick(*v, res, sci, min_dec)
}

/// Multiples of 1, 2 or 5 × 10^k inside `(lo, hi)`, at most `max` of them: the values
/// plotters itself picks for a linear axis.
pub fn nice_ticks(lo: f64, hi: f64, max: usize) -> Vec<f64> {
    let step = nice_step(lo, hi, max);
    ((lo / step).ceil() as i64..=(hi / step).floor() as i64).map(|k| k as f64 * step).collect()
}

/// The tick spacing plotters chooses for a linear axis with at most `max` labels.
fn nice_step(lo: f64, hi: f64, max: usize) -> f64 {
    let span = hi - lo;
    let mag = 10f64.powf(span.log10().floor());
    [0.1, 0.2, 0.5, 1.0, 2.0, 5.0, 10.0].iter().map(|m| m * mag).find(|s| span / s <= max as f64).unwrap_or(10.0 * mag)
}

/// Tick positions for a logarithmic axis.
///
/// Plotters labels only whole decades, which leaves short ranges (common for y axes of
/// transfer functions) with one label or none; here the labelled ticks are decades, or
/// 1-2-5 steps, or 1…9 steps as the range narrows, and the grid shows every 1…9 × 10^k.
pub struct LogTicks {
    pub bold: Vec<f64>,
    pub light: Vec<f64>,
}

impl LogTicks {
    pub fn new(lo: f64, hi: f64) -> Self {
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
            // 1.5 as well: a range ending a little above a power of ten (4 to 16) would
            // otherwise leave the top fifth of the axis unlabelled.
            _ => at(&[1.0, 1.5, 2.0, 3.0, 4.0, 5.0, 6.0, 7.0, 8.0, 9.0], 1),
        };
        if bold.len() < 2 {
            bold = nice_ticks(lo, hi, 6);
        }
        let light = at(&[1.0, 2.0, 3.0, 4.0, 5.0, 6.0, 7.0, 8.0, 9.0], 1);
        LogTicks { bold, light }
    }
}

/// The symmetric-log map y ↦ sign(y)·log₁₀(1 + |y|/c): linear within ±c, logarithmic
/// beyond, and zero at zero, so signed values spanning decades share one axis.
pub fn symlog(y: f64, c: f64) -> f64 {
    y.signum() * (y.abs() / c).ln_1p() / std::f64::consts::LN_10
}

/// The inverse of [`symlog`].
pub fn symlog_inv(u: f64, c: f64) -> f64 {
    u.signum() * c * (u.abs() * std::f64::consts::LN_10).exp_m1()
}

/// How an axis maps values to positions.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Scale {
    Linear,
    Log,
    /// [`symlog`] with this linear threshold; the axis's `lo`/`hi` are mapped values.
    SymLog(f64),
}

/// One axis, ready to draw: range, ticks, their text, and the label that goes with them.
pub struct Axis {
    pub lo: f64,
    pub hi: f64,
    pub scale: Scale,
    /// The label as drawn (a unit prefix added, or the unit moved onto the ticks).
    pub label: String,
    /// Labelled and grid-only tick positions (log and symmetric-log axes).
    bold: Vec<f64>,
    light: Vec<f64>,
    fmt: Box<dyn Fn(f64) -> String>,
}

/// A log axis's tick text: plain decimals (`0.5`, `20`), or where an axis needs exponents
/// (`sci`) a power of ten as it is printed, `10⁻⁴`, `2×10⁻⁴`.
pub fn log_tick(v: f64, sci: bool) -> String {
    if !sci || v == 0.0 || !v.is_finite() {
        return fmt_tick(v, v.abs() * 1e-6, false, 0);
    }
    let k = (v.abs() * (1.0 + 1e-9)).log10().floor() as i32;
    let m = significant(v.abs() / 10f64.powi(k), 3);
    let sign = if v < 0.0 { "-" } else { "" };
    match m.as_str() {
        "1" => format!("{sign}10{}", superscript(k)),
        _ => format!("{sign}{m}×10{}", superscript(k)),
    }
}

/// An integer in superscript digits (`-4` → `⁻⁴`).
fn superscript(k: i32) -> String {
    const DIGITS: [char; 10] = ['⁰', '¹', '²', '³', '⁴', '⁵', '⁶', '⁷', '⁸', '⁹'];
    let digits = k.unsigned_abs().to_string();
    let digits = digits.chars().map(|d| DIGITS[d as usize - '0' as usize]);
    (if k < 0 { Some('⁻') } else { None }).into_iter().chain(digits).collect()
}

impl Axis {
    /// A linear axis over `(lo, hi)`; with `prefix`, an SI prefix on a unit that takes one.
    pub fn linear(lo: f64, hi: f64, label: &str, prefix: bool) -> Self {
        let e = if prefix && prefixable(label).is_some() { exponent3(lo.abs().max(hi.abs())) } else { 0 };
        let s = 10f64.powi(e);
        let f = linear_ticks(lo / s, hi / s);
        Axis {
            lo,
            hi,
            scale: Scale::Linear,
            label: with_prefix(label, e),
            bold: Vec::new(),
            light: Vec::new(),
            fmt: Box::new(move |v| f(&(v / s))),
        }
    }

    /// A logarithmic axis over `(lo, hi)` (both positive); with `prefix`, an SI prefix on a
    /// unit that takes one, chosen by the top of the axis as on a linear axis, so the label's
    /// unit is the ticks' (`power (µW)`, ticks 4 … 10).
    pub fn log(lo: f64, hi: f64, label: &str, prefix: bool) -> Self {
        let t = LogTicks::new(lo, hi);
        let e = if prefix && prefixable(label).is_some() { exponent3(hi) } else { 0 };
        // Ticks that need powers of ten anyway read best in the unit itself.
        let e = if t.bold.iter().any(|v| needs_sci(v.abs() / 10f64.powi(e))) { 0 } else { e };
        let s = 10f64.powi(e);
        let sci = t.bold.iter().any(|v| needs_sci(v.abs() / s));
        let fmt: Box<dyn Fn(f64) -> String> = Box::new(move |v| log_tick(v / s, sci));
        Axis { lo, hi, scale: Scale::Log, label: with_prefix(label, e), bold: t.bold, light: t.light, fmt }
    }

    /// A symmetric-log axis with threshold `c` over mapped values `(lo, hi)`: labelled
    /// ticks at 0 and ±c·10^k (k ≥ 1: ±c itself would crowd zero), every decade or every
    /// other one when there are many, counted down from the largest.
    pub fn symlog(lo: f64, hi: f64, c: f64, label: &str) -> Self {
        let top = lo.abs().max(hi.abs());
        let decades = symlog_inv(top, c) / c;
        let kmax = decades.log10().floor().max(0.0) as i32;
        let every = if kmax > 5 { 2 } else { 1 };
        let inside = |v: &f64| *v >= lo - 1e-9 && *v <= hi + 1e-9;
        let mut bold = vec![0.0];
        let mut light = Vec::new();
        for k in 0..=kmax + 1 {
            for sign in [1.0, -1.0] {
                let d = c * 10f64.powi(k);
                if k >= 1 && (kmax - k) % every == 0 {
                    bold.push(symlog(sign * d, c));
                }
                light.extend((1..10).map(|m| symlog(sign * m as f64 * d, c)));
            }
        }
        bold.retain(inside);
        light.retain(inside);
        bold.sort_by(f64::total_cmp);
        light.sort_by(f64::total_cmp);
        // The unit's prefix by the largest tick, as on a linear axis; the smallest ticks
        // then need powers of ten (`10⁻³`), as on a log axis.
        let e = if prefixable(label).is_some() { exponent3(symlog_inv(top, c)) } else { 0 };
        let sci_in = |e: i32| bold.iter().any(|&u| u != 0.0 && needs_sci(symlog_inv(u, c).abs() / 10f64.powi(e)));
        let e = if sci_in(e) { 0 } else { e };
        let (s, sci) = (10f64.powi(e), sci_in(e));
        let fmt: Box<dyn Fn(f64) -> String> =
            Box::new(move |u| if u == 0.0 { "0".into() } else { log_tick(symlog_inv(u, c) / s, sci) });
        let label = with_prefix(label, e);
        Axis { lo, hi, scale: Scale::SymLog(c), label, bold, light, fmt }
    }

    /// Tick text at a position.
    pub fn text(&self, v: f64) -> String {
        (self.fmt)(v)
    }

    /// The texts of the labelled ticks (to size the label area).
    pub fn samples(&self) -> Vec<String> {
        let at = match self.scale {
            Scale::Linear => {
                let t = nice_ticks(self.lo, self.hi, 8);
                if t.is_empty() {
                    vec![self.lo]
                } else {
                    t
                }
            }
            _ => self.bold.clone(),
        };
        at.into_iter().map(|v| self.text(v)).collect()
    }

    /// Plotters' coordinate for a log axis.
    pub fn log_coord(&self) -> WithKeyPoints<LogCoord<f64>> {
        (self.lo..self.hi).log_scale().with_key_points(self.bold.clone()).with_light_points(self.light.clone())
    }

    /// Plotters' coordinate for a symmetric-log axis (linear in mapped values).
    pub fn symlog_coord(&self) -> Keyed {
        Keyed { inner: (self.lo..self.hi).into(), bold: self.bold.clone(), light: self.light.clone() }
    }
}

/// A linear coordinate with given tick positions. (Plotters' own `WithKeyPoints` over a
/// linear axis loses the value formatting that the mesh needs.)
pub struct Keyed {
    inner: RangedCoordf64,
    bold: Vec<f64>,
    light: Vec<f64>,
}

impl Ranged for Keyed {
    type ValueType = f64;
    type FormatOption = DefaultFormatting;

    fn range(&self) -> std::ops::Range<f64> {
        self.inner.range()
    }

    fn map(&self, value: &f64, limit: (i32, i32)) -> i32 {
        self.inner.map(value, limit)
    }

    fn key_points<Hint: KeyPointHint>(&self, hint: Hint) -> Vec<f64> {
        if hint.weight().allow_light_points() {
            self.light.clone()
        } else {
            self.bold.clone()
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn tick_text() {
        let f = linear_ticks(0.0, 1.0);
        assert_eq!((f(&0.0), f(&0.5), f(&1.0), f(&0.2)), ("0".into(), "0.5".into(), "1.0".into(), "0.2".into()));
        let f = linear_ticks(-2e-9, 3e-9);
        assert_eq!((f(&1e-9), f(&-1.5e-9), f(&0.0)), ("1e-9".into(), "-1.5e-9".into(), "0".into()));
        let f = linear_ticks(0.0, 2e6);
        assert_eq!(f(&1.5e6), "1.5e6");
        let f = linear_ticks(0.0, 3e-7);
        assert_eq!(f(&2.5e-7), "250e-9");
        let ax = Axis::log(20.0, 1500.0, "frequency (Hz)", true);
        assert_eq!(ax.samples(), vec!["20", "50", "100", "200", "500", "1000"]);
        let ay = Axis::log(2e-6, 3e-2, "mobility (m/(N·s))", true);
        assert_eq!(ay.samples(), vec!["0.01", "0.1", "1", "10"]);
        assert_eq!(ay.label, "mobility (mm/(N·s))");
        assert!(ay.light.contains(&3e-6) && ay.light.len() > 30);
        let ap = Axis::log(4e-6, 1.6e-5, "power (W)", true);
        assert_eq!((ap.samples()[0].as_str(), ap.label.as_str()), ("4", "power (µW)"));
        assert_eq!(ap.samples().last().map(String::as_str), Some("15"), "the top fifth labelled");
        // Too many decades for decimals: powers of ten, in the unit itself.
        let aw = Axis::log(3e-12, 2e-3, "power (W)", true);
        assert_eq!((aw.samples()[0].as_str(), aw.label.as_str()), ("10⁻¹⁰", "power (W)"));
        let an = Axis::log(2e-7, 3e-3, "|Y| (1/(N·s))", true);
        assert_eq!(an.samples(), vec!["10⁻⁶", "10⁻⁵", "10⁻⁴", "10⁻³"]);
        assert_eq!(Axis::log(2.0, 7.0, "x", true).samples(), vec!["2", "3", "4", "5", "6", "7"]);
        assert_eq!(Axis::log(1.01, 1.05, "x", true).samples().len(), 5);
        assert!((5..=9).contains(&LogTicks::new(1.0, 1e40).bold.len()));
        assert_eq!(fmt_tick(9.99999999e-5, 1e-9, true, 0), "100e-6");
        assert_eq!(fmt_tick(9.99999999e-7, 1e-12, true, 0), "1e-6");
        let f = linear_ticks(-0.0014, 0.0007);
        assert_eq!((f(&-0.001), f(&0.0005), f(&0.0)), ("-0.0010".into(), "0.0005".into(), "0".into()));
    }

    #[test]
    fn y_axes_take_si_prefixes() {
        let a = Axis::linear(-8e-6, 2.3e-5, "power (W)", true);
        assert_eq!(a.label, "power (µW)");
        assert_eq!((a.text(2e-5), a.text(-5e-6), a.text(0.0)), ("20".into(), "-5".into(), "0".into()));
        let a = Axis::linear(-0.02, 0.02, "force (N)", true);
        assert_eq!((a.label.as_str(), a.text(0.015).as_str()), ("force (mN)", "15"));
        let a = Axis::linear(0.0, 0.5, "x (m)", false);
        assert_eq!((a.label.as_str(), a.text(0.25).as_str()), ("x (m)", "0.25"));
        let a = Axis::linear(-60.0, 40.0, "level (dB re 1 N)", true);
        assert_eq!(a.label, "level (dB re 1 N)");
    }

    #[test]
    fn symmetric_log_keeps_the_sign_and_the_decades() {
        let c = 1e-9;
        for y in [0.0, 1e-10, -3e-9, 2.2e-5, -8e-6] {
            assert!((symlog_inv(symlog(y, c), c) - y).abs() <= 1e-12 * y.abs().max(c), "{y}");
        }
        assert_eq!(symlog(0.0, c), 0.0);
        assert!(symlog(-1e-6, c) < 0.0 && (symlog(1e-5, c) - symlog(1e-6, c) - 1.0).abs() < 1e-3);
        let a = Axis::symlog(symlog(-1e-5, c), symlog(3e-5, c), c, "power (W)");
        assert_eq!(a.label, "power (µW)");
        let s = a.samples();
        assert!(
            s.contains(&"0".to_string()) && s.contains(&"10".to_string()) && s.contains(&"-1".to_string()),
            "{s:?}"
        );
    }

    #[test]
    fn powers_of_ten_read_as_printed() {
        assert_eq!(log_tick(1e-4, true), "10⁻⁴");
        assert_eq!(log_tick(2e-4 * (1.0 - 1e-15), true), "2×10⁻⁴");
        assert_eq!(log_tick(-1e12, true), "-10¹²");
        assert_eq!(log_tick(1.0, true), "10⁰");
        assert_eq!(log_tick(0.05, false), "0.05");
    }

    #[test]
    fn ranges() {
        assert_eq!(fit_range([2.0, 2.0].into_iter(), false, 0.05, false), (1.8, 2.2));
        assert_eq!(fit_range([0.0].into_iter(), false, 0.05, false), (-1.0, 1.0));
        assert_eq!(fit_range(std::iter::empty(), true, 0.05, false), (1.0, 10.0));
        assert_eq!(fit_range([1.0, 3.0].into_iter(), false, 0.0, true), (0.0, 3.0));
    }
}
