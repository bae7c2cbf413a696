//! The results file: one standard HDF5 file per run, self-describing enough to be read
//! with h5py or `h5dump` without beamflow or its source.
//!
//! Conventions (the user-facing description lives in `docs/results-format.md`):
//! * every numeric dataset carries string attributes `unit` (SI, `"1"` when
//!   dimensionless) and `description`, because a bare array of numbers is useless a year
//!   later;
//! * arrays are 1-D or 2-D, row-major (C order), as h5py and NumPy expect;
//! * complex values are a compound of two `f64` fields `r` and `i`, the layout h5py maps
//!   to `complex128` natively (HDF5 1.10 has no complex type of its own);
//! * text is variable-length UTF-8.
//!
//! The file is built under a temporary name and renamed into place by
//! [`ResultsFile::finish`], so a crashed or failed run never leaves a file that looks
//! complete (see [`crate::io::atomic`]).

use std::path::{Path, PathBuf};
use std::str::FromStr;

use ::hdf5::types::{H5Type, TypeDescriptor, VarLenAscii, VarLenUnicode};
use num_complex::Complex64;

use super::atomic::PendingFile;
use super::sink::{check_name, check_shape, GroupSink};
use super::tree::{Attr, Data, Dataset, Group};
use crate::error::{Error, Result};
use std::collections::BTreeMap;

/// In-file layout of one complex number: the compound `{r: f64, i: f64}` that h5py reads
/// as `complex128` (its description derived from the `repr(C)` layout). Kept private;
/// callers use [`Complex64`].
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, ::hdf5::H5Type)]
struct H5Complex {
    r: f64,
    i: f64,
}

/// Turns an HDF5 library error into [`Error::Hdf5`] naming the user-facing file (never the
/// temporary name) and what was being done.
fn h5err(path: &Path, what: impl std::fmt::Display) -> impl FnOnce(::hdf5::Error) -> Error {
    let path = path.display().to_string();
    let what = what.to_string();
    move |e| Error::Hdf5 { path, message: format!("{what}: {e}") }
}

fn varlen(path: &Path, what: &str, s: &str) -> Result<VarLenUnicode> {
    VarLenUnicode::from_str(s).map_err(|e| Error::Hdf5 {
        path: path.display().to_string(),
        message: format!("{what}: text cannot be stored ({e})"),
    })
}

/// Sets (or replaces) a scalar attribute on any HDF5 object.
fn put_attr<T: H5Type>(path: &Path, loc: &::hdf5::Location, name: &str, value: &T) -> Result<()> {
    let what = format!("attribute `{name}` on `{}`", loc.name());
    if loc.attr_names().map_err(h5err(path, &what))?.iter().any(|n| n == name) {
        loc.delete_attr(name).map_err(h5err(path, &what))?;
    }
    let attr = loc.new_attr::<T>().shape(()).create(name).map_err(h5err(path, &what))?;
    attr.as_writer().write_scalar(value).map_err(h5err(path, &what))
}

fn put_attr_str(path: &Path, loc: &::hdf5::Location, name: &str, value: &str) -> Result<()> {
    let v = varlen(path, &format!("attribute `{name}`"), value)?;
    put_attr(path, loc, name, &v)
}

/// Opens `sub` below `base`, creating every missing level ("a/b/c" creates a, a/b, a/b/c).
fn open_or_create(path: &Path, base: &::hdf5::Group, sub: &str) -> Result<::hdf5::Group> {
    let parts: Vec<&str> = sub.split('/').filter(|p| !p.is_empty()).collect();
    if parts.is_empty() {
        return Err(Error::input(path.display().to_string(), sub, "group path is empty"));
    }
    let mut g = base.clone();
    for part in parts {
        let what = format!("group `{part}` in `{}`", g.name());
        g = if g.link_exists(part) {
            g.group(part).map_err(h5err(path, &what))?
        } else {
            // Without timestamps, identical results give byte-identical files.
            g.create_group_builder().obj_track_times(false).create(part).map_err(h5err(path, &what))?
        };
    }
    Ok(g)
}

/// A results file being written. Nothing appears at the destination until
/// [`finish`](Self::finish) succeeds; dropping it unfinished deletes the temporary file.
pub struct ResultsFile {
    // Field order matters: the HDF5 file must be closed before `pending` deletes it.
    file: Option<::hdf5::File>,
    pending: Option<PendingFile>,
    path: PathBuf,
}

