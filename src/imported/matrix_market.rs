//! Reading a structure's M, K or C from a Matrix Market file (spec §17): coordinate, real,
//! `symmetric` (one triangle) or `general` storage, 1-based indices.
//!
//! The reader streams the file line by line and checks each entry as it comes, so a broken
//! or hostile file is refused at its first bad line, in time and memory bounded by the
//! entry count its size line declares (admitted against the memory budget before any entry
//! is stored).

use crate::error::{Error, Result};
use crate::linalg::Csr;
use std::io::{BufRead, BufReader, Read as _};
use std::path::Path;

/// Bytes one stored entry costs while reading (a triplet) and after (CSR, both triangles).
pub const BYTES_PER_ENTRY: u64 = 3 * 24;

/// Difference |a_ij − a_ji| relative to the entries' natural scale √(|a_ii|·|a_jj|) above
/// which a `general` file is refused as not symmetric: an exporter's assembly round-off
/// (sums in another order, ≈ ε of the diagonal) is far below it, while any asymmetry a
/// model means is far above.
pub const SYMMETRY_TOLERANCE: f64 = 1e-10;

/// A square symmetric matrix as read, with the file it came from for messages.
pub struct Read {
    pub matrix: Csr,
    /// Entries stored in the file.
    pub stored: usize,
}

/// Reads the square symmetric matrix in `path` (named `what`, e.g. "stiffness", in
/// messages), refusing: a header that is not `coordinate real|integer symmetric|general`, a
/// non-square size, more entries than `max_entries`, an index outside the size, a value that
/// is not a finite number, a `general` matrix that is not symmetric, or a line count that
/// disagrees with the size line. Duplicate entries are summed, as in every Matrix Market
/// reader.
pub fn read(path: &Path, max_entries: u64) -> Result<Read> {
    crate::input_file::regular_file(path)?;
    let file = std::fs::File::open(path).map_err(|e| Error::io(path, e))?;
    let name = path.display().to_string();
    let bad = |line: usize, why: String| Error::input(&name, format!("line {line}"), why);
    let mut lines = Lines { reader: BufReader::new(file), number: 0, buf: Vec::new() };
    let next = |lines: &mut Lines| -> Result<Option<(usize, String)>> { lines.next().map_err(|(i, why)| bad(i, why)) };
    let (_, header) = next(&mut lines)?.ok_or_else(|| bad(1, "the file is empty".into()))?;
    let symmetric = parse_header(&header).map_err(|why| bad(1, why))?;
    // The size line: the first line that is not a comment.
    let (size_line, size) = loop {
        match next(&mut lines)? {
            None => return Err(bad(2, "no size line `rows columns entries`".into())),
            Some((_, l)) if l.starts_with('%') || l.trim().is_empty() => continue,
            Some((i, l)) => break (i, l),
        }
    };
    let [rows, cols, declared] = parse_size(&size).map_err(|why| bad(size_line, why))?;
    if rows != cols {
        return Err(bad(size_line, format!("the matrix is {rows} × {cols}: a structure's matrix is square")));
    }
    if declared as u64 > max_entries {
        return Err(bad(
            size_line,
            format!(
                "{declared} entries would need about {} of memory, more than the budget allows ({max_entries} \
                 entries); raise the memory budget or reduce the model",
                crate::analysis::budget::bytes_text((declared as u64).saturating_mul(BYTES_PER_ENTRY))
            ),
        ));
    }
    let n = rows;
    let mut triplets: Vec<(usize, usize, f64)> = Vec::with_capacity(declared.min(1 << 24));
    while let Some((i, l)) = next(&mut lines)? {
        if l.starts_with('%') || l.trim().is_empty() {
            continue;
        }
        if triplets.len() == declared {
            return Err(bad(i, format!("more entries than the {declared} the size line declares")));
        }
        let (r, c, v) = parse_entry(&l, n).map_err(|why| bad(i, why))?;
        if symmetric && c > r {
            return Err(bad(
                i,
                format!(
                    "entry ({}, {}) is above the diagonal: a symmetric file stores the lower triangle",
                    r + 1,
                    c + 1
                ),
            ));
        }
        triplets.push((r, c, v));
    }
    if triplets.len() != declared {
        return Err(bad(size_line, format!("declares {declared} entries but the file holds {}", triplets.len())));
    }
    let stored = triplets.len();
    if symmetric {
        let upper: Vec<_> = triplets.iter().filter(|t| t.0 != t.1).map(|&(r, c, v)| (c, r, v)).collect();
        triplets.extend(upper);
    }
    let matrix = Csr::from_triplets(n, &triplets);
    drop(triplets);
    if !symmetric {
        check_symmetric(&matrix)
            .map_err(|(r, c, why)| Error::input(&name, format!("entry ({}, {})", r + 1, c + 1), why))?;
    }
    Ok(Read { matrix, stored })
}

