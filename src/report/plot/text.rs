//! Text in figures: subscripts, SI prefixes and engineering notation.
//!
//! Labels may carry subscripts as `F_{T}`: Unicode has subscript forms for digits and a
//! few lower-case letters only (none for the capitals of F_T, F_E, x_E), so a subscript is
//! drawn as a smaller run below the baseline. A plain underscore (`left_leg`, a user's
//! name) stays as it is.

use plotters::coord::Shift;
use plotters::prelude::*;
use plotters::style::text_anchor::{HPos, Pos, VPos};
use plotters::style::FontTransform;

use super::{de, font, DrawResult};

/// Subscript size and drop below the baseline, as fractions of the font size.
const SUB_SIZE: f64 = 0.72;
const SUB_DROP: f64 = 0.38;

/// A label split into runs of normal text (`false`) and subscripts (`true`).
pub fn runs(s: &str) -> Vec<(String, bool)> {
    let mut out: Vec<(String, bool)> = Vec::new();
    let mut rest = s;
    while let Some(i) = rest.find("_{") {
        match rest[i + 2..].find('}') {
            Some(j) => {
                if i > 0 {
                    out.push((rest[..i].to_string(), false));
                }
                out.push((rest[i + 2..i + 2 + j].to_string(), true));
                rest = &rest[i + 3 + j..];
            }
            None => break,
        }
    }
    if !rest.is_empty() || out.is_empty() {
        out.push((rest.to_string(), false));
    }
    out
}

/// The label with its subscript markup removed (`F_{T}` → `F_T`), for places that draw
/// plain text.
pub fn plain(s: &str) -> String {
    runs(s).into_iter().map(|(t, sub)| if sub { format!("_{t}") } else { t }).collect()
}

fn sub_px(px: u32) -> u32 {
    ((px as f64 * SUB_SIZE).round() as u32).max(1)
}

/// Width of one run; a subscript gets a little room after it, since its glyphs sit low
/// and close to what follows.
fn run_width<DB: DrawingBackend>(area: &DrawingArea<DB, Shift>, t: &str, sub: bool, px: u32) -> i32 {
    let size = if sub { sub_px(px) } else { px };
    let w = area.estimate_text_size(t, &font(size)).map_or(0, |(w, _)| w as i32);
    if sub {
        w + (px as i32 + 7) / 8
    } else {
        w
    }
}

/// Width in pixels of a label drawn at `px`.
pub fn width<DB: DrawingBackend>(area: &DrawingArea<DB, Shift>, s: &str, px: u32) -> u32 {
    runs(s).iter().map(|(t, sub)| run_width(area, t, *sub, px) as u32).sum()
}

/// Draws a label with its subscripts, `h` aligned on `at` horizontally (along the text)
/// and centred on it across the text; `upward` turns it to read bottom to top (a y-axis
/// label).
pub fn draw<DB: DrawingBackend>(
    area: &DrawingArea<DB, Shift>,
    s: &str,
    at: (i32, i32),
    px: u32,
    h: HPos,
    upward: bool,
) -> DrawResult {
    let total = width(area, s, px) as i32;
    let mut u = match h {
        HPos::Left => 0,
        HPos::Center => -total / 2,
        HPos::Right => -total,
    };
    // Every run is placed by the top of its layout box, which both backends put at the same
    // height relative to the baseline within a pixel or two; the box is px/1.24 high.
    let top = -(px as f64 / 2.48).round() as i32;
    for (t, sub) in runs(s) {
        let size = if sub { sub_px(px) } else { px };
        let v = if sub { top + (SUB_DROP * px as f64).round() as i32 } else { top };
        let mut style = font(size).pos(Pos::new(HPos::Left, VPos::Top));
        let pos = if upward {
            style = style.transform(FontTransform::Rotate270);
            (at.0 + v, at.1 - u)
        } else {
            (at.0 + u, at.1 + v)
        };
        area.draw_text(&t, &style, pos).map_err(de)?;
        u += run_width(area, &t, sub, px);
    }
    Ok(())
}

/// SI prefixes from femto to giga, by power of ten.
const PREFIXES: [(i32, &str); 9] =
    [(-15, "f"), (-12, "p"), (-9, "n"), (-6, "µ"), (-3, "m"), (0, ""), (3, "k"), (6, "M"), (9, "G")];

