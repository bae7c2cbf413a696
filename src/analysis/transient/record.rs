//! What a run records: each period's raw channels ([`PeriodRecord`]), sorted from the
//! read-outs once the period is over, the window of periods kept for output ([`Window`]),
//! and the result series built from it.

use super::readout::Readout;
use crate::actuator::Stack;
use crate::analysis::series::{BodySeries, DriveSeries, LinkSeries, LoadSeries, SensorSeries};
use crate::assembly::{LinkDofs, Model};
use crate::power::link::{interface_force, pzt_force, transmitted_force};
use std::collections::VecDeque;

/// Per-sample raw channels of one period (or of a window of periods).
#[derive(Clone, Default)]
pub(super) struct PeriodRecord {
    pub t: Vec<f64>,
    /// [link] → samples: stretch, its rate, base velocity and acceleration at the foot.
    pub u: Vec<Vec<f64>>,
    pub ud: Vec<Vec<f64>>,
    pub fv: Vec<Vec<f64>>,
    pub fa: Vec<Vec<f64>>,
    /// [body dof] → samples
    pub q: Vec<Vec<f64>>,
    pub qd: Vec<Vec<f64>>,
    pub qdd: Vec<Vec<f64>>,
    /// [actuator] → samples: voltage, h, F_p.
    pub v: Vec<Vec<f64>>,
    pub h: Vec<Vec<f64>>,
    pub fp: Vec<Vec<f64>>,
    /// [sensor] → samples
    pub sw: Vec<Vec<f64>>,
    pub sv: Vec<Vec<f64>>,
    pub sa: Vec<Vec<f64>>,
    /// [point load] → samples: force, and w, ẇ, ẅ at its point.
    pub lf: Vec<Vec<f64>>,
    pub lw: Vec<Vec<f64>>,
    pub lv: Vec<Vec<f64>>,
    pub la: Vec<Vec<f64>>,
}

