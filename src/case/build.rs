//! From a validated case to the physical model.

use super::plate_mesh::PlateMesh;
use super::schema::*;
use super::LoadedCase;
use crate::actuator::{Actuator, FootBase, Frame, Inertial, Leg, Stack};
use crate::assembly::system::{Model, PointLoad, Sensor};
use crate::assembly::{Damping, Rayleigh};
use crate::beam::mesh::RequiredPoint;
use crate::beam::{Beam, GroundedSpring, MassKind, Material, Mesh, PointMass, Section, Support, SupportKind};
use crate::error::{Error, Result};
use crate::plate::{Edge, Edges, Grid, Plate, PointSupport, PointSupportKind};
use crate::structure::{Location, Structure};

/// Points that must be mesh nodes, named after the field that asks for them.
pub fn required_points(case: &Case) -> Vec<RequiredPoint> {
    let mut pts = Vec::new();
    let b = &case.beam;
    let mut add = |x: f64, name: String| pts.push(RequiredPoint { x, name });
    for (i, s) in b.support.iter().enumerate() {
        add(s.x, format!("beam.support[{i}].x"));
    }
    for (i, p) in b.point_mass.iter().enumerate() {
        add(p.x, format!("beam.point_mass[{i}].x"));
    }
    for (i, s) in b.spring.iter().enumerate() {
        add(s.x, format!("beam.spring[{i}].x"));
    }
    if case.base == BaseKind::Beam {
        for (i, a) in case.actuator.iter().enumerate() {
            add(a.x_e, format!("actuator[{i}].x_e"));
            if let BodySpec::Frame(f) = &a.body {
                let (left, right) = f.leg_positions(a.x_e);
                add(left, format!("actuator[{i}] left leg (x_e − e − a)"));
                add(right, format!("actuator[{i}] right leg (x_e − e + a)"));
            }
        }
    }
    for (i, s) in case.sensor.iter().enumerate() {
        add(s.location().x(), format!("sensor[{i}].x"));
    }
    for (i, l) in case.load.iter().enumerate() {
        add(l.location().x(), format!("load[{i}].x"));
    }
    for (i, an) in case.analysis.iter().enumerate() {
        if let AnalysisSpec::Harmonic { force, .. } = an {
            for (j, f) in force.iter().enumerate() {
                add(f.location().x(), format!("analysis[{i}].force[{j}].x"));
            }
        }
    }
    pts
}

/// The points of a plate case that attach to the plate: every actuator foot, sensor, load,
/// harmonic force, point support, mass and spring, each named after the field that places
/// it.
pub fn plate_points(case: &Case, p: &PlateSpec) -> Vec<((f64, f64), String)> {
    let mut pts: Vec<(Location, String)> = Vec::new();
    for (i, a) in case.actuator.iter().enumerate() {
        pts.extend(a.feet().into_iter().map(|(foot, at)| (at, format!("actuator[{i}] {foot} foot"))));
    }
    pts.extend(case.sensor.iter().enumerate().map(|(i, s)| (s.location(), format!("sensor[{i}].at"))));
    pts.extend(case.load.iter().enumerate().map(|(i, l)| (l.location(), format!("load[{i}].at"))));
    for (i, an) in case.analysis.iter().enumerate() {
        if let AnalysisSpec::Harmonic { force, .. } = an {
            let named = force.iter().enumerate().map(|(j, f)| (f.location(), format!("analysis[{i}].force[{j}].at")));
            pts.extend(named);
        }
    }
    let mut xy: Vec<((f64, f64), String)> =
        pts.into_iter().map(|(l, name)| ((l.x(), l.y().unwrap_or(0.0)), name)).collect();
    let at = |kind: &str, i: usize, at: [f64; 2]| ((at[0], at[1]), format!("plate.{kind}[{i}].at"));
    xy.extend(p.support.iter().enumerate().map(|(i, s)| at("support", i, s.at)));
    xy.extend(p.point_mass.iter().enumerate().map(|(i, s)| at("point_mass", i, s.at)));
    xy.extend(p.spring.iter().enumerate().map(|(i, s)| at("spring", i, s.at)));
    xy
}

