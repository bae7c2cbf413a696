//! The layout of a run's HDF5 file (documented in docs/results-format.md).

use super::hdf5::{utc_timestamp, ResultsFile};
use super::sink::GroupSink;
use crate::actuator::link_id;
use crate::analysis::case_run::Comparison;
use crate::analysis::case_run::{AnalysisResult, CaseRun};
use crate::analysis::harmonic::HarmonicResult;
use crate::analysis::mesh_estimate::MeshCheck;
use crate::analysis::modes::ModesResult;
use crate::analysis::reduction::ReductionReport;
use crate::analysis::series::{
    BodySeries, DriveSeries, LinkSeries, LinkSpectrum, LoadSeries, LoadSpectrum, SensorSeries,
};
use crate::analysis::steady_state::SteadyStateResult;
use crate::analysis::transient::TransientResult;
use crate::case::measured::MeasuredQuantity;
use crate::case::LoadedCase;
use crate::error::Result;
use crate::power::balance::EnergyBalance;
use crate::power::record::RecordAnalysis;
use crate::structure::{Location, Structure};
use std::path::Path;

/// Writes one self-describing file for a case run (atomically).
pub fn write(path: &Path, lc: &LoadedCase, run: &CaseRun) -> Result<()> {
    let f = ResultsFile::create(path)?;
    write_into(&f.root_group(), lc, run)?;
    f.finish()
}

/// Writes the layout of a case run into a root group: an HDF5 file's ([`write`]) or an
/// in-memory tree's ([`crate::io::tree::TreeSink`]).
pub fn write_into<S: GroupSink>(f: &S, lc: &LoadedCase, run: &CaseRun) -> Result<()> {
    f.attr_str("program", "beamflow")?;
    f.attr_str("version", env!("CARGO_PKG_VERSION"))?;
    f.attr_str("case_file", &lc.file)?;
    f.attr_str("title", &lc.case.title)?;
    f.attr_str("created", &utc_timestamp())?;
    f.attr_str("sign_convention", "forces and displacements positive up (+w); power positive into the base; complex amplitudes q(t) = Re(Q·exp(+iωt))")?;
    f.group("case")?.write_str("toml", &lc.text)?;
    let m = f.group("model")?;
    write_provenance(&m, lc)?;
    m.attr_i64("n_dofs", run.system.n() as i64)?;
    m.attr_f64("rayleigh_a0", run.model.rayleigh().a0)?;
    m.attr_f64("rayleigh_a1", run.model.rayleigh().a1)?;
    if let Some(s) = &run.model.structure {
        m.attr_str("structure", s.kind())?;
        let at: Vec<_> = (0..s.n_nodes()).map(|n| s.node_location(n)).collect();
        let x: Vec<f64> = at.iter().map(|a| a.x()).collect();
        m.write_f64("node_x", &x, &[x.len()], "m", "structure node coordinates")?;
        write_node_places(&m, &at)?;
    }
    m.write_str_list(
        "actuators",
        &run.model.actuators.iter().map(|a| format!("{} ({})", a.name(), a.kind())).collect::<Vec<_>>(),
    )?;
    for (i, r) in run.results.iter().enumerate() {
        match r {
            AnalysisResult::Modes(x) => {
                write_modes(&f.group(&format!("analysis_{i}_modes"))?, x, run.model.structure.as_ref())?
            }
            AnalysisResult::Harmonic(x) => write_harmonic(&f.group(&format!("analysis_{i}_harmonic"))?, x)?,
            AnalysisResult::Transient(x) => write_transient(&f.group(&format!("analysis_{i}_transient"))?, x, run)?,
            AnalysisResult::SteadyState(x) => write_steady(&f.group(&format!("analysis_{i}_steady_state"))?, x, run)?,
        }
    }
    for (i, m) in run.mesh.iter().enumerate() {
        let kind = match run.results[i] {
            AnalysisResult::Transient(_) => "transient",
            _ => "steady_state",
        };
        if let Some(m) = m {
            write_mesh_estimate(&f.group(&format!("analysis_{i}_{kind}/mesh_estimate"))?, m)?;
        }
    }
    for c in &run.measured {
        let kind = match run.results[c.analysis] {
            AnalysisResult::Transient(_) => "transient",
            _ => "steady_state",
        };
        write_measured(&f.group(&format!("analysis_{}_{kind}/measurements/{}", c.analysis, c.name))?, c)?;
    }
    Ok(())
}

