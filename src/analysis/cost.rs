//! What each analysis of a case will take — memory and steps — computed from the case,
//! the model and its assembled system alone, before the analysis allocates or steps
//! anything. [`crate::analysis::budget::Budget::admit`] compares a [`Cost`] with the budget.
//!
//! The estimates are upper bounds at the peak, by the sizes the analyses allocate: the
//! assembled system and its solvers per DOF ([`BYTES_PER_DOF`], measured: 1.7–2.4 kB a DOF
//! for meshes of 10⁴–4·10⁵ elements), dense eigen-decompositions (n² doubles, five times),
//! and each recorded series as the run, its window, the results and their copies for
//! output hold it (four times). Every product is checked: one beyond 64 bits is refused.

use super::budget::{count, product, sum, whole, Cost, CostScope};
use super::drive::{DriveTiming, CYCLE_MAX_PERIODS};
use super::modes::DENSE_EIGEN_LIMIT;
use super::series::body_dofs;
use super::transient::TransientSettings;
use crate::assembly::{Damping, Model, System};
use crate::case::LoadedCase;

/// Memory per DOF of an assembled system, its factorisations, work vectors and a few of its
/// modes (bytes).
pub const BYTES_PER_DOF: u64 = 4096;

/// Copies of a recorded series alive at the peak (the run's window, the joined record, the
/// result series and the output's copy).
const SERIES_COPIES: u64 = 4;

/// Copies of an n × n matrix a dense eigen-decomposition holds (K, M, the factor, the
/// reduced matrix, the eigenvectors).
const DENSE_COPIES: u64 = 5;

fn cost(bytes: Option<u64>, steps: Option<u64>, unit: &'static str, what: String, detail: String) -> Cost {
    Cost { bytes, steps, unit, what, detail, field: String::new(), scope: CostScope::Analysis, advice: String::new() }
}

impl Cost {
    /// The same cost, driven by the analysis setting `field`.
    fn of_setting(mut self, field: &str, advice: impl Into<String>) -> Self {
        self.field = field.to_string();
        self.scope = CostScope::Analysis;
        self.advice = advice.into();
        self
    }

    /// The same cost, driven by the case field `field` (a dotted path from the root).
    fn of_case_field(mut self, field: &str, advice: impl Into<String>) -> Self {
        self.field = field.to_string();
        self.scope = CostScope::Case;
        self.advice = advice.into();
        self
    }
}

/// Bytes of `n` DOFs' assembled system and solvers.
fn system_bytes(n: u64) -> Option<u64> {
    product(&[n, BYTES_PER_DOF])
}

/// Bytes of a two-dimensional structure's `n` DOFs whose skyline rows reach back `band`
/// entries: [`system_bytes`] plus a real and a complex profile factor.
fn profile_bytes(n: u64, band: u64) -> Option<u64> {
    sum(&[system_bytes(n), product(&[n, band, 8 * 3])])
}

/// How far back a skyline row of a plate reaches (entries) when its shorter side has `side`
/// grid lines: four DOFs per node over about one RCM front and a margin.
fn plate_band(side: u64) -> u64 {
    count(4).saturating_mul(side.saturating_add(2))
}

/// The structure DOFs of a model (every node's kinds, before supports remove some), and
/// how far back a skyline row reaches on it (0 for a beam, whose band is a few entries).
fn structure_dofs(model: &Model) -> (u64, u64) {
    match &model.structure {
        Some(crate::structure::Structure::Plate(p)) => {
            let side = p.grid.x.len().min(p.grid.y.len());
            (count(p.grid.n_nodes() * 4), plate_band(count(side)))
        }
        // A node's rows are numbered together but it carries only some of the components,
        // so the reach in row positions over-counts the rows between: an upper bound.
        Some(crate::structure::Structure::Imported(m)) => (count(m.n()), count(m.mean_band)),
        Some(s) => (count(s.n_nodes()).saturating_mul(2), 0),
        None => (0, 0),
    }
}