impl PeriodRecord {
    /// Empty channels for the quantities of `layout`, each with room for `cap` samples.
    fn new(layout: &Readout, cap: usize) -> Self {
        // Not vec![Vec::with_capacity(cap); k]: clones of a Vec do not keep its capacity.
        let mk = |k: usize| (0..k).map(|_| Vec::with_capacity(cap)).collect::<Vec<Vec<f64>>>();
        let (nl, nb, na, ns) = (layout.links(), layout.bodies.len(), layout.drives(), layout.sensors());
        let np = layout.loads();
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
            lf: mk(np),
            lw: mk(np),
            lv: mk(np),
            la: mk(np),
        }
    }

    fn channels_mut(&mut self) -> [&mut Vec<Vec<f64>>; 17] {
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
            &mut self.lf,
            &mut self.lw,
            &mut self.lv,
            &mut self.la,
        ]
    }

    fn channels(&self) -> [&Vec<Vec<f64>>; 17] {
        [
            &self.u, &self.ud, &self.fv, &self.fa, &self.q, &self.qd, &self.qdd, &self.v, &self.h, &self.fp, &self.sw,
            &self.sv, &self.sa, &self.lf, &self.lw, &self.lv, &self.la,
        ]
    }

    /// Empties every series, keeping the buffers.
    fn clear(&mut self) {
        self.t.clear();
        for ch in self.channels_mut() {
            ch.iter_mut().for_each(Vec::clear);
        }
    }

    /// Keeps the samples whose step index in the run (`first` for this period's first) is a
    /// multiple of `every`.
    fn thin(&mut self, first: usize, every: usize) {
        let kept = |v: &mut Vec<f64>| {
            let mut i = 0;
            v.retain(|_| {
                i += 1;
                (first + i - 1) % every == 0
            });
        };
        kept(&mut self.t);
        for ch in self.channels_mut() {
            ch.iter_mut().for_each(kept);
        }
    }

    fn append(&mut self, o: &PeriodRecord) {
        self.t.extend(&o.t);
        for (a, b) in self.channels_mut().into_iter().zip(o.channels()) {
            for (x, y) in a.iter_mut().zip(b) {
                x.extend(y);
            }
        }
    }

    /// Stores the drives of a period: sample times, each stack's voltage and h, the stack
    /// forces F_p as they stood at each sample (`f_p`: one block of one value per actuator
    /// per sample), and each point load's force (`loads`, at least as long as `t`).
    pub fn store_drives(&mut self, t: &[f64], v: &[Vec<f64>], h: &[Vec<f64>], f_p: &[f64], loads: &[Vec<f64>]) {
        let n = t.len();
        for (series, f) in self.lf.iter_mut().zip(loads) {
            series.extend_from_slice(&f[..n]);
        }
        self.t.extend_from_slice(t);
        for (a, (va, ha)) in v.iter().zip(h).enumerate() {
            self.v[a].extend_from_slice(&va[..n]);
            self.h[a].extend_from_slice(&ha[..n]);
        }
        let na = self.fp.len();
        if na > 0 {
            for (a, series) in self.fp.iter_mut().enumerate() {
                series.extend(f_p.chunks_exact(na).map(|f| f[a]));
            }
        }
    }

    /// Sorts a period's read-outs (one block of `layout.len()` rows per sample) into the
    /// link, body and sensor channels.
    pub fn store_readouts(&mut self, layout: &Readout, observed: &[[f64; 3]]) {
        if layout.len() == 0 {
            return;
        }
        let samples = || observed.chunks_exact(layout.len());
        for l in 0..layout.links() {
            let (s, f) = (layout.stretch(l), layout.foot(l));
            self.u[l].extend(samples().map(|o| o[s][0]));
            self.ud[l].extend(samples().map(|o| o[s][1]));
            self.fv[l].extend(samples().map(|o| o[f][1]));
            self.fa[l].extend(samples().map(|o| o[f][2]));
        }
        for b in 0..layout.bodies.len() {
            let row = layout.body(b);
            for (q, series) in [&mut self.q[b], &mut self.qd[b], &mut self.qdd[b]].into_iter().enumerate() {
                series.extend(samples().map(|o| o[row][q]));
            }
        }
        for s in 0..layout.sensors() {
            let row = layout.sensor(s);
            for (q, series) in [&mut self.sw[s], &mut self.sv[s], &mut self.sa[s]].into_iter().enumerate() {
                series.extend(samples().map(|o| o[row][q]));
            }
        }
        for j in 0..layout.loads() {
            let row = layout.load(j);
            for (q, series) in [&mut self.lw[j], &mut self.lv[j], &mut self.la[j]].into_iter().enumerate() {
                series.extend(samples().map(|o| o[row][q]));
            }
        }
    }

    /// Link l's transmitted and interface forces (N) at each sample (`lk` its DOFs).
    pub fn link_forces(&self, l: usize, lk: &LinkDofs) -> (Vec<f64>, Vec<f64>) {
        let n = self.u[l].len();
        let (mut transmitted, mut interface) = (Vec::with_capacity(n), Vec::with_capacity(n));
        let samples = self.u[l].iter().zip(&self.ud[l]).zip(&self.fa[l]).zip(&self.fp[lk.actuator]);
        for (((&u, &ud), &fa), &fp) in samples {
            let ft = transmitted_force(lk, u, ud, fp);
            transmitted.push(ft);
            interface.push(interface_force(lk, ft, fa));
        }
        (transmitted, interface)
    }

    /// Link l's series: the stretch and the base motion recorded, the forces from them.
    pub fn link_series(&self, l: usize, lk: &LinkDofs) -> LinkSeries {
        let (transmitted, interface) = self.link_forces(l, lk);
        let series = LinkSeries {
            stretch: self.u[l].clone(),
            stretch_rate: self.ud[l].clone(),
            f_pzt: self.fp[lk.actuator].iter().map(|&f| pzt_force(lk, f)).collect(),
            transmitted,
            interface,
            base_velocity: self.fv[l].clone(),
            base_acceleration: self.fa[l].clone(),
            ..LinkSeries::of(lk)
        };
        series.complete(lk)
    }

    /// Moves the body, drive and sensor channels out into their result series.
    pub fn into_series(
        mut self,
        model: &Model,
        layout: &Readout,
        stacks: &[&Stack],
    ) -> (Vec<BodySeries>, Vec<DriveSeries>, Vec<SensorSeries>, Vec<LoadSeries>) {
        let take = std::mem::take::<Vec<f64>>;
        let bodies = layout
            .bodies
            .iter()
            .enumerate()
            .map(|(b, dof)| BodySeries {
                actuator: dof.actuator,
                dof: dof.name.to_string(),
                q: take(&mut self.q[b]),
                q_dot: take(&mut self.qd[b]),
                q_ddot: take(&mut self.qdd[b]),
            })
            .collect();
        let drives = stacks
            .iter()
            .enumerate()
            .map(|(a, st)| {
                DriveSeries::new(a, &st.hysteresis, take(&mut self.v[a]), take(&mut self.h[a]), take(&mut self.fp[a]))
            })
            .collect();
        let sensors = model
            .sensors
            .iter()
            .enumerate()
            .map(|(s, se)| SensorSeries {
                name: se.name.clone(),
                x: se.at.x(),
                y: se.at.y(),
                at: Some(se.at),
                w: take(&mut self.sw[s]),
                v: take(&mut self.sv[s]),
                a: take(&mut self.sa[s]),
            })
            .collect();
        let loads = model
            .loads
            .iter()
            .enumerate()
            .map(|(j, l)| LoadSeries {
                name: l.name.clone(),
                x: l.at.x(),
                y: l.at.y(),
                at: Some(l.at),
                force: take(&mut self.lf[j]),
                w: take(&mut self.lw[j]),
                v: take(&mut self.lv[j]),
                a: take(&mut self.la[j]),
            })
            .collect();
        (bodies, drives, sensors, loads)
    }
}