/// Smallest gap between two grid lines through points, as a fraction of the nominal
/// element L/n: a line through each of two points closer than that makes a sliver of
/// elements beside full ones, whose stiffness (∝ 1/h³ across it) swamps the plate's
/// bending in round-off (at 4·10⁻⁴ of an element the calibration's modes are wrong; at
/// 10⁻² powers still hold 3·10⁻⁸).
const SLIVER: f64 = 1e-3;

/// Refuses two points whose grid lines along x (or y) would be closer than [`SLIVER`] of an
/// element but not the same line, naming both and what to do.
fn refuse_slivers(file: &str, pts: &[((f64, f64), String)], lengths: [f64; 2], elements: [usize; 2]) -> Result<()> {
    for (axis, name) in [(0, "x"), (1, "y")] {
        let coord = |p: &((f64, f64), String)| if axis == 0 { p.0 .0 } else { p.0 .1 };
        let mut sorted: Vec<&((f64, f64), String)> = pts.iter().collect();
        sorted.sort_by(|a, b| coord(a).total_cmp(&coord(b)));
        let (same, h) = (1e-9 * lengths[axis], lengths[axis] / elements[axis].max(1) as f64);
        for w in sorted.windows(2) {
            let gap = coord(w[1]) - coord(w[0]);
            if gap > same && gap < SLIVER * h {
                return Err(Error::input(
                    file,
                    w[1].1.clone(),
                    format!(
                        "{name} = {} lies {gap:.3e} m from {name} = {} of `{}`: a grid line through each makes \
                         elements {gap:.1e} m wide beside ones of {h:.3e} m, too thin to solve accurately. Put \
                         both on one line (the same {name}), at least {:.1e} m apart, or set \
                         `plate.mesh.through_points = false`",
                        coord(w[1]),
                        coord(w[0]),
                        w[0].1,
                        SLIVER * h
                    ),
                ));
            }
        }
    }
    Ok(())
}

/// The plate's grid and its elements' sheets: a mesh file's, or the generated grid (lines
/// through every attachment point unless the mesh says otherwise) of the plate's own sheet.
fn plate_mesh(lc: &LoadedCase, p: &PlateSpec) -> Result<PlateMesh> {
    if let Some(f) = &p.mesh.file {
        // A mesh that cannot be read at all is the case's `plate.mesh.file` pointing at the
        // wrong file; its contents' mistakes are the mesh file's.
        return super::plate_mesh::read(&lc.dir.join(f), p).map_err(|e| match e {
            Error::Io { .. } | Error::Parse { .. } => Error::input(&lc.file, "plate.mesh.file", e.to_string()),
            e => e,
        });
    }
    let [nx, ny] = p.mesh.elements();
    let named = plate_points(&lc.case, p);
    if p.mesh.through_points() {
        refuse_slivers(&lc.file, &named, [p.length_x, p.length_y], [nx, ny])?;
    }
    let pts: Vec<(f64, f64)> = named.into_iter().map(|(at, _)| at).collect();
    let through: &[(f64, f64)] = if p.mesh.through_points() { &pts } else { &[] };
    let grid = Grid::through(p.length_x, p.length_y, nx, ny, through);
    Ok(PlateMesh { grid, sheets: Vec::new(), element_sheet: Vec::new() })
}

