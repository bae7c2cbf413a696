//! A run's output files committed as a set.
//!
//! Each file is already written atomically ([`super::atomic`]), but a run writes several
//! (HDF5, JSON, figures, matrices): a run killed between two of them would leave a new HDF5
//! file beside the previous run's JSON. So the files are first written into a staging
//! folder inside the output folder (`.staging-<pid>-<n>`, same file system, so a rename is
//! atomic), a `COMMIT` marker is written there once the last one is complete, and only then
//! are they renamed into place. The output folder is locked ([`super::lock`]) from the
//! staging folder's creation to its commit.
//!
//! The output folder is the user's: the next run in it touches only what a killed run of
//! this program left there. A staging folder is created exclusively (never an existing
//! entry, never through a link) and marked as ours at once with an owner file naming its
//! process. A staging folder whose process is gone and which carries that mark is rolled
//! forward if it holds the commit marker (its set was complete; the renames are finished)
//! and removed otherwise (the set never became visible; its temporary files go with it).
//! Anything else — a folder or file merely named like ours, a link — is left alone.

use std::fs;
use std::io::Write;
use std::path::{Path, PathBuf};

use super::lock::OutputLock;
use crate::error::{Error, Result};

const MARKER: &str = "COMMIT";
const PREFIX: &str = ".staging-";
/// The owner file of a staging folder: hidden, so never an output name.
const OWNER: &str = ".beamflow-staging";

/// What the owner file of process `pid`'s staging folder holds.
fn owner_text(pid: u32) -> String {
    format!("beamflow staging folder of process {pid}\n")
}

/// The staging folder of one run's outputs.
#[derive(Debug)]
pub struct OutputSet {
    dest: PathBuf,
    staging: PathBuf,
    committed: bool,
    /// Held until the set is committed or dropped (declared last: released last).
    _lock: OutputLock,
}

