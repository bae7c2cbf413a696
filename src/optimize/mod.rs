//! Placement optimisation: where to put the actuators (and how to drive them) for the most
//! power into the beam, into chosen modes, or for a response at a sensor.
//!
//! An optimisation file ([`spec`]) names a base case, the case fields that vary (by dotted
//! path, as sweeps vary them: `actuator[1].x_e`, `actuator[0].voltage.frequency`, …) within
//! bounds, one objective ([`objective`], from the result quantities of [`quantity`]) or two
//! for a Pareto front, and constraints ([`constraint`]). Each candidate is the base with its
//! values set, checked against the placement limits before it is solved, then solved by the
//! frequency-domain periodic steady state in the sweep's headline mode ([`evaluate`]). The
//! search ([`search`]) is CMA-ES from seeded starts with a Nelder–Mead polish; [`run`]
//! drives it, keeps the history and picks the distinct optima.
//!
//! ```no_run
//! # fn main() -> beamflow::Result<()> {
//! let spec = beamflow::optimize::load(std::path::Path::new("cases/two_frames.opt.toml"))?;
//! let result = beamflow::optimize::run(&spec, &beamflow::optimize::RunOptions::default())?;
//! println!("best: {}", spec.describe(&result.best.u));
//! # Ok(()) }
//! ```

pub mod constraint;
pub mod evaluate;
pub mod explain;
pub mod local;
pub mod objective;
pub mod quantity;
pub mod run;
pub mod search;
pub mod spec;

pub use run::{run, RunOptions, RunResult};
pub use spec::{load, Spec};
