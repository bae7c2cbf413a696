//! Post-processing: reads solver results, computes what an engineer asks for (spectra,
//! power flow, energy balance, modal decomposition). Solvers do not depend on it.

pub mod modal;
pub mod power;
pub mod spectra;
