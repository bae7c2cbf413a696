//! What a case run produced: each analysis' result in case order, with the model and the
//! assembled system they ran on. Output and figures read this; the application layer's runner
//! fills it.

use crate::analysis::harmonic::HarmonicResult;
use crate::analysis::modes::ModesResult;
use crate::analysis::steady_state::SteadyStateResult;
use crate::analysis::transient::TransientResult;
use crate::assembly::{Model, System};

/// One analysis' result, in case order.
#[derive(Clone, Debug)]
pub enum AnalysisResult {
    Modes(ModesResult),
    Harmonic(HarmonicResult),
    Transient(Box<TransientResult>),
    SteadyState(Box<SteadyStateResult>),
}

/// Everything a case run produced.
#[derive(Clone, Debug)]
pub struct CaseRun {
    pub model: Model,
    pub system: System,
    pub results: Vec<AnalysisResult>,
}
