//! One writer at a time per output.
//!
//! Two commands writing the same outputs at once (two identical sweeps, a run and its
//! rerun) would share checkpoints and staging, and one would remove what the other still
//! needs. So every command takes an advisory lock (`flock`) before it writes: on
//! `.beamflow.lock` in its output folder, or for a command whose output is one named file
//! and the files derived from its name (a sweep table with its checkpoints and reports,
//! synthetic records), on `.<file name>.beamflow.lock` beside it, so that the shards of one
//! sweep still run at once into one folder. A second writer waits, saying once for which
//! process, and then finds the outputs as the first left them (a second identical sweep
//! reuses the finished table).
//!
//! A lock file is the program's own: created exclusively, holding a marker line with the
//! creator's process id, and removed by its holder before the lock is let go. A waiter that
//! then gets the lock on the removed file notices that the name no longer leads to it and
//! starts over. A file of that name without the marker is the user's: it is locked as it
//! is, never written or removed; a link or anything but a regular file is refused.

use std::fs;
use std::io::Write;
use std::path::{Path, PathBuf};

use crate::error::{Error, Result};

/// The lock file's name in an output folder.
pub const LOCK_FILE: &str = ".beamflow.lock";
/// The end of the lock file's name beside an output file.
const FILE_LOCK_SUFFIX: &str = ".beamflow.lock";

/// The first line of a lock file this program wrote.
const MAGIC: &str = "beamflow output-folder lock, process ";

/// Holds the lock on one output (a folder, or a file) until dropped.
#[derive(Debug)]
pub struct OutputLock {
    path: PathBuf,
    file: fs::File,
    /// Whether this process wrote the lock file (and removes it on release).
    owned: bool,
}

impl OutputLock {
    /// Creates the output folder `dir` if needed and locks it, waiting while another
    /// process holds it.
    pub fn folder(dir: &Path) -> Result<OutputLock> {
        Self::acquire(dir, dir.join(LOCK_FILE), dir)
    }

    /// Locks the output file `file` (creating its folder if needed): the file, and the files
    /// a command derives from its name beside it.
    pub fn file(file: &Path) -> Result<OutputLock> {
        let dir = match file.parent() {
            Some(p) if !p.as_os_str().is_empty() => p,
            _ => Path::new("."),
        };
        let name = file.file_name().map(|n| format!(".{}{FILE_LOCK_SUFFIX}", n.to_string_lossy()));
        match name.filter(|n| n.len() <= crate::io::paths::FILE_NAME_MAX) {
            Some(n) => Self::acquire(dir, dir.join(n), file),
            // A name too long to carry the suffix: the whole folder is locked instead.
            None => Self::folder(dir),
        }
    }

    /// Locks the lock file `path` in the output folder `dir`, for the output `what`.
    fn acquire(dir: &Path, path: PathBuf, what: &Path) -> Result<OutputLock> {
        fs::create_dir_all(dir).map_err(|e| Error::io(dir, e))?;
        let mut told = false;
        loop {
            let Some((file, created)) = open(&path)? else { continue };
            match file.try_lock() {
                Ok(()) => {}
                Err(fs::TryLockError::WouldBlock) => {
                    if !told {
                        eprintln!("{}: waiting for {}, which is writing it", what.display(), holder(&path));
                        told = true;
                    }
                    file.lock().map_err(|e| Error::io(&path, e))?;
                }
                Err(fs::TryLockError::Error(e)) => return Err(Error::io(&path, e)),
            }
            if !names(&path, &file) {
                continue;
            }
            // Ours but not created now: left by a run killed while it held the lock (a
            // holder that finishes removes its file). Start afresh with a file naming this
            // process; if it cannot be removed, hold it as it is.
            if !created && is_ours(&path) && fs::remove_file(&path).is_ok() {
                continue;
            }
            return Ok(OutputLock { path, file, owned: created });
        }
    }
}

impl Drop for OutputLock {
    /// Removes the lock file while still holding the lock (a waiter then starts over on a
    /// fresh file), unless it is not this process's file.
    fn drop(&mut self) {
        if self.owned && names(&self.path, &self.file) {
            let _ = fs::remove_file(&self.path);
        }
    }
}

/// Opens the lock file at `path`, creating it (with the marker) if absent: the file and
/// whether it was created now; None if it vanished in between (try again).
fn open(path: &Path) -> Result<Option<(fs::File, bool)>> {
    // `create_new` fails on any existing entry, a link included, and never follows one.
    match fs::OpenOptions::new().write(true).create_new(true).open(path) {
        Ok(mut f) => {
            let marker = format!("{MAGIC}{}\n", std::process::id());
            f.write_all(marker.as_bytes()).map_err(|e| Error::io(path, e))?;
            return Ok(Some((f, true)));
        }
        Err(e) if e.kind() == std::io::ErrorKind::AlreadyExists => {}
        Err(e) => return Err(Error::io(path, e)),
    }
    let meta = match fs::symlink_metadata(path) {
        Ok(m) => m,
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => return Ok(None),
        Err(e) => return Err(Error::io(path, e)),
    };
    if !meta.is_file() {
        return Err(Error::io(
            path,
            std::io::Error::other(
                "is not a regular file, so not this program's lock file: remove it, or choose another output folder",
            ),
        ));
    }
    match fs::File::open(path) {
        Ok(f) => Ok(Some((f, false))),
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => Ok(None),
        Err(e) => Err(Error::io(path, e)),
    }
}

