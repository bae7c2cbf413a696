//! A small reader for numeric CSV files with a header row.
//!
//! Measurement and voltage files in beamflow are plain tables: one header row naming the
//! columns, then one row of numbers per sample. This reader takes only the columns asked
//! for, by name, and refuses anything it cannot turn into finite numbers, saying which file,
//! which column and which row is at fault.
//!
//! Accepted layout:
//! - the separator is taken from the header: `,` if it has one, else `;`, else a tab, else
//!   runs of white space;
//! - blank lines and lines whose first non-blank character is `#` are skipped anywhere;
//! - header names are trimmed and may be wrapped in double quotes; matching is exact
//!   (case-sensitive);
//! - every data row must have as many fields as the header;
//! - every requested cell must parse as a finite `f64` (`nan`, `inf` are rejected).
//!
//! Rows are numbered from 1 for the first data row (the header is not a row); messages also
//! give the line number in the file, which counts every line.

use std::path::Path;

use crate::error::{Error, Result};

/// How fields are separated in a file, decided from its header line.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Separator {
    Char(char),
    Whitespace,
}

impl Separator {
    fn detect(header: &str) -> Self {
        for c in [',', ';', '\t'] {
            if header.contains(c) {
                return Separator::Char(c);
            }
        }
        Separator::Whitespace
    }

    fn split<'a>(&self, line: &'a str) -> Vec<&'a str> {
        match *self {
            Separator::Char(c) => line.split(c).map(str::trim).collect(),
            Separator::Whitespace => line.split_whitespace().collect(),
        }
    }
}

fn unquote(s: &str) -> &str {
    let s = s.trim();
    if s.len() >= 2 && s.starts_with('"') && s.ends_with('"') {
        s[1..s.len() - 1].trim()
    } else {
        s
    }
}

fn is_skipped(line: &str) -> bool {
    let t = line.trim();
    t.is_empty() || t.starts_with('#')
}

/// Reads the named numeric columns of a CSV file with a header row.
///
/// Returns one `Vec<f64>` per requested name, in the order of `names`, all of the same
/// length (the number of data rows). Errors ([`Error::Input`] unless the file cannot be read
/// at all, which is [`Error::Io`]) name the file and the column or row:
/// empty file, no data rows, a requested column missing from the header (or present twice),
/// a row with a different number of fields than the header, an empty or unparsable cell, a
/// NaN or infinite value.
pub fn read_columns(path: &Path, names: &[&str]) -> Result<Vec<Vec<f64>>> {
    let text = crate::input_file::read_text(path)?;
    parse_columns(&text, &path.display().to_string(), names)
}

/// [`read_columns`] on text already in memory; `file` is the name used in messages.
pub fn parse_columns(text: &str, file: &str, names: &[&str]) -> Result<Vec<Vec<f64>>> {
    let mut lines = text.lines().enumerate().filter(|(_, l)| !is_skipped(l));
    let Some((_, header)) = lines.next() else {
        return Err(Error::input(
            file,
            "header",
            "the file is empty: expected a header row naming the columns, then rows of numbers",
        ));
    };
    let header = header.trim_start_matches('\u{feff}');
    let sep = Separator::detect(header);
    let head: Vec<&str> = sep.split(header).into_iter().map(unquote).collect();

    let mut index = Vec::with_capacity(names.len());
    for &name in names {
        let hits: Vec<usize> = head.iter().enumerate().filter(|(_, h)| **h == name).map(|(i, _)| i).collect();
        match hits.as_slice() {
            [i] => index.push(*i),
            [] => {
                return Err(Error::input(
                    file,
                    name,
                    format!("column not found in the header; the header has: {}", head.join(", ")),
                ))
            }
            _ => {
                return Err(Error::input(
                    file,
                    name,
                    format!("the header names this column {} times; it must be unique", hits.len()),
                ))
            }
        }
    }

    let mut cols: Vec<Vec<f64>> = vec![Vec::new(); names.len()];
    let mut row = 0usize;
    for (lineno, line) in lines {
        row += 1;
        let line_no = lineno + 1;
        let fields = sep.split(line);
        if fields.len() != head.len() {
            return Err(Error::input(
                file,
                format!("row {row}"),
                format!(
                    "line {line_no} has {} fields but the header has {}; all rows must have the same length",
                    fields.len(),
                    head.len()
                ),
            ));
        }
        for (k, (&i, &name)) in index.iter().zip(names).enumerate() {
            let cell = unquote(fields[i]);
            if cell.is_empty() {
                return Err(Error::input(
                    file,
                    name,
                    format!("row {row} (line {line_no}): empty cell, expected a number"),
                ));
            }
            let x: f64 = cell.parse().map_err(|_| {
                Error::input(file, name, format!("row {row} (line {line_no}): cannot read `{cell}` as a number"))
            })?;
            if !x.is_finite() {
                return Err(Error::input(
                    file,
                    name,
                    format!(
                        "row {row} (line {line_no}): value `{cell}` is not finite; NaN and infinity are not accepted"
                    ),
                ));
            }
            cols[k].push(x);
        }
    }
    if row == 0 {
        return Err(Error::input(file, "rows", "the file has a header but no data rows"));
    }
    Ok(cols)
}