impl ResultsFile {
    /// Starts a results file that will become `path` (parent directories are created).
    pub fn create(path: impl AsRef<Path>) -> Result<Self> {
        let path = path.as_ref().to_path_buf();
        let pending = PendingFile::new(&path)?;
        // No HDF5 file lock: the library opens without close-on-exec, so a process another
        // thread spawns would inherit the descriptor and hold the lock after we close; the
        // temporary file is ours alone, so the lock would protect nothing.
        let file = ::hdf5::File::with_options()
            .with_fapl(|p| p.file_locking(false))
            .create(pending.tmp_path())
            .map_err(h5err(&path, "creating file"))?;
        Ok(ResultsFile { file: Some(file), pending: Some(pending), path })
    }

    /// The destination path (where the file will be after `finish`).
    pub fn path(&self) -> &Path {
        &self.path
    }

    fn root(&self) -> &::hdf5::File {
        self.file.as_ref().expect("file is open until finish")
    }

    /// Sets a string attribute on the root group (e.g. `program`, `version`, `case_file`).
    pub fn set_attr_str(&self, name: &str, value: &str) -> Result<()> {
        put_attr_str(&self.path, self.root(), name, value)
    }

    /// Sets a floating-point attribute on the root group.
    pub fn set_attr_f64(&self, name: &str, value: f64) -> Result<()> {
        put_attr(&self.path, self.root(), name, &value)
    }

    /// Sets an integer attribute on the root group.
    pub fn set_attr_i64(&self, name: &str, value: i64) -> Result<()> {
        put_attr(&self.path, self.root(), name, &value)
    }

    /// The root group, for writing a layout through [`GroupSink`].
    pub fn root_group(&self) -> GroupWriter<'_> {
        GroupWriter { group: (**self.root()).clone(), path: &self.path }
    }

    /// Opens or creates the group at `path` (slash-separated, relative to the root, e.g.
    /// `"transient/actuator_0"`), creating intermediate groups.
    pub fn group(&self, path: &str) -> Result<GroupWriter<'_>> {
        let group = open_or_create(&self.path, self.root(), path)?;
        Ok(GroupWriter { group, path: &self.path })
    }

    /// Closes the file, flushes it to disk and renames it to its destination.
    pub fn finish(mut self) -> Result<()> {
        let file = self.file.take().expect("file is open until finish");
        file.flush().map_err(h5err(&self.path, "flushing file"))?;
        file.close().map_err(h5err(&self.path, "closing file"))?;
        self.pending.take().expect("pending until finish").commit()
    }
}

impl std::fmt::Debug for ResultsFile {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("ResultsFile").field("path", &self.path).finish_non_exhaustive()
    }
}

/// Writes datasets and attributes into one group of a [`ResultsFile`]. Borrows the file,
/// so the compiler guarantees all writers are gone before `finish`.
pub struct GroupWriter<'f> {
    group: ::hdf5::Group,
    path: &'f Path,
}

