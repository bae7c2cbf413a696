//! The thin plate (spec §16) as a case file writes it: `[plate]` in place of `[beam]`.

use super::{non_negative, positive, Extent};
use crate::error::{Error, Result};
use crate::structure::Location;
use serde::{Deserialize, Serialize};

/// A uniform isotropic rectangular plate: geometry (m), material (Pa, kg/m³), mesh, edges,
/// point supports and attachments. Nothing defaults: a plate is always described.
#[derive(Clone, Debug, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct PlateSpec {
    pub length_x: f64,
    pub length_y: f64,
    pub thickness: f64,
    pub youngs_modulus: f64,
    pub poisson_ratio: f64,
    pub density: f64,
    #[serde(default, serialize_with = "resolved_mesh")]
    pub mesh: PlateMeshSpec,
    pub edges: EdgesSpec,
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub support: Vec<PlateSupportSpec>,
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub point_mass: Vec<PlatePointMassSpec>,
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub spring: Vec<PlateSpringSpec>,
}

/// Either the generated grid: about `elements = [n_x, n_y]` Bogner–Fox–Schmit elements,
/// with grid lines through every attachment point (or, with `through_points = false`, a
/// uniform grid on which points between nodes attach through the element's shape
/// functions); or a mesh file (`file`, relative to the case file: its grid lines and
/// regions of other thickness or material, see [`crate::case::plate_mesh`]).
#[derive(Clone, Debug, Default, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct PlateMeshSpec {
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub elements: Option<[usize; 2]>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub through_points: Option<bool>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub file: Option<String>,
    /// Whether each steady state and periodic transient is also run on a grid of half the
    /// elements each way, to estimate the grid's error in every point power (default on
    /// a generated grid; a mesh file has no coarser grid).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub error_estimate: Option<bool>,
}

/// The generated grid's elements when none are given.
pub const DEFAULT_PLATE_ELEMENTS: [usize; 2] = [20, 16];

impl PlateMeshSpec {
    /// The generated grid's elements along x and y.
    pub fn elements(&self) -> [usize; 2] {
        self.elements.unwrap_or(DEFAULT_PLATE_ELEMENTS)
    }

    /// Whether the generated grid has lines through every attachment point (default).
    pub fn through_points(&self) -> bool {
        self.through_points.unwrap_or(true)
    }

    /// Whether the run estimates the grid's error (default: on a generated grid).
    pub fn error_estimate(&self) -> bool {
        self.error_estimate.unwrap_or(self.file.is_none())
    }
}

/// The mesh as a results file and a sweep see it: a generated grid with its defaults
/// filled in, a mesh file as written.
fn resolved_mesh<S: serde::Serializer>(m: &PlateMeshSpec, s: S) -> std::result::Result<S::Ok, S::Error> {
    let resolved = match m.file {
        Some(_) => m.clone(),
        None => PlateMeshSpec {
            elements: Some(m.elements()),
            through_points: Some(m.through_points()),
            file: None,
            error_estimate: Some(m.error_estimate()),
        },
    };
    resolved.serialize(s)
}

#[derive(Clone, Copy, Debug, Deserialize, Serialize, PartialEq, Eq)]
#[serde(rename_all = "snake_case")]
pub enum EdgeSpec {
    Clamped,
    SimplySupported,
    Free,
}

/// Each edge's condition: `x0` is x = 0, `x1` is x = L_x, `y0` is y = 0, `y1` is y = L_y.
#[derive(Clone, Copy, Debug, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct EdgesSpec {
    pub x0: EdgeSpec,
    pub x1: EdgeSpec,
    pub y0: EdgeSpec,
    pub y1: EdgeSpec,
}

#[derive(Clone, Copy, Debug, Deserialize, Serialize, PartialEq, Eq)]
#[serde(rename_all = "snake_case")]
pub enum PlateSupportKindSpec {
    /// w = 0.
    Pinned,
    /// w = ∂w/∂x = ∂w/∂y = 0.
    Clamped,
    /// A spring on w, `k_w` (N/m).
    Spring,
}

#[derive(Clone, Debug, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct PlateSupportSpec {
    pub at: [f64; 2],
    pub kind: PlateSupportKindSpec,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub k_w: Option<f64>,
}

#[derive(Clone, Debug, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct PlatePointMassSpec {
    pub at: [f64; 2],
    /// kg
    pub mass: f64,
}

