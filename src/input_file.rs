//! Reading input files (cases, meshes, sweep and optimisation files, CSV series and
//! measurements) with a size limit.
//!
//! Every input is read whole into memory, so a file that never ends (`/dev/zero`, a pipe)
//! or a huge one by mistake would take all the machine's memory before any check could
//! refuse it. Only regular files are read ([`regular_file`]): opening a FIFO blocks until
//! a writer comes, and a device may never end. Reads stop at [`MAX_INPUT_BYTES`]; a larger
//! input is refused with the limit in the message. Like [`crate::error`], every layer that
//! reads a file uses this one (binary inputs such as HDF5 files are checked with
//! [`regular_file`] before their reader opens them).

use crate::error::{Error, Result};
use std::io::Read;
use std::path::Path;

/// The largest input file read: 64 MiB, some hundred times the largest measurement record
/// or mesh a study uses (a million CSV rows of four columns is ≈ 60 MB).
pub const MAX_INPUT_BYTES: u64 = 64 << 20;

/// Reads the UTF-8 text of `path`, refusing a file larger than [`MAX_INPUT_BYTES`]
/// without reading more than that. Every failure is an [`Error::Io`] naming the path.
pub fn read_text(path: &Path) -> Result<String> {
    read_text_limited(path, MAX_INPUT_BYTES)
}

/// [`read_text`] with a given limit (bytes).
pub fn read_text_limited(path: &Path, limit: u64) -> Result<String> {
    // I/O errors, so that a caller that names the field pointing at the file (a case's
    // `beam.mesh.file`) does so for these too.
    let too_large = |what: String| {
        let reason = format!("{what}, above the {} limit for input files; split or shorten the file", bytes(limit));
        Error::io(path, std::io::Error::new(std::io::ErrorKind::FileTooLarge, reason))
    };
    regular_file(path)?;
    let file = std::fs::File::open(path).map_err(|e| Error::io(path, e))?;
    // The file opened may not be the one checked if it was replaced in between.
    let meta = file.metadata().map_err(|e| Error::io(path, e))?;
    if !meta.is_file() {
        return Err(not_regular(path, &meta));
    }
    if meta.len() > limit {
        return Err(too_large(format!("the file holds {}", bytes(meta.len()))));
    }
    // A file still growing may hold more than its length said: read one byte past the
    // limit to tell.
    let mut buf = Vec::with_capacity(meta.len() as usize);
    file.take(limit + 1).read_to_end(&mut buf).map_err(|e| Error::io(path, e))?;
    if buf.len() as u64 > limit {
        return Err(too_large("the file holds more".into()));
    }
    String::from_utf8(buf).map_err(|e| {
        let at = e.utf8_error().valid_up_to();
        let reason = format!("not UTF-8 text (byte {at} is not); save it as UTF-8");
        Error::io(path, std::io::Error::new(std::io::ErrorKind::InvalidData, reason))
    })
}

/// Refuses `path` unless it is a regular file (or a link to one), before anything opens it:
/// a FIFO would block the open until a writer comes, a device may never end, a directory
/// holds no text.
pub fn regular_file(path: &Path) -> Result<()> {
    let meta = std::fs::metadata(path).map_err(|e| Error::io(path, e))?;
    if meta.is_file() {
        Ok(())
    } else {
        Err(not_regular(path, &meta))
    }
}

/// The error for an input that is not a regular file, saying what it is.
fn not_regular(path: &Path, meta: &std::fs::Metadata) -> Error {
    let t = meta.file_type();
    let what = if t.is_dir() { "a directory" } else { special_kind(&t) };
    let kind = if t.is_dir() { std::io::ErrorKind::IsADirectory } else { std::io::ErrorKind::InvalidInput };
    Error::io(path, std::io::Error::new(kind, format!("is {what}, not a regular file; give a regular file")))
}

/// What a file that is neither a regular file nor a directory is.
#[cfg(unix)]
fn special_kind(t: &std::fs::FileType) -> &'static str {
    use std::os::unix::fs::FileTypeExt;
    if t.is_fifo() {
        "a FIFO (named pipe)"
    } else if t.is_char_device() || t.is_block_device() {
        "a device"
    } else if t.is_socket() {
        "a socket"
    } else {
        "a special file"
    }
}

#[cfg(not(unix))]
fn special_kind(_: &std::fs::FileType) -> &'static str {
    "a special file"
}

/// A byte count in the unit that reads best (B, KiB, MiB, GiB).
fn bytes(n: u64) -> String {
    const UNITS: [&str; 4] = ["B", "KiB", "MiB", "GiB"];
    let mut x = n as f64;
    let mut u = 0;
    while x >= 1024.0 && u < UNITS.len() - 1 {
        x /= 1024.0;
        u += 1;
    }
    if u == 0 || x.fract() == 0.0 {
        format!("{x:.0} {}", UNITS[u])
    } else {
        format!("{x:.1} {}", UNITS[u])
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn reads_text_up_to_the_limit_and_refuses_beyond() {
        let dir = tempfile::tempdir().unwrap();
        let p = dir.path().join("a.csv");
        std::fs::write(&p, "t,v\n0,1\n").unwrap();
        assert_eq!(read_text_limited(&p, 8).unwrap(), "t,v\n0,1\n");
        let e = read_text_limited(&p, 7).unwrap_err().to_string();
        assert!(e.contains("a.csv") && e.contains("8 B") && e.contains("7 B limit"), "{e}");
    }

    #[test]
    fn devices_and_fifos_are_refused_before_they_are_opened() {
        let t = std::time::Instant::now();
        let e = read_text(Path::new("/dev/zero")).unwrap_err().to_string();
        assert!(e.contains("/dev/zero") && e.contains("a device, not a regular file"), "{e}");
        let dir = tempfile::tempdir().unwrap();
        let fifo = dir.path().join("series.csv");
        let made = std::process::Command::new("mkfifo").arg(&fifo).status().unwrap();
        assert!(made.success());
        // Opening a FIFO without a writer would block this test forever.
        let e = read_text(&fifo).unwrap_err().to_string();
        assert!(e.contains("series.csv") && e.contains("a FIFO (named pipe), not a regular file"), "{e}");
        assert!(t.elapsed().as_secs_f64() < 1.0);
        // A link to a regular file is read.
        let target = dir.path().join("a.csv");
        std::fs::write(&target, "t,v\n").unwrap();
        let link = dir.path().join("link.csv");
        std::os::unix::fs::symlink(&target, &link).unwrap();
        assert_eq!(read_text(&link).unwrap(), "t,v\n");
    }

    #[test]
    fn binary_and_directories_are_refused_with_the_path() {
        let dir = tempfile::tempdir().unwrap();
        let p = dir.path().join("b.toml");
        std::fs::write(&p, b"ok\xff").unwrap();
        let e = read_text(&p).unwrap_err().to_string();
        assert!(e.contains("b.toml") && e.contains("UTF-8") && e.contains("byte 2"), "{e}");
        let e = read_text(dir.path()).unwrap_err().to_string();
        assert!(e.contains("a directory, not a regular file"), "{e}");
    }

    #[test]
    fn sizes_read_in_binary_units() {
        assert_eq!(bytes(64 << 20), "64 MiB");
        assert_eq!(bytes(1536), "1.5 KiB");
        assert_eq!(bytes(5), "5 B");
    }
}
