//! Objectives: a weighted sum of result quantities, optionally per volt² or per kilogram
//! of actuator, maximised or minimised. The formulas are in docs/optimize.md.

use super::quantity::{Outcome, Quantity};
use serde::Deserialize;

/// Maximise or minimise.
#[derive(Clone, Copy, Debug, Default, Deserialize, PartialEq, Eq)]
#[serde(rename_all = "snake_case")]
pub enum Goal {
    #[default]
    Maximize,
    Minimize,
}

/// What an objective is divided by.
#[derive(Clone, Copy, Debug, Deserialize, PartialEq, Eq)]
#[serde(rename_all = "snake_case")]
pub enum Per {
    /// Σ_a V̂_a² (V²): the peak drive voltages squared.
    Volt2,
    /// Σ_a m_a (kg): the actuators' moving masses (stack plus top mass or frame beam).
    Kg,
}

/// One objective.
#[derive(Clone, Debug)]
pub struct Objective {
    /// As written (`net_power`, or `0.7·net_power[0] + …` for a weighted sum), for tables.
    pub label: String,
    pub goal: Goal,
    /// (weight, quantity); a single quantity has weight 1.
    pub terms: Vec<(f64, Quantity)>,
    pub per: Option<Per>,
}

impl Objective {
    /// f = Σ_i w_i·q_i, divided by the `per` normaliser.
    pub fn value(&self, o: &Outcome) -> std::result::Result<f64, String> {
        let mut f = 0.0;
        for (w, q) in &self.terms {
            f += w * o.value(q)?;
        }
        Ok(match self.per {
            None => f,
            Some(Per::Volt2) => f / o.volt2,
            Some(Per::Kg) => f / o.mass,
        })
    }

    /// The value as a cost to minimise: −f when maximising.
    pub fn cost(&self, f: f64) -> f64 {
        match self.goal {
            Goal::Maximize => -f,
            Goal::Minimize => f,
        }
    }

    /// Whether `a` is better than `b`.
    pub fn better(&self, a: f64, b: f64) -> bool {
        self.cost(a) < self.cost(b)
    }

    /// The unit of the value.
    pub fn unit(&self) -> String {
        let u = self.terms.first().map_or("1", |(_, q)| q.unit());
        match self.per {
            None => u.to_string(),
            Some(Per::Volt2) => format!("{u}/V^2"),
            Some(Per::Kg) => format!("{u}/kg"),
        }
    }

    /// Whether any term needs the mode-resolved power.
    pub fn needs_modes(&self) -> bool {
        self.terms.iter().any(|(_, q)| q.modes_needed().is_some())
    }
}
