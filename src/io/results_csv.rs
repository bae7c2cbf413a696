//! A run's results as tidy CSV tables (`--csv`), made from the same layout as the HDF5 file
//! ([`super::results::write_into`] into an in-memory tree), so every value and unit equals
//! the file's. Column names are the datasets' names (paths below the analysis group for the
//! time series), complex amplitudes split into `re` and `im`.
//!
//! Per analysis `analysis_<i>_<type>` (documented in docs/results-format.md):
//! * transient and steady state: `series` (time histories), `spectra` (per link and
//!   harmonic), `load_spectra`, `point_power`, `net_power`; the steady state's mode-resolved
//!   view as `modal_modes`, `modal_point_power` and `modal_harmonics`; a non-periodic
//!   transient's `record_points` and `record_drives`;
//! * modes: `modes` and `mode_shapes`;
//! * harmonic: `harmonic` (per frequency) and `harmonic_points` (per point and frequency).

use super::csv::{Column, Table};
use super::tree::{Attr, Data, Dataset, Group, TreeSink};
use crate::analysis::case_run::CaseRun;
use crate::case::LoadedCase;
use crate::error::Result;
use std::path::{Path, PathBuf};

/// Writes the run's tables as `<stem>_<analysis group>_<table>.csv` into `dir` (each file
/// atomically) and returns their paths.
pub fn write(dir: &Path, stem: &str, lc: &LoadedCase, run: &CaseRun) -> Result<Vec<PathBuf>> {
    let sink = TreeSink::new();
    super::results::write_into(&sink, lc, run)?;
    let mut written = Vec::new();
    for (name, table) in tables(&sink.tree()) {
        let p = crate::io::paths::output_file(dir, &format!("{stem}_{name}.csv"))?;
        table.write(&p)?;
        written.push(p);
    }
    Ok(written)
}

/// Every table of a results tree, named `<analysis group>_<table>`.
pub fn tables(root: &Group) -> Vec<(String, Table)> {
    let actuators: Vec<String> = match root.dataset("model/actuators").map(|d| &d.data) {
        // Listed as "name (kind)".
        Some(Data::StrList(v)) => v.iter().map(|s| s.split(" (").next().unwrap_or(s).to_string()).collect(),
        _ => Vec::new(),
    };
    let mut out = Vec::new();
    for (gname, g) in &root.groups {
        if !gname.starts_with("analysis_") {
            continue;
        }
        let mut add = |name: &str, t: Option<Table>| {
            if let Some(t) = t.filter(|t| t.rows() > 0) {
                out.push((format!("{gname}_{name}"), t));
            }
        };
        if gname.ends_with("_modes") {
            add("modes", modes(g));
            add("mode_shapes", mode_shapes(g));
            if let Some(c) = g.group("coupled") {
                add("coupled_modes", per_index(c, "frequencies_hz", Some("mode"), &[]));
                add(
                    "coupled_mode_shapes",
                    g.datasets.get("node_x").and_then(|x| shapes(g, x, c.datasets.get("shapes_w")?)),
                );
            }
        } else if gname.ends_with("_harmonic") {
            add("harmonic", harmonic(g));
            add("harmonic_points", harmonic_points(g));
            add("transfer_velocity", transfer(g, "transfer_velocity", "point_names", "point"));
            add("transfer_interface", transfer(g, "transfer_interface", "link_names", "link"));
        } else {
            add("series", series(g));
            add("spectra", Some(long(g.group("spectra"), "link", "frequency")));
            add("load_spectra", Some(long(g.group("loads"), "load", "frequency")));
            add("point_power", point_power(g));
            add("net_power", net_power(g, &actuators));
            if let Some(m) = g.group("modal") {
                let per_mode =
                    ["dissipation", "kinetic_energy", "strain_energy", "power_participation", "response_participation"];
                add("modal_modes", per_index(m, "mode_frequency_hz", Some("mode"), &per_mode));
                add("modal_point_power", modal_point_power(m, g));
                add("modal_harmonics", modal_harmonics(m, &actuators));
            }
            for q in ["force", "acceleration", "power"] {
                add(&format!("measurements_{q}"), measurements(g, q));
            }
            if let Some(r) = g.group("record") {
                add("record_points", record(r, "points", "point"));
                add("record_drives", record(r, "drives", "drive"));
            }
        }
    }
    out
}

