//! The output folder is the user's and only regular files are read, through the binary in
//! a sandbox: what a run did not create survives it (entries merely named like its staging
//! folders and temporary files, a planted link), two sweeps into one folder both finish, and
//! a FIFO given as any input is refused at once instead of blocking in `open`.

use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};
use std::time::{Duration, Instant};

/// A process id above the kernel's maximum: never a running process.
const DEAD: u32 = 4_000_000;

fn cases() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("cases")
}

/// What one run of the binary did.
struct Ran {
    /// None when it had to be killed after the time limit.
    code: Option<i32>,
    stderr: String,
    took: Duration,
}

/// Starts `beamflow args` in `cwd` with standard error to `err` and no input.
fn start(cwd: &Path, args: &[&str], err: &Path) -> std::process::Child {
    Command::new(env!("CARGO_BIN_EXE_beamflow"))
        .args(args)
        .current_dir(cwd)
        .stdin(Stdio::null())
        .stdout(Stdio::null())
        .stderr(std::fs::File::create(err).unwrap())
        .spawn()
        .unwrap()
}

/// Waits for `child`, killing it after `limit`.
fn finish(mut child: std::process::Child, err: &Path, started: Instant, limit: Duration) -> Ran {
    let code = loop {
        if let Some(s) = child.try_wait().unwrap() {
            break s.code();
        }
        if started.elapsed() > limit {
            let _ = child.kill();
            let _ = child.wait();
            break None;
        }
        std::thread::sleep(Duration::from_millis(5));
    };
    Ran { code, stderr: std::fs::read_to_string(err).unwrap_or_default(), took: started.elapsed() }
}

fn run(cwd: &Path, args: &[&str]) -> Ran {
    let err = cwd.join("..").join("stderr.txt");
    let t = Instant::now();
    finish(start(cwd, args, &err), &err, t, Duration::from_secs(60))
}

/// A sandbox with the folder `work` (the working directory and `--out .`), holding the
/// frame case as `c.toml`.
fn sandbox() -> (tempfile::TempDir, PathBuf) {
    let dir = tempfile::tempdir().unwrap();
    let work = dir.path().join("work");
    std::fs::create_dir(&work).unwrap();
    std::fs::copy(cases().join("beam-frame-12V-60Hz.toml"), work.join("c.toml")).unwrap();
    (dir, work)
}

/// Plants a user's folder named like a dead run's staging folder (with a commit marker)
/// and a user's file named like a dead run's temporary file.
fn plant_look_alikes(work: &Path) {
    let folder = work.join(format!(".staging-{DEAD}-0"));
    std::fs::create_dir(&folder).unwrap();
    std::fs::write(folder.join("notes.txt"), "mine").unwrap();
    std::fs::write(folder.join("COMMIT"), "").unwrap();
    std::fs::write(work.join(format!(".notes.tmp-{DEAD}-1.txt")), "mine too").unwrap();
}

fn assert_look_alikes_intact(work: &Path) {
    let folder = work.join(format!(".staging-{DEAD}-0"));
    assert_eq!(std::fs::read_to_string(folder.join("notes.txt")).unwrap(), "mine");
    assert!(folder.join("COMMIT").exists());
    assert!(!work.join("notes.txt").exists(), "the user's folder was rolled forward");
    assert_eq!(std::fs::read_to_string(work.join(format!(".notes.tmp-{DEAD}-1.txt"))).unwrap(), "mine too");
}

/// The hidden entries of `dir`, sorted.
fn hidden(dir: &Path) -> Vec<String> {
    let mut v: Vec<String> = std::fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .filter(|n| n.starts_with('.'))
        .collect();
    v.sort();
    v
}

#[test]
fn a_users_look_alikes_survive_run_into_their_folder() {
    let (_dir, work) = sandbox();
    plant_look_alikes(&work);
    let before = hidden(&work);
    let r = run(&work, &["run", "c.toml", "--out", ".", "--no-plots", "--quiet"]);
    assert_eq!(r.code, Some(0), "{}", r.stderr);
    assert_look_alikes_intact(&work);
    assert!(work.join("c.json").exists() && work.join("c.h5").exists());
    assert_eq!(hidden(&work), before, "no staging folder, temporary or lock file left");
}

