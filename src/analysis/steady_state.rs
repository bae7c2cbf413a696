//! The exact periodic steady state, solved in the frequency domain (physics spec §9).
//!
//! The structure is linear and F_p depends on the voltage alone, so: settle h into its
//! periodic cycle, take the Fourier coefficients of each stack's F_p over one period, and
//! solve (K − ω_k²M + iω_kC)·Q_k = Σ_a b_a·F̂_p,a,k for each harmonic ω_k = k·ω₀ (a static
//! solve for the mean). The profile factorisation is refilled in place for each harmonic.
//! The point powers, spectra and balance come from [`crate::power`]; results take the same
//! form as the transient path's.
//!
//! A sweep runs the same analysis in [`Detail::Headline`]: the same numbers, bit for bit,
//! without the period reconstructed in time (about a third of a full run), with the
//! stack-force harmonics from a cache shared by the cases and the [`HarmonicSolver`] kept
//! between cases that share a system.

use super::drive::{force_harmonics, load_cycles, stack_cycle, DriveTiming, StackCycle, StackForceCache};
use super::reduction::{ReductionError, ReductionReport};
use super::roundoff::{self, MeshRefinement};
use super::series::{
    body_dofs, BodySeries, DriveSeries, LinkSeries, LinkSpectrum, LoadSeries, LoadSpectrum, SensorSeries,
};
use crate::assembly::{LinkDofs, Model, System};
use crate::error::{Error, Result};
use crate::power::balance::balance_error;
use crate::power::link::{link_harmonic, link_power_error};
use crate::power::modal::{decompose, ModalDamping, ModalDecomposition};
use crate::power::point::{beam_dissipation, mean_power, mean_power_error, net_power, own_scales};
use crate::power::spectra::harmonics;
use crate::signal::sampling::resolved_harmonics;
use crate::solve::dynamic_stiffness::DynamicStiffness;
use crate::solve::eigen::Modes;
use crate::solve::modal_coupling::ModalCoupling;
use crate::solve::refine::Refined;
use num_complex::Complex64;
use serde::Serialize;
use std::f64::consts::PI;
use std::sync::Arc;

/// Periodic steady state.
#[derive(Clone, Debug, Default, Serialize)]
pub struct SteadyStateResult {
    /// Drive period (s) and the number of harmonics solved (besides the mean).
    pub period: f64,
    pub harmonics: usize,
    /// A bound of what the harmonics above `harmonics` and the sampling of the forces
    /// leave out of every point's power, relative to that point's own power: the largest
    /// over the points of the measured rest up to the samples' Nyquist harmonic, an
    /// envelope of the rest beyond it and the aliasing of the harmonics (see
    /// `run_counted`; NaN where not estimated: a sweep's headline run).
    pub truncation_estimate: f64,
    /// Periods it took h to settle into its cycle.
    pub hysteresis_periods: usize,
    /// Bound on the relative round-off of every link's and load's mean power, the largest
    /// over them ([`crate::analysis::roundoff`]).
    pub mesh_roundoff: f64,
    /// Frequencies k·f₀ (Hz), k = 0..=harmonics.
    pub frequency: Vec<f64>,
    /// Complex DOF amplitudes Q_k, k = 0..=harmonics (q(t) = Re Σ Q_k e^{ikω₀t}); empty in
    /// [`Detail::Headline`].
    #[serde(skip)]
    pub q: Vec<Vec<Complex64>>,
    /// Stack force harmonics F̂_p,k per actuator (N).
    #[serde(skip)]
    pub f_p: Vec<Vec<Complex64>>,
    pub spectra: Vec<LinkSpectrum>,
    pub mean_power: Vec<f64>,
    pub net_power: Vec<f64>,
    /// Per point load, its mean power into the beam and its harmonics.
    pub load_spectra: Vec<LoadSpectrum>,
    /// Beam dissipation per harmonic and in total (W).
    pub beam_dissipation_per_harmonic: Vec<f64>,
    pub beam_dissipation: f64,
    /// |Σ interface and load power − beam dissipation| / beam dissipation (0 on a rigid base).
    pub balance_error: f64,
    /// One period reconstructed from the harmonics, for plots and comparison (empty in
    /// [`Detail::Headline`]).
    pub t: Vec<f64>,
    pub links: Vec<LinkSeries>,
    pub bodies: Vec<BodySeries>,
    pub drives: Vec<DriveSeries>,
    pub sensors: Vec<SensorSeries>,
    pub loads: Vec<LoadSeries>,
    /// Mode-resolved power flow (filled by the runner; costly for sweeps, so optional).
    pub modal: Option<ModalDecomposition>,
    /// Set when the run used a modal reduction: its basis and error estimate.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub reduction: Option<ReductionReport>,
}

/// How much of the steady state [`run_with`] computes.
#[derive(Clone, Copy, Debug)]
pub enum Detail<'c> {
    /// Everything, with one period reconstructed in time (output files, plots).
    Full,
    /// The headline numbers a sweep tabulates — spectra, point and net powers, beam
    /// dissipation, balance — and nothing in time: no period reconstructed, no drive
    /// samples, the amplitudes Q_k left in the solver. The stack-force harmonics come from
    /// the cache, shared by the cases of a sweep.
    Headline(&'c StackForceCache),
}

/// Solves the periodic steady state with `n_harm` harmonics from `samples` per period.
pub fn run(model: &Model, sys: &System, n_harm: usize, samples: usize) -> Result<SteadyStateResult> {
    run_with(model, &mut HarmonicSolver::new(sys), n_harm, samples, Detail::Full)
}

/// How many harmonics a steady state keeps.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum HarmonicCount {
    /// Exactly this many (the truncation is still estimated and reported).
    Fixed(usize),
    /// The fewest whose neglected rest, with the aliasing of the sampling, changes no
    /// point power by more than this fraction of its own ([`own_scales`]).
    Tolerance(f64),
}

/// The steady state with its harmonic count chosen (or checked) against every harmonic
/// `samples` resolve: they are all solved once, the point powers per harmonic decide the
/// count, and the run keeps that many and states a bound of what it leaves out
/// ([`Truncation`]): every point is held to the tolerance on its own power.
pub fn run_counted(model: &Model, sys: &System, count: HarmonicCount, samples: usize) -> Result<SteadyStateResult> {
    let all = resolved_harmonics(samples.max(4));
    let (full, refinement, [spectra, doubled]) = if roundoff::coarse_bound(model).is_some() {
        let full = run(model, sys, all, samples)?;
        let cache = StackForceCache::default();
        let doubled = run_with(model, &mut HarmonicSolver::new(sys), all, 2 * samples, Detail::Headline(&cache))?;
        let spectra = [&full, &doubled].map(|r| point_spectra(r).cloned().collect());
        (Some(full), None, spectra)
    } else {
        let (refinement, spectra) = fine_spectra(model, sys, all, samples)?;
        (None, Some(refinement), spectra)
    };
    let truncation = Truncation::of(&spectra, aliasing(&spectra, &doubled));
    let n_harm = match count {
        HarmonicCount::Fixed(n) => n.min(all),
        HarmonicCount::Tolerance(tol) => (1..=all).find(|&k| truncation.estimate(k) <= tol).ok_or_else(|| {
            Error::analysis_setting(
                "samples_per_period",
                format!(
                    "{samples} samples per period resolve {all} harmonics, and what lies beyond them or is \
                     folded back onto them by the sampling ({:.1e} of a point's power) exceeds the tolerance \
                     {tol:e}: raise `samples_per_period`",
                    truncation.estimate(all)
                ),
            )
        })?,
    };
    // A fine mesh's count states no round-off bound (see `fine_spectra`).
    let mut r = match full {
        Some(full) if n_harm == all => full,
        // The count's refinement (its element rows) serves the kept harmonics too.
        _ => {
            let mut solver = HarmonicSolver::new(sys);
            solver.refinement = refinement;
            run_with(model, &mut solver, n_harm, samples, Detail::Full)?
        }
    };
    r.truncation_estimate = truncation.estimate(n_harm);
    Ok(r)
}

