//! Stepping through one period: the stacks' forces of the period computed up front
//! ([`StackHistories`]), the integrator advanced step by step, and the energy each step
//! brings in and dissipates, by the midpoint rule the trapezoidal scheme balances exactly
//! ([`Stepper`], [`EnergyLedger`]).

use super::readout::Readout;
use crate::actuator::Stack;
use crate::analysis::drive::DriveTiming;
use crate::analysis::series::Balances;
use crate::assembly::{LinkDofs, Model, System};
use crate::error::Result;
use crate::power::energy::{StoredEnergy, StrainEnergy};
use crate::power::link::{interface_force, transmitted_force};
use crate::power::point::{damper_dissipation, midpoint_work};
use crate::signal::voltage::VoltageInput;
use crate::solve::band_newmark::BandNewmark;
use std::sync::Arc;

/// The drives over the current period: each stack's voltage and h, and each point load's
/// force, at its N + 1 sample times. F_p depends on the voltage alone, so h is integrated
/// exactly (in voltage space) for the whole period before it is stepped.
pub(super) struct StackHistories<'m> {
    pub stacks: Vec<&'m Stack>,
    pub loads: Vec<&'m VoltageInput>,
    /// Each point load's force at `times` (N).
    pub load_f: Vec<Vec<f64>>,
    /// h at the start of the next period, per stack (m).
    h_now: Vec<f64>,
    /// The period's sample times, both ends included (s).
    pub times: Vec<f64>,
    /// Voltage (V) and h (m) at `times`, per stack.
    pub v: Vec<Vec<f64>>,
    pub h: Vec<Vec<f64>>,
}

impl<'m> StackHistories<'m> {
    pub fn new(model: &'m Model, timing: &DriveTiming) -> Self {
        let stacks: Vec<&Stack> = model.actuators.iter().map(|a| a.stack()).collect();
        let na = stacks.len();
        StackHistories {
            h_now: stacks.iter().map(|st| st.h0).collect(),
            stacks,
            loads: model.loads.iter().map(|l| &l.force).collect(),
            load_f: vec![Vec::new(); model.loads.len()],
            times: vec![0.0; timing.steps_per_period + 1],
            v: vec![Vec::new(); na],
            h: vec![Vec::new(); na],
        }
    }

    /// F_p of each stack at t = 0 (N).
    pub fn initial_forces(&self) -> Vec<f64> {
        self.stacks
            .iter()
            .zip(&self.h_now)
            .map(|(st, &h)| st.active_force(st.voltage.value(0.0), if st.hysteresis_on { h } else { 0.0 }))
            .collect()
    }

    /// The integrator's load weights at t = 0: each F_p (N), then each point load (N).
    pub fn initial_weights(&self) -> Vec<f64> {
        let mut w = self.initial_forces();
        w.extend(self.loads.iter().map(|f| f.value(0.0)));
        w
    }

    /// Fills the histories of period `p` (from p·T).
    pub fn advance(&mut self, p: usize, timing: &DriveTiming) {
        let t0 = p as f64 * timing.period;
        for (j, t) in self.times.iter_mut().enumerate() {
            *t = t0 + j as f64 * timing.dt;
        }
        let n = timing.steps_per_period;
        for (a, st) in self.stacks.iter().enumerate() {
            let (hv, hh) = (&mut self.v[a], &mut self.h[a]);
            if st.hysteresis_on {
                st.hysteresis.history_into(&st.voltage, &self.times, self.h_now[a], hh, hv);
            } else {
                hv.clear();
                hv.extend(self.times.iter().map(|&t| st.voltage.value(t)));
                hh.clear();
                hh.resize(self.times.len(), 0.0);
            }
            self.h_now[a] = hh[n];
        }
        for (f, series) in self.loads.iter().zip(&mut self.load_f) {
            series.clear();
            series.extend(self.times.iter().map(|&t| f.value(t)));
        }
    }

    /// F_p of stack a at sample j of the period (N).
    fn force(&self, a: usize, j: usize) -> f64 {
        self.stacks[a].active_force(self.v[a][j], self.h[a][j])
    }
}

/// A link's state at one instant (SI units).
#[derive(Clone, Copy, Debug)]
struct LinkState {
    /// Stretch rate u̇ (m/s), base velocity at the foot (m/s).
    ud: f64,
    fv: f64,
    /// Interface force on the beam, F_T − m_foot·ẅ (N).
    fi: f64,
}

