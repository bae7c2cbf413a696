//! The optimisation file (TOML): which base case, which fields vary within which bounds,
//! what is maximised or minimised, under which constraints, and how hard to search.
//! Loading checks everything a user can get wrong before any case is solved, and every
//! message names the file (or the base case file) and the field.

use super::constraint::{Bound, Limits};
use super::objective::{Goal, Objective, Per};
use super::quantity::{ModeSet, Quantity};
use crate::case::{Case, DampingKind};
use crate::error::{Error, Result};
use crate::sweep::base::BaseCase;
use crate::sweep::field::Field;
use crate::sweep::spec::harmonic_counts;
use serde::Deserialize;
use std::path::Path;

#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
struct OptimizeFile {
    #[serde(default)]
    title: String,
    base: String,
    harmonics: Option<usize>,
    samples_per_period: Option<usize>,
    #[serde(default)]
    search: Search,
    #[serde(default)]
    variable: Vec<VariableFile>,
    #[serde(default)]
    objective: Vec<ObjectiveFile>,
    #[serde(default)]
    constraints: LimitsFile,
    #[serde(default)]
    constraint: Vec<BoundFile>,
}

/// How the optimiser searches (the `[search]` table).
#[derive(Clone, Debug, Deserialize, PartialEq)]
#[serde(deny_unknown_fields, default)]
pub struct Search {
    /// Seed of every random choice: the same seed gives the same result on any thread count.
    pub seed: u64,
    /// Independent starts of the global optimiser, from seeded random points.
    pub starts: usize,
    /// Steady states the global search may solve (all starts together; the polish and the
    /// figure's profiles come on top).
    pub evaluations: usize,
    /// Distinct optima reported.
    pub top: usize,
    /// Least distance between two reported optima, as a fraction of each variable's range
    /// (Euclidean over the variables).
    pub distinct: f64,
    /// Polish the best point with Nelder–Mead.
    pub polish: bool,
    /// Points on a two-objective Pareto front (scalarisations searched).
    pub pareto_points: usize,
}

impl Default for Search {
    fn default() -> Self {
        Search { seed: 1, starts: 4, evaluations: 1500, top: 5, distinct: 0.05, polish: true, pareto_points: 7 }
    }
}

#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
struct VariableFile {
    path: Option<String>,
    /// Several fields that take the same value (e.g. every actuator's drive frequency).
    paths: Option<Vec<String>>,
    min: Option<f64>,
    max: Option<f64>,
    #[serde(default)]
    integer: bool,
    /// A categorical variable: one of these values (e.g. `["inertial", "frame"]`).
    values: Option<Vec<toml::Value>>,
    /// A choice of the nodes of an imported model inside a box (a `node` field's values).
    nodes_in: Option<crate::sweep::base::NodeBox>,
}

#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
struct ObjectiveFile {
    quantity: Option<String>,
    #[serde(default)]
    terms: Vec<TermFile>,
    #[serde(default)]
    goal: Goal,
    per: Option<Per>,
}

#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
struct TermFile {
    quantity: String,
    weight: f64,
}

#[derive(Debug, Default, Deserialize)]
#[serde(deny_unknown_fields)]
struct LimitsFile {
    #[serde(default)]
    support_clearance: f64,
    #[serde(default)]
    clearance: f64,
    max_voltage: Option<f64>,
}

#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
struct BoundFile {
    expression: String,
}

/// The values a variable takes.
#[derive(Clone, Debug, PartialEq)]
pub enum Domain {
    /// A real number in [min, max].
    Real { min: f64, max: f64 },
    /// A whole number in [min, max].
    Integer { min: i64, max: i64 },
    /// One of these values.
    Choice(Vec<toml::Value>),
}

/// One optimisation variable: the fields it sets and the values it takes. The optimiser
/// works on u ∈ [0, 1] per variable; [`Variable::value`] maps u to the field value.
#[derive(Clone, Debug)]
pub struct Variable {
    /// The first path, for tables and messages.
    pub name: String,
    pub fields: Vec<Field>,
    pub domain: Domain,
}

impl Variable {
    /// The field value at u ∈ [0, 1]: min + u·(max − min) for a real; integers and choices
    /// split [0, 1] into equal cells, one per value.
    pub fn value(&self, u: f64) -> toml::Value {
        let u = u.clamp(0.0, 1.0);
        match &self.domain {
            Domain::Real { min, max } => toml::Value::Float(min + u * (max - min)),
            Domain::Integer { min, max } => {
                let n = (max - min + 1) as f64;
                toml::Value::Integer(min + ((u * n).floor() as i64).min(max - min))
            }
            Domain::Choice(v) => v[((u * v.len() as f64).floor() as usize).min(v.len() - 1)].clone(),
        }
    }