/// What the run was made from: the program version, the hashes of the case text and of
/// the files it reads (a mesh file, an imported model's), and every
/// parameter of the case as resolved (defaults filled in), under `parameters/` — the
/// structure, each actuator's stack, body and drive, the damping, the analyses — so that
/// the file alone says what was computed.
fn write_provenance<S: GroupSink>(m: &S, lc: &LoadedCase) -> Result<()> {
    m.attr_str("version", env!("CARGO_PKG_VERSION"))?;
    m.attr_str("case_hash", &super::hash::text_hash(&lc.text))?;
    if let Some((_, file)) = lc.case.mesh_file() {
        let p = lc.dir.join(file);
        m.attr_str("mesh_hash", &super::hash::file_hash(&p).map_err(|e| crate::error::Error::io(&p, e))?)?;
    }
    if let Some(spec) = &lc.case.imported {
        let f = spec.files(&lc.dir);
        let named = [("mass", Some(&f.mass)), ("stiffness", Some(&f.stiffness)), ("damping", f.damping.as_ref())];
        for (role, path) in named.into_iter().chain([("dofs", Some(&f.dofs))]) {
            if let Some(p) = path {
                let h = super::hash::file_hash(p).map_err(|e| crate::error::Error::io(p, e))?;
                m.attr_str(&format!("imported_{role}_hash"), &h)?;
            }
        }
    }
    let resolved =
        toml::Value::try_from(&lc.case).map_err(|e| crate::error::Error::input(&lc.file, "case", e.to_string()))?;
    m.write_str("resolved_toml", &toml::to_string(&resolved).unwrap_or_default())?;
    if let toml::Value::Table(t) = &resolved {
        let p = m.group("parameters")?;
        p.attr_str("units", "SI, as in the case file (docs/case-format.md)")?;
        write_table(&p, t)?;
    }
    Ok(())
}

/// A TOML table as a group: tables as groups, arrays of tables as groups `<name>_<i>`,
/// numbers, booleans and text as attributes, arrays of numbers as datasets.
fn write_table<S: GroupSink>(g: &S, t: &toml::map::Map<String, toml::Value>) -> Result<()> {
    use toml::Value;
    for (k, v) in t {
        match v {
            Value::Table(sub) => write_table(&g.group(k)?, sub)?,
            Value::Float(x) => g.attr_f64(k, *x)?,
            Value::Integer(i) => g.attr_i64(k, *i)?,
            Value::Boolean(b) => g.attr_str(k, if *b { "true" } else { "false" })?,
            Value::String(s) => g.attr_str(k, s)?,
            Value::Datetime(d) => g.attr_str(k, &d.to_string())?,
            Value::Array(a) if !a.is_empty() && a.iter().all(Value::is_table) => {
                for (i, x) in a.iter().enumerate() {
                    write_table(&g.group(&format!("{k}_{i}"))?, x.as_table().expect("a table"))?;
                }
            }
            Value::Array(a) if a.iter().all(|x| x.is_float() || x.is_integer()) => {
                let x: Vec<f64> =
                    a.iter().map(|x| x.as_float().or(x.as_integer().map(|i| i as f64)).unwrap_or(0.0)).collect();
                g.write_f64(k, &x, &[x.len()], "", "as in the case file")?;
            }
            Value::Array(a) => g.write_str_list(k, &a.iter().map(|x| x.to_string()).collect::<Vec<_>>())?,
        }
    }
    Ok(())
}

/// A measurement against the analysis' prediction, under `measurements/<name>/<quantity>`.
fn write_measured<S: GroupSink>(g: &S, c: &Comparison) -> Result<()> {
    let q = g.group(c.quantity.name())?;
    q.attr_str("file", &c.file)?;
    q.attr_str("point", &c.point)?;
    q.attr_str("unit", c.unit())?;
    q.attr_f64("max_abs_error_db", c.max_abs_error_db())?;
    if c.rms_error.is_finite() {
        q.attr_f64("rms_error", c.rms_error)?;
        q.attr_f64("relative_rms_error", c.relative_rms_error)?;
    }
    if let (Some(t), Some(ok)) = (c.tolerance_db, c.agrees()) {
        q.attr_f64("tolerance_db", t)?;
        q.attr_i64("agrees", ok as i64)?;
    }
    let n = c.harmonic.len();
    q.write_i64(
        "harmonic",
        &c.harmonic.iter().map(|&k| k as i64).collect::<Vec<_>>(),
        &[n],
        "1",
        "harmonics compared: present in both within 60 dB of their largest line",
    )?;
    q.write_f64("frequency", &c.frequency, &[n], "Hz", "k/T")?;
    if c.quantity == MeasuredQuantity::Power {
        let re = |v: &[num_complex::Complex64]| v.iter().map(|x| x.re).collect::<Vec<_>>();
        q.write_f64("measured", &re(&c.measured), &[n], "W", "measured power per harmonic -0.5*Im(F*conj(A))/w")?;
        q.write_f64("predicted", &re(&c.predicted), &[n], "W", "predicted power per harmonic, the same way")?;
        q.write_f64("error_db", &c.error_db, &[n], "dB", "10*log10|measured/predicted|")?;
        q.write_f64("phase_error", &c.phase_error, &[n], "rad", "0 where the signs agree, pi where they differ")
    } else {
        q.write_c64("measured", &c.measured, &[n], c.unit(), "measured complex amplitude (least-squares fit)")?;
        q.write_c64("predicted", &c.predicted, &[n], c.unit(), "predicted complex amplitude")?;
        q.write_f64("error_db", &c.error_db, &[n], "dB", "20*log10|measured/predicted|")?;
        q.write_f64("phase_error", &c.phase_error, &[n], "rad", "arg(measured/predicted)")
    }
}

