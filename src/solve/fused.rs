//! The fast path of the Newmark family for linear systems.
//!
//! [`Newmark`](super::newmark::Newmark) does a step as the textbook writes it, through the
//! general CSR and profile kernels: every product walks column indices and every triangular
//! sweep runs loops of data-dependent length. Per degree of freedom a step is only about 60
//! flops, so index arithmetic, bounds checks and loop overhead, not the flops, set its cost.
//! This integrator does the same arithmetic on storage shaped for the beam:
//!
//! * The step solves for the **increment** Δu = u_{n+1} − u_n, not for u_{n+1}: the same
//!   arithmetic in exact terms, but the solver's relative round-off then falls on Δu, which
//!   the acceleration (Δu − Δt·v)/(βΔt²) amplifies ≈ 1/(βΔtω) rather than 1/(βΔt²ω²) times
//!   (≈ 30× more accurate on the paper beam, `tests/precision.rs`). Its right-hand side is
//!   M·w₁ + C·w₂ − K·u with w₁, w₂ the v and a terms of the history.
//! * M, C and K are stored by **diagonals** of a band of half-width B (3 for Hermite beam
//!   elements): the right-hand side is then one loop over rows whose body reads
//!   3·(2B+1) contiguous streams, which the compiler vectorises.
//! * The factor L·D·Lᵀ of the effective stiffness is stored **by rows of width B** with
//!   1/D; the forward and backward sweeps, which are recurrences and cannot be vectorised,
//!   are fully unrolled for B known at compile time, ordered so the newest unknown enters
//!   last (the critical path per row is one multiply–add), and use fused multiply–add where
//!   the processor has it. For B = 3 (every beam) they carry the last three unknowns in
//!   registers and finish four rows at a time, the Newmark update of those rows as vectors
//!   (`groups.rs`).
//! * The few rows that reach beyond the band (an actuator's body rows reach back to its
//!   feet) keep their extra entries in short side lists.
//! * Loads are sparse (actuators load a handful of DOFs), the dissipation v̄ᵀ·C·v̄ of the
//!   step is optional (and counted in the next step's right-hand side pass, which reads C
//!   anyway), and nothing in a step allocates.
//!
//! On x86-64 the step is compiled twice, for the baseline target and for AVX2 + FMA, and the
//! faster one is chosen at run time when the processor supports it (with AVX-512F, the band
//! right-hand side then takes eight rows at a time). The FMA version rounds
//! differently (a fused multiply–add rounds once), so the two agree to round-off, as does
//! this integrator with `Newmark` (`tests/newmark.rs`).

// The kernels index several arrays with one row index on purpose: that is the form the
// vectoriser and the reader both follow.
#![allow(clippy::needless_range_loop)]

use super::newmark::Scheme;
use crate::error::{Error, Result};
use crate::linalg::{Csr, Skyline};

mod groups;

/// A row of the factor that reaches back beyond the band: its columns `first..row − B`
/// are `tail[offset..]`.
#[derive(Clone, Copy, Debug)]
struct LongRow {
    row: usize,
    first: usize,
    offset: usize,
}

// The dot product and the scatter of a long row are called from every row of every sweep
// variant but run for a handful of rows a step (four for a frame actuator). Inlined, they
// grew the AVX2 step by 60 % (13,200 → 20,900 instructions) and slowed the rows that never
// take them: out of line, the step took 0.87 (bare beam) and 0.89 (frame system) of the
// time in alternating pairs (`scripts/paired.sh`), in a slow and a fast state of a shared
// host alike. So they are cold calls.
impl LongRow {
    /// Its entries in the columns `first..row − B`, from the side list `l_tail`.
    #[inline(always)]
    fn tail<'a>(&self, l_tail: &'a [f64], b: usize) -> &'a [f64] {
        &l_tail[self.offset..self.offset + (self.row - b - self.first)]
    }

    /// Σ_j L(row, j)·y_j over those columns, for the forward sweep (`y` padded by B in
    /// front). Four partial sums: one running sum would make the row a chain of dependent
    /// multiply–adds (a frame's leg-to-body rows span ≈ 45 columns).
    #[inline(always)]
    fn dot<const FMA: bool>(&self, l_tail: &[f64], b: usize, y: &[f64]) -> f64 {
        #[cfg(target_arch = "x86_64")]
        if FMA {
            // SAFETY: the FMA build runs only where AVX2 and FMA were detected (`dispatch`).
            return unsafe { self.dot_fma(l_tail, b, y) };
        }
        self.dot_plain(l_tail, b, y)
    }

    #[cfg(target_arch = "x86_64")]
    #[target_feature(enable = "avx2,fma")]
    #[cold]
    #[inline(never)]
    unsafe fn dot_fma(&self, l_tail: &[f64], b: usize, y: &[f64]) -> f64 {
        let tail = self.tail(l_tail, b);
        dot_lanes::<true>(tail, &y[self.first + b..self.first + b + tail.len()])
    }

    #[cold]
    #[inline(never)]
    fn dot_plain(&self, l_tail: &[f64], b: usize, y: &[f64]) -> f64 {
        let tail = self.tail(l_tail, b);
        dot_lanes::<false>(tail, &y[self.first + b..self.first + b + tail.len()])
    }

    /// x_j −= L(row, j)·x_row over those columns, for the backward sweep as soon as x_row
    /// is known (`x` unpadded). No fused multiply–add here, so one build serves both.
    #[cold]
    #[inline(never)]
    fn scatter(&self, l_tail: &[f64], b: usize, x: &mut [f64], x_row: f64) {
        for (t, &lv) in self.tail(l_tail, b).iter().enumerate() {
            x[self.first + t] -= lv * x_row;
        }
    }
}

/// An entry of M, C, K outside the band (lower triangle, i > j); applied symmetrically.
#[derive(Clone, Copy, Debug)]
struct Extra {
    i: usize,
    j: usize,
    m: f64,
    c: f64,
    k: f64,
}

/// The Newmark update of one row from its increment x = Δu: a, v, u, the step's mean
/// velocity v̄ (with `VBAR`: only the dissipation reads it) and the next step's history
/// terms w₁, w₂. The caller passes the solution vector itself as `vbar`: once the row is
/// updated its Δu is read no more, so v̄ stored there costs no stream of its own.
#[allow(clippy::too_many_arguments)]
#[inline(always)]
fn update_row<const FMA: bool, const VBAR: bool>(
    k: Coeffs,
    i: usize,
    x: f64,
    u: &mut [f64],
    v: &mut [f64],
    a: &mut [f64],
    vbar: &mut [f64],
    w1: &mut [f64],
    w2: &mut [f64],
) {
    let (ui, vi, ai) = (u[i], v[i], a[i]);
    let a_new = madd::<FMA>(x - k.dt * vi, k.ab, -k.a_old * ai);
    let v_new = madd::<FMA>(k.va_new, a_new, madd::<FMA>(k.va_old, ai, vi));
    let u_new = ui + x;
    u[i] = u_new;
    v[i] = v_new;
    a[i] = a_new;
    if VBAR {
        vbar[i] = 0.5 * (vi + v_new);
    }
    (w1[i], w2[i]) = k.history::<FMA>(u_new, v_new, a_new);
}

/// w₁, w₂ of every DOF from u, v, a: after `set_state`, before an update has written them.
#[inline(always)]
fn fill_history<const FMA: bool>(k: Coeffs, u: &[f64], v: &[f64], a: &[f64], w1: &mut [f64], w2: &mut [f64]) {
    for i in 0..v.len() {
        (w1[i], w2[i]) = k.history::<FMA>(u[i], v[i], a[i]);
    }
}

/// The band half-width as a type, so that fixed widths unroll.
trait Width: Copy {
    fn b(self) -> usize;
}
#[derive(Clone, Copy)]
struct Fixed<const B: usize>;
impl<const B: usize> Width for Fixed<B> {
    #[inline(always)]
    fn b(self) -> usize {
        B
    }
}
#[derive(Clone, Copy)]
struct Dynamic(usize);
impl Width for Dynamic {
    #[inline(always)]
    fn b(self) -> usize {
        self.0
    }
}

/// a·b + c, fused (one rounding) when compiled for a processor with FMA.
#[inline(always)]
fn madd<const FMA: bool>(a: f64, b: f64, c: f64) -> f64 {
    if FMA {
        a.mul_add(b, c)
    } else {
        a * b + c
    }
}