/// Builds the plate alone: its grid and sheets ([`plate_mesh`]), edges, point supports,
/// masses and springs.
pub fn build_plate(lc: &LoadedCase, p: &PlateSpec) -> Result<Plate> {
    let PlateMesh { grid, sheets, element_sheet } = plate_mesh(lc, p)?;
    let edge = |e: EdgeSpec| match e {
        EdgeSpec::Clamped => Edge::Clamped,
        EdgeSpec::SimplySupported => Edge::SimplySupported,
        EdgeSpec::Free => Edge::Free,
    };
    let e = p.edges;
    let mut plate = Plate {
        grid,
        thickness: p.thickness,
        youngs_modulus: p.youngs_modulus,
        poisson_ratio: p.poisson_ratio,
        density: p.density,
        sheets,
        element_sheet,
        edges: Edges { x0: edge(e.x0), x1: edge(e.x1), y0: edge(e.y0), y1: edge(e.y1) },
        supports: Vec::new(),
        point_masses: Vec::new(),
        springs: Vec::new(),
    };
    // Point supports, masses and springs act on one node each: with grid lines through
    // the points they are nodes; on a uniform grid or a mesh file's they must already be.
    let why = match &p.mesh.file {
        Some(f) => format!("the mesh file {f} has no grid line through it in x or y; add one"),
        None => "plate.mesh.through_points = false puts no grid line through it".to_string(),
    };
    let node = |at: [f64; 2], field: String| {
        plate.grid.node_at(at[0], at[1]).ok_or_else(|| {
            Error::input(&lc.file, field, format!("(x, y) = ({}, {}) m is not a grid node ({why})", at[0], at[1]))
        })
    };
    for (i, s) in p.support.iter().enumerate() {
        let kind = match s.kind {
            PlateSupportKindSpec::Pinned => PointSupportKind::Pinned,
            PlateSupportKindSpec::Clamped => PointSupportKind::Clamped,
            PlateSupportKindSpec::Spring => PointSupportKind::Spring { k_w: s.k_w.unwrap_or(0.0) },
        };
        let n = node(s.at, format!("plate.support[{i}].at"))?;
        plate.supports.push(PointSupport { node: n, kind });
    }
    for (i, m) in p.point_mass.iter().enumerate() {
        let n = node(m.at, format!("plate.point_mass[{i}].at"))?;
        plate.point_masses.push(PointMass { node: n, mass: m.mass, rotary_inertia: 0.0 });
    }
    for (i, s) in p.spring.iter().enumerate() {
        let n = node(s.at, format!("plate.spring[{i}].at"))?;
        plate.springs.push(GroundedSpring { node: n, stiffness: s.stiffness, damping: s.damping });
    }
    Ok(plate)
}

/// Builds the case's structure: its plate or imported model if it has one, else its beam.
pub fn build_structure(lc: &LoadedCase) -> Result<Structure> {
    match (&lc.case.plate, &lc.case.imported) {
        (Some(p), _) => Ok(Structure::Plate(build_plate(lc, p)?)),
        (None, Some(m)) => Ok(Structure::Imported(crate::imported::shared(&m.files(&lc.dir), &lc.file)?)),
        (None, None) => Ok(Structure::Beam(build_beam(lc)?)),
    }
}

/// Where a point of the case is on `structure` (an imported node's position filled in, a
/// point written by position resolved to its node), refused naming `field` if it does not
/// attach there.
fn resolved(
    file: &str,
    structure: Option<&Structure>,
    at: Location,
    field: impl Fn(&Location) -> String,
) -> Result<Location> {
    let Some(s) = structure else { return Ok(at) };
    if let Location::Node { .. } | Location::Near { .. } = at {
        s.attach(&at).map_err(|why| Error::input(file, field(&at), why))?;
    }
    Ok(s.resolve(at))
}

/// A frame's three nodes on an imported model against its `a` and `e`: the legs 2a apart,
/// the stack e from their midpoint (each to 1 % of a), so the top beam's rigid-body
/// kinematics describe the frame that stands there.
fn frame_spacing(file: &str, f: &str, feet: [Location; 3], a: f64, e: f64) -> Result<()> {
    let xyz = |l: &Location| match l {
        Location::Node { xyz, .. } => *xyz,
        _ => [l.x(), l.y().unwrap_or(0.0), 0.0],
    };
    let [s, l, r] = feet.map(|p| xyz(&p));
    let dist = |p: [f64; 3], q: [f64; 3]| p.iter().zip(&q).map(|(a, b)| (a - b) * (a - b)).sum::<f64>().sqrt();
    let mid = [0, 1, 2].map(|i| 0.5 * (l[i] + r[i]));
    let (span, offset) = (dist(l, r), dist(s, mid));
    if (span - 2.0 * a).abs() > 0.01 * a || (offset - e.abs()).abs() > 0.01 * a {
        return Err(Error::input(
            file,
            format!("{f}.legs"),
            format!(
                "the leg nodes are {span} m apart and the stack node {offset} m from their midpoint, but the \
                 frame has 2a = {} m and |e| = {} m: set `a` and `e` to the nodes' spacing",
                2.0 * a,
                e.abs()
            ),
        ));
    }
    Ok(())
}

