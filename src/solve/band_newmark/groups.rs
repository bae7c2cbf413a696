//! The triangular sweeps in groups of four rows, for band half-width 3 (every beam).
//!
//! A sweep is a recurrence, but most of its work is not: the forward sweep stores y and
//! x = y/d, and the backward sweep updates a, v, u, v̄, w₁ and w₂ of each finished row
//! (three loads, six stores and thirteen flops besides the recurrence's three multiply–adds).
//! Row by row all of that is scalar, and a profile of the step showed it setting the pace.
//! Here each sweep carries the last B unknowns in registers, so the recurrence reads no
//! stored unknowns, and finishes four rows at a time: the backward sweep updates them with
//! one AVX2 vector per quantity.
//!
//! Then the recurrence's latency set the pace: row i needs row i − 1 through one
//! multiply–add, four cycles on the hosts measured, and one more dependent multiply–add per
//! row made the step 39 % slower. So the rows go in **pairs** computed from the same three
//! unknowns before the pair: the second row of a pair with the first substituted into it
//! (`PairRows`: four multipliers instead of three, computed once from the factor). The
//! chain is then one multiply–add per two rows; the step measured 0.91 (bare paper beam)
//! to 0.94 (10⁴–10⁵ DOFs) of its time before, in alternating pairs (`scripts/paired.sh`). The substitution rounds differently from the row-by-row sweeps in
//! `sweeps.rs`, so the two agree to round-off, not to the bit (`tests/newmark.rs`); the
//! error against an extended-precision reference is unchanged (`tests/precision.rs`).
//! The substituted multipliers stay small: at most 1 in magnitude on meshes of 38 to 10⁵
//! DOFs with or without the frame (where L itself reaches 5·10⁴, w and θ rows differing
//! by 1/h), and the two terms each sums cancel by at most a factor 3.3 (11 at the frame's
//! rows), i.e. two to four bits of one multiplier, not a growth through the sweep.
//!
//! Four rows can form a group because B ≥ 3: a long row of the factor reaches columns below
//! row − B, which in the forward sweep must already be stored and in the backward sweep
//! must not be swept yet; with B ≥ 3 those columns lie below the group of the row. A group
//! with a long row in it goes row by row. Other widths (no beam has them) sweep row by row.

use super::factor_runs::FactorRun;
use super::{BandNewmark, Width};
use crate::simd::madd;
use crate::simd::update::{store_group, update_group, update_row, StepCoeffs, G};

impl BandNewmark {
    /// Whether the grouped sweeps apply to half-width `b`.
    #[inline(always)]
    pub(super) fn groups_apply(b: usize) -> bool {
        b == 3
    }