/// The periods kept for output: the last `keep`, the oldest recycled (its buffers keep
/// their capacity). Behind the newest `whole` periods, a period keeps only the steps whose
/// index in the run is a multiple of `every` (a long history thinned, its end whole).
pub(super) struct Window {
    records: VecDeque<PeriodRecord>,
    keep: usize,
    samples: usize,
    whole: usize,
    every: usize,
    /// Periods pushed so far (the run's period index of the next one).
    pushed: usize,
}

impl Window {
    /// A window of `keep` periods of `samples` samples, the newest `whole` of them whole
    /// and the older ones every `every`-th step.
    pub fn new(keep: usize, samples: usize, (whole, every): (usize, usize)) -> Self {
        Window { records: VecDeque::new(), keep, samples, whole, every: every.max(1), pushed: 0 }
    }

    /// An empty record for the next period: the oldest of a full window, or a new one.
    pub fn next_record(&mut self, layout: &Readout) -> PeriodRecord {
        if self.records.len() >= self.keep {
            let mut old = self.records.pop_front().expect("a full window");
            old.clear();
            old
        } else {
            PeriodRecord::new(layout, self.samples)
        }
    }

    pub fn push(&mut self, rec: PeriodRecord) {
        self.records.push_back(rec);
        self.pushed += 1;
        // The period that has just left the whole tail is thinned, once.
        if self.every > 1 && self.records.len() > self.whole {
            let index = self.records.len() - 1 - self.whole;
            let first = (self.pushed - 1 - self.whole) * self.samples;
            self.records[index].thin(first, self.every);
        }
    }

    /// The kept periods as one record.
    pub fn joined(&self, layout: &Readout) -> PeriodRecord {
        let mut all = PeriodRecord::new(layout, self.records.len() * self.samples);
        for r in &self.records {
            all.append(r);
        }
        all
    }
}