impl<'f> GroupWriter<'f> {
    /// Opens or creates a subgroup (slash-separated path relative to this group).
    pub fn group(&self, sub: &str) -> Result<GroupWriter<'f>> {
        let group = open_or_create(self.path, &self.group, sub)?;
        Ok(GroupWriter { group, path: self.path })
    }

    /// Full path of this group inside the file, e.g. `/transient/actuator_0`.
    pub fn name(&self) -> String {
        self.group.name()
    }

    /// Full path of a new dataset `name`, after checking that the name is a plain name
    /// and not taken (HDF5 itself only says "unknown library error" for a duplicate).
    fn new_dataset_path(&self, name: &str) -> Result<String> {
        let full = format!("{}/{name}", self.group.name().trim_end_matches('/'));
        check_name(&self.path.display().to_string(), &full, name)?;
        if self.group.link_exists(name) {
            return Err(Error::Hdf5 {
                path: self.path.display().to_string(),
                message: format!("`{full}` already exists"),
            });
        }
        Ok(full)
    }

    /// Sets a string attribute on this group.
    pub fn attr_str(&self, name: &str, value: &str) -> Result<()> {
        put_attr_str(self.path, &self.group, name, value)
    }

    /// Sets a floating-point attribute on this group.
    pub fn attr_f64(&self, name: &str, value: f64) -> Result<()> {
        put_attr(self.path, &self.group, name, &value)
    }

    /// Sets an integer attribute on this group.
    pub fn attr_i64(&self, name: &str, value: i64) -> Result<()> {
        put_attr(self.path, &self.group, name, &value)
    }

    /// Writes a real array. `shape` is `[n]` or `[rows, cols]` (row-major) and its product
    /// must equal `data.len()`. `unit` is the SI unit (`"1"` if dimensionless).
    pub fn write_f64(&self, name: &str, data: &[f64], shape: &[usize], unit: &str, description: &str) -> Result<()> {
        self.write_numeric(name, data, shape, unit, description)
    }

    /// Writes a complex array as compound `{r, i}` (h5py: `complex128`); shape as in
    /// [`write_f64`](Self::write_f64).
    pub fn write_c64(
        &self,
        name: &str,
        data: &[Complex64],
        shape: &[usize],
        unit: &str,
        description: &str,
    ) -> Result<()> {
        let packed: Vec<H5Complex> = data.iter().map(|c| H5Complex { r: c.re, i: c.im }).collect();
        self.write_numeric(name, &packed, shape, unit, description)
    }

    /// Writes an integer array (counts, indices, node numbers); shape as in
    /// [`write_f64`](Self::write_f64).
    pub fn write_i64(&self, name: &str, data: &[i64], shape: &[usize], unit: &str, description: &str) -> Result<()> {
        self.write_numeric(name, data, shape, unit, description)
    }

    fn write_numeric<T: H5Type>(
        &self,
        name: &str,
        data: &[T],
        shape: &[usize],
        unit: &str,
        description: &str,
    ) -> Result<()> {
        let full = self.new_dataset_path(name)?;
        check_shape(&self.path.display().to_string(), &full, shape, data.len())?;
        let what = format!("dataset `{full}`");
        let ds = self.group.new_dataset::<T>().shape(shape.to_vec()).create(name).map_err(h5err(self.path, &what))?;
        ds.as_writer().write_raw(data).map_err(h5err(self.path, &what))?;
        put_attr_str(self.path, &ds, "unit", unit)?;
        put_attr_str(self.path, &ds, "description", description)
    }

    /// Writes a scalar UTF-8 text dataset (used for the embedded case file, `/case/toml`).
    /// Text datasets carry no `unit`/`description` attributes.
    pub fn write_str(&self, name: &str, value: &str) -> Result<()> {
        let what = format!("dataset `{}`", self.new_dataset_path(name)?);
        let v = varlen(self.path, &what, value)?;
        let ds = self.group.new_dataset::<VarLenUnicode>().shape(()).create(name).map_err(h5err(self.path, &what))?;
        ds.as_writer().write_scalar(&v).map_err(h5err(self.path, &what))
    }

    /// Writes a 1-D array of UTF-8 strings (e.g. actuator or case names of a sweep).
    pub fn write_str_list(&self, name: &str, values: &[String]) -> Result<()> {
        let what = format!("dataset `{}`", self.new_dataset_path(name)?);
        let v = values.iter().map(|s| varlen(self.path, &what, s)).collect::<Result<Vec<_>>>()?;
        let ds =
            self.group.new_dataset::<VarLenUnicode>().shape([v.len()]).create(name).map_err(h5err(self.path, &what))?;
        ds.as_writer().write_raw(&v).map_err(h5err(self.path, &what))
    }
}

impl GroupSink for GroupWriter<'_> {
    fn group(&self, sub: &str) -> Result<Self> {
        GroupWriter::group(self, sub)
    }
    fn attr_str(&self, name: &str, value: &str) -> Result<()> {
        GroupWriter::attr_str(self, name, value)
    }
    fn attr_f64(&self, name: &str, value: f64) -> Result<()> {
        GroupWriter::attr_f64(self, name, value)
    }
    fn attr_i64(&self, name: &str, value: i64) -> Result<()> {
        GroupWriter::attr_i64(self, name, value)
    }
    fn write_f64(&self, name: &str, data: &[f64], shape: &[usize], unit: &str, description: &str) -> Result<()> {
        GroupWriter::write_f64(self, name, data, shape, unit, description)
    }
    fn write_c64(&self, name: &str, data: &[Complex64], shape: &[usize], unit: &str, description: &str) -> Result<()> {
        GroupWriter::write_c64(self, name, data, shape, unit, description)
    }
    fn write_i64(&self, name: &str, data: &[i64], shape: &[usize], unit: &str, description: &str) -> Result<()> {
        GroupWriter::write_i64(self, name, data, shape, unit, description)
    }
    fn write_str(&self, name: &str, value: &str) -> Result<()> {
        GroupWriter::write_str(self, name, value)
    }
    fn write_str_list(&self, name: &str, values: &[String]) -> Result<()> {
        GroupWriter::write_str_list(self, name, values)
    }
}