/// Bytes of the lowest `wanted` modes of an `n`-DOF structure, by the solver
/// [`crate::analysis::modes::bare_modes_of`] picks: dense below [`DENSE_EIGEN_LIMIT`] DOFs
/// or for a quarter of the modes or more, Lanczos (a basis of about 3·count vectors) else.
pub fn eigen_bytes(n: u64, wanted: u64) -> Option<u64> {
    let c = wanted.min(n);
    if n <= count(DENSE_EIGEN_LIMIT) || c >= n / 4 {
        product(&[n, n, 8, DENSE_COPIES])
    } else {
        product(&[n, 8, c.checked_mul(3)?.checked_add(64)?])
    }
}

/// The DOFs of a beam of `nodes` nodes carrying `bodies` actuator DOFs (w and θ per node).
fn dofs(nodes: u64, bodies: u64) -> Option<u64> {
    nodes.checked_mul(2)?.checked_add(bodies)
}

/// The mesh a case asks for, before it is built: a uniform mesh's elements (plus the nodes
/// inserted at the case's points) make its DOFs. A mesh file is sized from its text, by
/// [`mesh_file`].
pub fn mesh(lc: &LoadedCase) -> Option<Cost> {
    let case = &lc.case;
    if case.mesh_file().is_some() {
        return None;
    }
    if let Some(p) = &case.plate {
        return Some(plate_mesh(lc, p));
    }
    if case.base == crate::case::BaseKind::Rigid {
        return None;
    }
    Some(mesh_of(lc, case.beam.mesh.elements))
}

/// The mesh a case's mesh file (`text`) describes, counted from the text before it is
/// parsed: a beam's nodes, a plate's grid lines.
pub fn mesh_file(lc: &LoadedCase, text: &str) -> Option<Cost> {
    let (field, file) = lc.case.mesh_file()?;
    if lc.case.plate.is_none() {
        return Some(mesh_of(lc, crate::beam::Mesh::elements_at_least(text)));
    }
    let [nx, ny] = crate::case::plate_mesh::lines_at_least(text).map(count);
    Some(plate_grid(nx, ny).of_case_field(field, format!("use fewer grid lines in the mesh file {file}")))
}

/// A plate's grid before it is built: its grid lines (about `elements` per side plus one
/// through each point's coordinate) make its nodes, four DOFs each, numbered across the
/// shorter side.
fn plate_mesh(lc: &LoadedCase, p: &crate::case::PlateSpec) -> Cost {
    let case = &lc.case;
    let points = count(
        case.actuator.len() * 3
            + case.sensor.len()
            + case.load.len()
            + p.support.len()
            + p.point_mass.len()
            + p.spring.len()
            + 2,
    );
    let [nx, ny] = p.mesh.elements().map(|n| count(n).saturating_add(1).saturating_add(points));
    plate_grid(nx, ny).of_case_field("plate.mesh.elements", "use fewer elements")
}

/// A plate grid of `nx` × `ny` lines: four DOFs a node, numbered across the shorter side.
fn plate_grid(nx: u64, ny: u64) -> Cost {
    let n = product(&[nx, ny, 4]);
    let band = plate_band(nx.min(ny));
    cost(
        n.and_then(|n| profile_bytes(n, band)),
        Some(0),
        "steps",
        "the plate's mesh".into(),
        format!("{nx} × {ny} grid lines, ≈ {} DOFs", n.map_or("> 2⁶⁴".into(), |n| n.to_string())),
    )
}

/// The memory of a mesh of `elements` elements for `lc`'s attachments: what [`mesh`]
/// estimates, for a mesh file's elements counted from its text before it is parsed.
pub fn mesh_of(lc: &LoadedCase, elements: usize) -> Cost {
    let case = &lc.case;
    let elements = count(elements);
    let points = count(case.actuator.len() * 3 + case.sensor.len() + case.load.len() + case.beam.support.len() + 2);
    let n = elements.checked_add(1).and_then(|e| e.checked_add(points)).and_then(|nodes| dofs(nodes, 0));
    let bytes = n.and_then(system_bytes);
    cost(
        bytes,
        Some(0),
        "steps",
        "the mesh".into(),
        format!(
            "{} elements, ≈ {} DOFs at {} kB each",
            elements,
            n.map_or("> 2⁶⁴".into(), |n| n.to_string()),
            BYTES_PER_DOF / 1024
        ),
    )
    .of_case_field("beam.mesh.elements", "use fewer elements (the shipped cases use 200)")
}