fn write_modes<S: GroupSink>(g: &S, r: &ModesResult, structure: Option<&Structure>) -> Result<()> {
    let n = r.frequencies_hz.len();
    g.attr_str("reference", &r.reference)?;
    g.attr_i64("rigid_body_modes", r.rigid_body_modes as i64)?;
    g.write_f64("frequencies_hz", &r.frequencies_hz, &[n], "Hz", "natural frequencies of the bare beam")?;
    if !r.analytic_hz.is_empty() {
        g.write_f64("analytic_hz", &r.analytic_hz, &[r.analytic_hz.len()], "Hz", "closed-form natural frequencies")?;
        g.write_f64(
            "relative_error",
            &r.relative_error,
            &[r.relative_error.len()],
            "1",
            "(f - f_analytic)/f_analytic",
        )?;
    }
    g.write_f64(
        "roundoff_bound",
        &r.roundoff_bound,
        &[r.roundoff_bound.len()],
        "1",
        "order-of-magnitude bound on each frequency's relative round-off",
    )?;
    let nx = r.node_x.len();
    g.write_f64("node_x", &r.node_x, &[nx], "m", "node coordinates")?;
    if let Some(s) = structure {
        write_node_places(g, &(0..s.n_nodes()).map(|n| s.node_location(n)).collect::<Vec<_>>())?;
    }
    let flat: Vec<f64> = r.shapes_w.iter().flatten().copied().collect();
    g.write_f64(
        "shapes_w",
        &flat,
        &[n, nx],
        "m/sqrt(kg)",
        "mass-normalised mode shapes: w at each node, one row per mode",
    )?;
    if let Some(c) = &r.coupled {
        let cg = g.group("coupled")?;
        let n = c.frequencies_hz.len();
        cg.write_f64("frequencies_hz", &c.frequencies_hz, &[n], "Hz", "natural frequencies of beam and actuators")?;
        cg.write_f64(
            "shapes_w",
            &c.shapes_w.concat(),
            &[n, nx],
            "m/sqrt(kg)",
            "coupled mode shapes, mass-normalised over the whole system: w at each node, one row per mode",
        )?;
        cg.write_str_list("body_names", &c.body_names)?;
        cg.write_f64(
            "body_shapes",
            &c.body_shapes.concat(),
            &[n, c.body_names.len()],
            "m/sqrt(kg)",
            "each mode on the actuators' body DOFs (columns: body_names; rad/sqrt(kg) for rotations)",
        )?;
    }
    Ok(())
}

fn write_harmonic<S: GroupSink>(g: &S, r: &HarmonicResult) -> Result<()> {
    let nf = r.frequency_hz.len();
    let np = r.point_x.len();
    let nforce = r.input_power.first().map_or(0, Vec::len);
    g.attr_f64("mesh_roundoff", r.mesh_roundoff)?;
    g.attr_i64("forced", r.forced() as i64)?;
    g.write_f64("frequency_hz", &r.frequency_hz, &[nf], "Hz", "analysis frequencies")?;
    g.write_f64("point_x", &r.point_x, &[np], "m", "response points: force points, sensors, then (coupled) link feet")?;
    write_point_places(g, &r.point_at)?;
    g.write_str_list("point_names", &r.point_names)?;
    let mob: Vec<_> = r.mobility.iter().flat_map(|m| m.iter().flatten().copied()).collect();
    g.write_c64(
        "mobility",
        &mob,
        &[nf, np * nforce],
        "m/(N*s)",
        "mobility V_i/F_j; row per frequency, column i*n_forces + j",
    )?;
    let vel: Vec<_> = r.velocity.iter().flatten().copied().collect();
    g.write_c64("velocity", &vel, &[nf, np], "m/s", "velocity at each response point under all forces")?;
    let pin: Vec<f64> = r.input_power.iter().flatten().copied().collect();
    g.write_f64("input_power", &pin, &[nf, nforce], "W", "time-averaged input power per force point")?;
    g.write_f64("total_power", &r.total_power, &[nf], "W", "sum over force points")?;
    g.write_f64(
        "dissipated_power",
        &r.dissipated_power,
        &[nf],
        "W",
        "dissipation 0.5*w^2*Q^H*C*Q (beam, and the links' dampers)",
    )?;
    g.write_f64("balance_error", &r.balance_error, &[nf], "1", "|total - dissipated|/dissipated")?;
    let ni = r.transfer_inputs.len();
    if ni > 0 {
        let nl = r.link_names.len();
        g.write_str_list("transfer_inputs", &r.transfer_inputs)?;
        g.write_str_list("link_names", &r.link_names)?;
        let flat = |t: &[Vec<Vec<num_complex::Complex64>>]| {
            t.iter().flat_map(|m| m.iter().flatten().copied()).collect::<Vec<_>>()
        };
        g.write_c64(
            "transfer_velocity",
            &flat(&r.transfer_velocity),
            &[nf, np * ni],
            "m/(N*s)",
            "coupled system: velocity at point i per unit input j (a foot force or a stack force); column i*n_inputs + j",
        )?;
        g.write_c64(
            "transfer_interface",
            &flat(&r.transfer_interface),
            &[nf, nl * ni],
            "1",
            "coupled system: interface force under link l per unit input j (N/N); column l*n_inputs + j",
        )?;
    }
    Ok(())
}