    /// The value at u as a number for tables and figures (a choice of numbers, such as node
    /// ids: the number; other choices: its index).
    pub fn number(&self, u: f64) -> f64 {
        match (&self.domain, self.value(u)) {
            (Domain::Choice(_), toml::Value::Integer(i)) => i as f64,
            (Domain::Choice(_), toml::Value::Float(f)) => f,
            (Domain::Choice(v), x) => v.iter().position(|y| *y == x).unwrap_or(0) as f64,
            (_, toml::Value::Integer(i)) => i as f64,
            (_, toml::Value::Float(f)) => f,
            _ => f64::NAN,
        }
    }

    /// The u of a field value (the centre of its cell for integers and choices).
    pub fn unit_of(&self, x: f64) -> f64 {
        match &self.domain {
            Domain::Real { min, max } => (x - min) / (max - min),
            Domain::Integer { min, max } => (x - *min as f64 + 0.5) / (max - min + 1) as f64,
            Domain::Choice(v) => (x + 0.5) / v.len() as f64,
        }
    }

    /// Whether the variable moves continuously (the polish and the profiles treat the
    /// others by their cells).
    pub fn is_real(&self) -> bool {
        matches!(self.domain, Domain::Real { .. })
    }

    /// The unit of the field.
    pub fn unit(&self) -> &'static str {
        self.fields[0].unit
    }
}

/// A loaded, checked optimisation.
#[derive(Clone, Debug)]
pub struct Spec {
    /// The file as given (for messages) and its text.
    pub file: String,
    pub text: String,
    pub title: String,
    pub base: BaseCase,
    pub harmonics: usize,
    pub samples_per_period: usize,
    pub variables: Vec<Variable>,
    /// One objective, or two for a Pareto front.
    pub objectives: Vec<Objective>,
    pub limits: Limits,
    pub bounds: Vec<Bound>,
    pub search: Search,
    /// Bare-beam modes the modal quantities need (0: none).
    pub modes: usize,
}

/// Reads and checks an optimisation file.
impl Spec {
    /// Evaluations of the polish: a tenth of the global search's, at most 800 but at least
    /// 40 per variable.
    pub fn polish_evaluations(&self) -> usize {
        let s = &self.search;
        if s.polish {
            (s.evaluations / 10).min(800).max(self.variables.len().saturating_mul(40))
        } else {
            0
        }
    }

    /// The most evaluations a run takes (None: beyond 64 bits): the global search, the
    /// polish and, since CMA-ES ends a start after the generation that spends its share,
    /// up to one population (4 + ⌊3 ln d⌋) more per start — once per scalarisation (the
    /// Pareto points of two objectives) — and the climbs to the local optima.
    pub fn max_evaluations(&self) -> Option<u64> {
        let s = &self.search;
        let population = 4 + (3.0 * (self.variables.len() as f64).ln()).floor() as usize;
        let scalarisations = if self.objectives.len() == 2 { s.pareto_points } else { 1 };
        let total = s
            .evaluations
            .checked_add(self.polish_evaluations())?
            .checked_add(s.starts.checked_mul(population)?)?
            .checked_mul(scalarisations)?
            .checked_add(super::local::budget(self.variables.len(), s.top))?;
        u64::try_from(total).ok()
    }

    /// The evaluations a run takes, as a [`Cost`] to hold to a budget before the search.
    ///
    /// [`Cost`]: crate::analysis::budget::Cost
    pub fn evaluations_cost(&self) -> crate::analysis::budget::Cost {
        let numbers = self.variables.len() + self.objectives.len() + 2 * self.base.actuators.len();
        crate::analysis::cost::cases(
            "this optimisation",
            self.max_evaluations(),
            numbers as u64,
            format!("{} evaluations of {} variables", self.search.evaluations, self.variables.len()),
            "search.evaluations",
            "give fewer `evaluations` or `pareto_points`",
        )
    }
}

pub fn load(path: &Path) -> Result<Spec> {
    let text = crate::input_file::read_text(path)?;
    let dir = path.parent().map(Path::to_path_buf).unwrap_or_default();
    Spec::from_str(&text, &path.display().to_string(), &dir)
}

