//! When a periodic run has reached its steady state.
//!
//! The criterion: after each period, the mean power at every interface point and the RMS
//! of every transmitted force are compared with the previous period's, each change relative
//! to the largest of its kind; the run has settled when the largest change is below the
//! tolerance. (Lightly damped modes beat against the drive, so neighbouring periods can
//! agree while the mean is still off; a settling estimate that sees the beat would replace
//! [`SettleCheck`] behind the same two calls: [`SettleCheck::settled_after`] after each
//! period, [`SettleCheck::change`] for the result.)

use super::record::PeriodRecord;
use crate::assembly::LinkDofs;
use crate::power::point::mean_product;

/// The steady-state check of a run, period by period.
pub(super) struct SettleCheck {
    tolerance: f64,
    previous: Option<Vec<f64>>,
    change: f64,
}

impl SettleCheck {
    /// A check that the run has settled to `tolerance` (relative change between periods).
    pub fn new(tolerance: f64) -> Self {
        SettleCheck { tolerance, previous: None, change: f64::NAN }
    }

    /// Takes the record of the period just run (`links` the system's links): whether it
    /// agrees with the period before to the tolerance (never after the first period).
    pub fn settled_after(&mut self, links: &[LinkDofs], rec: &PeriodRecord) -> bool {
        let metrics = period_metrics(links, rec);
        let settled = match &self.previous {
            Some(prev) => {
                self.change = relative_change(&metrics, prev);
                self.change < self.tolerance
            }
            None => false,
        };
        self.previous = Some(metrics);
        settled
    }

    /// The relative change between the last two periods (NaN after one period).
    pub fn change(&self) -> f64 {
        self.change
    }
}

/// Per link, the mean interface power (W) and the RMS transmitted force (N) over the
/// period: [P₀, F₀, P₁, F₁, …].
fn period_metrics(links: &[LinkDofs], rec: &PeriodRecord) -> Vec<f64> {
    let mut metrics = Vec::with_capacity(2 * links.len());
    for (l, lk) in links.iter().enumerate() {
        let ls = rec.link_series(l, lk);
        metrics.push(mean_product(&ls.interface, &ls.base_velocity));
        metrics.push(mean_product(&ls.transmitted, &ls.transmitted).sqrt());
    }
    metrics
}

/// The largest change of a metric between two periods, relative to the largest metric of
/// its kind (powers, forces) in the newer period.
fn relative_change(metrics: &[f64], prev: &[f64]) -> f64 {
    let pscale = metrics.iter().step_by(2).fold(0.0f64, |m, x| m.max(x.abs()));
    let fscale = metrics.iter().skip(1).step_by(2).fold(0.0f64, |m, x| m.max(x.abs()));
    let mut change = 0.0f64;
    for (k, (a, b)) in metrics.iter().zip(prev).enumerate() {
        let scale = if k % 2 == 0 { pscale } else { fscale };
        if scale > 0.0 {
            change = change.max((a - b).abs() / scale);
        }
    }
    change
}
