//! The bad-input table: every row under `tests/data/hostile/<class>/<name>.toml` is run
//! through the `beamflow` binary in a sandbox, and each row must
//! - end with its expected exit status, within [`TIMEOUT`] (a hang is a failure);
//! - on failure, name the file at fault (the case file unless the row says otherwise) and
//!   every expected substring in its message;
//! - write nothing outside its output folder, change no input, and leave no staging folder
//!   or temporary file in it;
//! - leave no NaN or infinity in any output (JSON, CSV, HDF5);
//! - never panic.
//!
//! A row is a case file whose first comment lines the runner reads (see
//! `tests/data/hostile/README.md`):
//! ```text
//! # args: run --out {out} {case}
//! # exit: 1
//! # expect: actuator[0].name | valid name
//! # files: sensor.csv
//! # names: sensor.csv
//! # seconds: 1
//! # memory: 100M
//! ```
//! `seconds` and `memory` bound the row's wall time and the peak resident memory of the
//! program and everything it starts (measured by `wait4`), for rows that must be refused
//! from their sizes alone, before any work or allocation.
//! All rows run before the test reports, so one run lists every failing row.

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};
use std::time::{Duration, Instant};

/// A row that runs longer than this hangs.
const TIMEOUT: Duration = Duration::from_secs(20);

/// The table is meant to cover each class of hostile input of the issue with this many
/// rows at least.
const MIN_ROWS: usize = 60;

/// One row of the table.
#[derive(Debug)]
struct Row {
    /// The row's file, e.g. `tests/data/hostile/names/slash.toml`.
    path: PathBuf,
    /// `names/slash`, for the report.
    id: String,
    args: Vec<String>,
    exit: i32,
    expect: Vec<String>,
    files: Vec<String>,
    /// The file the message must name (default: the case file's name).
    names: Option<String>,
    /// Most wall time the row may take.
    seconds: Option<Duration>,
    /// Most resident memory (bytes) the program may reach.
    memory: Option<u64>,
}

fn table_dir() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data/hostile")
}

/// Reads a row's header: the comment lines at the top of the file.
fn parse_row(path: &Path) -> Result<Row, String> {
    let text = std::fs::read_to_string(path).map_err(|e| format!("cannot read: {e}"))?;
    let rel = path.strip_prefix(table_dir()).unwrap_or(path).with_extension("");
    let mut row = Row {
        path: path.to_path_buf(),
        id: rel.display().to_string(),
        args: Vec::new(),
        exit: -1,
        expect: Vec::new(),
        files: Vec::new(),
        names: None,
        seconds: None,
        memory: None,
    };
    let list = |v: &str, sep: char| v.split(sep).map(str::trim).filter(|s| !s.is_empty()).map(String::from).collect();
    for line in text.lines().map(str::trim).take_while(|l| l.starts_with('#')) {
        let Some((key, value)) = line.trim_start_matches('#').split_once(':') else { continue };
        let value = value.trim();
        match key.trim() {
            "args" => row.args = value.split_whitespace().map(String::from).collect(),
            "exit" => row.exit = value.parse().map_err(|_| format!("`# exit: {value}` is not an exit status"))?,
            "expect" => row.expect = list(value, '|'),
            "files" => row.files = list(value, ','),
            "names" => row.names = Some(value.to_string()),
            "seconds" => {
                let s: f64 = value.parse().map_err(|_| format!("`# seconds: {value}` is not a number"))?;
                row.seconds = Some(Duration::from_secs_f64(s));
            }
            "memory" => row.memory = Some(beamflow::analysis::budget::parse_bytes(value)?),
            _ => {}
        }
    }
    if row.args.is_empty() {
        return Err("no `# args:` line".into());
    }
    if row.exit < 0 {
        return Err("no `# exit:` line".into());
    }
    Ok(row)
}

/// Every row, sorted by path.
fn rows() -> Vec<Result<Row, (PathBuf, String)>> {
    let mut paths = Vec::new();
    for class in std::fs::read_dir(table_dir()).expect("tests/data/hostile").flatten() {
        if !class.path().is_dir() {
            continue;
        }
        for f in std::fs::read_dir(class.path()).unwrap().flatten() {
            if f.path().extension().is_some_and(|e| e == "toml") {
                paths.push(f.path());
            }
        }
    }
    paths.sort();
    paths.into_iter().map(|p| parse_row(&p).map_err(|e| (p, e))).collect()
}