/// Read access to a results file (tests, merging sweep shards). Dataset and object paths
/// are absolute or relative to the root, e.g. `"transient/actuator_0/force"`.
pub struct ResultsReader {
    file: ::hdf5::File,
    path: PathBuf,
}

impl std::fmt::Debug for ResultsReader {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("ResultsReader").field("path", &self.path).finish_non_exhaustive()
    }
}

impl ResultsReader {
    /// Opens an existing file read-only.
    pub fn open(path: impl AsRef<Path>) -> Result<Self> {
        let path = path.as_ref().to_path_buf();
        // Report a missing file as the plain I/O error it is, not an HDF5 stack; refuse a
        // FIFO or device before the HDF5 library opens (and blocks on) it.
        crate::input_file::regular_file(&path)?;
        // No lock to take (see `ResultsFile::create`): a reader never writes.
        let file = ::hdf5::File::with_options()
            .with_fapl(|p| p.file_locking(false))
            .open(&path)
            .map_err(h5err(&path, "opening file"))?;
        Ok(ResultsReader { file, path })
    }

    /// The file being read.
    pub fn path(&self) -> &Path {
        &self.path
    }

    fn dataset(&self, name: &str) -> Result<::hdf5::Dataset> {
        if !self.exists(name) {
            return Err(Error::Hdf5 { path: self.path.display().to_string(), message: format!("no dataset `{name}`") });
        }
        self.file.dataset(name).map_err(h5err(&self.path, format!("opening dataset `{name}`")))
    }

    fn read_numeric<T: H5Type>(&self, name: &str) -> Result<(Vec<T>, Vec<usize>)> {
        let ds = self.dataset(name)?;
        let data = ds.read_raw::<T>().map_err(h5err(&self.path, format!("reading dataset `{name}`")))?;
        Ok((data, ds.shape()))
    }

    /// Reads a real dataset and its shape (integer datasets are converted).
    pub fn read_f64(&self, name: &str) -> Result<(Vec<f64>, Vec<usize>)> {
        self.read_numeric(name)
    }

    /// Reads a complex dataset (compound with fields `r` and `i`) and its shape.
    pub fn read_c64(&self, name: &str) -> Result<(Vec<Complex64>, Vec<usize>)> {
        let (data, shape) = self.read_numeric::<H5Complex>(name)?;
        Ok((data.into_iter().map(|c| Complex64::new(c.r, c.i)).collect(), shape))
    }

    /// Reads an integer dataset and its shape.
    pub fn read_i64(&self, name: &str) -> Result<(Vec<i64>, Vec<usize>)> {
        self.read_numeric(name)
    }

    /// Reads a scalar text dataset.
    pub fn read_str(&self, name: &str) -> Result<String> {
        let ds = self.dataset(name)?;
        let r = ds.as_reader();
        r.read_scalar::<VarLenUnicode>()
            .map(|s| s.as_str().to_owned())
            .or_else(|_| r.read_scalar::<VarLenAscii>().map(|s| s.as_str().to_owned()))
            .map_err(h5err(&self.path, format!("reading text dataset `{name}`")))
    }

    /// Reads a 1-D array of strings.
    pub fn read_str_list(&self, name: &str) -> Result<Vec<String>> {
        let ds = self.dataset(name)?;
        let v = ds.read_raw::<VarLenUnicode>().map_err(h5err(&self.path, format!("reading text dataset `{name}`")))?;
        Ok(v.iter().map(|s| s.as_str().to_owned()).collect())
    }

    /// Opens a group or dataset as a location for attribute access (`"/"` is the root).
    fn location(&self, obj: &str) -> Result<::hdf5::Location> {
        let what = format!("opening object `{obj}`");
        if obj.trim_matches('/').is_empty() {
            return Ok((**self.file).clone());
        }
        if !self.exists(obj) {
            return Err(Error::Hdf5 { path: self.path.display().to_string(), message: format!("no object `{obj}`") });
        }
        match self.file.group(obj) {
            Ok(g) => Ok((*g).clone()),
            Err(_) => self.file.dataset(obj).map(|d| (**d).clone()).map_err(h5err(&self.path, what)),
        }
    }

    fn read_attr<T: H5Type>(&self, obj: &str, name: &str) -> Result<T> {
        let what = format!("attribute `{name}` of `{obj}`");
        let attr = self.location(obj)?.attr(name).map_err(h5err(&self.path, &what))?;
        attr.as_reader().read_scalar::<T>().map_err(h5err(&self.path, &what))
    }

