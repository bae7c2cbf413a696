//! Data for other tools and the console: the Matrix Market matrices and the DOF map beside
//! them name each row (checked against element stiffnesses computed here); CSV tables equal
//! the HDF5 file; JSON on standard output; help and progress reports.

mod common;

use beamflow::io::mtx::read_matrix_market;
use std::path::Path;

/// A row of `<stem>_dofs.csv`: (row − 1, node, x, kind, actuator).
type DofLine = (usize, Option<usize>, Option<f64>, String, String);

fn dof_map(path: &Path) -> Vec<DofLine> {
    let text = std::fs::read_to_string(path).unwrap();
    let mut lines = text.lines();
    assert_eq!(lines.next(), Some("row,node,x_m,y_m,z_m,kind,actuator"));
    lines
        .map(|l| {
            let f: Vec<&str> = l.split(',').collect();
            assert!(f[3].is_empty() && f[4].is_empty(), "a beam's rows have no y or z: {l}");
            (f[0].parse::<usize>().unwrap() - 1, f[1].parse().ok(), f[2].parse().ok(), f[5].into(), f[6].into())
        })
        .collect()
}

#[test]
fn the_dof_map_names_the_stack_foot_and_the_top_mass_rows() {
    let dir = tempfile::tempdir().unwrap();
    let case = dir.path().join("foot.toml");
    let k_p = 3.0e7;
    std::fs::write(
        &case,
        format!(
            "[beam.mesh]\nelements = 40\n[damping]\nkind = \"rayleigh\"\na0 = 5.0\na1 = 1e-5\n\
             [[actuator]]\ntype = \"inertial\"\nname = \"shaker\"\nx_e = 0.15\n\
             [actuator.stack]\nk_p = {k_p:e}\n[actuator.voltage]\nkind = \"sine\"\namplitude = 12.0\nfrequency = 60.0\n\
             [[analysis]]\ntype = \"modes\"\ncount = 2\n[output]\nmatrices = true\nplots = false\n"
        ),
    )
    .unwrap();
    let out = dir.path().join("out");
    beamflow::app::commands::run(&case, Some(&out), None, false, false, &beamflow::analysis::budget::Budget::default())
        .unwrap();
    let k = read_matrix_market(&out.join("foot_K.mtx")).unwrap();
    assert!(std::fs::read_to_string(out.join("foot_K.mtx"))
        .unwrap()
        .starts_with("%%MatrixMarket matrix coordinate real symmetric"));
    let rows = dof_map(&out.join("foot_dofs.csv"));
    assert_eq!(rows.len(), k.rows());
    let foot =
        rows.iter().find(|r| r.3 == "w" && r.2.is_some_and(|x| (x - 0.15).abs() < 1e-12)).expect("w row at 0.15 m");
    let top = rows.iter().find(|r| r.3 == "z_t" && r.4 == "shaker").expect("the top mass's row");
    // Neighbouring nodes of the foot give the two element lengths around it.
    let xs: Vec<f64> = rows.iter().filter(|r| r.3 == "w").filter_map(|r| r.2).collect();
    let at = xs.iter().position(|&x| (x - 0.15).abs() < 1e-12).unwrap();
    let (h1, h2) = (xs[at] - xs[at - 1], xs[at + 1] - xs[at]);
    // A Hermite element's w–w stiffness is 12·EI/h³ at each end; the stack adds k_p.
    let beam = 12.0 * common::EI / h1.powi(3) + 12.0 * common::EI / h2.powi(3);
    let kd = |i: usize, j: usize| k.get(i, j).copied().unwrap_or(0.0);
    assert!(common::rel(kd(foot.0, foot.0), beam + k_p) < 1e-12, "{} vs {}", kd(foot.0, foot.0), beam + k_p);
    assert_eq!(kd(top.0, top.0), k_p);
    assert_eq!(kd(top.0, foot.0), -k_p);
    assert_eq!(kd(foot.0, top.0), -k_p);
}