/// The step's coefficients: w₁ = c_v·v + c_a·a, w₂ = e_v·v + e_a·a + e_u·u, and the update
/// from the increment x = Δu: a_new = (x − Δt·v)·ab − a_old·a, v_new = v + va_old·a +
/// va_new·a_new. e_u is 0 but in the proportional form (`Coeffs::proportional`).
#[derive(Clone, Copy)]
struct Coeffs {
    cv: f64,
    ca: f64,
    ev: f64,
    ea: f64,
    eu: f64,
    dt: f64,
    ab: f64,
    a_old: f64,
    va_old: f64,
    va_new: f64,
}

impl Coeffs {
    /// The history terms (w₁, w₂) of one DOF with velocity v and acceleration a. They are
    /// those of the whole displacement less K_eff·u_n's: u enters the increment's
    /// right-hand side only through −K·u.
    #[inline(always)]
    fn history<const FMA: bool>(self, u: f64, v: f64, a: f64) -> (f64, f64) {
        (madd::<FMA>(self.cv, v, self.ca * a), madd::<FMA>(self.ev, v, madd::<FMA>(self.ea, a, self.eu * u)))
    }

    /// The history terms of the proportional form (see [`Proportional`]): with
    /// C = a₀·M + a₁·K + R, M·w₁ + C·w₂ − K·u = M·(w₁ + a₀·w₂) − K·(u − a₁·w₂) + R·w₂, so the
    /// update writes w₁' = w₁ + a₀·w₂ and w₂' = u − a₁·w₂ and the band sees no C.
    fn proportional(self, a0: f64, a1: f64) -> Self {
        Coeffs {
            cv: self.cv + a0 * self.ev,
            ca: self.ca + a0 * self.ea,
            ev: -a1 * self.ev,
            ea: -a1 * self.ea,
            eu: 1.0,
            ..self
        }
    }

    /// The coefficients of a scheme at step Δt (s).
    fn new(s: Scheme, dt: f64) -> Self {
        let (am, af, g, b) = (s.alpha_m, s.alpha_f, s.gamma, s.beta);
        let cu = (1.0 - am) / (b * dt * dt);
        Coeffs {
            cv: cu * dt,
            ca: (1.0 - am) * (0.5 / b - 1.0) - am,
            ev: -(1.0 - af) * (1.0 - g / b) - af,
            ea: -(1.0 - af) * dt * (1.0 - 0.5 * g / b),
            eu: 0.0,
            dt,
            ab: 1.0 / (b * dt * dt),
            a_old: 0.5 / b - 1.0,
            va_old: dt * (1.0 - g),
            va_new: dt * g,
        }
    }
}

/// Widest band whose right-hand side runs on per-diagonal slices (vectorised).
const MAX_SLICED: usize = 5;

/// Systems at most this large whose band covers half the matrix are stepped densely.
const DENSE_LIMIT: usize = 48;

/// The step of a small dense system as Δu = x = K_eff⁻¹·F + (K_eff⁻¹M)·w₁ + (K_eff⁻¹C)·w₂ −
/// (K_eff⁻¹K)·u, each operator from solves with the factor. A modal-reduced model is
/// dense by construction, and for it independent multiply–adds beat two triangular sweeps
/// whose every row waits on the previous one. The operators are stored side by side by
/// rows, [K_eff⁻¹M | K_eff⁻¹C | K_eff⁻¹K], each row padded to a multiple of four, so that
/// row i of x is one dot product with w = [w₁ | w₂ | −u] over lanes of four and the n
/// rows are independent of each other.
#[derive(Clone, Debug)]
struct DenseStep {
    /// C by rows (padded like `ops`), for the dissipation.
    c: Vec<f64>,
    /// Padded length of a row of `c` (n rounded up to four).
    c_stride: usize,
    /// [K_eff⁻¹M | K_eff⁻¹C | K_eff⁻¹K] by rows, `stride` numbers per row.
    ops: Vec<f64>,
    stride: usize,
    /// w = [w₁ | w₂ | −u] of the step in progress, zero-padded to `stride`.
    w: Vec<f64>,
    /// K_eff⁻¹ column-major, for loads given as sparse pairs.
    a: Vec<f64>,
}

/// Σ aᵢ·bᵢ over a (b at least as long) in four lanes (lane l takes the terms i ≡ l mod 4),
/// summed as (l₀ + l₁) + (l₂ + l₃): the rounding of `gemv_avx2` when the length is a
/// multiple of four; four independent chains rather than one for a long row of the factor.
#[inline(always)]
fn dot_lanes<const FMA: bool>(a: &[f64], b: &[f64]) -> f64 {
    let b = &b[..a.len()];
    let mut acc = [0.0f64; 4];
    let (ac, bc) = (a.chunks_exact(4), b.chunks_exact(4));
    let (ar, br) = (ac.remainder(), bc.remainder());
    for (x, y) in ac.zip(bc) {
        for l in 0..4 {
            acc[l] = madd::<FMA>(x[l], y[l], acc[l]);
        }
    }
    for (l, (x, y)) in ar.iter().zip(br).enumerate() {
        acc[l] = madd::<FMA>(*x, *y, acc[l]);
    }
    (acc[0] + acc[1]) + (acc[2] + acc[3])
}

/// out = A·w for a row-major A with `stride` numbers per row (a multiple of four), at least
/// out.len() rounded up to four rows (zero rows past the end), and w of length ≥ stride. Each
/// row is `dot_lanes` of the row and w, so every build rounds the same way up to fused
/// multiply–adds.
#[inline(always)]
fn gemv<const FMA: bool>(a: &[f64], stride: usize, w: &[f64], out: &mut [f64]) {
    assert!(stride.is_multiple_of(4) && w.len() >= stride && a.len() >= out.len().next_multiple_of(4) * stride);
    #[cfg(target_arch = "x86_64")]
    if FMA {
        // SAFETY: the FMA build of the step runs only inside `step_avx2`, which is called
        // only when the processor reports AVX2 and FMA; the sizes are checked above.
        return unsafe { gemv_avx2(a, stride, w, out) };
    }
    for (i, o) in out.iter_mut().enumerate() {
        *o = dot_lanes::<FMA>(&a[i * stride..(i + 1) * stride], &w[..stride]);
    }
}

/// `gemv` four rows at a time: four independent accumulators share each load of w, and
/// one horizontal reduction yields four results.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2,fma")]
unsafe fn gemv_avx2(a: &[f64], stride: usize, w: &[f64], out: &mut [f64]) {
    use std::arch::x86_64::*;
    let n = out.len();
    let (pa, pw) = (a.as_ptr(), w.as_ptr());
    let mut i = 0;
    while i < n {
        let r = pa.add(i * stride);
        let (mut a0, mut a1, mut a2, mut a3) =
            (_mm256_setzero_pd(), _mm256_setzero_pd(), _mm256_setzero_pd(), _mm256_setzero_pd());
        let mut k = 0;
        while k < stride {
            let x = _mm256_loadu_pd(pw.add(k));
            a0 = _mm256_fmadd_pd(_mm256_loadu_pd(r.add(k)), x, a0);
            a1 = _mm256_fmadd_pd(_mm256_loadu_pd(r.add(stride + k)), x, a1);
            a2 = _mm256_fmadd_pd(_mm256_loadu_pd(r.add(2 * stride + k)), x, a2);
            a3 = _mm256_fmadd_pd(_mm256_loadu_pd(r.add(3 * stride + k)), x, a3);
            k += 4;
        }
        let sum = row_sums4([a0, a1, a2, a3]);
        if i + 4 <= n {
            _mm256_storeu_pd(out.as_mut_ptr().add(i), sum);
        } else {
            // The last, partial group, lane by lane with explicit stores (a copy loop of
            // variable length is turned into a call to memcpy).
            let (lo, hi) = (_mm256_castpd256_pd128(sum), _mm256_extractf128_pd(sum, 1));
            let o = out.as_mut_ptr().add(i);
            _mm_storel_pd(o, lo);
            if n - i > 1 {
                _mm_storeh_pd(o.add(1), lo);
            }
            if n - i > 2 {
                _mm_storel_pd(o.add(2), hi);
            }
        }
        i += 4;
    }
}

/// The four lanes of each of four accumulators summed as (l₀ + l₁) + (l₂ + l₃), for four
/// rows at once: lane r of the result is accumulator r's sum.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2,fma")]
#[inline]
unsafe fn row_sums4(acc: [std::arch::x86_64::__m256d; 4]) -> std::arch::x86_64::__m256d {
    use std::arch::x86_64::*;
    // [l0+l1, l2+l3] of each accumulator, interleaved by pairs, then the two halves added.
    let h01 = _mm256_hadd_pd(acc[0], acc[1]);
    let h23 = _mm256_hadd_pd(acc[2], acc[3]);
    _mm256_add_pd(_mm256_permute2f128_pd(h01, h23, 0x20), _mm256_permute2f128_pd(h01, h23, 0x31))
}