/// What the kept harmonics leave out of each point's power, from each point's power per
/// harmonic solved with every harmonic the samples resolve (K of them):
///
/// - the harmonics above the kept n up to K, measured: Σ_{n<k≤K} |P_k|;
/// - those beyond K, bounded by an envelope. A drive of bounded variation has force
///   harmonics |F_k| ≤ C/k, and above the structure's modes the point mobility falls at
///   least as k^{-1/2} (an infinite beam's; a mass's falls as 1/k), so |P_k| ≤ ½|F_k|²|Y_k|
///   falls at least as k^{-5/2}. Taking only k^{-2}, the rest beyond K is at most
///   1/((4/3) − 1) = 3 times the last quarter Σ_{3K/4<k≤K} |P_k|;
/// - the aliasing of every harmonic up to K, kept or measured as left out (the harmonics
///   beyond the Nyquist one folded back onto them by the sampling; see [`aliasing`]).
///
/// Each point's sum is taken relative to its own power ([`own_scales`]), and the estimate
/// is the largest over the points.
struct Truncation {
    /// rest[i][k] = Σ_{k<j≤K} |P_i,j| (W), k = 0..=K.
    rest: Vec<Vec<f64>>,
    /// Each point's bound of the power beyond K and of the aliasing (W).
    beyond: Vec<f64>,
    /// Each point's scale (W).
    scales: Vec<f64>,
}

impl Truncation {
    /// From each point's power per harmonic k = 0..=K (W) and its `aliasing` (W); a point's
    /// power is the sum of its harmonics'.
    fn of(spectra: &[Vec<f64>], aliasing: Vec<f64>) -> Self {
        let all = spectra.first().map_or(0, |p| p.len() - 1);
        let rest: Vec<Vec<f64>> = spectra
            .iter()
            .map(|power| {
                let mut rest = vec![0.0f64; all + 1];
                for k in (0..all).rev() {
                    rest[k] = rest[k + 1] + power[k + 1].abs();
                }
                rest
            })
            .collect();
        let beyond = rest.iter().zip(aliasing).map(|(r, a)| 3.0 * r[all - all / 4] + a).collect();
        let powers: Vec<f64> = spectra.iter().map(|p| p.iter().sum()).collect();
        Truncation { rest, beyond, scales: own_scales(&powers) }
    }

    /// The largest over the points of what n kept harmonics leave out, relative to the
    /// point's power.
    fn estimate(&self, n: usize) -> f64 {
        (0..self.rest.len()).fold(0.0f64, |m, i| {
            let left = self.rest[i][n.min(self.rest[i].len() - 1)] + self.beyond[i];
            m.max(if left == 0.0 { 0.0 } else { left / self.scales[i] })
        })
    }
}

/// Each point's power per harmonic (W): each link's, then each point load's.
fn point_spectra(r: &SteadyStateResult) -> impl Iterator<Item = &Vec<f64>> {
    r.spectra.iter().map(|s| &s.power).chain(r.load_spectra.iter().map(|s| &s.power))
}

/// A bound of each point's power error (W) that sampling the forces with `samples` per
/// period brings into the harmonics of `full`: their Fourier coefficients carry the
/// harmonics beyond the Nyquist one folded back onto them. The same steady state from
/// twice the samples (`doubled`) folds back only the harmonics beyond twice the Nyquist
/// one; with force harmonics falling at least as 1/k its folding is at most half that of
/// `samples`, e_2N ≤ e_N/2, so e_N ≤ |P_N − P_2N| + e_N/2, and e_N ≤ 2·|P_N − P_2N|,
/// harmonic by harmonic: the bound is 2·Σ_k |P_k(N) − P_k(2N)|. Each point's power per
/// harmonic (W) from `samples` and from twice the samples.
fn aliasing(full: &[Vec<f64>], doubled: &[Vec<f64>]) -> Vec<f64> {
    let folded = |(a, b): (&Vec<f64>, &Vec<f64>)| 2.0 * a.iter().zip(b).map(|(x, y)| (x - y).abs()).sum::<f64>();
    full.iter().zip(doubled).map(folded).collect()
}

/// Each point's power per harmonic k = 0..=`all` (W) from `samples` per period and from
/// twice the samples, on a mesh whose solves are refined: what the truncation estimate
/// needs of the runs with every resolved harmonic ([`Truncation`], [`aliasing`]), without
/// their amplitudes (which would take 2 × 0.3 GB on 20,000 elements) or a round-off bound
/// (the harmonics kept are solved again with theirs, [`run_counted`]).
///
/// The two samplings solve at the same frequencies k·ω₀, so each harmonic is factorised
/// once for both; with a single forcing (one stack, no point load) their right-hand sides
/// are parallel, b₂ = (F₂/F₁)·b₁, and so is the solution: the first sampling's, scaled,
/// is the second's with its error scaled alike (the same relative error, held to the same
/// share of the tolerance, [`Shares`]). With several forcings each sampling has its own
/// solve. Each sampling judges its refinement against its own powers so far, as a run of
/// its own would.
fn fine_spectra(
    model: &Model,
    sys: &System,
    all: usize,
    samples: usize,
) -> Result<(MeshRefinement, [Vec<Vec<f64>>; 2])> {
    let cache = StackForceCache::default();
    let (period, first) = forcing_harmonics(model, samples, all, &cache)?;
    let (_, second) = forcing_harmonics(model, 2 * samples, all, &cache)?;
    let forcings = [first, second];
    let w0 = 2.0 * PI / period;
    let largest = forcings.each_ref().map(|f| (0..=all).map(|k| forcing_size(f, k)).fold(0.0f64, f64::max));
    let active: Vec<usize> = (0..=all)
        .filter(|&k| (0..2).any(|s| forcing_size(&forcings[s], k) > NEGLIGIBLE_HARMONIC * largest[s]))
        .collect();
    let refinement = MeshRefinement::new(model, sys)?;
    let points = sys.links.len() + sys.loads.len();
    let mut spectra = [(); 2].map(|_| vec![vec![0.0; all + 1]; points]);
    let mut shares = [(); 2].map(|_| Shares::new(sys, active.len(), false));
    let task = crate::progress::Task::start("harmonic count", Some(active.len() as u64), "harmonics solved");
    let mut stages = [(); 2].map(|_| PairStage::new(sys));
    let count = Count { sys, forcings: &forcings, w0, refinement: &refinement };
    let pairs: Vec<&[usize]> = active.chunks(2).collect();
    let solve = |stage: &mut PairStage, pair: &[usize], shares: [Shares; 2]| stage.count(&count, pair, shares);
    in_waves(&mut stages, &pairs, &mut shares, &task, solve, |shares, _, solved, _| {
        for (k, powers) in solved {
            for (s, p) in powers.into_iter().enumerate() {
                shares[s].so_far.iter_mut().zip(&p).for_each(|(t, x)| *t += x);
                spectra[s].iter_mut().zip(p).for_each(|(row, x)| row[k] = x);
            }
        }
    })?;
    Ok((refinement, spectra))
}