/// A small transient-free case in `dir` (modes and a steady state, no figures).
fn small_case(dir: &Path) -> std::path::PathBuf {
    let case = dir.join("small.toml");
    std::fs::write(
        &case,
        "[beam.mesh]\nelements = 20\n[damping]\nkind = \"rayleigh\"\na0 = 5.0\na1 = 1e-5\n\
         [[actuator]]\ntype = \"inertial\"\nname = \"shaker\"\n\
         [actuator.voltage]\nkind = \"sine\"\namplitude = 12.0\nfrequency = 60.0\n\
         [[analysis]]\ntype = \"steady_state\"\n[output]\nplots = false\n",
    )
    .unwrap();
    case
}

fn beamflow(args: &[&str]) -> std::process::Output {
    std::process::Command::new(env!("CARGO_BIN_EXE_beamflow")).args(args).output().unwrap()
}

#[test]
fn json_to_standard_output_is_the_only_thing_there() {
    let dir = tempfile::tempdir().unwrap();
    let case = small_case(dir.path());
    let out = dir.path().join("out");
    let o = beamflow(&["run", case.to_str().unwrap(), "--out", out.to_str().unwrap(), "--json", "-"]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let v: serde_json::Value = serde_json::from_slice(&o.stdout).expect("stdout is one JSON document");
    assert!(v.is_object());
    // The same numbers as the file the run writes, and the status lines on standard error.
    let file: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("small.json")).unwrap()).unwrap();
    assert_eq!(v, file);
    assert!(String::from_utf8_lossy(&o.stderr).contains("wrote"));
    let q = beamflow(&["run", case.to_str().unwrap(), "--out", out.to_str().unwrap(), "--quiet"]);
    assert!(q.status.success() && q.stdout.is_empty() && q.stderr.is_empty());
}

#[test]
fn json_may_not_replace_the_case_or_another_output() {
    let dir = tempfile::tempdir().unwrap();
    let case = small_case(dir.path());
    let before = std::fs::read(&case).unwrap();
    let out = dir.path().join("out");
    let targets = [
        (case.clone(), "the case file"),
        (out.join("small.h5"), "another output"),
        (out.join("sub/../small.json"), "another output"),
    ];
    for (target, why) in targets {
        let o = beamflow(&[
            "run",
            case.to_str().unwrap(),
            "--out",
            out.to_str().unwrap(),
            "--json",
            target.to_str().unwrap(),
        ]);
        let e = String::from_utf8_lossy(&o.stderr);
        assert!(!o.status.success() && e.contains("--json") && e.contains(why), "{e}");
    }
    assert_eq!(std::fs::read(&case).unwrap(), before);
}

#[test]
fn completions_are_printed_for_each_shell() {
    for shell in ["bash", "zsh", "fish"] {
        let o = beamflow(&["completions", shell]);
        assert!(o.status.success());
        let text = String::from_utf8_lossy(&o.stdout);
        assert!(text.contains("beamflow") && text.contains("sweep"), "{shell}");
    }
}

#[test]
fn a_reader_that_stops_early_is_not_a_crash() {
    // `beamflow completions bash | head -3`: the pipe closes before the script is written.
    for args in
        [&["completions", "bash"][..], &["run", "cases/beam-inertial-12V-60Hz.toml", "--json", "-", "--no-plots"]]
    {
        let out = tempfile::tempdir().unwrap();
        let mut child = std::process::Command::new(env!("CARGO_BIN_EXE_beamflow"))
            .args(args)
            .args(if args[0] == "run" { vec!["--out", out.path().to_str().unwrap()] } else { vec![] })
            .current_dir(env!("CARGO_MANIFEST_DIR"))
            .stdout(std::process::Stdio::piped())
            .stderr(std::process::Stdio::piped())
            .spawn()
            .unwrap();
        drop(child.stdout.take());
        let o = child.wait_with_output().unwrap();
        let e = String::from_utf8_lossy(&o.stderr);
        assert!(o.status.success() && !e.contains("panicked"), "{args:?}: {e}");
    }
}

/// The keys of every analysis of a summary, sorted.
fn analysis_keys(v: &serde_json::Value) -> Vec<Vec<String>> {
    v["analyses"]
        .as_array()
        .unwrap()
        .iter()
        .map(|a| {
            let mut k: Vec<String> = a.as_object().unwrap().keys().cloned().collect();
            k.sort();
            k
        })
        .collect()
}