/// Where a point is beyond its x (which each group writes under its own name): attribute
/// `<prefix>y_m` (m) on a plate and an imported model; `<prefix>z_m` (m), `<prefix>node`
/// (the source model's id) and `<prefix>component` (`uz`, `-uz`, …) on an imported model.
/// Nothing on a beam, whose groups stay as they were.
fn write_place<S: GroupSink>(g: &S, prefix: &str, at: &Location) -> Result<()> {
    if let Some(y) = at.y() {
        g.attr_f64(&format!("{prefix}y_m"), y)?;
    }
    if let Some(z) = at.z() {
        g.attr_f64(&format!("{prefix}z_m"), z)?;
    }
    if let Some((node, component)) = at.node_component() {
        g.attr_i64(&format!("{prefix}node"), node)?;
        g.attr_str(&format!("{prefix}component"), &component)?;
    }
    Ok(())
}

/// The nodes' coordinates beyond `node_x`: `node_y` (m) on a plate and an imported model,
/// `node_z` (m) and `node_id` on an imported model.
fn write_node_places<S: GroupSink>(g: &S, at: &[Location]) -> Result<()> {
    let y: Vec<f64> = at.iter().filter_map(Location::y).collect();
    if !y.is_empty() {
        g.write_f64("node_y", &y, &[y.len()], "m", "node y coordinates (plate or imported model)")?;
    }
    let z: Vec<f64> = at.iter().filter_map(Location::z).collect();
    if !z.is_empty() {
        g.write_f64("node_z", &z, &[z.len()], "m", "node z coordinates (imported model)")?;
    }
    let id: Vec<i64> = at.iter().filter_map(|a| a.node_component()).map(|p| p.0).collect();
    if !id.is_empty() {
        g.write_i64("node_id", &id, &[id.len()], "1", "node ids as the imported model numbers them")?;
    }
    Ok(())
}

/// The response points' coordinates beyond `point_x`: `point_y` (m) on a plate and an
/// imported model, `point_z` (m), `point_node` and `point_component` on an imported model.
fn write_point_places<S: GroupSink>(g: &S, at: &[Location]) -> Result<()> {
    let n = at.len();
    let y: Vec<f64> = at.iter().filter_map(Location::y).collect();
    if !y.is_empty() && y.len() == n {
        g.write_f64("point_y", &y, &[n], "m", "response points' y (plate or imported model)")?;
    }
    let z: Vec<f64> = at.iter().filter_map(Location::z).collect();
    if !z.is_empty() && z.len() == n {
        g.write_f64("point_z", &z, &[n], "m", "response points' z (imported model)")?;
    }
    let nodes: Vec<(i64, String)> = at.iter().filter_map(Location::node_component).collect();
    if !nodes.is_empty() && nodes.len() == n {
        let id: Vec<i64> = nodes.iter().map(|p| p.0).collect();
        g.write_i64("point_node", &id, &[n], "1", "response points' node ids (imported model)")?;
        g.write_str_list("point_component", &nodes.into_iter().map(|p| p.1).collect::<Vec<_>>())?;
    }
    Ok(())
}

fn write_energy<S: GroupSink>(g: &S, name: &str, e: &EnergyBalance) -> Result<()> {
    let s = g.group(name)?;
    s.attr_f64("input_J", e.input)?;
    s.attr_f64("dissipated_J", e.dissipated)?;
    s.attr_f64("stored_change_J", e.stored_change)?;
    s.attr_f64("relative_error", e.relative_error())
}

fn link_group_name(run: &CaseRun, l: &LinkSeries) -> String {
    link_id(run.model.actuators[l.actuator].name(), &l.name)
}