/// out[i] = (rowᵢ·u, rowᵢ·v, rowᵢ·a) for a row-major A as in `gemv` (zero rows up to a
/// multiple of four) and u, v, a of length ≥ stride: the three products of each row in one
/// pass over A, each rounded as `dot_lanes`.
fn gemv3<const FMA: bool>(a: &[f64], stride: usize, u: &[f64], v: &[f64], acc: &[f64], out: &mut [[f64; 3]]) {
    assert!(stride.is_multiple_of(4) && a.len() >= out.len().next_multiple_of(4) * stride);
    assert!(u.len() >= stride && v.len() >= stride && acc.len() >= stride);
    #[cfg(target_arch = "x86_64")]
    if FMA {
        // SAFETY: as in `gemv`; the sizes are checked above.
        return unsafe { gemv3_avx2(a, stride, [u, v, acc], out) };
    }
    for (i, o) in out.iter_mut().enumerate() {
        let row = &a[i * stride..(i + 1) * stride];
        *o = [dot_lanes::<FMA>(row, u), dot_lanes::<FMA>(row, v), dot_lanes::<FMA>(row, acc)];
    }
}

/// `gemv3` four rows at a time: each load of a row's four entries serves u, v and a, twelve
/// accumulators in all.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2,fma")]
unsafe fn gemv3_avx2(a: &[f64], stride: usize, x: [&[f64]; 3], out: &mut [[f64; 3]]) {
    use std::arch::x86_64::*;
    let n = out.len();
    let pa = a.as_ptr();
    let px = [x[0].as_ptr(), x[1].as_ptr(), x[2].as_ptr()];
    let mut i = 0;
    while i < n {
        let r = pa.add(i * stride);
        let mut acc = [[_mm256_setzero_pd(); 4]; 3];
        let mut k = 0;
        while k < stride {
            let xs = [_mm256_loadu_pd(px[0].add(k)), _mm256_loadu_pd(px[1].add(k)), _mm256_loadu_pd(px[2].add(k))];
            for row in 0..4 {
                let g = _mm256_loadu_pd(r.add(row * stride + k));
                for q in 0..3 {
                    acc[q][row] = _mm256_fmadd_pd(g, xs[q], acc[q][row]);
                }
            }
            k += 4;
        }
        let mut sums = [[0.0f64; 4]; 3];
        for q in 0..3 {
            _mm256_storeu_pd(sums[q].as_mut_ptr(), row_sums4(acc[q]));
        }
        for row in 0..4.min(n - i) {
            *out.get_unchecked_mut(i + row) = [sums[0][row], sums[1][row], sums[2][row]];
        }
        i += 4;
    }
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
const RUN_LANES: usize = 8;

/// Shortest periodic run worth its own loop, in groups.
const MIN_RUN_GROUPS: usize = 4;

/// Rows `start..end` (whole groups of a kernel's lanes) in which every group of the band
/// right-hand side loads the same values of M, C and K as the first. A segment of equal
/// elements makes its rows repeat with period two (w and θ rows), so there the
/// step reads one group's copy, which stays in L1, instead of streaming the 3·(B+1)
/// diagonals. The values are exactly those of the band storage, so the result is the same
/// to the bit (`tests/newmark.rs`).
#[derive(Clone, Debug)]
struct PeriodicRun {
    start: usize,
    end: usize,
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
    fn find(n: usize, b: usize, [m, c, k]: [&[f64]; 3], lanes: usize) -> Vec<PeriodicRun> {
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

/// Rows `start..end` of the factor whose rows (B entries of L and 1/d) repeat with period
/// two, bit for bit: the factorisation of a segment of equal elements converges to such a
/// pattern after a transient of a few hundred to some ten thousand rows (longer the finer
/// the mesh), and there the sweeps read the pattern instead of streaming L and 1/d.
#[derive(Clone, Debug)]
struct FactorRun {
    start: usize,
    end: usize,
    /// Row r's entries L(r, r − 3 + s), s ∈ 0..3, negated, and 1/d_r, for r even and odd.
    l_neg: [[f64; 3]; 2],
    d_inv: [f64; 2],
    /// For the backward sweep at a row of each parity: −L(i + s, i) at s ∈ 1..=3 (0 unused).
    up_neg: [[f64; 4]; 2],
}

impl FactorRun {
    /// The runs of at least `MIN_FACTOR_RUN` rows in factor rows `l` (B per row) and `d_inv`,
    /// none of them a long row. Only for B = 3, the beam's width, which the grouped sweeps
    /// (`groups.rs`), the only readers of the runs, handle.
    fn find(n: usize, b: usize, l: &[f64], d_inv: &[f64], long: &[LongRow]) -> Vec<FactorRun> {
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
/// With `RAY` (the proportional form, [`Proportional`]) the right-hand side is M·w₁ − K·u
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

/// Largest system whose band right-hand side runs on 512-bit vectors. Above it the state
/// streams from main memory, where on an AMD EPYC (Zen 5) VM the 512-bit kernel took
/// twice the 256-bit one's time (the whole step 5 % slower at 4·10⁵ DOFs, 18 % at 2·10⁶,
/// in alternating pairs; 5 % faster at 2·10⁵ and 4 % at 3·10⁵), and on an Intel Xeon VM
/// the two were equal there. Software prefetching and 64-byte-aligned vectors did not
/// change it.
const WIDE_RHS_MAX_DOFS: usize = 300_000;

/// Whether the processor has AVX-512F.
fn wide_vectors() -> bool {
    #[cfg(target_arch = "x86_64")]
    {
        std::arch::is_x86_feature_detected!("avx512f")
    }
    #[cfg(not(target_arch = "x86_64"))]
    false
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

/// A linear system's Newmark integrator on band storage.
#[derive(Clone)]
pub struct FusedNewmark {
    scheme: Scheme,
    dt: f64,
    n: usize,
    b: usize,
    /// Lower diagonal t ∈ 0..=B of M at `m[t·(n + B) + i]` = M(i, i − t) (zero where
    /// i < t and for the B padding entries past n); the upper half is the same numbers.
    m: Vec<f64>,
    c: Vec<f64>,
    /// K by diagonals, for the increment's −K·u_n.
    k: Vec<f64>,
    extra: Vec<Extra>,
    /// Row i of L at `l[i·B + s]` = L(i, i − B + s) (zero before column 0; B zero rows
    /// follow the last).
    l: Vec<f64>,
    long: Vec<LongRow>,
    l_tail: Vec<f64>,
    d_inv: Vec<f64>,
    /// u_i at B + i, with B zeros before and padding after (see `new`).
    u: Vec<f64>,
    v: Vec<f64>,
    a: Vec<f64>,
    /// w₁, w₂, padded with B zeros at both ends.
    w1: Vec<f64>,
    w2: Vec<f64>,
    /// Right-hand side then y (forward sweep), padded with B leading zeros.
    z: Vec<f64>,
    /// y/d, then Δu as the backward sweep finishes each row, then, once a row is updated,
    /// the step's mean velocity v̄ (u takes u + Δu); padded with B zeros before and B + 4
    /// after, so that the sweep's and the dense step's dissipation's reads past n are zeros.
    x: Vec<f64>,
    /// Dense load of the step in progress, zero except at the DOFs just loaded.
    load: Vec<f64>,
    touched: Vec<usize>,
    /// F_n, kept for α_f ≠ 0.
    f_prev: Vec<(usize, f64)>,
    fma: bool,
    /// 512-bit vectors for the band right-hand side (within the AVX2 build; only up to
    /// `WIDE_RHS_MAX_DOFS`).
    avx512: bool,
    /// Periodic runs of the band right-hand side for groups of four and of eight rows, of
    /// the factor's rows, and whether the step uses them (see [`PeriodicRun`],
    /// [`FactorRun`]).
    runs4: Vec<PeriodicRun>,
    runs8: Vec<PeriodicRun>,
    factor_runs: Vec<FactorRun>,
    /// The grouped sweeps' row pairs (`groups.rs`).
    pairs: groups::PairRows,
    use_runs: bool,
    /// Whether the sweeps run in groups of four rows (`groups.rs`) where the band allows.
    use_groups: bool,
    /// For small dense systems (modal-reduced models), the step as dense products.
    dense: Option<DenseStep>,
    /// Registered load patterns b_a (see `set_load_patterns`), K_eff⁻¹·b_a for the dense
    /// step, and the pattern weights of the step in progress (α_f-blended) and of F_n.
    patterns: Vec<Vec<(usize, f64)>>,
    patterns_solved: Vec<Vec<f64>>,
    weights: Vec<f64>,
    weights_prev: Vec<f64>,
    use_weights: bool,
    /// w₁, w₂ already hold the next step's history terms (the update writes them while it
    /// has u, v, a in registers); false after `set_state`.
    w_ready: bool,
    /// Accumulate the dissipated energy Σ Δt·v̄ᵀ·C·v̄ (v̄ each step's mean velocity), read
    /// by `dissipated`.
    pub track_dissipation: bool,
    /// Σ v̄ᵀ·C·v̄ over the steps counted so far (without the factor Δt).
    diss_sum: f64,
    /// `x` holds the v̄ of a step not yet in `diss_sum`: the band step counts it in the next
    /// step's right-hand side pass, which reads C's diagonals anyway, or in `dissipated`.
    diss_pending: bool,
    /// Registered read-outs (see `set_observations`) and their latest values.
    observations: Observations,
    /// The step's coefficients, fixed by the scheme and Δt (and the proportional form).
    coeffs: Coeffs,
    /// The proportional form of the right-hand side, when switched on.
    proportional: Option<Proportional>,
}

/// C = a₀·M + a₁·K + R with R sparse: Rayleigh damping of the structure, plus the dashpots,
/// masses and springs it does not cover (an actuator's links and body, point masses,
/// supports). Then M·w₁ + C·w₂ − K·u = M·(w₁ + a₀·w₂) − K·(u − a₁·w₂) + R·w₂: the update
/// writes the two combined vectors instead of w₁ and w₂ (`Coeffs::proportional`), and the
/// band right-hand side has two products instead of three, with R's few entries added
/// after it. C's diagonals are then read only for the dissipation, which keeps using C
/// itself.
#[derive(Clone, Debug)]
struct Proportional {
    /// R's entries (i ≥ j; applied symmetrically).
    residual: Vec<(usize, usize, f64)>,
    /// The scheme's w₂ = e_v·v + e_a·a, which R multiplies.
    ev: f64,
    ea: f64,
}

/// An entry of C − a₀·M − a₁·K below this fraction of |C| + |a₀·M| + |a₁·K| (a few
/// units of round-off) counts as zero. With the coefficients the damping was assembled
/// from, the structure's entries come out exactly zero (measured on the paper beam, the
/// frame and inertial cases, 1,000 elements and an irregular 333-element mesh), so this
/// only allows for another assembly order. It must stay that tight: C's entries are
/// dominated by a₁·K, so a coefficient a₀ off by δ leaves entries of only ≈ 1e-7·δ of |C|
/// on the paper beam, yet it is a mass-proportional change that the lowest modes feel in
/// full; such a remainder must be kept (and then declines the form), not dropped.
const PROPORTIONAL_ROUND_OFF: f64 = 1e-15;

/// Read-outs gᵀ·(u, v, a) of the state evaluated after every step, while the state is in
/// cache: the analyses' links, feet, drives and sensors. A row with many entries (every row
/// of a modal-reduced model) is kept dense and read over lanes; short rows stay pairs.
#[derive(Clone, Debug, Default)]
struct Observations {
    /// Dense rows, `stride` (n rounded up to four) numbers each, zero rows up to a multiple
    /// of four, and the observation each belongs to.
    dense: Vec<f64>,
    stride: usize,
    dense_index: Vec<usize>,
    /// The dense rows' products with u, v and a.
    products: Vec<[f64; 3]>,
    /// Short rows as (observation, pairs).
    sparse: Vec<(usize, Vec<(usize, f64)>)>,
    /// (gᵀu, gᵀv, gᵀa) per observation.
    values: Vec<[f64; 3]>,
}

/// Rows with at least this many entries are read densely.
const DENSE_OBSERVATION: usize = 8;

impl FusedNewmark {
    /// Sets up the integrator and factorises the effective stiffness. `envelope` must cover
    /// the patterns of M, C and K.
    pub fn new(m: &Csr, c: &Csr, k: &Csr, envelope: &[usize], scheme: Scheme, dt: f64) -> Result<Self> {
        if !(dt > 0.0 && dt.is_finite()) {
            return Err(Error::Numerical(format!("time step must be positive, got {dt}")));
        }
        let n = m.dim();
        let s = scheme;
        let mut k_eff = Skyline::<f64>::zeros(envelope.to_vec());
        k.add_into_skyline(1.0 - s.alpha_f, &mut k_eff);
        c.add_into_skyline((1.0 - s.alpha_f) * s.gamma / (s.beta * dt), &mut k_eff);
        m.add_into_skyline((1.0 - s.alpha_m) / (s.beta * dt * dt), &mut k_eff);
        let factor = k_eff.factorize()?;
        let (first, start, lv, d) = factor.clone().into_parts();

        // Band half-width: covers nine rows in ten; the rest get side lists.
        let mut widths: Vec<usize> = first.iter().enumerate().map(|(i, &f)| i - f).collect();
        widths.sort_unstable();
        let b = widths.get((n * 9) / 10).copied().unwrap_or(0);

        // B rows of zeros past the end, so the backward sweep's gathers need no bounds.
        let mut l = vec![0.0; (n + b) * b];
        let mut long = Vec::new();
        let mut l_tail = Vec::new();
        for i in 0..n {
            let row = &lv[start[i]..start[i + 1] - 1];
            for (t, &val) in row.iter().enumerate() {
                let j = first[i] + t;
                if j + b >= i {
                    l[i * b + (j + b - i)] = val;
                } else {
                    if long.last().map(|lr: &LongRow| lr.row) != Some(i) {
                        long.push(LongRow { row: i, first: j, offset: l_tail.len() });
                    }
                    l_tail.push(val);
                }
            }
        }
        let mut extra: Vec<Extra> = Vec::new();
        let mut dia = |a: &Csr, which: usize| {
            let mut out = vec![0.0; (b + 1) * (n + b)];
            for (i, j, v) in a.triplets() {
                if j <= i && i - j <= b {
                    out[(i - j) * (n + b) + i] = v;
                } else if i > j + b {
                    let e = match extra.iter().position(|e| e.i == i && e.j == j) {
                        Some(p) => &mut extra[p],
                        None => {
                            extra.push(Extra { i, j, m: 0.0, c: 0.0, k: 0.0 });
                            extra.last_mut().unwrap()
                        }
                    };
                    *[&mut e.m, &mut e.c, &mut e.k][which] = v;
                }
            }
            out
        };
        let (mm, cc, kk) = (dia(m, 0), dia(c, 1), dia(k, 2));
        let runs = |lanes| PeriodicRun::find(n, b, [&mm, &cc, &kk], lanes);
        let (runs4, runs8) = (runs(4), runs(8));
        let d_inv: Vec<f64> = d.iter().map(|x| 1.0 / x).collect();
        let factor_runs = FactorRun::find(n, b, &l, &d_inv, &long);
        let pairs = groups::PairRows::new(n, b, &l);
        extra.sort_by_key(|e| (e.i, e.j));
        let dense = (n <= DENSE_LIMIT && 2 * b >= n).then(|| {
            let column = |a: Option<&Csr>, j: usize| {
                let mut x = vec![0.0; n];
                match a {
                    Some(a) => (0..n).for_each(|i| x[i] = a.get(i, j)),
                    None => x[j] = 1.0,
                }
                factor.solve_in_place(&mut x);
                x
            };
            let blocks = [m, c, k];
            let stride = (blocks.len() * n).next_multiple_of(4);
            let rows = n.next_multiple_of(4);
            let mut ops = vec![0.0; rows * stride];
            for (q, a) in blocks.iter().enumerate() {
                for j in 0..n {
                    for (i, x) in column(Some(a), j).into_iter().enumerate() {
                        ops[i * stride + q * n + j] = x;
                    }
                }
            }
            let c_stride = n.next_multiple_of(4);
            let mut cr = vec![0.0; rows * c_stride];
            for i in 0..n {
                for j in 0..n {
                    cr[i * c_stride + j] = c.get(i, j);
                }
            }
            DenseStep {
                c: cr,
                c_stride,
                ops,
                stride,
                w: vec![0.0; stride],
                a: (0..n).flat_map(|j| column(None, j)).collect(),
            }
        });
        #[cfg(target_arch = "x86_64")]
        let fma = std::arch::is_x86_feature_detected!("avx2") && std::arch::is_x86_feature_detected!("fma");
        #[cfg(not(target_arch = "x86_64"))]
        let fma = false;
        Ok(FusedNewmark {
            scheme,
            dt,
            n,
            b,
            m: mm,
            c: cc,
            k: kk,
            extra,
            l,
            long,
            l_tail,
            d_inv,
            // u_i at index B + i: B zeros before, where the right-hand side's −K·u reads
            // them as the band's shifted copies, and after it zero padding to B past n and to
            // a multiple of four, so dense read-outs run over whole lanes.
            u: vec![0.0; b + (n + b).next_multiple_of(4)],
            v: vec![0.0; n.next_multiple_of(4)],
            a: vec![0.0; n.next_multiple_of(4)],
            w1: vec![0.0; n + 2 * b],
            w2: vec![0.0; n + 2 * b],
            z: vec![0.0; n + b],
            x: vec![0.0; n + 2 * b + 4],
            load: vec![0.0; n],
            touched: Vec::new(),
            f_prev: Vec::new(),
            fma,
            avx512: fma && wide_vectors() && n <= WIDE_RHS_MAX_DOFS,
            runs4,
            runs8,
            factor_runs,
            pairs,
            use_runs: true,
            use_groups: true,
            dense,
            patterns: Vec::new(),
            patterns_solved: Vec::new(),
            weights: Vec::new(),
            weights_prev: Vec::new(),
            use_weights: false,
            w_ready: false,
            track_dissipation: false,
            diss_sum: 0.0,
            diss_pending: false,
            observations: Observations::default(),
            coeffs: Coeffs::new(scheme, dt),
            proportional: None,
        })
    }

    pub fn dt(&self) -> f64 {
        self.dt
    }

    pub fn dim(&self) -> usize {
        self.n
    }

    /// Half-width of the band part of the storage (rows reaching further have side lists).
    pub fn band_width(&self) -> usize {
        self.b
    }

    /// Bytes held by the integrator (matrices, factor, state and work vectors): linear in
    /// the number of DOFs, since everything is stored by band.
    pub fn memory_bytes(&self) -> usize {
        let f = std::mem::size_of::<f64>();
        let vecs = [&self.m, &self.c, &self.k, &self.l, &self.l_tail, &self.d_inv, &self.u, &self.v, &self.a]
            .iter()
            .chain([&self.w1, &self.w2, &self.z, &self.x, &self.load].iter())
            .map(|v| v.len())
            .sum::<usize>();
        (vecs + self.pairs.len()) * f
            + self.extra.len() * std::mem::size_of::<Extra>()
            + self.long.len() * std::mem::size_of::<LongRow>()
    }

    /// Whether the step runs as dense products (small dense systems).
    pub fn is_dense(&self) -> bool {
        self.dense.is_some()
    }

    /// Whether the AVX2 + FMA build of the step is in use.
    pub fn uses_fma(&self) -> bool {
        self.fma
    }

    /// Uses the baseline build of the step even where FMA is available (to compare them).
    pub fn disable_fma(&mut self) {
        self.fma = false;
        self.avx512 = false;
    }

    /// Streams M and C from the band storage even in periodic runs (the reference the runs
    /// are tested against).
    pub fn disable_periodic_runs(&mut self) {
        self.use_runs = false;
    }

    /// Sweeps row by row even where the band allows groups of four rows (the reference the
    /// grouped sweeps are tested against).
    pub fn disable_grouped_sweeps(&mut self) {
        self.use_groups = false;
    }

    /// Rows whose right-hand side reads M and C from a periodic run rather than the band
    /// (for the widest kernel this processor runs); zero in the baseline build.
    pub fn periodic_rows(&self) -> usize {
        let runs = if self.avx512 { &self.runs8 } else { &self.runs4 };
        if self.use_runs && self.fma && self.dense.is_none() {
            runs.iter().map(|r| r.end - r.start).sum()
        } else {
            0
        }
    }

    /// Rows whose forward sweep reads the factor from a periodic run rather than the band
    /// (every build, in the grouped sweeps; the backward sweep, which also needs the B rows
    /// below, a few fewer).
    pub fn periodic_factor_rows(&self) -> usize {
        if self.use_runs && self.use_groups && self.dense.is_none() {
            self.factor_runs.iter().map(|r| r.end - r.start).sum()
        } else {
            0
        }
    }

    /// Uses the proportional form of the right-hand side (see [`Proportional`]) for
    /// C = a₀·M + a₁·K + R, where R is what Rayleigh damping with a₀ (1/s) and a₁ (s) leaves
    /// out: one band product fewer a step (the dissipation still reads C). Returns whether
    /// it is in use: not for the dense step (small reduced models) nor where R would be
    /// more than a few entries a row (the three products are then kept, or restored if an
    /// earlier call had switched the form on). It takes effect from the next step on.
    pub fn use_proportional_damping(&mut self, a0: f64, a1: f64) -> bool {
        self.disable_proportional_damping();
        if self.dense.is_some() || !(a0.is_finite() && a1.is_finite()) {
            return false;
        }
        let (n, b) = (self.n, self.b);
        let stride = n + b;
        let mut residual = Vec::new();
        let mut keep = |i: usize, j: usize, m: f64, c: f64, k: f64| {
            let r = c - a0 * m - a1 * k;
            if r.abs() > PROPORTIONAL_ROUND_OFF * (c.abs() + (a0 * m).abs() + (a1 * k).abs()) {
                residual.push((i, j, r));
            }
        };
        for t in 0..=b {
            for i in t..n {
                let o = t * stride + i;
                keep(i, i - t, self.m[o], self.c[o], self.k[o]);
            }
        }
        for e in &self.extra {
            keep(e.i, e.j, e.m, e.c, e.k);
        }
        if residual.len() > n / 8 + 64 {
            return false;
        }
        let k = Coeffs::new(self.scheme, self.dt);
        self.proportional = Some(Proportional { residual, ev: k.ev, ea: k.ea });
        self.coeffs = k.proportional(a0, a1);
        self.w_ready = false;
        true
    }

    /// Whether the right-hand side runs in the proportional form.
    pub fn uses_proportional_damping(&self) -> bool {
        self.proportional.is_some()
    }

    /// Back to the three-product right-hand side (the reference the proportional form is
    /// tested against); from the next step on.
    pub fn disable_proportional_damping(&mut self) {
        if self.proportional.take().is_some() {
            self.coeffs = Coeffs::new(self.scheme, self.dt);
            self.w_ready = false;
        }
    }

    /// Keeps the AVX2 build to 256-bit vectors even where AVX-512 is available.
    pub fn disable_avx512(&mut self) {
        self.avx512 = false;
    }

    /// Whether the band right-hand side uses 512-bit vectors (AVX-512F and at most
    /// `WIDE_RHS_MAX_DOFS` rows).
    pub fn uses_avx512(&self) -> bool {
        self.avx512
    }

    /// Displacement, velocity and acceleration at the current time.
    pub fn u(&self) -> &[f64] {
        &self.u[self.b..self.b + self.n]
    }
    pub fn v(&self) -> &[f64] {
        &self.v[..self.n]
    }
    pub fn a(&self) -> &[f64] {
        &self.a[..self.n]
    }

    /// Starts from displacement u₀, velocity v₀ and acceleration a₀ (which should be the
    /// consistent one, M⁻¹·(F₀ − C·v₀ − K·u₀)), with load F₀ as sparse pairs.
    pub fn set_state(&mut self, u0: &[f64], v0: &[f64], a0: &[f64], f0: &[(usize, f64)]) {
        self.u[self.b..self.b + self.n].copy_from_slice(u0);
        self.v[..self.n].copy_from_slice(v0);
        self.a[..self.n].copy_from_slice(a0);
        self.w_ready = false;
        self.diss_sum = 0.0;
        self.diss_pending = false;
        self.f_prev.clear();
        self.f_prev.extend_from_slice(f0);
        self.observe_dispatch();
    }

    /// Registers read-outs: row r is gᵣ as sparse pairs (duplicates summed). After
    /// `set_observations`, `set_state` and every step, `observed()[r]` holds
    /// (gᵣᵀu, gᵣᵀv, gᵣᵀa).
    pub fn set_observations(&mut self, rows: &[Vec<(usize, f64)>]) {
        let n = self.n;
        let stride = n.next_multiple_of(4);
        let mut o = Observations { values: vec![[0.0; 3]; rows.len()], stride, ..Default::default() };
        for (r, g) in rows.iter().enumerate() {
            if g.len() >= DENSE_OBSERVATION {
                let mut row = vec![0.0; stride];
                for &(d, c) in g {
                    row[d] += c;
                }
                o.dense.extend(row);
                o.dense_index.push(r);
            } else {
                o.sparse.push((r, g.clone()));
            }
        }
        o.dense.resize(o.dense_index.len().next_multiple_of(4) * stride, 0.0);
        o.products = vec![[0.0; 3]; o.dense_index.len()];
        self.observations = o;
        self.observe_dispatch();
    }

    /// (gᵣᵀu, gᵣᵀv, gᵣᵀa) of each registered read-out at the current state.
    pub fn observed(&self) -> &[[f64; 3]] {
        &self.observations.values
    }

    fn observe_dispatch(&mut self) {
        #[cfg(target_arch = "x86_64")]
        if self.fma {
            // SAFETY: `fma` is set only when the processor reports AVX2 and FMA.
            return unsafe { self.observe_avx2() };
        }
        self.observe::<false>();
    }

    #[cfg(target_arch = "x86_64")]
    #[target_feature(enable = "avx2,fma")]
    unsafe fn observe_avx2(&mut self) {
        self.observe::<true>();
    }

    #[inline(always)]
    fn observe<const FMA: bool>(&mut self) {
        let n = self.n;
        let o = &mut self.observations;
        if o.values.is_empty() {
            return;
        }
        if !o.dense_index.is_empty() {
            // u, v, a carry zero padding up to `stride`.
            gemv3::<FMA>(&o.dense, o.stride, &self.u[self.b..], &self.v, &self.a, &mut o.products);
            for (&r, &p) in o.dense_index.iter().zip(&o.products) {
                o.values[r] = p;
            }
        }
        let (u, v, a) = (&self.u[self.b..self.b + n], &self.v[..n], &self.a[..n]);
        for (r, g) in &o.sparse {
            let mut val = [0.0; 3];
            for &(d, c) in g {
                val = [madd::<FMA>(c, u[d], val[0]), madd::<FMA>(c, v[d], val[1]), madd::<FMA>(c, a[d], val[2])];
            }
            o.values[*r] = val;
        }
    }

    /// Registers load patterns b_a (sparse, on the system's DOFs) for `step_weighted`, whose
    /// load is Σ_a b_a·weight_a: the actuators' drives. For a dense system K_eff⁻¹·b_a is
    /// computed once, so a step's load costs n multiply–adds per pattern.
    pub fn set_load_patterns(&mut self, patterns: Vec<Vec<(usize, f64)>>) {
        let n = self.n;
        self.patterns_solved = match &self.dense {
            Some(ops) => patterns
                .iter()
                .map(|b| {
                    let mut x = vec![0.0; n];
                    for &(d, c) in b {
                        for i in 0..n {
                            x[i] += ops.a[d * n + i] * c;
                        }
                    }
                    x
                })
                .collect(),
            None => Vec::new(),
        };
        self.weights = vec![0.0; patterns.len()];
        self.weights_prev = vec![0.0; patterns.len()];
        self.patterns = patterns;
    }

    /// Sets the weights of F_n (the current load) for α_f schemes; see `set_load_patterns`.
    pub fn set_previous_weights(&mut self, w: &[f64]) {
        self.weights_prev.copy_from_slice(w);
    }

    /// Advances one step to the load F_{n+1} = Σ_a b_a·wₐ of the registered patterns.
    pub fn step_weighted(&mut self, w: &[f64]) {
        assert_eq!(w.len(), self.patterns.len(), "one weight per registered load pattern");
        let af = self.scheme.alpha_f;
        for a in 0..w.len() {
            self.weights[a] = (1.0 - af) * w[a] + af * self.weights_prev[a];
            self.weights_prev[a] = w[a];
        }
        if self.dense.is_none() {
            for (b, &wa) in self.patterns.iter().zip(&self.weights) {
                for &(d, c) in b {
                    self.load[d] += c * wa;
                    self.touched.push(d);
                }
            }
        }
        // F_n of the pattern weights is kept in `weights_prev`; `step` leaves `f_prev` alone.
        self.use_weights = true;
        self.step(&[]);
        self.use_weights = false;
    }

    /// Advances one step to the load F_{n+1} (sparse pairs, duplicates summed).
    pub fn step(&mut self, f_next: &[(usize, f64)]) {
        let af = self.scheme.alpha_f;
        for &(d, f) in f_next {
            self.load[d] += (1.0 - af) * f;
            self.touched.push(d);
        }
        if af != 0.0 && !self.use_weights {
            for &(d, f) in &self.f_prev {
                self.load[d] += af * f;
                self.touched.push(d);
            }
        }
        let k = self.coeffs;
        // The right-hand side consumed (and zeroed) the touched load entries.
        self.dispatch(k);
        self.touched.clear();
        if af != 0.0 && !self.use_weights {
            self.f_prev.clear();
            self.f_prev.extend_from_slice(f_next);
        }
    }

    /// Energy dissipated by C since the start (`set_state` or construction):
    /// Σ Δt·v̄ᵀ·C·v̄ over the steps, v̄ each step's mean velocity (J). Zero unless
    /// `track_dissipation` was set for those steps.
    pub fn dissipated(&self) -> f64 {
        let mut sum = self.diss_sum;
        if self.diss_pending {
            let start_part = self.band_dissipation_lanes();
            sum += self.band_dissipation_rows(start_part);
        }
        self.dt * sum
    }

    fn dispatch(&mut self, k: Coeffs) {
        #[cfg(target_arch = "x86_64")]
        if self.fma {
            // SAFETY: `fma` is set only when the processor reports AVX2 and FMA.
            return unsafe { self.step_avx2(k) };
        }
        self.by_width::<false>(k)
    }

    #[cfg(target_arch = "x86_64")]
    #[target_feature(enable = "avx2,fma")]
    unsafe fn step_avx2(&mut self, k: Coeffs) {
        self.by_width::<true>(k)
    }

    #[inline(always)]
    fn by_width<const FMA: bool>(&mut self, k: Coeffs) {
        self.advance::<FMA>(k);
        self.observe::<FMA>();
    }

    #[inline(always)]
    fn advance<const FMA: bool>(&mut self, k: Coeffs) {
        if self.dense.is_some() {
            self.dense_solve::<FMA>(k);
            self.update::<FMA>(k);
            if self.track_dissipation {
                self.diss_sum += self.dense_dissipation::<FMA>();
            }
            return;
        }
        match self.b {
            0 => self.step_impl::<_, FMA>(Fixed::<0>, k),
            1 => self.step_impl::<_, FMA>(Fixed::<1>, k),
            2 => self.step_impl::<_, FMA>(Fixed::<2>, k),
            3 => self.step_impl::<_, FMA>(Fixed::<3>, k),
            4 => self.step_impl::<_, FMA>(Fixed::<4>, k),
            w => self.step_impl::<_, FMA>(Dynamic(w), k),
        }
    }

    #[inline(always)]
    fn step_impl<W: Width, const FMA: bool>(&mut self, w: W, k: Coeffs) {
        self.rhs::<W, FMA>(w, k);
        if Self::groups_apply(w.b()) && self.use_groups {
            self.forward_groups::<W, FMA>(w);
            if self.track_dissipation {
                self.backward_groups::<W, FMA, true>(w, k);
            } else {
                self.backward_groups::<W, FMA, false>(w, k);
            }
        } else {
            self.forward::<W, FMA>(w);
            if self.track_dissipation {
                self.backward::<W, FMA, true>(w, k);
            } else {
                self.backward::<W, FMA, false>(w, k);
            }
        }
        self.w_ready = true;
        self.diss_pending = self.track_dissipation;
    }

    /// Δu = x = (K_eff⁻¹M)·w₁ + (K_eff⁻¹C)·w₂ − (K_eff⁻¹K)·u + K_eff⁻¹·load, row by row.
    #[inline(always)]
    fn dense_solve<const FMA: bool>(&mut self, k: Coeffs) {
        let (n, b) = (self.n, self.b);
        let ops = self.dense.as_mut().expect("dense step");
        let (u, v, a) = (&self.u[b..b + n], &self.v[..n], &self.a[..n]);
        let (w1, rest) = ops.w.split_at_mut(n);
        let (w2, rest) = rest.split_at_mut(n);
        if !self.w_ready {
            fill_history::<FMA>(k, u, v, a, w1, w2);
        }
        for j in 0..n {
            rest[j] = -u[j];
        }
        gemv::<FMA>(&ops.ops, ops.stride, &ops.w, &mut self.x[b..b + n]);
        let ops = self.dense.as_ref().expect("dense step");
        let x = &mut self.x[b..b + n];
        if self.use_weights {
            for (xa, &wa) in self.patterns_solved.iter().zip(&self.weights) {
                for i in 0..n {
                    x[i] = madd::<FMA>(xa[i], wa, x[i]);
                }
            }
        }
        for &d in &self.touched {
            let f = std::mem::take(&mut self.load[d]);
            if f != 0.0 {
                let col = &ops.a[d * n..(d + 1) * n];
                for i in 0..n {
                    x[i] = madd::<FMA>(col[i], f, x[i]);
                }
            }
        }
    }

    /// z = load + M·w₁ + C·w₂ − K·u, by diagonals.
    #[inline(always)]
    fn rhs<W: Width, const FMA: bool>(&mut self, w: W, k: Coeffs) {
        let (n, b) = (self.n, w.b());
        if !self.w_ready {
            let (u, v, a) = (&self.u[b..b + n], &self.v[..n], &self.a[..n]);
            fill_history::<FMA>(k, u, v, a, &mut self.w1[b..b + n], &mut self.w2[b..b + n]);
        }
        let ray = self.proportional.is_some();
        // The last step's dissipation: folded into this pass in the AVX2 build (it reads C's
        // lower diagonals anyway, and v̄ is not overwritten before the backward sweep), a pass
        // of its own in the baseline build.
        let fold = self.diss_pending && FMA && cfg!(target_arch = "x86_64");
        if self.diss_pending && !fold {
            self.diss_sum += self.band_dissipation_rows((0, [0.0; 4]));
            self.diss_pending = false;
        }
        let mut lanes = (0, [0.0f64; 4]);
        // Row i: Σ_t D_t[i]·w[i−t] (lower half) + Σ_{t≥1} D_t[i+t]·w[i+t] (upper half, the
        // same diagonal read t entries further on). Padded index of column j is j + B.
        let stride = n + b;
        let (m, c, kk) = (&self.m[..(b + 1) * stride], &self.c[..(b + 1) * stride], &self.k[..(b + 1) * stride]);
        // In the proportional form w₂ holds w₂' = u − a₁·w₂ and takes u's place against K.
        let (w1, w2) = (&self.w1[..n + 2 * b], &self.w2[..n + 2 * b]);
        let up = if ray { w2 } else { &self.u[..n + 2 * b] };
        // The products M·w₁, C·w₂, K·u (q = 0, 1, 2) the right-hand side takes: the
        // proportional form skips C.
        let terms: &[usize] = if ray { &[0, 2] } else { &[0, 1, 2] };
        let z = &mut self.z[b..b + n];
        if cfg!(target_arch = "x86_64") && FMA {
            // SAFETY: the FMA build runs only inside `step_avx2` (see `gemv`); the
            // kernel checks the slice lengths it relies on.
            #[cfg(target_arch = "x86_64")]
            unsafe {
                let vb = &self.x[..n + 2 * b];
                let none: &[PeriodicRun] = &[];
                let (r4, r8) = if self.use_runs { (&self.runs4[..], &self.runs8[..]) } else { (none, none) };
                let (mck, ws) = ([m, c, kk], [w1, w2, up]);
                let part = &mut lanes.1;
                let (from, r4) = match (self.avx512, fold, ray) {
                    (false, _, _) => (0, r4),
                    (true, true, true) => (rhs_band_avx512::<true, true>(n, b, mck, ws, z, vb, part, r8), none),
                    (true, true, false) => (rhs_band_avx512::<true, false>(n, b, mck, ws, z, vb, part, r8), none),
                    (true, false, true) => (rhs_band_avx512::<false, true>(n, b, mck, ws, z, vb, part, r8), none),
                    (true, false, false) => (rhs_band_avx512::<false, false>(n, b, mck, ws, z, vb, part, r8), none),
                };
                lanes.0 = match (fold, ray) {
                    (true, true) => rhs_band_avx2::<true, true>(from, n, b, mck, ws, z, vb, part, r4),
                    (true, false) => rhs_band_avx2::<true, false>(from, n, b, mck, ws, z, vb, part, r4),
                    (false, true) => rhs_band_avx2::<false, true>(from, n, b, mck, ws, z, vb, part, r4),
                    (false, false) => rhs_band_avx2::<false, false>(from, n, b, mck, ws, z, vb, part, r4),
                };
            }
        } else if b <= MAX_SLICED {
            // Every diagonal and every shifted copy of w as a slice of length n, so that no
            // index in the row loop needs a bounds check (the baseline build; the compiler
            // kept even this loop scalar, hence `rhs_band_avx2`).
            // Lower and upper diagonal t of M, C, K and the matching shifts of w₁, w₂, u.
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
                z[i] = if ray { sums[0] - sums[2] } else { (sums[0] + sums[1]) - sums[2] };
            }
        } else {
            for i in 0..n {
                let mut sums = [0.0; 3];
                for &q in terms {
                    let (a, x) = [(m, w1), (c, w2), (kk, up)][q];
                    let mut sq = a[i] * x[i + b];
                    for t in 1..=b {
                        // SAFETY: t ≤ B and i < n, so t·(n+B) + i + t < (B+1)·(n+B), and
                        // i + B ± t lies in 0..n + 2B.
                        unsafe {
                            let (lo, hi) = (t * stride + i, t * stride + i + t);
                            sq = madd::<FMA>(*a.get_unchecked(lo), *x.get_unchecked(i + b - t), sq);
                            sq = madd::<FMA>(*a.get_unchecked(hi), *x.get_unchecked(i + b + t), sq);
                        }
                    }
                    sums[q] = sq;
                }
                z[i] = if ray { sums[0] - sums[2] } else { (sums[0] + sums[1]) - sums[2] };
            }
        }
        // The load touches a handful of DOFs: added here rather than streamed in the loop.
        for &d in &self.touched {
            z[d] += std::mem::take(&mut self.load[d]);
        }
        // Out of the band as in it: K against `up`, and C only in the three-product form
        // (in the proportional one C's part is in the residual).
        for e in &self.extra {
            let (i, j, c) = (e.i, e.j, if ray { 0.0 } else { e.c });
            z[i] += e.m * w1[j + b] + c * w2[j + b] - e.k * up[j + b];
            z[j] += e.m * w1[i + b] + c * w2[i + b] - e.k * up[i + b];
        }
        if let Some(p) = &self.proportional {
            // R·w₂ with w₂ = e_v·v + e_a·a of the scheme, from v and a of the DOFs R touches.
            let w2 = |d: usize| madd::<FMA>(p.ev, self.v[d], p.ea * self.a[d]);
            for &(i, j, r) in &p.residual {
                z[i] += r * w2(j);
                if i != j {
                    z[j] += r * w2(i);
                }
            }
        }
        if fold {
            self.diss_sum += self.band_dissipation_rows(lanes);
            self.diss_pending = false;
        }
    }

    /// L·y = z in place in z, and x = y/d. The newest unknown enters each row last and
    /// is carried in a register, so a row's critical path is one multiply–add rather than a
    /// store, a reload and a multiply–add.
    #[inline(always)]
    fn forward<W: Width, const FMA: bool>(&mut self, w: W) {
        let (n, b) = (self.n, w.b());
        let l = &self.l[..n * b];
        let d_inv = &self.d_inv[..n];
        let z = &mut self.z[..n + b];
        let x = &mut self.x[..n + b];
        let mut lp = 0;
        let mut prev = 0.0; // y_{i−1}
        for i in 0..n {
            // Padded index of column i − B + s is i + s.
            let mut y = z[i + b];
            if lp < self.long.len() && self.long[lp].row == i {
                y -= self.long[lp].dot::<FMA>(&self.l_tail, b, z);
                lp += 1;
            }
            if b > 0 {
                for t in 0..b - 1 {
                    // SAFETY: i·B + t < n·B and i + t < n + B.
                    unsafe {
                        y = madd::<FMA>(-*l.get_unchecked(i * b + t), *z.get_unchecked(i + t), y);
                    }
                }
                y = madd::<FMA>(-l[i * b + b - 1], prev, y);
            }
            z[i + b] = y;
            x[i + b] = y * d_inv[i];
            prev = y;
        }
    }

    /// Lᵀ·x = y/d. Band entries are gathered down column i (entry l_{i+s,i} sits in row i+s
    /// at slot B−s) from u, where each finished row's displacement already is, the newest
    /// xᵢ₊₁ last and from a register; the entries of long rows, which reach far back, are
    /// scattered into x as soon as their xₖ is known. x keeps only what the dissipation
    /// needs (v̄, with `VBAR`): one stream fewer than keeping the solution there too.
    #[inline(always)]
    fn backward<W: Width, const FMA: bool, const VBAR: bool>(&mut self, w: W, k: Coeffs) {
        let (n, b) = (self.n, w.b());
        let l = &self.l[..(n + b) * b];
        // Δu of rows i + 1..=i + B, read by row i, stays in x (zero past row n − 1) until
        // no later row reads it: row i + B is updated (and its v̄ stored over its Δu) only
        // once row i is done.
        let x = &mut self.x[b..b + n + b];
        let (u, v, a) = (&mut self.u[b..b + n], &mut self.v[..n], &mut self.a[..n]);
        let (w1, w2) = (&mut self.w1[b..b + n], &mut self.w2[b..b + n]);
        let mut lp = self.long.len();
        let mut prev = 0.0; // x_{i+1}
        for i in (0..n).rev() {
            let mut xi = x[i];
            if b > 0 {
                for s in (2..=b).rev() {
                    // SAFETY: (i+s)·B + B − s < (n+B)·B and i + s < n + B.
                    unsafe {
                        xi = madd::<FMA>(-*l.get_unchecked((i + s) * b + b - s), *x.get_unchecked(i + s), xi);
                    }
                }
                xi = madd::<FMA>(-l[(i + 1) * b + b - 1], prev, xi);
            }
            prev = xi;
            x[i] = xi;
            if i + b < n {
                update_row::<FMA, VBAR>(k, i + b, x[i + b], u, v, a, x, w1, w2);
            }
            if lp > 0 && self.long[lp - 1].row == i {
                lp -= 1;
                self.long[lp].scatter(&self.l_tail, b, x, xi);
            }
        }
        for i in 0..b.min(n) {
            update_row::<FMA, VBAR>(k, i, x[i], u, v, a, x, w1, w2);
        }
    }

    /// New u, v, a (and v̄, w₁, w₂) from x, for the dense step.
    #[inline(always)]
    fn update<const FMA: bool>(&mut self, k: Coeffs) {
        let (n, b) = (self.n, self.b);
        let x = &mut self.x[b..b + n];
        let (u, v, a) = (&mut self.u[b..b + n], &mut self.v[..n], &mut self.a[..n]);
        // The next step's w₁, w₂ go straight into the dense step's w.
        let ops = self.dense.as_mut().expect("dense step");
        let (w1, rest) = ops.w.split_at_mut(n);
        let w2 = &mut rest[..n];
        for i in 0..n {
            update_row::<FMA, true>(k, i, x[i], u, v, a, x, w1, w2);
        }
        self.w_ready = true;
    }

    /// v̄ᵀ·C·v̄ of the step just taken by the dense step, with C by rows; v̄ is padded with
    /// zeros past n (`x` has B + 4 spare entries, and the padding of a row of `c` is zero).
    #[inline(always)]
    fn dense_dissipation<const FMA: bool>(&mut self) -> f64 {
        let (n, b) = (self.n, self.b);
        let ops = self.dense.as_ref().expect("dense step");
        let vb = &self.x[b..b + ops.c_stride];
        let cv = &mut self.z[..n];
        gemv::<FMA>(&ops.c, ops.c_stride, vb, cv);
        vb.iter().zip(cv.iter()).map(|(v, c)| v * c).sum()
    }

    /// The banded v̄ᵀ·C·v̄ of the v̄ in `x` over whole groups of four rows in the AVX2 build, as
    /// (first row left, four partial sums); nothing in the baseline build.
    fn band_dissipation_lanes(&self) -> (usize, [f64; 4]) {
        let mut part = [0.0f64; 4];
        #[cfg(target_arch = "x86_64")]
        if self.fma {
            let (n, b) = (self.n, self.b);
            let stride = n + b;
            // SAFETY: `fma` is set only when the processor reports AVX2 and FMA; the lengths
            // are the ones `dissipation_avx2` checks.
            let start = unsafe { dissipation_avx2(n, b, &self.c[..(b + 1) * stride], &self.x[..n + 2 * b], &mut part) };
            return (start, part);
        }
        (0, part)
    }

    /// Finishes the banded v̄ᵀ·C·v̄ = Σᵢ v̄ᵢ·(C_ii·v̄ᵢ + 2·Σ_{t≥1} C_{i,i−t}·v̄_{i−t}) from row
    /// `start` on, lane l taking rows i ≡ l mod 4 (as the vector kernels do), plus the entries
    /// outside the band.
    fn band_dissipation_rows(&self, (start, mut part): (usize, [f64; 4])) -> f64 {
        let (n, b) = (self.n, self.b);
        let stride = n + b;
        let c = &self.c[..(b + 1) * stride];
        let vb = &self.x[..n + 2 * b];
        let madd = |x: f64, y: f64, acc: f64| if self.fma { x.mul_add(y, acc) } else { x * y + acc };
        for i in start..n {
            let mut s = 0.5 * c[i] * vb[i + b];
            for t in 1..=b {
                s = madd(c[t * stride + i], vb[i + b - t], s);
            }
            part[i % 4] = madd(2.0 * s, vb[i + b], part[i % 4]);
        }
        let mut diss = (part[0] + part[1]) + (part[2] + part[3]);
        for e in &self.extra {
            diss += 2.0 * e.c * vb[e.i + b] * vb[e.j + b];
        }
        diss
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The builds of the dense products this processor can run (FMA or not).
    fn builds() -> Vec<bool> {
        let mut b = vec![false];
        #[cfg(target_arch = "x86_64")]
        if std::arch::is_x86_feature_detected!("avx2") && std::arch::is_x86_feature_detected!("fma") {
            b.push(true);
        }
        b
    }

    /// Every row count (whole groups of four and each partial last group), both builds:
    /// the product equals plain sums to round-off and writes nothing past `out`.
    #[test]
    fn gemv_matches_plain_sums_for_every_row_count() {
        let stride = 8;
        let w: Vec<f64> = (0..stride).map(|k| 0.3 + 0.7 * ((k * 7 % 5) as f64) - 1.1).collect();
        for rows in 1..=9usize {
            let a: Vec<f64> = (0..rows.next_multiple_of(4) * stride)
                .map(|q| if q < rows * stride { ((q * 13 % 11) as f64 - 5.0) / 3.0 } else { 0.0 })
                .collect();
            for fma in builds() {
                // A sentinel past the rows checks that the last group stores only its rows.
                let mut out = vec![f64::NAN; rows + 1];
                let (head, tail) = out.split_at_mut(rows);
                tail[0] = 42.0;
                if fma {
                    gemv::<true>(&a, stride, &w, head);
                } else {
                    gemv::<false>(&a, stride, &w, head);
                }
                for (i, &got) in out[..rows].iter().enumerate() {
                    let row = &a[i * stride..(i + 1) * stride];
                    let want: f64 = row.iter().zip(&w).map(|(x, y)| x * y).sum();
                    let scale: f64 = row.iter().zip(&w).map(|(x, y)| (x * y).abs()).sum();
                    assert!((got - want).abs() <= 1e-14 * scale, "rows {rows}, fma {fma}, row {i}: {got} vs {want}");
                }
                assert_eq!(out[rows], 42.0, "rows {rows}, fma {fma}: wrote past the end");
            }
        }
    }

    /// `gemv3` gives, for every row count and both builds, the bits of three `gemv`s (the
    /// same lanes in the same order) and writes nothing past `out`.
    #[test]
    fn gemv3_is_three_gemvs_for_every_row_count() {
        let stride = 12;
        let x: Vec<Vec<f64>> =
            (0..3).map(|q| (0..stride).map(|k| ((k * 7 + q * 3) % 5) as f64 * 0.37 - 0.6).collect()).collect();
        for rows in 1..=9usize {
            let a: Vec<f64> = (0..rows.next_multiple_of(4) * stride)
                .map(|p| if p < rows * stride { ((p * 13 % 11) as f64 - 5.0) / 3.0 } else { 0.0 })
                .collect();
            for fma in builds() {
                let mut out = vec![[f64::NAN; 3]; rows + 1];
                out[rows] = [42.0; 3];
                let mut one = vec![0.0; rows];
                if fma {
                    gemv3::<true>(&a, stride, &x[0], &x[1], &x[2], &mut out[..rows]);
                } else {
                    gemv3::<false>(&a, stride, &x[0], &x[1], &x[2], &mut out[..rows]);
                }
                for q in 0..3 {
                    if fma {
                        gemv::<true>(&a, stride, &x[q], &mut one);
                    } else {
                        gemv::<false>(&a, stride, &x[q], &mut one);
                    }
                    for i in 0..rows {
                        assert_eq!(
                            out[i][q].to_bits(),
                            one[i].to_bits(),
                            "rows {rows}, fma {fma}, row {i}, vector {q}"
                        );
                    }
                }
                assert_eq!(out[rows], [42.0; 3], "rows {rows}, fma {fma}: wrote past the end");
            }
        }
    }
}
