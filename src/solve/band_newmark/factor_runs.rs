//! Where the band factor repeats: the rows the grouped sweeps read from a pattern held in
//! registers instead of from the factor's storage.

use crate::linalg::band::LongRow;

/// Rows `start..end` of the factor whose rows (B entries of L and 1/d) repeat with period
/// two, bit for bit: the factorisation of a segment of equal elements converges to such a
/// pattern after a transient of a few hundred to some ten thousand rows (longer the finer
/// the mesh), and there the sweeps read the pattern instead of streaming L and 1/d.
#[derive(Clone, Debug)]
pub(super) struct FactorRun {
    pub(super) start: usize,
    pub(super) end: usize,
    /// Row r's entries L(r, r − 3 + s), s ∈ 0..3, negated, and 1/d_r, for r even and odd.
    pub(super) l_neg: [[f64; 3]; 2],
    pub(super) d_inv: [f64; 2],
    /// For the backward sweep at a row of each parity: −L(i + s, i) at s ∈ 1..=3 (0 unused).
    pub(super) up_neg: [[f64; 4]; 2],
}

impl FactorRun {
    /// The runs of at least `MIN_FACTOR_RUN` rows in factor rows `l` (B per row) and `d_inv`,
    /// none of them a long row. Only for B = 3, the beam's width, which the grouped sweeps
    /// (`groups.rs`), the only readers of the runs, handle.
    pub(super) fn find(n: usize, b: usize, l: &[f64], d_inv: &[f64], long: &[LongRow]) -> Vec<FactorRun> {
        if b != 3 {
            return Vec::new();
        }
        let same = |r: usize| {
            r >= 2
                && d_inv[r].to_bits() == d_inv[r - 2].to_bits()
                && (0..b).all(|s| l[r * b + s].to_bits() == l[(r - 2) * b + s].to_bits())
        };
        let is_long: Vec<bool> = {
            let mut v = vec![false; n];
            long.iter().for_each(|lr| v[lr.row] = true);
            v
        };
        let mut runs = Vec::new();
        let mut r = 0;
        while r < n {
            // A run starts at two rows (its pattern) and goes on while each row repeats the
            // one two before.
            if is_long[r] || r + 1 >= n || is_long[r + 1] {
                r += 1;
                continue;
            }
            let start = r;
            let mut end = r + 2;
            while end < n && !is_long[end] && same(end) {
                end += 1;
            }
            if end - start >= MIN_FACTOR_RUN {
                let mut run = FactorRun { start, end, l_neg: [[0.0; 3]; 2], d_inv: [0.0; 2], up_neg: [[0.0; 4]; 2] };
                for row in [start, start + 1] {
                    let p = row % 2;
                    for s in 0..b {
                        run.l_neg[p][s] = -l[row * b + s];
                    }
                    run.d_inv[p] = d_inv[row];
                }
                for p in 0..2 {
                    for s in 1..=b {
                        run.up_neg[p][s] = run.l_neg[(p + s) % 2][b - s];
                    }
                }
                runs.push(run);
                r = end;
            } else {
                r = start + 1;
            }
        }
        runs
    }
}

/// Shortest factor run worth its own loop, in rows.
const MIN_FACTOR_RUN: usize = 32;