impl Spec {
    /// Parses and checks optimisation text; `file` names it in messages and `dir` is where
    /// the base case path is resolved.
    pub fn from_str(text: &str, file: &str, dir: &Path) -> Result<Spec> {
        let of: OptimizeFile = crate::toml_input::parse(text, file, crate::toml_input::Kind::Optimization)?;
        let mut base = BaseCase::load(file, "base", dir, &of.base)?;
        let (harmonics, samples_per_period) = harmonic_counts(of.harmonics, of.samples_per_period, &base, file)?;
        check_search(&of.search, file)?;
        if of.variable.is_empty() {
            return Err(Error::input(file, "variable", "an optimisation needs at least one [[variable]]"));
        }
        let mut variables: Vec<Variable> = Vec::new();
        for (i, v) in of.variable.iter().enumerate() {
            let var = variable(v, &base, file, &format!("variable[{i}]"))?;
            for f in &var.fields {
                if let Some(j) = variables.iter().position(|w| w.fields.iter().any(|g| g.path == f.path)) {
                    return Err(Error::input(
                        file,
                        format!("variable[{i}].path"),
                        format!("`{}` is already set by variable[{j}]", f.path),
                    ));
                }
            }
            variables.push(var);
        }
        let fields: Vec<&Field> = variables.iter().flat_map(|v| &v.fields).collect();
        base.share_structure(&fields);
        base.cache_damping(&fields)?;

        let objectives = match of.objective.len() {
            1 | 2 => of
                .objective
                .iter()
                .enumerate()
                .map(|(i, o)| objective(o, file, &format!("objective[{i}]")))
                .collect::<Result<Vec<_>>>()?,
            0 => return Err(Error::input(file, "objective", "give one [[objective]] (or two for a Pareto front)")),
            n => {
                return Err(Error::input(
                    file,
                    "objective",
                    format!("{n} objectives: give one, or two for a Pareto front (a weighted sum is one objective with `terms`)"),
                ))
            }
        };
        let limits = limits(&of.constraints, file)?;
        let bounds = of
            .constraint
            .iter()
            .enumerate()
            .map(|(i, b)| {
                Bound::parse(&b.expression).map_err(|r| Error::input(file, format!("constraint[{i}].expression"), r))
            })
            .collect::<Result<Vec<_>>>()?;

        // Every quantity must name a result the base case has.
        let mut named: Vec<(String, &Quantity)> = Vec::new();
        for (i, o) in objectives.iter().enumerate() {
            let field =
                if o.terms.len() == 1 { format!("objective[{i}].quantity") } else { format!("objective[{i}].terms") };
            named.extend(o.terms.iter().map(|(_, q)| (field.clone(), q)));
        }
        named.extend(bounds.iter().enumerate().map(|(i, b)| (format!("constraint[{i}].expression"), &b.quantity)));
        let mut modes = 0;
        for (field, q) in &named {
            check_quantity(q, &base.case, harmonics, file, field)?;
            modes = modes.max(modes_for(q, &base, file, field)?);
        }

        Ok(Spec {
            file: file.to_string(),
            text: text.to_string(),
            title: of.title,
            base,
            harmonics,
            samples_per_period,
            variables,
            objectives,
            limits,
            bounds,
            search: of.search,
            modes,
        })
    }

    /// Holds every candidate to `budget` before the search starts: each variable at its
    /// bounds (or each of its values), and the steady state on the largest case
    /// ([`BaseCase::admit_cases`]).
    pub fn admit(&self, budget: &crate::analysis::budget::Budget) -> Result<()> {
        let counts = (self.harmonics, self.samples_per_period);
        self.base.admit_cases(&self.file, &self.extremes(), crate::sweep::SweepAnalysis::SteadyState, counts, budget)
    }

    /// Each variable at its bounds (or each of its values): `(name, field, value)`.
    pub fn extremes(&self) -> Vec<(String, &Field, toml::Value)> {
        let mut extremes = Vec::new();
        for (i, v) in self.variables.iter().enumerate() {
            let values = match &v.domain {
                Domain::Choice(values) => values.clone(),
                _ => vec![v.value(0.0), v.value(1.0)],
            };
            for f in &v.fields {
                extremes.extend(values.iter().map(|x| (format!("variable[{i}]"), f, x.clone())));
            }
        }
        extremes
    }

