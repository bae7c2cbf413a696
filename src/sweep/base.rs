//! The base case of a study (a sweep or an optimisation): read and checked once, its
//! analyses removed (the study says what to solve), and turned into a case for any values
//! of the fields the study varies. Every message names the study file or the base file.

use super::field::{get_path, set_path, Field, Segment};
use super::spec::SweepAnalysis;
use crate::actuator::{link_id, Frame, Inertial};
use crate::analysis::budget::Budget;
use crate::analysis::drive::{DriveTiming, Step};
use crate::analysis::reduction::SharedReduction;
use crate::analysis::{cost, plan, transient::TransientSettings};
use crate::assembly::Rayleigh;
use crate::case::signal::SignalSpec;
use crate::case::{AnalysisSpec, BaseKind, BodySpec, Case, DampingKind, LoadedCase, ReductionSpec, DEFAULT_HARMONICS};
use crate::error::{Error, Result};
use crate::signal::voltage::VoltageInput;
use std::path::{Path, PathBuf};
use std::sync::{Arc, Mutex};

/// Sets `through_points = false` on the plate of the case document `doc` (if it has one and
/// no mesh file, whose grid is fixed already): the grid a shared reduction was built on.
pub fn uniform_plate_mesh(doc: &mut toml::Table) {
    let Some(plate) = doc.get_mut("plate").and_then(toml::Value::as_table_mut) else { return };
    let mesh = plate.entry("mesh").or_insert_with(|| toml::Value::Table(Default::default()));
    if let Some(m) = mesh.as_table_mut().filter(|m| !m.contains_key("file")) {
        m.insert("through_points".into(), toml::Value::Boolean(false));
    }
}

/// Whether a varied field can change the structure or its damping.
fn touches_structure(varied: &[&Field]) -> bool {
    varied.iter().any(|f| matches!(f.segments[0].key.as_str(), "beam" | "plate" | "imported" | "damping" | "base"))
}

/// A study's base case.
#[derive(Clone, Debug)]
pub struct BaseCase {
    /// The base case file (as resolved against the study file) and its text.
    pub file: String,
    pub text: String,
    /// Directory the base case's relative paths resolve against.
    pub dir: PathBuf,
    /// The base case as loaded and validated (with its analyses).
    pub case: Case,
    /// Harmonics and samples per period of the base case's steady-state or transient
    /// analysis (9 and none when it has neither).
    pub harmonics: usize,
    pub samples_per_period: Option<usize>,
    /// Rayleigh coefficients computed once from the base case and used by every case
    /// ([`BaseCase::cache_damping`]).
    pub cached_damping: Option<Rayleigh>,
    /// The modal reduction the base case's steady state asks for, if any: a study solves
    /// its cases' steady states on it (`sweep::reduced`).
    pub reduction: Option<ReductionSpec>,
    /// Whether every case of the study has the base's structure, so that one reduction basis
    /// serves them all ([`BaseCase::share_structure`]).
    pub shared_structure: bool,
    /// That reduction once a case has built it, for every evaluator of the study (the
    /// search's and the figures' alike): clones of the base share it.
    pub shared_reduction: Arc<Mutex<Option<Arc<SharedReduction>>>>,
    /// Actuator and link names of the base model, in model order.
    pub actuators: Vec<String>,
    pub links: Vec<String>,
    /// The base document with the analyses removed (and the cached damping inserted).
    value: toml::Value,
}

impl BaseCase {
    /// The files the study `study` reads through its base case: the base case file and its
    /// data files, each with what it is.
    pub fn input_files(&self, study: &str) -> Vec<(PathBuf, String)> {
        let mut files = vec![(PathBuf::from(&self.file), format!("the base case file of {study}"))];
        files.extend(self.case.data_files(&self.dir, &self.file));
        files
    }