/// The built model before its damping is calibrated: its DOFs, and the modes
/// `rayleigh_ratio` damping names.
pub fn model(model: &Model) -> Cost {
    let (structure, band) = structure_dofs(model);
    let n = structure.saturating_add(count(model.actuators.len() * 3));
    let (wanted, field) = match model.damping {
        Damping::RayleighRatio { modes, .. } if model.structure.is_some() => {
            (count(modes[0].max(modes[1])), "damping.modes")
        }
        _ => (0, "beam.mesh"),
    };
    let eigen =
        if wanted > 0 { eigen_bytes(n.saturating_sub(count(model.actuators.len() * 3)), wanted) } else { Some(0) };
    let bytes = sum(&[profile_bytes(n, band), eigen]);
    let detail = if wanted > 0 {
        format!("{n} DOFs, and {wanted} modes of the bare structure to calibrate the damping")
    } else {
        format!("{n} DOFs")
    };
    cost(bytes, Some(0), "steps", "the model".into(), detail)
        .of_case_field(field, "use a coarser mesh, or calibrate the damping at lower modes")
}

/// A modes analysis of `count` modes (the case's `count`).
pub fn modes(model: &Model, wanted: usize) -> Cost {
    let (n, band) = structure_dofs(model);
    let c = count(wanted).min(n);
    let bytes = sum(&[profile_bytes(n, band), eigen_bytes(n, c), product(&[c, n, 8, 3])]);
    cost(bytes, Some(0), "steps", "this modes analysis".into(), format!("{c} modes of {n} DOFs"))
        .of_setting("count", "ask for fewer modes, or use a coarser mesh")
}

/// A harmonic analysis at `frequencies` frequencies with `forces` force points and `sensors`
/// more response points; `modal`: with modal damping (every mode of the bare beam).
pub fn harmonic(sys: &System, frequencies: u64, forces: usize, sensors: usize, modal: bool) -> Cost {
    let n = count(sys.n());
    let (f, p) = (count(forces), count(forces + sensors));
    // Per frequency: mobilities p × f and velocities p (complex), input powers f, balance.
    let per_frequency = product(&[p, f.saturating_add(3), 16]).and_then(|b| b.checked_add(f * 8 + 128));
    let eigen = if modal { eigen_bytes(n, n) } else { Some(0) };
    let bytes = sum(&[system_bytes(n), eigen, per_frequency.and_then(|b| b.checked_mul(frequencies))]);
    cost(
        bytes,
        Some(frequencies),
        "frequencies",
        "this harmonic analysis".into(),
        format!("{frequencies} frequencies × {p} points × {f} forces"),
    )
    .of_setting("frequencies.count", "ask for fewer frequencies")
}

/// The series a run records per sample (time, each link's four channels, each body DOF's
/// three, each stack's voltage, h and F_p, each sensor's three, each load's four), and the
/// read-out rows the integrator evaluates per step.
fn channels(model: &Model, sys: &System) -> (u64, u64) {
    let (nl, nb) = (count(sys.links.len()), count(body_dofs(model, sys).len()));
    let (na, ns, np) = (count(sys.drives.len()), count(model.sensors.len()), count(sys.loads.len()));
    (1 + 4 * nl + 3 * nb + 3 * na + 3 * ns + 4 * np, 2 * nl + na + ns + nb + np)
}

