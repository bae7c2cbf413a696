//! Where a command's messages and text go: status lines to standard output, standard error
//! or nowhere (`--quiet`), and text to a file or standard output (`-`). Set by the command
//! line, used by every command.

/// Where status lines go: standard output, standard error (when standard output carries
/// data, as with `--json -`) or nowhere (`--quiet`).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Status {
    Stdout = 0,
    Stderr = 1,
    Quiet = 2,
}

static STATUS: std::sync::atomic::AtomicU8 = std::sync::atomic::AtomicU8::new(Status::Stdout as u8);

pub(crate) fn set_status(s: Status) {
    STATUS.store(s as u8, std::sync::atomic::Ordering::Relaxed);
}

fn status() -> Status {
    match STATUS.load(std::sync::atomic::Ordering::Relaxed) {
        1 => Status::Stderr,
        2 => Status::Quiet,
        _ => Status::Stdout,
    }
}

/// Whether `path` is `-`, the command line's name for standard output.
pub fn is_stdout(path: &std::path::Path) -> bool {
    path.as_os_str() == "-"
}

/// Writes `text` to `path` atomically, or to standard output when `path` is `-`.
pub fn write_text_or_stdout(path: &std::path::Path, text: &str) -> crate::error::Result<()> {
    if is_stdout(path) {
        use std::io::Write;
        let mut out = std::io::stdout().lock();
        return match out.write_all(text.as_bytes()).and_then(|()| out.write_all(b"\n")) {
            Err(e) if e.kind() != std::io::ErrorKind::BrokenPipe => Err(crate::Error::io(path, e)),
            _ => Ok(()),
        };
    }
    crate::io::atomic::write_atomic_string(path, text)
}

/// A status line that belongs on standard error whatever `--json` does (a sweep's and an
/// optimisation's counts and timings); nothing with `--quiet`.
pub fn note_line(args: std::fmt::Arguments) {
    if !matches!(status(), Status::Quiet) {
        eprintln!("{args}");
    }
}

/// The body of [`say!`](crate::say).
pub fn say_line(args: std::fmt::Arguments) {
    use std::io::Write;
    match status() {
        Status::Quiet => return,
        Status::Stderr => {
            eprintln!("{args}");
            return;
        }
        Status::Stdout => {}
    }
    let mut out = std::io::stdout().lock();
    if let Err(e) = out.write_fmt(args).and_then(|()| out.write_all(b"\n")) {
        if e.kind() != std::io::ErrorKind::BrokenPipe {
            eprintln!("warning: could not write to standard output: {e}");
        }
    }
}