fn write_series<S: GroupSink>(
    g: &S,
    t: &[f64],
    links: &[LinkSeries],
    bodies: &[BodySeries],
    drives: &[DriveSeries],
    sensors: &[SensorSeries],
    run: &CaseRun,
) -> Result<()> {
    let n = t.len();
    g.write_f64("t", t, &[n], "s", "sample times of the recorded window")?;
    for l in links {
        let lg = g.group(&format!("links/{}", link_group_name(run, l)))?;
        if let Some(x) = l.foot_x {
            lg.attr_f64("foot_x_m", x)?;
        }
        if let Some(at) = &l.foot_at {
            write_place(&lg, "foot_", at)?;
        }
        for (name, data, unit, desc) in [
            ("stretch", &l.stretch, "m", "u = z_top - z_foot"),
            ("stretch_rate", &l.stretch_rate, "m/s", "du/dt"),
            ("f_stiffness", &l.f_stiffness, "N", "stiffness component k*u of the transmitted force"),
            ("f_damping", &l.f_damping, "N", "damping component c*du/dt"),
            ("f_pzt", &l.f_pzt, "N", "PZT component -F_p (stack only)"),
            ("transmitted", &l.transmitted, "N", "force on the base at the foot, positive up"),
            ("interface", &l.interface, "N", "interface force: transmitted minus foot-mass inertia"),
            ("base_velocity", &l.base_velocity, "m/s", "base velocity at the foot"),
            ("base_acceleration", &l.base_acceleration, "m/s^2", "base acceleration at the foot"),
            ("power", &l.power, "W", "instantaneous power into the base at the foot"),
        ] {
            lg.write_f64(name, data, &[data.len()], unit, desc)?;
        }
    }
    for b in bodies {
        let bg = g.group(&format!("bodies/{}_{}", run.model.actuators[b.actuator].name(), b.dof))?;
        let unit = if b.dof == "phi" { "rad" } else { "m" };
        bg.write_f64("q", &b.q, &[b.q.len()], unit, "body DOF")?;
        bg.write_f64("q_dot", &b.q_dot, &[b.q.len()], &format!("{unit}/s"), "rate")?;
        bg.write_f64("q_ddot", &b.q_ddot, &[b.q.len()], &format!("{unit}/s^2"), "acceleration")?;
    }
    for d in drives {
        let dg = g.group(&format!("drives/{}", run.model.actuators[d.actuator].name()))?;
        dg.write_f64("voltage", &d.voltage, &[d.voltage.len()], "V", "stack voltage")?;
        dg.write_f64("h", &d.h, &[d.h.len()], "m", "Bouc-Wen hysteretic displacement")?;
        dg.write_f64("stroke", &d.stroke, &[d.stroke.len()], "m", "free stroke d_p*V - h")?;
        dg.write_f64("f_p", &d.f_p, &[d.f_p.len()], "N", "active (PZT) force k_p*stroke")?;
    }
    for s in sensors {
        let sg = g.group(&format!("sensors/{}", s.name))?;
        sg.attr_f64("x_m", s.x)?;
        if let Some(at) = &s.at {
            write_place(&sg, "", at)?;
        }
        sg.write_f64("w", &s.w, &[s.w.len()], "m", "beam displacement")?;
        sg.write_f64("v", &s.v, &[s.v.len()], "m/s", "beam velocity")?;
        sg.write_f64("a", &s.a, &[s.a.len()], "m/s^2", "beam acceleration")?;
    }
    Ok(())
}

/// Each point load's group: its series over the recorded window, its mean power into the
/// beam and its power per harmonic.
fn write_loads<S: GroupSink>(g: &S, series: &[LoadSeries], spectra: &[LoadSpectrum]) -> Result<()> {
    for (j, l) in series.iter().enumerate() {
        let lg = g.group(&format!("loads/{}", l.name))?;
        lg.attr_f64("x_m", l.x)?;
        if let Some(at) = &l.at {
            write_place(&lg, "", at)?;
        }
        lg.write_f64("force", &l.force, &[l.force.len()], "N", "prescribed force on the beam, positive up")?;
        lg.write_f64("w", &l.w, &[l.w.len()], "m", "beam displacement at the load")?;
        lg.write_f64("v", &l.v, &[l.v.len()], "m/s", "beam velocity at the load")?;
        lg.write_f64("a", &l.a, &[l.a.len()], "m/s^2", "beam acceleration at the load")?;
        // A non-periodic run has no harmonics: its record analysis stands in.
        let Some(sp) = spectra.get(j) else { continue };
        lg.attr_f64("mean_power_W", sp.power_total)?;
        let n = sp.frequency.len();
        lg.write_f64("frequency", &sp.frequency, &[n], "Hz", "harmonic frequencies k/T")?;
        lg.write_f64("power_per_harmonic", &sp.power, &[n], "W", "1/2 Re(F_k conj V_k) into the beam")?;
        let abs = |c: &[num_complex::Complex64]| c.iter().map(|x| x.norm()).collect::<Vec<_>>();
        lg.write_f64("force_amplitude", &abs(&sp.force), &[n], "N", "|F_k|")?;
        lg.write_f64("velocity_amplitude", &abs(&sp.velocity), &[n], "m/s", "|V_k| at the load")?;
    }
    Ok(())
}