    /// Reads the base case `rel` (relative to `dir`, the study file's directory) named by
    /// field `field` of `study`. It must be a valid case on its own (its errors name the
    /// base file) and have at least one actuator.
    pub fn load(study: &str, field: &str, dir: &Path, rel: &str) -> Result<BaseCase> {
        let path = dir.join(rel);
        let file = path.display().to_string();
        let text = crate::input_file::read_text(&path)
            .map_err(|e| Error::input(study, field, format!("cannot read the base case: {e}")))?;
        let base_dir = path.parent().map(Path::to_path_buf).unwrap_or_default();
        let lc = LoadedCase::from_str(&text, &file, base_dir.clone())?;
        let mut value: toml::Value = toml::from_str(&text)
            .map_err(|e| Error::Parse { file: file.clone(), message: e.to_string().trim_end().to_string() })?;
        if let Some(t) = value.as_table_mut() {
            t.remove("analysis");
        }
        let reduction = lc.case.analysis.iter().find_map(|a| match a {
            AnalysisSpec::SteadyState { reduction, .. } => reduction.clone(),
            _ => None,
        });
        let (harmonics, samples_per_period) = lc
            .case
            .analysis
            .iter()
            .find_map(|a| match a {
                AnalysisSpec::SteadyState { harmonics, samples_per_period, .. } => {
                    Some((harmonics.unwrap_or(DEFAULT_HARMONICS), Some(*samples_per_period)))
                }
                AnalysisSpec::Transient { harmonics, .. } => Some((harmonics.unwrap_or(DEFAULT_HARMONICS), None)),
                _ => None,
            })
            .unwrap_or((DEFAULT_HARMONICS, None));
        let (actuators, links) = names(&lc.case);
        if actuators.is_empty() {
            return Err(Error::input(&file, "actuator", "a study's base case needs at least one actuator"));
        }
        Ok(BaseCase {
            file,
            text,
            dir: base_dir,
            case: lc.case,
            harmonics,
            samples_per_period,
            cached_damping: None,
            reduction,
            shared_structure: false,
            shared_reduction: Arc::default(),
            actuators,
            links,
            value,
        })
    }

    /// The base document as the study uses it (analyses removed).
    pub fn value(&self) -> &toml::Value {
        &self.value
    }

    /// Checks `field` on the base case at each of `values`, alone: an unknown path, an
    /// integer field given a fraction, or a value the case refuses fails here, before
    /// anything runs, naming `study` and `name` (e.g. `parameter[0]`). Sets
    /// [`Field::integer`] from the base (a field it leaves at its default may be an
    /// integer: tried when the first value is whole).
    pub fn check_field(&self, field: &mut Field, values: &[f64], study: &str, name: &str) -> Result<()> {
        field.integer = matches!(get_path(&self.value, &field.segments), Some(toml::Value::Integer(_)));
        for (k, &v) in values.iter().enumerate() {
            match self.check_value(field, field.toml(v), study, name) {
                Ok(()) => {}
                Err(e) if k == 0 && !field.integer && v.fract() == 0.0 => {
                    let mut as_int = field.clone();
                    as_int.integer = true;
                    if self.check_value(&as_int, as_int.toml(v), study, name).is_err() {
                        return Err(e);
                    }
                    field.integer = true;
                }
                Err(e) => return Err(e),
            }
            if field.integer && v.fract() != 0.0 {
                return Err(Error::input(
                    study,
                    format!("{name}.values"),
                    format!("`{}` is an integer field, got {v}", field.path),
                ));
            }
        }
        Ok(())
    }

    /// Checks the base case with `field` set to `value` alone (see [`BaseCase::check_field`]).
    pub fn check_value(&self, field: &Field, value: toml::Value, study: &str, name: &str) -> Result<()> {
        let shown = value.to_string();
        let mut val = self.value.clone();
        set_path(&mut val, &field.segments, value)
            .map_err(|r| Error::input(study, format!("{name}.path"), format!("`{}`: {r}", field.path)))?;
        let case: Case = val.try_into().map_err(|e: toml::de::Error| {
            Error::input(
                study,
                format!("{name}.path"),
                format!("`{}` is not a case field the base case accepts: {}", field.path, e.message().trim_end()),
            )
        })?;
        case.validate(&self.file).map_err(|e| {
            Error::input(study, format!("{name}.values"), format!("{} = {shown} is not acceptable: {e}", field.path))
        })
    }

