//! The structure's damping, as the model holds it.
//!
//! Damping belongs to the model: every analysis reads it from there. Damping given by
//! ratio (ζ at two of the bare beam's modes) is stated in terms of modes, so it becomes
//! coefficients only once those modes are computed; that calibration runs where analyses
//! are planned ([`crate::analysis::plan`]), never while a case is read, and assembly
//! refuses a model whose damping is still a ratio.

use crate::error::{Error, Result};

/// Rayleigh damping of the beam, C_beam = a₀·M_beam + a₁·K_beam.
#[derive(Clone, Copy, Debug, PartialEq, Default)]
pub struct Rayleigh {
    /// Mass-proportional coefficient a₀ (1/s).
    pub a0: f64,
    /// Stiffness-proportional coefficient a₁ (s).
    pub a1: f64,
}

impl Rayleigh {
    /// Coefficients giving damping ratio ζ at circular frequencies ωᵢ and ωⱼ (rad/s).
    pub fn from_ratio(zeta: f64, wi: f64, wj: f64) -> Self {
        let a1 = 2.0 * zeta / (wi + wj);
        Rayleigh { a0: a1 * wi * wj, a1 }
    }

    /// Damping ratio this gives at circular frequency ω: ζ(ω) = a₀/(2ω) + a₁ω/2.
    pub fn ratio_at(&self, w: f64) -> f64 {
        self.a0 / (2.0 * w) + self.a1 * w / 2.0
    }
}

/// The damping of the structure (the actuators' dampers belong to their links).
#[derive(Clone, Debug, PartialEq, Default)]
pub enum Damping {
    /// No structural damping.
    #[default]
    None,
    /// Viscous, proportional to the beam's mass and stiffness.
    Rayleigh(Rayleigh),
    /// Rayleigh damping stated as ratio `zeta` at the bare beam's modes `modes` (1-based);
    /// [`crate::analysis::plan::calibrate`] turns it into [`Damping::Rayleigh`].
    RayleighRatio { zeta: f64, modes: [usize; 2] },
    /// A viscous ratio per bare-beam mode (the last repeats for higher modes): a matrix only
    /// in the bare beam's modal coordinates, so analyses apply it on a modal basis.
    Modal(Vec<f64>),
    /// Hysteretic (structural) damping: the beam's stiffness is K_beam·(1 + iη) in the
    /// frequency domain; `eta` is the loss factor η.
    Hysteretic { eta: f64 },
}

impl Damping {
    /// The Rayleigh coefficients this damping puts in C (zero for every other kind).
    pub fn rayleigh(&self) -> Rayleigh {
        match self {
            Damping::Rayleigh(r) => *r,
            _ => Rayleigh::default(),
        }
    }

    /// The hysteretic loss factor η (zero for every other kind).
    pub fn loss_factor(&self) -> f64 {
        match self {
            Damping::Hysteretic { eta } => *eta,
            _ => 0.0,
        }
    }

    /// The slowest free decay rate σ = ζ_r·ω_r (1/s) of modes at or above ω (rad/s): for
    /// Rayleigh damping (a₀ + a₁ω²)/2, which grows with ω; for modal ratios the least ratio
    /// times ω; zero without damping.
    pub fn slowest_decay(&self, w: f64) -> f64 {
        match self {
            Damping::Rayleigh(r) => 0.5 * (r.a0 + r.a1 * w * w),
            Damping::Modal(ratios) => ratios.iter().copied().fold(f64::INFINITY, f64::min) * w,
            Damping::Hysteretic { eta } => 0.5 * eta * w,
            Damping::None | Damping::RayleighRatio { .. } => 0.0,
        }
    }

    /// The modal damping ratios, if the damping is modal.
    pub fn modal_ratios(&self) -> Option<&[f64]> {
        match self {
            Damping::Modal(r) => Some(r),
            _ => None,
        }
    }

    /// Whether C holds all of it, so an analysis integrating the assembled M, C, K in
    /// physical coordinates applies it (modal damping is not a matrix there, hysteretic
    /// damping has no time-domain form).
    pub fn is_viscous(&self) -> bool {
        matches!(self, Damping::None | Damping::Rayleigh(_))
    }

    /// Refuses damping that is still a ratio: assembly needs coefficients.
    pub fn require_calibrated(&self) -> Result<()> {
        match self {
            Damping::RayleighRatio { .. } => Err(Error::case_field(
                "damping",
                "Rayleigh damping by ratio is calibrated from the bare beam's modes before assembly \
                 (analysis::plan::calibrate)",
            )),
            _ => Ok(()),
        }
    }
}