#[derive(Clone, Debug, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct PlateSpringSpec {
    pub at: [f64; 2],
    /// N/m
    pub stiffness: f64,
    /// N·s/m
    #[serde(default)]
    pub damping: f64,
}

/// Most elements a generated plate grid may have along a side.
pub const MAX_SIDE_ELEMENTS: usize = 2000;

/// Refuses a `thickness` (m, the field `field`) that is not thin beside the sides `lx` ×
/// `ly`: Kirchhoff theory needs h below a tenth of the shorter side.
pub fn thin(file: &str, field: &str, thickness: f64, lx: f64, ly: f64) -> Result<()> {
    if thickness < 0.1 * lx.min(ly) {
        return Ok(());
    }
    Err(Error::input(
        file,
        field,
        format!(
            "{thickness} m is not thin beside the sides {lx} × {ly} m: Kirchhoff theory (spec §16) needs h below a \
             tenth of the shorter side"
        ),
    ))
}

impl PlateSpec {
    pub fn extent(&self) -> Extent {
        Extent::Plate { lx: self.length_x, ly: self.length_y }
    }

    pub(super) fn validate(&self, file: &str) -> Result<()> {
        let p = self;
        positive(file, "plate.length_x", p.length_x)?;
        positive(file, "plate.length_y", p.length_y)?;
        positive(file, "plate.thickness", p.thickness)?;
        positive(file, "plate.youngs_modulus", p.youngs_modulus)?;
        positive(file, "plate.density", p.density)?;
        crate::case::ranges::poisson_ratio(file, "plate.poisson_ratio", p.poisson_ratio)?;
        thin(file, "plate.thickness", p.thickness, p.length_x, p.length_y)?;
        match (&p.mesh.file, p.mesh.elements, p.mesh.through_points) {
            (Some(_), Some(_), _) => {
                return Err(Error::input(
                    file,
                    "plate.mesh.elements",
                    "give `elements` (a generated grid) or `file` (a mesh file), not both",
                ))
            }
            (Some(_), None, Some(_)) => {
                return Err(Error::input(
                    file,
                    "plate.mesh.through_points",
                    "a mesh file's grid lines are as written: points between them attach through the elements' \
                     shape functions; drop `through_points`",
                ))
            }
            (Some(_), _, _) if p.mesh.error_estimate == Some(true) => {
                return Err(Error::input(
                    file,
                    "plate.mesh.error_estimate",
                    "the estimate compares the generated grid with one of half its elements; a mesh file's grid \
                     is as written: compare two mesh files' runs yourself, or give `elements`",
                ))
            }
            _ => {}
        }
        for (k, n) in ["x", "y"].iter().zip(p.mesh.elements()) {
            if !(1..=MAX_SIDE_ELEMENTS).contains(&n) {
                return Err(Error::input(
                    file,
                    "plate.mesh.elements",
                    format!("{n} elements along {k}: give 1 to {MAX_SIDE_ELEMENTS}"),
                ));
            }
        }
        let ext = self.extent();
        let point = |field: String, at: [f64; 2]| -> Result<()> {
            ext.holds(&Location::Plate { x: at[0], y: at[1] }).map_err(|why| Error::input(file, field, why))
        };
        for (i, s) in p.support.iter().enumerate() {
            point(format!("plate.support[{i}].at"), s.at)?;
            match (s.kind, s.k_w) {
                (PlateSupportKindSpec::Spring, Some(k)) => non_negative(file, &format!("plate.support[{i}].k_w"), k)?,
                (PlateSupportKindSpec::Spring, None) => {
                    return Err(Error::input(file, format!("plate.support[{i}]"), "a spring support needs `k_w`"))
                }
                (_, Some(_)) => {
                    return Err(Error::input(
                        file,
                        format!("plate.support[{i}].k_w"),
                        "applies only to kind = \"spring\"",
                    ))
                }
                (_, None) => {}
            }
        }
        for (i, m) in p.point_mass.iter().enumerate() {
            point(format!("plate.point_mass[{i}].at"), m.at)?;
            non_negative(file, &format!("plate.point_mass[{i}].mass"), m.mass)?;
        }
        for (i, s) in p.spring.iter().enumerate() {
            point(format!("plate.spring[{i}].at"), s.at)?;
            non_negative(file, &format!("plate.spring[{i}].stiffness"), s.stiffness)?;
            non_negative(file, &format!("plate.spring[{i}].damping"), s.damping)?;
        }
        Ok(())
    }
}
