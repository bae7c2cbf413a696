//! The exact periodic steady state, solved in the frequency domain.
//!
//! The structure is linear and F_p depends on the voltage alone, so: integrate h over
//! whole periods until its cycle repeats, take the Fourier coefficients of each stack's
//! F_p over one period, and solve (K − ω_k²M + iω_kC)·Q_k = Σ_a b_a·F̂_p,a,k for each
//! harmonic ω_k = k·ω₀ (a static solve for the mean). The profile factorisation is refilled
//! in place for each harmonic. Results take the same form as the transient path's.

use super::transient::{time_grid, BodySeries, DriveSeries, LinkSeries, LinkSpectrum, SensorSeries, TransientSettings};
use crate::assembly::{Model, System};
use crate::error::{Error, Result};
use crate::power::link::link_harmonic;
use crate::power::modal::{decompose, ModalDamping, ModalDecomposition};
use crate::power::point::dissipated_power;
use crate::power::spectra::harmonics;
use crate::solve::eigen::Modes;
use crate::solve::harmonic::DynamicStiffness;
use num_complex::Complex64;
use serde::Serialize;
use std::f64::consts::PI;

/// Periodic steady state.
#[derive(Clone, Debug, Default, Serialize)]
pub struct SteadyStateResult {
    /// Drive period (s) and the number of harmonics solved (besides the mean).
    pub period: f64,
    pub harmonics: usize,
    /// Periods it took h to settle into its cycle.
    pub hysteresis_periods: usize,
    /// Frequencies k·f₀ (Hz), k = 0..=harmonics.
    pub frequency: Vec<f64>,
    /// Complex DOF amplitudes Q_k, k = 0..=harmonics (q(t) = Re Σ Q_k e^{ikω₀t}).
    #[serde(skip)]
    pub q: Vec<Vec<Complex64>>,
    /// Stack force harmonics F̂_p,k per actuator (N).
    #[serde(skip)]
    pub f_p: Vec<Vec<Complex64>>,
    pub spectra: Vec<LinkSpectrum>,
    pub mean_power: Vec<f64>,
    pub net_power: Vec<f64>,
    /// Beam dissipation per harmonic and in total (W).
    pub beam_dissipation_per_harmonic: Vec<f64>,
    pub beam_dissipation: f64,
    /// |Σ interface power − beam dissipation| / beam dissipation (0 on a rigid base).
    pub balance_error: f64,
    /// One period reconstructed from the harmonics, for plots and comparison.
    pub t: Vec<f64>,
    pub links: Vec<LinkSeries>,
    pub bodies: Vec<BodySeries>,
    pub drives: Vec<DriveSeries>,
    pub sensors: Vec<SensorSeries>,
    /// Mode-resolved power flow (filled by the runner; costly for sweeps, so optional).
    pub modal: Option<ModalDecomposition>,
    /// Set when the run used a modal reduction: its basis and error estimate.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub reduction: Option<super::reduction::ReductionReport>,
}

/// Stack forces over one period of the hysteresis's periodic cycle: (V, h, F_p) samples at
/// t_j = j·T/N, j < N, for each actuator, and the number of periods it took.
///
/// The cycle settles over whole periods from h₀ at t = 0, until h at the end of a period
/// repeats its start to 1e-13 of the hysteresis bound. h at the end of a period does not
/// depend on the samples in between (the Bouc–Wen solution is exact over every monotone
/// piece of the voltage, see [`crate::actuator::bouc_wen`]), so the settling periods are
/// advanced from turning point to turning point, a few closed-form steps each, and only the
/// settled period is sampled N times. Splitting at the samples as well would give the same
/// h up to rounding, at N steps a period.
pub fn periodic_stack_forces(model: &Model, period: f64, n: usize) -> Result<(Vec<[Vec<f64>; 3]>, usize)> {
    let mut out = Vec::new();
    let mut most = 0;
    for st in model.actuators.iter().map(|a| a.stack()) {
        let bw = &st.hysteresis;
        let bound = bw.bound(st.h0).max(f64::MIN_POSITIVE);
        let mut h0 = st.h0;
        let mut p = 0;
        if st.hysteresis_on {
            loop {
                let h_end = bw.advance_time(&st.voltage, h0, p as f64 * period, (p as f64 + 1.0) * period);
                let change = (h_end - h0).abs() / bound;
                p += 1;
                if change < 1e-13 {
                    break;
                }
                if p > 10_000 {
                    return Err(Error::Numerical("the hysteresis cycle did not repeat within 10 000 periods".into()));
                }
                h0 = h_end;
            }
        } else {
            p = 1;
        }
        // The settled period, p − 1, sampled.
        let t: Vec<f64> = (0..=n).map(|j| ((p - 1) as f64 + j as f64 / n as f64) * period).collect();
        let mut h = if st.hysteresis_on { bw.history(&st.voltage, &t, h0) } else { vec![0.0; n + 1] };
        h.truncate(n);
        let v: Vec<f64> = t[..n].iter().map(|&t| st.voltage.value(t)).collect();
        most = most.max(p);
        let f = v.iter().zip(&h).map(|(&v, &h)| st.active_force(v, h)).collect();
        out.push([v, h, f]);
    }
    Ok((out, most))
}