    /// The fields and values of the candidate u (one u per variable, in [0, 1]).
    pub fn assignment<'s>(&'s self, u: &[f64]) -> Vec<(&'s Field, toml::Value)> {
        self.variables.iter().zip(u).flat_map(|(v, &x)| v.fields.iter().map(move |f| (f, v.value(x)))).collect()
    }

    /// `path = value, …` of the candidate u, for messages.
    pub fn describe(&self, u: &[f64]) -> String {
        self.variables
            .iter()
            .zip(u)
            .map(|(v, &x)| match v.value(x) {
                toml::Value::Float(f) => format!("{} = {}", v.name, crate::report::sweep::num(f)),
                other => format!("{} = {other}", v.name),
            })
            .collect::<Vec<_>>()
            .join(", ")
    }
}

fn check_search(s: &Search, file: &str) -> Result<()> {
    let bad = |f: &str, r: &str| Err(Error::input(file, format!("search.{f}"), r));
    if s.starts == 0 {
        return bad("starts", "must be at least 1");
    }
    if s.evaluations < s.starts.saturating_mul(10) {
        return bad("evaluations", "must be at least 10 per start");
    }
    if s.top == 0 {
        return bad("top", "must be at least 1");
    }
    if !(s.distinct >= 0.0 && s.distinct < 1.0) {
        return bad("distinct", "must lie in [0, 1)");
    }
    if s.pareto_points < 2 {
        return bad("pareto_points", "must be at least 2");
    }
    Ok(())
}

fn variable(v: &VariableFile, base: &BaseCase, file: &str, name: &str) -> Result<Variable> {
    let paths: Vec<String> = match (&v.path, &v.paths) {
        (Some(p), None) => vec![p.clone()],
        (None, Some(p)) if !p.is_empty() => p.clone(),
        (None, Some(_)) => return Err(Error::input(file, format!("{name}.paths"), "is empty: give at least one path")),
        (Some(_), Some(_)) => return Err(Error::input(file, name, "give either `path` or `paths`, not both")),
        (None, None) => return Err(Error::input(file, format!("{name}.path"), "missing: which case field varies?")),
    };
    let nodes = match &v.nodes_in {
        Some(_) if v.values.is_some() || v.min.is_some() || v.max.is_some() || v.integer => {
            return Err(Error::input(file, name, "give either `nodes_in` or `values` or `min` and `max`, not several"))
        }
        Some(b) => {
            let f = Field::parse(&paths[0]).map_err(|r| Error::input(file, format!("{name}.path"), r))?;
            Some(base.nodes_in(&f, b, file, name)?.into_iter().map(toml::Value::Integer).collect())
        }
        None => v.values.clone(),
    };
    let domain = match (&nodes, v.min, v.max) {
        (Some(_), Some(_), _) | (Some(_), _, Some(_)) => {
            return Err(Error::input(file, name, "give either `values` (a choice) or `min` and `max`, not both"))
        }
        (Some(vals), None, None) => {
            if vals.is_empty() {
                return Err(Error::input(file, format!("{name}.values"), "is empty: give at least one value"));
            }
            Domain::Choice(vals.clone())
        }
        (None, Some(lo), Some(hi)) => {
            if !(lo.is_finite() && hi.is_finite()) {
                return Err(Error::input(file, format!("{name}.min"), "bounds must be finite"));
            }
            if !(lo < hi) {
                return Err(Error::input(
                    file,
                    format!("{name}.max"),
                    format!("the bounds are empty: max = {hi} must exceed min = {lo}"),
                ));
            }
            if v.integer {
                if lo.fract() != 0.0 || hi.fract() != 0.0 {
                    return Err(Error::input(file, format!("{name}.min"), "an integer variable has whole bounds"));
                }
                Domain::Integer { min: lo as i64, max: hi as i64 }
            } else {
                Domain::Real { min: lo, max: hi }
            }
        }
        (None, lo, _) => {
            let missing = if lo.is_none() { "min" } else { "max" };
            return Err(Error::input(
                file,
                format!("{name}.{missing}"),
                "missing: a variable needs `min` and `max` (or `values`)",
            ));
        }
    };
    let mut fields = Vec::new();
    for p in &paths {
        let mut f = Field::parse(p).map_err(|r| Error::input(file, format!("{name}.path"), r))?;
        match &domain {
            Domain::Real { min, max } => base.check_field(&mut f, &[*min, *max], file, name)?,
            Domain::Integer { min, max } => {
                f.integer = true;
                for x in [*min, *max] {
                    base.check_value(&f, toml::Value::Integer(x), file, name)?;
                }
            }
            Domain::Choice(vals) => {
                for x in vals {
                    base.check_value(&f, x.clone(), file, name)?;
                }
            }
        }
        if matches!(domain, Domain::Real { .. }) && f.integer {
            return Err(Error::input(
                file,
                format!("{name}.integer"),
                format!("`{}` is an integer field: set `integer = true`", f.path),
            ));
        }
        fields.push(f);
    }
    Ok(Variable { name: paths[0].clone(), fields, domain })
}