#[test]
fn a_users_look_alikes_survive_optimize_into_their_folder() {
    let (_dir, work) = sandbox();
    std::fs::write(
        work.join("o.opt.toml"),
        "base = \"c.toml\"\nharmonics = 5\n[search]\nseed = 1\nstarts = 1\nevaluations = 12\n\
         [[variable]]\npath = \"actuator[0].x_e\"\nmin = 0.1\nmax = 0.6\n\
         [[objective]]\nquantity = \"net_power\"\n",
    )
    .unwrap();
    plant_look_alikes(&work);
    let before = hidden(&work);
    let r = run(&work, &["optimize", "o.opt.toml", "--out", ".", "--no-plots", "--quiet"]);
    assert_eq!(r.code, Some(0), "{}", r.stderr);
    assert_look_alikes_intact(&work);
    assert!(work.join("best.toml").exists() && work.join("summary.json").exists());
    assert_eq!(hidden(&work), before, "no staging folder, temporary or lock file left");
}

#[test]
fn a_planted_staging_link_moves_nothing_and_deletes_nothing() {
    let (dir, work) = sandbox();
    // Another folder that looks like a complete set, reached through a link named like a
    // dead run's staging folder.
    let other = dir.path().join("other");
    std::fs::create_dir(&other).unwrap();
    std::fs::write(other.join("theirs.h5"), "theirs").unwrap();
    std::fs::write(other.join("COMMIT"), "").unwrap();
    let link = work.join(format!(".staging-{DEAD}-3"));
    std::os::unix::fs::symlink(&other, &link).unwrap();
    let r = run(&work, &["run", "c.toml", "--out", ".", "--no-plots", "--quiet"]);
    assert_eq!(r.code, Some(0), "{}", r.stderr);
    assert!(std::fs::symlink_metadata(&link).unwrap().is_symlink(), "the link was removed");
    assert_eq!(std::fs::read_to_string(other.join("theirs.h5")).unwrap(), "theirs");
    assert!(other.join("COMMIT").exists());
    assert!(!work.join("theirs.h5").exists(), "a file was moved through the link");
    assert!(work.join("c.json").exists());
}

#[test]
fn two_sweeps_into_one_folder_both_succeed() {
    let dir = tempfile::tempdir().unwrap();
    let work = dir.path().join("work");
    std::fs::create_dir_all(work.join("out")).unwrap();
    for f in ["placement-frame.toml", "placement-frame.sweep.toml"] {
        std::fs::copy(cases().join(f), work.join(f)).unwrap();
    }
    let args = ["sweep", "placement-frame.sweep.toml", "--out", "out/p.h5", "--no-plots", "--threads", "2"];
    let (err1, err2) = (dir.path().join("err1.txt"), dir.path().join("err2.txt"));
    let t1 = Instant::now();
    let first = start(&work, &args, &err1);
    let pid = first.id();
    // Start the second while the first holds the table (its lock file exists).
    let lock = work.join("out/.p.h5.beamflow.lock");
    while !lock.exists() && t1.elapsed() < Duration::from_secs(30) {
        std::thread::sleep(Duration::from_millis(2));
    }
    assert!(lock.exists(), "the first sweep never locked its table");
    let t2 = Instant::now();
    let second = start(&work, &args, &err2);
    let r1 = finish(first, &err1, t1, Duration::from_secs(120));
    let r2 = finish(second, &err2, t2, Duration::from_secs(120));
    assert_eq!(r1.code, Some(0), "first: {}", r1.stderr);
    assert_eq!(r2.code, Some(0), "second: {}", r2.stderr);
    assert!(r2.stderr.contains(&format!("waiting for process {pid}")), "second: {}", r2.stderr);
    assert!(r2.stderr.contains("0 cases computed") && r2.stderr.contains("3840 reused"), "second: {}", r2.stderr);
    let table = beamflow::sweep::SweepTable::read(&work.join("out/p.h5")).unwrap();
    assert!(table.is_complete() && table.rows.len() == 3840);
    let mut left: Vec<_> = std::fs::read_dir(work.join("out")).unwrap().map(|e| e.unwrap().file_name()).collect();
    left.sort();
    assert_eq!(left, ["p.h5"], "no checkpoints or lock file left");
}

