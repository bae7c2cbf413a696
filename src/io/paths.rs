//! Where outputs may go: every output file's path is built by [`output_file`], which joins
//! a plain file name to the output folder and refuses a name that would leave it; an output
//! named on the command line is refused when it is one of the run's inputs
//! ([`refuse_input`]) or when two outputs of a run share a name ([`refuse_duplicates`]).
//!
//! Case validation already keeps names to letters, digits, `_` and `-`; this is the second
//! line of defence, so that no name built in code (a new figure, a future field) can write
//! outside `--out` or over an input.

use crate::error::{Error, Result};
use std::path::{Component, Path, PathBuf};

/// Longest output file name (bytes): the usual file-system limit.
pub const FILE_NAME_MAX: usize = 255;

/// `dir/name`, where `name` must be a plain file name: not empty, at most
/// [`FILE_NAME_MAX`] bytes, no path separator, NUL or control character, no leading `.`
/// (hidden files and `..`).
pub fn output_file(dir: &Path, name: &str) -> Result<PathBuf> {
    let why = if name.is_empty() {
        Some("is empty")
    } else if name.len() > FILE_NAME_MAX {
        Some("is longer than 255 bytes")
    } else if name.contains(['/', '\\']) {
        Some("contains a path separator")
    } else if name.chars().any(char::is_control) {
        Some("contains a control character")
    } else if name.starts_with('.') {
        Some("starts with `.`")
    } else {
        None
    };
    if let Some(why) = why {
        return Err(Error::input(
            dir.display().to_string(),
            "output file name",
            format!("{name:?} {why}: outputs are plain file names inside the output folder"),
        ));
    }
    let path = dir.join(name);
    debug_assert_eq!(path.parent(), Some(dir));
    Ok(path)
}

/// `path` made absolute, with `.` and `..` resolved lexically (no file-system access).
fn lexical(path: &Path) -> PathBuf {
    let abs = std::path::absolute(path).unwrap_or_else(|_| path.to_path_buf());
    let mut out = PathBuf::new();
    for c in abs.components() {
        match c {
            Component::ParentDir => {
                out.pop();
            }
            Component::CurDir => {}
            c => out.push(c),
        }
    }
    out
}

/// `path` with its existing ancestors' links resolved: the canonical form of the deepest
/// existing ancestor, joined with the rest (a file to be written need not exist yet).
fn resolved(path: &Path) -> PathBuf {
    let lex = lexical(path);
    let mut base = lex.as_path();
    let mut rest = Vec::new();
    loop {
        if let Ok(c) = base.canonicalize() {
            return rest.iter().rev().fold(c, |p, r| p.join(r));
        }
        match (base.parent(), base.file_name()) {
            (Some(parent), Some(name)) => {
                rest.push(name.to_os_string());
                base = parent;
            }
            _ => return lex,
        }
    }
}

/// Whether two paths name the same file: the same file on disk (device and inode, so hard
/// links count), or equal once made absolute with links and `..` resolved.
pub fn same_file(a: &Path, b: &Path) -> bool {
    #[cfg(unix)]
    {
        use std::os::unix::fs::MetadataExt;
        if let (Ok(x), Ok(y)) = (std::fs::metadata(a), std::fs::metadata(b)) {
            return x.dev() == y.dev() && x.ino() == y.ino();
        }
    }
    resolved(a) == resolved(b)
}

/// A file a command reads, and what it is, for messages (`"the case file"`).
#[derive(Clone, Debug)]
pub struct Input {
    pub path: PathBuf,
    pub what: String,
}

impl Input {
    pub fn new(path: impl Into<PathBuf>, what: impl Into<String>) -> Input {
        Input { path: path.into(), what: what.into() }
    }
}

