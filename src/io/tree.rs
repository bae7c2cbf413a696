//! A results layout held in memory: groups with attributes, datasets with their shape,
//! unit and description — the same tree as the HDF5 file, without the file.
//!
//! [`TreeSink`] is the [`GroupSink`] that builds it (the Python package's `Results` is this
//! tree), [`Group::write_to`] replays a tree into any sink (an HDF5 file: `to_hdf5`), and
//! [`super::hdf5::ResultsReader::read_tree`] reads a file back into one.

use super::sink::{check_name, check_shape, GroupSink};
use crate::error::{Error, Result};
use num_complex::Complex64;
use std::collections::BTreeMap;
use std::sync::{Arc, Mutex, MutexGuard};

/// A scalar attribute.
#[derive(Clone, Debug, PartialEq)]
pub enum Attr {
    Str(String),
    F64(f64),
    I64(i64),
}

/// The values of a dataset.
#[derive(Clone, Debug, PartialEq)]
pub enum Data {
    F64(Vec<f64>),
    C64(Vec<Complex64>),
    I64(Vec<i64>),
    /// A scalar text dataset (shape `[]`).
    Str(String),
    /// A 1-D array of strings.
    StrList(Vec<String>),
}

/// A dataset: values, shape (row-major), unit and description (empty for text).
#[derive(Clone, Debug, PartialEq)]
pub struct Dataset {
    pub data: Data,
    pub shape: Vec<usize>,
    pub unit: String,
    pub description: String,
}

/// A group: attributes, subgroups and datasets, each by name (sorted, like HDF5 lists them).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Group {
    pub attrs: BTreeMap<String, Attr>,
    pub groups: BTreeMap<String, Group>,
    pub datasets: BTreeMap<String, Dataset>,
}

impl Group {
    /// The subgroup at a slash-separated path (`""` is this group).
    pub fn group(&self, path: &str) -> Option<&Group> {
        path.split('/').filter(|p| !p.is_empty()).try_fold(self, |g, part| g.groups.get(part))
    }

    /// The dataset at a slash-separated path, e.g. `analysis_0_modes/frequencies_hz`.
    pub fn dataset(&self, path: &str) -> Option<&Dataset> {
        let (dir, name) = path.trim_start_matches('/').rsplit_once('/').unwrap_or(("", path));
        self.group(dir)?.datasets.get(name)
    }

    /// Writes this group's attributes, datasets and subgroups into `sink`.
    pub fn write_to<S: GroupSink>(&self, sink: &S) -> Result<()> {
        for (name, a) in &self.attrs {
            match a {
                Attr::Str(v) => sink.attr_str(name, v)?,
                Attr::F64(v) => sink.attr_f64(name, *v)?,
                Attr::I64(v) => sink.attr_i64(name, *v)?,
            }
        }
        for (name, d) in &self.datasets {
            let (s, u, desc) = (&d.shape, &d.unit, &d.description);
            match &d.data {
                Data::F64(v) => sink.write_f64(name, v, s, u, desc)?,
                Data::C64(v) => sink.write_c64(name, v, s, u, desc)?,
                Data::I64(v) => sink.write_i64(name, v, s, u, desc)?,
                Data::Str(v) => sink.write_str(name, v)?,
                Data::StrList(v) => sink.write_str_list(name, v)?,
            }
        }
        for (name, g) in &self.groups {
            g.write_to(&sink.group(name)?)?;
        }
        Ok(())
    }
}

/// Builds a [`Group`] tree through [`GroupSink`]. Cheap to clone: clones are handles to
/// other groups of the same tree.
#[derive(Clone, Debug, Default)]
pub struct TreeSink {
    root: Arc<Mutex<Group>>,
    path: Vec<String>,
}

/// What the tree's messages name as the file.
const LABEL: &str = "<results in memory>";

impl TreeSink {
    /// An empty tree; this handle is its root.
    pub fn new() -> Self {
        TreeSink::default()
    }

    /// The tree built so far.
    pub fn tree(&self) -> Group {
        self.lock().clone()
    }

    fn lock(&self) -> MutexGuard<'_, Group> {
        // A panic while holding the lock leaves a tree that is still consistent data.
        self.root.lock().unwrap_or_else(|p| p.into_inner())
    }

    fn full(&self, name: &str) -> String {
        format!("/{}", self.path.iter().map(String::as_str).chain([name]).collect::<Vec<_>>().join("/"))
    }

    /// Runs `f` on this handle's group (which exists: [`GroupSink::group`] created it).
    fn with<T>(&self, f: impl FnOnce(&mut Group) -> T) -> T {
        let mut root = self.lock();
        let mut g = &mut *root;
        for part in &self.path {
            g = g.groups.entry(part.clone()).or_default();
        }
        f(g)
    }

    fn put(&self, name: &str, data: Data, shape: Vec<usize>, unit: &str, description: &str) -> Result<()> {
        let full = self.full(name);
        check_name(LABEL, &full, name)?;
        self.with(|g| {
            if g.datasets.contains_key(name) || g.groups.contains_key(name) {
                return Err(Error::Hdf5 { path: LABEL.into(), message: format!("`{full}` already exists") });
            }
            g.datasets
                .insert(name.to_string(), Dataset { data, shape, unit: unit.into(), description: description.into() });
            Ok(())
        })
    }

    fn numeric(&self, name: &str, data: Data, len: usize, shape: &[usize], unit: &str, desc: &str) -> Result<()> {
        check_shape(LABEL, &self.full(name), shape, len)?;
        self.put(name, data, shape.to_vec(), unit, desc)
    }

    fn attr(&self, name: &str, value: Attr) -> Result<()> {
        self.with(|g| g.attrs.insert(name.to_string(), value));
        Ok(())
    }
}