fn objective(o: &ObjectiveFile, file: &str, name: &str) -> Result<Objective> {
    let terms = match (&o.quantity, o.terms.is_empty()) {
        (Some(q), true) => {
            vec![(1.0, Quantity::parse(q).map_err(|r| Error::input(file, format!("{name}.quantity"), r))?)]
        }
        (None, false) => o
            .terms
            .iter()
            .enumerate()
            .map(|(k, t)| {
                if !t.weight.is_finite() {
                    return Err(Error::input(file, format!("{name}.terms[{k}].weight"), "must be finite"));
                }
                let q = Quantity::parse(&t.quantity)
                    .map_err(|r| Error::input(file, format!("{name}.terms[{k}].quantity"), r))?;
                Ok((t.weight, q))
            })
            .collect::<Result<Vec<_>>>()?,
        (Some(_), false) => return Err(Error::input(file, name, "give either `quantity` or `terms`, not both")),
        (None, true) => {
            return Err(Error::input(file, format!("{name}.quantity"), "missing: what is maximised or minimised?"))
        }
    };
    let label = match (&o.quantity, &o.terms[..]) {
        (Some(q), _) => q.trim().to_string(),
        (None, t) => t.iter().map(|t| format!("{}·{}", t.weight, t.quantity.trim())).collect::<Vec<_>>().join(" + "),
    };
    let label = match o.per {
        None => label,
        Some(Per::Volt2) => format!("({label}) per V²"),
        Some(Per::Kg) => format!("({label}) per kg"),
    };
    Ok(Objective { label, goal: o.goal, terms, per: o.per })
}

fn limits(l: &LimitsFile, file: &str) -> Result<Limits> {
    for (f, v) in [("support_clearance", l.support_clearance), ("clearance", l.clearance)] {
        if !(v >= 0.0 && v.is_finite()) {
            return Err(Error::input(file, format!("constraints.{f}"), format!("must be ≥ 0 m, got {v}")));
        }
    }
    if let Some(v) = l.max_voltage {
        if !(v > 0.0 && v.is_finite()) {
            return Err(Error::input(file, "constraints.max_voltage", format!("must be > 0 V, got {v}")));
        }
    }
    Ok(Limits { support_clearance: l.support_clearance, clearance: l.clearance, max_voltage: l.max_voltage })
}

/// A quantity must name something the base case has.
fn check_quantity(q: &Quantity, case: &Case, harmonics: usize, file: &str, field: &str) -> Result<()> {
    let bad = |r: String| Err(Error::input(file, field, r));
    match q {
        Quantity::NetPower { actuator: Some(a), .. } if *a >= case.actuator.len() => {
            bad(format!("actuator {a} does not exist: the base case has {} actuator(s)", case.actuator.len()))
        }
        Quantity::NetPower { harmonic: Some(k), .. } if *k > harmonics => {
            bad(format!("harmonic {k} is above the {harmonics} solved (set `harmonics`)"))
        }
        Quantity::Sensor { name, harmonic, .. } => {
            if !case.sensor.iter().any(|s| s.name == *name) {
                let have: Vec<&str> = case.sensor.iter().map(|s| s.name.as_str()).collect();
                return bad(format!(
                    "the base case has no sensor `{name}` (it has: {})",
                    if have.is_empty() { "none".to_string() } else { have.join(", ") }
                ));
            }
            if *harmonic > harmonics {
                return bad(format!("harmonic {harmonic} is above the {harmonics} solved (set `harmonics`)"));
            }
            if case.damping.kind == DampingKind::Modal {
                return bad("sensor quantities need viscous (Rayleigh) damping, not modal damping".into());
            }
            Ok(())
        }
        Quantity::ModalPower(_) if case.damping.kind == DampingKind::Modal => {
            bad("mode-resolved quantities need viscous (Rayleigh) damping, not modal damping".into())
        }
        Quantity::ModalPower(_) if case.base != crate::case::BaseKind::Beam => {
            bad("mode-resolved quantities need a beam (the base case has base = \"rigid\")".into())
        }
        _ => Ok(()),
    }
}