/// Samples the hysteresis cycle of the model's hysteretic stacks may take to settle at
/// `samples` per period (each at most [`CYCLE_MAX_PERIODS`] periods).
fn cycle_steps(model: &Model, samples: u64) -> Option<u64> {
    let hysteretic = count(model.actuators.iter().filter(|a| a.stack().hysteresis_on).count());
    product(&[hysteretic, samples, count(CYCLE_MAX_PERIODS)])
}

/// A transient on `timing` with settings `s`.
pub fn transient(model: &Model, sys: &System, s: &TransientSettings, timing: &DriveTiming) -> Cost {
    let spp = count(timing.steps_per_period);
    let (periods, field, advice) = match (timing.periodic, s.periods) {
        (false, _) => (1, if s.dt.is_some() { "dt" } else { "duration" }, "give a shorter `duration` or a larger `dt`"),
        (true, Some(p)) => (count(p), "periods", "run fewer `periods` or fewer steps per period"),
        (true, None) if s.steady_state => {
            (count(s.max_periods), "max_periods", "lower `max_periods` or the steps per period")
        }
        (true, None) => (1, "dt", "use fewer steps per period"),
    };
    // A period finer than the default dominates: name what sets it.
    let (field, advice) = if timing.periodic && spp > 100_000 {
        let f = match (s.dt, s.steps_per_period, s.harmonics) {
            (Some(_), _, _) => "dt",
            (_, Some(_), _) => "steps_per_period",
            (_, _, Some(_)) => "harmonics",
            _ => "dt",
        };
        (f, "use fewer steps per period (a larger `dt`, fewer `harmonics`)")
    } else {
        (field, advice)
    };
    let keep = if s.full_history {
        periods
    } else if timing.periodic {
        count(s.record_periods).min(periods)
    } else {
        1
    };
    // A thinned history keeps every step of its last periods and every k-th before them.
    let whole = keep.min(count(s.record_periods));
    let thinned = spp.div_ceil(count(s.history_every.max(1)));
    let kept_samples = sum(&[product(&[whole, spp]), product(&[keep - whole, thinned])]);
    let (ch, rows) = channels(model, sys);
    let kept = product(&[kept_samples.unwrap_or(u64::MAX), ch, 8, SERIES_COPIES]);
    let per_period = product(&[spp.saturating_add(1), 3 * rows + ch, 8, 2]);
    let bytes = sum(&[system_bytes(count(sys.n())), kept, per_period]);
    let stepped = product(&[periods, spp]);
    let reference = if timing.periodic && s.steady_state { cycle_steps(model, spp) } else { Some(0) };
    let steps = sum(&[stepped, reference]);
    let cycle = match reference {
        Some(0) => String::new(),
        Some(r) => format!(", and up to {r} steps of the stacks' periodic hysteresis cycle"),
        None => ", and more steps of the stacks' periodic hysteresis cycle than 64 bits count".into(),
    };
    let detail = if timing.periodic {
        format!(
            "{} period(s) × {} steps per period (Δt = {:.3e} s){cycle}, {} period(s) of {ch} series kept",
            periods, spp, timing.dt, keep
        )
    } else {
        // A record (its default length included) has no periods: its steps and series.
        format!(
            "a record of {:.4e} s in {} steps (Δt = {:.3e} s), {ch} series kept whole",
            timing.period, spp, timing.dt
        )
    };
    cost(bytes, steps, "time steps", "this transient".into(), detail).of_setting(field, advice)
}

/// A frequency-domain steady state from `samples` per period: every harmonic they resolve
/// is solved (to choose or check the count), so its amplitudes are held for all DOFs.
pub fn steady_state(model: &Model, sys: &System, samples: usize) -> Cost {
    let (n, samples) = (count(sys.n()), count(samples));
    let harmonics = samples / 2 + 1;
    let (ch, _) = channels(model, sys);
    // Q_k for each DOF and harmonic (twice: the count is chosen, then solved again),
    // the drive cycles and the rebuilt period's series.
    let amplitudes = product(&[harmonics, n, 16, 2]);
    let series = product(&[samples, ch, 8, SERIES_COPIES]);
    let bytes = sum(&[system_bytes(n), amplitudes, series]);
    let steps = sum(&[Some(samples), cycle_steps(model, samples)]);
    let detail = format!("{samples} samples per period, {harmonics} harmonics × {n} DOFs");
    cost(bytes, steps, "samples", "this steady state".into(), detail)
        .of_setting("samples_per_period", "use fewer `samples_per_period` (default 1024)")
}

