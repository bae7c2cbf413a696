//! Local optima of a finished search: the basins its evaluations show, each climbed to a
//! point no neighbour improves on.
//!
//! Why not "the best points at least `distinct` apart": on a broad peak the points on its
//! flanks are at least `distinct` from its top, rank above a lower peak's top and push it
//! out of the list, though none of them is an optimum. Here a basin is seeded by a point
//! with no better point within `distinct` (nearest-better clustering: a flank point almost
//! always has a better one close by, up its own slope), and each seed is then climbed by a
//! compass search (a step doubled after each move that improves, halved after each poll
//! that does not). The search ends when no poll point ±h along any axis improves and h has
//! fallen below its least step: the end point is a local optimum to that resolution, not a
//! sample that happened to be good. A climb that reaches an optimum already found merges
//! into it. Poll points are clamped to the box, so an optimum on a face or in a corner is
//! landed on exactly, not approached.

use super::search::{Cost, Point};
use rayon::prelude::*;

/// Polls one compass search may take (each polls 2·d points).
pub const POLLS_PER_CLIMB: usize = 24;

/// The largest step a climb grows to (a success doubles the step, a failed poll halves it).
const MAX_STEP: f64 = 0.25;

/// How the climbs run.
#[derive(Clone, Copy, Debug)]
pub struct Climb {
    /// Optima wanted.
    pub top: usize,
    /// Least distance between two optima in the unit box (Euclidean).
    pub distinct: f64,
    /// The least step of the first climb (the search's best): it ends when no poll at
    /// this step improves. The other optima are climbed to 100 times this step.
    pub min_step: f64,
}

/// The unit-box distance between two points.
pub fn distance(a: &[f64], b: &[f64]) -> f64 {
    a.iter().zip(b).map(|(x, y)| (x - y).powi(2)).sum::<f64>().sqrt()
}

/// Evaluations [`local_optima`] may take for `d` variables: one climb per optimum and two
/// more for seeds that merge.
pub fn budget(d: usize, top: usize) -> usize {
    (2 * d).saturating_mul(POLLS_PER_CLIMB).saturating_mul(top.saturating_add(2))
}

/// Up to `c.top` local optima of `f`, best first, from `samples` (evaluated points, any
/// order; their costs already known). `first` is climbed first with a fine step (the
/// search's best, already polished); every climb starts at half the `distinct` distance.
/// Stops when `c.top` are found, when the seeds run out or when [`budget`] is spent.
pub fn local_optima(f: &dyn Cost, first: &Point, samples: &[Point], c: &Climb) -> Vec<Point> {
    let d = first.u.len();
    let mut left = budget(d, c.top);
    let mut found: Vec<Point> = Vec::new();
    let seeds = std::iter::once((first.clone(), (c.min_step * 1e3).min(c.distinct / 2.0)))
        .chain(basin_seeds(samples, c.distinct).into_iter().map(|p| (p, c.distinct / 2.0)));
    for (seed, step) in seeds {
        if found.len() >= c.top || left < 2 * d {
            break;
        }
        if found.iter().any(|o| distance(&o.u, &seed.u) < c.distinct) {
            continue;
        }
        let near_found = |u: &[f64]| found.iter().any(|o| distance(&o.u, u) < c.distinct / 2.0);
        let least = if found.is_empty() { c.min_step } else { (100.0 * c.min_step).min(c.distinct / 8.0) };
        let climbed = compass(f, &seed, step, least, &mut left, &near_found);
        if let Some(p) = climbed {
            if !found.iter().any(|o| distance(&o.u, &p.u) < c.distinct) {
                found.push(p);
            }
        }
    }
    found.sort_by(|a, b| a.cost.total_cmp(&b.cost));
    found
}

/// The points of `samples` with no better point within `distinct`, best first: one per
/// basin the samples show (and a few flank points of sparsely sampled slopes, which their
/// climbs merge away).
fn basin_seeds(samples: &[Point], distinct: f64) -> Vec<Point> {
    let mut sorted: Vec<&Point> = samples.iter().filter(|p| p.cost.is_finite()).collect();
    sorted.sort_by(|a, b| a.cost.total_cmp(&b.cost));
    let mut seeds = Vec::new();
    for (i, p) in sorted.iter().enumerate() {
        if sorted[..i].iter().all(|q| q.cost == p.cost || distance(&q.u, &p.u) >= distinct) {
            seeds.push((*p).clone());
        }
    }
    seeds
}

