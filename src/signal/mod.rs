//! Driving signals: the voltage applied to a stack, and the CSV reader its tabulated form
//! (and the identification code) uses.

pub mod csv;
pub mod sampling;
pub mod voltage;

pub use voltage::{ChirpLaw, SineComponent, VoltageInput};