/// Real time series x_j = Re Σ_k c_k·e^{2πi·kj/N}, j < N, of one period from its harmonic
/// amplitudes c_k (k < N), by one inverse FFT: N·log N work instead of N·(k + 1) sines and
/// cosines of a direct sum. `buf` is scratch of length N for `fft`.
fn synthesise(fft: &dyn rustfft::Fft<f64>, buf: &mut [Complex64], c: &[Complex64]) -> Vec<f64> {
    buf.fill(Complex64::default());
    buf[..c.len()].copy_from_slice(c);
    fft.process(buf);
    buf.iter().map(|x| x.re).collect()
}

/// Solves the periodic steady state with `n_harm` harmonics from `samples` per period.
pub fn run(model: &Model, sys: &System, n_harm: usize, samples: usize) -> Result<SteadyStateResult> {
    let grid = TransientSettings { harmonics: n_harm, ..Default::default() };
    let (_, _, period, periodic) = time_grid(model, &grid)?;
    if !periodic {
        return Err(Error::input("<case>", "analysis.type", "a frequency-domain steady state needs a periodic drive"));
    }
    if samples < 2 * n_harm + 2 {
        return Err(Error::input(
            "<case>",
            "analysis.samples_per_period",
            format!("at least {} samples are needed for {n_harm} harmonics", 2 * n_harm + 2),
        ));
    }
    let (forces, hyst_periods) = periodic_stack_forces(model, period, samples)?;
    let fp_h: Vec<Vec<Complex64>> = forces.iter().map(|f| harmonics(&f[2])[..=n_harm].to_vec()).collect();
    let w0 = 2.0 * PI / period;
    let (q_all, diss) = solve_harmonics(sys, |a, k| fp_h[a][k], n_harm, w0)?;
    let mut res = SteadyStateResult {
        period,
        harmonics: n_harm,
        hysteresis_periods: hyst_periods,
        frequency: (0..=n_harm).map(|k| k as f64 / period).collect(),
        f_p: fp_h.clone(),
        ..Default::default()
    };
    // Link quantities per harmonic.
    for lk in &sys.links {
        let mut sp = LinkSpectrum { frequency: res.frequency.clone(), ..Default::default() };
        for (k, q) in q_all.iter().enumerate() {
            let fp: Vec<Complex64> = fp_h.iter().map(|f| f[k]).collect();
            let h = link_harmonic(lk, q, k as f64 * w0, &fp);
            sp.transmitted.push(h.transmitted);
            sp.interface.push(h.interface);
            sp.velocity.push(h.velocity);
            sp.acceleration.push(h.acceleration);
            sp.power.push(if k == 0 { 2.0 * h.power } else { h.power });
            sp.power_from_acceleration.push(if k == 0 {
                0.0
            } else {
                -0.5 * (h.interface * h.acceleration.conj()).im / (k as f64 * w0)
            });
        }
        sp.power_total = sp.power.iter().sum();
        res.mean_power.push(sp.power_total);
        res.spectra.push(sp);
    }
    res.net_power = (0..model.actuators.len())
        .map(|a| sys.links.iter().zip(&res.mean_power).filter(|(l, _)| l.actuator == a).map(|(_, p)| p).sum())
        .collect();
    res.beam_dissipation = diss.iter().sum();
    res.beam_dissipation_per_harmonic = diss;
    let input: f64 = res.mean_power.iter().sum();
    res.balance_error = if res.beam_dissipation != 0.0 {
        (input - res.beam_dissipation).abs() / res.beam_dissipation.abs()
    } else {
        input.abs()
    };
    // One period in time, for plots.
    let nt = samples;
    res.t = (0..nt).map(|j| j as f64 * period / nt as f64).collect();
    // t_j = j·T/N, so e^{ikω₀t_j} = e^{2πi·kj/N}: one period is an inverse DFT of the
    // harmonics (rustfft's inverse transform is unnormalised, as the sum needs).
    let ifft = rustfft::FftPlanner::new().plan_fft_inverse(nt);
    let mut buf = vec![Complex64::default(); nt];
    let mut synth = |c: &[Complex64]| -> Vec<f64> { synthesise(ifft.as_ref(), &mut buf, c) };
    for (l, lk) in sys.links.iter().enumerate() {
        let sp = &res.spectra[l];
        let u: Vec<Complex64> = q_all.iter().map(|q| lk.stretch.iter().map(|&(d, c)| q[d] * c).sum()).collect();
        let ud: Vec<Complex64> = u.iter().enumerate().map(|(k, x)| x * Complex64::new(0.0, k as f64 * w0)).collect();
        let fpz: Vec<Complex64> =
            (0..=n_harm).map(|k| if lk.active { -fp_h[lk.actuator][k] } else { Complex64::default() }).collect();
        let mut s = LinkSeries {
            actuator: lk.actuator,
            name: lk.name.clone(),
            foot_x: lk.foot_x,
            stretch: synth(&u),
            stretch_rate: synth(&ud),
            f_pzt: synth(&fpz),
            transmitted: synth(&sp.transmitted),
            interface: synth(&sp.interface),
            base_velocity: synth(&sp.velocity),
            base_acceleration: synth(&sp.acceleration),
            ..Default::default()
        };
        s.f_stiffness = s.stretch.iter().map(|x| lk.k * x).collect();
        s.f_damping = s.stretch_rate.iter().map(|x| lk.c * x).collect();
        s.power = s.interface.iter().zip(&s.base_velocity).map(|(f, v)| f * v).collect();
        res.links.push(s);
    }
    for (a, ds) in sys.dofs.bodies.iter().enumerate() {
        let names = model.actuators[a].component().dof_names;
        for (k, &d) in ds.iter().enumerate() {
            let q: Vec<Complex64> = q_all.iter().map(|q| q[d]).collect();
            let qd: Vec<Complex64> =
                q.iter().enumerate().map(|(h, x)| x * Complex64::new(0.0, h as f64 * w0)).collect();
            let qdd: Vec<Complex64> =
                qd.iter().enumerate().map(|(h, x)| x * Complex64::new(0.0, h as f64 * w0)).collect();
            res.bodies.push(BodySeries {
                actuator: a,
                dof: names[k].to_string(),
                q: synth(&q),
                q_dot: synth(&qd),
                q_ddot: synth(&qdd),
            });
        }
    }
    for (a, f) in forces.iter().enumerate() {
        let d_p = model.actuators[a].stack().hysteresis.d_p;
        res.drives.push(DriveSeries {
            actuator: a,
            voltage: f[0].clone(),
            h: f[1].clone(),
            stroke: f[0].iter().zip(&f[1]).map(|(v, h)| d_p * v - h).collect(),
            f_p: f[2].clone(),
        });
    }
    for se in &model.sensors {
        let d = sys.w_at(model, se.x, "sensor.x")?;
        let w: Vec<Complex64> = q_all.iter().map(|q| d.iter().map(|&(i, c)| q[i] * c).sum()).collect();
        let v: Vec<Complex64> = w.iter().enumerate().map(|(k, x)| x * Complex64::new(0.0, k as f64 * w0)).collect();
        let a: Vec<Complex64> = v.iter().enumerate().map(|(k, x)| x * Complex64::new(0.0, k as f64 * w0)).collect();
        res.sensors.push(SensorSeries { name: se.name.clone(), x: se.x, w: synth(&w), v: synth(&v), a: synth(&a) });
    }
    res.q = q_all;
    Ok(res)
}