    /// Reads a string attribute of the object at `obj` (`"/"` for the root).
    pub fn attr_str(&self, obj: &str, name: &str) -> Result<String> {
        let what = format!("attribute `{name}` of `{obj}`");
        let attr = self.location(obj)?.attr(name).map_err(h5err(&self.path, &what))?;
        let r = attr.as_reader();
        r.read_scalar::<VarLenUnicode>()
            .map(|s| s.as_str().to_owned())
            .or_else(|_| r.read_scalar::<VarLenAscii>().map(|s| s.as_str().to_owned()))
            .map_err(h5err(&self.path, &what))
    }

    /// Reads a floating-point attribute.
    pub fn attr_f64(&self, obj: &str, name: &str) -> Result<f64> {
        self.read_attr(obj, name)
    }

    /// Reads an integer attribute.
    pub fn attr_i64(&self, obj: &str, name: &str) -> Result<i64> {
        self.read_attr(obj, name)
    }

    fn open_group(&self, group: &str) -> Result<::hdf5::Group> {
        let g = if group.trim_matches('/').is_empty() { "/" } else { group };
        if g != "/" && !self.exists(g) {
            return Err(Error::Hdf5 { path: self.path.display().to_string(), message: format!("no group `{group}`") });
        }
        self.file.group(g).map_err(h5err(&self.path, format!("opening group `{group}`")))
    }

    fn basenames(names: impl Iterator<Item = String>) -> Vec<String> {
        let mut v: Vec<String> = names.map(|n| n.rsplit('/').next().unwrap_or_default().to_owned()).collect();
        v.sort();
        v
    }

    /// Names (not paths) of the subgroups of `group`, sorted.
    pub fn list_groups(&self, group: &str) -> Result<Vec<String>> {
        let g = self.open_group(group)?;
        let subs = g.groups().map_err(h5err(&self.path, format!("listing group `{group}`")))?;
        Ok(Self::basenames(subs.iter().map(|s| s.name())))
    }

    /// Names (not paths) of the datasets directly in `group`, sorted.
    pub fn list_datasets(&self, group: &str) -> Result<Vec<String>> {
        let g = self.open_group(group)?;
        let ds = g.datasets().map_err(h5err(&self.path, format!("listing group `{group}`")))?;
        Ok(Self::basenames(ds.iter().map(|d| d.name())))
    }

    /// The whole file as an in-memory tree (attributes, groups, datasets with their unit
    /// and description), the form [`super::tree::TreeSink`] builds for a run.
    pub fn read_tree(&self) -> Result<Group> {
        self.read_group("/")
    }

    fn read_group(&self, path: &str) -> Result<Group> {
        let mut g = Group { attrs: self.read_attrs(path)?, ..Default::default() };
        let child = |name: &str| format!("{}/{name}", path.trim_end_matches('/'));
        for name in self.list_datasets(path)? {
            g.datasets.insert(name.clone(), self.read_dataset(&child(&name))?);
        }
        for name in self.list_groups(path)? {
            g.groups.insert(name.clone(), self.read_group(&child(&name))?);
        }
        Ok(g)
    }

    /// Every attribute of an object, typed as stored (text, float, integer).
    fn read_attrs(&self, obj: &str) -> Result<BTreeMap<String, Attr>> {
        let loc = self.location(obj)?;
        let what = format!("attributes of `{obj}`");
        let mut out = BTreeMap::new();
        for name in loc.attr_names().map_err(h5err(&self.path, &what))? {
            let dtype = loc.attr(&name).and_then(|a| a.dtype()).and_then(|t| t.to_descriptor());
            let a = match dtype.map_err(h5err(&self.path, &what))? {
                TypeDescriptor::Float(_) => Attr::F64(self.attr_f64(obj, &name)?),
                TypeDescriptor::Integer(_) | TypeDescriptor::Unsigned(_) => Attr::I64(self.attr_i64(obj, &name)?),
                _ => Attr::Str(self.attr_str(obj, &name)?),
            };
            out.insert(name, a);
        }
        Ok(out)
    }

    /// A dataset as stored: real, complex, integer, text or a list of text; numeric ones
    /// with their `unit` and `description`.
    fn read_dataset(&self, name: &str) -> Result<Dataset> {
        let ds = self.dataset(name)?;
        let what = format!("type of dataset `{name}`");
        let kind = ds.dtype().and_then(|t| t.to_descriptor()).map_err(h5err(&self.path, &what))?;
        let (data, shape) = match kind {
            TypeDescriptor::Float(_) => self.read_f64(name).map(|(v, s)| (Data::F64(v), s))?,
            TypeDescriptor::Integer(_) | TypeDescriptor::Unsigned(_) => {
                self.read_i64(name).map(|(v, s)| (Data::I64(v), s))?
            }
            TypeDescriptor::Compound(_) => self.read_c64(name).map(|(v, s)| (Data::C64(v), s))?,
            _ if ds.ndim() == 0 => (Data::Str(self.read_str(name)?), Vec::new()),
            _ => {
                let v = self.read_str_list(name)?;
                let n = v.len();
                (Data::StrList(v), vec![n])
            }
        };
        let text = |attr: &str| if self.has_attr(name, attr) { self.attr_str(name, attr) } else { Ok(String::new()) };
        Ok(Dataset { data, shape, unit: text("unit")?, description: text("description")? })
    }