    /// L·y = z in place in z, and x = y/d, in groups of four rows (see the module).
    #[inline(always)]
    pub(super) fn forward_groups<W: Width, const FMA: bool>(&mut self, w: W) {
        let (n, b) = (self.n, w.b());
        debug_assert!(Self::groups_apply(b));
        let l = &self.factor.l[..n * b];
        let d_inv = &self.factor.d_inv[..n];
        let z = &mut self.z[..n + b];
        let x = &mut self.x[..n + b];
        let (long, l_tail) = (&self.factor.long[..], &self.factor.l_tail[..]);
        let mut lp = 0;
        // win.s = y_{i−1−s}: the unknowns row i reads, newest first (zero before row 0). A
        // tuple, not an array: an array indexed in a loop stayed in memory.
        let mut win = (0.0f64, 0.0f64, 0.0f64);

        // Row i's y, with entries −L(i, i − B + t) = l_neg(t); `$long`: whether row i may
        // be a long row (false where the caller knows it is not, so the check is compiled out).
        macro_rules! row {
            ($i:expr, $l_neg:expr, $long:expr) => {{
                let (i, l_neg) = ($i, $l_neg);
                let mut y = z[i + b];
                if $long && lp < long.len() && long[lp].row == i {
                    // Columns below i − B: rows of earlier groups, already stored in z.
                    y -= long[lp].dot::<FMA>(l_tail, b, z);
                    lp += 1;
                }
                // Column i − 3 + t holds y_{i−3+t}, i.e. win.(2 − t).
                y = madd::<FMA>(l_neg(0), win.2, y);
                y = madd::<FMA>(l_neg(1), win.1, y);
                y = madd::<FMA>(l_neg(2), win.0, y);
                win = (y, win.0, win.1);
                y
            }};
        }
        let band = |i: usize, t: usize| -l[i * b + t];
        let pairs_f = &self.pairs.fwd[..];
        // Rows r (even) and r + 1 from the same window, y_{r+1} with y_r substituted
        // (`la`: `PairRows::fwd`).
        macro_rules! pair {
            ($r:expr, $l_neg:expr, $la:expr) => {{
                let (r, l_neg) = ($r, $l_neg);
                let plain = [l_neg(0), l_neg(1), l_neg(2)];
                let (ye, yo) = pair_rows::<FMA>(z[r + b], z[r + 1 + b], plain, $la, win);
                win = (yo, ye, win.0);
                (ye, yo)
            }};
        }
        let runs: &[FactorRun] = if self.use_runs { &self.factor_runs } else { &[] };
        let mut i = 0;
        // Rows i..i + 4, with −L(r, r − B + t) = even(r, t) for rows r of i's parity and
        // odd(r, t) for the others (i is even), `la(p)` the multipliers of pair p, and their
        // 1/d. A group with a long row goes row by row; the others in two pairs.
        macro_rules! group {
            ($even:expr, $odd:expr, $la:expr, $d_inv:expr, $long:expr) => {{
                let (even, odd) = ($even, $odd);
                let ys = if $long {
                    [
                        row!(i, |t| even(i, t), $long),
                        row!(i + 1, |t| odd(i + 1, t), $long),
                        row!(i + 2, |t| even(i + 2, t), $long),
                        row!(i + 3, |t| odd(i + 3, t), $long),
                    ]
                } else {
                    let (y0, y1) = pair!(i, |t| even(i, t), $la(i / 2));
                    let (y2, y3) = pair!(i + 2, |t| even(i + 2, t), $la(i / 2 + 1));
                    [y0, y1, y2, y3]
                };
                store_group::<FMA>(&mut z[i + b..i + b + G], &mut x[i + b..i + b + G], ys, $d_inv);
                i += G;
            }};
        }
        // A band group, checking its rows for long ones only if the next long row is in it:
        // one comparison a group instead of one a row.
        macro_rules! band_group {
            () => {{
                let dv = [d_inv[i], d_inv[i + 1], d_inv[i + 2], d_inv[i + 3]];
                if lp < long.len() && long[lp].row < i + G {
                    group!(band, band, |p: usize| PairRows::ahead(&pairs_f[p]), dv, true);
                } else {
                    // The group's two pairs, sliced once: a pair's reads need no bounds checks.
                    let (i0, two) = (i, window::<_, 2>(pairs_f, i / 2));
                    let even = |r: usize, t: usize| two[(r - i0) / 2][t];
                    let la = |p: usize| PairRows::ahead(&two[p - i0 / 2]);
                    group!(even, even, la, dv, false);
                }
            }};
        }
        // Groups wholly inside a run read its pattern, held in registers for the whole run
        // (a run has no long rows).
        for run in runs {
            while i + G <= n && i < run.start {
                band_group!();
            }
            let [even, odd] = run.l_neg;
            let la_run = PairRows::ahead_fwd(even, odd);
            let la = |_: usize| la_run;
            let (even, odd) = (|_: usize, t: usize| even[t], |_: usize, t: usize| odd[t]);
            let dv = [run.d_inv[0], run.d_inv[1], run.d_inv[0], run.d_inv[1]];
            debug_assert!(long[lp..].first().is_none_or(|r| r.row >= run.end), "a long row in a factor run");
            while i + G <= run.end {
                group!(even, odd, la, dv, false);
            }
        }
        while i + G <= n {
            band_group!();
        }
        while i < n {
            let y = row!(i, |t| band(i, t), true);
            z[i + b] = y;
            x[i + b] = y * d_inv[i];
            i += 1;
        }
    }