/// Solves (K − ω²M + iωC)·Q = Σ_a b_a·F̂_p,a for one frequency ω (rad/s).
pub fn solve_at(sys: &System, w: f64, fp: &[Complex64]) -> Result<Vec<Complex64>> {
    let mut dk = DynamicStiffness::new(&sys.k, &sys.m, &sys.c, &sys.envelope);
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

impl SteadyStateResult {
    /// Moves the amplitudes Q_k of a run on a reduced system to the full model's DOFs.
    pub fn expand(&mut self, reduced: &System) {
        if let Some(p) = &reduced.projection {
            self.q = self.q.iter().map(|qk| p.expand(qk)).collect();
        }
    }

    /// Adds the mode-resolved decomposition with the first `count` bare-structure modes
    /// (`sys` is the full system the amplitudes Q_k belong to; `modal_ratios` the case's
    /// modal damping ratios, if any).
    pub fn decompose_modes(
        &mut self,
        model: &Model,
        sys: &System,
        count: usize,
        modal_ratios: Option<&[f64]>,
    ) -> Result<()> {
        let modes = super::modes::bare_modes_on(model, sys, count)?;
        self.decompose_with(sys, modes.as_ref(), ModalDamping::of(&model.rayleigh, modal_ratios));
        Ok(())
    }

    /// Adds the mode-resolved decomposition with the bare structure's `modes`, numbered on
    /// the DOFs of `sys`, the full system the amplitudes Q_k belong to (None: the model has
    /// no structure, and there is no decomposition).
    pub fn decompose_with(&mut self, sys: &System, modes: Option<&Modes>, damping: ModalDamping) {
        let interface: Vec<Vec<Complex64>> = self.spectra.iter().map(|s| s.interface.clone()).collect();
        let w0 = 2.0 * PI / self.period;
        self.modal = modes.map(|m| decompose(sys, m, damping, &self.q, w0, &interface));
    }
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
pub struct HarmonicSolver<'s> {
    sys: &'s System,
    dk: DynamicStiffness,
    /// Q_k, k = 0..=n_harm, of the last [`HarmonicSolver::solve`] (DOF units: m, rad).
    pub q: Vec<Vec<Complex64>>,
    /// Beam dissipation per harmonic (W) of the last solve.
    pub diss: Vec<f64>,
}

impl<'s> HarmonicSolver<'s> {
    pub fn new(sys: &'s System) -> Self {
        HarmonicSolver {
            sys,
            dk: DynamicStiffness::new(&sys.k, &sys.m, &sys.c, &sys.envelope),
            q: Vec::new(),
            diss: Vec::new(),
        }
    }

    /// The system solved against.
    pub fn system(&self) -> &'s System {
        self.sys
    }

    /// Solves for k = 0..=n_harm at ω_k = k·ω₀ (rad/s), `fp_h(a, k)` = F̂_p,a,k (N), into
    /// [`HarmonicSolver::q`] and [`HarmonicSolver::diss`].
    pub fn solve(&mut self, fp_h: impl Fn(usize, usize) -> Complex64, n_harm: usize, w0: f64) -> Result<()> {
        let sys = self.sys;
        let n = sys.n();
        self.q.resize_with(n_harm + 1, Vec::new);
        self.diss.clear();
        for (k, rhs) in self.q.iter_mut().enumerate() {
            rhs.clear();
            rhs.resize(n, Complex64::default());
            for (a, b) in sys.drives.iter().enumerate() {
                for &(d, c) in b {
                    rhs[d] += fp_h(a, k) * c;
                }
            }
        }
        // A harmonic whose stack forces are all below NEGLIGIBLE_HARMONIC of the largest is
        // not solved: its Q_k is zero. For a sine drive these are the even harmonics (and
        // the mean), which the hysteresis's odd symmetry makes zero up to the FFT's
        // round-off; skipping them halves the work of a steady state.
        let size = |k: usize| (0..sys.drives.len()).map(|a| fp_h(a, k).norm()).fold(0.0f64, f64::max);
        let largest = (0..=n_harm).map(size).fold(0.0f64, f64::max);
        let mut active = Vec::with_capacity(n_harm + 1);
        for k in 0..=n_harm {
            if size(k) > NEGLIGIBLE_HARMONIC * largest {
                active.push(k);
            } else {
                self.q[k].iter_mut().for_each(|x| *x = Complex64::default());
            }
        }
        // Harmonics in pairs (see DynamicStiffness::factorize_pair): the same bits as one
        // at a time, in less time.
        for pair in active.chunks(2) {
            match *pair {
                [ka, kb] => {
                    self.dk.factorize_pair(ka as f64 * w0, kb as f64 * w0)?;
                    let (lo, hi) = self.q.split_at_mut(kb);
                    self.dk.solve_pair(&mut lo[ka], &mut hi[0]);
                }
                [k] => {
                    self.dk.factorize(k as f64 * w0)?;
                    self.dk.solve_in_place(&mut self.q[k]);
                }
                _ => unreachable!("chunks of 1 or 2"),
            }
        }
        for (k, q) in self.q.iter().enumerate() {
            self.diss.push(if active.contains(&k) { dissipated_power(&sys.c_beam, q, k as f64 * w0) } else { 0.0 });
        }
        Ok(())
    }
}