/// A non-periodic run's record analysis: per drive its PSD, per point its energy, PSDs,
/// power spectral density and H1 FRFs with coherence.
fn write_record<S: GroupSink>(g: &S, r: &RecordAnalysis) -> Result<()> {
    let rg = g.group("record")?;
    rg.attr_f64("duration_s", r.duration)?;
    rg.attr_f64("segment_s", r.segment_s)?;
    rg.attr_i64("segments", r.segments as i64)?;
    rg.attr_f64("overlap", r.welch.overlap)?;
    rg.attr_str("window", if r.welch.hann { "hann" } else { "rectangular" })?;
    rg.attr_str("estimator", r.estimate.reason)?;
    rg.attr_str("description", &r.estimate.describe(r.dt, r.segments))?;
    rg.attr_f64("end_activity", r.estimate.end_activity)?;
    rg.attr_f64("band_low_hz", r.band.0)?;
    rg.attr_f64("band_high_hz", r.band.1)?;
    if let Some(c) = r.estimate.min_coherence {
        rg.attr_f64("min_coherence_in_band", c)?;
    }
    rg.attr_i64("trustworthy", r.estimate.warnings.is_empty() as i64)?;
    if !r.estimate.warnings.is_empty() {
        rg.write_str_list("warnings", &r.estimate.warnings)?;
    }
    let n = r.frequency.len();
    rg.write_f64("frequency", &r.frequency, &[n], "Hz", "k / segment length")?;
    rg.write_f64("net_energy", &r.net_energy, &[r.net_energy.len()], "J", "energy into the structure per actuator")?;
    for d in &r.drives {
        let dg = rg.group(&format!("drives/{}", d.name))?;
        dg.write_f64("psd", &d.psd, &[n], &format!("{}^2/Hz", d.unit), "one-sided Welch PSD of the drive")?;
    }
    for p in &r.points {
        let pg = rg.group(&format!("points/{}", p.name))?;
        let unit = r.drives.iter().find(|d| d.name == p.drive).map_or("1", |d| d.unit.as_str());
        pg.attr_str("drive", &p.drive)?;
        pg.attr_f64("energy_J", p.energy)?;
        pg.write_f64("power_density", &p.power_density, &[n], "W/Hz", "Re G_Fv: power into the structure per Hz")?;
        pg.write_f64("force_psd", &p.force_psd, &[n], "N^2/Hz", "PSD of the force into the structure")?;
        pg.write_f64("acceleration_psd", &p.acceleration_psd, &[n], "(m/s^2)^2/Hz", "PSD of the acceleration")?;
        pg.write_c64("force_frf", &p.force_frf, &[n], &format!("N/{unit}"), "H1 from the drive to the force")?;
        // One segment has no coherence: the datasets are there only for Welch averages.
        if !p.force_coherence.is_empty() {
            pg.write_f64("force_coherence", &p.force_coherence, &[n], "1", "coherence of force_frf")?;
            pg.write_f64(
                "acceleration_coherence",
                &p.acceleration_coherence,
                &[n],
                "1",
                "coherence of acceleration_frf",
            )?;
        }
        pg.attr_f64("end_activity", p.end_activity)?;
        pg.write_c64(
            "acceleration_frf",
            &p.acceleration_frf,
            &[n],
            &format!("(m/s^2)/{unit}"),
            "H1 from the drive to the acceleration",
        )?;
        pg.attr_f64("mean_power_W", p.energy / r.duration)?;
        pg.write_f64(
            "power_frf",
            &p.power_frf,
            &[n],
            &format!("W/{unit}^2"),
            "Re G_Fv / G_uu: a sine drive of amplitude A puts A^2/2 times this in",
        )?;
    }
    for sr in &r.sensors {
        let sg = rg.group(&format!("sensors/{}", sr.name))?;
        let unit = r.drives.iter().find(|d| d.name == sr.drive).map_or("1", |d| d.unit.as_str());
        sg.attr_str("drive", &sr.drive)?;
        sg.write_f64("acceleration_psd", &sr.acceleration_psd, &[n], "(m/s^2)^2/Hz", "PSD of the acceleration")?;
        sg.write_c64(
            "acceleration_frf",
            &sr.acceleration_frf,
            &[n],
            &format!("(m/s^2)/{unit}"),
            "H1 from the drive to the acceleration",
        )?;
        if !sr.acceleration_coherence.is_empty() {
            sg.write_f64(
                "acceleration_coherence",
                &sr.acceleration_coherence,
                &[n],
                "1",
                "coherence of acceleration_frf",
            )?;
        }
    }
    Ok(())
}

fn write_spectra<S: GroupSink>(g: &S, links: &[LinkSeries], spectra: &[LinkSpectrum], run: &CaseRun) -> Result<()> {
    for (l, s) in links.iter().zip(spectra) {
        let sg = g.group(&format!("spectra/{}", link_group_name(run, l)))?;
        let n = s.frequency.len();
        sg.attr_f64("power_total_W", s.power_total)?;
        sg.write_f64("frequency", &s.frequency, &[n], "Hz", "harmonic frequencies k*f0")?;
        sg.write_c64(
            "transmitted",
            &s.transmitted,
            &[n],
            "N",
            "single-sided complex amplitude of the transmitted force",
        )?;
        sg.write_c64("interface", &s.interface, &[n], "N", "single-sided complex amplitude of the interface force")?;
        sg.write_c64("velocity", &s.velocity, &[n], "m/s", "base velocity amplitude")?;
        sg.write_c64("acceleration", &s.acceleration, &[n], "m/s^2", "base acceleration amplitude")?;
        sg.write_f64("power", &s.power, &[n], "W", "power per harmonic 0.5*Re(F*conj(V))")?;
        sg.write_f64(
            "power_from_acceleration",
            &s.power_from_acceleration,
            &[n],
            "W",
            "power per harmonic -0.5*Im(F*conj(A))/w",
        )?;
    }
    Ok(())
}