    /// Lᵀ·x = y/d and each row's Newmark update, in groups of four rows (see the module).
    /// With `VBAR` the step's mean velocity is stored in x, as `backward` does.
    #[inline(always)]
    pub(super) fn backward_groups<W: Width, const FMA: bool, const VBAR: bool>(&mut self, w: W, k: StepCoeffs) {
        let (n, b) = (self.n, w.b());
        debug_assert!(Self::groups_apply(b));
        let l = &self.factor.l[..(n + b) * b];
        let x = &mut self.x[b..b + n];
        let (u, v, a) = (&mut self.u[b..b + n], &mut self.v[..n], &mut self.a[..n]);
        let (w1, w2) = (&mut self.w1[b..b + n], &mut self.w2[b..b + n]);
        let (long, l_tail) = (&self.factor.long[..], &self.factor.l_tail[..]);
        let mut lp = long.len();
        // win.s = x_{i+1+s}: the unknowns row i reads, newest first (zero past row n − 1).
        let mut win = (0.0f64, 0.0f64, 0.0f64);

        // Row i's x, with entries −L(i + s, i) = up_neg(s), s ∈ 1..=B; `$long` as in the
        // forward sweep.
        macro_rules! row {
            ($i:expr, $up_neg:expr, $long:expr) => {{
                let (i, up_neg) = ($i, $up_neg);
                let mut xi = x[i];
                xi = madd::<FMA>(up_neg(3), win.2, xi);
                xi = madd::<FMA>(up_neg(2), win.1, xi);
                xi = madd::<FMA>(up_neg(1), win.0, xi);
                win = (xi, win.0, win.1);
                if $long && lp > 0 && long[lp - 1].row == i {
                    lp -= 1;
                    // Columns below i − B: rows of later (lower) groups, not yet swept.
                    long[lp].scatter(l_tail, b, x, xi);
                }
                xi
            }};
        }
        let band = |i: usize, s: usize| -l[(i + s) * b + b - s];
        let pairs_b = &self.pairs.bwd[..];
        // Rows o = e + 1 and e (even) from the same window, x_e with x_o substituted
        // (`la`: `PairRows::bwd`).
        macro_rules! pair {
            ($e:expr, $up_o:expr, $la:expr) => {{
                let (e, up_o) = ($e, $up_o);
                let plain = [up_o(3), up_o(2), up_o(1)];
                let (xo, xe) = pair_rows::<FMA>(x[e + 1], x[e], plain, $la, win);
                win = (xe, xo, win.0);
                (xe, xo)
            }};
        }
        let top = n / G * G;
        let mut i = n;
        while i > top {
            i -= 1;
            let xi = row!(i, |s| band(i, s), true);
            update_row::<FMA, VBAR>(k, i, xi, u, v, a, x, w1, w2);
        }
        let runs: &[FactorRun] = if self.use_runs { &self.factor_runs } else { &[] };
        // Rows g..g + 4 and their update, with −L(i + s, i) = even(i, s) for rows i of g's
        // parity and odd(i, s) for the others (g is even) and `la(p)` the multipliers of
        // pair p; row by row if a long row is in the group, else in two pairs.
        macro_rules! group {
            ($g:expr, $even:expr, $odd:expr, $la:expr, $long:expr) => {{
                let (g, even, odd) = ($g, $even, $odd);
                let xs = if $long {
                    let x3 = row!(g + 3, |s| odd(g + 3, s), $long);
                    let x2 = row!(g + 2, |s| even(g + 2, s), $long);
                    let x1 = row!(g + 1, |s| odd(g + 1, s), $long);
                    [row!(g, |s| even(g, s), $long), x1, x2, x3]
                } else {
                    let (x2, x3) = pair!(g + 2, |s| odd(g + 3, s), $la(g / 2 + 1));
                    let (x0, x1) = pair!(g, |s| odd(g + 1, s), $la(g / 2));
                    [x0, x1, x2, x3]
                };
                update_group::<FMA, VBAR>(k, g, xs, [&mut *u, &mut *v, &mut *a], x, [&mut *w1, &mut *w2]);
                i = g;
            }};
        }
        // A band group, checking for long rows only if the next one (going up) is in it.
        macro_rules! band_group {
            () => {{
                let g0 = i - G;
                if lp > 0 && long[lp - 1].row >= g0 {
                    group!(g0, band, band, |p: usize| PairRows::ahead(&pairs_b[p]), true);
                } else {
                    // As in the forward sweep.
                    let two = window::<_, 2>(pairs_b, g0 / 2);
                    let odd = |r: usize, s: usize| two[(r - g0) / 2][s];
                    let la = |p: usize| PairRows::ahead(&two[p - g0 / 2]);
                    group!(g0, odd, odd, la, false);
                }
            }};
        }
        // Rows g..g + 4 read the pattern, held in registers for the whole run, if rows
        // g + 1..=g + 3 + B all lie in the run (a run has no long rows).
        for run in runs.iter().rev() {
            while i >= G && i - G + 3 + b >= run.end {
                band_group!();
            }
            let [even, odd] = run.up_neg;
            let la_run = PairRows::ahead_bwd(even, odd);
            let la = |_: usize| la_run;
            let (even, odd) = (|_: usize, s: usize| even[s], |_: usize, s: usize| odd[s]);
            debug_assert!(long[..lp].last().is_none_or(|r| r.row < run.start), "a long row in a factor run");
            while i >= G && i - G >= run.start {
                group!(i - G, even, odd, la, false);
            }
        }
        while i >= G {
            band_group!();
        }
    }
}

