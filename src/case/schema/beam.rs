//! The beam, its mesh, supports and attachments, and its damping, as a case file writes them.

use super::{non_negative, on_beam, positive};
use crate::error::{Error, Result};
use serde::{Deserialize, Serialize};

/// The beam: geometry (m), material (Pa, kg/m³), mesh, supports and attachments.
#[derive(Clone, Debug, Deserialize, Serialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct BeamSpec {
    #[serde(default = "d_length")]
    pub length: f64,
    #[serde(default = "d_width")]
    pub width: f64,
    #[serde(default = "d_thickness")]
    pub thickness: f64,
    #[serde(default = "d_e")]
    pub youngs_modulus: f64,
    #[serde(default = "d_rho")]
    pub density: f64,
    /// `consistent` (default) or `lumped`.
    #[serde(default)]
    pub mass: MassSpec,
    #[serde(default)]
    pub mesh: MeshSpec,
    /// Supports; default: clamped at x = 0 and x = L.
    #[serde(default)]
    pub support: Vec<SupportSpec>,
    #[serde(default)]
    pub point_mass: Vec<PointMassSpec>,
    #[serde(default)]
    pub spring: Vec<SpringSpec>,
}

fn d_length() -> f64 {
    0.730
}
fn d_width() -> f64 {
    0.050
}
fn d_thickness() -> f64 {
    0.005
}
fn d_e() -> f64 {
    210e9
}
fn d_rho() -> f64 {
    7850.0
}

impl Default for BeamSpec {
    fn default() -> Self {
        toml::from_str("").expect("defaults")
    }
}

#[derive(Clone, Copy, Debug, Default, Deserialize, Serialize, PartialEq, Eq)]
#[serde(rename_all = "snake_case")]
pub enum MassSpec {
    #[default]
    Consistent,
    Lumped,
}

/// Either a generated mesh of about `elements` elements, or a mesh file.
#[derive(Clone, Debug, Deserialize, Serialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct MeshSpec {
    #[serde(default = "d_elements")]
    pub elements: usize,
    /// Mesh file (relative to the case file); overrides `elements`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub file: Option<String>,
    /// Relative accuracy the harmonic and steady-state solves hold point powers and
    /// mobilities to against round-off (see `analysis::roundoff`); a result whose bound
    /// exceeds it is warned of.
    #[serde(default = "d_roundoff_tolerance")]
    pub roundoff_tolerance: f64,
    /// Refuse (instead of warn of) a result whose round-off bound exceeds the tolerance.
    #[serde(default)]
    pub strict_roundoff: bool,
}

fn d_elements() -> usize {
    200
}

fn d_roundoff_tolerance() -> f64 {
    crate::analysis::roundoff::DEFAULT_TOLERANCE
}

impl Default for MeshSpec {
    fn default() -> Self {
        MeshSpec {
            elements: d_elements(),
            file: None,
            roundoff_tolerance: d_roundoff_tolerance(),
            strict_roundoff: false,
        }
    }
}

#[derive(Clone, Copy, Debug, Deserialize, Serialize, PartialEq, Eq)]
#[serde(rename_all = "snake_case")]
pub enum SupportKindSpec {
    Clamped,
    Pinned,
    Guided,
    Free,
    Spring,
}

#[derive(Clone, Debug, Deserialize, Serialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct SupportSpec {
    /// Position (m).
    pub x: f64,
    pub kind: SupportKindSpec,
    /// Translational spring (N/m), for `spring`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub k_w: Option<f64>,
    /// Rotational spring (N·m/rad), for `spring`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub k_theta: Option<f64>,
}

#[derive(Clone, Debug, Deserialize, Serialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct PointMassSpec {
    pub x: f64,
    /// kg
    pub mass: f64,
    /// kg·m²
    #[serde(default)]
    pub rotary_inertia: f64,
}

#[derive(Clone, Debug, Deserialize, Serialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct SpringSpec {
    pub x: f64,
    /// N/m
    pub stiffness: f64,
    /// N·s/m
    #[serde(default)]
    pub damping: f64,
}

/// Beam damping.
#[derive(Clone, Debug, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct DampingSpec {
    #[serde(default)]
    pub kind: DampingKind,
    /// Damping ratio for `rayleigh_ratio` (–).
    #[serde(default = "d_zeta")]
    pub zeta: f64,
    /// The two bare-beam modes (1-based) where ζ is matched.
    #[serde(default = "d_modes", deserialize_with = "two_modes")]
    pub modes: [usize; 2],
    /// Explicit coefficients for `rayleigh`: a₀ (1/s), a₁ (s).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub a0: Option<f64>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub a1: Option<f64>,
    /// Modal damping ratios per bare-beam mode for `modal` (the last repeats).
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub ratios: Vec<f64>,
    /// Loss factor η for `hysteretic` (–).
    #[serde(default = "d_eta")]
    pub eta: f64,
}

fn d_eta() -> f64 {
    0.01
}

fn d_zeta() -> f64 {
    0.01
}
fn d_modes() -> [usize; 2] {
    [1, 3]
}

/// Exactly two mode numbers: a list of any other length is refused, not cut or padded
/// (a fixed-size array alone would read `[1, 2, 3]` as `[1, 2]`).
fn two_modes<'de, D: serde::Deserializer<'de>>(d: D) -> std::result::Result<[usize; 2], D::Error> {
    let modes = Vec::<usize>::deserialize(d)?;
    <[usize; 2]>::try_from(modes.as_slice()).map_err(|_| {
        serde::de::Error::custom(format!(
            "damping.modes: Rayleigh damping by ratio matches ζ at exactly two modes (a₀ and a₁ are two \
             unknowns), got {} ({modes:?}); for a ratio per mode use kind = \"modal\" with `ratios`",
            modes.len()
        ))
    })
}

