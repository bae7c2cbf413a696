//! Building blocks of the HTML reports: one self-contained page (inline CSS, figures as
//! inline SVG, no script, no external address), so a report opens offline in any browser
//! and can be mailed as one file.
//!
//! Every piece of text that comes from a user (case titles, names, file names, the case
//! file itself) goes through [`escape`]; numbers are written with an SI prefix for people
//! and exactly (`data-value`) for machines.

use std::path::Path;

use crate::error::{Error, Result};
use crate::report::plot::text::{eng, si, significant};
pub use crate::report::plot::text::{escape, html as label};

/// The page's style: readable text width, tables with aligned numbers, figures that shrink
/// to the window.
const CSS: &str = "\
body{font-family:'DejaVu Sans',Verdana,sans-serif;margin:0 auto;max-width:1100px;padding:1em 1.5em;color:#222;line-height:1.45}\
h1{font-size:1.6em;margin-bottom:.2em}h2{border-bottom:1px solid #ccc;padding-bottom:.2em;margin-top:1.8em}\
h3{margin-top:1.4em}.meta{color:#555}\
table{border-collapse:collapse;margin:.6em 0;display:block;overflow-x:auto;max-width:100%}th,td{border:1px solid #ddd;padding:.25em .6em;vertical-align:top}\
th{background:#f4f4f4;text-align:left}td.num{text-align:right;font-variant-numeric:tabular-nums;white-space:nowrap}\
figure{margin:1.2em 0}figure svg{max-width:100%;height:auto;border:1px solid #eee}\
figcaption{color:#555;font-size:.9em}pre{background:#f7f7f7;padding:.8em;overflow-x:auto;border:1px solid #e4e4e4}\
.warn{background:#fff4e0;border-left:4px solid #e08a00;padding:.5em 1em}.ok{color:#176d2a}.bad{color:#b00020}\
details{margin:.6em 0}summary{cursor:pointer;color:#1f4e8a}nav ul{columns:2}";

/// A report page being written.
pub struct Page {
    body: String,
    /// (anchor, heading) of each section, for the contents.
    sections: Vec<(String, String)>,
}

impl Page {
    pub fn new() -> Self {
        Page { body: String::new(), sections: Vec::new() }
    }

    /// Raw HTML (already escaped).
    pub fn push(&mut self, html: &str) {
        self.body.push_str(html);
    }

    /// A section heading with an anchor; listed in the contents.
    pub fn section(&mut self, id: &str, heading: &str) {
        self.body += &format!("<h2 id=\"{}\">{}</h2>\n", escape(id), label(heading));
        self.sections.push((id.to_string(), heading.to_string()));
    }

    /// A paragraph of plain text.
    pub fn para(&mut self, text: &str) {
        self.body += &format!("<p>{}</p>\n", label(text));
    }

    /// The whole document: `title`, a line under it (`meta`, raw HTML), the contents and
    /// the sections.
    pub fn finish(self, title: &str, meta: &str) -> String {
        let mut nav = String::from("<nav><ul>");
        for (id, h) in &self.sections {
            nav += &format!("<li><a href=\"#{}\">{}</a></li>", escape(id), label(h));
        }
        nav += "</ul></nav>\n";
        format!(
            "<!DOCTYPE html>\n<html lang=\"en\">\n<head>\n<meta charset=\"utf-8\">\n\
             <meta name=\"viewport\" content=\"width=device-width, initial-scale=1\">\n\
             <title>{}</title>\n<style>{CSS}</style>\n</head>\n<body>\n<h1>{}</h1>\n<p class=\"meta\">{meta}</p>\n{nav}{}</body>\n</html>\n",
            escape(&crate::report::plot::text::plain(title)),
            label(title),
            self.body
        )
    }
}

impl Default for Page {
    fn default() -> Self {
        Self::new()
    }
}

/// A table cell holding a number: SI-prefixed text in `unit` (engineering notation when
/// the unit takes no prefix), the exact value in `data-value` and in the tooltip.
pub fn num(v: f64, unit: &str) -> String {
    let text = if !v.is_finite() {
        "–".to_string()
    } else if unit == "Hz" || crate::report::plot::text::prefixable(&format!("x ({unit})")).is_some() {
        si(v, unit, 4)
    } else if (unit.is_empty() || unit == "1") && (1e-3..1e4).contains(&v.abs()) {
        // Ratios such as a MAC of 0.9999 read best as plain decimals.
        significant(v, 4)
    } else if unit.is_empty() || unit == "1" {
        eng(v, 4)
    } else {
        format!("{} {}", eng(v, 4), escape(unit))
    };
    format!("<td class=\"num\" data-value=\"{v:e}\" title=\"{v:e}\">{}</td>", escape(&text))
}

/// A table cell of text (escaped, subscripts kept).
pub fn cell(text: &str) -> String {
    format!("<td>{}</td>", label(text))
}

