//! Time integration of the coupled system driven by the stacks' voltages.
//!
//! The run advances whole drive periods. Because F_p depends on the voltage alone, each
//! period's stack forces are computed up front (h exact in voltage space), then the
//! Newmark loop steps through the period. At each period end the mean power at every
//! interface point and the RMS of every transmitted force are compared with the previous
//! period; the run is in steady state when both change by less than the tolerance.

use super::series::{Balances, BodySeries, DriveSeries, LinkSeries, LinkSpectrum, SensorSeries};
use crate::assembly::{Model, System};
use crate::error::{Error, Result};
use crate::power::energy::StoredEnergy;
use crate::power::point::mean_product;
use crate::power::spectra::{harmonics, power_from_acceleration, power_per_harmonic};
use crate::solve::fused::FusedNewmark;
use crate::solve::newmark::{consistent_acceleration, Scheme};
use serde::Serialize;
use std::collections::VecDeque;

/// How to run.
#[derive(Clone, Debug)]
pub struct TransientSettings {
    pub dt: Option<f64>,
    pub periods: Option<usize>,
    pub duration: Option<f64>,
    pub scheme: Scheme,
    pub steady_state: bool,
    pub tolerance: f64,
    pub max_periods: usize,
    /// Highest harmonic of the drive analysed (sets the Δt limit and the spectra length).
    pub harmonics: usize,
    /// Periods kept at the end of the run for output (and run at least before the
    /// steady-state criterion may stop it).
    pub record_periods: usize,
    /// Keep every period of the run for output instead (`[output] full_history`).
    pub full_history: bool,
}

impl Default for TransientSettings {
    fn default() -> Self {
        TransientSettings {
            dt: None,
            periods: None,
            duration: None,
            scheme: Scheme::average_acceleration(),
            steady_state: true,
            tolerance: 1e-4,
            max_periods: 400,
            harmonics: 9,
            record_periods: 3,
            full_history: false,
        }
    }
}

/// Result of a transient run.
#[derive(Clone, Debug, Default, Serialize)]
pub struct TransientResult {
    /// Time step used (s) and drive period (s).
    pub dt: f64,
    pub period: f64,
    pub steps_per_period: usize,
    pub periods_run: usize,
    pub steps_run: usize,
    /// Whether the steady-state criterion was met, and the last relative change.
    pub converged: bool,
    pub final_change: f64,
    /// Times of the recorded window (s).
    pub t: Vec<f64>,
    pub links: Vec<LinkSeries>,
    pub bodies: Vec<BodySeries>,
    pub drives: Vec<DriveSeries>,
    pub sensors: Vec<SensorSeries>,
    /// Mean power into the base at each link's foot over the last period (W).
    pub mean_power: Vec<f64>,
    /// Net mean power into the base per actuator (W).
    pub net_power: Vec<f64>,
    pub spectra: Vec<LinkSpectrum>,
    /// Over the whole run, and over the last period.
    pub energy_run: Balances,
    pub energy_last_period: Balances,
    /// Mean power dissipated in the beam over the last period (W).
    pub beam_dissipation: f64,
    /// Mean power into the beam over the last period by the same (midpoint) quadrature as
    /// the dissipation, so the two balance to round-off in steady state (W). The per-point
    /// `mean_power` are sample means, consistent with the spectra; both converge at O(Δt²).
    pub beam_input_power: f64,
    /// Set when the run used a modal reduction: its basis and error estimate.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub reduction: Option<super::reduction::ReductionReport>,
}

/// Per-sample raw channels of one period.
#[derive(Clone, Default)]
struct PeriodRecord {
    t: Vec<f64>,
    /// [link] → samples
    u: Vec<Vec<f64>>,
    ud: Vec<Vec<f64>>,
    fv: Vec<Vec<f64>>,
    fa: Vec<Vec<f64>>,
    /// [body dof] → samples
    q: Vec<Vec<f64>>,
    qd: Vec<Vec<f64>>,
    qdd: Vec<Vec<f64>>,
    /// [actuator] → samples
    v: Vec<Vec<f64>>,
    h: Vec<Vec<f64>>,
    fp: Vec<Vec<f64>>,
    /// [sensor] → samples
    sw: Vec<Vec<f64>>,
    sv: Vec<Vec<f64>>,
    sa: Vec<Vec<f64>>,
}