/// A plate grid's error estimate (the coarser grid's powers beside the differences), or
/// why there is none.
fn write_mesh_estimate<S: GroupSink>(g: &S, m: &MeshCheck) -> Result<()> {
    let e = match m {
        MeshCheck::NotEstimated(why) => return g.attr_str("not_estimated", why),
        MeshCheck::Estimate(e) => e,
    };
    g.attr_f64("max_relative_error", e.max_relative_error)?;
    g.attr_f64("order", crate::analysis::mesh_estimate::ORDER)?;
    let grid = |n: [usize; 2]| n.map(|k| k as f64);
    g.write_f64("elements", &grid(e.elements), &[2], "1", "the grid's elements along x and y, as built")?;
    g.write_f64("coarse_elements", &grid(e.coarse_elements), &[2], "1", "the coarser grid's, as built")?;
    let n = e.relative_error.len();
    g.write_f64("coarse_mean_power", &e.coarse_mean_power, &[n], "W", "mean power per link on the coarser grid")?;
    g.write_f64("relative_error", &e.relative_error, &[n], "1", "|P_h - P_2h| / |P_h| per link")?;
    let a = e.net_power_relative_error.len();
    g.write_f64(
        "net_power_relative_error",
        &e.net_power_relative_error,
        &[a],
        "1",
        "the same per actuator's net power",
    )?;
    let l = e.load_relative_error.len();
    g.write_f64("coarse_load_power", &e.coarse_load_power, &[l], "W", "mean power per point load on the coarser grid")?;
    g.write_f64("load_relative_error", &e.load_relative_error, &[l], "1", "the same per point load's power")
}

fn write_powers<S: GroupSink>(g: &S, mean: &[f64], net: &[f64], run: &CaseRun) -> Result<()> {
    g.write_f64(
        "mean_power",
        mean,
        &[mean.len()],
        "W",
        "time-averaged power into the base per link (order of links/)",
    )?;
    g.write_str_list(
        "link_names",
        &run.system.links.iter().map(|l| link_id(run.model.actuators[l.actuator].name(), &l.name)).collect::<Vec<_>>(),
    )?;
    g.write_f64("net_power", net, &[net.len()], "W", "net power into the base per actuator")
}

fn write_transient<S: GroupSink>(g: &S, r: &TransientResult, run: &CaseRun) -> Result<()> {
    g.attr_f64("dt_s", r.dt)?;
    g.attr_f64("period_s", r.period)?;
    g.attr_f64("mesh_roundoff", r.mesh_roundoff)?;
    // A record has no period: none of a periodic run's fields.
    if r.record.is_none() {
        g.attr_i64("steps_per_period", r.steps_per_period as i64)?;
        g.attr_i64("periods_run", r.periods_run as i64)?;
        g.attr_i64("converged", r.converged as i64)?;
        g.attr_f64("final_change", r.final_change)?;
        if r.settling_estimate.is_finite() {
            g.attr_f64("settling_estimate", r.settling_estimate)?;
        }
        if let Some(n) = r.periods_needed {
            g.attr_i64("periods_needed", n as i64)?;
        }
        g.attr_i64("harmonics", r.harmonics as i64)?;
    } else {
        g.attr_i64("steps_run", r.steps_run as i64)?;
    }
    // On a rigid base nothing moves the base: no power into it, no beam to dissipate.
    let beam = run.model.structure.is_some();
    if beam && r.record.is_none() {
        g.attr_f64("beam_dissipation_W", r.beam_dissipation)?;
        g.attr_f64("structure_dissipation_W", r.beam_dissipation)?;
    }
    write_series(g, &r.t, &r.links, &r.bodies, &r.drives, &r.sensors, run)?;
    write_spectra(g, &r.links, &r.spectra, run)?;
    write_loads(g, &r.loads, &r.load_spectra)?;
    if let Some(rec) = &r.record {
        write_record(g, rec)?;
    }
    if beam && r.record.is_none() {
        write_powers(g, &r.mean_power, &r.net_power, run)?;
    }
    let periodic = r.record.is_none();
    if beam {
        write_energy(g, "energy_run/beam", &r.energy_run.beam)?;
        if periodic {
            write_energy(g, "energy_last_period/beam", &r.energy_last_period.beam)?;
        }
    }
    write_energy(g, "energy_run/system", &r.energy_run.system)?;
    if periodic {
        write_energy(g, "energy_last_period/system", &r.energy_last_period.system)?;
    }
    write_reduction(g, r.reduction.as_ref())
}

