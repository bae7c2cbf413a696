//! Atomic file replacement: write everything to a temporary file in the destination's
//! directory, flush it to disk, then `rename` it over the destination.
//!
//! Why: a reader (a user, a plotting script, a sweep deciding which runs are already
//! done) must only ever see either the old complete file or the new complete file, never
//! a truncated one. `rename` within one directory is atomic on POSIX file systems, which
//! is also why the temporary file must live beside the destination and not in `/tmp`
//! (a different file system would turn the rename into a copy).

use std::fs;
use std::io::Write;
use std::path::{Path, PathBuf};
use std::time::{SystemTime, UNIX_EPOCH};

use crate::error::{Error, Result};

/// A reserved temporary file that becomes `dest` on [`PendingFile::commit`].
///
/// Dropping it without committing removes the temporary file, so an error (or a panic)
/// anywhere between creation and commit leaves the directory as it was. Use this when
/// the writer must outlive a single closure (e.g. an open HDF5 file); otherwise prefer
/// [`write_atomic`].
#[derive(Debug)]
pub struct PendingFile {
    tmp: PathBuf,
    dest: PathBuf,
    done: bool,
}

impl PendingFile {
    /// Creates the parent directory of `dest` if needed and reserves a fresh, empty
    /// temporary file next to it.
    ///
    /// The temporary name is `.<stem>.tmp-<pid>-<n>[.<ext>]`: hidden, unique per process
    /// (reserved with `create_new`, so concurrent writers never share one), and keeping
    /// the extension because some encoders pick the format from it.
    pub fn new(dest: &Path) -> Result<Self> {
        let name = dest.file_name().ok_or_else(|| Error::input(dest.display().to_string(), "path", "names no file"))?;
        let dir = parent_dir(dest);
        fs::create_dir_all(dir).map_err(|e| Error::io(dir, e))?;

        let name = Path::new(name);
        let stem = name.file_stem().unwrap_or(name.as_os_str()).to_string_lossy();
        let ext = name.extension().map(|e| format!(".{}", e.to_string_lossy())).unwrap_or_default();
        let pid = std::process::id();
        // A time-derived start point keeps names distinct across processes that reuse a
        // pid; `create_new` guarantees uniqueness, the loop only skips names in use.
        let start = SystemTime::now().duration_since(UNIX_EPOCH).map(|d| d.subsec_nanos()).unwrap_or(0);
        let mut last_err = None;
        for attempt in 0..1000u32 {
            let tmp = dir.join(format!(".{stem}.tmp-{pid}-{}{ext}", start.wrapping_add(attempt)));
            match fs::OpenOptions::new().write(true).create_new(true).open(&tmp) {
                Ok(_) => return Ok(PendingFile { tmp, dest: dest.to_path_buf(), done: false }),
                Err(e) if e.kind() == std::io::ErrorKind::AlreadyExists => last_err = Some(e),
                Err(e) => return Err(Error::io(&tmp, e)),
            }
        }
        Err(Error::io(dest, last_err.unwrap_or_else(|| std::io::Error::other("no free temporary name"))))
    }

    /// Where the content must be written before [`commit`](Self::commit).
    pub fn tmp_path(&self) -> &Path {
        &self.tmp
    }

    /// The final destination.
    pub fn dest(&self) -> &Path {
        &self.dest
    }

    /// Flushes the temporary file to disk and renames it over the destination.
    ///
    /// The data is `fsync`ed before the rename so that, after a power loss, the name
    /// cannot point at an empty file; the directory is synced afterwards (best effort)
    /// so that the rename itself is durable.
    pub fn commit(mut self) -> Result<()> {
        let file = fs::File::open(&self.tmp).map_err(|e| Error::io(&self.tmp, e))?;
        file.sync_all().map_err(|e| Error::io(&self.tmp, e))?;
        drop(file);
        fs::rename(&self.tmp, &self.dest).map_err(|e| Error::io(&self.dest, e))?;
        self.done = true;
        // Durability of the directory entry only; the content is already safe, and some
        // file systems refuse to open directories, so a failure here is not an error.
        if let Ok(d) = fs::File::open(parent_dir(&self.dest)) {
            let _ = d.sync_all();
        }
        Ok(())
    }
}

impl Drop for PendingFile {
    fn drop(&mut self) {
        if !self.done {
            let _ = fs::remove_file(&self.tmp);
        }
    }
}