impl OutputSet {
    /// Creates `dest` if needed, locks it, recovers what killed runs left there, and opens
    /// a fresh staging folder.
    pub fn begin(dest: &Path) -> Result<Self> {
        let lock = OutputLock::folder(dest)?;
        recover(dest)?;
        let staging = create_staging(dest, std::process::id())?;
        Ok(OutputSet { dest: dest.to_path_buf(), staging, committed: false, _lock: lock })
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

/// Creates a fresh staging folder of process `pid` in `dest`, marked with its owner file.
fn create_staging(dest: &Path, pid: u32) -> Result<PathBuf> {
    for n in 0..1000u32 {
        let staging = dest.join(format!("{PREFIX}{pid}-{n}"));
        // `create_dir` fails on any existing entry (a link too) and never follows one.
        match fs::create_dir(&staging) {
            Ok(()) => {
                let owner = staging.join(OWNER);
                let marked = fs::OpenOptions::new()
                    .write(true)
                    .create_new(true)
                    .open(&owner)
                    .and_then(|mut f| f.write_all(owner_text(pid).as_bytes()));
                if let Err(e) = marked {
                    let _ = fs::remove_dir_all(&staging);
                    return Err(Error::io(&owner, e));
                }
                return Ok(staging);
            }
            Err(e) if e.kind() == std::io::ErrorKind::AlreadyExists => continue,
            Err(e) => return Err(Error::io(&staging, e)),
        }
    }
    Err(Error::io(dest, std::io::Error::other("no free staging folder name")))
}

/// Moves the files of a complete staging folder into `dest` and removes the folder (with
/// its owner file, commit marker and any temporary file: hidden names are never outputs).
fn roll_forward(staging: &Path, dest: &Path) -> Result<()> {
    let entries = fs::read_dir(staging).map_err(|e| Error::io(staging, e))?;
    for entry in entries {
        let entry = entry.map_err(|e| Error::io(staging, e))?;
        let name = entry.file_name();
        if name == MARKER || name.to_string_lossy().starts_with('.') {
            continue;
        }
        let to = dest.join(&name);
        fs::rename(entry.path(), &to).map_err(|e| Error::io(&to, e))?;
    }
    fs::remove_dir_all(staging).map_err(|e| Error::io(staging, e))
}

/// Whether process `pid` is gone.
fn dead(pid: u32) -> bool {
    pid != std::process::id() && !Path::new(&format!("/proc/{pid}")).exists()
}

/// The process of `path` (named `name`) if it is a staging folder this program made: a
/// real folder (not a link) named `.staging-<pid>-<n>` whose owner file names that
/// process. None for anything else.
fn staging_owner(path: &Path, name: &str) -> Option<u32> {
    let (pid, n) = name.strip_prefix(PREFIX)?.split_once('-')?;
    let digits = |s: &str| !s.is_empty() && s.bytes().all(|b| b.is_ascii_digit());
    if !digits(pid) || !digits(n) {
        return None;
    }
    let pid: u32 = pid.parse().ok()?;
    if !fs::symlink_metadata(path).ok()?.is_dir() {
        return None;
    }
    let owner = path.join(OWNER);
    if !fs::symlink_metadata(&owner).ok()?.is_file() {
        return None;
    }
    let text = crate::input_file::read_text_limited(&owner, 128).ok()?;
    (text == owner_text(pid)).then_some(pid)
}

/// Finishes or removes the staging folders killed runs of this program left in `dest`;
/// everything else there is left alone.
pub fn recover(dest: &Path) -> Result<()> {
    let Ok(entries) = fs::read_dir(dest) else { return Ok(()) };
    for entry in entries.flatten() {
        let path = entry.path();
        let Some(pid) = staging_owner(&path, &entry.file_name().to_string_lossy()) else { continue };
        if !dead(pid) {
            continue;
        }
        if fs::symlink_metadata(path.join(MARKER)).is_ok_and(|m| m.is_file()) {
            roll_forward(&path, dest)?;
        } else {
            fs::remove_dir_all(&path).map_err(|e| Error::io(&path, e))?;
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

    // pid 1 is alive (init) on Linux; a pid above the kernel's maximum never is.
    const DEAD: u32 = 4_194_305;

    #[test]
    fn a_dead_runs_marked_folder_is_rolled_forward_if_complete_and_removed_if_not() {
        let dir = tempfile::tempdir().unwrap();
        let out = dir.path();
        let complete = create_staging(out, DEAD).unwrap();
        fs::write(complete.join("x.h5"), "new").unwrap();
        fs::write(complete.join(format!(".x.tmp-{DEAD}-7.h5")), "").unwrap();
        fs::write(complete.join(MARKER), "").unwrap();
        let partial = create_staging(out, DEAD).unwrap();
        fs::write(partial.join("y.h5"), "half").unwrap();
        let alive = create_staging(out, 1).unwrap();
        recover(out).unwrap();
        assert_eq!(fs::read_to_string(out.join("x.h5")).unwrap(), "new");
        assert!(!complete.exists() && !partial.exists() && !out.join("y.h5").exists());
        assert!(alive.exists(), "a running process's staging folder is left alone");
        let mut left: Vec<_> = fs::read_dir(out).unwrap().map(|e| e.unwrap().file_name()).collect();
        left.sort();
        assert_eq!(left, [alive.file_name().unwrap(), "x.h5".as_ref()]);
    }

    #[test]
    fn what_only_looks_like_ours_is_left_alone() {
        let dir = tempfile::tempdir().unwrap();
        let out = dir.path().join("out");
        fs::create_dir(&out).unwrap();
        // A user's folder and file named like a staging folder and a temporary file.
        let users = out.join(format!("{PREFIX}{DEAD}-0"));
        fs::create_dir(&users).unwrap();
        fs::write(users.join("notes.txt"), "mine").unwrap();
        fs::write(users.join(MARKER), "").unwrap();
        let notes = out.join(format!(".notes.tmp-{DEAD}-1.txt"));
        fs::write(&notes, "mine").unwrap();
        // A forged owner file naming another process.
        let forged = out.join(format!("{PREFIX}{DEAD}-1"));
        fs::create_dir(&forged).unwrap();
        fs::write(forged.join(OWNER), owner_text(DEAD + 1)).unwrap();
        // A link to another folder, marked and committed there.
        let other = create_staging(dir.path(), DEAD).unwrap();
        fs::write(other.join("theirs.h5"), "theirs").unwrap();
        fs::write(other.join(MARKER), "").unwrap();
        let link = out.join(format!("{PREFIX}{DEAD}-2"));
        std::os::unix::fs::symlink(&other, &link).unwrap();
        let set = OutputSet::begin(&out).unwrap();
        fs::write(set.dir().join("r.json"), "1").unwrap();
        set.commit().unwrap();
        assert_eq!(fs::read_to_string(users.join("notes.txt")).unwrap(), "mine");
        assert!(users.join(MARKER).exists() && forged.join(OWNER).exists());
        assert_eq!(fs::read_to_string(&notes).unwrap(), "mine");
        assert!(fs::symlink_metadata(&link).unwrap().is_symlink());
        assert_eq!(fs::read_to_string(other.join("theirs.h5")).unwrap(), "theirs");
        assert!(!out.join("theirs.h5").exists());
        assert_eq!(fs::read_to_string(out.join("r.json")).unwrap(), "1");
        // The four planted entries and the output; the set's staging folder and lock are gone.
        assert_eq!(fs::read_dir(&out).unwrap().count(), 5);
    }
}