/// The `N` entries of `x` from `start`, as an array: indexed by constants, they need no
/// bounds checks.
#[inline(always)]
fn window<T, const N: usize>(x: &[T], start: usize) -> &[T; N] {
    x[start..start + N].try_into().expect("a slice of N entries")
}

/// Two rows of a sweep from the same window w = (newest, middle, oldest) of unknowns:
/// the first as it stands, h_first + plain[0]·w.2 + plain[1]·w.1 + plain[2]·w.0, and the
/// second with the first substituted into it, h_second + la[3]·h_first + la[0]·w.2 +
/// la[1]·w.1 + la[2]·w.0 (`PairRows`). The two chains interleave, the newest unknown last
/// in each, so each waits on the window through one multiply–add.
#[inline(always)]
fn pair_rows<const FMA: bool>(
    h_first: f64,
    h_second: f64,
    plain: [f64; 3],
    la: [f64; 4],
    win: (f64, f64, f64),
) -> (f64, f64) {
    let mut second = madd::<FMA>(la[3], h_first, h_second);
    let mut first = h_first;
    first = madd::<FMA>(plain[0], win.2, first);
    second = madd::<FMA>(la[0], win.2, second);
    first = madd::<FMA>(plain[1], win.1, first);
    second = madd::<FMA>(la[1], win.1, second);
    first = madd::<FMA>(plain[2], win.0, first);
    second = madd::<FMA>(la[2], win.0, second);
    (first, second)
}