/// Every file and folder under `root` with a fingerprint of its content.
fn snapshot(root: &Path) -> BTreeMap<PathBuf, Option<Vec<u8>>> {
    let mut out = BTreeMap::new();
    let mut stack = vec![root.to_path_buf()];
    while let Some(dir) = stack.pop() {
        let Ok(entries) = std::fs::read_dir(&dir) else { continue };
        for e in entries.flatten() {
            let p = e.path();
            let rel = p.strip_prefix(root).unwrap().to_path_buf();
            match e.file_type() {
                Ok(t) if t.is_dir() => {
                    stack.push(p);
                    out.insert(rel, None);
                }
                // Inputs are small: their bytes are the fingerprint.
                _ => {
                    out.insert(rel, Some(std::fs::read(&p).unwrap_or_default()));
                }
            }
        }
    }
    out
}

/// The first non-finite number in a JSON value (serde_json writes NaN and ±inf as null).
fn json_non_finite(v: &serde_json::Value, at: &str) -> Option<String> {
    use serde_json::Value;
    match v {
        Value::Null => Some(at.to_string()),
        Value::Number(n) if !n.as_f64().is_some_and(f64::is_finite) => Some(at.to_string()),
        Value::Array(a) => a.iter().enumerate().find_map(|(i, x)| json_non_finite(x, &format!("{at}[{i}]"))),
        Value::Object(o) => o.iter().find_map(|(k, x)| json_non_finite(x, &format!("{at}.{k}"))),
        _ => None,
    }
}

/// The first non-finite number in a results tree.
fn tree_non_finite(g: &beamflow::io::tree::Group, at: &str) -> Option<String> {
    use beamflow::io::tree::{Attr, Data};
    for (k, a) in &g.attrs {
        if matches!(a, Attr::F64(x) if !x.is_finite()) {
            return Some(format!("{at}@{k}"));
        }
    }
    for (k, d) in &g.datasets {
        let bad = match &d.data {
            Data::F64(v) => v.iter().any(|x| !x.is_finite()),
            Data::C64(v) => v.iter().any(|x| !x.re.is_finite() || !x.im.is_finite()),
            _ => false,
        };
        if bad {
            return Some(format!("{at}/{k}"));
        }
    }
    g.groups.iter().find_map(|(k, sub)| tree_non_finite(sub, &format!("{at}/{k}")))
}

/// What is wrong with an output file's numbers, if anything.
fn output_non_finite(path: &Path) -> Option<String> {
    let ext = path.extension().and_then(|e| e.to_str()).unwrap_or("");
    match ext {
        "json" => {
            let text = std::fs::read_to_string(path).unwrap_or_default();
            match serde_json::from_str::<serde_json::Value>(&text) {
                Ok(v) => json_non_finite(&v, "").map(|at| format!("null or non-finite at `{at}`")),
                Err(e) => Some(format!("not JSON: {e}")),
            }
        }
        "csv" => {
            let text = std::fs::read_to_string(path).unwrap_or_default();
            let bad = |f: &str| {
                matches!(f.trim().to_ascii_lowercase().trim_start_matches(['-', '+']), "nan" | "inf" | "infinity")
            };
            text.lines().enumerate().find(|(_, l)| l.split(',').any(bad)).map(|(i, l)| format!("line {}: {l}", i + 1))
        }
        "h5" => match beamflow::io::hdf5::ResultsReader::open(path).and_then(|r| r.read_tree()) {
            Ok(tree) => tree_non_finite(&tree, "").map(|at| format!("non-finite values in `{at}`")),
            Err(e) => Some(format!("unreadable: {e}")),
        },
        _ => None,
    }
}

/// How a row's program ended.
struct Ended {
    /// Exit status (None when killed at [`TIMEOUT`]; -1 when ended by a signal).
    status: Option<i32>,
    stderr: String,
    took: Duration,
    /// Peak resident memory of the program and the processes it waited for (bytes).
    peak: u64,
}

/// Reaps `pid` (`block`: waits for it), with its resource usage, or None while it runs.
fn reap(pid: libc::pid_t, block: bool) -> Result<Option<(i32, libc::rusage)>, String> {
    let mut status = 0;
    // SAFETY: an all-zero rusage is a valid value of the plain C struct.
    let mut usage: libc::rusage = unsafe { std::mem::zeroed() };
    // SAFETY: `pid` is a child of this process not yet reaped (only this function reaps
    // it), and both out-pointers are valid for the call.
    let r = unsafe { libc::wait4(pid, &mut status, if block { 0 } else { libc::WNOHANG }, &mut usage) };
    match r {
        0 => Ok(None),
        r if r == pid => Ok(Some((status, usage))),
        _ => Err(format!("wait4: {}", std::io::Error::last_os_error())),
    }
}