/// The pairs of the count in waves whose pairs are solved side by side: the first pair
/// (the drive's harmonic and the next, which carry most of every point's power) alone,
/// then two at a time. Each pair judges its refinement against the powers of the waves
/// before it (and of its own first lane), whichever thread solves it, so the spectra are
/// the same bits on one core or two.
fn waves<'p>(pairs: &'p [&'p [usize]]) -> impl Iterator<Item = &'p [&'p [usize]]> {
    let (first, rest) = pairs.split_at(pairs.len().min(1));
    std::iter::once(first).filter(|f| !f.is_empty()).chain(rest.chunks(2))
}

/// Solves `pairs` in [`waves`], a wave's two pairs on the two `stages` side by side, each
/// from a copy of `state` as the waves before left it; `merge` then takes each pair's
/// result into `state`, in the pairs' order, with the stage that holds its solutions.
fn in_waves<S: Clone + Sync, T: Send>(
    stages: &mut [PairStage; 2],
    pairs: &[&[usize]],
    state: &mut S,
    task: &crate::progress::Task,
    solve: impl Fn(&mut PairStage, &[usize], S) -> Result<T> + Sync,
    mut merge: impl FnMut(&mut S, &[usize], T, &mut PairStage),
) -> Result<()> {
    let mut done = 0;
    for wave in waves(pairs) {
        task.set(done as u64)?;
        let [one, two] = stages;
        let solved = match wave {
            [a] => vec![solve(one, a, state.clone())?],
            [a, b] => {
                let (x, y) = crate::progress::side_by_side(
                    || solve(&mut *one, a, state.clone()),
                    || solve(&mut *two, b, state.clone()),
                );
                vec![x?, y?]
            }
            _ => unreachable!("waves of one or two pairs"),
        };
        for ((stage, pair), t) in [one, two].into_iter().zip(wave).zip(solved) {
            merge(state, pair, t, stage);
            done += pair.len();
        }
    }
    Ok(())
}

/// What every pair of the count shares: the system, each sampling's forcings (stack
/// forces, then point loads; harmonics k = 0..=K each), ω₀ (rad/s) and the element rows.
struct Count<'a> {
    sys: &'a System,
    forcings: &'a [Vec<Vec<Complex64>>; 2],
    w0: f64,
    refinement: &'a MeshRefinement,
}

/// What every pair of a run's kept harmonics shares: the system, each harmonic's forcing
/// (stack forces, then point loads), ω₀ (rad/s) and the element rows.
struct Kept<'a> {
    sys: &'a System,
    forcing: &'a [Vec<Complex64>],
    w0: f64,
    refinement: &'a MeshRefinement,
}

impl Count<'_> {
    /// Sampling s's forcing of harmonic k.
    fn forcing(&self, s: usize, k: usize) -> Vec<Complex64> {
        self.forcings[s].iter().map(|f| f[k]).collect()
    }
}

/// One pair of harmonics of the count: its factorisation, the first sampling's right-hand
/// sides and their solutions (one per lane).
struct PairStage {
    dk: DynamicStiffness,
    rhs0: [Vec<Complex64>; 2],
    q0: [Vec<Complex64>; 2],
    /// The second sampling's right-hand side and solution (where it is not the first's
    /// scaled), one at a time.
    rhs1: Vec<Complex64>,
    q1: Vec<Complex64>,
}

impl PairStage {
    fn new(sys: &System) -> Self {
        let (rhs0, q0) = Default::default();
        PairStage { dk: DynamicStiffness::of(sys), rhs0, q0, rhs1: vec![Complex64::default(); sys.n()], q1: Vec::new() }
    }

    /// Solves the run's kept `pair` of harmonics into `q0` and refines them with their
    /// bound, judged against `shares`; returns each harmonic's error estimate and power per
    /// point (W).
    fn kept(&mut self, c: &Kept, pair: &[usize], mut shares: Shares) -> Result<Vec<(Refined, Vec<f64>)>> {
        let firsts = self.solve_estimated(c.sys, pair, &|k| c.forcing[k].clone(), c.w0, (c.refinement, true))?;
        let mut firsts = firsts.map(Vec::into_iter);
        let PairStage { dk, rhs0, q0, .. } = self;
        let mut out = Vec::with_capacity(pair.len());
        for (lane, &k) in pair.iter().enumerate() {
            let first = firsts.as_mut().and_then(Iterator::next);
            let solve = Solved { dk, lane, rhs: &rhs0[lane] };
            out.push(shares.refine(first, c.refinement, solve, &mut q0[lane], (k, k as f64 * c.w0, &c.forcing[k])));
        }
        Ok(out)
    }

    /// Solves the count's `pair` of harmonics for both samplings, judging each solve's
    /// refinement against `shares` (each sampling's powers so far); returns each harmonic
    /// with each sampling's power per point (W).
    fn count(&mut self, c: &Count, pair: &[usize], mut shares: [Shares; 2]) -> Result<Vec<(usize, [Vec<f64>; 2])>> {
        let firsts = self.solve_estimated(c.sys, pair, &|k| c.forcing(0, k), c.w0, (c.refinement, false))?;
        let mut firsts = firsts.map(Vec::into_iter);
        let PairStage { dk, rhs0, q0, rhs1, q1 } = self;
        let mut out = Vec::with_capacity(pair.len());
        for (lane, &k) in pair.iter().enumerate() {
            let w = k as f64 * c.w0;
            let first = firsts.as_mut().and_then(Iterator::next);
            let solve = Solved { dk, lane, rhs: &rhs0[lane] };
            let first_powers = shares[0].refine(first, c.refinement, solve, &mut q0[lane], (k, w, &c.forcing(0, k))).1;
            let second = c.forcing(1, k);
            let second_powers = match c.forcings {
                [f1, f2] if f1.len() == 1 && f1[0][k] != Complex64::default() => {
                    let ratio = f2[0][k] / f1[0][k];
                    q1.clone_from(&q0[lane]);
                    q1.iter_mut().for_each(|x| *x *= ratio);
                    shares[1].add(q1, w, &second)
                }
                _ => {
                    forcing_vector(c.sys, &second, rhs1);
                    q1.clone_from(rhs1);
                    dk.solve_lane(lane, q1);
                    let solve = Solved { dk, lane, rhs: rhs1 };
                    shares[1].refine(None, c.refinement, solve, q1, (k, w, &second)).1
                }
            };
            out.push((k, [first_powers, second_powers]));
        }
        Ok(out)
    }