fn real(d: &Dataset) -> Option<&[f64]> {
    match &d.data {
        Data::F64(v) => Some(v),
        _ => None,
    }
}

fn strings(g: &Group, name: &str) -> Vec<String> {
    match g.datasets.get(name).map(|d| &d.data) {
        Some(Data::StrList(v)) => v.clone(),
        _ => Vec::new(),
    }
}

fn attr_f64(g: &Group, name: &str) -> f64 {
    match g.attrs.get(name) {
        Some(Attr::F64(x)) => *x,
        _ => f64::NAN,
    }
}

/// A 1-D dataset as columns (two for a complex one) named `name`, if it has `n` values.
fn columns(name: &str, d: &Dataset, n: usize) -> Vec<Column> {
    if d.shape.len() != 1 || d.shape[0] != n {
        return Vec::new();
    }
    match &d.data {
        Data::F64(v) => vec![Column::num(name, &d.unit, v.clone())],
        Data::C64(v) => Column::complex(name, &d.unit, v).into(),
        _ => Vec::new(),
    }
}

/// 1-based indices 1..=n.
fn one_based(n: usize) -> Vec<i64> {
    (1..=n as i64).collect()
}

/// The time histories: `t`, then every real series of the same length below `links/`,
/// `bodies/`, `drives/`, `sensors/` and `loads/`, named by its path.
fn series(g: &Group) -> Option<Table> {
    let t = g.datasets.get("t")?;
    let n = t.shape[0];
    let mut table = Table::default();
    table.columns.extend(columns("t", t, n));
    for coll in ["links", "bodies", "drives", "sensors", "loads"] {
        for (member, mg) in g.group(coll).map(|c| &c.groups).into_iter().flatten() {
            for (name, d) in &mg.datasets {
                if real(d).is_some() {
                    table.columns.extend(columns(&format!("{coll}/{member}/{name}"), d, n));
                }
            }
        }
    }
    Some(table)
}

/// A long table of a collection's members (`key` column), one row per entry of each
/// member's `index` dataset: that dataset, then the member's other 1-D datasets of the
/// same length. Members without `index` are left out.
fn long(coll: Option<&Group>, key: &str, index: &str) -> Table {
    let mut table = Table::default();
    for (member, mg) in coll.map(|c| &c.groups).into_iter().flatten() {
        let Some(ix) = mg.datasets.get(index) else { continue };
        let n = ix.shape[0];
        let mut t = Table::default();
        t.push(Column::text(key, vec![member.clone(); n]));
        t.push(Column::int("harmonic", (0..n as i64).collect()));
        t.columns.extend(columns(index, ix, n));
        for (name, d) in mg.datasets.iter().filter(|(name, _)| name.as_str() != index) {
            t.columns.extend(columns(name, d, n));
        }
        table.append(t);
    }
    table
}

/// Mean power per point: links (`mean_power` in the order of `link_names`) and point loads.
fn point_power(g: &Group) -> Option<Table> {
    let mut names = strings(g, "link_names");
    let mut power = real(g.datasets.get("mean_power")?)?.to_vec();
    let mut kind = vec!["link".to_string(); names.len()];
    // Each point's group and the prefix of its position attributes.
    let mut at: Vec<(Option<&Group>, &str)> = names.iter().map(|l| (g.group(&format!("links/{l}")), "foot_")).collect();
    for (name, lg) in g.group("loads").map(|c| &c.groups).into_iter().flatten() {
        if lg.attrs.contains_key("mean_power_W") {
            names.push(name.clone());
            kind.push("load".into());
            at.push((Some(lg), ""));
            power.push(attr_f64(lg, "mean_power_W"));
        }
    }
    let mut t = Table::default();
    t.push(Column::text("point", names));
    t.push(Column::text("kind", kind));
    t.columns.extend(point_places(&at));
    t.push(Column::num("mean_power", "W", power));
    if let Some(m) = g.group("modal") {
        let residual: Vec<f64> = ["point_residual", "load_residual"]
            .iter()
            .filter_map(|n| m.datasets.get(*n).and_then(real))
            .flatten()
            .copied()
            .collect();
        if residual.len() == t.rows() {
            t.push(Column::num("modal_residual", "W", residual));
        }
    }
    Some(t)
}

