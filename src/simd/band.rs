//! The band right-hand side of a Newmark step on the increment, z = M·w₁ + C·w₂ − K·u
//! (or M·w₁ − K·u in the proportional form, where the caller passes w₂' in u's place), with
//! M, C, K stored by diagonals, and the step's dissipation v̄ᵀ·C·v̄ — the only loops over
//! every row of the band that the compiler did not vectorise itself.
//!
//! Storage: diagonal t ∈ 0..=B of a matrix at `a[t·(n + B) + i]` = A(i, i − t) (the upper
//! half is the same numbers, read t entries further on); vectors padded with B entries
//! before and after, so that column j is at j + B.

use super::madd;

/// The slices a band right-hand side reads: `mck` = M, C, K by diagonals ((B+1)·(n+B)
/// each), `ws` = w₁, w₂, u padded (n + 2B each; in the proportional form the caller passes
/// w₂' as u), `vbar` the last step's v̄ padded like them (read only for the dissipation),
/// and the periodic runs for groups of four and of eight rows (empty: none used).
pub struct BandRhs<'a> {
    pub n: usize,
    pub b: usize,
    pub mck: [&'a [f64]; 3],
    pub ws: [&'a [f64]; 3],
    pub vbar: &'a [f64],
    pub runs4: &'a [PeriodicRun],
    pub runs8: &'a [PeriodicRun],
}

/// Which terms a band right-hand side computes and which kernel runs it.
#[derive(Clone, Copy, Debug)]
pub struct RhsForm {
    /// The proportional form: M·w₁ − K·u, C not read for the right-hand side.
    pub proportional: bool,
    /// Fold the last step's dissipation over whole vector groups into the same pass
    /// (vector build only).
    pub dissipation: bool,
    /// 512-bit vectors, eight rows a group (only after `has_avx512`).
    pub wide: bool,
}

/// z = M·w₁ + C·w₂ − K·u (or M·w₁ − K·u in the proportional form) over the n rows. With
/// `FMA` the vector kernels run (the same multiply–adds in the same order as
/// [`rhs_band_scalar`] with `FMA`, so the same bits); with `form.dissipation` they also
/// return the dissipation's first row left and four lane sums, to be finished by
/// [`dissipation_rows`]. Without `FMA` it is the scalar twin.
#[inline(always)]
pub fn rhs_band<const FMA: bool>(r: &BandRhs, z: &mut [f64], form: RhsForm) -> (usize, [f64; 4]) {
    let mut lanes = (0, [0.0f64; 4]);
    #[cfg(target_arch = "x86_64")]
    if FMA {
        let (n, b) = (r.n, r.b);
        let none: &[PeriodicRun] = &[];
        let (mck, ws, vb) = (r.mck, r.ws, r.vbar);
        let part = &mut lanes.1;
        // SAFETY: `FMA` is true only where the caller checked `has_fma`, and `wide` only
        // after `has_avx512`; each kernel checks the slice lengths it relies on.
        unsafe {
            let (from, r4) = match (form.wide, form.dissipation, form.proportional) {
                (false, _, _) => (0, r.runs4),
                (true, true, true) => (rhs_band_avx512::<true, true>(n, b, mck, ws, z, vb, part, r.runs8), none),
                (true, true, false) => (rhs_band_avx512::<true, false>(n, b, mck, ws, z, vb, part, r.runs8), none),
                (true, false, true) => (rhs_band_avx512::<false, true>(n, b, mck, ws, z, vb, part, r.runs8), none),
                (true, false, false) => (rhs_band_avx512::<false, false>(n, b, mck, ws, z, vb, part, r.runs8), none),
            };
            lanes.0 = match (form.dissipation, form.proportional) {
                (true, true) => rhs_band_avx2::<true, true>(from, n, b, mck, ws, z, vb, part, r4),
                (true, false) => rhs_band_avx2::<true, false>(from, n, b, mck, ws, z, vb, part, r4),
                (false, true) => rhs_band_avx2::<false, true>(from, n, b, mck, ws, z, vb, part, r4),
                (false, false) => rhs_band_avx2::<false, false>(from, n, b, mck, ws, z, vb, part, r4),
            };
        }
        return lanes;
    }
    rhs_band_scalar::<FMA>(r.n, r.b, r.mck, r.ws, z, form.proportional);
    lanes
}

/// Widest band whose scalar right-hand side runs on per-diagonal slices.
const MAX_SLICED: usize = 5;

/// The scalar twin of the band right-hand side: row i sums M_ii·w₁ᵢ, then for t = 1..=B
/// the lower and the upper entry of diagonal t, the same for C and w₂ and for K and u, and
/// returns (sm + sc) − sk (sm − sk in the proportional form).
#[inline(always)]
pub fn rhs_band_scalar<const FMA: bool>(
    n: usize,
    b: usize,
    [m, c, kk]: [&[f64]; 3],
    [w1, w2, up]: [&[f64]; 3],
    z: &mut [f64],
    proportional: bool,
) {
    let stride = n + b;
    let (m, c, kk) = (&m[..(b + 1) * stride], &c[..(b + 1) * stride], &kk[..(b + 1) * stride]);
    let (w1, w2, up) = (&w1[..n + 2 * b], &w2[..n + 2 * b], &up[..n + 2 * b]);
    let z = &mut z[..n];
    // The products M·w₁, C·w₂, K·u (q = 0, 1, 2): the proportional form skips C.
    let terms: &[usize] = if proportional { &[0, 2] } else { &[0, 1, 2] };
    if b <= MAX_SLICED {
        // Every diagonal and every shifted copy of w as a slice of length n, so that no
        // index in the row loop needs a bounds check.
        let empty: &[f64] = &[];
        let mut lo = [[empty; MAX_SLICED + 1]; 3];
        let mut hi = [[empty; MAX_SLICED + 1]; 3];
        let mut wl = [[empty; MAX_SLICED + 1]; 3];
        let mut wu = [[empty; MAX_SLICED + 1]; 3];
        for (q, (a, x)) in [(m, w1), (c, w2), (kk, up)].into_iter().enumerate() {
            for t in 0..=b {
                let o = t * stride;
                (lo[q][t], hi[q][t]) = (&a[o..o + n], &a[o + t..o + t + n]);
                (wl[q][t], wu[q][t]) = (&x[b - t..b - t + n], &x[b + t..b + t + n]);
            }
        }
        for i in 0..n {
            let mut sums = [0.0; 3];
            for &q in terms {
                let mut sq = lo[q][0][i] * wl[q][0][i];
                for t in 1..=b {
                    sq = madd::<FMA>(lo[q][t][i], wl[q][t][i], sq);
                    sq = madd::<FMA>(hi[q][t][i], wu[q][t][i], sq);
                }
                sums[q] = sq;
            }
            z[i] = if proportional { sums[0] - sums[2] } else { (sums[0] + sums[1]) - sums[2] };
        }
    } else {
        for i in 0..n {
            let mut sums = [0.0; 3];
            for &q in terms {
                let (a, x) = [(m, w1), (c, w2), (kk, up)][q];
                let mut sq = a[i] * x[i + b];
                for t in 1..=b {
                    // SAFETY: t ≤ B and i < n, so t·(n+B) + i + t < (B+1)·(n+B), and
                    // i + B ± t lies in 0..n + 2B (the slices were cut to those lengths).
                    unsafe {
                        let (lo, hi) = (t * stride + i, t * stride + i + t);
                        sq = madd::<FMA>(*a.get_unchecked(lo), *x.get_unchecked(i + b - t), sq);
                        sq = madd::<FMA>(*a.get_unchecked(hi), *x.get_unchecked(i + b + t), sq);
                    }
                }
                sums[q] = sq;
            }
            z[i] = if proportional { sums[0] - sums[2] } else { (sums[0] + sums[1]) - sums[2] };
        }
    }
}

/// The band's v̄ᵀ·C·v̄ = Σᵢ v̄ᵢ·(C_ii·v̄ᵢ + 2·Σ_{t≥1} C_{i,i−t}·v̄_{i−t}) from row `start`
/// on, lane l taking rows i ≡ l mod 4 (as the vector kernels do) and starting from their
/// four sums `part`; the lanes added as (l₀ + l₁) + (l₂ + l₃). `c`: C by diagonals, `vb`:
/// v̄ padded by B. From `(0, [0; 4])` it is the scalar twin of the vector passes.
pub fn dissipation_rows<const FMA: bool>(
    n: usize,
    b: usize,
    c: &[f64],
    vb: &[f64],
    (start, mut part): (usize, [f64; 4]),
) -> f64 {
    let stride = n + b;
    let (c, vb) = (&c[..(b + 1) * stride], &vb[..n + 2 * b]);
    for i in start..n {
        let mut s = 0.5 * c[i] * vb[i + b];
        for t in 1..=b {
            s = madd::<FMA>(c[t * stride + i], vb[i + b - t], s);
        }
        part[i % 4] = madd::<FMA>(2.0 * s, vb[i + b], part[i % 4]);
    }
    (part[0] + part[1]) + (part[2] + part[3])
}

/// The dissipation's four lane sums over whole groups of four rows (vector build), as
/// (first row left, sums), for [`dissipation_rows`] to finish; `(0, [0; 4])` without `FMA`.
pub fn dissipation_lanes<const FMA: bool>(n: usize, b: usize, c: &[f64], vb: &[f64]) -> (usize, [f64; 4]) {
    let mut part = [0.0f64; 4];
    #[cfg(target_arch = "x86_64")]
    if FMA {
        // SAFETY: `FMA` is true only where the caller checked `has_fma`; the kernel checks
        // the lengths it relies on.
        let start = unsafe { dissipation_avx2(n, b, c, vb, &mut part) };
        return (start, part);
    }
    let _ = (n, b, c, vb);
    (0, part)
}

/// The row loop of the band right-hand side (and, with `$diss`, of the last step's
/// dissipation) over whole groups of `$lanes` rows up to `$end` of the band storage, written
/// once for the 256- and 512-bit kernels. Each kernel brings its
/// vector operations into scope as `load`, `store`, `mul`, `fmadd`, `add`, `sub`, `zero`
/// and `splat` (a macro_rules body resolves such names where it is invoked). Row i:
/// z = M_ii·w₁ᵢ + Σ_t (M_{i,i−t}·w₁ᵢ₋ₜ + M_{i+t,i}·w₁ᵢ₊ₜ), the same for C and w₂ and for K
/// and u, then (sm + sc) − sk; the dissipation adds 2·v̄ᵢ·(½·C_ii·v̄ᵢ + Σ_t C_{i,i−t}·v̄ᵢ₋ₜ)
/// to `$acc`. Diagonal t of `$pm`, `$pc`, `$pk` starts at t·`$stride`. Advances `$i` past the last whole group
/// before `$end`.
macro_rules! rhs_groups {
    ($diss:expr, $ray:expr, $lanes:expr, $i:ident, $end:expr, $b:expr, $stride:expr, [$pm:expr, $pc:expr, $pk:expr], [$p1:expr, $p2:expr, $pu:expr, $pv:expr, $pz:expr], $acc:ident) => {{
        let (pm, pc, pk, p1, p2, pu, pv, pz, b, stride) = ($pm, $pc, $pk, $p1, $p2, $pu, $pv, $pz, $b, $stride);
        let (half, two) = (splat(0.5), splat(2.0));
        while $i + $lanes <= $end {
            let i = $i;
            let c0 = load(pc.add(i));
            let mut sm = mul(load(pm.add(i)), load(p1.add(b + i)));
            let mut sc = if $ray { zero() } else { mul(c0, load(p2.add(b + i))) };
            let mut sk = mul(load(pk.add(i)), load(pu.add(b + i)));
            let vi = if $diss { load(pv.add(b + i)) } else { zero() };
            let mut sd = if $diss { mul(mul(half, c0), vi) } else { zero() };
            for t in 1..=b {
                let (lo, up) = (t * stride + i, t * stride + i + t);
                let c_lo = load(pc.add(lo));
                sm = fmadd(load(pm.add(lo)), load(p1.add(b + i - t)), sm);
                sm = fmadd(load(pm.add(up)), load(p1.add(b + i + t)), sm);
                if !$ray {
                    sc = fmadd(c_lo, load(p2.add(b + i - t)), sc);
                    sc = fmadd(load(pc.add(up)), load(p2.add(b + i + t)), sc);
                }
                sk = fmadd(load(pk.add(lo)), load(pu.add(b + i - t)), sk);
                sk = fmadd(load(pk.add(up)), load(pu.add(b + i + t)), sk);
                if $diss {
                    sd = fmadd(c_lo, load(pv.add(b + i - t)), sd);
                }
            }
            store(pz.add(i), if $ray { sub(sm, sk) } else { sub(add(sm, sc), sk) });
            if $diss {
                $acc = fmadd(mul(two, sd), vi, $acc);
            }
            $i += $lanes;
        }
    }};
}

/// `rhs_groups!` over a periodic run when B = 3: the run's 21 vectors of M, C and K are
/// loaded once, before the row loop, and stay in registers (the compiler cannot hoist them
/// itself, since it cannot prove the stores to z leave them alone). The same operations in
/// the same order as `rhs_groups!`, so the same bits.
macro_rules! rhs_run_b3 {
    ($diss:expr, $ray:expr, $lanes:expr, $i:ident, $end:expr, [$pm:expr, $pc:expr, $pk:expr], [$p1:expr, $p2:expr, $pu:expr, $pv:expr, $pz:expr], $acc:ident) => {{
        const B: usize = 3;
        let (pm, pc, pk, p1, p2, pu, pv, pz) = ($pm, $pc, $pk, $p1, $p2, $pu, $pv, $pz);
        let two = splat(2.0);
        let (d0, _) = PeriodicRun::offsets(0);
        let (m0, c0, k0) = (load(pm.add(d0)), load(pc.add(d0)), load(pk.add(d0)));
        let half_c0 = mul(splat(0.5), c0);
        // Diagonal t's lower and upper values of M, C and K.
        let diag = |t: usize| {
            let (lo, up) = PeriodicRun::offsets(t);
            (
                (load(pm.add(lo)), load(pm.add(up))),
                (load(pc.add(lo)), load(pc.add(up))),
                (load(pk.add(lo)), load(pk.add(up))),
            )
        };
        let (d1, d2, d3) = (diag(1), diag(2), diag(3));
        while $i + $lanes <= $end {
            let i = $i;
            let mut sm = mul(m0, load(p1.add(B + i)));
            let mut sc = if $ray { zero() } else { mul(c0, load(p2.add(B + i))) };
            let mut sk = mul(k0, load(pu.add(B + i)));
            let vi = if $diss { load(pv.add(B + i)) } else { zero() };
            let mut sd = if $diss { mul(half_c0, vi) } else { zero() };
            for (t, ((m_lo, m_up), (c_lo, c_up), (k_lo, k_up))) in [(1, d1), (2, d2), (3, d3)] {
                sm = fmadd(m_lo, load(p1.add(B + i - t)), sm);
                sm = fmadd(m_up, load(p1.add(B + i + t)), sm);
                if !$ray {
                    sc = fmadd(c_lo, load(p2.add(B + i - t)), sc);
                    sc = fmadd(c_up, load(p2.add(B + i + t)), sc);
                }
                sk = fmadd(k_lo, load(pu.add(B + i - t)), sk);
                sk = fmadd(k_up, load(pu.add(B + i + t)), sk);
                if $diss {
                    sd = fmadd(c_lo, load(pv.add(B + i - t)), sd);
                }
            }
            store(pz.add(i), if $ray { sub(sm, sk) } else { sub(add(sm, sc), sk) });
            if $diss {
                $acc = fmadd(mul(two, sd), vi, $acc);
            }
            $i += $lanes;
        }
    }};
}

/// The band right-hand side over rows `$i..n` in groups of `$lanes`, taking each
/// periodic run's values from the run (no matrix streams there) and the band storage
/// elsewhere: the same loads of the same values in the same order either way.
macro_rules! rhs_band_and_runs {
    ($diss:expr, $ray:expr, $lanes:expr, $i:ident, $n:expr, $b:expr, $runs:expr, [$m:expr, $c:expr, $k:expr, $w1:expr, $w2:expr, $u:expr, $vb:expr, $z:expr], $acc:ident) => {{
        let (n, b) = ($n, $b);
        let stride = n + b;
        assert!($m.len() >= (b + 1) * stride && $c.len() >= (b + 1) * stride && $k.len() >= (b + 1) * stride);
        assert!($w1.len() >= n + 2 * b && $w2.len() >= n + 2 * b && $u.len() >= n + 2 * b && $z.len() >= n);
        assert!(!$diss || $vb.len() >= n + 2 * b);
        let (p1, p2, pu, pv, pz) = ($w1.as_ptr(), $w2.as_ptr(), $u.as_ptr(), $vb.as_ptr(), $z.as_mut_ptr());
        let band = [$m.as_ptr(), $c.as_ptr(), $k.as_ptr()];
        for run in $runs.iter() {
            assert!(b == 3 && run.start % $lanes == 0 && run.end % $lanes == 0 && run.end <= n);
            assert!([&run.m, &run.c, &run.k].iter().all(|v| v.len() >= (2 * b + 1) * RUN_LANES));
            if run.start >= $i {
                rhs_groups!(
                    $diss,
                    $ray,
                    $lanes,
                    $i,
                    run.start,
                    b,
                    stride,
                    [band[0], band[1], band[2]],
                    [p1, p2, pu, pv, pz],
                    $acc
                );
                let (rm, rc, rk) = (run.m.as_ptr(), run.c.as_ptr(), run.k.as_ptr());
                rhs_run_b3!($diss, $ray, $lanes, $i, run.end, [rm, rc, rk], [p1, p2, pu, pv, pz], $acc);
            }
        }
        rhs_groups!($diss, $ray, $lanes, $i, n, b, stride, [band[0], band[1], band[2]], [p1, p2, pu, pv, pz], $acc);
    }};
}

/// Lanes of a periodic run's stored group: the widest kernel's.
pub const RUN_LANES: usize = 8;

/// Shortest periodic run worth its own loop, in groups.
const MIN_RUN_GROUPS: usize = 4;

/// Rows `start..end` (whole groups of a kernel's lanes) in which every group of the band
/// right-hand side loads the same values of M, C and K as the first. A segment of equal
/// elements makes its rows repeat with period two (w and θ rows), so there the
/// step reads one group's copy, which stays in L1, instead of streaming the 3·(B+1)
/// diagonals. The values are exactly those of the band storage, so the result is the same
/// to the bit (`tests/newmark.rs`).
#[derive(Clone, Debug)]
pub struct PeriodicRun {
    pub start: usize,
    pub end: usize,
    /// The first group's values, `RUN_LANES` per position: 0 the diagonal, 2t − 1 the
    /// lower and 2t the upper value of diagonal t.
    m: Vec<f64>,
    c: Vec<f64>,
    k: Vec<f64>,
}

impl PeriodicRun {
    /// Offsets of diagonal t's lower and upper values in `m`, `c`, `k` (t = 0: the diagonal).
    #[inline(always)]
    fn offsets(t: usize) -> (usize, usize) {
        ((2 * t * RUN_LANES).saturating_sub(RUN_LANES), 2 * t * RUN_LANES)
    }

    /// The runs of groups of `lanes` (4 or 8) rows in band storage `m`, `c`, `k` of n rows
    /// and half-width b: maximal sequences of at least `MIN_RUN_GROUPS` groups whose values
    /// equal the first group's bit for bit (so −0 and +0 differ). Only for B = 3, the beam's
    /// width, whose kernel (`rhs_run_b3!`) keeps the run's values in registers.
    pub fn find(n: usize, b: usize, [m, c, k]: [&[f64]; 3], lanes: usize) -> Vec<PeriodicRun> {
        if b != 3 {
            return Vec::new();
        }
        let stride = n + b;
        let group = |a: &[f64], i: usize| -> Vec<u64> {
            let mut g = vec![0u64; (2 * b + 1) * RUN_LANES];
            for l in 0..lanes {
                g[l] = a[i + l].to_bits();
                for t in 1..=b {
                    let (lo, up) = Self::offsets(t);
                    g[lo + l] = a[t * stride + i + l].to_bits();
                    g[up + l] = a[t * stride + i + l + t].to_bits();
                }
            }
            g
        };
        let mut runs = Vec::new();
        type Groups = [Vec<u64>; 3];
        let mut close = |open: Option<(usize, Groups)>, end: usize| {
            if let Some((start, [gm, gc, gk])) = open {
                if end - start >= MIN_RUN_GROUPS * lanes {
                    let f = |g: Vec<u64>| g.into_iter().map(f64::from_bits).collect();
                    runs.push(PeriodicRun { start, end, m: f(gm), c: f(gc), k: f(gk) });
                }
            }
        };
        let mut open: Option<(usize, Groups)> = None;
        let mut i = 0;
        while i + lanes <= n {
            let g = [group(m, i), group(c, i), group(k, i)];
            if !matches!(&open, Some((_, first)) if *first == g) {
                close(open.take(), i);
                open = Some((i, g));
            }
            i += lanes;
        }
        close(open, i);
        runs
    }
}

/// The banded right-hand side of the increment, z = M·w₁ + C·w₂ − K·u, four rows at a time:
/// the same multiply–adds in the same order as the scalar loop of `rhs` (so the same bits),
/// written with vectors because the compiler left that loop scalar. `m`, `c`, `k`:
/// (B+1)·(n+B) diagonal storage; `w1`, `w2`, `u`: n + 2B, padded; `z`: n; `runs`: periodic
/// runs of groups of four, whose values come from the run instead of the band.
///
/// With `DISS`, the same pass also adds the last step's v̄ᵀ·C·v̄ over whole groups of four
/// rows to `part` (`vb`: v̄, padded like w₁), reusing the loads of C's lower diagonals, with
/// the rounding of `dissipation_avx2`; returns the first row it left to the scalar loop.
///
/// With `RAY` (the proportional form, the integrator's proportional form) the right-hand side is M·w₁ − K·u
/// with `u` the caller's w₂': no C term, C's diagonals read only for the dissipation.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2,fma")]
#[allow(clippy::too_many_arguments)]
unsafe fn rhs_band_avx2<const DISS: bool, const RAY: bool>(
    from: usize,
    n: usize,
    b: usize,
    [m, c, k]: [&[f64]; 3],
    [w1, w2, u]: [&[f64]; 3],
    z: &mut [f64],
    vb: &[f64],
    part: &mut [f64; 4],
    runs: &[PeriodicRun],
) -> usize {
    use std::arch::x86_64::{
        _mm256_add_pd as add, _mm256_fmadd_pd as fmadd, _mm256_loadu_pd as load, _mm256_mul_pd as mul,
        _mm256_set1_pd as splat, _mm256_setzero_pd as zero, _mm256_storeu_pd as store, _mm256_sub_pd as sub,
    };
    let mut acc = load(part.as_ptr());
    let mut i = from;
    rhs_band_and_runs!(DISS, RAY, 4, i, n, b, runs, [m, c, k, w1, w2, u, vb, z], acc);
    let (start, stride) = (i, n + b);
    for i in i..n {
        let mut sm = m[i] * w1[b + i];
        let mut sc = if RAY { 0.0 } else { c[i] * w2[b + i] };
        let mut sk = k[i] * u[b + i];
        for t in 1..=b {
            let (lo, up) = (t * stride + i, t * stride + i + t);
            sm = m[lo].mul_add(w1[b + i - t], sm);
            sm = m[up].mul_add(w1[b + i + t], sm);
            if !RAY {
                sc = c[lo].mul_add(w2[b + i - t], sc);
                sc = c[up].mul_add(w2[b + i + t], sc);
            }
            sk = k[lo].mul_add(u[b + i - t], sk);
            sk = k[up].mul_add(u[b + i + t], sk);
        }
        z[i] = if RAY { sm - sk } else { (sm + sc) - sk };
    }
    if DISS {
        store(part.as_mut_ptr(), acc);
    }
    start
}

/// `rhs_band_avx2` eight rows at a time with 512-bit vectors, over whole groups of eight;
/// returns the first row left. Each row's sums are the same multiply–adds in the same order
/// (the same bits); the dissipation's eight lanes are added pairwise into `part`'s four.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx512f")]
#[allow(clippy::too_many_arguments)]
unsafe fn rhs_band_avx512<const DISS: bool, const RAY: bool>(
    n: usize,
    b: usize,
    [m, c, k]: [&[f64]; 3],
    [w1, w2, u]: [&[f64]; 3],
    z: &mut [f64],
    vb: &[f64],
    part: &mut [f64; 4],
    runs: &[PeriodicRun],
) -> usize {
    use std::arch::x86_64::{
        _mm512_add_pd as add, _mm512_fmadd_pd as fmadd, _mm512_loadu_pd as load, _mm512_mul_pd as mul,
        _mm512_set1_pd as splat, _mm512_setzero_pd as zero, _mm512_storeu_pd as store, _mm512_sub_pd as sub,
    };
    let mut acc = zero();
    let mut i = 0;
    rhs_band_and_runs!(DISS, RAY, 8, i, n, b, runs, [m, c, k, w1, w2, u, vb, z], acc);
    if DISS {
        let mut lanes = [0.0f64; 8];
        store(lanes.as_mut_ptr(), acc);
        for l in 0..4 {
            part[l] += lanes[l] + lanes[l + 4];
        }
    }
    i
}

/// The banded dissipation's four partial sums (lane l takes the rows i ≡ l mod 4, as the
/// scalar loop of `band_dissipation_rows` does) over whole groups of four rows; returns the first row
/// left for the scalar loop.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2,fma")]
unsafe fn dissipation_avx2(n: usize, b: usize, c: &[f64], vb: &[f64], part: &mut [f64; 4]) -> usize {
    use std::arch::x86_64::*;
    let stride = n + b;
    assert!(c.len() >= (b + 1) * stride && vb.len() >= n + 2 * b);
    let (pc, pv) = (c.as_ptr(), vb.as_ptr());
    let mut acc = _mm256_loadu_pd(part.as_ptr());
    let half = _mm256_set1_pd(0.5);
    let two = _mm256_set1_pd(2.0);
    let mut i = 0;
    while i + 4 <= n {
        let vi = _mm256_loadu_pd(pv.add(b + i));
        let mut s = _mm256_mul_pd(_mm256_mul_pd(half, _mm256_loadu_pd(pc.add(i))), vi);
        for t in 1..=b {
            s = _mm256_fmadd_pd(_mm256_loadu_pd(pc.add(t * stride + i)), _mm256_loadu_pd(pv.add(b + i - t)), s);
        }
        acc = _mm256_fmadd_pd(_mm256_mul_pd(two, s), vi, acc);
        i += 4;
    }
    _mm256_storeu_pd(part.as_mut_ptr(), acc);
    i
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::simd::{builds, has_avx512};

    /// A pseudo-random value in (−1, 1) from a seed.
    fn hash(seed: usize) -> f64 {
        let x = (seed as u64).wrapping_mul(0x9E37_79B9_7F4A_7C15) >> 11;
        (x as f64 / (1u64 << 53) as f64) * 2.0 - 1.0
    }

    /// Diagonal storage of a symmetric band matrix of n rows and half-width b whose rows
    /// repeat with period two between rows n/4 and 3n/4 (so that B = 3 has periodic runs).
    fn band(n: usize, b: usize, seed: usize) -> Vec<f64> {
        let stride = n + b;
        let mut a = vec![0.0; (b + 1) * stride];
        for t in 0..=b {
            for i in t..n {
                let key = if i > n / 4 && i < 3 * n / 4 { i % 2 } else { i };
                a[t * stride + i] = hash(seed * 1_000_003 + t * 10_007 + key);
            }
        }
        a
    }

    fn padded(n: usize, b: usize, seed: usize) -> Vec<f64> {
        let mut v = vec![0.0; n + 2 * b];
        (0..n).for_each(|i| v[b + i] = hash(seed * 7_919 + i));
        v
    }

    /// The vector kernels (256- and 512-bit, with and without the folded dissipation, both
    /// forms, with periodic runs) give the scalar twin's bits, for widths 1–6 and row counts
    /// that leave every partial group.
    #[test]
    fn vector_right_hand_side_is_the_scalar_twin() {
        if !builds().contains(&true) {
            return;
        }
        for b in 1..=6 {
            for n in [5, 13, 38, 101, 402] {
                let (m, c, k) = (band(n, b, 1), band(n, b, 2), band(n, b, 3));
                let (w1, w2, u, vb) = (padded(n, b, 4), padded(n, b, 5), padded(n, b, 6), padded(n, b, 7));
                let (runs4, runs8) =
                    (PeriodicRun::find(n, b, [&m, &c, &k], 4), PeriodicRun::find(n, b, [&m, &c, &k], 8));
                if b == 3 && n >= 101 {
                    assert!(!runs4.is_empty() && !runs8.is_empty(), "{n} rows: the test matrices have runs");
                }
                let r =
                    BandRhs { n, b, mck: [&m, &c, &k], ws: [&w1, &w2, &u], vbar: &vb, runs4: &runs4, runs8: &runs8 };
                for proportional in [false, true] {
                    let mut want = vec![0.0; n];
                    rhs_band_scalar::<true>(n, b, [&m, &c, &k], [&w1, &w2, &u], &mut want, proportional);
                    let diss_want = dissipation_rows::<true>(n, b, &c, &vb, (0, [0.0; 4]));
                    let abs = |v: &[f64]| v.iter().map(|x| x.abs()).collect::<Vec<_>>();
                    let diss_scale = dissipation_rows::<false>(n, b, &abs(&c), &abs(&vb), (0, [0.0; 4]));
                    for wide in [false, true] {
                        if wide && !has_avx512() {
                            continue;
                        }
                        for dissipation in [false, true] {
                            let mut z = vec![f64::NAN; n];
                            let lanes = rhs_band::<true>(&r, &mut z, RhsForm { proportional, dissipation, wide });
                            let bits = |v: &[f64]| v.iter().map(|x| x.to_bits()).collect::<Vec<_>>();
                            let case = format!("b {b}, n {n}, proportional {proportional}, wide {wide}");
                            assert_eq!(bits(&z), bits(&want), "{case}");
                            if dissipation {
                                let got = dissipation_rows::<true>(n, b, &c, &vb, lanes);
                                // The 512-bit kernel adds its eight lanes pairwise into four.
                                let tol = if wide { 1e-15 * diss_scale } else { 0.0 };
                                assert!((got - diss_want).abs() <= tol, "{case}: {got} vs {diss_want}");
                            }
                        }
                    }
                }
                let lanes = dissipation_lanes::<true>(n, b, &c, &vb);
                let twin = dissipation_rows::<true>(n, b, &c, &vb, (0, [0.0; 4]));
                assert_eq!(dissipation_rows::<true>(n, b, &c, &vb, lanes).to_bits(), twin.to_bits(), "b {b}, n {n}");
            }
        }
    }

    /// The scalar twin is the band product it claims: against a dense sum over the symmetric
    /// matrices, to round-off.
    #[test]
    fn scalar_twin_is_the_band_product() {
        for b in [1, 3, 7] {
            let n = 29;
            let (m, c, k) = (band(n, b, 11), band(n, b, 12), band(n, b, 13));
            let (w1, w2, u) = (padded(n, b, 14), padded(n, b, 15), padded(n, b, 16));
            let entry = |a: &[f64], i: usize, j: usize| {
                let (hi, lo) = (i.max(j), i.min(j));
                if hi - lo > b {
                    0.0
                } else {
                    a[(hi - lo) * (n + b) + hi]
                }
            };
            for fma in builds() {
                let mut z = vec![0.0; n];
                if fma {
                    rhs_band_scalar::<true>(n, b, [&m, &c, &k], [&w1, &w2, &u], &mut z, false);
                } else {
                    rhs_band_scalar::<false>(n, b, [&m, &c, &k], [&w1, &w2, &u], &mut z, false);
                }
                for i in 0..n {
                    let want: f64 = (0..n)
                        .map(|j| entry(&m, i, j) * w1[b + j] + entry(&c, i, j) * w2[b + j] - entry(&k, i, j) * u[b + j])
                        .sum();
                    assert!((z[i] - want).abs() < 1e-13, "b {b}, row {i}: {} vs {want}", z[i]);
                }
            }
        }
    }
}