    /// [`PairStage::solve`], then both lanes' first estimates against the element rows of
    /// `refinement`, with their floor where `floor` ([`MeshRefinement::first_estimates`]).
    fn solve_estimated(
        &mut self,
        sys: &System,
        pair: &[usize],
        forcing: &dyn Fn(usize) -> Vec<Complex64>,
        w0: f64,
        (refinement, floor): (&MeshRefinement, bool),
    ) -> Result<Option<Vec<Refined>>> {
        self.solve(sys, pair, forcing, w0)?;
        let bs: Vec<&[Complex64]> = self.rhs0[..pair.len()].iter().map(Vec::as_slice).collect();
        let xs: Vec<&[Complex64]> = self.q0[..pair.len()].iter().map(Vec::as_slice).collect();
        Ok(refinement.first_estimates(&self.dk, &bs, &xs, floor))
    }

    /// Factorises at the pair's harmonics of ω₀ (rad/s) and solves for `forcing(k)`, both
    /// lanes side by side (the same bits as one at a time: DynamicStiffness::solve_pair).
    fn solve(
        &mut self,
        sys: &System,
        pair: &[usize],
        forcing: &dyn Fn(usize) -> Vec<Complex64>,
        w0: f64,
    ) -> Result<()> {
        match *pair {
            [ka, kb] => self.dk.factorize_pair(ka as f64 * w0, kb as f64 * w0)?,
            [k] => self.dk.factorize(k as f64 * w0)?,
            _ => unreachable!("chunks of 1 or 2"),
        }
        for (lane, &k) in pair.iter().enumerate() {
            forcing_vector(sys, &forcing(k), &mut self.rhs0[lane]);
            self.q0[lane].clone_from(&self.rhs0[lane]);
        }
        self.dk.solve_lanes(&mut self.q0[..pair.len()]);
        Ok(())
    }
}

/// [`run`] against a solver kept between cases (the cases of a sweep that differ only in
/// their drives share the assembled system, so they share its solver and allocate nothing
/// for the harmonic solves), computing what `detail` asks for. `model` must be the model
/// the solver's system was assembled from, up to the actuators' voltages. Every number
/// both details compute is the same, bit for bit.
pub fn run_with(
    model: &Model,
    solver: &mut HarmonicSolver,
    n_harm: usize,
    samples: usize,
    detail: Detail,
) -> Result<SteadyStateResult> {
    let timing = DriveTiming::sampled(model, samples)?;
    if n_harm > resolved_harmonics(samples) {
        return Err(Error::analysis_setting(
            "samples_per_period",
            format!("{samples} samples per period resolve {} harmonics, not {n_harm}", resolved_harmonics(samples)),
        ));
    }
    let StackForces { cycles, harmonics: f_p, periods: hysteresis_periods } =
        StackForces::of(model, &timing, n_harm, detail)?;
    let load_samples = load_cycles(model, &timing);
    let load_h: Vec<Vec<Complex64>> = load_samples.iter().map(|f| harmonics(f)[..=n_harm].to_vec()).collect();
    let period = timing.period;
    let forcing: Vec<&[Complex64]> = f_p.iter().chain(&load_h).map(Vec::as_slice).collect();
    solver.prepare(model)?;
    solver.solve(|j, k| forcing[j][k], n_harm, 2.0 * PI / period)?;
    let sys = solver.system();
    let mut res = SteadyStateResult {
        period,
        harmonics: n_harm,
        truncation_estimate: f64::NAN,
        hysteresis_periods,
        mesh_roundoff: 0.0,
        frequency: (0..=n_harm).map(|k| k as f64 / period).collect(),
        spectra: link_spectra(sys, &solver.q, &f_p, &timing),
        beam_dissipation: solver.diss.iter().sum(),
        beam_dissipation_per_harmonic: solver.diss.clone(),
        ..Default::default()
    };
    res.mean_power = res.spectra.iter().map(|s| s.power_total).collect();
    res.net_power = net_power(&sys.links, &res.mean_power, model.actuators.len());
    res.load_spectra = load_spectra(model, sys, &solver.q, load_h, &timing);
    let coarse = roundoff::coarse_bound(model).unwrap_or(0.0);
    res.mesh_roundoff = roundoff_bound(sys, &res, &solver.error, 2.0 * PI / period).max(coarse);
    let load_power: f64 = res.load_spectra.iter().map(|s| s.power_total).sum();
    res.balance_error = balance_error(res.mean_power.iter().sum::<f64>() + load_power, res.beam_dissipation);
    if let Detail::Full = detail {
        reconstruct(&mut res, model, sys, &solver.q, &f_p, cycles, samples)?;
        reconstruct_loads(&mut res, model, sys, &solver.q, load_samples);
        res.q = std::mem::take(&mut solver.q);
    }
    res.f_p = f_p;
    Ok(res)
}

/// The stacks' forces of a steady state.
struct StackForces {
    /// One period of each stack's V, h and F_p (not kept in [`Detail::Headline`]).
    cycles: Vec<StackCycle>,
    /// F̂_p,k (N), k = 0..=n_harm, per actuator.
    harmonics: Vec<Vec<Complex64>>,
    /// The most periods a hysteresis cycle took to settle.
    periods: usize,
}

impl StackForces {
    fn of(model: &Model, timing: &DriveTiming, n_harm: usize, detail: Detail) -> Result<Self> {
        let (period, samples) = (timing.period, timing.steps_per_period);
        let stacks = model.actuators.iter().map(|a| a.stack());
        Ok(match detail {
            Detail::Full => {
                let cycles: Vec<StackCycle> =
                    stacks.map(|st| stack_cycle(st, period, samples)).collect::<Result<_>>()?;
                StackForces {
                    harmonics: cycles.iter().map(|c| force_harmonics(c, n_harm)).collect(),
                    periods: cycles.iter().map(|c| c.periods).fold(0, usize::max),
                    cycles,
                }
            }
            Detail::Headline(cache) => {
                let h: Vec<Arc<_>> = stacks.map(|st| cache.get(st, period, samples, n_harm)).collect::<Result<_>>()?;
                StackForces {
                    cycles: Vec::new(),
                    harmonics: h.iter().map(|h| h.f_p.clone()).collect(),
                    periods: h.iter().map(|h| h.periods).fold(0, usize::max),
                }
            }
        })
    }
}

/// Each point load's spectrum from the solved amplitudes `q[k]` and its force harmonics.
fn load_spectra(
    model: &Model,
    sys: &System,
    q: &[Vec<Complex64>],
    load_h: Vec<Vec<Complex64>>,
    timing: &DriveTiming,
) -> Vec<LoadSpectrum> {
    let w0 = 2.0 * PI / timing.period;
    let n_harm = q.len() - 1;
    model
        .loads
        .iter()
        .zip(&sys.loads)
        .zip(load_h)
        .map(|((l, pattern), force)| {
            let w = gather(q, pattern);
            let v = w.iter().enumerate().map(|(k, x)| x * Complex64::new(0.0, k as f64 * w0)).collect();
            LoadSpectrum::new(&l.name, l.at.x(), (timing.period, timing.steps_per_period, n_harm), force, v)
        })
        .collect()
}