/// Why the band [lo, hi] (Hz) holds none of the bare-beam modes at `f` (Hz, ascending):
/// the modes on either side of it.
fn empty_band(lo: f64, hi: f64, f: &[f64]) -> String {
    let mode = |r: usize| format!("mode {} at {:.2} Hz", r + 1, f[r]);
    let below = f.iter().rposition(|&x| x < lo).map(mode);
    let above = f.iter().position(|&x| x > hi).map(mode);
    let around = match (below, above) {
        (Some(b), Some(a)) => format!("{b} lies below it and {a} above"),
        (Some(b), None) => format!("{b}, the highest computed, lies below it"),
        (None, Some(a)) => format!("{a}, the lowest, lies above it"),
        (None, None) => "no mode was computed".to_string(),
    };
    format!(
        "no bare-beam mode lies in the band {lo}..{hi} Hz, so its modal power is 0 W for every candidate: {around}; \
         widen the band to hold one"
    )
}

/// How many bare-beam modes `q` needs: its highest mode, or for a band every mode up to
/// its upper frequency (from the base case's bare beam, which the placements do not change).
fn modes_for(q: &Quantity, base: &BaseCase, file: &str, field: &str) -> Result<usize> {
    let Some(m) = q.modes_needed() else { return Ok(0) };
    let lc = crate::case::LoadedCase {
        case: base.case.clone(),
        file: base.file.clone(),
        dir: base.dir.clone(),
        text: String::new(),
    };
    let beam = crate::case::build::build_structure(&lc)?;
    let dofs = crate::analysis::modes::bare_system(&beam)?.n();
    match q {
        Quantity::ModalPower(ModeSet::Band(lo, hi)) => {
            let all = crate::analysis::modes::bare_modes(&beam, dofs.min(60))?;
            let f = all.frequencies_hz();
            let n = f.iter().take_while(|&&f| f <= *hi).count();
            if !f.iter().any(|x| (*lo..=*hi).contains(x)) {
                return Err(Error::input(file, field, empty_band(*lo, *hi, &f)));
            }
            Ok(n)
        }
        _ if m > dofs => Err(Error::input(file, field, format!("mode {m} does not exist: the mesh has {dofs} DOFs"))),
        _ => Ok(m),
    }
}

impl Spec {
    /// The case of candidate u, deserialised but not validated (the placement constraints
    /// are checked on it first: a leg off the beam is their violation, not an input error).
    pub fn case_of(&self, u: &[f64]) -> std::result::Result<Case, String> {
        let doc = self.base.document(self.assignment(u))?;
        doc.try_into().map_err(|e: toml::de::Error| e.message().trim_end().to_string())
    }

    /// Refuses placement and drive limits that no candidate within the bounds meets, before
    /// anything is solved: `samples` seeded random candidates (and the centre) are checked,
    /// and if none passes, the limit most of them break is named.
    pub fn check_limits_can_hold(&self, samples: usize) -> Result<()> {
        let d = self.variables.len();
        use rand::{Rng, SeedableRng};
        let mut rng = rand_xoshiro::Xoshiro256PlusPlus::seed_from_u64(self.search.seed);
        let mut counts: Vec<(String, usize, String)> = Vec::new();
        for s in 0..=samples {
            let u: Vec<f64> = if s == 0 { vec![0.5; d] } else { (0..d).map(|_| rng.random::<f64>()).collect() };
            let case = self
                .case_of(&u)
                .map_err(|r| Error::input(&self.file, "variable", format!("{}: {r}", self.describe(&u))))?;
            let v = self.limits.violations(&case);
            if v.is_empty() {
                return Ok(());
            }
            let mut seen: Vec<String> = Vec::new();
            for x in v {
                if seen.contains(&x.constraint) {
                    continue;
                }
                seen.push(x.constraint.clone());
                match counts.iter_mut().find(|c| c.0 == x.constraint) {
                    Some(c) => c.1 += 1,
                    None => counts.push((x.constraint, 1, x.detail)),
                }
            }
        }
        let (name, n, example) = counts.into_iter().max_by_key(|c| c.1).expect("some limit was broken");
        Err(Error::input(
            &self.file,
            name,
            format!(
                "can never hold within the variables' bounds: {n} of {} candidates tried break it, e.g. {example}",
                samples + 1
            ),
        ))
    }
}
