//! Text as outlines: every `<text>` element plotters writes becomes a `<path>` of the
//! embedded font's glyphs, placed exactly as the layout measured them. An SVG file then
//! looks the same in every viewer whatever fonts it has (a browser's `sans-serif` is not
//! DejaVu Sans, and subscripts placed by DejaVu's widths drifted apart in it), and the PNG
//! and PDF drawn from that SVG need no font at all. The text stays readable to programs
//! and screen readers as each path's `aria-label`.

use ab_glyph::{Font, FontRef, GlyphId, OutlineCurve, Point, PxScale, ScaleFont};

use super::text::escape;

/// Plotters writes `font-size` as its size in pixels / 1.24 and lays text out with the
/// font scaled so that ascent − descent equals that size in pixels.
const PLOTTERS_EM: f64 = 1.24;

/// `svg` with every `<text …>…</text>` element replaced by the outlines of its glyphs.
pub(super) fn outline_text(svg: &str, font: &FontRef<'_>) -> String {
    let mut out = String::with_capacity(svg.len() * 2);
    let mut rest = svg;
    while let Some(i) = rest.find("<text ") {
        let Some(open_end) = rest[i..].find('>').map(|j| i + j + 1) else { break };
        let Some(close) = rest[open_end..].find("</text>").map(|j| open_end + j) else { break };
        out.push_str(&rest[..i]);
        let content = unescape(rest[open_end..close].trim_matches('\n'));
        out.push_str(&text_path(&rest[i..open_end], &content, font));
        rest = &rest[close + "</text>".len()..];
    }
    out.push_str(rest);
    out
}

/// The value of attribute `name` in a tag.
fn attr<'a>(tag: &'a str, name: &str) -> Option<&'a str> {
    let key = format!(" {name}=\"");
    let i = tag.find(&key)? + key.len();
    let j = tag[i..].find('"')? + i;
    Some(&tag[i..j])
}

fn num(tag: &str, name: &str) -> f64 {
    attr(tag, name).and_then(|v| v.parse().ok()).unwrap_or(0.0)
}

/// One `<text>` tag and its content as a filled path (nothing for blank text).
fn text_path(tag: &str, content: &str, font: &FontRef<'_>) -> String {
    if content.trim().is_empty() {
        return String::new();
    }
    let size = (num(tag, "font-size") * PLOTTERS_EM) as f32;
    let scaled = font.as_scaled(PxScale::from(size.max(0.01)));
    let em = scaled.h_scale_factor() as f64 * font.units_per_em().unwrap_or(2048.0) as f64;
    let (glyphs, width) = layout(&scaled, content);
    let x = num(tag, "x")
        - match attr(tag, "text-anchor") {
            Some("middle") => width / 2.0,
            Some("end") => width,
            _ => 0.0,
        };
    // Baseline below `y`, by the `dy` plotters writes for its vertical anchors.
    let ex =
        font.outline(font.glyph_id('x')).map_or(0.5 * em, |o| o.bounds.max.y as f64 * scaled.v_scale_factor() as f64);
    let y = num(tag, "y")
        + match attr(tag, "dy").unwrap_or("0") {
            "0.76em" => 0.76 * em,
            "0.5ex" => 0.5 * ex,
            "-0.5ex" => -0.5 * ex,
            _ => 0.0,
        };
    let mut d = String::new();
    for (id, pen) in glyphs {
        if let Some(o) = font.outline(id) {
            glyph_path(&mut d, &o.curves, (x + pen, y), scaled.h_scale_factor() as f64);
        }
    }
    let mut extra = String::new();
    for name in ["opacity", "transform"] {
        if let Some(v) = attr(tag, name) {
            extra.push_str(&format!(" {name}=\"{v}\""));
        }
    }
    let fill = attr(tag, "fill").unwrap_or("#000000");
    format!("<path aria-label=\"{}\" fill=\"{fill}\"{extra} d=\"{d}\"/>", escape(content))
}

/// Each glyph of `s` with its offset along the baseline, and the total width, as plotters
/// measures text (advances and kerning).
fn layout<F: Font, S: ScaleFont<F>>(scaled: &S, s: &str) -> (Vec<(GlyphId, f64)>, f64) {
    let mut glyphs = Vec::with_capacity(s.len());
    let mut pen = 0.0;
    let mut prev = None;
    for c in s.chars() {
        let id = scaled.glyph_id(c);
        if let Some(p) = prev {
            pen += scaled.kern(p, id) as f64;
        }
        glyphs.push((id, pen));
        pen += scaled.h_advance(id) as f64;
        prev = Some(id);
    }
    (glyphs, pen)
}