/// The largest relative round-off bound of the links' and loads' mean powers (sums over
/// harmonics, each harmonic's error bounded from its DOF error bounds `error[k]`).
fn roundoff_bound(sys: &System, res: &SteadyStateResult, error: &[Refined], w0: f64) -> f64 {
    let links = sys.links.iter().zip(&res.spectra).map(|(lk, s)| {
        let bound: f64 = error
            .iter()
            .enumerate()
            .map(|(k, e)| link_error(lk, e, k as f64 * w0, s.interface[k], s.velocity[k]))
            .sum();
        roundoff::relative(bound, s.power_total)
    });
    let loads = sys.loads.iter().zip(&res.load_spectra).map(|(pattern, s)| {
        let bound: f64 = error
            .iter()
            .enumerate()
            .map(|(k, e)| load_error(pattern, e, k as f64 * w0, s.force[k], s.velocity[k]))
            .sum();
        roundoff::relative(bound, s.power_total)
    });
    links.chain(loads).fold(0.0, f64::max)
}

/// A bound (W) of a link's mean power at one harmonic ω (rad/s), from the estimate `e` of
/// the DOFs' error, its interface force `fi` and foot velocity `v`.
fn link_error(lk: &LinkDofs, e: &Refined, w: f64, fi: Complex64, v: Complex64) -> f64 {
    link_power_error(lk, e.bound(&lk.stretch), e.bound(&lk.foot), w, fi, v)
}

/// A bound (W) of a point load's mean power at one harmonic ω (rad/s), from the estimate
/// `e` of the DOFs' error, its force `f` and the velocity `v` at its point.
fn load_error(pattern: &[(usize, f64)], e: &Refined, w: f64, f: Complex64, v: Complex64) -> f64 {
    mean_power_error(f, 0.0, v, w * e.bound(pattern))
}

/// Each point's mean power (W) at one harmonic ω (rad/s) of amplitudes `q`, and the bound
/// of its error from `e`: each link's, then each point load's. `forcing` holds the
/// harmonic's stack forces, then its point loads' forces.
fn harmonic_points<'a>(
    sys: &'a System,
    q: &'a [Complex64],
    w: f64,
    forcing: &'a [Complex64],
    e: &'a Refined,
) -> impl Iterator<Item = (f64, f64)> + 'a {
    let links = sys.links.iter().map(move |lk| {
        let h = link_harmonic(lk, q, w, forcing);
        (h.power, link_error(lk, e, w, h.interface, h.velocity))
    });
    let loads = sys.loads.iter().zip(&forcing[sys.drives.len()..]).map(move |(pattern, &f)| {
        let v = Complex64::new(0.0, w) * pattern.iter().map(|&(d, c)| q[d] * c).sum::<Complex64>();
        (mean_power(f, v), load_error(pattern, e, w, f, v))
    });
    links.chain(loads)
}

/// Each link's spectrum from the solved amplitudes `q[k]` and the stack forces `f_p[a][k]`.
fn link_spectra(sys: &System, q: &[Vec<Complex64>], f_p: &[Vec<Complex64>], timing: &DriveTiming) -> Vec<LinkSpectrum> {
    let w0 = 2.0 * PI / timing.period;
    let n_harm = q.len() - 1;
    let mut fp = vec![Complex64::default(); f_p.len()];
    let mut spectra = Vec::with_capacity(sys.links.len());
    for lk in &sys.links {
        let (mut ft, mut fi, mut v, mut a) = (Vec::new(), Vec::new(), Vec::new(), Vec::new());
        for (k, qk) in q.iter().enumerate() {
            fp.iter_mut().zip(f_p).for_each(|(x, f)| *x = f[k]);
            let lh = link_harmonic(lk, qk, k as f64 * w0, &fp);
            ft.push(lh.transmitted);
            fi.push(lh.interface);
            v.push(lh.velocity);
            a.push(lh.acceleration);
        }
        spectra.push(LinkSpectrum::new(timing.period, timing.steps_per_period, n_harm, ft, fi, v, a));
    }
    spectra
}

/// One period in time from harmonic amplitudes c_k: t_j = j·T/N, so e^{ikω₀t_j} =
/// e^{2πi·kj/N} and the period is one inverse FFT (rustfft's inverse transform is
/// unnormalised, as the sum needs): N·log N work instead of N·(k + 1) sines and cosines.
pub(crate) struct PeriodSynthesis {
    ifft: Arc<dyn rustfft::Fft<f64>>,
    buf: Vec<Complex64>,
    w0: f64,
}

impl PeriodSynthesis {
    pub(crate) fn new(samples: usize, w0: f64) -> Self {
        let ifft = rustfft::FftPlanner::new().plan_fft_inverse(samples);
        PeriodSynthesis { ifft, buf: vec![Complex64::default(); samples], w0 }
    }

    /// x_j = Re Σ_k c_k·e^{2πi·kj/N}, j < N (k < N).
    pub(crate) fn series(&mut self, c: &[Complex64]) -> Vec<f64> {
        self.buf.fill(Complex64::default());
        self.buf[..c.len()].copy_from_slice(c);
        self.ifft.process(&mut self.buf);
        self.buf.iter().map(|x| x.re).collect()
    }

    /// The amplitudes of the time derivative: c_k·ikω₀.
    fn rate(&self, c: &[Complex64]) -> Vec<Complex64> {
        c.iter().enumerate().map(|(k, x)| x * Complex64::new(0.0, k as f64 * self.w0)).collect()
    }

    /// A signal and its first two time derivatives over the period.
    fn with_rates(&mut self, c: &[Complex64]) -> [Vec<f64>; 3] {
        let d1 = self.rate(c);
        let d2 = self.rate(&d1);
        [self.series(c), self.series(&d1), self.series(&d2)]
    }
}

/// Σ coeff·Q_k[dof] of a sparse read-out pattern, for each harmonic k.
fn gather(q: &[Vec<Complex64>], pattern: &[(usize, f64)]) -> Vec<Complex64> {
    q.iter().map(|qk| pattern.iter().map(|&(d, c)| qk[d] * c).sum()).collect()
}