/// Builds the beam alone (its mesh, supports and attachments).
pub fn build_beam(lc: &LoadedCase) -> Result<Beam> {
    let case = &lc.case;
    let b = &case.beam;
    let section = Section { width: b.width, thickness: b.thickness };
    let material = Material { youngs_modulus: b.youngs_modulus, density: b.density };
    let pts = required_points(case);
    let mesh = match &b.mesh.file {
        Some(f) => {
            let path = lc.dir.join(f);
            // Named from the case's side too: a mesh that cannot be read at all is the case's
            // `beam.mesh.file` pointing at the wrong file.
            let mesh = Mesh::read(&path, section, material).map_err(|e| match e {
                Error::Io { .. } | Error::Parse { .. } => Error::input(&lc.file, "beam.mesh.file", e.to_string()),
                e => e,
            })?;
            let mfile = path.display().to_string();
            super::ranges::mesh_lines(&mfile, "nodes", &mesh.x)?;
            if (mesh.length() - b.length).abs() > 1e-9 * b.length {
                return Err(Error::input(
                    &mfile,
                    "nodes",
                    format!(
                        "the mesh ends at x = {} m but beam.length in {} is {} m",
                        mesh.length(),
                        lc.file,
                        b.length
                    ),
                ));
            }
            mesh.require_nodes(&pts, &mfile)?;
            mesh
        }
        None => Mesh::uniform(b.length, b.mesh.elements, &pts, section, material),
    };
    let node = |x: f64, field: String| {
        mesh.node_at(x).ok_or_else(|| Error::input(&lc.file, field, format!("x = {x} m is not on a mesh node")))
    };
    let mut supports = Vec::new();
    if b.support.is_empty() {
        supports.push(Support { node: 0, kind: SupportKind::Clamped });
        supports.push(Support { node: mesh.n_nodes() - 1, kind: SupportKind::Clamped });
    }
    for (i, s) in b.support.iter().enumerate() {
        let kind = match s.kind {
            SupportKindSpec::Clamped => SupportKind::Clamped,
            SupportKindSpec::Pinned => SupportKind::Pinned,
            SupportKindSpec::Guided => SupportKind::Guided,
            SupportKindSpec::Free => continue,
            SupportKindSpec::Spring => {
                SupportKind::Spring { k_w: s.k_w.unwrap_or(0.0), k_theta: s.k_theta.unwrap_or(0.0) }
            }
        };
        supports.push(Support { node: node(s.x, format!("beam.support[{i}].x"))?, kind });
    }
    let mut beam = Beam::new(mesh.clone(), supports);
    beam.mass_kind = match b.mass {
        MassSpec::Consistent => MassKind::Consistent,
        MassSpec::Lumped => MassKind::Lumped,
    };
    for (i, p) in b.point_mass.iter().enumerate() {
        beam.point_masses.push(PointMass {
            node: node(p.x, format!("beam.point_mass[{i}].x"))?,
            mass: p.mass,
            rotary_inertia: p.rotary_inertia,
        });
    }
    for (i, s) in b.spring.iter().enumerate() {
        beam.springs.push(GroundedSpring {
            node: node(s.x, format!("beam.spring[{i}].x"))?,
            stiffness: s.stiffness,
            damping: s.damping,
        });
    }
    Ok(beam)
}

