//! The encapsulated piezo stack (EPSA): spring k_p and damper c_p in parallel with the
//! active force F_p = k_p·δ, δ the Bouc–Wen free stroke.

use super::bouc_wen::BoucWen;
use crate::signal::voltage::VoltageInput;

/// Stack parameters and its drive.
#[derive(Clone, Debug)]
pub struct Stack {
    /// Axial stiffness k_p (N/m).
    pub k_p: f64,
    /// Axial damping c_p (N·s/m).
    pub c_p: f64,
    /// Stack mass m_p (kg): half rides on the top body, half on the foot.
    pub m_p: f64,
    /// Hysteresis model of the free stroke.
    pub hysteresis: BoucWen,
    /// Initial hysteretic displacement h(0) (m).
    pub h0: f64,
    /// Applied voltage V(t).
    pub voltage: VoltageInput,
    /// Whether hysteresis is modelled; off gives the linear stack δ = d_p·V.
    pub hysteresis_on: bool,
}

impl Stack {
    /// Active (PZT) force F_p = k_p·δ = k_p·(d_p·V − h) (N) for voltage V (V) and h (m).
    pub fn active_force(&self, v: f64, h: f64) -> f64 {
        self.k_p * self.hysteresis.stroke(v, h)
    }
}