/// Fills the result's period in time: links, bodies, drives (from the stacks' `cycles`)
/// and sensors.
fn reconstruct(
    res: &mut SteadyStateResult,
    model: &Model,
    sys: &System,
    q: &[Vec<Complex64>],
    f_p: &[Vec<Complex64>],
    cycles: Vec<StackCycle>,
    samples: usize,
) -> Result<()> {
    let period = res.period;
    res.t = (0..samples).map(|j| j as f64 * period / samples as f64).collect();
    let mut synth = PeriodSynthesis::new(samples, 2.0 * PI / period);
    for (lk, sp) in sys.links.iter().zip(&res.spectra) {
        let u = gather(q, &lk.stretch);
        let fpz: Vec<Complex64> =
            f_p[lk.actuator].iter().map(|&f| if lk.active { -f } else { Complex64::default() }).collect();
        let series = LinkSeries {
            stretch: synth.series(&u),
            stretch_rate: synth.series(&synth.rate(&u)),
            f_pzt: synth.series(&fpz),
            transmitted: synth.series(&sp.transmitted),
            interface: synth.series(&sp.interface),
            base_velocity: synth.series(&sp.velocity),
            base_acceleration: synth.series(&sp.acceleration),
            ..LinkSeries::of(lk)
        };
        res.links.push(series.complete(lk));
    }
    for b in body_dofs(model, sys) {
        let amplitudes: Vec<Complex64> = q.iter().map(|qk| qk[b.dof]).collect();
        let [q, q_dot, q_ddot] = synth.with_rates(&amplitudes);
        res.bodies.push(BodySeries { actuator: b.actuator, dof: b.name.to_string(), q, q_dot, q_ddot });
    }
    for (a, c) in cycles.into_iter().enumerate() {
        res.drives.push(DriveSeries::new(a, &model.actuators[a].stack().hysteresis, c.voltage, c.h, c.f_p));
    }
    for se in &model.sensors {
        let [w, v, a] = synth.with_rates(&gather(q, &sys.w_at(model, &se.at, "sensor.x")?));
        res.sensors.push(SensorSeries { name: se.name.clone(), x: se.at.x(), y: se.at.y(), at: Some(se.at), w, v, a });
    }
    Ok(())
}

/// Fills the result's period of each point load: its force `samples` and the beam's motion
/// at its point.
fn reconstruct_loads(
    res: &mut SteadyStateResult,
    model: &Model,
    sys: &System,
    q: &[Vec<Complex64>],
    samples: Vec<Vec<f64>>,
) {
    let mut synth = PeriodSynthesis::new(res.t.len(), 2.0 * PI / res.period);
    for ((l, pattern), force) in model.loads.iter().zip(&sys.loads).zip(samples) {
        let [w, v, a] = synth.with_rates(&gather(q, pattern));
        res.loads.push(LoadSeries { name: l.name.clone(), x: l.at.x(), y: l.at.y(), at: Some(l.at), force, w, v, a });
    }
}

impl SteadyStateResult {
    /// Moves the amplitudes Q_k of a run on a reduced system to the full model's DOFs.
    pub fn expand(&mut self, reduced: &System) {
        if let Some(p) = &reduced.projection {
            self.q = self.q.iter().map(|qk| p.expand(qk)).collect();
        }
    }

    /// Adds the mode-resolved decomposition with the first `count` bare-structure modes
    /// (`sys` is the full system the amplitudes Q_k belong to).
    pub fn decompose_modes(&mut self, model: &Model, sys: &System, count: usize) -> Result<()> {
        let modes = super::modes::bare_modes_on(model, sys, count)?;
        self.decompose_with(sys, modes.as_ref(), ModalDamping::of_model(model, sys));
        Ok(())
    }

    /// Adds the mode-resolved decomposition with the bare structure's `modes`, numbered on
    /// the DOFs of `sys`, the full system the amplitudes Q_k belong to (None: the model has
    /// no structure, and there is no decomposition).
    pub fn decompose_with(&mut self, sys: &System, modes: Option<&Modes>, damping: ModalDamping) {
        let interface: Vec<Vec<Complex64>> = self.spectra.iter().map(|s| s.interface.clone()).collect();
        let w0 = 2.0 * PI / self.period;
        let loads: Vec<Vec<Complex64>> = self.load_spectra.iter().map(|s| s.force.clone()).collect();
        self.modal = modes.map(|m| decompose(sys, m, damping, (&self.q, w0), &interface, &loads));
    }
}

/// Solves (K − ω²M + iωC)·Q = Σ_a b_a·F̂_p,a for one frequency ω (rad/s).
pub fn solve_at(sys: &System, w: f64, fp: &[Complex64]) -> Result<Vec<Complex64>> {
    let mut dk = DynamicStiffness::of(sys);
    dk.factorize(w)?;
    let mut rhs = vec![Complex64::default(); sys.n()];
    for (a, b) in sys.drives.iter().enumerate() {
        for &(d, c) in b {
            rhs[d] += fp[a] * c;
        }
    }
    dk.solve_in_place(&mut rhs);
    Ok(rhs)
}

/// Solves (K − ω_k²M + iω_kC)·Q_k = Σ_a b_a·F̂_p,a,k for k = 0..=n_harm (ω_k = k·ω₀),
/// with `fp_h(a, k)` = F̂_p of actuator a at harmonic k,
/// refilling one profile factorisation, and returns Q_k and the beam dissipation per
/// harmonic (W).
pub fn solve_harmonics(
    sys: &System,
    fp_h: impl Fn(usize, usize) -> Complex64,
    n_harm: usize,
    w0: f64,
) -> Result<(Vec<Vec<Complex64>>, Vec<f64>)> {
    let mut solver = HarmonicSolver::new(sys);
    solver.solve(fp_h, n_harm, w0)?;
    Ok((solver.q, solver.diss))
}

/// Harmonics whose stack forces are below this fraction of the largest harmonic's are not
/// solved (their response is zero to this relative level).
pub const NEGLIGIBLE_HARMONIC: f64 = 1e-12;

/// The harmonic solves of one system, kept for many periodic steady states: a sweep
/// evaluates every drive frequency of a placement against one assembled system, and this
/// keeps its profile storage and the Q_k vectors, so a steady state allocates nothing.
/// Results are bit for bit those of [`solve_harmonics`].
///
/// A placement's system on a shared modal basis is solved in its coupled form
/// ([`ModalCoupling`]: the modes' receptance at the feet coupled to the actuators) where
/// that form holds and no refinement needs the dense factor; every other system by the
/// profile factor of its dynamic stiffness.
pub struct HarmonicSolver<'s> {
    sys: &'s System,
    /// The profile factor, built when first needed.
    dk: Option<DynamicStiffness>,
    coupled: Option<ModalCoupling>,
    /// The refinement of the solves against the model's element rows (set by
    /// [`HarmonicSolver::prepare`]; without it the factor's solutions stand, unbounded).
    refinement: Option<MeshRefinement>,
    /// Q_k, k = 0..=n_harm, of the last [`HarmonicSolver::solve`] (DOF units: m, rad).
    pub q: Vec<Vec<Complex64>>,
    /// Per harmonic, the estimate of Q_k's error (empty where not estimated).
    pub error: Vec<Refined>,
    /// Two stages for a refined mesh's pairs of harmonics, solved side by side (built when
    /// first needed).
    stages: Option<[PairStage; 2]>,
    /// Beam dissipation per harmonic (W) of the last solve.
    pub diss: Vec<f64>,
}

impl<'s> HarmonicSolver<'s> {
    pub fn new(sys: &'s System) -> Self {
        let coupled = ModalCoupling::of(sys);
        HarmonicSolver {
            sys,
            dk: None,
            coupled,
            refinement: None,
            q: Vec::new(),
            error: Vec::new(),
            stages: None,
            diss: Vec::new(),
        }
    }

    /// Refines the solves against `model`'s element rows from now on (once; `model` is the
    /// one the system was assembled from), unless its mesh is coarse enough for the
    /// envelope ([`roundoff::coarse_bound`]).
    pub fn prepare(&mut self, model: &Model) -> Result<()> {
        if self.refinement.is_none() && roundoff::coarse_bound(model).is_none() {
            self.refinement = Some(MeshRefinement::new(model, self.sys)?);
        }
        Ok(())
    }