/// Checks a time column: finite, strictly increasing and, if `require_uniform`, uniformly
/// spaced to 1e-6 relative to the mean spacing.
///
/// Needs at least two samples. Errors name `file`, `column` and the first offending row
/// (numbered from 1 for the first data row, as in [`read_columns`]).
pub fn check_time_axis(file: &str, column: &str, t: &[f64], require_uniform: bool) -> Result<()> {
    if t.len() < 2 {
        return Err(Error::input(file, column, format!("a time axis needs at least 2 samples, found {}", t.len())));
    }
    if let Some(i) = t.iter().position(|x| !x.is_finite()) {
        return Err(Error::input(file, column, format!("row {}: time {} is not finite", i + 1, t[i])));
    }
    for i in 1..t.len() {
        if t[i] <= t[i - 1] {
            return Err(Error::input(
                file,
                column,
                format!(
                    "row {}: time {} is not greater than the previous row's {}; time must be strictly increasing",
                    i + 1,
                    t[i],
                    t[i - 1]
                ),
            ));
        }
    }
    if require_uniform {
        let n = t.len();
        let mean = (t[n - 1] - t[0]) / (n - 1) as f64;
        for i in 1..n {
            let dt = t[i] - t[i - 1];
            if (dt - mean).abs() > 1e-6 * mean {
                return Err(Error::input(
                    file,
                    column,
                    format!(
                        "row {}: step {dt:e} s differs from the mean step {mean:e} s by more than 1e-6 relative; uniform sampling is required",
                        i + 1
                    ),
                ));
            }
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    fn msg(e: Error) -> String {
        e.to_string()
    }

    #[test]
    fn reads_requested_columns_in_order() {
        let text = "# comment\ntime, \"voltage\", other\n0, 1.5, 9\n\n0.1, -2e0, 8\n";
        let c = parse_columns(text, "a.csv", &["voltage", "time"]).unwrap();
        assert_eq!(c, vec![vec![1.5, -2.0], vec![0.0, 0.1]]);
        // semicolon and whitespace separated files
        let c = parse_columns("t;v\n1;2\n", "b.csv", &["v"]).unwrap();
        assert_eq!(c, vec![vec![2.0]]);
        let c = parse_columns("t v\n1   2\n3\t4\n", "c.txt", &["t", "v"]).unwrap();
        assert_eq!(c, vec![vec![1.0, 3.0], vec![2.0, 4.0]]);
    }

    #[test]
    fn errors_name_file_column_and_row() {
        let e = msg(parse_columns("", "e.csv", &["time"]).unwrap_err());
        assert!(e.contains("e.csv") && e.contains("empty"), "{e}");
        let e = msg(parse_columns("time,voltage\n", "e.csv", &["time"]).unwrap_err());
        assert!(e.contains("e.csv") && e.contains("no data rows"), "{e}");
        let e = msg(parse_columns("time,volt\n0,1\n", "m.csv", &["time", "voltage"]).unwrap_err());
        assert!(e.contains("m.csv") && e.contains("`voltage`") && e.contains("not found"), "{e}");
        let e = msg(parse_columns("time,voltage\n0,1\n1,x1\n", "p.csv", &["voltage"]).unwrap_err());
        assert!(e.contains("p.csv") && e.contains("`voltage`") && e.contains("row 2") && e.contains("x1"), "{e}");
        let e = msg(parse_columns("time,voltage\n0,1\n1,NaN\n", "n.csv", &["voltage"]).unwrap_err());
        assert!(
            e.contains("n.csv") && e.contains("`voltage`") && e.contains("row 2") && e.contains("not finite"),
            "{e}"
        );
        let e = msg(parse_columns("time,voltage\n0,inf\n", "n.csv", &["voltage"]).unwrap_err());
        assert!(e.contains("row 1") && e.contains("not finite"), "{e}");
        let e = msg(parse_columns("time,voltage\n0,1\n1\n", "u.csv", &["time"]).unwrap_err());
        assert!(e.contains("u.csv") && e.contains("row 2") && e.contains("line 3"), "{e}");
        let e = msg(parse_columns("time,voltage\n0,\n", "u.csv", &["voltage"]).unwrap_err());
        assert!(e.contains("empty cell"), "{e}");
        let e = msg(parse_columns("t,t\n0,1\n", "d.csv", &["t"]).unwrap_err());
        assert!(e.contains("unique"), "{e}");
    }

    #[test]
    fn time_axis_checks() {
        check_time_axis("f.csv", "time", &[0.0, 0.1, 0.2], true).unwrap();
        check_time_axis("f.csv", "time", &[0.0, 0.1, 0.25], false).unwrap();
        check_time_axis("f.csv", "time", &[0.0, 0.1, 0.2 + 1e-8], true).unwrap();
        let e = msg(check_time_axis("f.csv", "time", &[0.0, 0.1, 0.2, 0.3, 0.4 + 1e-6], true).unwrap_err());
        assert!(e.contains("f.csv") && e.contains("`time`") && e.contains("row 2") && e.contains("uniform"), "{e}");
        let e = msg(check_time_axis("f.csv", "time", &[0.0, 0.1, 0.1, 0.2], false).unwrap_err());
        assert!(
            e.contains("f.csv") && e.contains("`time`") && e.contains("row 3") && e.contains("strictly increasing"),
            "{e}"
        );
        let e = msg(check_time_axis("f.csv", "t", &[0.0, 0.2, 0.1], false).unwrap_err());
        assert!(e.contains("row 3"), "{e}");
        assert!(check_time_axis("f.csv", "t", &[0.0], false).is_err());
    }
}