#[test]
fn a_rigid_base_reports_forces_and_no_beam_fields_in_the_same_shape() {
    let dir = tempfile::tempdir().unwrap();
    let cases = Path::new(env!("CARGO_MANIFEST_DIR")).join("cases");
    let out = dir.path().join("out");
    let run = |case: &str| {
        let o = beamflow(&[
            "run",
            cases.join(case).to_str().unwrap(),
            "--out",
            out.to_str().unwrap(),
            "--no-plots",
            "--json",
            "-",
        ]);
        assert!(o.status.success());
        let v: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
        (v, String::from_utf8_lossy(&o.stderr).into_owned())
    };
    let (rigid, console) = run("rigid-base-48V-30Hz.toml");
    let (beam, _) = run("beam-frame-12V-60Hz.toml");
    assert_eq!((rigid["base"].as_str(), beam["base"].as_str()), (Some("rigid"), Some("beam")));
    let t = &rigid["analyses"][0];
    for key in ["mean_power_w", "net_power_w", "beam_dissipation_w"] {
        assert!(t[key].is_null(), "{key}: {}", t[key]);
    }
    assert!(t["energy_balance_rel_error"]["beam_run"].is_null());
    assert!(t["energy_balance_rel_error"]["structure_run"].is_null());
    let balance = &beam["analyses"][1]["energy_balance_rel_error"];
    assert!(balance["structure_last_period"].as_f64().is_some(), "{balance}");
    assert_eq!(balance["structure_last_period"], balance["beam_last_period"]);
    assert_eq!(balance["structure_run"], balance["beam_run"]);
    assert!(t["energy_balance_rel_error"]["system_run"].as_f64().unwrap() < 1e-9);
    // The same keys as a transient on the beam.
    assert_eq!(analysis_keys(&rigid)[0], analysis_keys(&beam)[1]);
    // The console shows the forces and the stack-force ratio, the point of the case.
    let f = &t["transmitted_force_amplitude_at_drive_n"];
    let ratio = f["frame_stack"].as_f64().unwrap() / f["inertial_stack"].as_f64().unwrap();
    assert!(console.contains(&format!("frame_stack / inertial_stack force ratio {ratio:.1}")), "{console}");
    assert!(!console.contains("mean power into the base"), "{console}");
}

/// A CSV file: its header cells split into (name, unit), and its rows of cells.
type Csv = (Vec<(String, Option<String>)>, Vec<Vec<String>>);

fn read_csv(path: &Path) -> Csv {
    let text = std::fs::read_to_string(path).unwrap();
    let mut lines = text.lines();
    let header = lines
        .next()
        .unwrap()
        .split(',')
        .map(|h| match h.strip_suffix(']').and_then(|h| h.split_once(" [")) {
            Some((name, unit)) => (name.to_string(), Some(unit.to_string())),
            None => (h.to_string(), None),
        })
        .collect();
    (header, lines.map(|l| l.split(',').map(str::to_string).collect()).collect())
}

/// Columns that name or count rows rather than measure something: the only ones without a
/// unit.
const KEYS: [&str; 11] =
    ["link", "load", "point", "kind", "actuator", "drive", "measurement", "input", "harmonic", "mode", "case_index"];

fn num(cell: &str) -> f64 {
    cell.parse().unwrap_or_else(|_| panic!("not a number: {cell}"))
}

/// A dataset's values as reals: a complex one's real (`re`) or imaginary (`im`) part.
fn values(tree: &beamflow::io::tree::Group, path: &str, part: Option<&str>) -> (Vec<f64>, String) {
    use beamflow::io::tree::Data;
    let d = tree.dataset(path).unwrap_or_else(|| panic!("no dataset {path}"));
    let v = match (&d.data, part) {
        (Data::F64(v), None) => v.clone(),
        (Data::C64(v), Some("re")) => v.iter().map(|c| c.re).collect(),
        (Data::C64(v), Some("im")) => v.iter().map(|c| c.im).collect(),
        _ => panic!("{path}: unexpected kind for {part:?}"),
    };
    (v, d.unit.clone())
}

