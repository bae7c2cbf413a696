//! Optimisation text → parse and validate (base case, variables, objectives, constraints)
//! → the evaluations and every candidate held to a small budget before the search starts,
//! as `beamflow optimize` does.
//!
//! Loading, the check of each variable at its bounds on the base case and the budget of
//! the largest candidate see the input as it is: they must refuse or accept any text
//! without panicking, hanging or allocating without bound. No candidate is solved.
#![no_main]

use beamflow::analysis::budget::{Budget, DEFAULT_STEPS};
use beamflow::optimize::Spec;
use libfuzzer_sys::fuzz_target;
use std::path::PathBuf;

/// What each input may take: memory far below the machine; steps as by default (nothing is
/// stepped here, only estimated).
const BUDGET: Budget = Budget { memory: 256 << 20, steps: DEFAULT_STEPS };

fn dir() -> PathBuf {
    // `base` resolves as for the shipped optimisation.
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../cases")
}

fuzz_target!(|data: &[u8]| {
    let Ok(text) = std::str::from_utf8(data) else { return };
    let Ok(spec) = Spec::from_str(text, "fuzz.opt.toml", &dir()) else { return };
    if BUDGET.admit(&spec.evaluations_cost()).is_ok() {
        let _ = spec.admit(&BUDGET);
    }
});