/// Appends a glyph's contours (font units, y up) at `origin` on the baseline, `s` pixels
/// per unit, as path data.
fn glyph_path(d: &mut String, curves: &[OutlineCurve], origin: (f64, f64), s: f64) {
    let at = |p: &Point| (origin.0 + p.x as f64 * s, origin.1 - p.y as f64 * s);
    let mut end: Option<Point> = None;
    for c in curves {
        let (start, last) = match c {
            OutlineCurve::Line(a, b) | OutlineCurve::Quad(a, _, b) | OutlineCurve::Cubic(a, _, _, b) => (*a, *b),
        };
        if end != Some(start) {
            if end.is_some() {
                d.push('Z');
            }
            push(d, 'M', &[at(&start)]);
        }
        match c {
            OutlineCurve::Line(_, b) => push(d, 'L', &[at(b)]),
            OutlineCurve::Quad(_, c1, b) => push(d, 'Q', &[at(c1), at(b)]),
            OutlineCurve::Cubic(_, c1, c2, b) => push(d, 'C', &[at(c1), at(c2), at(b)]),
        }
        end = Some(last);
    }
    if end.is_some() {
        d.push('Z');
    }
}

/// A path command with its points, to 0.01 px.
fn push(d: &mut String, cmd: char, pts: &[(f64, f64)]) {
    d.push(cmd);
    for (i, (x, y)) in pts.iter().enumerate() {
        if i > 0 {
            d.push(' ');
        }
        d.push_str(&format!("{} {}", round2(*x), round2(*y)));
    }
}

fn round2(v: f64) -> f64 {
    let r = (v * 100.0).round() / 100.0;
    if r == 0.0 {
        0.0
    } else {
        r
    }
}

/// Text that plotters escaped for XML, as written.
/// Element content as written back to text: the five XML entities (plotters writes `'` as
/// `&apos;`) and numeric references, in one pass, so `&amp;lt;` stays the text `&lt;`.
fn unescape(s: &str) -> String {
    let mut out = String::with_capacity(s.len());
    let mut rest = s;
    while let Some(i) = rest.find('&') {
        out.push_str(&rest[..i]);
        let tail = &rest[i..];
        let entity = tail.find(';').filter(|&j| j <= 10).and_then(|j| Some((entity_char(&tail[1..j])?, j)));
        match entity {
            Some((c, j)) => {
                out.push(c);
                rest = &tail[j + 1..];
            }
            None => {
                out.push('&');
                rest = &tail[1..];
            }
        }
    }
    out.push_str(rest);
    out
}

/// The character an entity name (between `&` and `;`) stands for.
fn entity_char(name: &str) -> Option<char> {
    match name {
        "lt" => Some('<'),
        "gt" => Some('>'),
        "quot" => Some('"'),
        "apos" => Some('\''),
        "amp" => Some('&'),
        _ => {
            let code = match name.strip_prefix("#x").or_else(|| name.strip_prefix("#X")) {
                Some(hex) => u32::from_str_radix(hex, 16).ok()?,
                None => name.strip_prefix('#')?.parse().ok()?,
            };
            char::from_u32(code)
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn dejavu() -> FontRef<'static> {
        FontRef::try_from_slice(super::super::FONT_BYTES).unwrap()
    }

    #[test]
    fn text_becomes_paths_placed_by_the_layout() {
        let svg = "<svg>\n<text x=\"10\" y=\"20\" dy=\"0.76em\" text-anchor=\"start\" font-family=\"sans-serif\" \
                   font-size=\"12.4\" opacity=\"1\" fill=\"#000000\">\nF &amp; T\n</text>\n\
                   <text x=\"100\" y=\"20\" dy=\"0.76em\" text-anchor=\"end\" font-size=\"12.4\" fill=\"#FF0000\" \
                   transform=\"rotate(270, 100, 20)\">W</text>\n<text x=\"1\" y=\"1\">  </text></svg>";
        let out = outline_text(svg, &dejavu());
        assert!(!out.contains("<text"), "{out}");
        assert_eq!(out.matches("<path").count(), 2, "blank text draws nothing: {out}");
        assert!(out.contains("aria-label=\"F &amp; T\"") && out.contains("aria-label=\"W\""), "{out}");
        assert!(out.contains("transform=\"rotate(270, 100, 20)\"") && out.contains("fill=\"#FF0000\""), "{out}");
        // The first glyph starts at x = 10 (F's stem is a little right of its origin) and
        // a right-anchored text ends at its x.
        let first = out.split("d=\"M").nth(1).unwrap();
        let x0: f64 = first.split(' ').next().unwrap().parse().unwrap();
        assert!((10.0..12.0).contains(&x0), "{x0}");
        let scaled = dejavu().into_scaled(PxScale::from(12.4 * 1.24));
        let w = layout(&scaled, "W").1;
        assert!(w > 10.0 && w < 20.0, "{w}");
    }

    #[test]
    fn entities_are_read_once() {
        assert_eq!(
            unescape("mode&apos;s &amp;apos; &lt;&#39;&#x3b1;&gt; AT&amp;T & x;"),
            "mode's &apos; <'α> AT&T & x;"
        );
        let svg = "<svg><text x=\"0\" y=\"9\" font-size=\"12\">beam&apos;s</text></svg>";
        let out = outline_text(svg, &dejavu());
        assert!(out.contains("aria-label=\"beam&#39;s\""), "{out}");
    }
}