/// Units a prefix may go in front of (as the first factor of a compound unit: `m/s²`
/// becomes `mm/s²`, which is right because the factor has exponent one).
const PREFIXABLE: [&str; 7] = ["W", "N", "J", "m", "V", "Pa", "s"];

/// A label ending in `(unit)`, split as (text before the parenthesis, unit), when an SI
/// prefix can go in front of the unit.
pub fn prefixable(label: &str) -> Option<(&str, &str)> {
    let body = label.strip_suffix(')')?;
    // The parenthesis that opens the final group, allowing nested ones inside it.
    let mut depth = 0;
    let mut open = None;
    for (i, c) in body.char_indices().rev() {
        match c {
            ')' => depth += 1,
            '(' if depth == 0 => {
                open = Some(i);
                break;
            }
            '(' => depth -= 1,
            _ => {}
        }
    }
    let open = open?;
    let unit = &body[open + 1..];
    let factor_end = unit.find(['/', '·', ' ', '*']).unwrap_or(unit.len());
    PREFIXABLE.contains(&&unit[..factor_end]).then(|| (label[..open].trim_end(), unit))
}

/// The power of ten (a multiple of 3, femto to giga) that brings `m` into [1, 1000).
pub fn exponent3(m: f64) -> i32 {
    if !(m.is_finite() && m > 0.0) {
        return 0;
    }
    // A little tolerance so that 999.9999999 (round-off of 1000) goes up a prefix.
    let e = ((m * (1.0 + 1e-9)).log10() / 3.0).floor() as i32 * 3;
    e.clamp(-15, 9)
}

fn prefix(e: i32) -> &'static str {
    PREFIXES.iter().find(|(p, _)| *p == e).map_or("", |(_, s)| s)
}

/// `label` with its unit prefixed for values scaled by 10^−e (`power (W)`, −6 →
/// `power (µW)`); unchanged when e is 0 or the unit takes no prefix.
pub fn with_prefix(label: &str, e: i32) -> String {
    match prefixable(label) {
        Some((text, unit)) if e != 0 => format!("{text} ({}{unit})", prefix(e)),
        _ => label.to_string(),
    }
}

/// `v` with `digits` significant digits, trailing zeros removed.
pub fn significant(v: f64, digits: usize) -> String {
    if v == 0.0 {
        return "0".into();
    }
    let decimals = (digits as i32 - 1 - v.abs().log10().floor() as i32).max(0) as usize;
    let s = format!("{v:.decimals$}");
    if s.contains('.') {
        s.trim_end_matches('0').trim_end_matches('.').to_string()
    } else {
        s
    }
}

/// A value with an SI prefix on its unit: `2.03e-8`, `W` → `20.3 nW`.
pub fn si(v: f64, unit: &str, digits: usize) -> String {
    if !v.is_finite() {
        return format!("{v} {unit}");
    }
    let e = exponent3(v.abs());
    let m = v / 10f64.powi(e);
    // Beyond the prefixes (below 1 f, from 1000 G on): engineering notation.
    if v != 0.0 && !(1.0..1000.0).contains(&(m.abs() * (1.0 + 1e-9))) {
        return format!("{} {unit}", eng(v, digits));
    }
    // Rounding can reach the next prefix (999.96 → "1000").
    let text = significant(m, digits);
    if text.trim_start_matches('-').starts_with("1000") && e < 9 {
        return si(v.signum() * 10f64.powi(e + 3), unit, digits);
    }
    format!("{text} {}{unit}", prefix(e)).trim_end().to_string()
}

/// A value with its unit as a legend or a note names it, four significant digits:
/// SI-prefixed where the unit takes a prefix (`26.43 mW`, `93.17 mm`), degrees as `°`,
/// a plain number for a ratio (unit `1`, or `?` where none is known).
pub fn quantity(v: f64, unit: &str) -> String {
    match unit {
        "1" | "" | "?" => significant(v, 4),
        "deg" | "°" => format!("{}°", significant(v, 4)),
        u if prefixable(&format!("({u})")).is_some() => si(v, u, 4),
        u => format!("{} {u}", significant(v, 4)),
    }
}