    /// The system solved against.
    pub fn system(&self) -> &'s System {
        self.sys
    }

    /// Solves for k = 0..=n_harm at ω_k = k·ω₀ (rad/s) into [`HarmonicSolver::q`] and
    /// [`HarmonicSolver::diss`]. `fp_h(j, k)` (N) is harmonic k of forcing j: the stack
    /// force F̂_p of actuator j, then (j ≥ actuators) the force of point load j − actuators.
    pub fn solve(&mut self, fp_h: impl Fn(usize, usize) -> Complex64, n_harm: usize, w0: f64) -> Result<()> {
        let sys = self.sys;
        self.q.resize_with(n_harm + 1, Vec::new);
        self.diss.clear();
        let forcings = sys.drives.len() + sys.loads.len();
        for (k, rhs) in self.q.iter_mut().enumerate() {
            let forcing: Vec<Complex64> = (0..forcings).map(|j| fp_h(j, k)).collect();
            forcing_vector(sys, &forcing, rhs);
        }
        // A harmonic whose stack forces are all below NEGLIGIBLE_HARMONIC of the largest is
        // not solved: its Q_k is zero. For a sine drive these are the even harmonics (and
        // the mean), which the hysteresis's odd symmetry makes zero up to the FFT's
        // round-off; skipping them halves the work of a steady state.
        let size = |k: usize| (0..forcings).map(|j| fp_h(j, k).norm()).fold(0.0f64, f64::max);
        let largest = (0..=n_harm).map(size).fold(0.0f64, f64::max);
        let mut active = Vec::with_capacity(n_harm + 1);
        for k in 0..=n_harm {
            if size(k) > NEGLIGIBLE_HARMONIC * largest {
                active.push(k);
            } else {
                self.q[k].iter_mut().for_each(|x| *x = Complex64::default());
            }
        }
        self.error.clear();
        self.error.resize_with(n_harm + 1, Refined::default);
        let task = crate::progress::Task::start("steady state", Some(active.len() as u64), "harmonics solved");
        // The coupled form where no element rows ask for the dense factor's refinement (the
        // error estimate is then none either way), the dense factor where a solve of it
        // does not settle.
        match &mut self.coupled {
            Some(mc) if self.refinement.as_ref().is_none_or(|r| !r.can_refine()) => {
                let rhs: Vec<Vec<Complex64>> = active.iter().map(|&k| self.q[k].clone()).collect();
                let omegas: Vec<f64> = active.iter().map(|&k| k as f64 * w0).collect();
                let mut xs: Vec<&mut [Complex64]> = self
                    .q
                    .iter_mut()
                    .enumerate()
                    .filter(|(k, _)| active.contains(k))
                    .map(|(_, q)| &mut q[..])
                    .collect();
                let settled = mc.solve_at(&omegas, &mut xs)?;
                task.set(active.len() as u64)?;
                for ((&k, rhs), settled) in active.iter().zip(rhs).zip(settled) {
                    if !settled {
                        let dk = self.dk.get_or_insert_with(|| DynamicStiffness::of(sys));
                        self.q[k] = rhs;
                        dk.factorize(k as f64 * w0)?;
                        dk.solve_in_place(&mut self.q[k]);
                    }
                }
            }
            _ => self.solve_dense(&active, &fp_h, w0, &task)?,
        }
        for (k, q) in self.q.iter().enumerate() {
            let w = k as f64 * w0;
            self.diss.push(match (&self.refinement, active.contains(&k)) {
                (_, false) => 0.0,
                (Some(r), true) => r.dissipation(sys, q, w),
                (None, true) => beam_dissipation(sys, q, w),
            });
        }
        Ok(())
    }

    /// The `active` harmonics' solves (right-hand sides in [`HarmonicSolver::q`]) by the
    /// profile factor, refined where the model asks.
    fn solve_dense(
        &mut self,
        active: &[usize],
        fp_h: impl Fn(usize, usize) -> Complex64,
        w0: f64,
        task: &crate::progress::Task,
    ) -> Result<()> {
        let sys = self.sys;
        let Some(r) = &self.refinement else {
            let dk = self.dk.get_or_insert_with(|| DynamicStiffness::of(sys));
            // Harmonics in pairs (see DynamicStiffness::factorize_pair): the same bits as
            // one at a time, in less time.
            for (done, pair) in active.chunks(2).enumerate() {
                task.set(2 * done as u64)?;
                match *pair {
                    [ka, kb] => {
                        dk.factorize_pair(ka as f64 * w0, kb as f64 * w0)?;
                        let (lo, hi) = self.q.split_at_mut(kb);
                        dk.solve_pair(&mut lo[ka], &mut hi[0]);
                    }
                    [k] => {
                        dk.factorize(k as f64 * w0)?;
                        dk.solve_in_place(&mut self.q[k]);
                    }
                    _ => unreachable!("chunks of 1 or 2"),
                }
            }
            return Ok(());
        };
        // A refined mesh's pairs are solved in waves on two stages, as the count's are.
        let forcings = sys.drives.len() + sys.loads.len();
        let forcing: Vec<Vec<Complex64>> =
            (0..self.q.len()).map(|k| (0..forcings).map(|j| fp_h(j, k)).collect()).collect();
        let stages = self.stages.get_or_insert_with(|| [(); 2].map(|_| PairStage::new(sys)));
        let kept = Kept { sys, forcing: &forcing, w0, refinement: r };
        let pairs: Vec<&[usize]> = active.chunks(2).collect();
        let (q, error) = (&mut self.q, &mut self.error);
        let solve = |stage: &mut PairStage, pair: &[usize], shares: Shares<'s>| stage.kept(&kept, pair, shares);
        in_waves(
            stages,
            &pairs,
            &mut Shares::new(sys, active.len(), true),
            task,
            solve,
            |shares, pair, solved, stage| {
                for (lane, (&k, (e, powers))) in pair.iter().zip(solved).enumerate() {
                    std::mem::swap(&mut q[k], &mut stage.q0[lane]);
                    error[k] = e;
                    shares.so_far.iter_mut().zip(&powers).for_each(|(t, x)| *t += x);
                }
            },
        )?;
        Ok(())
    }
}

/// The right-hand side Σ_j f_j·b_j of one harmonic's `forcing` (stack forces, then point
/// loads), into `rhs` (resized to the system's DOFs).
fn forcing_vector(sys: &System, forcing: &[Complex64], rhs: &mut Vec<Complex64>) {
    rhs.clear();
    rhs.resize(sys.n(), Complex64::default());
    for (b, f) in sys.drives.iter().chain(&sys.loads).zip(forcing) {
        for &(d, c) in b {
            rhs[d] += f * c;
        }
    }
}

/// The largest of one harmonic's forcings (N), from each forcing's harmonics.
fn forcing_size(forcings: &[Vec<Complex64>], k: usize) -> f64 {
    forcings.iter().map(|f| f[k].norm()).fold(0.0f64, f64::max)
}

