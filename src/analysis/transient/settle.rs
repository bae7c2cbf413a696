//! When a periodic run has reached its steady state.
//!
//! Lightly damped modes beat against the drive, so two neighbouring periods can agree while
//! the mean power is still several per cent off (mode 1 at 49.9 Hz against 60 Hz: about 19
//! periods per beat, decaying by 5 % a period). So the run is compared with the exact
//! periodic state of the same discrete system ([`super::reference`]): after each period the
//! mean power at every interface point and point load and the RMS of every transmitted
//! force are compared with that state's, each difference relative to that point's own
//! power or force (a power below [`SMALL_POWER`](crate::power::point::SMALL_POWER) of the largest: relative to that fraction
//! of the largest), and the run has settled when every point is within the tolerance.
//!
//! The largest of those distances is the stated `settling_estimate`, and it bounds the
//! error of every point's power against the exact periodic state of the discrete system.
//! The distance is measured, not extrapolated from the change between periods, so the only
//! gap between it and that error is what the measurement cannot see, a relative margin δ:
//! with d the distance of a point from the reference r, the error is at most
//! (d + δ)/(1 − δ), the estimate stated. What δ holds:
//! - on a fine mesh whose steps use the element rows, the refined reference's own bound
//!   (`reference::Reference::bound`) and the N·ε of each of the two means of N samples
//!   (ε the machine epsilon): the run's round-off is part of the measured distance;
//! - otherwise twice the mesh's measured envelope of round-off
//!   ([`crate::analysis::roundoff::envelope`]) and the means' N·ε, the reference and the run
//!   each carrying it.
//!
//! A tolerance below 2δ cannot be told from round-off; the run then stops at 2δ and states
//! its estimate.
//!
//! The change between neighbouring periods is kept too, for non-periodic drives (which
//! have no periodic state) and as a diagnostic.

use super::record::PeriodRecord;
use crate::assembly::LinkDofs;
use crate::power::point::{largest_relative, mean_product, own_scales};

/// The steady-state check of a run, period by period.
pub(super) struct SettleCheck {
    tolerance: f64,
    /// The periodic state's metrics, when the drive has one.
    reference: Option<Metrics>,
    /// The relative margin δ for the reference's and the run's round-off.
    margin: f64,
    previous: Option<Metrics>,
    change: f64,
    remaining: f64,
    /// `remaining` after each period so far.
    history: Vec<f64>,
}

impl SettleCheck {
    /// A check that the run has settled to `tolerance` (relative), against the periodic
    /// state's metrics `reference` ([`period_metrics`] of it), with the relative `margin`
    /// δ for what the measured distance cannot see, or, without one, between neighbouring
    /// periods.
    pub fn new(tolerance: f64, reference: Option<Metrics>, margin: f64) -> Self {
        SettleCheck {
            tolerance,
            reference,
            margin,
            previous: None,
            change: f64::NAN,
            remaining: f64::NAN,
            history: Vec::new(),
        }
    }

    /// Takes the record of the period just run (`links` the system's links): whether the
    /// run has settled to the tolerance.
    pub fn settled_after(&mut self, links: &[LinkDofs], rec: &PeriodRecord) -> bool {
        let metrics = period_metrics(links, rec);
        if let Some(prev) = &self.previous {
            self.change = relative_change(&metrics, prev);
        }
        let settled = match &self.reference {
            Some(r) => {
                self.remaining = (relative_change(&metrics, r) + self.margin) / (1.0 - self.margin);
                self.history.push(self.remaining);
                // No comparison resolves less than its round-off: a tolerance below twice
                // the margin is held at that.
                self.remaining < self.tolerance.max(2.0 * self.margin)
            }
            None => self.previous.is_some() && self.change < self.tolerance,
        };
        self.previous = Some(metrics);
        settled
    }

    /// The relative change between the last two periods (NaN after one period).
    pub fn change(&self) -> f64 {
        self.change
    }

    /// The remaining start-up transient of the last period: the largest relative distance
    /// of a point from the periodic state, with the round-off margin (NaN without one).
    pub fn remaining(&self) -> f64 {
        self.remaining
    }