impl Default for DampingSpec {
    fn default() -> Self {
        DampingSpec {
            kind: DampingKind::RayleighRatio,
            zeta: d_zeta(),
            modes: d_modes(),
            a0: None,
            a1: None,
            ratios: Vec::new(),
            eta: d_eta(),
        }
    }
}

#[derive(Clone, Copy, Debug, Default, Deserialize, Serialize, PartialEq, Eq)]
#[serde(rename_all = "snake_case")]
pub enum DampingKind {
    /// Rayleigh with ζ matched at two bare-beam modes (default).
    #[default]
    RayleighRatio,
    /// Rayleigh with explicit a₀, a₁.
    Rayleigh,
    /// Modal damping ratios (frequency-domain analyses).
    Modal,
    /// Hysteretic (structural) damping: the beam's stiffness K·(1 + iη), loss factor `eta`
    /// (harmonic and steady-state analyses; no causal time-domain form).
    Hysteretic,
    /// Undamped beam.
    None,
    /// An imported model's own damping matrix (`imported.damping`), as given.
    Given,
}

impl BeamSpec {
    /// Checks geometry, material, mesh, supports, point masses and springs.
    pub(super) fn validate(&self, file: &str) -> Result<()> {
        let b = self;
        positive(file, "beam.length", b.length)?;
        positive(file, "beam.width", b.width)?;
        positive(file, "beam.thickness", b.thickness)?;
        positive(file, "beam.youngs_modulus", b.youngs_modulus)?;
        positive(file, "beam.density", b.density)?;
        if b.mesh.file.is_none() && b.mesh.elements == 0 {
            return Err(Error::input(file, "beam.mesh.elements", "must be at least 1"));
        }
        let tol = b.mesh.roundoff_tolerance;
        if !(tol >= 1e-12 && tol < 1.0) {
            return Err(Error::input(
                file,
                "beam.mesh.roundoff_tolerance",
                format!("{tol}: a relative tolerance in [1e-12, 1) (default 1e-6)"),
            ));
        }
        for (i, s) in b.support.iter().enumerate() {
            on_beam(file, &format!("beam.support[{i}].x"), s.x, b.length)?;
            match s.kind {
                SupportKindSpec::Spring => {
                    if s.k_w.is_none() && s.k_theta.is_none() {
                        return Err(Error::input(
                            file,
                            format!("beam.support[{i}]"),
                            "a spring support needs `k_w` and/or `k_theta`",
                        ));
                    }
                    non_negative(file, &format!("beam.support[{i}].k_w"), s.k_w.unwrap_or(0.0))?;
                    non_negative(file, &format!("beam.support[{i}].k_theta"), s.k_theta.unwrap_or(0.0))?;
                }
                _ => {
                    if s.k_w.is_some() || s.k_theta.is_some() {
                        return Err(Error::input(
                            file,
                            format!("beam.support[{i}]"),
                            "`k_w`/`k_theta` apply only to kind = \"spring\"",
                        ));
                    }
                }
            }
        }
        for (i, p) in b.point_mass.iter().enumerate() {
            on_beam(file, &format!("beam.point_mass[{i}].x"), p.x, b.length)?;
            positive(file, &format!("beam.point_mass[{i}].mass"), p.mass)?;
            non_negative(file, &format!("beam.point_mass[{i}].rotary_inertia"), p.rotary_inertia)?;
        }
        for (i, s) in b.spring.iter().enumerate() {
            on_beam(file, &format!("beam.spring[{i}].x"), s.x, b.length)?;
            non_negative(file, &format!("beam.spring[{i}].stiffness"), s.stiffness)?;
            non_negative(file, &format!("beam.spring[{i}].damping"), s.damping)?;
        }
        Ok(())
    }
}

impl DampingSpec {
    /// Checks the fields of the damping's kind.
    pub(super) fn validate(&self, file: &str) -> Result<()> {
        let d = self;
        match d.kind {
            DampingKind::RayleighRatio => {
                non_negative(file, "damping.zeta", d.zeta)?;
                if d.modes[0] == 0 || d.modes[1] == 0 || d.modes[0] == d.modes[1] {
                    return Err(Error::input(
                        file,
                        "damping.modes",
                        format!("two different 1-based mode numbers are needed, got {:?}", d.modes),
                    ));
                }
            }
            DampingKind::Rayleigh => {
                non_negative(
                    file,
                    "damping.a0",
                    d.a0.ok_or_else(|| Error::input(file, "damping.a0", "required for kind = \"rayleigh\""))?,
                )?;
                non_negative(
                    file,
                    "damping.a1",
                    d.a1.ok_or_else(|| Error::input(file, "damping.a1", "required for kind = \"rayleigh\""))?,
                )?;
            }
            DampingKind::Modal => {
                if d.ratios.is_empty() {
                    return Err(Error::input(file, "damping.ratios", "modal damping needs at least one ratio"));
                }
                for (i, &z) in d.ratios.iter().enumerate() {
                    non_negative(file, &format!("damping.ratios[{i}]"), z)?;
                }
            }
            DampingKind::Hysteretic => {
                if !(d.eta > 0.0 && d.eta < 1.0) {
                    return Err(Error::input(file, "damping.eta", format!("must be in (0, 1), got {}", d.eta)));
                }
            }
            DampingKind::None | DampingKind::Given => {}
        }
        Ok(())
    }
}