/// A table: header texts, then rows of cells made by [`num`] and [`cell`].
pub fn table(header: &[&str], rows: &[Vec<String>]) -> String {
    let mut s = String::from("<table>\n<tr>");
    for h in header {
        s += &format!("<th>{}</th>", label(h));
    }
    s += "</tr>\n";
    for r in rows {
        s += "<tr>";
        for c in r {
            s += c;
        }
        s += "</tr>\n";
    }
    s + "</table>\n"
}

/// Content that opens on a click (no script: the `details` element).
pub fn details(summary: &str, inner: &str) -> String {
    format!("<details><summary>{}</summary>\n{inner}</details>\n", label(summary))
}

/// A figure file (its SVG) inline, with its file name as the caption.
pub fn figure(svg_path: &Path) -> Result<String> {
    let text = std::fs::read_to_string(svg_path).map_err(|e| Error::io(svg_path, e))?;
    let start = text.find("<svg").ok_or_else(|| Error::io(svg_path, std::io::Error::other("no <svg> element")))?;
    let stem = svg_path.file_stem().map(|n| n.to_string_lossy().into_owned()).unwrap_or_default();
    // The figure's own anchor, then a link to each of its files beside the report.
    let files: Vec<String> = crate::report::plot::Format::ALL
        .iter()
        .map(|f| svg_path.with_extension(f.ext()))
        .filter(|p| p.exists())
        .filter_map(|p| p.file_name().map(|n| n.to_string_lossy().into_owned()))
        .map(|n| file_link(&n, n.rsplit('.').next().unwrap_or("")))
        .collect();
    let id = anchor(&stem);
    Ok(format!(
        "<figure id=\"{id}\">\n{}\n<figcaption><a href=\"#{id}\">{}</a> · {}</figcaption>\n</figure>\n",
        text[start..].trim_end(),
        escape(&stem),
        files.join(" ")
    ))
}

/// The anchor of a figure in a report (`fig-<file stem>`).
pub fn anchor(stem: &str) -> String {
    let safe: String =
        stem.chars().map(|c| if c.is_ascii_alphanumeric() || c == '-' || c == '_' { c } else { '-' }).collect();
    format!("fig-{safe}")
}

/// A relative link to a file beside the report: its name percent-encoded in the href,
/// the text escaped.
pub fn file_link(name: &str, text: &str) -> String {
    let href: String = name
        .bytes()
        .map(|b| match b {
            b'A'..=b'Z' | b'a'..=b'z' | b'0'..=b'9' | b'-' | b'_' | b'.' | b'~' => (b as char).to_string(),
            _ => format!("%{b:02X}"),
        })
        .collect();
    format!("<a href=\"{href}\">{}</a>", escape(text))
}

/// The files of a run as a list of links to them (relative: the report sits beside them).
pub fn file_list(files: &[std::path::PathBuf]) -> String {
    let items: String = files
        .iter()
        .filter_map(|f| f.file_name())
        .map(|n| n.to_string_lossy().into_owned())
        .map(|n| format!("<li><code>{}</code></li>", file_link(&n, &n)))
        .collect();
    format!("<ul>{items}</ul>\n")
}

/// Markdown as the reports write it (headings, pipe tables, paragraphs, `code`) as HTML;
/// everything else is kept as escaped text.
pub fn markdown(md: &str) -> String {
    let mut out = String::new();
    let mut para: Vec<&str> = Vec::new();
    let mut rows: Vec<Vec<String>> = Vec::new();
    let flush_para = |para: &mut Vec<&str>, out: &mut String| {
        if !para.is_empty() {
            *out += &format!("<p>{}</p>\n", inline(&para.join(" ")));
            para.clear();
        }
    };
    let flush_table = |rows: &mut Vec<Vec<String>>, out: &mut String| {
        if !rows.is_empty() {
            *out += "<table>\n";
            for (i, r) in rows.iter().enumerate() {
                let tag = if i == 0 { "th" } else { "td" };
                *out += "<tr>";
                for c in r {
                    *out += &format!("<{tag}>{}</{tag}>", inline(c));
                }
                *out += "</tr>\n";
            }
            *out += "</table>\n";
            rows.clear();
        }
    };
    for line in md.lines() {
        let t = line.trim();
        if t.starts_with('|') {
            flush_para(&mut para, &mut out);
            let cells: Vec<String> = t.trim_matches('|').split('|').map(|c| c.trim().to_string()).collect();
            if !cells.iter().all(|c| !c.is_empty() && c.chars().all(|ch| matches!(ch, '-' | ':'))) {
                rows.push(cells);
            }
            continue;
        }
        flush_table(&mut rows, &mut out);
        if t.is_empty() {
            flush_para(&mut para, &mut out);
        } else if let Some(h) = t.strip_prefix("# ") {
            flush_para(&mut para, &mut out);
            out += &format!("<h2>{}</h2>\n", inline(h));
        } else if let Some(h) = t.strip_prefix("## ") {
            flush_para(&mut para, &mut out);
            out += &format!("<h3>{}</h3>\n", inline(h));
        } else {
            para.push(t);
        }
    }
    flush_table(&mut rows, &mut out);
    flush_para(&mut para, &mut out);
    out
}

