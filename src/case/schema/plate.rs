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
    #[serde(default)]
    pub mesh: PlateMeshSpec,
    pub edges: EdgesSpec,
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub support: Vec<PlateSupportSpec>,
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub point_mass: Vec<PlatePointMassSpec>,
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub spring: Vec<PlateSpringSpec>,
}

/// The generated grid: about `elements = [n_x, n_y]` Bogner–Fox–Schmit elements, with grid
/// lines through every attachment point (or, with `through_points = false`, a uniform grid
/// on which points between nodes attach through the element's shape functions).
#[derive(Clone, Debug, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct PlateMeshSpec {
    #[serde(default = "d_elements")]
    pub elements: [usize; 2],
    #[serde(default = "d_true")]
    pub through_points: bool,
}

fn d_elements() -> [usize; 2] {
    [20, 16]
}

fn d_true() -> bool {
    true
}

impl Default for PlateMeshSpec {
    fn default() -> Self {
        PlateMeshSpec { elements: d_elements(), through_points: true }
    }
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
        if !(p.poisson_ratio > -1.0 && p.poisson_ratio < 0.5) {
            return Err(Error::input(
                file,
                "plate.poisson_ratio",
                format!("{}: an isotropic solid has −1 < ν < 0.5", p.poisson_ratio),
            ));
        }
        if p.thickness >= 0.1 * p.length_x.min(p.length_y) {
            return Err(Error::input(
                file,
                "plate.thickness",
                format!(
                    "{} m is not thin beside the sides {} × {} m: Kirchhoff theory (spec §16) needs h below a \
                     tenth of the shorter side",
                    p.thickness, p.length_x, p.length_y
                ),
            ));
        }
        for (k, n) in ["x", "y"].iter().zip(p.mesh.elements) {
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
