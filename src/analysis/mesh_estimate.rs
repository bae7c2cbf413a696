//! How far a plate's point powers are from converged in its grid: the same analysis on a
//! grid of half the elements each way, compared point by point.
//!
//! Point powers on a plate converge as h² (a frame's stiff legs hold the plate between
//! points a few centimetres apart; the curvature under a point force is singular). Where
//! P_h − P = C·h², Richardson's estimate of the fine grid's error is |P_h − P_2h| / 3; the
//! whole difference |P_h − P_2h| is stated, a threefold margin for a rate that is not yet
//! asymptotic. It is an estimate, not a bound: two grids in the asymptotic range show the
//! rate, no pair of grids proves it (docs/structures.md, "Accuracy").

use serde::Serialize;

/// The observed order of the point powers' convergence on plate grids.
pub const ORDER: f64 = 2.0;

/// The grid a fine grid of `elements` is compared with: half the elements each way, at
/// least one.
pub fn coarser(elements: [usize; 2]) -> [usize; 2] {
    elements.map(|n| n.div_ceil(2).max(1))
}

/// The fine grid's point powers against a coarser grid's, for one analysis.
#[derive(Clone, Debug, Default, Serialize)]
pub struct MeshEstimate {
    /// Elements of the generated grids along x and y, as asked (lines through attachment
    /// points come on top of both).
    pub elements: [usize; 2],
    pub coarse_elements: [usize; 2],
    /// Mean power into the structure per link on the coarser grid (W).
    pub coarse_mean_power: Vec<f64>,
    /// |P_h − P_2h| / |P_h| per link; a link whose power is below 1e-6 of the largest is
    /// measured against that largest instead.
    pub relative_error: Vec<f64>,
    /// The same for each actuator's net power.
    pub net_power_relative_error: Vec<f64>,
    /// The largest of the two lists: the headline estimate.
    pub max_relative_error: f64,
}

impl MeshEstimate {
    /// The estimate from the fine grid's powers `fine` and the coarse grid's `coarse`,
    /// each (mean power per link, net power per actuator) in W.
    pub fn between(elements: [usize; 2], fine: (&[f64], &[f64]), coarse: (&[f64], &[f64])) -> Self {
        let relative_error = relative(fine.0, coarse.0);
        let net_power_relative_error = relative(fine.1, coarse.1);
        let max_relative_error = relative_error.iter().chain(&net_power_relative_error).fold(0.0f64, |a, &b| a.max(b));
        MeshEstimate {
            elements,
            coarse_elements: coarser(elements),
            coarse_mean_power: coarse.0.to_vec(),
            relative_error,
            net_power_relative_error,
            max_relative_error,
        }
    }
}

/// |c − f| / |f| per entry, |f| floored at 1e-6 of the largest |f|.
fn relative(fine: &[f64], coarse: &[f64]) -> Vec<f64> {
    let floor = 1e-6 * fine.iter().fold(0.0f64, |a, p| a.max(p.abs()));
    fine.iter()
        .zip(coarse)
        .map(|(&f, &c)| {
            let d = f.abs().max(floor);
            if d > 0.0 {
                (c - f).abs() / d
            } else {
                (c - f).abs()
            }
        })
        .collect()
}

/// A result's mesh estimate, or why it has none.
#[derive(Clone, Debug, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum MeshCheck {
    Estimate(MeshEstimate),
    NotEstimated(String),
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn halves_each_side_rounding_up() {
        assert_eq!(coarser([20, 16]), [10, 8]);
        assert_eq!(coarser([5, 1]), [3, 1]);
    }

    /// A quantity converging as C·h²: the stated difference is three times the fine grid's
    /// actual error, per point and for the net power; a tiny point is measured against the
    /// largest.
    #[test]
    fn the_difference_is_three_times_the_error_of_an_h2_quantity() {
        let exact = [2.0, -1.0, 1e-9];
        let at = |h: f64| exact.map(|p| p * (1.0 + 0.5 * h * h));
        let (fine, coarse) = (at(0.1), at(0.2));
        let e = MeshEstimate::between([10, 10], (&fine, &[fine[0] + fine[1]]), (&coarse, &[coarse[0] + coarse[1]]));
        for l in 0..2 {
            let actual = (fine[l] - exact[l]).abs() / fine[l].abs();
            assert!((e.relative_error[l] / actual - 3.0).abs() < 1e-9, "{} vs {actual}", e.relative_error[l]);
        }
        assert!(e.relative_error[2] < 1e-5, "a tiny point against the largest: {}", e.relative_error[2]);
        assert!((e.max_relative_error - e.relative_error[0]).abs() < 1e-15);
        assert_eq!(e.coarse_elements, [5, 5]);
    }
}