/// The period and the harmonics k = 0..=`n_harm` (N) of every forcing from `samples` per
/// period: each stack's F_p (from `cache`), then each point load's.
fn forcing_harmonics(
    model: &Model,
    samples: usize,
    n_harm: usize,
    cache: &StackForceCache,
) -> Result<(f64, Vec<Vec<Complex64>>)> {
    let timing = DriveTiming::sampled(model, samples)?;
    let stacks = StackForces::of(model, &timing, n_harm, Detail::Headline(cache))?;
    let loads = load_cycles(model, &timing).into_iter().map(|f| harmonics(&f)[..=n_harm].to_vec());
    Ok((timing.period, stacks.harmonics.into_iter().chain(loads).collect()))
}

/// One harmonic's solve: factorisation `lane` of `dk`, for right-hand side `rhs`.
#[derive(Clone, Copy)]
struct Solved<'a> {
    dk: &'a DynamicStiffness,
    lane: usize,
    rhs: &'a [Complex64],
}

/// Each point's power from the harmonics solved so far, against which a harmonic's share
/// of the tolerance is judged.
///
/// A harmonic is refined unless its first estimate already keeps the bound of every
/// point's power within its share of the tolerance: REFINE_FRACTION/(the harmonics solved)
/// of the power the point has from the harmonics before it (the lower ones, which carry
/// most of it; the first has none, and is refined). In [`in_waves`] "before it" is the
/// waves before its own and its pair's first lane: a smaller budget, never a larger one.
/// The shares sum to REFINE_FRACTION of the tolerance wherever the power so far is the
/// point's power; the bound stated is
/// computed afterwards from every harmonic's estimate, whatever was refined, so the choice
/// can cost accuracy but never the bound's validity. The mean (k = 0) carries no power but
/// the static shape, where the factor is worst: it is held to the tolerance as a whole. A
/// harmonic left so has a small share of the motion too (its apparent power is small
/// beside every point's), so the displacements it adds to the time series are off by as
/// little.
#[derive(Clone)]
struct Shares<'s> {
    sys: &'s System,
    share: f64,
    so_far: Vec<f64>,
    /// Whether the estimates get their rounding floor (a stated bound needs it).
    floor: bool,
}

impl<'s> Shares<'s> {
    fn new(sys: &'s System, harmonics: usize, floor: bool) -> Self {
        let share = roundoff::REFINE_FRACTION / harmonics.max(1) as f64;
        Shares { sys, share, so_far: vec![0.0; sys.links.len() + sys.loads.len()], floor }
    }

    /// Refines `q`, harmonic k's solution from `solve`, unless its share allows (above), and
    /// adds the harmonic's power to each point's; returns the estimate of q's error and each
    /// point's power (W). `at`: k, ω_k (rad/s) and the harmonic's forcing (stack forces,
    /// then point loads).
    /// `first` is q's first estimate where it is already known
    /// ([`MeshRefinement::first_estimates`]), None to compute it here.
    fn refine(
        &mut self,
        first: Option<Refined>,
        r: &MeshRefinement,
        solve: Solved,
        q: &mut [Complex64],
        at: (usize, f64, &[Complex64]),
    ) -> (Refined, Vec<f64>) {
        let (sys, (k, w, forcing)) = (self.sys, at);
        let budget: Vec<f64> = self.so_far.iter().map(|p| self.share * r.tolerance() * p.abs()).collect();
        let enough = |q: &[Complex64], e: &Refined| {
            k > 0 && harmonic_points(sys, q, w, forcing, e).zip(&budget).all(|((_, err), b)| err <= *b)
        };
        let e = r.refine_unless(first, solve.dk, solve.lane, solve.rhs, q, enough, self.floor);
        (e, self.add(q, w, forcing))
    }

    /// Adds the power of harmonic motion `q` at ω (rad/s) under `forcing` to each point's;
    /// returns each point's power (W).
    fn add(&mut self, q: &[Complex64], w: f64, forcing: &[Complex64]) -> Vec<f64> {
        let none = Refined::default();
        let powers: Vec<f64> = harmonic_points(self.sys, q, w, forcing, &none).map(|(p, _)| p).collect();
        self.so_far.iter_mut().zip(&powers).for_each(|(s, p)| *s += p);
        powers
    }
}

/// Compares two steady states of the same model (point and net powers).
pub fn reduction_error(full: &SteadyStateResult, reduced: &SteadyStateResult) -> ReductionError {
    ReductionError::between(
        full.harmonics,
        (&full.mean_power, &full.net_power),
        (&reduced.mean_power, &reduced.net_power),
    )
}

/// Runs the frequency-domain steady state of both models at `harmonics` harmonics and
/// compares their point powers.
pub fn estimate_reduction_error(
    model: &Model,
    full: &System,
    reduced: &System,
    harmonics: usize,
    samples: usize,
) -> Result<ReductionError> {
    let f = run(model, full, harmonics, samples)?;
    let r = run(model, reduced, harmonics, samples)?;
    Ok(reduction_error(&f, &r))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A fine mesh's count (each harmonic factorised once for both samplings, the one
    /// forcing's solve scaled from one to the other) gives each point's power per harmonic,
    /// and the aliasing from their differences, as the two runs solved apart do, to the
    /// share of the tolerance their refinement holds each to.
    #[test]
    fn a_fine_meshs_count_gives_the_spectra_of_the_two_runs_apart() {
        let text = include_str!("../../cases/beam-frame-12V-60Hz.toml")
            .replace("[beam]", "[beam]\n[beam.mesh]\nelements = 400");
        let lc = crate::case::LoadedCase::from_str(&text, "frame.toml", std::path::PathBuf::from(".")).unwrap();
        let model = crate::analysis::plan::calibrated_model(&lc).unwrap();
        let sys = System::assemble(&model).unwrap();
        assert!(roundoff::coarse_bound(&model).is_none(), "a mesh whose solves are refined");
        let (all, samples) = (127, 256);
        let (_, counted) = fine_spectra(&model, &sys, all, samples).unwrap();
        let cache = StackForceCache::default();
        let apart = [
            run(&model, &sys, all, samples).unwrap(),
            run_with(&model, &mut HarmonicSolver::new(&sys), all, 2 * samples, Detail::Headline(&cache)).unwrap(),
        ]
        .map(|r| point_spectra(&r).cloned().collect::<Vec<_>>());
        let powers: Vec<f64> = apart[0].iter().map(|p| p.iter().sum()).collect();
        let scales = own_scales(&powers);
        let held = 2.0 * roundoff::REFINE_FRACTION * model.roundoff_tolerance;
        for (c, a) in counted.iter().zip(&apart) {
            for (i, ((c, a), s)) in c.iter().zip(a).zip(&scales).enumerate() {
                assert_eq!(c.len(), all + 1);
                let off: f64 = c.iter().zip(a).map(|(x, y)| (x - y).abs()).sum();
                assert!(off <= held * s, "point {i}: {off:e} W off, against {s:e} W");
            }
        }
        let folded = [aliasing(&counted[0], &counted[1]), aliasing(&apart[0], &apart[1])];
        for (i, ((c, a), s)) in folded[0].iter().zip(&folded[1]).zip(&scales).enumerate() {
            assert!((c - a).abs() <= 2.0 * held * s, "point {i}: aliasing {c:e} W against {a:e} W");
        }
    }
}