/// The modal reduction a run used, if any: basis and error estimate.
fn write_reduction<S: GroupSink>(g: &S, r: Option<&ReductionReport>) -> Result<()> {
    let Some(r) = r else { return Ok(()) };
    let rg = g.group("reduction")?;
    rg.attr_f64("cutoff_Hz", r.cutoff_hz)?;
    rg.attr_i64("static_correction", r.static_correction as i64)?;
    rg.attr_i64("modes_kept", r.modes_kept as i64)?;
    rg.attr_i64("residual_vectors", r.residual_vectors as i64)?;
    rg.attr_i64("full_dofs", r.full_dofs as i64)?;
    rg.attr_i64("reduced_dofs", r.reduced_dofs as i64)?;
    let n = r.mode_frequencies_hz.len();
    rg.write_f64("mode_frequencies", &r.mode_frequencies_hz, &[n], "Hz", "bare-beam modes kept")?;
    let n = r.residual_frequencies_hz.len();
    rg.write_f64(
        "residual_frequencies",
        &r.residual_frequencies_hz,
        &[n],
        "Hz",
        "pseudo-frequencies of the residual-flexibility vectors",
    )?;
    if let Some(e) = &r.error {
        rg.attr_f64("max_relative_error", e.max_relative_error)?;
        rg.attr_i64("error_harmonics", e.harmonics as i64)?;
        let n = e.relative_error.len();
        rg.write_f64(
            "full_mean_power",
            &e.full_mean_power,
            &[n],
            "W",
            "full model, frequency-domain steady state, per link",
        )?;
        rg.write_f64(
            "reduced_mean_power",
            &e.reduced_mean_power,
            &[n],
            "W",
            "reduced model, frequency-domain steady state, per link",
        )?;
        rg.write_f64("relative_error", &e.relative_error, &[n], "1", "|P_reduced - P_full| / |P_full| per link")?;
    }
    Ok(())
}

fn write_steady<S: GroupSink>(g: &S, r: &SteadyStateResult, run: &CaseRun) -> Result<()> {
    g.attr_f64("period_s", r.period)?;
    g.attr_f64("mesh_roundoff", r.mesh_roundoff)?;
    if r.truncation_estimate.is_finite() {
        g.attr_f64("truncation_estimate", r.truncation_estimate)?;
    }
    g.attr_i64("harmonics", r.harmonics as i64)?;
    g.attr_f64("beam_dissipation_W", r.beam_dissipation)?;
    g.attr_f64("structure_dissipation_W", r.beam_dissipation)?;
    g.attr_f64("balance_error", r.balance_error)?;
    g.write_f64(
        "beam_dissipation_per_harmonic",
        &r.beam_dissipation_per_harmonic,
        &[r.harmonics + 1],
        "W",
        "beam dissipation per harmonic",
    )?;
    write_series(g, &r.t, &r.links, &r.bodies, &r.drives, &r.sensors, run)?;
    write_spectra(g, &r.links, &r.spectra, run)?;
    write_loads(g, &r.loads, &r.load_spectra)?;
    write_powers(g, &r.mean_power, &r.net_power, run)?;
    if let Some(m) = &r.modal {
        let mg = g.group("modal")?;
        let nm = m.mode_frequency_hz.len();
        let nk = m.frequency.len();
        let nl = m.point_power.len();
        mg.write_f64(
            "mode_frequency_hz",
            &m.mode_frequency_hz,
            &[nm],
            "Hz",
            "bare-beam natural frequencies of the modes used",
        )?;
        mg.write_f64("frequency", &m.frequency, &[nk], "Hz", "harmonic frequencies k/T of the rows of eta_abs")?;
        mg.write_f64(
            "eta_abs",
            &m.eta_abs.concat(),
            &[nk, nm],
            "m*sqrt(kg)",
            "modal coordinate amplitude |eta_r| per harmonic (row) and mode (column)",
        )?;
        mg.write_f64(
            "point_power",
            &m.point_power.concat(),
            &[nl, nm],
            "W",
            "power per link (row, order of link_names) and mode (column)",
        )?;
        mg.write_f64("point_residual", &m.point_residual, &[nl], "W", "P_i minus the truncated modal sum")?;
        let nj = m.load_power.len();
        if nj > 0 {
            mg.write_str_list("load_names", &r.loads.iter().map(|l| l.name.clone()).collect::<Vec<_>>())?;
            mg.write_f64(
                "load_power",
                &m.load_power.concat(),
                &[nj, nm],
                "W",
                "power per point load (row, order of the case's [[load]]) and mode (column)",
            )?;
            mg.write_f64("load_residual", &m.load_residual, &[nj], "W", "load power minus the truncated modal sum")?;
        }
        mg.write_f64("dissipation", &m.dissipation, &[nm], "W", "modal dissipated power")?;
        mg.write_f64("kinetic_energy", &m.kinetic_energy, &[nm], "J", "time-averaged kinetic energy per mode")?;
        mg.write_f64("strain_energy", &m.strain_energy, &[nm], "J", "time-averaged strain energy per mode")?;
        mg.write_f64(
            "power_participation",
            &m.power_participation,
            &[nm],
            "1",
            "share of the net input power per mode",
        )?;
        mg.write_f64(
            "response_participation",
            &m.response_participation,
            &[nm],
            "1",
            "share of the kinetic energy per mode",
        )?;
        for (a, gf) in m.generalised_force_abs.iter().enumerate() {
            mg.write_f64(
                &format!("generalised_force_abs_{}", run.model.actuators[a].name()),
                &gf.concat(),
                &[nk, nm],
                "N/sqrt(kg)",
                "|sum_i phi_r(x_i) F_i| per harmonic (row) and mode (column)",
            )?;
        }
    }
    write_reduction(g, r.reduction.as_ref())
}
