//! Figures and reports: a small plot toolkit ([`plot`]: line plots, panels, bars, stems
//! and heat maps to PNG or SVG from one description), the figures built with it for a case
//! run ([`figures`]; measurements beside predictions in [`measured`], the coupled system's
//! transfer functions and modes in [`coupled`]), a sweep table ([`sweep`]), an
//! optimisation ([`optimize`]) and the identification steps ([`identify`]), and
//! self-contained HTML reports ([`html`], a case run's: [`run_page`]).
//! Figures and reports read results; they never run an analysis.

pub mod coupled;
pub mod figures;
pub mod html;
pub mod identify;
pub mod measured;
pub mod optimize;
pub mod palette;
pub mod plate;
pub mod plot;
pub mod run_page;
pub mod sweep;

/// Numbers for people, in the console and the reports alike: an SI prefix on the unit
/// (`72.73 N`, `818.2 nW`), engineering notation where a unit takes none.
pub use plot::text::{eng, si};