/// Whether `path` (not followed if a link) is still the file `file` holds open.
fn names(path: &Path, file: &fs::File) -> bool {
    let (Ok(at), Ok(held)) = (fs::symlink_metadata(path), file.metadata()) else { return false };
    same_inode(&at, &held)
}

#[cfg(unix)]
fn same_inode(a: &fs::Metadata, b: &fs::Metadata) -> bool {
    use std::os::unix::fs::MetadataExt;
    a.dev() == b.dev() && a.ino() == b.ino()
}

#[cfg(not(unix))]
fn same_inode(a: &fs::Metadata, b: &fs::Metadata) -> bool {
    a.is_file() && b.is_file()
}

/// The process id a lock file of this program names.
fn marked_pid(path: &Path) -> Option<u32> {
    let text = crate::input_file::read_text_limited(path, 128).ok()?;
    text.strip_prefix(MAGIC)?.strip_suffix('\n')?.parse().ok()
}

fn is_ours(path: &Path) -> bool {
    marked_pid(path).is_some()
}

/// Who holds the lock, for the waiting line.
fn holder(path: &Path) -> String {
    marked_pid(path).map_or_else(|| "another process".to_string(), |pid| format!("process {pid}"))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_second_holder_waits_and_the_file_goes_with_the_last() {
        let dir = tempfile::tempdir().unwrap();
        let out = dir.path().join("out");
        let first = OutputLock::folder(&out).unwrap();
        let path = out.join(LOCK_FILE);
        assert_eq!(marked_pid(&path), Some(std::process::id()));
        let got = std::sync::atomic::AtomicBool::new(false);
        std::thread::scope(|s| {
            let waiter = s.spawn(|| {
                let second = OutputLock::folder(&out).unwrap();
                got.store(true, std::sync::atomic::Ordering::SeqCst);
                drop(second);
            });
            std::thread::sleep(std::time::Duration::from_millis(200));
            assert!(!got.load(std::sync::atomic::Ordering::SeqCst), "the second holder must wait");
            drop(first);
            waiter.join().unwrap();
        });
        assert!(got.load(std::sync::atomic::Ordering::SeqCst));
        assert_eq!(fs::read_dir(&out).unwrap().count(), 0, "the lock file is removed");
    }

    #[test]
    fn a_users_file_is_left_alone_and_a_killed_holders_file_is_taken_over() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join(LOCK_FILE);
        fs::write(&path, "my notes\n").unwrap();
        drop(OutputLock::folder(dir.path()).unwrap());
        assert_eq!(fs::read_to_string(&path).unwrap(), "my notes\n");
        // A holder killed before it could remove its file (pid above the kernel's maximum).
        fs::write(&path, format!("{MAGIC}4194305\n")).unwrap();
        let lock = OutputLock::folder(dir.path()).unwrap();
        assert_eq!(marked_pid(&path), Some(std::process::id()));
        drop(lock);
        assert!(!path.exists());
    }

    #[test]
    fn a_link_in_its_place_is_refused_and_kept() {
        let dir = tempfile::tempdir().unwrap();
        let target = dir.path().join("elsewhere");
        fs::write(&target, "x").unwrap();
        let out = dir.path().join("out");
        fs::create_dir(&out).unwrap();
        std::os::unix::fs::symlink(&target, out.join(LOCK_FILE)).unwrap();
        let e = OutputLock::folder(&out).unwrap_err().to_string();
        assert!(e.contains(LOCK_FILE) && e.contains("not a regular file"), "{e}");
        assert!(fs::symlink_metadata(out.join(LOCK_FILE)).unwrap().is_symlink());
        assert_eq!(fs::read_to_string(&target).unwrap(), "x");
    }

    #[test]
    fn two_files_in_one_folder_are_locked_apart() {
        let dir = tempfile::tempdir().unwrap();
        let a = OutputLock::file(&dir.path().join("shard-1.h5")).unwrap();
        assert_eq!(marked_pid(&dir.path().join(".shard-1.h5.beamflow.lock")), Some(std::process::id()));
        let (tx, rx) = std::sync::mpsc::channel();
        let other = dir.path().join("shard-2.h5");
        std::thread::spawn(move || tx.send(OutputLock::file(&other).map(drop).is_ok()).unwrap());
        let got = rx.recv_timeout(std::time::Duration::from_secs(10));
        assert_eq!(got, Ok(true), "the second file's lock must not wait for the first's");
        drop(a);
        assert_eq!(fs::read_dir(dir.path()).unwrap().count(), 0);
    }
}