impl PeriodRecord {
    fn new(nl: usize, nb: usize, na: usize, ns: usize, cap: usize) -> Self {
        // Not vec![Vec::with_capacity(cap); k]: clones of a Vec do not keep its capacity.
        let mk = |k: usize| (0..k).map(|_| Vec::with_capacity(cap)).collect::<Vec<Vec<f64>>>();
        PeriodRecord {
            t: Vec::with_capacity(cap),
            u: mk(nl),
            ud: mk(nl),
            fv: mk(nl),
            fa: mk(nl),
            q: mk(nb),
            qd: mk(nb),
            qdd: mk(nb),
            v: mk(na),
            h: mk(na),
            fp: mk(na),
            sw: mk(ns),
            sv: mk(ns),
            sa: mk(ns),
        }
    }

    fn channels_mut(&mut self) -> [&mut Vec<Vec<f64>>; 13] {
        [
            &mut self.u,
            &mut self.ud,
            &mut self.fv,
            &mut self.fa,
            &mut self.q,
            &mut self.qd,
            &mut self.qdd,
            &mut self.v,
            &mut self.h,
            &mut self.fp,
            &mut self.sw,
            &mut self.sv,
            &mut self.sa,
        ]
    }

    /// Empties every series, keeping the buffers.
    fn clear(&mut self) {
        self.t.clear();
        for ch in self.channels_mut() {
            ch.iter_mut().for_each(Vec::clear);
        }
    }

    fn append(&mut self, o: &PeriodRecord) {
        self.t.extend(&o.t);
        for (a, b) in [
            (&mut self.u, &o.u),
            (&mut self.ud, &o.ud),
            (&mut self.fv, &o.fv),
            (&mut self.fa, &o.fa),
            (&mut self.q, &o.q),
            (&mut self.qd, &o.qd),
            (&mut self.qdd, &o.qdd),
            (&mut self.v, &o.v),
            (&mut self.h, &o.h),
            (&mut self.fp, &o.fp),
            (&mut self.sw, &o.sw),
            (&mut self.sv, &o.sv),
            (&mut self.sa, &o.sa),
        ] {
            for (x, y) in a.iter_mut().zip(b) {
                x.extend(y);
            }
        }
    }
}

/// A link's state at one instant (SI units).
#[derive(Clone, Copy, Debug)]
struct LinkState {
    ud: f64,
    fv: f64,
    /// Interface force on the beam, F_T − m_foot·ẅ (N).
    fi: f64,
}

/// The time grid of a run: step, samples per period and the period (s).
pub fn time_grid(model: &Model, s: &TransientSettings) -> Result<(f64, usize, f64, bool)> {
    let first = model.actuators.first().ok_or_else(|| {
        Error::input("<case>", "actuator", "a transient analysis needs at least one actuator to drive the system")
    })?;
    let period = first.stack().voltage.period();
    for (i, a) in model.actuators.iter().enumerate().skip(1) {
        let p = a.stack().voltage.period();
        if let (Some(p0), Some(pi)) = (period, p) {
            let ratio = p0.max(pi) / p0.min(pi);
            if (ratio - ratio.round()).abs() > 1e-9 {
                return Err(Error::input(
                    "<case>",
                    format!("actuator[{i}].voltage"),
                    "all actuators must share a common drive period for a periodic transient",
                ));
            }
        }
    }
    match period {
        Some(p) if s.duration.is_none() => {
            let p = model.actuators.iter().filter_map(|a| a.stack().voltage.period()).fold(p, f64::max);
            let f0 = 1.0 / p;
            let dt_max =
                1.0 / (20.0 * s.harmonics as f64 * first.stack().voltage.fundamental_frequency().unwrap_or(f0));
            let n = match s.dt {
                Some(dt) => {
                    if dt > dt_max * (1.0 + 1e-12) {
                        return Err(Error::input("<case>", "analysis.dt", format!("Δt = {dt} s is too coarse for harmonic {} of the drive: it must not exceed 1/20 of that harmonic's period, {dt_max:.6e} s", s.harmonics)));
                    }
                    (p / dt - 1e-9).ceil() as usize
                }
                None => ((p / dt_max).ceil() as usize).max(200),
            };
            Ok((p / n as f64, n, p, true))
        }
        _ => {
            let d = s
                .duration
                .ok_or_else(|| Error::input("<case>", "analysis.duration", "a non-periodic drive needs `duration`"))?;
            let hf = model.actuators.iter().filter_map(|a| a.stack().voltage.highest_frequency()).fold(0.0, f64::max);
            let dt = match (s.dt, hf > 0.0) {
                (Some(dt), _) => dt,
                (None, true) => 1.0 / (20.0 * hf),
                (None, false) => {
                    return Err(Error::input(
                        "<case>",
                        "analysis.dt",
                        "the drive has no frequency to derive a time step from: give `dt`",
                    ))
                }
            };
            let n = (d / dt - 1e-9).ceil() as usize;
            Ok((d / n as f64, n, d, false))
        }
    }
}