/// Longest line read (bytes): an entry is three numbers; a longer "line" (a file of zeros,
/// or binary data) is refused without being held in memory.
const MAX_LINE: u64 = 1024;

/// The file's lines, each read up to [`MAX_LINE`] bytes.
struct Lines {
    reader: BufReader<std::fs::File>,
    number: usize,
    buf: Vec<u8>,
}

impl Lines {
    /// The next line and its 1-based number, None at the end; the line and the reason if it
    /// is too long or not text.
    fn next(&mut self) -> std::result::Result<Option<(usize, String)>, (usize, String)> {
        self.number += 1;
        self.buf.clear();
        let n = (&mut self.reader)
            .take(MAX_LINE + 1)
            .read_until(b'\n', &mut self.buf)
            .map_err(|e| (self.number, format!("cannot be read: {e}")))?;
        if n == 0 {
            return Ok(None);
        }
        if self.buf.last() != Some(&b'\n') && n as u64 > MAX_LINE {
            return Err((self.number, format!("is longer than {MAX_LINE} bytes: not a Matrix Market line")));
        }
        let text = std::str::from_utf8(&self.buf).map_err(|_| (self.number, "is not text (UTF-8)".to_string()))?;
        Ok(Some((self.number, text.trim_end_matches(['\n', '\r']).to_string())))
    }
}

/// `true` for symmetric storage, `false` for general; the reason otherwise.
fn parse_header(line: &str) -> std::result::Result<bool, String> {
    let words: Vec<String> = line.split_whitespace().map(str::to_ascii_lowercase).collect();
    let w: Vec<&str> = words.iter().map(String::as_str).collect();
    match w.as_slice() {
        ["%%matrixmarket", "matrix", "coordinate", "real" | "integer", sym] => match *sym {
            "symmetric" => Ok(true),
            "general" => Ok(false),
            other => Err(format!("`{other}` storage is not read: write `symmetric` or `general`")),
        },
        ["%%matrixmarket", "matrix", "array", ..] => {
            Err("dense `array` format is not read: write the sparse `coordinate` format".into())
        }
        ["%%matrixmarket", "matrix", "coordinate", field, ..] => {
            Err(format!("`{field}` entries are not read: a structure's matrix is `real`"))
        }
        _ => Err(format!("{line:?} is not a Matrix Market header (`%%MatrixMarket matrix coordinate real symmetric`)")),
    }
}

fn parse_size(line: &str) -> std::result::Result<[usize; 3], String> {
    let v: Vec<&str> = line.split_whitespace().collect();
    let parsed: Option<Vec<usize>> = v.iter().map(|s| s.parse().ok()).collect();
    match parsed.as_deref() {
        Some(&[r, c, e]) if r > 0 => Ok([r, c, e]),
        _ => Err(format!("{line:?} is not a size line `rows columns entries` of whole numbers, rows ≥ 1")),
    }
}

/// A 0-based (row, column, value).
fn parse_entry(line: &str, n: usize) -> std::result::Result<(usize, usize, f64), String> {
    let v: Vec<&str> = line.split_whitespace().collect();
    let [r, c, x] = v.as_slice() else {
        return Err(format!("{line:?} is not an entry `row column value`"));
    };
    let index = |s: &str| -> std::result::Result<usize, String> {
        match s.parse::<usize>() {
            Ok(i) if (1..=n).contains(&i) => Ok(i - 1),
            _ => Err(format!("index {s:?} is not in 1..={n}")),
        }
    };
    let value: f64 = x.parse().map_err(|_| format!("value {x:?} is not a number"))?;
    if !value.is_finite() {
        return Err(format!("value {x} is not finite"));
    }
    Ok((index(r)?, index(c)?, value))
}

