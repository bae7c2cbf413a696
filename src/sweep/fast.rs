//! The sweep's fast path: the frequency-domain periodic steady state of
//! [`crate::analysis::steady_state`] (physics spec §9), reduced to the headline numbers.
//!
//! It is the same computation, built from the same public pieces (`periodic_stack_forces`,
//! `harmonics`, `DynamicStiffness`, `dissipated_power`, `link_harmonic`) in the same order,
//! with two differences that only save time:
//! * no time-domain reconstruction of one period (plots need it, a table does not; it is
//!   about a third of `steady_state::run`'s time);
//! * the stack-force harmonics F̂_p,k are cached by stack and voltage: F_p depends on the
//!   voltage and the stack alone, not on where the stack stands, so a placement sweep
//!   integrates the Bouc–Wen cycle once per drive instead of once per case. The cached value
//!   is a pure function of its key, so which thread fills it does not change any bit.
//!
//! [`steady_state_with`] also keeps the harmonic solver of one system between cases that
//! share it (see `exec::Evaluator::evaluate_group`).
//!
//! `tests/sweeps.rs` checks it against `steady_state::run` on the same cases.

use crate::analysis::steady_state::{periodic_stack_forces, HarmonicSolver};
use crate::analysis::transient::{time_grid, TransientSettings};
use crate::assembly::{Model, System};
use crate::error::{Error, Result};
use crate::power::link::link_harmonic;
use crate::power::spectra::harmonics;
use num_complex::Complex64;
use std::collections::HashMap;
use std::f64::consts::PI;
use std::sync::atomic::{AtomicUsize, Ordering};
use std::sync::{Arc, Mutex};

/// Stack-force harmonics shared by the cases of a run.
#[derive(Debug, Default)]
pub struct ForceCache {
    map: Mutex<HashMap<String, Arc<Vec<Complex64>>>>,
    /// Hysteresis cycles integrated (cache misses).
    pub computed: AtomicUsize,
}

impl ForceCache {
    /// F̂_p,k, k = 0..=n_harm, of actuator `a`'s stack over `period` from `samples` samples.
    fn get(&self, model: &Model, a: usize, period: f64, samples: usize, n_harm: usize) -> Result<Arc<Vec<Complex64>>> {
        // Debug formatting of f64 round-trips exactly, so equal keys mean equal inputs.
        let key = format!("{:?}|{:?}|{samples}|{n_harm}", model.actuators[a].stack(), period);
        if let Some(v) = self.map.lock().expect("cache lock").get(&key) {
            return Ok(v.clone());
        }
        let alone = Model {
            beam: None,
            rayleigh: Default::default(),
            actuators: vec![model.actuators[a].clone()],
            sensors: Vec::new(),
        };
        let (forces, _) = periodic_stack_forces(&alone, period, samples)?;
        let h = Arc::new(harmonics(&forces[0][2])[..=n_harm].to_vec());
        self.computed.fetch_add(1, Ordering::Relaxed);
        self.map.lock().expect("cache lock").entry(key).or_insert(h.clone());
        Ok(h)
    }
}

/// The headline numbers of a periodic steady state.
#[derive(Clone, Debug, Default)]
pub struct Headline {
    /// Net mean power into the beam per actuator (W).
    pub net_power: Vec<f64>,
    /// Mean power into the beam per link (W).
    pub mean_power: Vec<f64>,
    /// |F̂_T| at the fundamental per link (N).
    pub force_amplitude: Vec<f64>,
    pub beam_dissipation: f64,
    pub balance_error: f64,
}

/// The periodic steady state's headline numbers, as `steady_state::run` computes them.
pub fn steady_state(
    model: &Model,
    sys: &System,
    n_harm: usize,
    samples: usize,
    cache: &ForceCache,
) -> Result<Headline> {
    steady_state_with(model, &mut HarmonicSolver::new(sys), n_harm, samples, cache)
}

/// [`steady_state`] against a solver kept between cases: the cases of a sweep that differ
/// only in their drives (voltage) share the assembled system, so they share its solver and
/// allocate nothing for the harmonic solves. `model` must be the model the solver's system
/// was assembled from, up to the actuators' voltages. Bit for bit the same as
/// [`steady_state`].
// The harmonic loop is written as in `steady_state::run`, to keep the two easy to compare.
#[allow(clippy::needless_range_loop)]
pub fn steady_state_with(
    model: &Model,
    solver: &mut HarmonicSolver,
    n_harm: usize,
    samples: usize,
    cache: &ForceCache,
) -> Result<Headline> {
    let sys = solver.system();
    let grid = TransientSettings { harmonics: n_harm, ..Default::default() };
    let (_, _, period, periodic) = time_grid(model, &grid)?;
    if !periodic {
        return Err(Error::input("<case>", "analysis", "a frequency-domain steady state needs a periodic drive"));
    }
    let fp_h =
        (0..model.actuators.len()).map(|a| cache.get(model, a, period, samples, n_harm)).collect::<Result<Vec<_>>>()?;
    let w0 = 2.0 * PI / period;
    solver.solve(|a, k| fp_h[a][k], n_harm, w0)?;
    let (q_all, diss) = (&solver.q, &solver.diss);
    let mut fp = vec![Complex64::default(); fp_h.len()];
    let mut out = Headline::default();
    for lk in &sys.links {
        let mut power = Vec::with_capacity(n_harm + 1);
        for (k, q) in q_all.iter().enumerate() {
            fp.iter_mut().zip(&fp_h).for_each(|(x, f)| *x = f[k]);
            let h = link_harmonic(lk, q, k as f64 * w0, &fp);
            power.push(if k == 0 { 2.0 * h.power } else { h.power });
            if k == 1 {
                out.force_amplitude.push(h.transmitted.norm());
            }
        }
        if n_harm == 0 {
            out.force_amplitude.push(0.0);
        }
        // Summed like steady_state::run's `power_total`, so the bits agree.
        out.mean_power.push(power.iter().sum());
    }
    out.net_power = (0..model.actuators.len())
        .map(|a| sys.links.iter().zip(&out.mean_power).filter(|(l, _)| l.actuator == a).map(|(_, p)| p).sum())
        .collect();
    out.beam_dissipation = diss.iter().sum();
    let input: f64 = out.mean_power.iter().sum();
    out.balance_error = if out.beam_dissipation != 0.0 {
        (input - out.beam_dissipation).abs() / out.beam_dissipation.abs()
    } else {
        input.abs()
    };
    Ok(out)
}