/// Builds the model a case describes, exactly as written: damping given as a ratio stays a
/// ratio until [`crate::analysis::plan::calibrate`] computes the modes it names.
pub fn build_model(lc: &LoadedCase) -> Result<Model> {
    let case = &lc.case;
    let beam = match case.base {
        BaseKind::Beam => Some(build_structure(lc)?),
        BaseKind::Rigid => None,
    };
    let d = &case.damping;
    let damping = match (&beam, d.kind) {
        // A given damping matrix is part of the structure's own C (assembly).
        (None, _) | (_, DampingKind::None | DampingKind::Given) => Damping::None,
        (Some(_), DampingKind::Rayleigh) => {
            Damping::Rayleigh(Rayleigh { a0: d.a0.unwrap_or(0.0), a1: d.a1.unwrap_or(0.0) })
        }
        (Some(_), DampingKind::RayleighRatio) => Damping::RayleighRatio { zeta: d.zeta, modes: d.modes },
        (Some(_), DampingKind::Modal) => Damping::Modal(d.ratios.clone()),
        (Some(_), DampingKind::Hysteretic) => Damping::Hysteretic { eta: d.eta },
    };
    let mut actuators = Vec::new();
    for (i, a) in case.actuator.iter().enumerate() {
        let voltage = a.voltage.build(&lc.dir, &lc.file, &format!("actuator[{i}].voltage"))?;
        let s = &a.stack;
        let stack = Stack {
            k_p: s.k_p,
            c_p: s.c_p,
            m_p: s.m_p,
            hysteresis: s.bouc_wen(),
            h0: s.h0,
            voltage,
            hysteresis_on: s.hysteresis,
        };
        let on = beam.as_ref();
        let f_field = |what: &'static str| move |_: &Location| format!("actuator[{i}].{what}");
        let at = resolved(&lc.file, on, a.location(), |at| format!("actuator[{i}].{}", at.field()))?;
        let foot = match case.base {
            BaseKind::Beam => FootBase::On(at),
            BaseKind::Rigid => FootBase::Ground,
        };
        let legs = match (&a.body, a.legs) {
            (BodySpec::Frame(fr), Some(_)) => {
                let feet = a.feet();
                let l = resolved(&lc.file, on, feet[1].1, f_field("legs"))?;
                let r = resolved(&lc.file, on, feet[2].1, f_field("legs"))?;
                frame_spacing(&lc.file, &format!("actuator[{i}]"), [at, l, r], fr.a, fr.e)?;
                Some([l, r])
            }
            // On an imported model the legs stand on the nodes nearest x_c ∓ a·d from the
            // stack's node, so that they move with it (a sweep or optimisation over nodes).
            (BodySpec::Frame(fr), None) if matches!(at, Location::Node { .. }) => {
                let [_, l, r] = crate::actuator::frame::feet(at, fr.e, fr.a, a.direction.to_radians())
                    .map(|p| p.within(a.tolerance));
                let leg = |p, side: &str| {
                    resolved(&lc.file, on, p, |_| format!("actuator[{i}].direction")).map_err(|e| match e {
                        Error::Input { file, field, reason } => {
                            Error::Input { file, field, reason: format!("the {side} leg: {reason}") }
                        }
                        e => e,
                    })
                };
                let (l, r) = (leg(l, "left")?, leg(r, "right")?);
                frame_spacing(&lc.file, &format!("actuator[{i}]"), [at, l, r], fr.a, fr.e)?;
                Some([l, r])
            }
            _ => None,
        };
        let name = a.effective_name(i, case.actuator.len());
        actuators.push(match &a.body {
            BodySpec::Inertial { m_t } => Actuator::Inertial(Inertial { name, stack, m_t: *m_t, foot }),
            BodySpec::Frame(f) => Actuator::Frame(Frame {
                name,
                stack,
                m_b: f.m_b,
                j_b: f.j_b,
                a: f.a,
                e: f.e,
                left: Leg { k_l: f.left.k_l, c_l: f.left.c_l },
                right: Leg { k_l: f.right.k_l, c_l: f.right.c_l },
                at: matches!(foot, FootBase::On(_)).then_some(at),
                direction: a.direction.to_radians(),
                legs,
            }),
        });
    }
    let mut sensors = Vec::with_capacity(case.sensor.len());
    for (i, s) in case.sensor.iter().enumerate() {
        let at = resolved(&lc.file, beam.as_ref(), s.location(), |at| format!("sensor[{i}].{}", at.field()))?;
        sensors.push(Sensor { name: s.name.clone(), at });
    }
    let mut loads = Vec::with_capacity(case.load.len());
    for (i, l) in case.load.iter().enumerate() {
        let force = l.force.build(&lc.dir, &lc.file, &format!("load[{i}].force"))?;
        let at = resolved(&lc.file, beam.as_ref(), l.location(), |at| format!("load[{i}].{}", at.field()))?;
        loads.push(PointLoad { name: l.effective_name(i), at, force });
    }
    let roundoff_tolerance = case.beam.mesh.roundoff_tolerance;
    Ok(Model { structure: beam, damping, actuators, sensors, loads, roundoff_tolerance })
}
