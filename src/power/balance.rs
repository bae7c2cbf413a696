//! The energy bookkeeping that checks the power flow (physics spec §10): over an interval,
//! work in = dissipated + Δ(stored); in a periodic steady state, power in = power dissipated.

use serde::Serialize;

/// Energy balance of a subsystem over an interval: work in = dissipated + Δ(stored).
#[derive(Clone, Copy, Debug, Default, Serialize)]
pub struct EnergyBalance {
    /// Work done on the subsystem by the forces acting on it (J).
    pub input: f64,
    /// Energy dissipated by its dampers (J).
    pub dissipated: f64,
    /// Change of its kinetic plus strain energy (J).
    pub stored_change: f64,
}

impl EnergyBalance {
    /// |input − dissipated − Δstored| relative to the largest of the three.
    pub fn relative_error(&self) -> f64 {
        let scale = self.input.abs().max(self.dissipated.abs()).max(self.stored_change.abs());
        if scale == 0.0 {
            0.0
        } else {
            (self.input - self.dissipated - self.stored_change).abs() / scale
        }
    }
}

/// The steady-state balance error |input − dissipated| / |dissipated| of a mean input power
/// and a mean dissipated power (W); |input| itself when nothing is dissipated (a rigid base
/// takes no power).
pub fn balance_error(input: f64, dissipated: f64) -> f64 {
    if dissipated != 0.0 {
        (input - dissipated).abs() / dissipated.abs()
    } else {
        input.abs()
    }
}