/// The turning-point search over the drives of the hysteretic stacks, for the drive that
/// takes the most ([`crate::signal::voltage::VoltageInput::search_evaluations`]): `span`
/// seconds of drive cut into `intervals`. Each evaluation counts as a step (it is far
/// cheaper than one). None when no stack's drive needs a search.
pub fn drive_search(model: &Model, span: f64, intervals: u64) -> Option<Cost> {
    let (a, evaluations) = model
        .actuators
        .iter()
        .enumerate()
        .filter(|(_, a)| a.stack().hysteresis_on)
        .map(|(i, a)| (i, a.stack().voltage.search_evaluations(span, intervals)))
        .max_by_key(|(_, n)| n.unwrap_or(u64::MAX))?;
    if evaluations == Some(0) {
        return None;
    }
    let detail = format!("{span:.3e} s of drive searched for its turning points (hysteresis), {intervals} intervals");
    Some(
        cost(Some(0), evaluations, "drive evaluations", "the drive's turning-point search".into(), detail)
            .of_case_field(
                &format!("actuator[{a}].voltage"),
                "give the drive fewer components or lower frequencies (or a shorter run)",
            ),
    )
}

/// The turning-point search of a stack's periodic cycle on `timing`: one period searched
/// for the periods it takes to settle, one at its samples.
pub fn cycle_search(model: &Model, timing: &DriveTiming) -> Option<Cost> {
    drive_search(model, 2.0 * timing.period, count(timing.steps_per_period))
}

/// A request sized by the arguments of a command (a fit, a synthetic record): `bytes` at
/// the peak and `steps` counted in `unit`, driven by the argument `flag`.
pub fn of_arguments(
    what: &str,
    (bytes, steps): (Option<u64>, Option<u64>),
    unit: &'static str,
    detail: String,
    flag: &str,
    advice: &str,
) -> Cost {
    let mut c = cost(bytes, steps, unit, what.to_string(), detail);
    (c.field, c.scope, c.advice) = (flag.to_string(), CostScope::Argument, advice.to_string());
    c
}

/// A recorded series of `samples` rows of `columns` numbers, held as numbers and as CSV text.
pub fn record_bytes(samples: u64, columns: u64) -> Option<u64> {
    product(&[samples, columns, 8 * SERIES_COPIES + 24])
}

/// The number of frequencies a harmonic analysis's list holds, None past 64 bits.
pub fn frequency_count(spec: &crate::case::FrequencySpec) -> Option<u64> {
    count(spec.values.len()).checked_add(spec.count.map_or(0, count))
}

/// Steps of `x` seconds at Δt (for messages of runs refused before their timing exists).
pub fn steps_of(x: f64, dt: f64) -> Option<u64> {
    whole(x / dt)
}

/// Bytes a sweep or optimisation holds per case besides its row's numbers: the case's
/// index in the shard's and the to-do lists, and the row's vectors.
const CASE_OVERHEAD: u64 = 128;

/// A sweep or an optimisation of `cases` case runs (None: beyond 64 bits), each keeping a
/// row of `numbers` values (its inputs and results) in the table, driven by the case field
/// `field`; `detail` gives the factors.
pub fn cases(what: &str, cases: Option<u64>, numbers: u64, detail: String, field: &str, advice: &str) -> Cost {
    let row = numbers.saturating_mul(8 * SERIES_COPIES).saturating_add(CASE_OVERHEAD);
    let bytes = cases.and_then(|n| n.checked_mul(row));
    cost(bytes, cases, "cases", what.to_string(), detail).of_case_field(field, advice)
}
