//! A run's output files committed as a set.
//!
//! Each file is already written atomically ([`super::atomic`]), but a run writes several
//! (HDF5, JSON, figures, matrices): a run killed between two of them would leave a new HDF5
//! file beside the previous run's JSON. So the files are first written into a staging
//! folder inside the output folder (`.staging-<pid>-<n>`, same file system, so a rename is
//! atomic), a `COMMIT` marker is written there once the last one is complete, and only then
//! are they renamed into place.
//!
//! The next run in the same folder recovers what a killed one left: a staging folder whose
//! process is gone is rolled forward if it holds the marker (its set was complete; the
//! renames are finished) and removed otherwise (the set never became visible). Stray
//! temporary files of dead processes (`.<name>.tmp-<pid>-…`) are removed too.

use std::fs;
use std::path::{Path, PathBuf};

use crate::error::{Error, Result};

const MARKER: &str = "COMMIT";
const PREFIX: &str = ".staging-";

/// The staging folder of one run's outputs.
#[derive(Debug)]
pub struct OutputSet {
    dest: PathBuf,
    staging: PathBuf,
    committed: bool,
}

impl OutputSet {
    /// Creates `dest` if needed, recovers what killed runs left there, and opens a fresh
    /// staging folder.
    pub fn begin(dest: &Path) -> Result<Self> {
        fs::create_dir_all(dest).map_err(|e| Error::io(dest, e))?;
        recover(dest)?;
        let pid = std::process::id();
        for n in 0..1000u32 {
            let staging = dest.join(format!("{PREFIX}{pid}-{n}"));
            match fs::create_dir(&staging) {
                Ok(()) => return Ok(OutputSet { dest: dest.to_path_buf(), staging, committed: false }),
                Err(e) if e.kind() == std::io::ErrorKind::AlreadyExists => continue,
                Err(e) => return Err(Error::io(&staging, e)),
            }
        }
        Err(Error::io(dest, std::io::Error::other("no free staging folder name")))
    }

    /// Where the run writes its files (they become visible in [`Self::dest`] on commit).
    pub fn dir(&self) -> &Path {
        &self.staging
    }

    /// The output folder.
    pub fn dest(&self) -> &Path {
        &self.dest
    }

    /// The final path of a file written as `staged` inside [`Self::dir`].
    pub fn final_path(&self, staged: &Path) -> PathBuf {
        staged.strip_prefix(&self.staging).map(|rel| self.dest.join(rel)).unwrap_or_else(|_| staged.to_path_buf())
    }

    /// Marks the set complete and moves every file into the output folder.
    pub fn commit(mut self) -> Result<()> {
        let marker = self.staging.join(MARKER);
        fs::write(&marker, b"").map_err(|e| Error::io(&marker, e))?;
        if let Ok(f) = fs::File::open(&self.staging) {
            let _ = f.sync_all();
        }
        roll_forward(&self.staging, &self.dest)?;
        self.committed = true;
        Ok(())
    }
}

impl Drop for OutputSet {
    /// A set that was not committed (an error, a panic) never becomes visible.
    fn drop(&mut self) {
        if !self.committed {
            let _ = fs::remove_dir_all(&self.staging);
        }
    }
}

/// Moves the files of a complete staging folder into `dest` and removes the folder.
fn roll_forward(staging: &Path, dest: &Path) -> Result<()> {
    let entries = fs::read_dir(staging).map_err(|e| Error::io(staging, e))?;
    for entry in entries {
        let entry = entry.map_err(|e| Error::io(staging, e))?;
        let name = entry.file_name();
        if name == MARKER || name.to_string_lossy().contains(".tmp-") {
            continue;
        }
        let to = dest.join(&name);
        fs::rename(entry.path(), &to).map_err(|e| Error::io(&to, e))?;
    }
    fs::remove_dir_all(staging).map_err(|e| Error::io(staging, e))
}

/// Whether the process that named a staging folder or temporary file is gone.
fn dead(pid: &str) -> bool {
    match pid.parse::<u32>() {
        Ok(p) if p == std::process::id() => false,
        Ok(p) => !Path::new(&format!("/proc/{p}")).exists(),
        Err(_) => false,
    }
}

/// Finishes or removes what killed runs left in `dest`.
pub fn recover(dest: &Path) -> Result<()> {
    let Ok(entries) = fs::read_dir(dest) else { return Ok(()) };
    for entry in entries.flatten() {
        let name = entry.file_name().to_string_lossy().into_owned();
        let path = entry.path();
        if let Some(rest) = name.strip_prefix(PREFIX) {
            if dead(rest.split('-').next().unwrap_or("")) {
                if path.join(MARKER).exists() {
                    roll_forward(&path, dest)?;
                } else {
                    fs::remove_dir_all(&path).map_err(|e| Error::io(&path, e))?;
                }
            }
        } else if let Some((_, after)) = name.split_once(".tmp-") {
            if name.starts_with('.') && dead(after.split('-').next().unwrap_or("")) {
                fs::remove_file(&path).map_err(|e| Error::io(&path, e))?;
            }
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn files_appear_only_on_commit() {
        let dir = tempfile::tempdir().unwrap();
        let out = dir.path().join("out");
        let set = OutputSet::begin(&out).unwrap();
        fs::write(set.dir().join("a.json"), "1").unwrap();
        assert!(!out.join("a.json").exists());
        assert_eq!(set.final_path(&set.dir().join("a.json")), out.join("a.json"));
        set.commit().unwrap();
        assert_eq!(fs::read_to_string(out.join("a.json")).unwrap(), "1");
        assert_eq!(fs::read_dir(&out).unwrap().count(), 1);
        // Dropped without commit: nothing changes.
        let set = OutputSet::begin(&out).unwrap();
        fs::write(set.dir().join("a.json"), "2").unwrap();
        drop(set);
        assert_eq!(fs::read_to_string(out.join("a.json")).unwrap(), "1");
        assert_eq!(fs::read_dir(&out).unwrap().count(), 1);
    }

    #[test]
    fn a_dead_run_is_rolled_forward_if_complete_and_removed_if_not() {
        let dir = tempfile::tempdir().unwrap();
        let out = dir.path();
        // pid 1 is alive (init) on Linux; a pid above the kernel's maximum never is.
        let dead_pid = 4_194_305u32;
        let complete = out.join(format!("{PREFIX}{dead_pid}-0"));
        fs::create_dir_all(&complete).unwrap();
        fs::write(complete.join("x.h5"), "new").unwrap();
        fs::write(complete.join(MARKER), "").unwrap();
        let partial = out.join(format!("{PREFIX}{dead_pid}-1"));
        fs::create_dir_all(&partial).unwrap();
        fs::write(partial.join("y.h5"), "half").unwrap();
        let alive = out.join(format!("{PREFIX}1-0"));
        fs::create_dir_all(&alive).unwrap();
        let stray = out.join(format!(".x.tmp-{dead_pid}-7.h5"));
        fs::write(&stray, "").unwrap();
        recover(out).unwrap();
        assert_eq!(fs::read_to_string(out.join("x.h5")).unwrap(), "new");
        assert!(!complete.exists() && !partial.exists() && !out.join("y.h5").exists() && !stray.exists());
        assert!(alive.exists(), "a running process's staging folder is left alone");
    }
}