/// User text as Markdown shows it literally, on one line: control characters (a newline
/// would start a heading or a list) become spaces, and every character Markdown or HTML
/// gives a meaning (`* _ [ ] # | < > &` …) is escaped with a backslash.
pub fn markdown_escape(s: &str) -> String {
    let mut o = String::with_capacity(s.len());
    for c in s.chars() {
        match c {
            c if c.is_control() => o.push(' '),
            '\\' | '`' | '*' | '_' | '[' | ']' | '<' | '>' | '&' | '|' | '#' | '~' | '!' | '(' | ')' => {
                o.push('\\');
                o.push(c);
            }
            c => o.push(c),
        }
    }
    o
}

/// User text (a file name) as a Markdown code span, on one line; as escaped text when it
/// holds a backtick, which would end the span.
pub fn markdown_code(s: &str) -> String {
    if s.contains('`') {
        return markdown_escape(s);
    }
    format!("`{}`", s.chars().map(|c| if c.is_control() { ' ' } else { c }).collect::<String>())
}

/// Escapes a line of Markdown, turns its `code` spans into `<code>` and its backslash
/// escapes into the characters they stand for.
fn inline(s: &str) -> String {
    // Subscripts are the one tag Markdown text may carry (`F<sub>T</sub>`); an escaped
    // character never forms part of one.
    let flush = |text: &mut String, out: &mut String| {
        *out += &escape(text).replace("&lt;sub&gt;", "<sub>").replace("&lt;/sub&gt;", "</sub>");
        text.clear();
    };
    let (mut out, mut text) = (String::new(), String::new());
    let mut chars = s.chars().peekable();
    while let Some(c) = chars.next() {
        match c {
            '\\' if chars.peek().is_some_and(char::is_ascii_punctuation) => {
                flush(&mut text, &mut out);
                out += &escape(&chars.next().unwrap_or(c).to_string());
            }
            '`' => {
                flush(&mut text, &mut out);
                let code: String = chars.by_ref().take_while(|&n| n != '`').collect();
                out += &format!("<code>{}</code>", escape(&code));
            }
            c => text.push(c),
        }
    }
    flush(&mut text, &mut out);
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn user_text_is_escaped_everywhere() {
        let mut p = Page::new();
        p.section("a<b", "<script>alert(1)</script>");
        p.para("x & y");
        let html = p.finish("T<i>", "meta");
        assert!(!html.contains("<script>") && !html.contains("<i>"), "{html}");
        assert!(html.contains("&lt;script&gt;") && html.contains("x &amp; y"));
        assert_eq!(cell("F_{T} \"q\""), "<td>F<sub>T</sub> &quot;q&quot;</td>");
    }

    #[test]
    fn user_text_in_markdown_stays_text() {
        let title = "<script>x</script>\n# heading | cell *b* `c` \\";
        let md = markdown_escape(title);
        assert!(!md.contains('\n') && !md.contains("<script>") && !md.contains(" # "), "{md}");
        let h = markdown(&format!("# Sweep: {md}\n"));
        assert_eq!(h.matches("<h2>").count(), 1, "{h}");
        assert!(h.contains("&lt;script&gt;x&lt;/script&gt; # heading | cell *b* `c` \\"), "{h}");
        assert_eq!(markdown_code("a`b\nc"), "a\\`b c");
        assert_eq!(markdown_code("dir/s.toml"), "`dir/s.toml`");
    }

    #[test]
    fn numbers_keep_their_exact_value() {
        let c = num(6.323020285825615e-6, "W");
        assert!(c.contains("6.323 µW") && c.contains("data-value=\"6.323020285825615e-6\""), "{c}");
        assert!(num(3.5e-11, "").contains(">35e-12<"));
        assert!(num(f64::NAN, "W").contains(">–<"));
        assert!(num(2.0, "m/s²").contains("2 m/s²"));
        assert!(num(0.99987, "").contains(">0.9999<") && num(1237.8, "Hz").contains(">1.238 kHz<"));
    }

    #[test]
    fn markdown_tables_and_code() {
        let h = markdown("# Title\n\ntext `a<b` more\n\n| x | y |\n|---|---:|\n| 1 | <2> |\n");
        assert!(markdown("F<sub>T</sub> <sub onload=x>").contains("F<sub>T</sub> &lt;sub onload=x&gt;"));
        assert_eq!(
            h,
            "<h2>Title</h2>\n<p>text <code>a&lt;b</code> more</p>\n<table>\n<tr><th>x</th><th>y</th></tr>\n\
             <tr><td>1</td><td>&lt;2&gt;</td></tr>\n</table>\n"
        );
    }
}
