//! # beamflow
//!
//! How much vibrational power a piezoelectric force actuator pushes into a structure,
//! where it enters, and through which modes.
//!
//! Data flows one way: [`case`] (what the user wrote) → [`beam`] and [`actuator`] (the
//! physics) → [`assembly`] (the system of equations) → [`solve`] (eigen, harmonic,
//! time integration) driven by [`analysis`] → [`power`] (power flow, balances, spectra,
//! modes) → I/O at the edge. There is no global state: two cases can run side by side in one process.

// Input checks write `!(x > 0.0)` on purpose: unlike `x <= 0.0` it also rejects NaN.
#![allow(clippy::neg_cmp_op_on_partial_ord)]

/// Prints a line to standard output like `println!`, but a closed output (the reader of a
/// pipe such as `beamflow modes case.toml | head` has gone) is not an error: the rest of
/// the output is dropped and the command finishes its work (results are still written).
#[macro_export]
macro_rules! say {
    ($($arg:tt)*) => {
        $crate::app::console::say_line(format_args!($($arg)*))
    };
}

pub mod actuator;
pub mod analysis;
pub mod app;
pub mod assembly;
pub mod beam;
pub mod case;
pub mod error;
pub mod identify;
pub mod imported;
pub mod input_file;
pub mod io;
pub mod linalg;
pub mod optimize;
pub mod plate;
pub mod power;
pub mod progress;
pub mod report;
pub mod signal;
pub mod simd;
pub mod solve;
pub mod structure;
pub mod sweep;
pub mod toml_input;

pub use error::{Error, Result};