/// The directory holding `path` (`.` for a bare file name).
fn parent_dir(path: &Path) -> &Path {
    match path.parent() {
        Some(p) if !p.as_os_str().is_empty() => p,
        _ => Path::new("."),
    }
}

/// Writes `path` atomically: `write` receives a temporary path in the same directory and
/// must create the complete file there; on success it replaces `path`, on error (or panic)
/// the temporary file is removed and `path` is left untouched.
///
/// Parent directories of `path` are created if missing.
pub fn write_atomic<F>(path: &Path, write: F) -> Result<()>
where
    F: FnOnce(&Path) -> Result<()>,
{
    let pending = PendingFile::new(path)?;
    write(pending.tmp_path())?;
    pending.commit()
}

/// Atomically replaces `path` with `bytes`.
pub fn write_atomic_bytes(path: &Path, bytes: &[u8]) -> Result<()> {
    write_atomic(path, |tmp| {
        let mut f = fs::File::create(tmp).map_err(|e| Error::io(path, e))?;
        f.write_all(bytes).map_err(|e| Error::io(path, e))
    })
}

/// Atomically replaces `path` with the UTF-8 text `text`.
pub fn write_atomic_string(path: &Path, text: &str) -> Result<()> {
    write_atomic_bytes(path, text.as_bytes())
}

#[cfg(test)]
mod tests {
    use super::*;

    fn entries(dir: &Path) -> Vec<String> {
        let mut v: Vec<String> =
            fs::read_dir(dir).unwrap().map(|e| e.unwrap().file_name().to_string_lossy().into_owned()).collect();
        v.sort();
        v
    }

    #[test]
    fn writes_and_replaces_and_creates_parents() {
        let dir = tempfile::tempdir().unwrap();
        let p = dir.path().join("a/b/out.txt");
        write_atomic_string(&p, "first").unwrap();
        assert_eq!(fs::read_to_string(&p).unwrap(), "first");
        write_atomic_bytes(&p, b"second").unwrap();
        assert_eq!(fs::read_to_string(&p).unwrap(), "second");
        assert_eq!(entries(p.parent().unwrap()), vec!["out.txt"]);
    }

    #[test]
    fn failed_write_leaves_old_file_and_no_temp() {
        let dir = tempfile::tempdir().unwrap();
        let p = dir.path().join("keep.txt");
        write_atomic_string(&p, "old").unwrap();
        let err = write_atomic(&p, |tmp| {
            fs::write(tmp, "partial").unwrap();
            Err(Error::Numerical("boom".into()))
        })
        .unwrap_err();
        assert!(err.to_string().contains("boom"));
        assert_eq!(fs::read_to_string(&p).unwrap(), "old");
        assert_eq!(entries(dir.path()), vec!["keep.txt"]);
    }

    #[test]
    fn panicking_writer_leaves_no_temp() {
        let dir = tempfile::tempdir().unwrap();
        let p = dir.path().join("x.bin");
        let r = std::panic::catch_unwind(|| {
            let _ = write_atomic(&p, |_| panic!("writer panicked"));
        });
        assert!(r.is_err());
        assert!(entries(dir.path()).is_empty());
    }

    #[test]
    fn temp_name_is_hidden_unique_and_keeps_extension() {
        let dir = tempfile::tempdir().unwrap();
        let dest = dir.path().join("fig.png");
        let a = PendingFile::new(&dest).unwrap();
        let b = PendingFile::new(&dest).unwrap();
        assert_ne!(a.tmp_path(), b.tmp_path());
        let name = a.tmp_path().file_name().unwrap().to_string_lossy().into_owned();
        assert!(name.starts_with(".fig.tmp-") && name.ends_with(".png"), "{name}");
        assert_eq!(a.tmp_path().parent(), dest.parent());
        drop(a);
        drop(b);
        assert!(entries(dir.path()).is_empty());
    }

    #[test]
    fn bare_file_name_and_error_names_path() {
        let dir = tempfile::tempdir().unwrap();
        // A destination whose parent is a regular file cannot be created.
        let blocker = dir.path().join("file");
        fs::write(&blocker, "x").unwrap();
        let err = write_atomic_string(&blocker.join("sub.txt"), "y").unwrap_err();
        assert!(err.to_string().contains(&blocker.display().to_string()), "{err}");
        assert!(PendingFile::new(Path::new("/")).is_err());
    }
}