#[test]
fn csv_tables_carry_units_and_equal_the_hdf5_file() {
    let dir = tempfile::tempdir().unwrap();
    let case = dir.path().join("c.toml");
    std::fs::write(
        &case,
        "[beam.mesh]\nelements = 20\n[damping]\nkind = \"rayleigh\"\na0 = 5.0\na1 = 1e-5\n\
         [[actuator]]\ntype = \"inertial\"\nname = \"shaker\"\nx_e = 0.146\n\
         [actuator.voltage]\nkind = \"sine\"\namplitude = 12.0\nfrequency = 60.0\n\
         [[load]]\nname = \"tap\"\nx = 0.292\n[load.force]\nkind = \"sine\"\namplitude = 0.5\nfrequency = 60.0\n\
         [[sensor]]\nname = \"mid\"\nx = 0.365\n\
         [[analysis]]\ntype = \"modes\"\ncount = 3\n\
         [[analysis]]\ntype = \"harmonic\"\nsystem = \"coupled\"\n[analysis.frequencies]\nvalues = [30.0, 60.0]\n\
         [[analysis]]\ntype = \"steady_state\"\nharmonics = 5\nsamples_per_period = 256\n\
         [[analysis]]\ntype = \"transient\"\nperiods = 3\n[output]\nplots = false\n",
    )
    .unwrap();
    let out = dir.path().join("out");
    let o = beamflow(&["run", case.to_str().unwrap(), "--out", out.to_str().unwrap(), "--csv", "--quiet"]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let tree = beamflow::io::hdf5::ResultsReader::open(out.join("c.h5")).unwrap().read_tree().unwrap();
    let summary: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("c.json")).unwrap()).unwrap();
    let csv = |name: &str| read_csv(&out.join(format!("c_{name}.csv")));
    let mut checked = 0;

    // Every file: one header line, units on every measured column, rows as long as it.
    let files: Vec<_> = std::fs::read_dir(&out).unwrap().map(|e| e.unwrap().path()).collect();
    for f in files.iter().filter(|f| f.extension().is_some_and(|e| e == "csv")) {
        let (head, rows) = read_csv(f);
        for (name, unit) in &head {
            assert!(unit.is_some() || KEYS.contains(&name.as_str()), "{}: `{name}` has no unit", f.display());
        }
        assert!(!rows.is_empty() && rows.iter().all(|r| r.len() == head.len()), "{}", f.display());
    }

    // Time histories: each column is the dataset at its path, bit for bit, with its unit.
    for g in ["analysis_2_steady_state", "analysis_3_transient"] {
        let (head, rows) = csv(&format!("{g}_series"));
        assert!(head.iter().any(|(n, _)| n == "sensors/mid/a") && head.iter().any(|(n, _)| n == "loads/tap/force"));
        for (j, (name, unit)) in head.iter().enumerate() {
            let (v, u) = values(&tree, &format!("{g}/{name}"), None);
            assert_eq!(unit.as_deref(), Some(u.as_str()), "{name}");
            let col: Vec<f64> = rows.iter().map(|r| num(&r[j])).collect();
            assert!(col.iter().zip(&v).all(|(a, b)| a.to_bits() == b.to_bits()) && col.len() == v.len(), "{g}/{name}");
            checked += 1;
        }
        // Spectra per link and harmonic, per load and harmonic.
        for (table, coll) in [("spectra", "spectra"), ("load_spectra", "loads")] {
            let (head, rows) = csv(&format!("{g}_{table}"));
            for row in &rows {
                let k: usize = row[1].parse().unwrap();
                for (j, (name, unit)) in head.iter().enumerate().skip(2) {
                    let (base, part) = match name.rsplit_once(' ') {
                        Some((b, p)) => (b, Some(p)),
                        None => (name.as_str(), None),
                    };
                    let (v, u) = values(&tree, &format!("{g}/{coll}/{}/{base}", row[0]), part);
                    assert_eq!((num(&row[j]).to_bits(), unit.as_deref()), (v[k].to_bits(), Some(u.as_str())), "{name}");
                    checked += 1;
                }
            }
        }
        // Point powers: the JSON summary's numbers (serde_json reads decimals to within an ulp).
        let (head, rows) = csv(&format!("{g}_point_power"));
        let p = head.iter().position(|(n, _)| n == "mean_power").unwrap();
        let a = &summary["analyses"][if g.contains("steady") { 2 } else { 3 }];
        for row in &rows {
            let key = if row[1] == "link" { "mean_power_w" } else { "load_power_w" };
            let json = a[key][&row[0]].as_f64().unwrap();
            assert!(common::rel(num(&row[p]), json) < 1e-15, "{}: {} vs {json}", row[0], row[p]);
            checked += 1;
        }
        assert_eq!(rows.len(), 2, "the actuator's link and the load");
    }

    // Mode-resolved power: the matrix point_power[link][mode], load_power[load][mode].
    let (_, rows) = csv("analysis_2_steady_state_modal_point_power");
    let (pp, _) = values(&tree, "analysis_2_steady_state/modal/point_power", None);
    let (lp, _) = values(&tree, "analysis_2_steady_state/modal/load_power", None);
    let nm = rows.iter().filter(|r| r[1] == "link").count();
    for r in &rows {
        let m: usize = r[2].parse().unwrap();
        let expect = if r[1] == "link" { pp[m - 1] } else { lp[m - 1] };
        assert_eq!(num(&r[4]), expect);
    }
    assert_eq!(rows.len(), 2 * nm);

    // Modes, and the bare beam's point mobilities of the harmonic analysis.
    let (_, rows) = csv("analysis_0_modes_modes");
    let (f, _) = values(&tree, "analysis_0_modes/frequencies_hz", None);
    assert_eq!(rows.iter().map(|r| num(&r[1])).collect::<Vec<_>>(), f);
    let (head, rows) = csv("analysis_1_harmonic_harmonic_points");
    let re = head.iter().position(|(n, _)| n == "velocity re").unwrap();
    let (v, _) = values(&tree, "analysis_1_harmonic/velocity", Some("re"));
    let np = rows.len() / 2;
    for (i, r) in rows.iter().enumerate() {
        assert_eq!(num(&r[re]), v[(i % 2) * np + i / 2], "row {i}");
    }
    // The coupled system's transfer functions, row by row: output, input, frequency.
    let (head, rows) = csv("analysis_1_harmonic_transfer_velocity");
    let col = |n: &str| head.iter().position(|(h, _)| h == n).unwrap();
    let (re, im) = (
        values(&tree, "analysis_1_harmonic/transfer_velocity", Some("re")).0,
        values(&tree, "analysis_1_harmonic/transfer_velocity", Some("im")).0,
    );
    let ni = 2; // the shaker's foot and its drive
    let np = rows.len() / (2 * ni);
    for (r, row) in rows.iter().enumerate() {
        let (o, i, k) = (r / (ni * 2), (r / 2) % ni, r % 2);
        let c = num_complex::Complex64::new(re[k * np * ni + o * ni + i], im[k * np * ni + o * ni + i]);
        assert_eq!((num(&row[col("transfer_velocity re")]), num(&row[col("|transfer_velocity|")])), (c.re, c.norm()));
    }
    assert_eq!(rows[0][col("input")], "shaker_stack");
    assert!(checked > 50, "{checked}");
}