/// Net power per actuator.
fn net_power(g: &Group, actuators: &[String]) -> Option<Table> {
    let d = g.datasets.get("net_power")?;
    let mut t = Table::default();
    t.push(Column::text("actuator", actuators.to_vec()));
    t.columns.extend(columns("net_power", d, actuators.len()));
    Some(t)
}

/// One row per entry of `index` (a 1-D dataset of `g`), numbered from 1 in `counter`
/// (None: no counter), with the datasets `others` of `g` (those present, of the same
/// length; named, since another of the same length may index something else).
fn per_index(g: &Group, index: &str, counter: Option<&str>, others: &[&str]) -> Option<Table> {
    let ix = g.datasets.get(index)?;
    let n = ix.shape[0];
    let mut t = Table::default();
    if let Some(c) = counter {
        t.push(Column::int(c, one_based(n)));
    }
    t.columns.extend(columns(index, ix, n));
    for name in others {
        t.columns.extend(g.datasets.get(*name).map(|d| columns(name, d, n)).unwrap_or_default());
    }
    Some(t)
}

/// A matrix dataset (rows × columns, row-major) in long form: the row's label columns, the
/// column's label columns, the value. Labels must match the matrix's shape.
fn matrix_long(d: &Dataset, rows: &[Column], cols: &[Column], name: &str) -> Option<Table> {
    let (&[nr, nc], Some(v)) = (d.shape.as_slice(), real(d)) else { return None };
    if rows.iter().any(|c| c.cells.len() != nr) || cols.iter().any(|c| c.cells.len() != nc) {
        return None;
    }
    let mut t = Table::default();
    for c in rows {
        t.push(c.select((0..nr * nc).map(|i| i / nc)));
    }
    for c in cols {
        t.push(c.select((0..nr * nc).map(|i| i % nc)));
    }
    t.push(Column::num(name, &d.unit, v.to_vec()));
    Some(t)
}

/// The modes' columns of a modal group: number and bare-beam frequency.
fn mode_columns(m: &Group) -> Option<Vec<Column>> {
    let f = m.datasets.get("mode_frequency_hz")?;
    let n = f.shape[0];
    let mut c = vec![Column::int("mode", one_based(n))];
    c.extend(columns("mode_frequency_hz", f, n));
    Some(c)
}

/// Power per point and mode, links then loads.
fn modal_point_power(m: &Group, g: &Group) -> Option<Table> {
    let modes = mode_columns(m)?;
    let mut t = Table::default();
    for (data, names, kind) in
        [("point_power", strings(g, "link_names"), "link"), ("load_power", strings(m, "load_names"), "load")]
    {
        let Some(d) = m.datasets.get(data) else { continue };
        let rows = [Column::text("point", names.clone()), Column::text("kind", vec![kind.to_string(); names.len()])];
        if let Some(part) = matrix_long(d, &rows, &modes, "power") {
            t.append(part);
        }
    }
    Some(t)
}

/// Modal amplitudes and generalised forces per harmonic and mode.
fn modal_harmonics(m: &Group, actuators: &[String]) -> Option<Table> {
    let modes = mode_columns(m)?;
    let f = m.datasets.get("frequency")?;
    let harm = [Column::int("harmonic", (0..f.shape[0] as i64).collect()), columns("frequency", f, f.shape[0]).pop()?];
    let mut t = matrix_long(m.datasets.get("eta_abs")?, &harm, &modes, "eta_abs")?;
    for a in actuators {
        let name = format!("generalised_force_abs_{a}");
        if let Some(d) = m.datasets.get(&name) {
            let part = matrix_long(d, &harm, &modes, &name)?;
            t.columns.push(part.columns.last()?.clone());
        }
    }
    Some(t)
}