/// The sweeps' row pairs (2p, 2p + 1) with one row substituted into the other, so that both
/// rows of a pair are computed from the same three unknowns before it (see the module).
#[derive(Clone, Debug, Default)]
pub(super) struct PairRows {
    /// Forward, pair p: −L(e, e − 3 + t), t ∈ 0..3, of the even row e = 2p (and a zero),
    /// then the odd row r = 2p + 1 with y_{r−1} substituted, as the multipliers of y_{r−4},
    /// y_{r−3}, y_{r−2} and of z_{r−1} ([`PairRows::ahead`]). A pair's band reads are one
    /// line of eight numbers rather than rows of the factor.
    fwd: Vec<[f64; 8]>,
    /// Backward, pair p: −L(o + s, o), s ∈ 1..=3 (index 0 unused), of the odd row o = 2p + 1,
    /// then the even row e = 2p with x_{e+1} substituted, as the multipliers of x_{e+4},
    /// x_{e+3}, x_{e+2} and of the right-hand side of row e + 1.
    bwd: Vec<[f64; 8]>,
}

impl PairRows {
    /// From the factor rows `l` (B per row, B zero rows past n); empty unless the grouped
    /// sweeps apply to `b`.
    pub(super) fn new(n: usize, b: usize, l: &[f64]) -> Self {
        if !BandNewmark::groups_apply(b) {
            return Self::default();
        }
        // −L(r, r − 3 + t), t ∈ 0..3, and −L(r + s, r), s ∈ 1..=3 (index 0 unused).
        let left = |r: usize| [-l[r * b], -l[r * b + 1], -l[r * b + 2]];
        let below = |r: usize| {
            let mut v = [0.0; 4];
            (1..=3).for_each(|s| v[s] = -l[(r + s) * b + b - s]);
            v
        };
        let pairs = 0..n / 2;
        let line = |plain: [f64; 4], ahead: [f64; 4]| {
            let mut q = [0.0; 8];
            q[..4].copy_from_slice(&plain);
            q[4..].copy_from_slice(&ahead);
            q
        };
        let fwd = |p: usize| {
            let e = left(2 * p);
            line([e[0], e[1], e[2], 0.0], Self::ahead_fwd(e, left(2 * p + 1)))
        };
        let bwd = |p: usize| line(below(2 * p + 1), Self::ahead_bwd(below(2 * p), below(2 * p + 1)));
        PairRows { fwd: pairs.clone().map(fwd).collect(), bwd: pairs.map(bwd).collect() }
    }

    pub(super) fn len(&self) -> usize {
        8 * (self.fwd.len() + self.bwd.len())
    }

    /// The substituted multipliers of a pair's line.
    #[inline(always)]
    fn ahead(line: &[f64; 8]) -> [f64; 4] {
        [line[4], line[5], line[6], line[7]]
    }

    /// y_o = z_o + a_o·y_{o−3} + b_o·y_{o−2} + c_o·y_{o−1} (`odd` = [a_o, b_o, c_o]) with
    /// y_{o−1} = z_{o−1} + a_e·y_{o−4} + b_e·y_{o−3} + c_e·y_{o−2} (`even`) substituted:
    /// [c_o·a_e, a_o + c_o·b_e, b_o + c_o·c_e, c_o].
    #[inline(always)]
    pub(super) fn ahead_fwd(even: [f64; 3], odd: [f64; 3]) -> [f64; 4] {
        let c = odd[2];
        [c * even[0], odd[0] + c * even[1], odd[1] + c * even[2], c]
    }

    /// x_e = x̂_e + p_e·x_{e+1} + q_e·x_{e+2} + r_e·x_{e+3} (`even` = [_, p_e, q_e, r_e])
    /// with x_{e+1} = x̂_{e+1} + p_o·x_{e+2} + q_o·x_{e+3} + r_o·x_{e+4} (`odd`) substituted:
    /// [p_e·r_o, r_e + p_e·q_o, q_e + p_e·p_o, p_e].
    #[inline(always)]
    pub(super) fn ahead_bwd(even: [f64; 4], odd: [f64; 4]) -> [f64; 4] {
        let p = even[1];
        [p * odd[3], even[3] + p * odd[2], even[2] + p * odd[1], p]
    }
}