    /// Prepares a study whose base case's steady state asks for a modal reduction to share
    /// one reduction basis between its cases, when they all have the base's structure: a
    /// plate or an imported model that no field of `varied` changes (nor its damping). A
    /// plate is then meshed once, as the uniform grid of its `elements` (or its mesh file's
    /// grid), and every case's points attach through the elements' shape functions
    /// (`through_points = false`, exact for that mesh); otherwise each case's grid would
    /// follow its points. A beam study solves every case on its own mesh (which follows
    /// the feet) as before.
    pub fn share_structure(&mut self, varied: &[&Field]) {
        // A plate's point supports, masses and springs stand on grid lines drawn through
        // them; on the uniform grid they could fall between nodes, so such a plate shares
        // its structure only if it already asks for the uniform grid (or a mesh file).
        let plate_fixed = self.case.plate.as_ref().is_none_or(|p| {
            let points = !p.support.is_empty() || !p.point_mass.is_empty() || !p.spring.is_empty();
            !points || p.mesh.file.is_some() || !p.mesh.through_points()
        });
        let kind_shares = self.case.plate.is_some() || self.case.imported.is_some();
        if self.reduction.is_none() || !kind_shares || !plate_fixed || touches_structure(varied) {
            return;
        }
        uniform_plate_mesh(self.value.as_table_mut().expect("a case is a table"));
        self.shared_structure = true;
    }

    /// Computes the structure's Rayleigh damping once and puts it in the base, when none of
    /// `varied` can change it (they leave the structure, `damping` and `base` alone), the
    /// base asks for Rayleigh damping by ratio, and every case has the base's structure (a
    /// beam's mesh moves with the feet by less than its discretisation error; a plate's
    /// only when the study shares one mesh, [`BaseCase::share_structure`]).
    pub fn cache_damping(&mut self, varied: &[&Field]) -> Result<()> {
        let same_structure = self.case.base == BaseKind::Beam || self.shared_structure;
        if touches_structure(varied) || !same_structure || self.case.damping.kind != DampingKind::RayleighRatio {
            return Ok(());
        }
        let stripped: Case = self.value.clone().try_into().map_err(|e: toml::de::Error| Error::Parse {
            file: self.file.clone(),
            message: e.message().trim_end().to_string(),
        })?;
        let lc = LoadedCase { case: stripped, file: self.file.clone(), dir: self.dir.clone(), text: String::new() };
        let structure = crate::case::build::build_structure(&lc)?;
        let d = &lc.case.damping;
        let r = crate::analysis::plan::rayleigh_from_ratio(&structure, d.zeta, d.modes)
            .map_err(|e| e.in_file(&self.file))?;
        let mut t = toml::map::Map::new();
        t.insert("kind".into(), toml::Value::String("rayleigh".into()));
        t.insert("a0".into(), toml::Value::Float(r.a0));
        t.insert("a1".into(), toml::Value::Float(r.a1));
        self.value.as_table_mut().expect("a case is a table").insert("damping".into(), toml::Value::Table(t));
        self.cached_damping = Some(r);
        Ok(())
    }

