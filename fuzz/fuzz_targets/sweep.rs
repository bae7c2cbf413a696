//! Sweep text → parse and validate (base case, parameters, value ranges) → every case held
//! to a small budget before any runs, as `beamflow sweep` does.
//!
//! Loading, the check of each parameter over its values on the base case and the budget
//! of the largest case see the input as it is: they must refuse or accept any text without
//! panicking, hanging or allocating without bound. No case is solved.
#![no_main]

use beamflow::analysis::budget::{Budget, DEFAULT_STEPS};
use beamflow::sweep::{Shard, Sweep};
use libfuzzer_sys::fuzz_target;
use std::path::PathBuf;

/// What each input may take: memory far below the machine; steps as by default (nothing is
/// stepped here, only estimated).
const BUDGET: Budget = Budget { memory: 256 << 20, steps: DEFAULT_STEPS };

fn dir() -> PathBuf {
    // `base` resolves as for the shipped sweeps.
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../cases")
}

fuzz_target!(|data: &[u8]| {
    let Ok(text) = std::str::from_utf8(data) else { return };
    let Ok(s) = Sweep::from_str(text, "fuzz.sweep.toml", &dir()) else { return };
    if BUDGET.admit(&s.cases_cost(Shard::ALL).1).is_ok() {
        let _ = s.admit(&BUDGET);
    }
});