/// Engineering notation: a mantissa in [1, 1000) and an exponent that is a multiple of 3
/// (`2.5e-7` → `250e-9`), or plain decimals when the exponent is 0.
pub fn eng(v: f64, digits: usize) -> String {
    if v == 0.0 || !v.is_finite() {
        return format!("{v}");
    }
    let e = ((v.abs() * (1.0 + 1e-9)).log10() / 3.0).floor() as i32 * 3;
    let text = significant(v / 10f64.powi(e), digits);
    if text.trim_start_matches('-').starts_with("1000") {
        return eng(v.signum() * 10f64.powi(e + 3), digits);
    }
    if e == 0 {
        text
    } else {
        format!("{text}e{e}")
    }
}

/// A label's text with subscripts as HTML (`F_{T}` → `F<sub>T</sub>`), every part escaped.
pub fn html(s: &str) -> String {
    runs(s).into_iter().map(|(t, sub)| if sub { format!("<sub>{}</sub>", escape(&t)) } else { escape(&t) }).collect()
}

/// Text escaped for HTML and SVG (element content and quoted attributes).
pub fn escape(s: &str) -> String {
    let mut o = String::with_capacity(s.len());
    for c in s.chars() {
        match c {
            '&' => o.push_str("&amp;"),
            '<' => o.push_str("&lt;"),
            '>' => o.push_str("&gt;"),
            '"' => o.push_str("&quot;"),
            '\'' => o.push_str("&#39;"),
            c => o.push(c),
        }
    }
    o
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn subscripts_are_marked_with_braces_only() {
        assert_eq!(
            runs("F_{T} at x_{E}"),
            vec![("F".into(), false), ("T".into(), true), (" at x".into(), false), ("E".into(), true)]
        );
        assert_eq!(runs("left_leg"), vec![("left_leg".into(), false)]);
        assert_eq!(runs("broken_{"), vec![("broken_{".into(), false)]);
        assert_eq!(runs(""), vec![(String::new(), false)]);
        assert_eq!(plain("G_{Fv} and F_{T}"), "G_Fv and F_T");
        assert_eq!(html("F_{T} <b>"), "F<sub>T</sub> &lt;b&gt;");
    }

    #[test]
    fn units_take_a_prefix_only_where_it_is_right() {
        assert_eq!(prefixable("power (W)"), Some(("power", "W")));
        assert_eq!(prefixable("|Y| (m/(N·s))"), Some(("|Y|", "m/(N·s)")));
        assert_eq!(prefixable("acceleration (m/s²)"), Some(("acceleration", "m/s²")));
        for no in ["time (ms)", "level (dB re 1 N)", "w (1/√kg)", "area (m²)", "γ²", "x (µm)", "f (Hz)"] {
            assert_eq!(prefixable(no), None, "{no}");
        }
        assert_eq!(with_prefix("power (W)", -6), "power (µW)");
        assert_eq!(with_prefix("force (N)", 0), "force (N)");
        assert_eq!(exponent3(2.2e-5), -6);
        assert_eq!(exponent3(999.99999999999), 3);
        assert_eq!(exponent3(150.0), 0);
    }

    #[test]
    fn numbers_read_with_prefixes() {
        assert_eq!(si(2.0267e-8, "W", 3), "20.3 nW");
        assert_eq!(si(6.3143e-6, "W", 3), "6.31 µW");
        assert_eq!(si(-0.0154, "N", 3), "-15.4 mN");
        assert_eq!(si(999.96e-6, "W", 3), "1 mW");
        assert_eq!(si(150.0, "N", 3), "150 N");
        assert_eq!(si(1e-300, "W", 3), "1e-300 W");
        assert_eq!(si(2e13, "N", 3), "20e12 N");
        assert_eq!(si(0.0, "W", 3), "0 W");
        assert_eq!(eng(2.5e-7, 3), "250e-9");
        assert_eq!(eng(1.5e6, 3), "1.5e6");
        assert_eq!(eng(42.0, 3), "42");
        assert_eq!(quantity(0.093167, "m"), "93.17 mm");
        assert_eq!(
            (quantity(179.92, "deg"), quantity(83.0, "Hz"), quantity(4.0, "1")),
            ("179.9°".into(), "83 Hz".into(), "4".into())
        );
    }
}
