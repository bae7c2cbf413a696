//! How far a plate's point powers are from converged in its grid: the same analysis on a
//! grid of half the elements each way, compared point by point.
//!
//! Point powers on a plate converge as h² (a frame's stiff legs hold the plate between
//! points a few centimetres apart; the curvature under a point force is singular). Where
//! P_h − P = C·h², Richardson's estimate of the fine grid's error is |P_h − P_2h| / 3; the
//! whole difference |P_h − P_2h| is stated, a threefold margin for a rate that is not yet
//! asymptotic. It is an estimate, not a bound: two grids in the asymptotic range show the
//! rate, no pair of grids proves it (docs/structures.md, "Accuracy").

use crate::power::point::relative_to_own;
use serde::Serialize;

/// The observed order of the point powers' convergence on plate grids.
pub const ORDER: f64 = 2.0;

/// The grid a fine grid of `elements` is compared with: half the elements each way, at
/// least one.
pub fn coarser(elements: [usize; 2]) -> [usize; 2] {
    elements.map(|n| n.div_ceil(2).max(1))
}

/// A result's point powers (W): per link, net per actuator, per point load.
#[derive(Clone, Debug, Default)]
pub struct PointPowers {
    pub links: Vec<f64>,
    pub net: Vec<f64>,
    pub loads: Vec<f64>,
}

/// The fine grid's point powers against a coarser grid's, for one analysis.
#[derive(Clone, Debug, Default, Serialize)]
pub struct MeshEstimate {
    /// Elements of the two grids along x and y, as built (lines through attachment points
    /// included).
    pub elements: [usize; 2],
    pub coarse_elements: [usize; 2],
    /// Mean power into the structure per link and per point load on the coarser grid (W).
    pub coarse_mean_power: Vec<f64>,
    pub coarse_load_power: Vec<f64>,
    /// |P_h − P_2h| / |P_h| per link; a link whose power is below 1e-6 of the largest is
    /// measured against that largest instead.
    pub relative_error: Vec<f64>,
    /// The same for each actuator's net power and each point load's power.
    pub net_power_relative_error: Vec<f64>,
    pub load_relative_error: Vec<f64>,
    /// The largest of the three lists: the headline estimate.
    pub max_relative_error: f64,
}

impl MeshEstimate {
    /// The estimate from the powers of the fine grid of `elements` and of the coarse grid
    /// of `coarse_elements` (as built).
    pub fn between(grids: ([usize; 2], [usize; 2]), fine: &PointPowers, coarse: &PointPowers) -> Self {
        let relative_error = relative_to_own(&fine.links, &coarse.links);
        let net_power_relative_error = relative_to_own(&fine.net, &coarse.net);
        let load_relative_error = relative_to_own(&fine.loads, &coarse.loads);
        let max_relative_error = relative_error
            .iter()
            .chain(&net_power_relative_error)
            .chain(&load_relative_error)
            .fold(0.0f64, |a, &b| a.max(b));
        MeshEstimate {
            elements: grids.0,
            coarse_elements: grids.1,
            coarse_mean_power: coarse.links.clone(),
            coarse_load_power: coarse.loads.clone(),
            relative_error,
            net_power_relative_error,
            load_relative_error,
            max_relative_error,
        }
    }
}

/// Why two grids (elements along x and y, as built) cannot give an estimate, if they
/// cannot: the coarser must have fewer elements along both sides (a side of one element
/// cannot be halved; lines through attachment points can leave a halved count as it was).
pub fn not_coarser(fine: [usize; 2], coarse: [usize; 2]) -> Option<String> {
    let same: Vec<&str> =
        ["x", "y"].into_iter().zip(fine.iter().zip(&coarse)).filter(|(_, (f, c))| c >= f).map(|(k, _)| k).collect();
    (!same.is_empty()).then(|| {
        format!(
            "the grid of {} × {} elements cannot be coarsened along {} (halving it, with the lines through the \
             attachment points, gives {} × {}): refine `plate.mesh.elements` to have an estimate",
            fine[0],
            fine[1],
            same.join(" and "),
            coarse[0],
            coarse[1]
        )
    })
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
        let powers = |p: [f64; 3]| PointPowers { links: p.to_vec(), net: vec![p[0] + p[1]], loads: vec![p[0]] };
        let e = MeshEstimate::between(([10, 10], [5, 5]), &powers(fine), &powers(coarse));
        assert!((e.load_relative_error[0] - e.relative_error[0]).abs() < 1e-15);
        for l in 0..2 {
            let actual = (fine[l] - exact[l]).abs() / fine[l].abs();
            assert!((e.relative_error[l] / actual - 3.0).abs() < 1e-9, "{} vs {actual}", e.relative_error[l]);
        }
        assert!(e.relative_error[2] < 1e-5, "a tiny point against the largest: {}", e.relative_error[2]);
        assert!((e.max_relative_error - e.relative_error[0]).abs() < 1e-15);
        assert_eq!(e.coarse_elements, [5, 5]);
    }

    /// A grid that halving leaves as it was along a side gives no estimate, and says why.
    #[test]
    fn a_grid_that_cannot_be_coarsened_is_named() {
        assert!(not_coarser([22, 18], [12, 10]).is_none());
        let why = not_coarser([1, 16], [1, 8]).unwrap();
        assert!(why.contains("along x (") && why.contains("1 × 8"), "{why}");
        assert!(not_coarser([5, 5], [5, 5]).unwrap().contains("along x and y"));
    }
}