/// The first entry whose mirror differs by more than [`SYMMETRY_TOLERANCE`] (relative).
fn check_symmetric(a: &Csr) -> std::result::Result<(), (usize, usize, String)> {
    let largest = a.triplets().filter(|t| t.0 == t.1).fold(0.0f64, |m, t| m.max(t.2.abs()));
    for (i, j, v) in a.triplets().filter(|t| t.1 > t.0) {
        let w = a.get(j, i);
        let diagonal = (a.get(i, i) * a.get(j, j)).abs().sqrt();
        let scale = if diagonal > 0.0 { diagonal } else { largest.max(v.abs()).max(w.abs()) };
        if (v - w).abs() > SYMMETRY_TOLERANCE * scale {
            return Err((
                i,
                j,
                format!(
                    "is {v:e} but entry ({}, {}) is {w:e}: the matrix is not symmetric (tolerance \
                     {SYMMETRY_TOLERANCE:e} of √(a_ii·a_jj))",
                    j + 1,
                    i + 1
                ),
            ));
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    fn write(text: &str) -> (tempfile::TempDir, std::path::PathBuf) {
        let d = tempfile::tempdir().unwrap();
        let p = d.path().join("k.mtx");
        std::fs::write(&p, text).unwrap();
        (d, p)
    }

    #[test]
    fn symmetric_storage_mirrors_the_lower_triangle() {
        let (_d, p) =
            write("%%MatrixMarket matrix coordinate real symmetric\n% c\n3 3 4\n1 1 2\n2 1 -1\n2 2 2\n3 3 1.5\n");
        let r = read(&p, 100).unwrap();
        assert_eq!(r.stored, 4);
        assert_eq!(r.matrix.get(0, 1), -1.0);
        assert_eq!(r.matrix.get(1, 0), -1.0);
        assert_eq!(r.matrix.get(2, 2), 1.5);
    }

    #[test]
    fn each_broken_file_is_refused_at_its_line() {
        let h = "%%MatrixMarket matrix coordinate real general\n";
        for (text, expect) in [
            (format!("{h}2 2 2\n1 1 1\n1 2 1\n"), "entry (1, 2)"),
            (format!("{h}2 2 1\n1 1 nan\n"), "line 3"),
            (format!("{h}2 2 1\n3 1 1\n"), "not in 1..=2"),
            (format!("{h}2 3 1\n1 1 1\n"), "square"),
            (format!("{h}2 2 2\n1 1 1\n"), "declares 2"),
            (format!("{h}2 2 1\n1 1 1\n2 2 1\n"), "more entries"),
            ("%%MatrixMarket matrix array real general\n".to_string(), "array"),
            (format!("{h}2 2 99999999999\n"), "budget"),
            ("%%MatrixMarket matrix coordinate real symmetric\n2 2 1\n1 2 1\n".to_string(), "lower triangle"),
            (format!("{h}2 2 1\n{}", "0".repeat(5000)), "longer than"),
        ] {
            let (_d, p) = write(&text);
            let e = read(&p, 1000).err().unwrap_or_else(|| panic!("accepted {text:?}")).to_string();
            assert!(e.contains("k.mtx") && e.contains(expect), "{e} (expected {expect})");
        }
    }

    /// A 2 GB file (sparse on disk: a header, a size line, then zeros) is refused at its
    /// first long line, having read about a kilobyte of it.
    #[test]
    fn a_two_gigabyte_file_is_refused_at_once() {
        let (_d, p) = write("%%MatrixMarket matrix coordinate real general\n2 2 1\n");
        std::fs::OpenOptions::new().write(true).open(&p).unwrap().set_len(2 << 30).unwrap();
        let e = read(&p, 1000).err().unwrap().to_string();
        assert!(e.contains("line 3") && e.contains("longer than"), "{e}");
    }
}
