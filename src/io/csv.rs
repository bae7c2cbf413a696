//! Tidy CSV tables for spreadsheets, pandas, MATLAB and R.
//!
//! One header line whose column names carry their unit in brackets (`time [s]`,
//! `transmitted re [N]`; `[1]` for a dimensionless number, no bracket for a text column),
//! then one row per observation. Numbers are written so that they read back to the same
//! `f64` bit for bit (shortest round-trip form, exponent notation outside 1e-4..1e15);
//! `NaN` and `inf` stand for values that are not defined. Fields holding a separator, a
//! quote or a line break are quoted (RFC 4180).

use crate::error::{Error, Result};
use num_complex::Complex64;
use std::path::Path;

/// The cells of one column.
#[derive(Clone, Debug, PartialEq)]
pub enum Cells {
    Num(Vec<f64>),
    Int(Vec<i64>),
    Text(Vec<String>),
}

impl Cells {
    /// Number of cells.
    pub fn len(&self) -> usize {
        match self {
            Cells::Num(v) => v.len(),
            Cells::Int(v) => v.len(),
            Cells::Text(v) => v.len(),
        }
    }

    /// Whether the column has no cells.
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    fn cell(&self, i: usize) -> String {
        match self {
            Cells::Num(v) => number(v[i]),
            Cells::Int(v) => v[i].to_string(),
            Cells::Text(v) => quoted(&v[i]),
        }
    }
}

/// One column: its name, its unit (`None` for text and counts) and its cells.
#[derive(Clone, Debug, PartialEq)]
pub struct Column {
    pub name: String,
    pub unit: Option<String>,
    pub cells: Cells,
}

impl Column {
    /// A real column with its SI unit (`"1"` if dimensionless).
    pub fn num(name: impl Into<String>, unit: &str, values: Vec<f64>) -> Self {
        Column { name: name.into(), unit: Some(unit.to_string()), cells: Cells::Num(values) }
    }

    /// A text column (names of links, points, modes).
    pub fn text(name: impl Into<String>, values: Vec<String>) -> Self {
        Column { name: name.into(), unit: None, cells: Cells::Text(values) }
    }

    /// A count or index column.
    pub fn int(name: impl Into<String>, values: Vec<i64>) -> Self {
        Column { name: name.into(), unit: None, cells: Cells::Int(values) }
    }

    /// A complex quantity as two real columns, `<name> re` and `<name> im`, in the results'
    /// convention q(t) = Re(Q·exp(+iωt)).
    pub fn complex(name: &str, unit: &str, values: &[Complex64]) -> [Self; 2] {
        [
            Column::num(format!("{name} re"), unit, values.iter().map(|c| c.re).collect()),
            Column::num(format!("{name} im"), unit, values.iter().map(|c| c.im).collect()),
        ]
    }

    /// The column made of the cells at `rows` (in that order, repeats allowed).
    pub fn select(&self, rows: impl Iterator<Item = usize>) -> Self {
        let cells = match &self.cells {
            Cells::Num(v) => Cells::Num(rows.map(|i| v[i]).collect()),
            Cells::Int(v) => Cells::Int(rows.map(|i| v[i]).collect()),
            Cells::Text(v) => Cells::Text(rows.map(|i| v[i].clone()).collect()),
        };
        Column { name: self.name.clone(), unit: self.unit.clone(), cells }
    }

    /// The header cell: the name with its unit in brackets.
    pub fn header(&self) -> String {
        match &self.unit {
            Some(u) => format!("{} [{u}]", self.name),
            None => self.name.clone(),
        }
    }
}

/// A table: columns of equal length.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Table {
    pub columns: Vec<Column>,
}

impl Table {
    /// Number of rows (0 for a table without columns).
    pub fn rows(&self) -> usize {
        self.columns.first().map_or(0, |c| c.cells.len())
    }

    /// Appends a column.
    pub fn push(&mut self, c: Column) {
        self.columns.push(c);
    }

    /// Appends the rows of `other`, a table with the same headers (long tables are built
    /// one entity at a time).
    pub fn append(&mut self, other: Table) {
        if self.columns.is_empty() {
            *self = other;
            return;
        }
        for (a, b) in self.columns.iter_mut().zip(other.columns) {
            debug_assert_eq!(a.header(), b.header(), "appended tables share their columns");
            match (&mut a.cells, b.cells) {
                (Cells::Num(x), Cells::Num(y)) => x.extend(y),
                (Cells::Int(x), Cells::Int(y)) => x.extend(y),
                (Cells::Text(x), Cells::Text(y)) => x.extend(y),
                _ => unreachable!("appended tables share their column kinds"),
            }
        }
    }

    /// The table as CSV text; refuses columns of unequal length (`file` names it).
    pub fn to_csv(&self, file: &str) -> Result<String> {
        let n = self.rows();
        if let Some(c) = self.columns.iter().find(|c| c.cells.len() != n) {
            return Err(Error::Numerical(format!(
                "{file}: column `{}` has {} rows, the first column {n}",
                c.header(),
                c.cells.len()
            )));
        }
        let mut s = self.columns.iter().map(|c| quoted(&c.header())).collect::<Vec<_>>().join(",");
        s.push('\n');
        for i in 0..n {
            s += &self.columns.iter().map(|c| c.cells.cell(i)).collect::<Vec<_>>().join(",");
            s.push('\n');
        }
        Ok(s)
    }

    /// Writes the table atomically.
    pub fn write(&self, path: &Path) -> Result<()> {
        let text = self.to_csv(&path.display().to_string())?;
        crate::io::atomic::write_atomic_string(path, &text)
    }
}

/// A number that reads back to the same `f64`.
fn number(x: f64) -> String {
    if x.is_nan() {
        "NaN".into()
    } else if x.is_infinite() {
        if x > 0.0 { "inf" } else { "-inf" }.into()
    } else if x == 0.0 || (1e-4..1e15).contains(&x.abs()) {
        format!("{x}")
    } else {
        format!("{x:e}")
    }
}

/// A text field, quoted when it holds a comma, a quote or a line break.
fn quoted(s: &str) -> String {
    if s.contains([',', '"', '\n', '\r']) {
        format!("\"{}\"", s.replace('"', "\"\""))
    } else {
        s.to_string()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn numbers_read_back_bit_for_bit() {
        for x in [0.0, -0.0, 1.0, -2.5e-8, 1e-300, f64::MIN_POSITIVE, 1e300, 123456.789, 0.1 + 0.2, 1e15, 9.99e-5] {
            let s = number(x);
            assert_eq!(s.parse::<f64>().unwrap().to_bits(), x.to_bits(), "{x} → {s}");
        }
        assert_eq!(number(f64::NAN), "NaN");
        assert_eq!(number(f64::NEG_INFINITY), "-inf");
    }

    #[test]
    fn header_carries_units_and_text_is_quoted() {
        let mut t = Table::default();
        t.push(Column::text("link", vec!["a,b".into(), "say \"hi\"".into()]));
        t.push(Column::num("time", "s", vec![0.5, 1.0]));
        let [re, im] = Column::complex("F", "N", &[Complex64::new(1.0, -2.0), Complex64::new(0.0, 3.0)]);
        t.push(re);
        t.push(im);
        let s = t.to_csv("t.csv").unwrap();
        assert_eq!(s, "link,time [s],F re [N],F im [N]\n\"a,b\",0.5,1,-2\n\"say \"\"hi\"\"\",1,0,3\n");
        t.push(Column::int("k", vec![1]));
        assert!(t.to_csv("t.csv").unwrap_err().to_string().contains("`k` has 1 rows"));
    }
}