/// Link l's state from the integrator's current read-outs, F_p of its actuator `f_p` (N).
fn link_state(nm: &BandNewmark, layout: &Readout, l: usize, lk: &LinkDofs, f_p: f64) -> LinkState {
    let (stretch, foot) = (nm.observed()[layout.stretch(l)], nm.observed()[layout.foot(l)]);
    let ft = transmitted_force(lk, stretch[0], stretch[1], f_p);
    LinkState { ud: stretch[1], fv: foot[1], fi: interface_force(lk, ft, foot[2]) }
}

/// Advances the integrator period by period, keeping what the energy terms of the next
/// step need and the read-outs of the period's steps.
pub(super) struct Stepper {
    dt: f64,
    /// Each link's state, each drive's rate and the stack forces after the latest step:
    /// the start points of the next step's energy terms.
    links_now: Vec<LinkState>,
    drive_v: Vec<f64>,
    fp_prev: Vec<f64>,
    fp_step: Vec<f64>,
    /// The point loads' velocities after the latest step (m/s), and the integrator's load
    /// weights (F_p, then point loads) of the step.
    load_v: Vec<f64>,
    weights: Vec<f64>,
    /// The read-outs and stack forces at the start of each step of the period.
    pub observed: Vec<[f64; 3]>,
    pub f_p: Vec<f64>,
}

impl Stepper {
    /// Starts from the integrator's current state under the stack forces `f_p0` (N).
    pub fn new(nm: &BandNewmark, sys: &System, layout: &Readout, f_p0: &[f64], timing: &DriveTiming) -> Self {
        let n = timing.steps_per_period;
        Stepper {
            dt: timing.dt,
            links_now: sys
                .links
                .iter()
                .enumerate()
                .map(|(l, lk)| link_state(nm, layout, l, lk, f_p0[lk.actuator]))
                .collect(),
            drive_v: (0..layout.drives()).map(|a| nm.observed()[layout.drive(a)][1]).collect(),
            load_v: (0..layout.loads()).map(|j| nm.observed()[layout.load(j)][1]).collect(),
            weights: vec![0.0; f_p0.len() + layout.loads()],
            fp_prev: f_p0.to_vec(),
            fp_step: vec![0.0; f_p0.len()],
            observed: Vec::with_capacity(n * layout.len()),
            f_p: Vec::with_capacity(n * f_p0.len()),
        }
    }

    /// Steps through one period of `stacks`' histories. Returns the work brought into the
    /// beam (interface forces) and into the system (stack forces), and, as the beam's
    /// dissipation so far, minus what the links' dampers took: the integrator keeps the
    /// system's dissipation Σ Δt·v̄ᵀ·C·v̄, and C = C_beam + Σ c_l·g_l·g_lᵀ.
    /// `steps` (a record's task) is told every [`PROGRESS_STEPS`] steps how far it got.
    pub fn period(
        &mut self,
        nm: &mut BandNewmark,
        sys: &System,
        layout: &Readout,
        stacks: &StackHistories,
        steps: Option<&crate::progress::Task>,
    ) -> Result<Balances> {
        let mut pb = Balances::default();
        self.observed.clear();
        self.f_p.clear();
        for j in 0..stacks.times.len() - 1 {
            if let Some(t) = steps.filter(|_| j % PROGRESS_STEPS == 0) {
                t.set(j as u64)?;
            }
            // The state at t_j as it stands, sorted into series once the period is over.
            self.observed.extend_from_slice(nm.observed());
            self.f_p.extend_from_slice(&self.fp_prev);
            let na = self.fp_step.len();
            for (a, f) in self.fp_step.iter_mut().enumerate() {
                *f = stacks.force(a, j + 1);
            }
            self.weights[..na].copy_from_slice(&self.fp_step);
            for (w, f) in self.weights[na..].iter_mut().zip(&stacks.load_f) {
                *w = f[j + 1];
            }
            nm.step_weighted(&self.weights);
            let (mut d_links, mut w_beam) = (0.0, 0.0);
            for (l, lk) in sys.links.iter().enumerate() {
                let new = link_state(nm, layout, l, lk, self.fp_step[lk.actuator]);
                let old = &self.links_now[l];
                d_links += damper_dissipation(self.dt, lk.c, old.ud, new.ud);
                w_beam += midpoint_work(self.dt, old.fi, new.fi, old.fv, new.fv);
                self.links_now[l] = new;
            }
            let mut w_sys = 0.0;
            for a in 0..layout.drives() {
                let gv = nm.observed()[layout.drive(a)][1];
                w_sys += midpoint_work(self.dt, self.fp_prev[a], self.fp_step[a], self.drive_v[a], gv);
                self.drive_v[a] = gv;
            }
            for (l, f) in stacks.load_f.iter().enumerate() {
                let v = nm.observed()[layout.load(l)][1];
                let w = midpoint_work(self.dt, f[j], f[j + 1], self.load_v[l], v);
                w_beam += w;
                w_sys += w;
                self.load_v[l] = v;
            }
            self.fp_prev.copy_from_slice(&self.fp_step);
            pb.beam.input += w_beam;
            pb.beam.dissipated -= d_links;
            pb.system.input += w_sys;
        }
        Ok(pb)
    }
}