impl GroupSink for TreeSink {
    fn group(&self, sub: &str) -> Result<Self> {
        let parts: Vec<String> = sub.split('/').filter(|p| !p.is_empty()).map(str::to_string).collect();
        if parts.is_empty() {
            return Err(Error::input(LABEL, sub, "group path is empty"));
        }
        let mut path = self.path.clone();
        path.extend(parts);
        let child = TreeSink { root: self.root.clone(), path };
        child.with(|_| ());
        Ok(child)
    }
    fn attr_str(&self, name: &str, value: &str) -> Result<()> {
        self.attr(name, Attr::Str(value.to_string()))
    }
    fn attr_f64(&self, name: &str, value: f64) -> Result<()> {
        self.attr(name, Attr::F64(value))
    }
    fn attr_i64(&self, name: &str, value: i64) -> Result<()> {
        self.attr(name, Attr::I64(value))
    }
    fn write_f64(&self, name: &str, data: &[f64], shape: &[usize], unit: &str, description: &str) -> Result<()> {
        self.numeric(name, Data::F64(data.to_vec()), data.len(), shape, unit, description)
    }
    fn write_c64(&self, name: &str, data: &[Complex64], shape: &[usize], unit: &str, description: &str) -> Result<()> {
        self.numeric(name, Data::C64(data.to_vec()), data.len(), shape, unit, description)
    }
    fn write_i64(&self, name: &str, data: &[i64], shape: &[usize], unit: &str, description: &str) -> Result<()> {
        self.numeric(name, Data::I64(data.to_vec()), data.len(), shape, unit, description)
    }
    fn write_str(&self, name: &str, value: &str) -> Result<()> {
        self.put(name, Data::Str(value.to_string()), Vec::new(), "", "")
    }
    fn write_str_list(&self, name: &str, values: &[String]) -> Result<()> {
        self.put(name, Data::StrList(values.to_vec()), vec![values.len()], "", "")
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::io::hdf5::{ResultsFile, ResultsReader};

    fn sample<S: GroupSink>(root: &S) -> Result<()> {
        root.attr_str("program", "beamflow")?;
        root.attr_f64("rate", 0.1)?;
        root.attr_i64("count", -3)?;
        root.group("case")?.write_str("toml", "x = 1 # ä\n")?;
        let g = root.group("a/b")?;
        g.attr_f64("x_m", 0.25)?;
        g.write_f64("m", &[1.0, -0.0, f64::MIN_POSITIVE, 3.5, 1e300, -7.0], &[2, 3], "m", "two rows")?;
        g.write_c64("c", &[Complex64::new(1.0, -2.0)], &[1], "N", "one amplitude")?;
        g.write_i64("i", &[4, -5], &[2], "1", "indices")?;
        g.write_f64("empty", &[], &[0], "W", "nothing")?;
        root.group("a")?.write_str_list("names", &["p".into(), "qé".into()])
    }

    #[test]
    fn tree_equals_the_file_read_back() {
        let t = TreeSink::new();
        sample(&t).unwrap();
        let tree = t.tree();
        assert_eq!(tree.dataset("a/b/m").unwrap().shape, vec![2, 3]);
        assert_eq!(tree.dataset("/case/toml").unwrap().data, Data::Str("x = 1 # ä\n".into()));
        assert_eq!(tree.group("a/b").unwrap().attrs["x_m"], Attr::F64(0.25));

        let dir = tempfile::tempdir().unwrap();
        let p = dir.path().join("t.h5");
        let f = ResultsFile::create(&p).unwrap();
        sample(&f.root_group()).unwrap();
        f.finish().unwrap();
        let read = ResultsReader::open(&p).unwrap().read_tree().unwrap();
        assert_eq!(read, tree);

        // Replaying the tree into a file gives the same tree again.
        let p2 = dir.path().join("t2.h5");
        let f = ResultsFile::create(&p2).unwrap();
        tree.write_to(&f.root_group()).unwrap();
        f.finish().unwrap();
        assert_eq!(ResultsReader::open(&p2).unwrap().read_tree().unwrap(), tree);
    }

    #[test]
    fn tree_rejects_what_the_file_rejects() {
        let t = TreeSink::new();
        let g = t.group("g").unwrap();
        let e = g.write_f64("x", &[1.0, 2.0], &[3], "m", "").unwrap_err().to_string();
        assert!(e.contains("/g/x") && e.contains("3 values"), "{e}");
        assert!(g.write_f64("x", &[1.0], &[1, 1, 1], "m", "").is_err());
        g.write_f64("x", &[1.0], &[1], "m", "").unwrap();
        assert!(g.write_f64("x", &[1.0], &[1], "m", "").unwrap_err().to_string().contains("already exists"));
        assert!(g.write_str("a/b", "").is_err() && t.group("//").is_err());
    }
}
