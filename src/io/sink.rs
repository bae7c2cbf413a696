//! Where a results layout is written: a group of an HDF5 file ([`super::hdf5::GroupWriter`])
//! or of an in-memory tree ([`super::tree::TreeSink`], what the Python package hands out).
//! One layout function ([`super::results::write_into`]) serves both, so a result held in
//! memory equals the file on disk by construction.

use crate::error::{Error, Result};
use num_complex::Complex64;

/// The operations a results layout needs from one group. Paths of subgroups are
/// slash-separated and relative to this group; dataset names are plain names.
pub trait GroupSink: Sized {
    /// Opens or creates a subgroup, creating intermediate groups.
    fn group(&self, sub: &str) -> Result<Self>;
    /// Sets (or replaces) a string attribute on this group.
    fn attr_str(&self, name: &str, value: &str) -> Result<()>;
    /// Sets (or replaces) a floating-point attribute on this group.
    fn attr_f64(&self, name: &str, value: f64) -> Result<()>;
    /// Sets (or replaces) an integer attribute on this group.
    fn attr_i64(&self, name: &str, value: i64) -> Result<()>;
    /// A real array of `shape` (`[n]` or `[rows, cols]`, row-major) with its SI unit
    /// (`"1"` if dimensionless) and a description.
    fn write_f64(&self, name: &str, data: &[f64], shape: &[usize], unit: &str, description: &str) -> Result<()>;
    /// A complex array, shape and unit as in [`write_f64`](Self::write_f64).
    fn write_c64(&self, name: &str, data: &[Complex64], shape: &[usize], unit: &str, description: &str) -> Result<()>;
    /// An integer array (counts, indices), shape and unit as in [`write_f64`](Self::write_f64).
    fn write_i64(&self, name: &str, data: &[i64], shape: &[usize], unit: &str, description: &str) -> Result<()>;
    /// A scalar text dataset (no unit or description).
    fn write_str(&self, name: &str, value: &str) -> Result<()>;
    /// A 1-D array of strings (no unit or description).
    fn write_str_list(&self, name: &str, values: &[String]) -> Result<()>;
}

/// Checks a numeric dataset's shape against its data: 1 or 2 dimensions whose product is
/// the number of values. `file` and `full` (the dataset's path) name it in the message.
pub fn check_shape(file: &str, full: &str, shape: &[usize], len: usize) -> Result<()> {
    if !(1..=2).contains(&shape.len()) {
        return Err(Error::input(file, full, format!("shape {shape:?} must have 1 or 2 dimensions")));
    }
    let n: usize = shape.iter().product();
    if n != len {
        return Err(Error::input(file, full, format!("shape {shape:?} holds {n} values but {len} were given")));
    }
    Ok(())
}

/// Checks a new dataset's name: non-empty, without `/`, not `.`.
pub fn check_name(file: &str, full: &str, name: &str) -> Result<()> {
    if name.is_empty() || name.contains('/') || name == "." {
        return Err(Error::input(file, full, "dataset name must be non-empty without `/`"));
    }
    Ok(())
}