/// A record analysis' points or drives: one row per member and frequency bin.
fn record(r: &Group, coll: &str, key: &str) -> Option<Table> {
    let f = r.datasets.get("frequency")?;
    let n = f.shape[0];
    let mut table = Table::default();
    for (member, mg) in &r.group(coll)?.groups {
        let mut t = Table::default();
        t.push(Column::text(key, vec![member.clone(); n]));
        t.columns.extend(columns("frequency", f, n));
        for (name, d) in &mg.datasets {
            t.columns.extend(columns(name, d, n));
        }
        table.append(t);
    }
    Some(table)
}

/// Each measurement of `quantity` against the prediction: one row per measurement and
/// harmonic compared.
fn measurements(g: &Group, quantity: &str) -> Option<Table> {
    let mut table = Table::default();
    for (name, mg) in &g.group("measurements")?.groups {
        let Some(q) = mg.groups.get(quantity) else { continue };
        let n = q.datasets.get("harmonic")?.shape[0];
        let point = match q.attrs.get("point") {
            Some(Attr::Str(p)) => p.clone(),
            _ => String::new(),
        };
        let mut t = Table::default();
        t.push(Column::text("measurement", vec![name.clone(); n]));
        t.push(Column::text("point", vec![point; n]));
        if let Some(Data::I64(k)) = q.datasets.get("harmonic").map(|d| &d.data) {
            t.push(Column::int("harmonic", k.clone()));
        }
        for d in ["frequency", "measured", "predicted", "error_db", "phase_error"] {
            t.columns.extend(q.datasets.get(d).map(|ds| columns(d, ds, n)).unwrap_or_default());
        }
        table.append(t);
    }
    Some(table)
}

/// The points' positions from their groups' attributes (`<prefix>x_m`, …): `x`, and where
/// any point has them `y`, `z` (m), `node` and `component` (an imported model's). A point
/// without a position (a foot on the ground) has NaN, −1 and an empty component.
fn point_places(at: &[(Option<&Group>, &str)]) -> Vec<Column> {
    let f = |key: &str| -> Vec<f64> {
        at.iter().map(|(g, p)| g.map_or(f64::NAN, |g| attr_f64(g, &format!("{p}{key}")))).collect()
    };
    let has = |key: &str| at.iter().any(|(g, p)| g.is_some_and(|g| g.attrs.contains_key(&format!("{p}{key}"))));
    let mut cols = vec![Column::num("x", "m", f("x_m"))];
    for key in ["y", "z"].into_iter().filter(|k| has(&format!("{k}_m"))) {
        cols.push(Column::num(key, "m", f(&format!("{key}_m"))));
    }
    if has("node") {
        let node = |(g, p): &(Option<&Group>, &str)| match g.and_then(|g| g.attrs.get(&format!("{p}node"))) {
            Some(Attr::I64(n)) => *n,
            _ => -1,
        };
        let component = |(g, p): &(Option<&Group>, &str)| match g.and_then(|g| g.attrs.get(&format!("{p}component"))) {
            Some(Attr::Str(c)) => c.clone(),
            _ => String::new(),
        };
        cols.push(Column::int("node", at.iter().map(node).collect()));
        cols.push(Column::text("component", at.iter().map(component).collect()));
    }
    cols
}

/// The bare beam's natural frequencies, with the closed-form ones where they exist.
fn modes(g: &Group) -> Option<Table> {
    per_index(g, "frequencies_hz", Some("mode"), &["analytic_hz", "relative_error", "roundoff_bound"])
}

/// Mode shapes: node coordinate, then one column per mode.
fn mode_shapes(g: &Group) -> Option<Table> {
    shapes(g, g.datasets.get("node_x")?, g.datasets.get("shapes_w")?)
}

/// Node coordinates `x` (and, where the modes group `g` has them, `node_y`, `node_z` and
/// `node_id`) and a modes × nodes matrix `s` as columns.
fn shapes(g: &Group, x: &Dataset, s: &Dataset) -> Option<Table> {
    let (&[nm, nx], Some(v)) = (s.shape.as_slice(), real(s)) else { return None };
    let mut t = Table::default();
    t.columns.extend(columns("node_x", x, nx));
    for name in ["node_y", "node_z"] {
        t.columns.extend(g.datasets.get(name).map(|d| columns(name, d, nx)).unwrap_or_default());
    }
    if let Some(Data::I64(id)) = g.datasets.get("node_id").map(|d| &d.data).filter(|_| nx > 0) {
        if id.len() == nx {
            t.push(Column::int("node_id", id.clone()));
        }
    }
    for r in 0..nm {
        t.push(Column::num(format!("shapes_w mode {}", r + 1), &s.unit, v[r * nx..(r + 1) * nx].to_vec()));
    }
    Some(t)
}