    /// Holds every case a study can make to `budget` before any case is built. Each varied
    /// field at each of its `extremes` (`(name, field, value)`: a parameter's or variable's
    /// least and greatest values) sizes its case's mesh from the counts, held to the budget
    /// and to the elements the solves take; the case with the largest mesh is then built
    /// and `analysis` at `harmonics` and `samples` per period estimated on it. Errors name
    /// `study` and the varied field (`name`) or the study's own setting.
    pub fn admit_cases(
        &self,
        study: &str,
        extremes: &[(String, &Field, toml::Value)],
        analysis: SweepAnalysis,
        (harmonics, samples): (usize, usize),
        budget: &Budget,
    ) -> Result<()> {
        let mut largest = (0, None);
        for (name, field, value) in extremes {
            let at = |reason: String| Error::input(study, name, format!("`{}` = {value}: {reason}", field.path));
            let lc = self.case_with([(*field, value.clone())], &self.file).map_err(at)?;
            if let Some(c) = cost::mesh(&lc) {
                budget.admit(&c).map_err(|e| at(e.to_string()))?;
                let bytes = c.bytes.unwrap_or(u64::MAX);
                if bytes > largest.0 {
                    largest = (bytes, Some(lc.clone()));
                }
            }
        }
        let lc = match largest.1 {
            Some(lc) => lc,
            None => self.case_with([], &self.file).map_err(|r| Error::input(study, "base", r))?,
        };
        let (model, sys) = plan::model_and_system_within(&lc, budget).map_err(|e| e.in_file(study))?;
        let (solve, search) = match analysis {
            SweepAnalysis::SteadyState => {
                let timing = DriveTiming::sampled(&model, samples).map_err(|e| e.in_file(study))?;
                (cost::steady_state(&model, &sys, samples), cost::cycle_search(&model, &timing))
            }
            SweepAnalysis::Transient => {
                let s = TransientSettings { harmonics: Some(harmonics), ..Default::default() };
                let timing = DriveTiming::stepped(&model, Step::of(s.dt, s.steps_per_period), s.duration, s.harmonics)
                    .map_err(|e| e.in_file(study))?;
                let solve = cost::transient(&model, &sys, &s, &timing);
                let steps = solve.steps.unwrap_or(u64::MAX);
                (solve, cost::drive_search(&model, steps as f64 * timing.dt, steps))
            }
        };
        budget.admit(&solve).map_err(|e| e.in_file(study))?;
        search.map_or(Ok(()), |c| budget.admit(&c).map_err(|e| e.in_file(&self.file)))
    }

    /// The base document with each `(field, value)` set.
    pub fn document<'f>(
        &self,
        set: impl IntoIterator<Item = (&'f Field, toml::Value)>,
    ) -> std::result::Result<toml::Value, String> {
        let mut val = self.value.clone();
        for (f, v) in set {
            set_path(&mut val, &f.segments, v)?;
        }
        Ok(val)
    }

    /// The case with each `(field, value)` set, deserialised and validated; `label` names
    /// it in messages of the case layer (e.g. `base.toml [sweep case 3]`). The error is
    /// the reason, for the caller to place.
    pub fn case_with<'f>(
        &self,
        set: impl IntoIterator<Item = (&'f Field, toml::Value)>,
        label: &str,
    ) -> std::result::Result<LoadedCase, String> {
        let val = self.document(set)?;
        let case: Case = val.try_into().map_err(|e: toml::de::Error| e.message().trim_end().to_string())?;
        LoadedCase::from_case(case, label, self.dir.clone()).map_err(|e| e.to_string())
    }

    /// The voltage of actuator `a` with the fields under `actuator[a].voltage` among `set`
    /// applied, loaded and validated, without building the whole case.
    pub fn voltage_with<'f>(
        &self,
        a: usize,
        set: impl IntoIterator<Item = (&'f Field, toml::Value)>,
        label: &str,
    ) -> std::result::Result<VoltageInput, String> {
        let field = format!("actuator[{a}].voltage");
        let path = [Segment { key: "actuator".into(), index: Some(a) }, Segment { key: "voltage".into(), index: None }];
        let mut val = get_path(&self.value, &path).cloned().unwrap_or(toml::Value::Table(Default::default()));
        for (f, v) in set {
            if f.drive_of() == Some(a) {
                set_path(&mut val, &f.segments[2..], v)?;
            }
        }
        let spec: SignalSpec = val.try_into().map_err(|e: toml::de::Error| e.message().trim_end().to_string())?;
        spec.validate(label, &field).map_err(|e| e.to_string())?;
        spec.build(&self.dir, label, &field).map_err(|e| e.to_string())
    }
}

/// The nodes of an imported model inside a box, as a study writes a parameter's or
/// variable's values: `nodes_in = { min = [x, y, z], max = [x, y, z], component = "uz" }`
/// (m; the component defaults to the point's own in the base case).
#[derive(Clone, Debug, serde::Deserialize)]
#[serde(deny_unknown_fields)]
pub struct NodeBox {
    pub min: [f64; 3],
    pub max: [f64; 3],
    pub component: Option<String>,
}