    /// About how many periods in all the run would need to settle, from the decay of its
    /// distance over the last periods; None where fewer than [`DECAY_PERIODS`] ran against
    /// a periodic state, or the distance does not decay there.
    pub fn periods_needed(&self) -> Option<usize> {
        periods_to_reach(&self.history, self.tolerance.max(2.0 * self.margin))
    }
}

/// The fewest periods whose decay [`periods_to_reach`] measures.
pub const DECAY_PERIODS: usize = 20;

/// Periods in all until `distance` (one entry per period so far) falls below `target`, at
/// the rate it decays over its last 40 %: the peaks of that span's two halves (a lightly
/// damped mode beats against the drive, so the distance rises and falls within a beat),
/// their log-ratio per period, extrapolated from the later peak as if it were the last
/// period (the later peak is at most the last value's envelope: a conservative start).
pub fn periods_to_reach(distance: &[f64], target: f64) -> Option<usize> {
    let n = distance.len();
    if n < DECAY_PERIODS || !(target > 0.0) {
        return None;
    }
    let half = n / 5;
    let peak = |d: &[f64]| d.iter().fold(0.0f64, |a, &b| a.max(b));
    let (early, late) = (peak(&distance[n - 2 * half..n - half]), peak(&distance[n - half..]));
    if !(late > 0.0 && late < early) {
        return None;
    }
    let rate = (early / late).ln() / half as f64;
    let more = ((late / target).ln() / rate).ceil().max(0.0);
    // Beyond any count a run could take, the answer is "far more", not a number.
    (more < 1e9).then(|| n + more as usize)
}

/// What a period is judged by: the mean power at each interface point, then at each point
/// load (W), and the RMS transmitted force of each link (N).
#[derive(Clone, Debug, Default, PartialEq)]
pub(super) struct Metrics {
    pub powers: Vec<f64>,
    pub forces: Vec<f64>,
}

/// The metrics of a period's record.
pub(super) fn period_metrics(links: &[LinkDofs], rec: &PeriodRecord) -> Metrics {
    let mut m = Metrics::default();
    for (l, lk) in links.iter().enumerate() {
        let (transmitted, interface) = rec.link_forces(l, lk);
        m.powers.push(mean_product(&interface, &rec.fv[l]));
        m.forces.push(mean_product(&transmitted, &transmitted).sqrt());
    }
    for (f, v) in rec.lf.iter().zip(&rec.lv) {
        m.powers.push(mean_product(f, v));
    }
    m
}