/// Steps between progress reports within one period (a non-periodic record is one long
/// period).
const PROGRESS_STEPS: usize = 1024;

/// How many times the energy the start held and the drives put in a run may store before
/// it counts as diverging. Exactly it stores at most that energy (dissipation is never
/// negative); a stable scheme's quadrature of the work is off by far less than this, a
/// diverging one exceeds it by orders of magnitude within a period or two.
pub(super) const RUNAWAY_FACTOR: f64 = 1e3;

/// The two energy balances of a run (beam and system), closed at each period boundary
/// with the stored energies there.
pub(super) struct EnergyLedger {
    energy: StoredEnergy,
    /// Stored energies (beam, system) at the start and at the latest period boundary (J).
    start: (f64, f64),
    boundary: (f64, f64),
    /// The integrator's dissipation at the start of the current period (J).
    dissipated_before: f64,
    /// The work put into the system so far, each period's counted by its magnitude (J).
    supplied: f64,
    pub run: Balances,
    pub last_period: Balances,
}

impl EnergyLedger {
    /// `strain`: the strain energies from element rows (fine meshes), else from K.
    pub fn new(sys: &System, nm: &BandNewmark, strain: Option<Arc<dyn StrainEnergy>>) -> Self {
        let energy = StoredEnergy::new(sys).with_strain(strain);
        let start = energy.beam_and_system(nm.u(), nm.v());
        EnergyLedger {
            energy,
            start,
            boundary: start,
            dissipated_before: 0.0,
            supplied: 0.0,
            run: Balances::default(),
            last_period: Balances::default(),
        }
    }

    /// The system's stored energy at the latest period boundary and the energy it could
    /// hold at most — what it held at the start plus all work put in (J) — when it holds
    /// more than [`RUNAWAY_FACTOR`] times that: energy no drive supplied, which only a
    /// diverging time integration makes.
    pub fn runaway(&self) -> Option<(f64, f64)> {
        let stored = self.boundary.1;
        let supplied = self.start.1 + self.supplied;
        (stored > RUNAWAY_FACTOR * supplied && stored > 0.0).then_some((stored, supplied))
    }

    /// Marks the start of a period.
    pub fn open_period(&mut self, nm: &BandNewmark) {
        self.dissipated_before = nm.dissipated();
    }

    /// Closes the period whose work and link dissipation the stepper returned (`pb`): adds
    /// the system's dissipation and the change of the stored energies.
    pub fn close_period(&mut self, nm: &BandNewmark, mut pb: Balances) {
        let d_sys = nm.dissipated() - self.dissipated_before;
        pb.system.dissipated = d_sys;
        pb.beam.dissipated += d_sys;
        let (eb0, es0) = self.boundary;
        let (eb1, es1) = self.energy.beam_and_system(nm.u(), nm.v());
        self.boundary = (eb1, es1);
        pb.beam.stored_change = eb1 - eb0;
        pb.system.stored_change = es1 - es0;
        for (acc, x) in [(&mut self.run.beam, &pb.beam), (&mut self.run.system, &pb.system)] {
            acc.input += x.input;
            acc.dissipated += x.dissipated;
        }
        self.supplied += pb.system.input.abs();
        self.last_period = pb;
        self.run.beam.stored_change = eb1 - self.start.0;
        self.run.system.stored_change = es1 - self.start.1;
    }
}