/// A compass search from `start` with initial step `step`; None when it was abandoned
/// (`stop` said its point reached another optimum's neighbourhood) or ran out of
/// evaluations before its step fell below `min_step`.
fn compass(
    f: &dyn Cost,
    start: &Point,
    mut step: f64,
    min_step: f64,
    left: &mut usize,
    stop: &dyn Fn(&[f64]) -> bool,
) -> Option<Point> {
    let d = start.u.len();
    let mut at = start.clone();
    while step >= min_step {
        if *left < 2 * d || stop(&at.u) {
            return None;
        }
        let polls: Vec<Vec<f64>> = (0..2 * d)
            .map(|k| {
                let mut u = at.u.clone();
                let s = if k % 2 == 0 { step } else { -step };
                u[k / 2] = (u[k / 2] + s).clamp(0.0, 1.0);
                u
            })
            .filter(|u| *u != at.u)
            .collect();
        *left -= polls.len();
        f.generation(0);
        let best = polls
            .into_par_iter()
            .map(|u| {
                let cost = f.cost(&u);
                Point { u, cost }
            })
            .collect::<Vec<_>>()
            .into_iter()
            .min_by(|a, b| a.cost.total_cmp(&b.cost).then_with(|| bits(&a.u).cmp(&bits(&b.u))));
        match best {
            Some(p) if p.cost < at.cost => {
                at = p;
                step = (2.0 * step).min(MAX_STEP);
            }
            _ => step /= 2.0,
        }
    }
    Some(at)
}

fn bits(u: &[f64]) -> Vec<u64> {
    u.iter().map(|x| x.to_bits()).collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    struct Fun<F: Fn(&[f64]) -> f64 + Sync>(F);
    impl<F: Fn(&[f64]) -> f64 + Sync> Cost for Fun<F> {
        fn cost(&self, u: &[f64]) -> f64 {
            (self.0)(u)
        }
    }

    fn sample(f: &dyn Cost, n: usize) -> Vec<Point> {
        (0..n).map(|i| (i as f64 + 0.5) / n as f64).map(|x| Point { u: vec![x], cost: f.cost(&[x]) }).collect()
    }

    #[test]
    fn flank_points_of_a_broad_peak_do_not_push_out_a_lower_peak() {
        // A broad well at 0.3 and a narrow, shallower one at 0.8: the best points at least
        // 0.05 apart would be 0.3 and its flanks; the real second optimum is 0.8.
        let f = Fun(|u: &[f64]| -(-((u[0] - 0.3) / 0.2).powi(2)).exp() - 0.5 * (-((u[0] - 0.8) / 0.03).powi(2)).exp());
        let s = sample(&f, 60);
        let first = s.iter().min_by(|a, b| a.cost.total_cmp(&b.cost)).unwrap().clone();
        let o = local_optima(&f, &first, &s, &Climb { top: 3, distinct: 0.05, min_step: 1e-7 });
        assert_eq!(o.len(), 2, "{o:?}");
        // The broad well tilts the narrow one: its optimum lies a little off 0.8.
        assert!((o[0].u[0] - 0.3).abs() < 1e-5 && (o[1].u[0] - 0.8).abs() < 1e-3, "{o:?}");
    }

    #[test]
    fn an_optimum_on_a_corner_is_landed_on() {
        let f = Fun(|u: &[f64]| -(u[0] + 2.0 * u[1]));
        let s: Vec<Point> =
            [[0.9, 0.97], [0.5, 0.5]].iter().map(|u| Point { u: u.to_vec(), cost: f.cost(u) }).collect();
        let o = local_optima(&f, &s[0], &s, &Climb { top: 1, distinct: 0.05, min_step: 1e-7 });
        assert_eq!(o[0].u, vec![1.0, 1.0]);
    }
}
