//! Power flow through interface points and the energy bookkeeping that checks it.

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

/// Mean of the product of two sampled signals over whole periods (W for force × velocity).
pub fn mean_product(a: &[f64], b: &[f64]) -> f64 {
    if a.is_empty() {
        return 0.0;
    }
    a.iter().zip(b).map(|(x, y)| x * y).sum::<f64>() / a.len() as f64
}