#[test]
fn sweep_csv_equals_the_sweep_table() {
    let dir = tempfile::tempdir().unwrap();
    let base = dir.path().join("base.toml");
    std::fs::write(
        &base,
        "[beam.mesh]\nelements = 20\n[[actuator]]\ntype = \"inertial\"\n[actuator.voltage]\nkind = \"sine\"\n\
         amplitude = 12.0\nfrequency = 60.0\n[[analysis]]\ntype = \"steady_state\"\nharmonics = 3\nsamples_per_period = 64\n",
    )
    .unwrap();
    let sweep = dir.path().join("s.sweep.toml");
    std::fs::write(
        &sweep,
        "base = \"base.toml\"\n[[parameter]]\npath = \"actuator[0].x_e\"\nvalues = [0.1, 0.2, 0.3]\n",
    )
    .unwrap();
    let table = dir.path().join("t.h5");
    let o = beamflow(&["sweep", sweep.to_str().unwrap(), "--out", table.to_str().unwrap(), "--csv", "--no-plots"]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let t = beamflow::sweep::SweepTable::read(&table).unwrap();
    let (head, rows) = read_csv(&dir.path().join("t.csv"));
    let col = |name: &str| head.iter().position(|(n, _)| n == name).unwrap_or_else(|| panic!("{name}"));
    assert_eq!(head[col("inputs/actuator_0.x_e")].1.as_deref(), Some("m"));
    assert_eq!(rows.len(), 3);
    for (r, row) in t.rows.iter().zip(&rows) {
        assert_eq!(row[col("case_index")].parse::<usize>().unwrap(), r.index);
        assert_eq!(num(&row[col("inputs/actuator_0.x_e")]), r.inputs[0]);
        assert_eq!(num(&row[col(&format!("net_power {}", t.actuators[0]))]), r.net_power[0]);
        assert_eq!(num(&row[col(&format!("force_amplitude {}", t.links[0]))]), r.force_amplitude[0]);
        assert_eq!(num(&row[col("balance_error")]), r.balance_error);
    }
}

#[test]
fn every_positional_argument_has_help() {
    use clap::CommandFactory;
    fn walk(cmd: &clap::Command, path: &str, missing: &mut Vec<String>) {
        for a in cmd.get_positionals() {
            if a.get_help().is_none() && a.get_long_help().is_none() {
                missing.push(format!("{path} <{}>", a.get_id()));
            }
        }
        for sub in cmd.get_subcommands() {
            walk(sub, &format!("{path} {}", sub.get_name()), missing);
        }
    }
    let mut missing = Vec::new();
    walk(&beamflow::app::cli::Cli::command(), "beamflow", &mut missing);
    assert!(missing.is_empty(), "positional arguments without help: {missing:?}");
}

/// Each task reported: its label, its total and its (position, message) updates.
type TaskLog = std::rc::Rc<std::cell::RefCell<Vec<(String, Option<u64>, Vec<(u64, String)>)>>>;

/// Records what tasks report.
#[derive(Default)]
struct Recorder(TaskLog);

struct RecorderBar(TaskLog, usize);

impl beamflow::progress::Observer for Recorder {
    fn start(&self, label: &str, total: Option<u64>, _unit: &str) -> Box<dyn beamflow::progress::Bar> {
        let mut log = self.0.borrow_mut();
        log.push((label.to_string(), total, Vec::new()));
        Box::new(RecorderBar(self.0.clone(), log.len() - 1))
    }
}

impl beamflow::progress::Bar for RecorderBar {
    fn update(&self, position: u64, message: &str) {
        self.0.borrow_mut()[self.1].2.push((position, message.to_string()));
    }
}

#[test]
fn long_runs_report_periods_settling_and_harmonics() {
    use beamflow::analysis::case_run::AnalysisResult;
    let lc = common::case(
        "[beam.mesh]\nelements = 20\n[damping]\nkind = \"rayleigh\"\na0 = 5.0\na1 = 1e-5\n\
         [[actuator]]\ntype = \"inertial\"\n[actuator.voltage]\nkind = \"sine\"\namplitude = 12.0\nfrequency = 60.0\n\
         [[analysis]]\ntype = \"steady_state\"\nharmonics = 5\nsamples_per_period = 64\n\
         [[analysis]]\ntype = \"transient\"\nmax_periods = 300\n",
    );
    let rec = Recorder::default();
    let log = rec.0.clone();
    let run = beamflow::progress::observe(std::rc::Rc::new(rec), || beamflow::app::runner::run_case(&lc)).unwrap();
    let AnalysisResult::Transient(t) = &run.results[1] else { panic!("transient second") };
    let log = log.borrow();
    let (_, total, updates) = log.iter().find(|(l, _, _)| l == "transient").expect("a transient task");
    assert_eq!(*total, Some(300));
    let (last, message) = updates.last().unwrap();
    assert_eq!(*last as usize, t.periods_run);
    assert!(t.converged && message.contains(&format!("{:.1e}", t.settling_estimate)), "{message}");
    // The steady state's harmonic solves: the odd harmonics of the sine drive, counted.
    assert!(log.iter().any(|(l, total, _)| l == "steady state" && total.is_some_and(|n| n >= 3)), "{:?}", *log);
    // Nothing is reported once the observer is gone.
    assert!(!beamflow::progress::Task::start("after", None, "x").watched());
}