/// Runs the transient.
pub fn run(model: &Model, sys: &System, s: &TransientSettings) -> Result<TransientResult> {
    let (dt, n_per, period, periodic) = time_grid(model, s)?;
    let n = sys.n();
    let na = model.actuators.len();
    let nl = sys.links.len();
    let body_dofs: Vec<(usize, String, usize)> = sys
        .dofs
        .bodies
        .iter()
        .enumerate()
        .flat_map(|(a, ds)| {
            let names = model.actuators[a].component().dof_names;
            ds.iter().enumerate().map(move |(k, &d)| (a, names[k].to_string(), d)).collect::<Vec<_>>()
        })
        .collect();
    let sensor_dofs: Vec<Vec<(usize, f64)>> =
        model.sensors.iter().map(|se| sys.w_at(model, se.x, "sensor")).collect::<Result<_>>()?;

    let mut nm = FusedNewmark::new(&sys.m, &sys.c, &sys.k, &sys.envelope, s.scheme, dt)?;
    // The structure's Rayleigh damping lets the band step drop its C product (a reduced,
    // dense system declines: its C is no longer banded).
    nm.use_proportional_damping(model.rayleigh.a0, model.rayleigh.a1);
    nm.track_dissipation = true;
    let stacks: Vec<_> = model.actuators.iter().map(|a| a.stack().clone()).collect();
    let mut h_now: Vec<f64> = stacks.iter().map(|st| st.h0).collect();
    let fp0: Vec<f64> = stacks
        .iter()
        .enumerate()
        .map(|(a, st)| {
            if st.hysteresis_on {
                st.active_force(st.voltage.value(0.0), h_now[a])
            } else {
                st.active_force(st.voltage.value(0.0), 0.0)
            }
        })
        .collect();
    // F₀ = Σ_a b_a·F_p,a(0) as sparse pairs, for the initial acceleration.
    let loads: Vec<(usize, f64)> =
        sys.drives.iter().zip(&fp0).flat_map(|(b, &fp)| b.iter().map(move |&(d, c)| (d, c * fp))).collect();
    let zeros = vec![0.0; n];
    let a0 = consistent_acceleration(&sys.m, &sys.c, &sys.k, &sys.envelope, &zeros, &zeros, &loads)?;
    nm.set_state(&zeros, &zeros, &a0, &loads);
    nm.set_load_patterns(sys.drives.clone());
    nm.set_previous_weights(&fp0);

    let total_periods = if !periodic {
        1
    } else if let Some(p) = s.periods {
        p
    } else if s.steady_state {
        s.max_periods
    } else {
        1
    };
    let min_periods = if periodic { s.record_periods.max(1) } else { 1 };
    let keep = if s.full_history { total_periods.max(1) } else { min_periods };
    let mut window: VecDeque<PeriodRecord> = VecDeque::new();
    let mut prev_metrics: Option<Vec<f64>> = None;
    let mut converged = false;
    let mut final_change = f64::NAN;
    let mut periods_run = 0;
    let mut run_bal = Balances::default();
    let mut per_bal = Balances::default();
    let energy = StoredEnergy::new(sys);
    let stored = |nm: &FusedNewmark| -> (f64, f64) { energy.beam_and_system(nm.u(), nm.v()) };
    let (eb_start, es_start) = stored(&nm);
    // Stored energies at the latest period boundary (the end of one period starts the next).
    let mut e_boundary = (eb_start, es_start);
    // Read-outs the integrator evaluates after every step: each link's stretch and foot,
    // each drive, each sensor and each body DOF, in that order.
    let mut rows: Vec<Vec<(usize, f64)>> = Vec::new();
    for lk in &sys.links {
        rows.push(lk.stretch.clone());
        rows.push(lk.foot.clone());
    }
    let (drive_row, sensor_row) = (2 * nl, 2 * nl + sys.drives.len());
    let body_row = sensor_row + sensor_dofs.len();
    rows.extend(sys.drives.iter().cloned());
    rows.extend(sensor_dofs.iter().cloned());
    rows.extend(body_dofs.iter().map(|&(_, _, d)| vec![(d, 1.0)]));
    nm.set_observations(&rows);
    // Each link's state (stretch rate, foot velocity, interface force) is evaluated once per
    // step, after the step, as the end point of this step's energy terms (the records come
    // from the read-outs themselves).
    let link_state = |nm: &FusedNewmark, l: usize, lk: &crate::assembly::LinkDofs, fp: &[f64]| -> LinkState {
        let (stretch, foot) = (nm.observed()[2 * l], nm.observed()[2 * l + 1]);
        let (su, sud, fv, fa) = (stretch[0], stretch[1], foot[1], foot[2]);
        let ft = lk.k * su + lk.c * sud - if lk.active { fp[lk.actuator] } else { 0.0 };
        LinkState { ud: sud, fv, fi: ft - lk.foot_mass * fa }
    };
    let drive_rate = |nm: &FusedNewmark, a: usize| -> f64 { nm.observed()[drive_row + a][1] };
    let mut links_now: Vec<LinkState> =
        sys.links.iter().enumerate().map(|(l, lk)| link_state(&nm, l, lk, &fp0)).collect();
    let mut drive_v: Vec<f64> = (0..sys.drives.len()).map(|a| drive_rate(&nm, a)).collect();
    let mut fp_prev = fp0.clone();

    let mut times = vec![0.0; n_per + 1];
    let mut hist_h: Vec<Vec<f64>> = vec![Vec::new(); na];
    let mut hist_v: Vec<Vec<f64>> = vec![Vec::new(); na];
    let mut fp_step = vec![0.0; na];
    let n_obs = nm.observed().len();
    let mut snap: Vec<[f64; 3]> = Vec::with_capacity(n_per * n_obs);
    let mut fp_snap: Vec<f64> = Vec::with_capacity(n_per * na);
    for p in 0..total_periods {
        let t0 = p as f64 * period;
        for (j, t) in times.iter_mut().enumerate() {
            *t = t0 + j as f64 * dt;
        }
        for (a, st) in stacks.iter().enumerate() {
            let (hv, hh) = (&mut hist_v[a], &mut hist_h[a]);
            if st.hysteresis_on {
                st.hysteresis.history_into(&st.voltage, &times, h_now[a], hh, hv);
            } else {
                hv.clear();
                hv.extend(times.iter().map(|&t| st.voltage.value(t)));
                hh.clear();
                hh.resize(times.len(), 0.0);
            }
            h_now[a] = hh[n_per];
        }
        // The oldest period of a full window is recycled (its buffers keep their capacity).
        let mut rec = if window.len() >= keep {
            let mut old = window.pop_front().expect("a full window");
            old.clear();
            old
        } else {
            PeriodRecord::new(nl, body_dofs.len(), na, model.sensors.len(), n_per)
        };
        let (eb0, es0) = e_boundary;
        let d_sys0 = nm.dissipated();
        let mut pb = Balances::default();
        snap.clear();
        fp_snap.clear();
        for j in 0..n_per {
            // Record the state at t_j: the read-outs as they stand (each link's stretch and
            // foot, drives, sensors, bodies) and the stack forces, sorted into series once
            // the period is over.
            snap.extend_from_slice(nm.observed());
            fp_snap.extend_from_slice(&fp_prev);
            // Step to t_{j+1}.
            for a in 0..na {
                fp_step[a] = stacks[a].active_force(hist_v[a][j + 1], hist_h[a][j + 1]);
            }
            // Energy by the midpoint rule, which the trapezoidal scheme balances exactly:
            // the system's dissipation Σ Δt·v̄ᵀ·C·v̄ is kept by the integrator (read once a
            // period); the beam's is that minus the links' dampers, C = C_beam + Σ c_l·g_l·g_lᵀ.
            nm.step_weighted(&fp_step);
            let mut d_links = 0.0;
            let mut w_beam = 0.0;
            for (l, lk) in sys.links.iter().enumerate() {
                let new = link_state(&nm, l, lk, &fp_step);
                let old = &links_now[l];
                let ud_mid = 0.5 * (old.ud + new.ud);
                d_links += dt * lk.c * ud_mid * ud_mid;
                w_beam += dt * 0.5 * (old.fi + new.fi) * 0.5 * (old.fv + new.fv);
                links_now[l] = new;
            }
            let mut w_sys = 0.0;
            for a in 0..sys.drives.len() {
                let gv = drive_rate(&nm, a);
                w_sys += dt * 0.5 * (fp_prev[a] + fp_step[a]) * 0.5 * (drive_v[a] + gv);
                drive_v[a] = gv;
            }
            fp_prev.copy_from_slice(&fp_step);
            pb.beam.input += w_beam;
            pb.beam.dissipated -= d_links;
            pb.system.input += w_sys;
        }
        let d_sys = nm.dissipated() - d_sys0;
        pb.system.dissipated = d_sys;
        pb.beam.dissipated += d_sys;
        for a in 0..na {
            rec.v[a].extend_from_slice(&hist_v[a][..n_per]);
            rec.h[a].extend_from_slice(&hist_h[a][..n_per]);
        }
        rec.t.extend_from_slice(&times[..n_per]);
        if n_obs > 0 {
            let samples = || snap.chunks_exact(n_obs);
            for l in 0..nl {
                let (s, f) = (2 * l, 2 * l + 1);
                rec.u[l].extend(samples().map(|o| o[s][0]));
                rec.ud[l].extend(samples().map(|o| o[s][1]));
                rec.fv[l].extend(samples().map(|o| o[f][1]));
                rec.fa[l].extend(samples().map(|o| o[f][2]));
            }
            for b in 0..body_dofs.len() {
                for (q, series) in [&mut rec.q[b], &mut rec.qd[b], &mut rec.qdd[b]].into_iter().enumerate() {
                    series.extend(samples().map(|o| o[body_row + b][q]));
                }
            }
            for si in 0..sensor_dofs.len() {
                for (q, series) in [&mut rec.sw[si], &mut rec.sv[si], &mut rec.sa[si]].into_iter().enumerate() {
                    series.extend(samples().map(|o| o[sensor_row + si][q]));
                }
            }
        }
        if na > 0 {
            for (a, series) in rec.fp.iter_mut().enumerate() {
                series.extend(fp_snap.chunks_exact(na).map(|f| f[a]));
            }
        }
        let (eb1, es1) = stored(&nm);
        e_boundary = (eb1, es1);
        pb.beam.stored_change = eb1 - eb0;
        pb.system.stored_change = es1 - es0;
        for (acc, x) in [(&mut run_bal.beam, &pb.beam), (&mut run_bal.system, &pb.system)] {
            acc.input += x.input;
            acc.dissipated += x.dissipated;
        }
        per_bal = pb;
        periods_run = p + 1;
        // Steady-state metrics: mean power and RMS transmitted force per link.
        let mut metrics = Vec::with_capacity(2 * nl);
        for l in 0..nl {
            let lk = &sys.links[l];
            let ft: Vec<f64> = (0..n_per)
                .map(|j| {
                    lk.k * rec.u[l][j] + lk.c * rec.ud[l][j] - if lk.active { rec.fp[lk.actuator][j] } else { 0.0 }
                })
                .collect();
            let fi: Vec<f64> = ft.iter().zip(&rec.fa[l]).map(|(x, a)| x - lk.foot_mass * a).collect();
            metrics.push(mean_product(&fi, &rec.fv[l]));
            metrics.push((mean_product(&ft, &ft)).sqrt());
        }
        window.push_back(rec);
        if let Some(prev) = &prev_metrics {
            let pscale = metrics.iter().step_by(2).fold(0.0f64, |m, x| m.max(x.abs()));
            let fscale = metrics.iter().skip(1).step_by(2).fold(0.0f64, |m, x| m.max(x.abs()));
            let mut change = 0.0f64;
            for (k, (a, b)) in metrics.iter().zip(prev).enumerate() {
                let scale = if k % 2 == 0 { pscale } else { fscale };
                if scale > 0.0 {
                    change = change.max((a - b).abs() / scale);
                }
            }
            final_change = change;
            if periodic && s.steady_state && change < s.tolerance && periods_run >= min_periods {
                converged = true;
                if s.periods.is_none() {
                    break;
                }
            }
        }
        prev_metrics = Some(metrics);
    }
    let (eb_end, es_end) = e_boundary;
    run_bal.beam.stored_change = eb_end - eb_start;
    run_bal.system.stored_change = es_end - es_start;

    // Assemble the recorded window.
    let mut all = PeriodRecord::new(nl, body_dofs.len(), na, model.sensors.len(), window.len() * n_per);
    for r in &window {
        all.append(r);
    }
    let last = window.back().expect("at least one period");
    let mut result = TransientResult {
        dt,
        period,
        steps_per_period: n_per,
        periods_run,
        steps_run: periods_run * n_per,
        converged,
        final_change,
        t: all.t.clone(),
        energy_run: run_bal,
        energy_last_period: per_bal,
        ..Default::default()
    };
    result.beam_dissipation = per_bal.beam.dissipated / period;
    result.beam_input_power = per_bal.beam.input / period;
    let omega0 = 2.0 * std::f64::consts::PI / period;
    for (l, lk) in sys.links.iter().enumerate() {
        let series = |r: &PeriodRecord| {
            let mut ls =
                LinkSeries { actuator: lk.actuator, name: lk.name.clone(), foot_x: lk.foot_x, ..Default::default() };
            for j in 0..r.t.len() {
                let (u, ud) = (r.u[l][j], r.ud[l][j]);
                let fpz = if lk.active { -r.fp[lk.actuator][j] } else { 0.0 };
                let ft = lk.k * u + lk.c * ud + fpz;
                let fi = ft - lk.foot_mass * r.fa[l][j];
                ls.stretch.push(u);
                ls.stretch_rate.push(ud);
                ls.f_stiffness.push(lk.k * u);
                ls.f_damping.push(lk.c * ud);
                ls.f_pzt.push(fpz);
                ls.transmitted.push(ft);
                ls.interface.push(fi);
                ls.base_velocity.push(r.fv[l][j]);
                ls.base_acceleration.push(r.fa[l][j]);
                ls.power.push(fi * r.fv[l][j]);
            }
            ls
        };
        let lp = series(last);
        let fh = harmonics(&lp.transmitted);
        let ih = harmonics(&lp.interface);
        let vh = harmonics(&lp.base_velocity);
        let ah = harmonics(&lp.base_acceleration);
        let pv = power_per_harmonic(&ih, &vh, n_per);
        let pa = power_from_acceleration(&ih, &ah, omega0, n_per);
        let hmax = s.harmonics.min(fh.len() - 1);
        result.mean_power.push(mean_product(&lp.interface, &lp.base_velocity));
        result.spectra.push(LinkSpectrum {
            frequency: (0..=hmax).map(|k| k as f64 / period).collect(),
            transmitted: fh[..=hmax].to_vec(),
            interface: ih[..=hmax].to_vec(),
            velocity: vh[..=hmax].to_vec(),
            acceleration: ah[..=hmax].to_vec(),
            power: pv[..=hmax].to_vec(),
            power_from_acceleration: pa[..=hmax].to_vec(),
            power_total: pv.iter().sum(),
        });
        result.links.push(series(&all));
    }
    result.net_power = (0..na)
        .map(|a| sys.links.iter().zip(&result.mean_power).filter(|(lk, _)| lk.actuator == a).map(|(_, p)| p).sum())
        .collect();
    for (b, (a, name, _)) in body_dofs.iter().enumerate() {
        result.bodies.push(BodySeries {
            actuator: *a,
            dof: name.clone(),
            q: all.q[b].clone(),
            q_dot: all.qd[b].clone(),
            q_ddot: all.qdd[b].clone(),
        });
    }
    for (a, stack) in stacks.iter().enumerate() {
        let d_p = stack.hysteresis.d_p;
        result.drives.push(DriveSeries {
            actuator: a,
            voltage: all.v[a].clone(),
            h: all.h[a].clone(),
            stroke: all.v[a].iter().zip(&all.h[a]).map(|(v, h)| d_p * v - h).collect(),
            f_p: all.fp[a].clone(),
        });
    }
    for (si, se) in model.sensors.iter().enumerate() {
        result.sensors.push(SensorSeries {
            name: se.name.clone(),
            x: se.x,
            w: all.sw[si].clone(),
            v: all.sv[si].clone(),
            a: all.sa[si].clone(),
        });
    }
    Ok(result)
}