/// Per analysis frequency: powers and balance, and the input power of each force point.
fn harmonic(g: &Group) -> Option<Table> {
    let mut t = per_index(g, "frequency_hz", None, &["total_power", "dissipated_power", "balance_error"])?;
    let n = t.rows();
    let names = strings(g, "point_names");
    let d = g.datasets.get("input_power")?;
    if let (&[_, nf], Some(v)) = (d.shape.as_slice(), real(d)) {
        for j in 0..nf {
            let col = (0..n).map(|i| v[i * nf + j]).collect();
            t.push(Column::num(format!("input_power {}", names.get(j).map_or("?", String::as_str)), &d.unit, col));
        }
    }
    Some(t)
}

/// A coupled system's transfer functions `name` (frequency × (output · input)) in long
/// form: output (`key`, named by `labels`), input, frequency; the complex value as real
/// and imaginary parts, magnitude and phase.
fn transfer(g: &Group, name: &str, labels: &str, key: &str) -> Option<Table> {
    let d = g.datasets.get(name)?;
    let Data::C64(v) = &d.data else { return None };
    let (outputs, inputs) = (strings(g, labels), strings(g, "transfer_inputs"));
    let f = real(g.datasets.get("frequency_hz")?)?;
    let (nf, no, ni) = (f.len(), outputs.len(), inputs.len());
    if d.shape != [nf, no * ni] {
        return None;
    }
    let rows = nf * no * ni;
    // Row order: output, input, frequency (each output's FRFs contiguous).
    let at = |r: usize| (r / (ni * nf), (r / nf) % ni, r % nf);
    let value: Vec<num_complex::Complex64> = (0..rows)
        .map(|r| {
            let (o, i, k) = at(r);
            v[k * no * ni + o * ni + i]
        })
        .collect();
    let mut t = Table::default();
    t.push(Column::text(key, (0..rows).map(|r| outputs[at(r).0].clone()).collect()));
    t.push(Column::text("input", (0..rows).map(|r| inputs[at(r).1].clone()).collect()));
    t.push(Column::num("frequency_hz", "Hz", (0..rows).map(|r| f[at(r).2]).collect()));
    t.columns.extend(Column::complex(name, &d.unit, &value));
    t.push(Column::num(format!("|{name}|"), &d.unit, value.iter().map(|c| c.norm()).collect()));
    t.push(Column::num(format!("{name} phase"), "rad", value.iter().map(|c| c.arg()).collect()));
    Some(t)
}

/// Per response point and frequency: velocity under all forces and mobility to each force.
fn harmonic_points(g: &Group) -> Option<Table> {
    let f = g.datasets.get("frequency_hz")?;
    let nfreq = f.shape[0];
    let names = strings(g, "point_names");
    let vel = g.datasets.get("velocity")?;
    let mob = g.datasets.get("mobility")?;
    let (Data::C64(v), Data::C64(m)) = (&vel.data, &mob.data) else { return None };
    let np = names.len();
    let nforce = mob.shape.get(1).copied().unwrap_or(0).checked_div(np).unwrap_or(0);
    let mut table = Table::default();
    for (i, p) in names.iter().enumerate() {
        let mut t = Table::default();
        t.push(Column::text("point", vec![p.clone(); nfreq]));
        t.columns.extend(columns("frequency_hz", f, nfreq));
        let col = |k: usize, data: &[num_complex::Complex64], stride: usize| -> Vec<num_complex::Complex64> {
            (0..nfreq).map(|r| data[r * stride + k]).collect()
        };
        t.columns.extend(Column::complex("velocity", &vel.unit, &col(i, v, np)));
        for j in 0..nforce {
            let name = format!("mobility to {}", names.get(j).map_or("?", String::as_str));
            t.columns.extend(Column::complex(&name, &mob.unit, &col(i * nforce + j, m, np * nforce)));
        }
        table.append(t);
    }
    Some(table)
}