/// Refuses `output` (given by the command-line option `flag`) when it is one of `inputs`.
pub fn refuse_input(flag: &str, output: &Path, inputs: &[Input]) -> Result<()> {
    match inputs.iter().find(|i| same_file(output, &i.path)) {
        Some(i) => {
            let also = if i.path == output { String::new() } else { format!(" ({})", i.path.display()) };
            Err(Error::input(
                "<cli>",
                flag,
                format!(
                    "{} is {}{also}: an output must not replace an input; name a different file",
                    output.display(),
                    i.what,
                ),
            ))
        }
        None => Ok(()),
    }
}

/// Refuses `output` (option `flag`) when it is one of the run's other `outputs`.
pub fn refuse_output(flag: &str, output: &Path, outputs: &[PathBuf]) -> Result<()> {
    match outputs.iter().find(|o| same_file(output, o)) {
        Some(o) => Err(Error::input(
            "<cli>",
            flag,
            format!("{} is also {}, another output of this run; name a different file", output.display(), o.display()),
        )),
        None => Ok(()),
    }
}

/// Refuses a set of output files two of which share a name, ignoring case (on a
/// case-insensitive file system they would be one file).
pub fn refuse_duplicates(files: &[PathBuf]) -> Result<()> {
    let mut seen = std::collections::HashMap::new();
    for f in files {
        let key = lexical(f).to_string_lossy().to_lowercase();
        if let Some(first) = seen.insert(key, f) {
            return Err(Error::input(
                f.display().to_string(),
                "output file name",
                format!(
                    "two outputs of this run are named {} and {}: one would replace the other (rename an \
                     actuator, sensor or load so their names do not extend one another)",
                    first.display(),
                    f.display()
                ),
            ));
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn plain_names_join_and_everything_else_is_refused() {
        let dir = Path::new("out/x");
        assert_eq!(output_file(dir, "a_0-b.h5").unwrap(), dir.join("a_0-b.h5"));
        for bad in ["", "../up", "a/b", "a\\b", ".hidden", "..", "a\0b", "a\nb", &"x".repeat(256)] {
            let e = output_file(dir, bad).unwrap_err().to_string();
            assert!(e.contains("out/x") && e.contains("output file name"), "{bad:?}: {e}");
        }
    }

    #[test]
    fn same_file_sees_through_dots_links_and_missing_files() {
        let d = tempfile::tempdir().unwrap();
        let a = d.path().join("a.toml");
        std::fs::write(&a, "x").unwrap();
        std::fs::create_dir(d.path().join("sub")).unwrap();
        assert!(same_file(&a, &d.path().join("sub/../a.toml")));
        std::fs::hard_link(&a, d.path().join("hard.toml")).unwrap();
        assert!(same_file(&a, &d.path().join("hard.toml")));
        #[cfg(unix)]
        {
            std::os::unix::fs::symlink(d.path().join("sub"), d.path().join("link")).unwrap();
            // A file that does not exist yet, reached through a link to a folder.
            assert!(same_file(&d.path().join("sub/new.json"), &d.path().join("link/new.json")));
        }
        assert!(!same_file(&a, &d.path().join("b.toml")));
    }

    #[test]
    fn inputs_and_duplicates_are_refused_with_both_names() {
        let d = tempfile::tempdir().unwrap();
        let case = d.path().join("c.toml");
        std::fs::write(&case, "").unwrap();
        let inputs = [Input::new(&case, "the case file")];
        let e = refuse_input("--json", &case, &inputs).unwrap_err().to_string();
        assert!(e.contains("--json") && e.contains("the case file") && e.contains("c.toml"), "{e}");
        assert!(refuse_input("--json", &d.path().join("r.json"), &inputs).is_ok());
        let outs = [d.path().join("A_time.png"), d.path().join("a_time.png")];
        let e = refuse_duplicates(&outs).unwrap_err().to_string();
        assert!(e.contains("A_time.png") && e.contains("a_time.png"), "{e}");
        assert!(refuse_duplicates(&outs[..1]).is_ok());
    }
}