/// Runs `program` with `args` in `cwd`, killed after [`TIMEOUT`].
fn run_with_timeout(program: &Path, args: &[String], cwd: &Path, err_path: &Path) -> Result<Ended, String> {
    let err_file = std::fs::File::create(err_path).map_err(|e| e.to_string())?;
    let start = Instant::now();
    let mut child = Command::new(program)
        .args(args)
        .current_dir(cwd)
        .env_remove("RUST_BACKTRACE")
        .stdin(Stdio::null())
        .stdout(Stdio::null())
        .stderr(err_file)
        .spawn()
        .map_err(|e| format!("cannot start {}: {e}", program.display()))?;
    let pid = child.id() as libc::pid_t;
    let (status, usage) = loop {
        if let Some((status, usage)) = reap(pid, false)? {
            let code = if libc::WIFEXITED(status) { libc::WEXITSTATUS(status) } else { -1 };
            break (Some(code), usage);
        }
        if start.elapsed() > TIMEOUT {
            let _ = child.kill();
            let (_, usage) = reap(pid, true)?.expect("a blocking wait reaps");
            break (None, usage);
        }
        std::thread::sleep(Duration::from_millis(10));
    };
    let took = start.elapsed();
    let stderr = std::fs::read_to_string(err_path).unwrap_or_default();
    // Linux counts ru_maxrss in KiB.
    let peak = u64::try_from(usage.ru_maxrss).unwrap_or(0) * 1024;
    Ok(Ended { status, stderr, took, peak })
}

/// Runs one row in a fresh sandbox; every problem found, and the time it took.
fn check_row(program: &Path, row: &Row) -> (Vec<String>, Duration) {
    let sandbox = tempfile::tempdir().unwrap();
    // The case sits four folders deep so that a name climbing out of `--out` with `..`
    // still lands inside the snapshot (only the stderr file is outside it).
    let root = sandbox.path().join("root");
    let dir = root.join("a/b/c/case");
    std::fs::create_dir_all(&dir).unwrap();
    let from = row.path.parent().unwrap();
    let case_name = row.path.file_name().unwrap().to_string_lossy().into_owned();
    let case = dir.join(&case_name);
    std::fs::copy(&row.path, &case).unwrap();
    let mut problems = Vec::new();
    for f in &row.files {
        let to = dir.join(f);
        std::fs::create_dir_all(to.parent().unwrap()).unwrap();
        if let Err(e) = std::fs::copy(from.join(f), &to) {
            problems.push(format!("`# files:` {f}: {e}"));
        }
    }
    let out = dir.join("out");
    let expand = |a: &String| {
        a.replace("{out}", &out.display().to_string())
            .replace("{case}", &case.display().to_string())
            .replace("{dir}", &dir.display().to_string())
    };
    let args: Vec<String> = row.args.iter().map(expand).collect();
    let before = snapshot(&root);
    let Ended { status, stderr, took, peak } =
        match run_with_timeout(program, &args, &dir, &sandbox.path().join("stderr.txt")) {
            Ok(r) => r,
            Err(e) => return (vec![e], Duration::ZERO),
        };
    if let Some(limit) = row.seconds.filter(|&l| took > l) {
        problems.push(format!("took {took:.2?}, more than the row's {limit:?}"));
    }
    if let Some(limit) = row.memory.filter(|&l| peak > l) {
        problems.push(format!("reached {} MB of memory, more than the row's {} MB", peak >> 20, limit >> 20));
    }
    match status {
        None => problems.push(format!("no answer within {TIMEOUT:?} (a hang)")),
        Some(code) if code != row.exit => problems.push(format!("exit status {code}, expected {}", row.exit)),
        Some(_) => {}
    }
    for panic in ["panicked", "RUST_BACKTRACE"] {
        if stderr.contains(panic) {
            problems.push(format!("the message shows a panic (`{panic}`)"));
        }
    }
    if row.exit != 0 {
        let names = row.names.clone().unwrap_or(case_name);
        if !stderr.contains(&names) {
            problems.push(format!("the message does not name the file `{names}`"));
        }
    }
    for e in &row.expect {
        if !stderr.contains(e.as_str()) {
            problems.push(format!("the message does not contain `{e}`"));
        }
    }
    let after = snapshot(&root);
    let rel_out = out.strip_prefix(&root).unwrap();
    for (p, content) in &after {
        if p.starts_with(rel_out) {
            let name = p.file_name().unwrap().to_string_lossy();
            if name.starts_with(".staging-") || name.contains(".tmp-") {
                problems.push(format!("left behind in --out: {}", p.display()));
            } else if content.is_some() {
                if let Some(why) = output_non_finite(&root.join(p)) {
                    problems.push(format!("output {}: {why}", p.display()));
                }
            }
        } else if before.get(p) != Some(content) {
            let what = if before.contains_key(p) { "changed" } else { "written" };
            problems.push(format!("{what} outside --out: {}", p.display()));
        }
    }
    for p in before.keys().filter(|p| !after.contains_key(*p)) {
        problems.push(format!("removed: {}", p.display()));
    }
    if !problems.is_empty() {
        let shown: String = stderr.lines().take(6).map(|l| format!("\n      | {l}")).collect();
        problems.push(format!("stderr:{shown}"));
    }
    (problems, took)
}