impl BaseCase {
    /// The ids (ascending) of the base model's nodes inside `b` (faces included) where the
    /// point `field` names (a `node` field, e.g. `actuator[0].node`) can stand: those with
    /// an unfixed row of the component, and on which the case with the field set builds (a
    /// frame whose leg would fall off the model is left out). Refused if there are none,
    /// naming `study` and `name` (e.g. `parameter[0]`).
    pub fn nodes_in(&self, field: &Field, b: &NodeBox, study: &str, name: &str) -> Result<Vec<i64>> {
        let at = format!("{name}.nodes_in");
        let bad = |sub: &str, why: String| Error::input(study, format!("{at}{sub}"), why);
        if self.case.imported.is_none() {
            return Err(bad("", "lists nodes of an imported model, and the base case has none".into()));
        }
        let Some((_, parent)) = field.segments.split_last().filter(|(l, _)| l.key == "node" && l.index.is_none())
        else {
            return Err(bad(
                "",
                format!("lists node ids: vary a `node` field (e.g. `actuator[0].node`), not `{}`", field.path),
            ));
        };
        let sibling = [parent, &[Segment { key: "component".into(), index: None }]].concat();
        let component = match (&b.component, get_path(&self.value, &sibling).and_then(|v| v.as_str())) {
            (Some(c), _) => c.clone(),
            (None, Some(c)) => c.to_string(),
            (None, None) => return Err(bad(".component", "required: the base case gives this point none".into())),
        };
        let (c, _) = crate::imported::dof_map::parse_component(&component).map_err(|why| bad(".component", why))?;
        for k in 0..3 {
            if !(b.min[k].is_finite() && b.max[k].is_finite()) {
                return Err(bad("", "the corners must be finite (m)".into()));
            }
            if b.min[k] > b.max[k] {
                return Err(bad(".max", format!("max = {:?} is below min = {:?} along axis {k}", b.max, b.min)));
            }
        }
        let lc =
            LoadedCase { case: self.case.clone(), file: self.file.clone(), dir: self.dir.clone(), text: String::new() };
        let structure = crate::case::build::build_structure(&lc)?;
        let model = structure.imported().expect("an imported case builds an imported model");
        let inside = |p: &[f64; 3]| (0..3).all(|k| (b.min[k]..=b.max[k]).contains(&p[k]));
        let mut ids: Vec<i64> = (0..model.nodes.len())
            .filter(|&i| inside(&model.nodes[i].xyz) && model.row(i, c as usize).is_some_and(|r| !model.fixed[r]))
            .map(|i| model.nodes[i].id)
            .collect();
        ids.sort_unstable();
        let stands = |id: i64| {
            self.case_with([(field, toml::Value::Integer(id))], &self.file)
                .is_ok_and(|lc| crate::case::build::build_model(&lc).is_ok())
        };
        let found = ids.len();
        ids.retain(|&id| stands(id));
        if ids.is_empty() {
            let (lo, hi) = model.nodes.iter().fold(([f64::INFINITY; 3], [f64::NEG_INFINITY; 3]), |(lo, hi), n| {
                ([0, 1, 2].map(|k| lo[k].min(n.xyz[k])), [0, 1, 2].map(|k| hi[k].max(n.xyz[k])))
            });
            let name = crate::imported::COMPONENTS[c as usize];
            return Err(bad(
                "",
                if found == 0 {
                    format!(
                        "no node with a free {name} DOF lies in the box {:?} to {:?} m (the model's nodes span {lo:?} \
                         to {hi:?} m)",
                        b.min, b.max
                    )
                } else {
                    format!(
                        "`{}` can stand on none of the {found} nodes in the box: check the base case at one of them",
                        field.path
                    )
                },
            ));
        }
        Ok(ids)
    }
}

/// Actuator names (given, or `inertial`/`frame`, numbered when there are several) and
/// their links' identifiers ([`link_id`]: `name_stack`, `name_left_leg`, `name_right_leg`).
fn names(case: &Case) -> (Vec<String>, Vec<String>) {
    let mut actuators = Vec::new();
    let mut links = Vec::new();
    for (i, a) in case.actuator.iter().enumerate() {
        let name = a.effective_name(i, case.actuator.len());
        let l: &[&str] = match a.body {
            BodySpec::Inertial { .. } => &Inertial::LINKS,
            BodySpec::Frame(_) => &Frame::LINKS,
        };
        links.extend(l.iter().map(|l| link_id(&name, l)));
        actuators.push(name);
    }
    (actuators, links)
}