#[test]
fn a_fifo_as_any_input_is_refused_at_once() {
    let dir = tempfile::tempdir().unwrap();
    let work = dir.path().join("work");
    std::fs::create_dir(&work).unwrap();
    for name in ["case.toml", "mesh.toml", "series.csv", "measured.csv", "measured.h5", "s.sweep.toml"] {
        assert!(Command::new("mkfifo").arg(work.join(name)).status().unwrap().success());
    }
    let frame = "[[actuator]]\ntype = \"frame\"\nname = \"frame\"\nx_e = 0.15\n[[analysis]]\ntype = \"steady_state\"\n";
    let sine = "[actuator.voltage]\nkind = \"sine\"\namplitude = 12.0\nfrequency = 60.0\n";
    let write = |name: &str, text: String| std::fs::write(work.join(name), text).unwrap();
    write("with-mesh.toml", format!("[beam.mesh]\nfile = \"mesh.toml\"\n{frame}{sine}"));
    write("with-series.toml", format!("{frame}[actuator.voltage]\nkind = \"series\"\nfile = \"series.csv\"\n"));
    write(
        "with-measurement.toml",
        format!("{frame}{sine}[[measurement]]\nfile = \"measured.csv\"\npoint = \"frame_stack\"\n"),
    );
    let rows: [(&[&str], &str); 7] = [
        (&["run", "case.toml", "--out", "o"], "case.toml"),
        (&["check", "with-mesh.toml"], "mesh.toml"),
        (&["check", "with-series.toml"], "series.csv"),
        (&["check", "with-measurement.toml"], "measured.csv"),
        (&["identify", "bouc-wen", "measured.csv", "--d-p", "1.3e-7", "--out", "o"], "measured.csv"),
        (&["identify", "modal", "measured.h5", "--mass", "0.1", "--out", "o"], "measured.h5"),
        (&["sweep", "s.sweep.toml", "--out", "o/s.h5"], "s.sweep.toml"),
    ];
    for (args, fifo) in rows {
        let err = dir.path().join("stderr.txt");
        let t = Instant::now();
        let r = finish(start(&work, args, &err), &err, t, Duration::from_secs(10));
        assert_eq!(r.code, Some(1), "{args:?}: {}", r.stderr);
        assert!(r.took < Duration::from_secs(1), "{args:?} took {:?}", r.took);
        let says = "is a FIFO (named pipe), not a regular file";
        assert!(r.stderr.contains(fifo) && r.stderr.contains(says), "{args:?}: {}", r.stderr);
    }
    assert!(!work.join("o").exists(), "nothing written for a refused input");
}

/// A sweep whose `--out` names a user's file that is not a sweep table is refused with
/// what the file is not, and the file is left byte for byte.
#[test]
fn a_sweep_into_a_users_text_file_is_refused_and_the_file_kept() {
    let (_dir, work) = sandbox();
    for f in ["placement-frame.toml", "placement-frame.sweep.toml"] {
        std::fs::copy(cases().join(f), work.join(f)).unwrap();
    }
    let notes = "my measurements, not a table\n";
    std::fs::write(work.join("precious.txt"), notes).unwrap();
    let r = run(&work, &["sweep", "placement-frame.sweep.toml", "--out", "precious.txt", "--no-plots"]);
    assert_eq!(r.code, Some(1), "{}", r.stderr);
    for says in ["precious.txt", "not a beamflow sweep table", "not an HDF5 file", "left as it is"] {
        assert!(r.stderr.contains(says), "`{says}` in: {}", r.stderr);
    }
    assert!(!r.stderr.contains("H5F"), "no HDF5 library stack: {}", r.stderr);
    assert_eq!(std::fs::read_to_string(work.join("precious.txt")).unwrap(), notes);
}