    fn has_attr(&self, obj: &str, name: &str) -> bool {
        self.location(obj)
            .and_then(|l| l.attr_names().map_err(h5err(&self.path, "")))
            .is_ok_and(|n| n.iter().any(|a| a == name))
    }

    /// Whether a group or dataset exists at `path`.
    pub fn exists(&self, path: &str) -> bool {
        // Walk level by level: HDF5 reports a missing *intermediate* group as an error,
        // not as "does not exist".
        let mut prefix = String::new();
        for part in path.split('/').filter(|p| !p.is_empty()) {
            prefix.push('/');
            prefix.push_str(part);
            if !self.file.link_exists(&prefix) {
                return false;
            }
        }
        true
    }
}

/// Current UTC time as ISO 8601 (`2024-05-01T12:34:56Z`), for a `created` root attribute.
/// Computed from the system clock without a date library (proleptic Gregorian calendar).
pub fn utc_timestamp() -> String {
    let secs = std::time::SystemTime::now().duration_since(std::time::UNIX_EPOCH).map(|d| d.as_secs()).unwrap_or(0);
    format_utc(secs)
}

fn format_utc(secs: u64) -> String {
    let days = (secs / 86_400) as i64;
    let rem = secs % 86_400;
    // Civil-from-days, after Howard Hinnant's well-known algorithm.
    let z = days + 719_468;
    let era = z.div_euclid(146_097);
    let doe = z - era * 146_097;
    let yoe = (doe - doe / 1_460 + doe / 36_524 - doe / 146_096) / 365;
    let doy = doe - (365 * yoe + yoe / 4 - yoe / 100);
    let mp = (5 * doy + 2) / 153;
    let d = doy - (153 * mp + 2) / 5 + 1;
    let m = if mp < 10 { mp + 3 } else { mp - 9 };
    let y = yoe + era * 400 + i64::from(m <= 2);
    format!("{y:04}-{m:02}-{d:02}T{:02}:{:02}:{:02}Z", rem / 3600, rem % 3600 / 60, rem % 60)
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::process::Command;

    /// The complex compound is what h5py reads as `complex128`: `r` then `i`, two 8-byte
    /// floats in 16 bytes.
    #[test]
    fn complex_compound_is_the_h5py_layout() {
        let TypeDescriptor::Compound(c) = H5Complex::type_descriptor() else { panic!("not a compound") };
        assert_eq!(c.size, 16);
        let fields: Vec<_> = c.fields.iter().map(|f| (f.name.as_str(), f.offset, f.ty.clone())).collect();
        let f64_ty = TypeDescriptor::Float(::hdf5::types::FloatSize::U8);
        assert_eq!(fields, [("r", 0, f64_ty.clone()), ("i", 8, f64_ty)]);
    }

    /// A process spawned while a results file is being written inherits HDF5's descriptor;
    /// the finished file still opens while that process lives.
    #[test]
    fn a_child_process_holding_the_descriptor_does_not_lock_the_file() {
        let dir = tempfile::tempdir().unwrap();
        let p = dir.path().join("r.h5");
        let f = ResultsFile::create(&p).unwrap();
        f.set_attr_str("program", "beamflow").unwrap();
        let mut child = Command::new("sleep").arg("5").spawn().unwrap();
        f.finish().unwrap();
        let opened = ResultsReader::open(&p).map(|_| ());
        child.kill().ok();
        child.wait().ok();
        opened.unwrap();
    }

    fn sample(path: &Path) {
        let f = ResultsFile::create(path).unwrap();
        f.set_attr_str("program", "beamflow").unwrap();
        f.set_attr_str("version", "0.1.0").unwrap();
        f.set_attr_f64("sample_rate", 48_000.0).unwrap();
        f.set_attr_i64("n_actuators", 2).unwrap();
        f.set_attr_i64("n_actuators", 3).unwrap(); // replacing is allowed
        f.group("case").unwrap().write_str("toml", "[beam]\nlength = 1.5 # m\nname = \"ä\"\n").unwrap();
        let g = f.group("transient/actuator_0").unwrap();
        g.attr_str("label", "left").unwrap();
        g.attr_f64("position", 0.25).unwrap();
        g.attr_i64("node", 12).unwrap();
        g.write_f64("time", &[0.0, 0.5, 1.0], &[3], "s", "sample times").unwrap();
        g.write_f64("field", &[1.0, 2.0, 3.0, 4.0, 5.0, 6.0], &[2, 3], "m", "displacement, node x time").unwrap();
        g.write_c64(
            "mobility",
            &[Complex64::new(1.5, -2.0), Complex64::new(0.0, 3.25)],
            &[2],
            "m/(N s)",
            "point mobility",
        )
        .unwrap();
        g.write_i64("nodes", &[1, -2, 3], &[3], "1", "node indices").unwrap();
        g.write_f64("empty", &[], &[0], "W", "nothing").unwrap();
        g.group("deeper/still").unwrap().write_str_list("names", &["a".into(), "bé".into()]).unwrap();
        // Re-opening an existing group works and keeps its content.
        f.group("transient").unwrap().attr_str("kind", "time domain").unwrap();
        drop(g);
        f.finish().unwrap();
    }

    #[test]
    fn round_trip_through_reader() {
        let dir = tempfile::tempdir().unwrap();
        let p = dir.path().join("run.h5");
        sample(&p);
        let r = ResultsReader::open(&p).unwrap();
        assert_eq!(r.attr_str("/", "program").unwrap(), "beamflow");
        assert_eq!(r.attr_f64("/", "sample_rate").unwrap(), 48_000.0);
        assert_eq!(r.attr_i64("/", "n_actuators").unwrap(), 3);
        assert!(r.read_str("/case/toml").unwrap().contains("name = \"ä\""));
        assert_eq!(r.read_f64("transient/actuator_0/time").unwrap(), (vec![0.0, 0.5, 1.0], vec![3]));
        assert_eq!(r.read_f64("transient/actuator_0/field").unwrap().1, vec![2, 3]);
        assert_eq!(r.read_f64("transient/actuator_0/field").unwrap().0[4], 5.0);
        let (c, s) = r.read_c64("transient/actuator_0/mobility").unwrap();
        assert_eq!((c, s), (vec![Complex64::new(1.5, -2.0), Complex64::new(0.0, 3.25)], vec![2]));
        assert_eq!(r.read_i64("transient/actuator_0/nodes").unwrap().0, vec![1, -2, 3]);
        assert_eq!(r.read_f64("transient/actuator_0/nodes").unwrap().0, vec![1.0, -2.0, 3.0]);
        assert_eq!(r.read_f64("transient/actuator_0/empty").unwrap(), (vec![], vec![0]));
        assert_eq!(r.attr_str("transient/actuator_0/time", "unit").unwrap(), "s");
        assert_eq!(r.attr_str("transient/actuator_0/mobility", "description").unwrap(), "point mobility");
        assert_eq!(r.attr_str("transient/actuator_0/nodes", "unit").unwrap(), "1");
        assert_eq!(r.attr_str("transient/actuator_0", "label").unwrap(), "left");
        assert_eq!(r.attr_f64("transient/actuator_0", "position").unwrap(), 0.25);
        assert_eq!(r.attr_i64("transient/actuator_0", "node").unwrap(), 12);
        assert_eq!(r.attr_str("transient", "kind").unwrap(), "time domain");
        assert_eq!(r.read_str_list("transient/actuator_0/deeper/still/names").unwrap(), vec!["a", "bé"]);
        assert_eq!(r.list_groups("/").unwrap(), vec!["case", "transient"]);
        assert_eq!(r.list_groups("transient").unwrap(), vec!["actuator_0"]);
        assert_eq!(
            r.list_datasets("/transient/actuator_0").unwrap(),
            vec!["empty", "field", "mobility", "nodes", "time"]
        );
        assert!(r.exists("/transient/actuator_0/time") && r.exists("transient") && r.exists("/"));
        assert!(!r.exists("/transient/nope/time") && !r.exists("nope"));

        // Errors name the file and the object.
        let e = r.read_f64("/transient/nope").unwrap_err().to_string();
        assert!(e.contains("run.h5") && e.contains("/transient/nope"), "{e}");
        let e = r.attr_str("/transient/actuator_0", "missing").unwrap_err().to_string();
        assert!(e.contains("run.h5") && e.contains("missing"), "{e}");
        let e = r.read_c64("/transient/actuator_0/time").unwrap_err().to_string();
        assert!(e.contains("run.h5"), "{e}");
        let e = ResultsReader::open(dir.path().join("absent.h5")).unwrap_err().to_string();
        assert!(e.contains("absent.h5"), "{e}");
    }

    #[test]
    fn rejects_bad_shapes_and_duplicates() {
        let dir = tempfile::tempdir().unwrap();
        let p = dir.path().join("bad.h5");
        let f = ResultsFile::create(&p).unwrap();
        let g = f.group("g").unwrap();
        let e = g.write_f64("x", &[1.0, 2.0], &[3], "m", "").unwrap_err().to_string();
        assert!(e.contains("bad.h5") && e.contains("/g/x") && e.contains("3 values"), "{e}");
        assert!(g.write_f64("x", &[1.0], &[1, 1, 1], "m", "").is_err());
        assert!(g.write_f64("x", &[1.0], &[], "m", "").is_err());
        g.write_f64("x", &[1.0], &[1], "m", "").unwrap();
        g.write_str_list("none", &[]).unwrap();
        let e = g.write_f64("x", &[1.0], &[1], "m", "").unwrap_err();
        assert!(matches!(e, Error::Hdf5 { .. }) && e.to_string().contains("bad.h5"), "{e}");
        assert!(e.to_string().contains("`/g/x` already exists"), "{e}");
        assert!(g.write_str("toml", "a").is_ok() && g.write_str("toml", "b").is_err());
        assert!(g.write_f64("a/b", &[1.0], &[1], "m", "").is_err());
        assert!(f.group("").is_err() && f.group("//").is_err());
        drop(g);
        f.finish().unwrap();
        assert!(p.exists());
    }

    #[test]
    fn dropped_writer_leaves_nothing() {
        let dir = tempfile::tempdir().unwrap();
        let p = dir.path().join("sub/never.h5");
        {
            let f = ResultsFile::create(&p).unwrap();
            f.group("a").unwrap().write_f64("x", &[1.0], &[1], "1", "").unwrap();
            assert!(!p.exists(), "destination must not exist before finish");
        }
        assert!(!p.exists());
        let left: Vec<_> = std::fs::read_dir(dir.path().join("sub")).unwrap().collect();
        assert!(left.is_empty(), "temporary file left behind: {left:?}");
    }

    #[test]
    fn standard_hdf5_per_h5dump() {
        let Ok(out) = Command::new("h5dump").arg("--version").output() else {
            eprintln!("NOTICE: h5dump not on PATH; skipping the outside-reader check (install hdf5-tools)");
            return;
        };
        assert!(out.status.success());
        let dir = tempfile::tempdir().unwrap();
        let p = dir.path().join("run.h5");
        sample(&p);
        let out = Command::new("h5dump").arg(&p).output().unwrap();
        let text = String::from_utf8_lossy(&out.stdout);
        assert!(out.status.success(), "h5dump failed: {}", String::from_utf8_lossy(&out.stderr));
        for needle in [
            "GROUP \"/\"",
            "ATTRIBUTE \"program\"",
            "\"beamflow\"",
            "GROUP \"transient\"",
            "DATASET \"time\"",
            "H5T_IEEE_F64LE",
            "DATASPACE  SIMPLE { ( 2, 3 ) / ( 2, 3 ) }",
            "H5T_COMPOUND",
            "\"r\"",
            "\"i\"",
            "H5T_STD_I64LE",
            "ATTRIBUTE \"unit\"",
            "\"m/(N s)\"",
            "CSET H5T_CSET_UTF8",
            "DATASET \"toml\"",
            "length = 1.5",
        ] {
            assert!(text.contains(needle), "h5dump output lacks {needle:?}:\n{text}");
        }
        // A single value, read the way a user would check one number.
        let out = Command::new("h5dump")
            .args(["-d", "/transient/actuator_0/mobility", "-m", "%.4f"])
            .arg(&p)
            .output()
            .unwrap();
        let text = String::from_utf8_lossy(&out.stdout);
        assert!(text.contains("1.5000") && text.contains("-2.0000") && text.contains("3.2500"), "{text}");
    }

    #[test]
    fn timestamps() {
        assert_eq!(format_utc(0), "1970-01-01T00:00:00Z");
        assert_eq!(format_utc(951_782_400), "2000-02-29T00:00:00Z");
        assert_eq!(format_utc(1_714_566_896), "2024-05-01T12:34:56Z");
        assert_eq!(utc_timestamp().len(), 20);
    }
}