/// The largest change of a metric between `metrics` and `base` (a newer period against an
/// older one, or against the periodic state), each relative to its own size in `base`
/// ([`own_scales`] of its kind: powers, forces).
fn relative_change(metrics: &Metrics, base: &Metrics) -> f64 {
    let kind = |now: &[f64], base: &[f64]| largest_relative(now, base, &own_scales(base));
    kind(&metrics.powers, &base.powers).max(kind(&metrics.forces, &base.forces))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A distance decaying as e^{−0.05 p}, beating (|cos| of a 12-period beat, never below
    /// a tenth of its envelope): the periods it needs to reach 1e-4 are predicted at or
    /// beyond the first period whose envelope is below it, and within 10 % of it; a
    /// distance that does not decay, or too short a run, predicts nothing.
    #[test]
    fn the_decay_over_the_last_periods_predicts_the_periods_needed() {
        let envelope = |p: f64| 0.5 * (-0.05 * p).exp();
        let d: Vec<f64> = (0..100)
            .map(|p| envelope(p as f64) * (0.1 + 0.9 * (std::f64::consts::PI * p as f64 / 12.0).cos().abs()))
            .collect();
        let exact = ((0.5f64 / 1e-4).ln() / 0.05).ceil() as usize;
        let predicted = periods_to_reach(&d, 1e-4).unwrap();
        assert!(predicted >= exact && (predicted as f64) < 1.1 * exact as f64, "{predicted} vs {exact}");
        assert_eq!(periods_to_reach(&vec![1e-2; 100], 1e-4), None);
        assert_eq!(periods_to_reach(&d[..10], 1e-4), None);
    }

    /// A spring link (k = 1000 N/m, no damper, no foot mass) whose stretch and foot velocity
    /// are `u` and `v` at every sample: F_T = k·u, power k·u·v.
    fn period(u: &[f64], v: &[f64]) -> PeriodRecord {
        PeriodRecord {
            t: vec![0.0; u.len()],
            u: vec![u.to_vec()],
            ud: vec![vec![0.0; u.len()]],
            fv: vec![v.to_vec()],
            fa: vec![vec![0.0; u.len()]],
            fp: vec![vec![0.0; u.len()]],
            ..Default::default()
        }
    }

    fn links() -> Vec<LinkDofs> {
        vec![LinkDofs {
            actuator: 0,
            name: "spring".into(),
            k: 1000.0,
            c: 0.0,
            stretch: Vec::new(),
            foot_node: None,
            foot_dof: None,
            foot: Vec::new(),
            foot_at: None,
            foot_mass: 0.0,
            active: false,
        }]
    }

    #[test]
    fn settles_when_power_and_force_repeat_to_the_tolerance() {
        let (u, v) = ([1e-3, -1e-3, 2e-3, 0.0], [0.1, -0.1, 0.2, 0.0]);
        let mut check = SettleCheck::new(1e-3, None, 0.0);
        assert!(!check.settled_after(&links(), &period(&u, &v)), "one period cannot have settled");
        assert!(check.change().is_nan());
        assert!(check.settled_after(&links(), &period(&u, &v)));
        assert_eq!(check.change(), 0.0);
        // The power grows by 1 % (the velocity does), the RMS force stays: change 1e-2 of
        // the power before, not settled at 1e-3.
        let v2 = v.map(|x| 1.01 * x);
        assert!(!check.settled_after(&links(), &period(&u, &v2)));
        assert!((check.change() - 0.01).abs() < 1e-12, "{}", check.change());
    }

    #[test]
    fn against_a_periodic_state_the_distance_decides_not_the_change() {
        let (u, v) = ([1e-3, -1e-3, 2e-3, 0.0], [0.1, -0.1, 0.2, 0.0]);
        let reference = period_metrics(&links(), &period(&u, &v.map(|x| 1.02 * x)));
        let mut check = SettleCheck::new(1e-3, Some(reference), 0.0);
        assert!(!check.settled_after(&links(), &period(&u, &v)));
        // Two identical periods 2 % from the periodic state: the change is zero, the
        // remaining transient is not, and the run has not settled.
        assert!(!check.settled_after(&links(), &period(&u, &v)));
        assert_eq!(check.change(), 0.0);
        assert!((check.remaining() - 0.02 / 1.02).abs() < 1e-12, "{}", check.remaining());
        assert!(check.settled_after(&links(), &period(&u, &v.map(|x| 1.02 * x))));
    }

    /// Two links, one carrying a hundredth of the other's power: each is judged against its
    /// own power, so the small one's 1 % keeps the run from settling although it is 1e-4
    /// of the largest; the margin for round-off is added to the distance.
    #[test]
    fn every_point_is_judged_against_its_own_power() {
        let (u, v) = ([1e-3, -1e-3, 2e-3, 0.0], [0.1, -0.1, 0.2, 0.0]);
        let two = |small: f64| {
            let mut rec = period(&u, &v);
            rec.u.push(u.to_vec());
            rec.ud.push(vec![0.0; 4]);
            rec.fv.push(v.map(|x| small * x).to_vec());
            rec.fa.push(vec![0.0; 4]);
            rec.fp.push(vec![0.0; 4]);
            rec
        };
        let links = [links(), links()].concat();
        let reference = period_metrics(&links, &two(0.01));
        let mut check = SettleCheck::new(1e-3, Some(reference), 2e-6);
        assert!(!check.settled_after(&links, &two(0.0101)));
        let expected = (0.01 + 2e-6) / (1.0 - 2e-6);
        assert!((check.remaining() - expected).abs() < 1e-12, "{}", check.remaining());
        assert!(check.settled_after(&links, &two(0.01)));
        assert!((check.remaining() - 2e-6 / (1.0 - 2e-6)).abs() < 1e-15, "{}", check.remaining());
    }
}