#[test]
fn every_hostile_input_is_refused_cleanly_or_run_safely() {
    let program = PathBuf::from(env!("CARGO_BIN_EXE_beamflow"));
    let rows = rows();
    let mut failures = Vec::new();
    let mut good = Vec::new();
    for r in rows {
        match r {
            Ok(row) => good.push(row),
            Err((p, e)) => failures.push(format!("{}: {e}", p.display())),
        }
    }
    let threads = std::thread::available_parallelism().map_or(2, |n| n.get().min(4));
    let next = std::sync::atomic::AtomicUsize::new(0);
    let results = std::sync::Mutex::new(Vec::new());
    let start = Instant::now();
    std::thread::scope(|s| {
        for _ in 0..threads {
            s.spawn(|| loop {
                let i = next.fetch_add(1, std::sync::atomic::Ordering::Relaxed);
                let Some(row) = good.get(i) else { break };
                let (problems, took) = check_row(&program, row);
                results.lock().unwrap().push((row.id.clone(), problems, took));
            });
        }
    });
    let mut results = results.into_inner().unwrap();
    results.sort_by(|a, b| a.0.cmp(&b.0));
    let slowest = results.iter().max_by_key(|r| r.2).map(|r| (r.0.clone(), r.2));
    eprintln!("{} rows in {:.1?} (slowest: {slowest:?})", results.len(), start.elapsed());
    for (id, problems, _) in &results {
        if !problems.is_empty() {
            failures.push(format!("{id}:\n    {}", problems.join("\n    ")));
        }
    }
    let mut classes: Vec<&str> = good.iter().filter_map(|r| r.id.split('/').next()).collect();
    classes.dedup();
    assert!(failures.is_empty(), "{} of {} rows failed:\n{}", failures.len(), good.len(), failures.join("\n"));
    assert!(good.len() >= MIN_ROWS, "only {} rows in the table ({classes:?})", good.len());
}

/// The runner catches what it is there to catch: a stand-in program that escapes its
/// output folder, leaves NaN, hangs or panics fails its row.
#[test]
fn the_runner_catches_escapes_nan_panics_and_wrong_status() {
    let sh = PathBuf::from("/bin/sh");
    let dir = tempfile::tempdir().unwrap();
    let row_file = dir.path().join("x.toml");
    std::fs::write(&row_file, "").unwrap();
    let row = |script: &str, exit: i32| Row {
        path: row_file.clone(),
        id: "self".into(),
        args: vec!["-c".into(), script.into()],
        exit,
        expect: Vec::new(),
        files: Vec::new(),
        names: None,
        seconds: Some(Duration::from_secs(1)),
        memory: Some(100 << 20),
    };
    let fails = |script: &str, exit: i32, what: &str| {
        let (problems, _) = check_row(&sh, &row(script, exit));
        assert!(problems.iter().any(|p| p.contains(what)), "{script}: {problems:?}");
    };
    let (ok, _) = check_row(&sh, &row("mkdir out && echo '{\"a\": 1}' > out/r.json", 0));
    assert!(ok.is_empty(), "{ok:?}");
    fails("mkdir -p out && echo x > out/../../../../ESCAPED", 0, "written outside --out");
    fails("echo changed > x.toml", 0, "changed outside --out");
    fails("mkdir out && echo '{\"a\": null}' > out/r.json", 0, "null or non-finite at `.a`");
    fails("mkdir out && printf 't,p\\n0,NaN\\n' > out/r.csv", 0, "line 2");
    fails("mkdir -p out/.staging-1-0", 0, "left behind");
    fails("echo 'thread main panicked' >&2; exit 1", 1, "panic");
    fails("echo 'error: something' >&2; exit 1", 1, "does not name the file `x.toml`");
    fails("exit 3", 1, "exit status 3");
    fails("sleep 1.5", 0, "more than the row's 1s");
    // A child of the program that grows past the limit counts too.
    fails("dd if=/dev/zero of=/dev/null bs=300M count=1 2>/dev/null", 0, "MB of memory");
}
