//! Figures: a small plot toolkit ([`plot`]: line plots, stacked panels, bars, stems and
//! heat maps to PNG or SVG from one description) and the figures built with it for a case
//! run ([`figures`]; measurements beside predictions in [`measured`], the coupled system's
//! transfer functions and modes in [`coupled`]), a sweep table ([`sweep`]), an optimisation ([`optimize`]) and the
//! identification steps ([`identify`]).
//! Figures read results; they never run an analysis.

pub mod coupled;
pub mod figures;
pub mod identify;
pub mod measured;
pub mod optimize;
pub mod plot;
pub mod sweep;
